"""Onset of rocking under a constant horizontal acceleration (static closed form).

A rigid block of width b and height h on a rigid base, friction high enough to prevent sliding,
under gravity g and a uniform horizontal acceleration a (a body force m a, e.g. a quasi-static
seismic load factor) starts to rock about its leeward corner when the overturning moment
m a h/2 exceeds the restoring moment m g b/2, i.e. for a > g b/h (G.W. Housner, BSSA 53, 1963;
also the classical "equivalent static" rocking criterion, Makris & Konstantinidis, EESD 32,
2003). Block b/h = 0.2, mu = 1 (a/g = 0.2 < mu, no sliding); both the inelastic
Signorini-Coulomb law and the gap-based variant are run.

- a = 0.98 g b/h: the block must stay at rest: rotation below 1e-9 rad and displacement below
  1e-9 m after 1 s.
- a = 1.02 g b/h: it must uplift: the (clockwise) rotation grows monotonically, exceeds
  1e-3 rad after 1 s and matches, within 1 %, the rotation about the leeward corner given by
  the rigid-pivot equation I_O phi'' = m R [a cos(alpha - phi) - g sin(alpha - phi)]
  (R half diagonal, I_O = m (b^2 + h^2) / 3), integrated by scipy to 1e-12.
dt = 1e-3 s, theta = 0.5.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import saxum as sx

WIDTH, HEIGHT = 0.2, 1.0
G = 9.81
DT = 1e-3
DURATION = 1.0


def _block_under(accel, kind):
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-2.0, -0.2), (2.0, -0.2), (2.0, 0.0), (-2.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground", name="ground")
    body = b.add_block([(0.0, 0.0), (WIDTH, 0.0), (WIDTH, HEIGHT), (0.0, HEIGHT)],
                       density=2000.0, name="rocker")
    law = sx.ContactLaw(friction=1.0, kind=kind)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    b.add_acceleration(lambda t: (accel, 0.0))
    return b.finalize(), body


def _run(factor, kind):
    accel = factor * G * WIDTH / HEIGHT
    model, body = _block_under(accel, kind)
    sim = sx.Simulation(model, dt=DT, solver=sx.NLGS(tolerance=1e-10, max_iterations=2000))
    state = sim.initial_state()
    rotation, shift = [], []
    for _ in range(round(DURATION / DT)):
        sim.step(state)
        rotation.append(state.body_q[body, 2] - model.body_q0[body, 2])
        shift.append(float(np.hypot(*(state.body_q[body, :2] - model.body_q0[body, :2]))))
    return model, body, sim, np.array(rotation), np.array(shift), accel


KINDS = [sx.LawKind.SIGNORINI_COULOMB, sx.LawKind.GAP_SIGNORINI_COULOMB]


@pytest.mark.parametrize("kind", KINDS, ids=lambda k: k.name)
def test_block_stays_at_rest_below_threshold(kind):
    _, _, sim, rotation, shift, _ = _run(0.98, kind)
    assert np.abs(rotation).max() < 1e-9
    assert shift.max() < 1e-9
    assert np.all(sim.log.converged)


@pytest.mark.parametrize("kind", KINDS, ids=lambda k: k.name)
def test_block_uplifts_above_threshold(kind):
    model, body, sim, rotation, _, accel = _run(1.02, kind)
    t = DURATION
    # +x acceleration tips the block about its right corner: clockwise, theta < 0
    tip = -rotation
    assert tip[-1] > 1e-3
    assert np.all(np.diff(tip[10:]) > 0.0)
    # rigid rotation about the leeward corner: I_O phi'' = m R [a cos(alpha - phi)
    # - g sin(alpha - phi)], integrated to 1e-12 with scipy; the simulated tilt within 1 %
    alpha = math.atan(WIDTH / HEIGHT)
    r_half = 0.5 * math.hypot(WIDTH, HEIGHT)
    inertia_per_mass = (WIDTH**2 + HEIGHT**2) / 3.0
    assert model.body_inertia[body] / model.body_mass[body] + r_half**2 == pytest.approx(
        inertia_per_mass, rel=1e-12)

    def pivot(_, y):
        return [y[1], r_half * (accel * math.cos(alpha - y[0]) - G * math.sin(alpha - y[0]))
                / inertia_per_mass]

    exact = solve_ivp(pivot, (0.0, t), [0.0, 0.0], rtol=1e-12, atol=1e-14).y[0, -1]
    assert tip[-1] == pytest.approx(exact, rel=0.01)
    assert np.all(sim.log.converged)
