"""saxum.lmgc90 and LMGC90's POLYF contactor: a polyhedron given as its surface in patches.

The columns checked are those LMGC90's Fortran reads (mod_a_BDARY_POLYR.f90,
read_BDARY_POLYR and read_BDARY_POLYF): a POLYF's nb_patch and a patch's nb_vertex in
columns 40:47, its nb_faces in 60:67, a vertex's coo1..3 in 35:48, 56:69, 77:90 (D14.7), a
triangle's ver1..3 in 35:47, 56:68, 77:89.
"""

import itertools
import re

import numpy as np
import pytest

import saxum as sx
from saxum.cli import main
from saxum.errors import InputError
from saxum.lmgc90 import export_lmgc90, import_lmgc90, read_datbox

_PAD = " " * 29
"""A continuation line's first 29 columns."""


def _model():
    """A fixed slab, a free box on it and an L-shaped cluster (two boxes) beside it."""
    def box(x0, x1, y0, y1, z0, z1):
        return list(itertools.product((x0, x1), (y0, y1), (z0, z1)))

    b = sx.ModelBuilder(dim=3)
    b.add_block(box(-1, 1, -1, 1, -0.1, 0), kind=sx.BodyKind.FIXED, group="ground",
                name="ground")
    b.add_block(box(-0.5, -0.3, -0.1, 0.1, 0, 0.3), density=2000.0, group="stone",
                name="box")
    b.add_cluster([box(0, 0.4, -0.1, 0.1, 0, 0.1), box(0, 0.1, -0.1, 0.1, 0.1, 0.4)],
                  density=2400.0, group="stone", name="ell")
    b.set_law("stone", "ground", sx.ContactLaw(friction=0.6, alert=0.01))
    b.set_law("stone", "stone", sx.ContactLaw(friction=0.5, alert=0.01))
    return b.finalize()


def _columns(line: str, *spans) -> list[float]:
    """The values of `line` in the 1-based column spans (first, last), as Fortran reads."""
    return [float(line[a - 1:b].replace("D", "E")) for a, b in spans]


def test_polyf_round_trip_in_lmgc90_columns(tmp_path):
    model = _model()
    export_lmgc90(model, tmp_path / "full", precision="full", polyhedra="POLYF")
    text = (tmp_path / "full" / "BODIES.DAT").read_text()
    assert text.count(" POLYF ") == 4 and " POLYR " not in text  # the cluster: 2 POLYF
    back = import_lmgc90(tmp_path / "full").model()
    # 17 digits: the same blocks; the cluster's parts and mass as built
    assert back.body_name == model.body_name
    for k in range(model.body_count):
        apart = np.linalg.norm(model.vertices(k)[:, None] - back.vertices(k)[None], axis=2)
        assert apart.min(axis=1).max() <= 1e-12  # 1e-12 m: 17 digits of 1 m
    np.testing.assert_allclose(back.body_mass, model.body_mass, rtol=1e-12)
    ell = model.body("ell")
    assert np.count_nonzero(back.contactor_body == ell) == 2

    export_lmgc90(model, tmp_path / "cols", polyhedra="POLYF")
    lines = (tmp_path / "cols" / "BODIES.DAT").read_text().splitlines()
    box = read_datbox(tmp_path / "cols").bodies[model.body("box")]
    patches = box.contactors[0].patches
    assert len(patches) == 6  # a patch per face
    head = lines.index(next(x for x in lines if x.startswith(" POLYF")
                            and "STO" in x))  # the box's POLYF line
    assert lines[head][39:47].strip() == "6"  # nb_patch, an integer in columns 40-47
    row, volume = head + 1, 0.0
    for _ in range(6):
        nv, nf = (int(x) for x in _columns(lines[row], (40, 47), (60, 67)))
        pts = np.array([_columns(lines[row + 1 + k], (35, 48), (56, 69), (77, 90))
                        for k in range(nv)])
        tris = [[int(x) - 1 for x in _columns(lines[row + 1 + nv + k], (35, 47), (56, 68),
                                              (77, 89))] for k in range(nf)]
        volume += sum(np.dot(pts[i], np.cross(pts[j], pts[k])) for i, j, k in tris) / 6.0
        row += 1 + nv + nf
    # outward triangles: LMGC90 takes the volume from them (and stops on a negative one);
    # 0.2 x 0.2 x 0.3 m, 7 digits
    assert volume == pytest.approx(0.012, rel=1e-6)
    assert import_lmgc90(tmp_path / "cols").model().body_count == model.body_count


