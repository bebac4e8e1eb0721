"""Housner's rocking block: angular velocity ratio at impact.

G.W. Housner (1963), "The behavior of inverted pendulum structures during earthquakes",
Bull. Seismol. Soc. Am. 53(2), 403-417: a rigid rectangular block of width b and height h,
slenderness alpha = atan(b/h), rocking without sliding on a rigid base, loses kinetic energy
at each impact; if the impact is inelastic at the landing corner (it becomes the new pivot, the
old corner lifts off) and angular momentum about the new pivot is conserved, then

    omega_after / omega_before = 1 - 3/2 sin^2(alpha).

NSCD with the inelastic Signorini law (U_n+ = 0 at the active contacts) and Coulomb friction
(mu = 1, so the corners cannot slide) is expected to give exactly this value in the limit of
small time steps. Set-up: b/h = 0.2, the block rotated clockwise about its right bottom corner by
phi0 = 0.5 alpha (and 0.8 alpha), resting on that corner exactly on the ground surface, released
from rest. Tolerances: ratio within 2 % (the stated requirement); omega just before the impact
within 1 % of the energy-conservation value omega^2 = 2 m g R (cos(alpha - phi0) - cos(alpha)) /
I_O, R = half diagonal, I_O = m (b^2 + h^2) / 3 (the pivoting phase is conservative).
dt = 1e-4 s, theta = 0.5.
"""

import math

import numpy as np
import pytest

import saxum as sx

WIDTH, HEIGHT = 0.2, 1.0
ALPHA = math.atan(WIDTH / HEIGHT)
G = 9.81
DT = 1e-4


def _rotate_about(points, angle, centre):
    c, s = math.cos(angle), math.sin(angle)
    cx, cy = centre
    return [(cx + c * (x - cx) - s * (y - cy), cy + s * (x - cx) + c * (y - cy))
            for x, y in points]


def rocking_block(tilt, kind=sx.LawKind.SIGNORINI_COULOMB, mu=1.0):
    """The block tilted clockwise by `tilt` [rad] about its right bottom corner (WIDTH, 0)."""
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-2.0, -0.2), (2.0, -0.2), (2.0, 0.0), (-2.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground", name="ground")
    corners = [(0.0, 0.0), (WIDTH, 0.0), (WIDTH, HEIGHT), (0.0, HEIGHT)]
    body = b.add_block(_rotate_about(corners, -tilt, (WIDTH, 0.0)), density=2000.0,
                       name="rocker")
    law = sx.ContactLaw(friction=mu, kind=kind)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    return b.finalize(), body


@pytest.mark.parametrize("tilt_fraction", [0.5, 0.8])
def test_housner_coefficient_of_restitution(tilt_fraction):
    tilt = tilt_fraction * ALPHA
    model, body = rocking_block(tilt)
    # the lowest vertex lies on the ground surface (y = 0), none below it
    assert model.vertices(body)[:, 1].min() == pytest.approx(0.0, abs=1e-15)
    sim = sx.Simulation(model, dt=DT, solver=sx.NLGS(tolerance=1e-10, max_iterations=1000))
    state = sim.initial_state()
    omega = [0.0]
    impact = None
    for _ in range(round(0.8 / DT)):
        sim.step(state)
        omega.append(state.body_v[body, 2])
        # before the impact omega grows monotonically (the weight brings the block back)
        if omega[-1] < omega[-2] - 0.01 * abs(omega[-2]):
            impact = len(omega) - 1
            break
    assert impact is not None, "the block never landed on its second corner"
    assert np.all(sim.log.converged)
    before, after = omega[impact - 1], omega[impact]
    assert before > 0.0
    # it landed flat (rotation back to ~0) where it started: the pivot did not slide
    assert abs(state.body_q[body, 2] - tilt) < 1e-3 * ALPHA
    bottom = model.vertices(body, state.body_q)[:2]
    assert np.abs(bottom[:, 0] - [0.0, WIDTH]).max() < 1e-5 * WIDTH

    r_half = 0.5 * math.hypot(WIDTH, HEIGHT)
    inertia_corner = model.body_mass[body] * (WIDTH**2 + HEIGHT**2) / 3.0
    assert inertia_corner == pytest.approx(
        model.body_inertia[body] + model.body_mass[body] * r_half**2, rel=1e-12)
    expected_before = math.sqrt(
        2.0 * model.body_mass[body] * G * r_half * (math.cos(ALPHA - tilt) - math.cos(ALPHA))
        / inertia_corner)
    assert before == pytest.approx(expected_before, rel=0.01)

    housner = 1.0 - 1.5 * math.sin(ALPHA) ** 2
    assert after / before == pytest.approx(housner, rel=0.02)
