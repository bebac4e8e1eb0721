"""Newton's impact law on deformable blocks (issue 14): under a restitution law (LawKind.
RESTITUTION_COULOMB) each node contact of an elastic block that strikes rigid ground leaves
at U_n+ = -e_n U_n-, its own normal velocity before the impact times -e_n, as a rigid block's
contact does [M. Jean, CMAME 177 (1999) 235-257, sec. 4: the velocity-level Signorini
condition on U_n + e_n U_n-]. Before this was handled, the rigid assembly read an FE side's
velocity from its body row (which holds only its frame) and every node bounced as with
e_n = 0.

A 0.4 x 0.2 (3D: x 0.2) m block, E = 1 GPa, without gravity, at -1 m/s a hair above the
ground: in the one step of the impact every loaded node contact must satisfy the law within
1e-6 m/s of 0.5 m/s (the solver's tolerance is 1e-10 on the relative change per sweep;
what it leaves in the velocities was measured at 4e-11 m/s in 2D, 1.2e-9 m/s in 3D), and
the block's centre of mass must leave upwards, slower than e_n times the impact speed
(part of its momentum change goes into vibration of the elastic block: 0.375 m/s in 2D,
0.373 m/s in 3D, measured).
"""

import numpy as np
import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.laws import LawKind
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation
from saxum.solver.nlgs import NLGS

E_N = 0.5
V0 = 1.0  # impact speed [m/s]


def _block(dim):
    b = ModelBuilder(dim=dim, gravity=(0.0,) * dim)
    if dim == 2:
        b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=BodyKind.FIXED,
                    group="ground")
        b.add_block([(-0.2, 1e-4), (0.2, 1e-4), (0.2, 0.2), (-0.2, 0.2)],
                    material=Elastic(1.0e9, 0.2, 2000.0), mesh_size=0.1, group="block")
    else:
        b.add_block([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-0.2, 0)],
                    kind=BodyKind.FIXED, group="ground")
        b.add_block([(x, y, z) for x in (-0.2, 0.2) for y in (-0.1, 0.1) for z in (1e-4, 0.2)],
                    material=Elastic(1.0e9, 0.2, 2000.0), mesh_size=0.1, group="block")
    law = sx.ContactLaw(friction=0.5, kind=LawKind.RESTITUTION_COULOMB, restitution=E_N)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    return b.finalize()


@pytest.mark.parametrize("dim", [2, 3])
def test_each_node_contact_rebounds_by_newtons_law(dim):
    sim = Simulation(_block(dim), dt=1e-3, solver=NLGS(tolerance=1e-10))
    state = sim.initial_state()
    state.node_v[:, dim - 1] = -V0
    before = state.node_v.copy()
    sim.step(state)
    c = state.contacts
    loaded = c.impulse[: c.count, 1] > 0.0
    assert loaded.sum() == (5 if dim == 2 else 15)  # every bottom node
    assert (c.side_kind[: c.count, 0] == 1).all() and (c.side_kind[: c.count, 1] == 0).all()
    nodes = c.side_node[: c.count, 0, 0][loaded]
    normal = c.frame[: c.count, 1][loaded]
    u_before = np.einsum("kd,kd->k", normal, before[nodes])
    u_after = np.einsum("kd,kd->k", normal, state.node_v[nodes])
    assert np.abs(u_after + E_N * u_before).max() < 1e-6
    mass = sim.fe.blocks.node_mass
    centre = float(mass @ state.node_v[:, dim - 1]) / float(mass.sum())
    assert 0.0 < centre < E_N * V0
