"""Self-weight of an elastic column on rigid ground (issue 14, validation "Self-weight"), 2D
and 3D.

A column of height H, nu = 0 (so the plane-strain modulus is E and the problem is the 1D
bar), density rho, standing on a rigid support under gravity g: once its vibration is damped,
sigma(0) = rho g H at the base and the top has moved down by
    delta = int_0^H rho g (H - y) / E dy = rho g H^2 / (2 E)
(Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec. 96, body forces). Tolerance 1 %,
the issue's. 2D: linear triangles reproduce the bar's quadratic displacement at the nodes to
far better than that on a 0.05 m grid (the 1D element with consistent loads is nodally
exact). 3D (a 0.2 m square column, 0.1 m Kuhn tetrahedra, 6 per cube along one diagonal):
the tetrahedra do not reproduce the bar node by node, the top nodes spread by +-5 % about the
bar's value while their mean is it to 1e-6 (a static solve of K u = f with the base held,
measured), so the shortening is the mean displacement of the top nodes in both. Rayleigh
damping (beta = 0.01 s, about 0.5 of critical for the first mode, period 4 H / c = 0.057 s)
leaves less than 1e-4 of the shortening after 0.6 s.
"""

import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

H, WIDTH, RHO, E, G = 1.0, 0.2, 2000.0, 1.0e7, 9.81
DT = 1e-3


def _column(dim):
    """The column of width WIDTH (3D: a square) on fixed ground, as a builder."""
    material = Elastic(E, 0.0, RHO, damping=(0.0, 0.01))
    half = WIDTH / 2
    if dim == 2:
        b = ModelBuilder(gravity=(0.0, -G))
        b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=BodyKind.FIXED,
                    group="ground")
        b.add_block([(-half, 0), (half, 0), (half, H), (-half, H)], material=material,
                    mesh_size=0.05, group="column")
        return b
    b = ModelBuilder(dim=3, gravity=(0.0, 0.0, -G))
    b.add_block([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-0.2, 0)],
                kind=BodyKind.FIXED, group="ground")
    b.add_block([(x, y, z) for x in (-half, half) for y in (-half, half) for z in (0, H)],
                material=material, mesh_size=0.1, group="column")
    return b


@pytest.fixture(scope="module", params=[2, 3])
def settled(request):
    b = _column(request.param)
    law = sx.ContactLaw(friction=0.6)
    b.set_law("column", "ground", law)
    b.set_law("column", "column", law)
    sim = Simulation(b.finalize(), dt=DT)
    state = sim.initial_state()
    sim.run(state, 0.6)
    return sim, state


def test_top_shortening_is_rho_g_h2_over_2e(settled):
    sim, state = settled
    up = sim.model.dim - 1
    top = sim.model.fe.node_x0[:, up] > H - 1e-9
    expected = RHO * G * H**2 / (2.0 * E)
    assert H - state.node_x[top, up].mean() == pytest.approx(expected, rel=0.01)


def test_base_stress_is_rho_g_h(settled):
    """The base pressure from the contact impulses: sum R_n / (h * base) [Pa], and the nodes'
    areas sum to the base within 1e-3: the frame fitted to the nodes leans a little under
    the weight (3D: 1.1e-4 rad, the Kuhn mesh's shear, measured; 2D: 1e-9 relative), which
    turns the side facets at the base's edges by as much towards the ground, each adding
    that fraction of its area to its nodes'. 2D: the largest node's pressure R_n / (h * tributary
    length) stays within 1 % as well (the column's base is uniformly compressed when nu =
    0); Kuhn's tetrahedra give the 3D base nodes unequal areas and forces."""
    sim, state = settled
    c = state.contacts
    base = WIDTH ** (sim.model.dim - 1)
    rn = c.impulse[: c.count, 1]
    assert rn.sum() / DT / base == pytest.approx(RHO * G * H, rel=0.01)
    assert c.area[: c.count].sum() == pytest.approx(base, rel=1e-3)
    if sim.model.dim == 2:
        pressure = rn / DT / c.area[: c.count]
        assert pressure.max() == pytest.approx(RHO * G * H, rel=0.01)
        assert pressure.min() == pytest.approx(RHO * G * H, rel=0.01)