def test_polyr_triangles_in_lmgc90_columns(tmp_path):
    export_lmgc90(_model(), tmp_path / "DATBOX")
    lines = [x for x in (tmp_path / "DATBOX" / "BODIES.DAT").read_text().splitlines()
             if "ver1=" in x]
    tris = np.array([_columns(x, (35, 47), (56, 68), (77, 89)) for x in lines])
    assert len(tris) == 4 * 12  # four boxes (ground, box, the cluster's two), 12 triangles each
    assert tris.min() == 1 and tris.max() == 8


def _polyf_datbox(tmp_path):
    export_lmgc90(_model(), tmp_path / "DATBOX", polyhedra="POLYF")
    return tmp_path / "DATBOX"


def _replace(folder, old: str, new: str, nth: int = 0) -> int:
    """Replace the nth line of BODIES.DAT that contains `old` by `new` (a whole line, or ''
    to remove it); returns that line's number (from 1)."""
    path = folder / "BODIES.DAT"
    lines = path.read_text().splitlines()
    k = [i for i, x in enumerate(lines) if old in x][nth]
    if new:
        lines[k] = new
    else:
        del lines[k]
    path.write_text("\n".join(lines) + "\n")
    return k + 1


def test_non_convex_polyf_named_with_its_patch(tmp_path):
    """One POLYF with the patches of both parts of the L-shaped block: their surface is not
    convex; the error names the patch that lies inside the hull."""
    folder = _polyf_datbox(tmp_path)
    path = folder / "BODIES.DAT"
    lines = path.read_text().splitlines()
    heads = [i for i, x in enumerate(lines) if x.startswith(" POLYF")]
    first, second = heads[2], heads[3]  # the cluster's two POLYF
    lines[first] = lines[first].replace("nb_patch=      6", "nb_patch=     12")
    del lines[second]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=r"BODIES.DAT line \d+: POLYF of RBDY3 3 is not "
                                         r"convex: triangle \d+ of its patch \d+"):
        import_lmgc90(folder)


@pytest.mark.parametrize("old, new, message, at_changed_line", [
    ("coo1= 1.0000000D+00  coo2=-1.0000000D+00", _PAD + "coo1= 1.0D-01  coo2= 1.0D-01",
     "vertex 1 of 4 of patch 1 of the POLYF of BODIES.DAT line {head} needs coo1= coo2= "
     "coo3=", True),
    ("ver1=", _PAD + "ver1=      1         ver2=      2         ver3=      9",
     "triangle 1 of 2 of patch 1 of the POLYF of BODIES.DAT line {head} needs ver1= ver2= "
     "ver3=, vertex numbers from 1 to 4, found 1, 2, 9", True),
    ("nb_vertex=", _PAD + "nb_vertex=      4",
     "patch 1 of the POLYF of BODIES.DAT line {head} needs nb_faces= an integer >= 1, found "
     "none", True),
    ("nb_patch=", " POLYF      1  color  GRO01  nb_patch=      7",
     "the POLYF of BODIES.DAT line {head} ends before patch 7 of 7", False),
    ("nb_patch=", " POLYF      1  color  GRO01  nb_patch=      5",
     "the POLYF of BODIES.DAT line {head} has 5 patches", False),
])
def test_malformed_polyf_named_by_file_and_line(tmp_path, capsys, old, new, message,
                                                at_changed_line):
    folder = _polyf_datbox(tmp_path)
    lines = (folder / "BODIES.DAT").read_text().splitlines()
    head = next(i for i, x in enumerate(lines) if "nb_patch=" in x) + 1
    line = _replace(folder, old, new)
    at = str(line) if at_changed_line else r"\d+"
    with pytest.raises(InputError, match=f"BODIES.DAT line {at}: "
                       + re.escape(message.format(head=head))):
        import_lmgc90(folder)
    assert main(["import-lmgc90", str(folder), "-o", str(tmp_path / "m.toml")]) == 2
    assert message.format(head=head) in capsys.readouterr().err
    assert not (tmp_path / "m.toml").exists()


def test_missing_patch_refused(tmp_path):
    """A POLYF whose patches do not close its surface (one left out, nb_patch 5): the hull
    of the rest is the same box, but the triangles cover only part of it."""
    folder = _polyf_datbox(tmp_path)
    path = folder / "BODIES.DAT"
    lines = path.read_text().splitlines()
    head = next(i for i, x in enumerate(lines) if x.startswith(" POLYF"))
    lines[head] = lines[head].replace("nb_patch=      6", "nb_patch=      5")
    del lines[head + 1:head + 8]  # the first patch: its line, 4 vertices, 2 triangles
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=f"BODIES.DAT line {head + 1}: POLYF of RBDY3 1: its "
                                         "triangles' area, .* is not that of the solid"):
        import_lmgc90(folder)
