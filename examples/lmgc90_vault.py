"""LMGC90's example RIGID_3D/POLYF/Vault as a DATBOX of POLYF blocks, written by saxum.

The example (its gen_with_gmsh.py and command.py; its geometry abeille2.dat, which is
LMGC90's and not shipped here): a vault of 76 stones in Abeille's bond, each a hexahedron
given as its six quadrilateral faces, `{{{x, y, z}, ...}, ...}` per stone [m]; RIGID, density
2500 kg/m^3; the stones whose centre of mass is below z = 0.8 m have all their dofs imposed
at velocity 0 (the springings: colour REDxx, here FIXED), the others are free (BLEUx); each
stone one POLYF (a patch per face); IQS_CLB, mu = 0.3, between free stones (alert 1e-2 m)
and between free and fixed ones (alert 1.25e-2 m), none between fixed ones; gravity
-9.81 m/s^2 along z (pylmgc90's default in 3D). Run: 10 steps of 1e-3 s, theta 0.5, NLGS
'QM/16' 1.666e-4, at most 100 x 10 sweeps.

`main` reads abeille2.dat and writes the DATBOX with export_lmgc90 in LMGC90's fixed
columns, the stones as POLYF (tests/data/lmgc90/vault3d was made so):

    PYTHONPATH=src python examples/lmgc90_vault.py .../Vault/abeille2.dat DATBOX
"""

import re
import sys
from pathlib import Path

import numpy as np

import saxum as sx
from saxum.geometry3d import convex_polyhedron, polyhedron_properties
from saxum.lmgc90 import export_lmgc90

DENSITY = 2500.0  # [kg/m^3]
FRICTION = 0.3
SPRINGING = 0.8
"""[m] Stones whose centre of mass is below this height are fixed (gen_with_gmsh.py)."""


def read_stones(path: str | Path) -> list[np.ndarray]:
    """The stones of an abeille2.dat-like file: per stone the points [m] of its faces
    (n, 3), each point once (a point closes a face with one '}', a face closes a stone with
    two)."""
    stones, points, depth = [], [], 0
    for token in re.findall(r"[{}]|[^{},\s]+", Path(path).read_text(encoding="utf-8")):
        if token == "{":
            depth += 1
        elif token == "}":
            depth -= 1
            if depth == 0:  # the stone's list closes
                stones.append(np.unique(np.array(points).reshape(-1, 3), axis=0))
                points = []
        else:
            points.append(float(token))
    return stones


def vault(stones: list[np.ndarray], friction: float = FRICTION) -> sx.Model:
    """The example's vault of `stones` (read_stones), friction mu [-] on every law."""
    b = sx.ModelBuilder(dim=3, gravity=(0.0, 0.0, -9.81))
    for k, points in enumerate(stones):
        centre = polyhedron_properties(convex_polyhedron(points)).centroid
        fixed = centre[2] < SPRINGING
        b.add_block(points, density=DENSITY, group="REDxx" if fixed else "BLEUx",
                    kind=sx.BodyKind.FIXED if fixed else sx.BodyKind.FREE,
                    name=f"stone {k + 1}")
    iqs = sx.LawKind.SIGNORINI_COULOMB
    b.set_law("BLEUx", "BLEUx", sx.ContactLaw(friction=friction, kind=iqs, alert=1e-2))
    b.set_law("BLEUx", "REDxx", sx.ContactLaw(friction=friction, kind=iqs, alert=1.25e-2))
    b.set_law("REDxx", "REDxx", sx.NO_CONTACT)
    return b.finalize()


def main(source: str | Path, folder: str | Path) -> Path:
    """Write the vault of `source` (abeille2.dat) to the DATBOX `folder`, stones as POLYF."""
    model = vault(read_stones(source))
    return export_lmgc90(model, folder, polyhedra="POLYF")


if __name__ == "__main__":
    out = main(sys.argv[1], sys.argv[2])
    print(f"{out}: the vault as a DATBOX of POLYF stones")
