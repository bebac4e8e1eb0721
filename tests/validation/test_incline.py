"""A block on an inclined plane with Coulomb friction (closed form, e.g. any statics/dynamics
textbook; Coulomb's law as in NSCD.md / M. Jean, CMAME 177, 1999).

A block resting on a plane of slope a with friction coefficient mu
- sticks for tan(a) < mu: it stays at rest for ever;
- slides for tan(a) > mu with constant acceleration a_s = g (sin a - mu cos a) along the slope.

Two equivalent set-ups are used:
- "rotated gravity": the plane and the block are axis-aligned rectangles on a horizontal fixed
  plane and gravity is rotated, g = |g| (sin a, -cos a), which makes the block slide in +x;
- "rotated geometry": gravity is vertical and both the fixed plane and the block are rectangles
  rotated by -a about the origin (the block rests exactly on the plane's top face), so the
  contact frame is not axis-aligned.
Tolerances: sliding velocity along the slope within 1 % of a_s t at every step after the first
(in practice it agrees to round-off, as theta = 0.5 is exact under constant forces); sticking:
displacement below 1e-9 m after 1 s and the block never moves off the plane.
"""

import math

import numpy as np
import pytest

import saxum as sx

G = 9.81
DT = 1e-3
DURATION = 1.0


def _rotate(points, angle):
    c, s = math.cos(angle), math.sin(angle)
    return [(c * x - s * y, s * x + c * y) for x, y in points]


def _incline(slope, mu, setup, kind):
    """Returns (model, block index, unit vector down the slope, unit normal of the plane)."""
    plane = [(-5.0, -0.2), (20.0, -0.2), (20.0, 0.0), (-5.0, 0.0)]
    block = [(0.0, 0.0), (0.4, 0.0), (0.4, 0.2), (0.0, 0.2)]
    if setup == "rotated gravity":
        builder = sx.ModelBuilder(gravity=(G * math.sin(slope), -G * math.cos(slope)))
        down, normal = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    else:
        builder = sx.ModelBuilder(gravity=(0.0, -G))
        plane, block = _rotate(plane, -slope), _rotate(block, -slope)
        down = np.array([math.cos(slope), -math.sin(slope)])
        normal = np.array([math.sin(slope), math.cos(slope)])
    builder.add_block(plane, kind=sx.BodyKind.FIXED, group="plane", name="plane")
    body = builder.add_block(block, density=2000.0, name="slider")
    law = sx.ContactLaw(friction=mu, kind=kind)
    builder.set_law("block", "plane", law)
    builder.set_law("block", "block", law)
    return builder.finalize(), body, down, normal


SETUPS = ["rotated gravity", "rotated geometry"]
LAWS = [sx.LawKind.SIGNORINI_COULOMB, sx.LawKind.GAP_SIGNORINI_COULOMB]


def _run(slope, mu, setup, kind):
    model, body, down, normal = _incline(slope, mu, setup, kind)
    sim = sx.Simulation(model, dt=DT, solver=sx.NLGS(tolerance=1e-10, max_iterations=500))
    state = sim.initial_state()
    x0 = state.body_q[body, :2].copy()
    along, off, vel, spin = [], [], [], []
    for _ in range(round(DURATION / DT)):
        sim.step(state)
        d = state.body_q[body, :2] - x0
        along.append(float(d @ down))
        off.append(float(d @ normal))
        vel.append(float(state.body_v[body, :2] @ down))
        spin.append(state.body_q[body, 2] - model.body_q0[body, 2])
    assert np.all(sim.log.converged)
    return np.array(along), np.array(off), np.array(vel), np.array(spin)


@pytest.mark.parametrize("setup", SETUPS)
@pytest.mark.parametrize("kind", LAWS, ids=lambda k: k.name)
@pytest.mark.parametrize(("slope_deg", "mu"), [(30.0, 0.7), (25.0, 0.48)])
def test_block_sticks_below_friction_angle(slope_deg, mu, setup, kind):
    slope = math.radians(slope_deg)
    assert math.tan(slope) < mu
    along, off, vel, spin = _run(slope, mu, setup, kind)
    assert np.abs(along).max() < 1e-9
    assert np.abs(off).max() < 1e-9
    assert np.abs(spin).max() < 1e-9
    assert np.abs(vel).max() < 1e-9


@pytest.mark.parametrize("setup", SETUPS)
@pytest.mark.parametrize("kind", LAWS, ids=lambda k: k.name)
@pytest.mark.parametrize(("slope_deg", "mu"), [(30.0, 0.5), (30.0, 0.3), (20.0, 0.0),
                                               (25.0, 0.45)])
def test_block_slides_with_coulomb_acceleration(slope_deg, mu, setup, kind):
    slope = math.radians(slope_deg)
    assert math.tan(slope) > mu
    accel = G * (math.sin(slope) - mu * math.cos(slope))
    along, off, vel, spin = _run(slope, mu, setup, kind)
    t = DT * np.arange(1, len(vel) + 1)
    # velocity along the slope vs a_s t after the first steps, within 1 %
    assert np.all(np.abs(vel[5:] - accel * t[5:]) <= 0.01 * accel * t[5:])
    # displacement vs a_s t^2 / 2 at the end, within 1 %
    assert along[-1] == pytest.approx(0.5 * accel * t[-1] ** 2, rel=0.01)
    # it slides flat on the plane: no lift-off, sinking or tipping
    assert np.abs(off).max() < 1e-9
    assert np.abs(spin).max() < 1e-9
