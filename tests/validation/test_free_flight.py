"""Free flight of a spinning block: the closed-form solution of rigid-body dynamics.

A rigid body with no contact partner under uniform gravity g has, exactly,

    x(t) = x0 + v0 t + g t^2 / 2,    v(t) = v0 + g t,    theta(t) = theta0 + omega0 t,

(Newton-Euler equations; in 2D the gyroscopic term vanishes). The Moreau-Jean scheme with
theta = 0.5 is the trapezoidal rule on q and exact for a constant force (NSCD.md; M. Jean,
CMAME 177, 1999), so the discrete trajectory must match the parabola to round-off:
tolerance 1e-12 relative to the distance travelled (rotation: 1e-12 relative to the angle
turned). With theta = 1 the position update is q += h v_end, which is off by g h t / 2; that
closed-form discrete error is checked as well, to show the first check is not vacuous.
"""

import math

import numpy as np
import pytest

import saxum as sx

G = (0.7, -9.81)
V0 = (3.0, 5.0, 7.5)  # vx [m/s], vy [m/s], omega [rad/s]
DT = 1e-3
STEPS = 1500


def _spinning_block():
    """A single free pentagon (not symmetric, so the centroid is not a vertex average)."""
    b = sx.ModelBuilder(gravity=G)
    verts = [(0.0, 0.0), (0.5, -0.1), (0.8, 0.3), (0.45, 0.7), (-0.1, 0.4)]
    body = b.add_block(verts, density=1500.0, name="flyer")
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    return b.finalize(), body


def _fly(theta):
    model, body = _spinning_block()
    sim = sx.Simulation(model, dt=DT, theta=theta)
    state = sim.initial_state()
    state.body_v[body] = V0
    q0 = state.body_q[body].copy()
    sim.run(state, STEPS * DT)
    return model, sim, state, body, q0


def test_free_flight_follows_parabola_to_round_off():
    model, sim, state, body, q0 = _fly(0.5)
    t = STEPS * DT
    assert state.time == pytest.approx(t, rel=1e-12)
    g = np.array(G)
    v0 = np.array(V0[:2])
    expected_x = q0[:2] + v0 * t + 0.5 * g * t * t
    travelled = float(np.hypot(*(expected_x - q0[:2])))
    assert travelled > 5.0
    assert np.all(np.abs(state.body_q[body, :2] - expected_x) <= 1e-12 * travelled)
    assert np.all(np.abs(state.body_v[body, :2] - (v0 + g * t)) <= 1e-12 * np.hypot(*(g * t)))
    turned = V0[2] * t
    assert abs(state.body_q[body, 2] - (q0[2] + turned)) <= 1e-12 * abs(turned)
    assert state.body_v[body, 2] == V0[2]  # no torque: the spin rate is constant, bit for bit
    # No contact partner: nothing detected, no solver work, energy grows only by the work of g.
    assert np.all(sim.log.contacts == 0)
    assert np.all(sim.log.iterations == 0)
    assert np.all(sim.log.converged)
    m, inertia = model.body_mass[body], model.body_inertia[body]
    v_end = v0 + g * t
    energy = 0.5 * m * float(v_end @ v_end) + 0.5 * inertia * V0[2] ** 2
    assert sim.log.kinetic_energy[-1] == pytest.approx(energy, rel=1e-12)


def test_free_flight_theta_one_has_the_known_first_order_error():
    """theta = 1: q_i+1 = q_i + h v_i+1, so x_N = x0 + v0 t + g t^2/2 + g h t/2 exactly."""
    _, _, state, body, q0 = _fly(1.0)
    t = STEPS * DT
    g = np.array(G)
    expected_x = q0[:2] + np.array(V0[:2]) * t + 0.5 * g * t * t + 0.5 * g * DT * t
    travelled = float(np.hypot(*(expected_x - q0[:2])))
    assert np.all(np.abs(state.body_q[body, :2] - expected_x) <= 1e-12 * travelled)
    # and it differs from the exact parabola by far more than the tolerance used above
    exact = q0[:2] + np.array(V0[:2]) * t + 0.5 * g * t * t
    assert abs(state.body_q[body, 1] - exact[1]) > 1e3 * 1e-12 * travelled
    assert math.isclose(state.body_q[body, 2], q0[2] + V0[2] * t, rel_tol=1e-12)
