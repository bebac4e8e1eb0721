"""Self-weight of an elastic column of tetrahedra on rigid ground (issue 14, validation
"Self-weight", 3D; the 2D column: test_fe_self_weight.py).

A square column of height H, nu = 0 (the 1D bar: no lateral strain), density rho, standing on
a rigid slab under gravity g: once its vibration is damped, the base carries rho g H and the
top has moved down by
    delta = int_0^H rho g (H - z) / E dz = rho g H^2 / (2 E)
(Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec. 96, body forces). Tolerance 1 %,
the issue's. The shortening is the mean displacement of the top face's nodes: Kuhn
tetrahedra (6 per cube, all along one diagonal) do not reproduce the bar node by node, the
top nodes of this 0.1 m mesh spread by +-5 % about the bar's value while their mean is it to
1e-6 (a static solve of K u = f with the base held, measured), so the mean is the quantity
that the column's shortening names. Rayleigh damping beta = 0.01 s (about half critical for
the first mode, period 4 H / c = 0.057 s) leaves less than 1e-4 of it after 0.6 s.
"""

import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

H, WIDTH, RHO, E, G = 1.0, 0.2, 2000.0, 1.0e7, 9.81
DT = 1e-3


def _box(x0, x1, y0, y1, z0, z1):
    return [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]


@pytest.fixture(scope="module")
def settled():
    b = ModelBuilder(dim=3, gravity=(0.0, 0.0, -G))
    b.add_block(_box(-1, 1, -1, 1, -0.2, 0), kind=BodyKind.FIXED, group="ground")
    half = WIDTH / 2
    b.add_block(_box(-half, half, -half, half, 0, H),
                material=Elastic(E, 0.0, RHO, damping=(0.0, 0.01)), mesh_size=0.1,
                group="column")
    law = sx.ContactLaw(friction=0.6)
    b.set_law("column", "ground", law)
    b.set_law("column", "column", law)
    sim = Simulation(b.finalize(), dt=DT)
    state = sim.initial_state()
    sim.run(state, 0.6)
    return sim, state


def test_top_shortening_is_rho_g_h2_over_2e(settled):
    sim, state = settled
    top = sim.model.fe.node_x0[:, 2] > H - 1e-9
    expected = RHO * G * H**2 / (2.0 * E)
    assert H - state.node_x[top, 2].mean() == pytest.approx(expected, rel=0.01)


def test_base_stress_is_rho_g_h(settled):
    """The base pressure from the contact impulses, sum R_n / (h width^2) [Pa], and the areas
    of the base nodes summing to the base (within 1e-3: the frame fitted to the nodes leans
    by 1.1e-4 rad, the Kuhn mesh's shear under the weight, measured, which turns the side
    triangles at the base's edges by as much towards the ground, each adding that fraction
    of its area to its nodes')."""
    sim, state = settled
    c = state.contacts
    assert c.impulse[: c.count, 1].sum() / DT / WIDTH**2 == pytest.approx(RHO * G * H,
                                                                         rel=0.01)
    assert c.area[: c.count].sum() == pytest.approx(WIDTH**2, rel=1e-3)
