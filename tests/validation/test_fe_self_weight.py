"""Self-weight of an elastic column on rigid ground (issue 14, validation "Self-weight").

A column of height H, nu = 0 (so the plane-strain modulus is E and the problem is the 1D
bar), density rho, standing on a rigid support under gravity g: once its vibration is damped,
sigma_yy(0) = rho g H at the base and the top has moved down by
    delta = int_0^H rho g (H - y) / E dy = rho g H^2 / (2 E)
(Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec. 96, body forces). Tolerance 1 %,
the issue's: linear triangles reproduce the bar's quadratic displacement at the nodes to far
better than that on a 0.05 m grid (the 1D element with consistent loads is nodally exact),
and Rayleigh damping (beta = 0.01 s, about 0.5 of critical for the first mode) leaves less
than 1e-4 of the shortening after 0.6 s.
"""

import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

H, WIDTH, RHO, E, G = 1.0, 0.2, 2000.0, 1.0e7, 9.81
DT = 1e-3


@pytest.fixture(scope="module")
def settled():
    b = ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=BodyKind.FIXED, group="ground")
    b.add_block([(-WIDTH / 2, 0), (WIDTH / 2, 0), (WIDTH / 2, H), (-WIDTH / 2, H)],
                material=Elastic(E, 0.0, RHO, damping=(0.0, 0.01)), mesh_size=0.05,
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
    top = state.node_x[:, 1].max()
    expected = RHO * G * H**2 / (2.0 * E)
    assert H - top == pytest.approx(expected, rel=0.01)


def test_base_stress_is_rho_g_h(settled):
    """The base pressure from the contact impulses: sum R_n / (h * width) [Pa], and the
    largest node's pressure R_n / (h * tributary length) stays within 1 % as well (the
    column's base is uniformly compressed when nu = 0)."""
    sim, state = settled
    c = state.contacts
    rn = c.impulse[: c.count, 1]
    assert rn.sum() / DT / WIDTH == pytest.approx(RHO * G * H, rel=0.01)
    pressure = rn / DT / c.area[: c.count]
    assert pressure.max() == pytest.approx(RHO * G * H, rel=0.01)
    assert pressure.min() == pytest.approx(RHO * G * H, rel=0.01)
