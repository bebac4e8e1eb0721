"""The rest solution of a step in 3D (saxum.solver.equilibrium, second-order cones) exists
exactly when the blocks can stand: static thresholds from closed forms and from the 2D limit
analysis, as in 2D (test_rest_solution.py).

By the lower-bound theorem of limit analysis for rigid blocks with Coulomb joints, a step from
rest has a rest solution exactly when contact impulses inside the friction cones
|R_T| <= mu R_n balance the loads of the step. References:
- a block (0.4 x 0.3 x 0.1 m, so that it slides before it tips: the line of its weight leaves
  the base only at tan a >= 3 > mu) on a ground under gravity tilted by a towards a random
  horizontal direction phi: it stays if tan a < mu (Coulomb, isotropic: the direction does not
  matter), checked on random slopes, friction coefficients and directions at least 1e-5
  (relative) from the threshold;
- a block b_x x b_y x h = 0.2 x 0.3 x 1.0 m turned by psi about the vertical, mu = 1, under a
  horizontal acceleration lambda g along the azimuth theta: it stays while the line of the
  resultant of its weight and the load passes through its base, lambda < lambda_c =
  1 / (h max(|cos(theta - psi)| / b_x, |sin(theta - psi)| / b_y)) (the rigid block's
  overturning about a base edge; b/h about that edge for a load normal to a face: Housner,
  BSSA 53, 1963), checked at 0.999 and 1.001 lambda_c for a load normal to a face and an
  oblique one;
- the 15-voussoir semicircular arch, t/R = 0.15, mu = 1, extruded 0.5 m (one block per voussoir
  through the depth, saxum.structures.extruded), under a horizontal load factor lambda in its
  plane: a plane problem, so it stands if lambda < lambda_c of the 2D four-hinge limit analysis
  computed independently of saxum (limit_analysis.py), checked at 0.999 and 1.001 lambda_c.
(Observed by bisection: the rest solution stops existing at tan a / mu = 1 - 7e-8, lambda /
lambda_c = 1 - 1.6e-7 for the oblique load on the block and 1 - 6e-7 for the arch: the barrier
needs room inside the cones.)
When it exists: every impulse strictly inside its cone, the loads balanced to 1e-10, the blocks
at rest and one NLGS sweep from it changes nothing; when it does not: the impulses and
velocities left as they were (rest_check.py, with the tolerances).
"""

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from limit_analysis import semicircular_four_hinge
from rest_check import check, first_step

import saxum as sx
from saxum.structures import extruded, semicircular_arch

G = 9.81


def _box(a, b, c):
    return np.array([(x, y, z) for x in (0.0, a) for y in (0.0, b) for z in (0.0, c)])


def _block(gravity, size, yaw=0.0, mu=1.0, load=None):
    """A block of `size` [m] turned by yaw [rad] about z on a fixed ground slab."""
    b = sx.ModelBuilder(dim=3, gravity=gravity)
    b.add_block(_box(4.0, 4.0, 0.2) - (2.0, 2.0, 0.2), kind=sx.BodyKind.FIXED, group="ground",
                name="ground")
    turn = np.array([[math.cos(yaw), -math.sin(yaw), 0.0], [math.sin(yaw), math.cos(yaw), 0.0],
                     [0.0, 0.0, 1.0]])
    b.add_block(_box(*size) @ turn.T, density=2000.0, name="block")
    b.set_law("block", "ground", sx.ContactLaw(friction=mu))
    b.set_law("block", "block", sx.ContactLaw(friction=mu))
    if load is not None:
        b.add_acceleration(lambda t: load)
    return b.finalize()


@given(slope=st.floats(0.0, 1.2), mu=st.floats(0.05, 1.5), phi=st.floats(0.0, 2.0 * math.pi))
def test_block_on_a_slope_in_any_direction_rests_exactly_below_the_friction_angle(slope, mu,
                                                                                   phi):
    margin = math.tan(slope) / mu - 1.0
    if abs(margin) < 1e-5:
        return
    gravity = G * np.array([math.sin(slope) * math.cos(phi), math.sin(slope) * math.sin(phi),
                            -math.cos(slope)])
    model = _block(tuple(gravity), (0.4, 0.3, 0.1), mu=mu)
    check(first_step(model), model, margin < 0.0)


@pytest.mark.parametrize("factor", [0.999, 1.001])
@pytest.mark.parametrize(("yaw", "azimuth"), [(0.5, 0.5), (-0.3, 2.2)])
def test_block_under_horizontal_load_in_any_direction_rests_below_overturning(yaw, azimuth,
                                                                              factor):
    bx, by, h = 0.2, 0.3, 1.0
    relative = azimuth - yaw
    limit = 1.0 / (h * max(abs(math.cos(relative)) / bx, abs(math.sin(relative)) / by))
    lam = factor * limit
    model = _block((0.0, 0.0, -G), (bx, by, h), yaw=yaw,
                   load=(lam * G * math.cos(azimuth), lam * G * math.sin(azimuth), 0.0))
    check(first_step(model), model, factor < 1.0)


@pytest.fixture(scope="module")
def lambda_c():
    return semicircular_four_hinge(1.0, 0.15, 15)[0]


@pytest.mark.parametrize("factor", [0.999, 1.001])
def test_extruded_arch_under_horizontal_load_rests_below_the_2d_collapse_factor(factor,
                                                                                lambda_c):
    arch = extruded(semicircular_arch(radius=1.0, thickness=0.15, voussoirs=15, friction=1.0),
                    0.5)
    load = (factor * lambda_c * G, 0.0, 0.0)
    model = dataclasses.replace(arch, accelerations=(lambda t: load,))
    check(first_step(model), model, factor < 1.0)
