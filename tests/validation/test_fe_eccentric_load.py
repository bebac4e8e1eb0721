"""A deformable pier under an eccentric vertical load on rigid ground (issue 14, validation
"Eccentric load").

Navier's formula (any strength-of-materials text, e.g. Timoshenko & Gere, Mechanics of
Materials, sec. 7.4; Heyman, The Stone Skeleton, ch. 2, for masonry): a section of width b
carrying a normal force N at eccentricity e is compressed linearly,
    sigma(x) = N / b (1 + 12 e x / b^2),   x from the centre,
while e <= b/6 (the kern); past it, a joint that cannot carry tension opens and the pressure
is the triangle over 3 (b/2 - e) under the load's line, largest 2 N / (3 (b/2 - e)).

The load is a rigid block (100 kg per metre) standing off-centre on the pier's top, so N is
its weight plus the pier's and e = P e_load / N, e_load where the block's centre of mass ends
(it tilts a little on the elastic pier). The pier is 2 b high (St-Venant: the base is far
from the load's spreading) with nu = 0 (the beam's Navier is then the plane solution) on a
b / 10 mesh, damped (beta = 0.01 s) for 1 s until at rest. Measured: the pressure R_n / (h
area) at the inner nodes off the Navier line by at most 1.2 % of N / b (mesh 0.04 m; the two
corner nodes stand for a half element and carry the consistent-load mixture of two values,
so they are left out); beyond the kern the contact ends between the same two nodes as the
triangle, and the elastic pressure near the open edge is below the triangle's (the elastic
contact problem is not the beam's: its peak, extrapolated from the inner nodes, 4.5 % below
2 N / (3 (b/2 - e)) on this mesh). Tolerances: the resultant on the load's line within
0.5 % of b (equilibrium, at rest); the Navier line within 2 % of N / b; the open length within
one element.
"""

import numpy as np
import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

B, H, G, DT = 0.4, 0.8, 9.81, 1e-3
RHO_PIER, LOAD_MASS = 1000.0, 1000.0
MESH = 0.04


def _base_pressure(e_load: float):
    """(node x [m], pressure [Pa], N [N/m], e [m]) at the pier's base, at rest."""
    b = ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=BodyKind.FIXED, group="ground")
    b.add_block([(-B / 2, 0), (B / 2, 0), (B / 2, H), (-B / 2, H)],
                material=Elastic(1.0e8, 0.0, RHO_PIER, damping=(0.0, 0.01)), mesh_size=MESH,
                group="pier")
    b.add_block([(e_load - 0.05, H), (e_load + 0.05, H), (e_load + 0.05, H + 0.1),
                 (e_load - 0.05, H + 0.1)], density=LOAD_MASS / 0.01, group="load")
    law = sx.ContactLaw(friction=0.8)
    for pair in [("pier", "ground"), ("pier", "pier"), ("load", "pier"), ("load", "load"),
                 ("load", "ground")]:
        b.set_law(*pair, law)
    sim = Simulation(b.finalize(), dt=DT)
    state = sim.initial_state()
    sim.run(state, 1.0)
    c = state.contacts
    base = np.flatnonzero(c.antagonist[: c.count] == 0)
    order = base[np.argsort(c.point[base, 0])]
    x = c.point[order, 0]
    force = c.impulse[order, 1] / DT
    load = LOAD_MASS * G
    n = RHO_PIER * B * H * G + load
    return x, force / c.area[order], force, n, load * state.body_q[2, 0] / n


def test_within_the_kern_the_base_is_compressed_linearly():
    x, pressure, force, n, e = _base_pressure(0.04)
    assert e < B / 6
    assert force.sum() == pytest.approx(n, rel=1e-3)
    assert (force * x).sum() / force.sum() == pytest.approx(e, abs=0.005 * B)
    inner = slice(1, -1)
    navier = n / B * (1.0 + 12.0 * e * x[inner] / B**2)
    assert np.abs(pressure[inner] - navier).max() < 0.02 * n / B


def test_beyond_the_kern_the_joint_opens_over_the_triangle():
    x, pressure, force, n, e = _base_pressure(0.12)
    assert e > B / 6
    assert force.sum() == pytest.approx(n, rel=1e-3)
    assert (force * x).sum() / force.sum() == pytest.approx(e, abs=0.005 * B)
    edge = B / 2 - 3.0 * (B / 2 - e)  # where the triangle ends
    carries = pressure > 1e-9 * n / B  # (an open node's impulse is zero to round-off)
    open_nodes = x[~carries]
    loaded_nodes = x[carries]
    assert open_nodes.size and open_nodes.max() < edge + MESH
    assert loaded_nodes.min() > edge - MESH
