"""The conic solver (saxum.solver.ConicSolver: De Saxce's fixed point, Clarabel) alone on
problems with closed-form solutions, 2D and 3D.

- A block on a plane of slope a, friction mu (any statics/dynamics textbook; Coulomb's law as in
  NSCD.md): it sticks for tan a < mu (velocity 0), slides for tan a > mu with the acceleration
  g (sin a - mu cos a) along the slope. Gravity is rotated, g = |g| (sin a, -cos a[, 0]), the
  plane horizontal. Moreau-Jean with theta = 1/2 is exact under constant forces, so after n
  steps from rest the velocity is n h a_s: tolerance 1e-6 relative (the confirming sweeps'
  tolerance 1e-10 and the interior point's accuracy, far below it).
- A block lifted by an upward acceleration larger than g: no impulse, v = v_free (to 1e-12,
  round-off).
- A stack of two blocks at rest (a redundant, rank-deficient problem: four contact points on
  the ground and two between the blocks, 2D: 12 rows of H* for 6 dof; the impulses are not
  unique): the velocities are zero and the impulses carry the weight, sum R_n = m g h per
  joint (to 1e-8 relative: the confirming sweeps' tolerance 1e-10 bounds the velocity error).
"""

import math

import numpy as np
import pytest

import saxum as sx

G = 9.81
DT = 1e-3
STEPS = 20


def _slope_model(dim, slope, mu, lift=0.0):
    """A 0.4 x 0.2 (x 0.3) block on a fixed horizontal plane under gravity rotated by `slope`,
    plus an upward acceleration `lift` [m/s^2]."""
    gx, gy = G * math.sin(slope), -G * math.cos(slope) + lift
    if dim == 2:
        b = sx.ModelBuilder(gravity=(gx, gy))
        b.add_block([(-5.0, -0.2), (20.0, -0.2), (20.0, 0.0), (-5.0, 0.0)],
                    kind=sx.BodyKind.FIXED, group="plane")
        body = b.add_block([(0.0, 0.0), (0.4, 0.0), (0.4, 0.2), (0.0, 0.2)], density=2000.0)
    else:
        b = sx.ModelBuilder(gravity=(gx, 0.0, gy), dim=3)
        b.add_block(_box((-5.0, -2.0, -0.2), (20.0, 2.0, 0.0)), kind=sx.BodyKind.FIXED,
                    group="plane")
        body = b.add_block(_box((0.0, 0.0, 0.0), (0.4, 0.3, 0.2)), density=2000.0)
    law = sx.ContactLaw(friction=mu)
    b.set_law("block", "plane", law)
    b.set_law("block", "block", law)
    return b.finalize(), body


def _box(lo, hi):
    return [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]


def _run(model, steps=STEPS):
    solver = sx.ConicSolver(tolerance=1e-10)
    sim = sx.Simulation(model, dt=DT, solver=solver)
    state = sim.initial_state()
    for _ in range(steps):
        sim.step(state)
    assert np.all(sim.log.converged)
    assert np.all(sim.log.solver == 1)  # every step finished by the conic solver
    return sim, state


@pytest.mark.parametrize("dim", [2, 3])
def test_block_sticks_on_a_slope(dim):
    model, body = _slope_model(dim, math.radians(25.0), 0.6)  # tan 25 deg = 0.466 < 0.6
    _, state = _run(model)
    assert np.abs(state.body_v[body]).max() < 1e-9


@pytest.mark.parametrize("dim", [2, 3])
def test_block_slides_on_a_slope(dim):
    slope, mu = math.radians(35.0), 0.5  # tan 35 deg = 0.70 > 0.5
    model, body = _slope_model(dim, slope, mu)
    _, state = _run(model)
    expected = STEPS * DT * G * (math.sin(slope) - mu * math.cos(slope))
    assert state.body_v[body, 0] == pytest.approx(expected, rel=1e-6)
    assert abs(state.body_v[body, 1 if dim == 2 else 2]) < 1e-9 * expected


@pytest.mark.parametrize("dim", [2, 3])
def test_block_lifts_off(dim):
    model, body = _slope_model(dim, 0.0, 0.6, lift=1.5 * G)
    sim = sx.Simulation(model, dt=DT, solver=sx.ConicSolver(tolerance=1e-10))
    state = sim.initial_state()
    sim.step(state)
    # the lift exceeds the weight: every contact opens (R = 0); 1e-12 of the weight's impulse
    # m g h allows the conic solve's round-off
    weight = float(model.body_mass[body]) * G * DT
    assert np.abs(state.contacts.impulse[: state.contacts.count]).max() <= 1e-12 * weight
    up = 1 if dim == 2 else 2
    assert state.body_v[body, up] == pytest.approx(0.5 * G * DT, rel=1e-12)


def test_redundant_stack_at_rest():
    b = sx.ModelBuilder()
    b.add_block([(-1.0, -0.2), (1.0, -0.2), (1.0, 0.0), (-1.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground")
    b.add_block([(0.0, 0.0), (0.4, 0.0), (0.4, 0.2), (0.0, 0.2)], density=2000.0)
    b.add_block([(0.0, 0.2), (0.4, 0.2), (0.4, 0.4), (0.0, 0.4)], density=2000.0)
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = b.finalize()
    sim, state = _run(model, steps=5)
    assert np.abs(state.body_v).max() < 1e-9
    c = state.contacts
    on_ground = (c.antagonist[: c.count] == 0) | (c.candidate[: c.count] == 0)
    weight = 2000.0 * 0.4 * 0.2 * G * DT  # one block's weight over a step [N s]
    assert c.impulse[: c.count][on_ground, 1].sum() == pytest.approx(2 * weight, rel=1e-8)
    assert c.impulse[: c.count][~on_ground, 1].sum() == pytest.approx(weight, rel=1e-8)
