"""An elastic bar of tetrahedra hitting a rigid wall (issue 14, validation "Waves", 3D; the 2D
bar: test_fe_bar_impact.py).

A free bar of length L, wave speed c = sqrt(E / rho) (nu = 0: the 1D bar), moving at v0 onto
a rigid wall, stays in contact while the compression wave runs to the free end and back,
2 L / c (St-Venant's impact theory: Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec.
146; Graff, Wave Motion in Elastic Solids, sec. 2.3). Tolerance 2 %, the issue's; measured
0.995 of 2 L / c on this 0.05 m mesh (84 nodes), 0.993 on a 0.025 m one. The exit velocity,
which the issue also asks within 2 % of v0, is left to finer meshes than a quick test can
afford: linear tetrahedra disperse the wave front and keep part of the energy in vibration
after release, 0.964 v0 at 0.05 m and 0.976 v0 at 0.025 m (measured; 2D triangles: 0.963,
0.977 and 0.987 at 0.05, 0.025 and 0.0125 m).
"""

import numpy as np
import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

L, WIDTH, RHO, E, V0 = 1.0, 0.05, 1000.0, 1.0e7, 1.0
C = (E / RHO) ** 0.5
DT = 2e-5
GAP = 1e-3


def _box(x0, x1, y0, y1, z0, z1):
    return [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]


def test_contact_time_is_2l_over_c():
    b = ModelBuilder(dim=3, gravity=(0.0, 0.0, 0.0))
    b.add_block(_box(-0.2, 0, -0.5, 0.5, -0.5, 0.5), kind=BodyKind.FIXED, group="wall")
    half = WIDTH / 2
    b.add_block(_box(GAP, GAP + L, -half, half, -half, half), material=Elastic(E, 0.0, RHO),
                mesh_size=0.05, group="bar")
    law = sx.ContactLaw(friction=0.0)
    b.set_law("bar", "wall", law)
    b.set_law("bar", "bar", law)
    sim = Simulation(b.finalize(), dt=DT, theta=0.5,
                     detection=sx.DetectionSettings(alert=2.0 * GAP))
    state = sim.initial_state()
    state.node_v[:, 0] = -V0
    loaded = []
    for _ in range(round(0.03 / DT)):
        sim.step(state)
        c = state.contacts
        loaded.append(c.impulse[: c.count, 1].sum() > 0.0)
    steps = np.flatnonzero(loaded)
    assert steps.size and steps[-1] < len(loaded) - 1  # it has left the wall
    assert (steps[-1] - steps[0] + 1) * DT == pytest.approx(2.0 * L / C, rel=0.02)
    mass = sim.fe.blocks.node_mass
    assert (mass * state.node_v[:, 0]).sum() / mass.sum() > 0.0  # and moves away
