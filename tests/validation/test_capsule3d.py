"""A 3D capsule (spherocylinder, LMGC90's CYLND: a segment of length L with hemispherical ends
of radius r) on a plane, against closed forms of rigid-body statics and dynamics (J. L. Meriam,
L. G. Kraige, Engineering Mechanics: Dynamics: rolling of a wheel on an incline, a block on an
incline; Coulomb's law as in NSCD.md).

With m its mass and I = k m r^2 its moment of inertia about its axis (k from
saxum.spherocylinder_properties: (V_c / 2 + 2/5 V_s) / (V_c + V_s), V_c = pi r^2 L the
cylinder's volume, V_s = 4/3 pi r^3 the ends'; 0.486 here):
- Lying on a horizontal plane along a skew horizontal axis, it touches it at its two end
  spheres and holds: no drift beyond 1e-12 m (round-off of the positions), and the two
  contacts' normal impulses over a step sum to m g dt within 1e-9 relative (statics, NLGS
  tolerance 1e-10).
- Dropped flat from a height h, it lands at the free-fall time sqrt(2 h / g) within one step
  dt (the time stepping closes a gap at the end of a step) and comes to rest on the plane.
- Lying on a plane of slope a with its axis horizontal, it rolls without slipping when mu >=
  k tan(a) / (1 + k), its centre accelerating at g sin(a) / (1 + k) and spinning at v / r;
  with a smaller mu it slides at g (sin a - mu cos a) while friction spins it up at mu m g
  cos(a) r / I. Tolerance 1e-3 relative on the accelerations (issue 18's requirement; theta =
  0.5 integrates the constant forces exactly, so the agreement is to round-off in practice),
  after 0.3 s.
"""

import math

import numpy as np
import pytest

import saxum as sx

G = 9.81
DT = 1e-3
DURATION = 0.3
SLOPE = 0.3  # [rad]
LENGTH, RADIUS, DENSITY = 0.4, 0.05, 2000.0
VOLUME, AXIAL, _ = sx.spherocylinder_properties(LENGTH, RADIUS)
K = AXIAL / (VOLUME * RADIUS**2)  # I_axis / (m r^2)


def _capsule_on_plane(slope=0.0, axis=(0.0, 1.0, 0.0), lift=0.0, mu=0.5):
    """A fixed plane tilted by `slope` down +x and a capsule lying on it along `axis` (a
    horizontal direction), `lift` [m] above; returns (model, capsule, unit vector down the
    slope, unit normal)."""
    c, s = math.cos(slope), math.sin(slope)
    down, normal = np.array([c, 0.0, -s]), np.array([s, 0.0, c])
    builder = sx.ModelBuilder(dim=3)
    builder.add_plane(np.zeros(3), normal, (3.0, 3.0), group="plane", name="plane")
    body = builder.add_capsule((RADIUS + lift) * normal, LENGTH, RADIUS, axis=axis,
                               density=DENSITY, name="capsule")
    law = sx.ContactLaw(friction=mu)
    builder.set_law("block", "plane", law)
    builder.set_law("block", "block", law)
    return builder.finalize(), body, down, normal


def _simulation(model):
    return sx.Simulation(model, dt=DT, solver=sx.NLGS(tolerance=1e-10, max_iterations=500))


def test_capsule_lying_on_a_plane_holds_on_its_two_ends():
    axis = np.array([1.0, 2.0, 0.0]) / math.sqrt(5.0)
    model, body, _, _ = _capsule_on_plane(axis=axis)
    sim = _simulation(model)
    state = sim.initial_state()
    sim.run(state, 0.2)
    c = state.contacts
    mine = np.flatnonzero(c.candidate[: c.count] == body)
    assert np.all(sim.log.converged)
    assert np.abs(state.body_q - model.body_q0).max() < 1e-12
    assert len(mine) == 2
    ends = np.array([-0.5 * LENGTH * axis, 0.5 * LENGTH * axis])
    assert c.point[mine] == pytest.approx(ends, abs=1e-12)
    mass = DENSITY * VOLUME
    assert model.body_mass[body] == pytest.approx(mass, rel=1e-14)
    assert c.impulse[mine, 1].sum() == pytest.approx(mass * G * DT, rel=1e-9)


def test_capsule_dropped_flat_lands_at_the_free_fall_time():
    height = 0.1
    model, body, _, _ = _capsule_on_plane(lift=height)
    sim = _simulation(model)
    state = sim.initial_state()
    landed = None
    for _ in range(300):
        sim.step(state)
        c = state.contacts
        if landed is None and (c.impulse[: c.count, 1] > 0.0).any():
            landed = state.time
    assert np.all(sim.log.converged)
    assert landed == pytest.approx(math.sqrt(2.0 * height / G), abs=DT)
    # flat: both ends land together, it neither turns nor bounces (restitution 0)
    assert np.abs(state.body_v[body]).max() < 1e-9
    assert abs(state.body_q[body, 2] - RADIUS) < 1e-6  # at rest on the plane


def _roll(mu):
    """(acceleration along the slope [m/s^2], spin rate about the axis [rad/s], largest
    motion normal to the plane [m]) of the capsule after DURATION."""
    model, body, down, normal = _capsule_on_plane(SLOPE, mu=mu)
    sim = _simulation(model)
    state = sim.initial_state()
    x0 = state.body_q[body, :3].copy()
    off = 0.0
    for _ in range(round(DURATION / DT)):
        sim.step(state)
        off = max(off, abs(float((state.body_q[body, :3] - x0) @ normal)))
    assert np.all(sim.log.converged)
    # the body frame's z is the capsule's axis, the world's y: rolling down +x turns about +y
    spin = state.body_v[body, 5]
    return float(state.body_v[body, :3] @ down) / DURATION, spin, off


def test_capsule_rolls_without_slipping():
    mu = 0.5
    assert mu > K * math.tan(SLOPE) / (1 + K)
    accel, spin, off = _roll(mu)
    assert accel == pytest.approx(G * math.sin(SLOPE) / (1 + K), rel=1e-3)
    assert spin * RADIUS == pytest.approx(accel * DURATION, rel=1e-3)  # v = omega r
    assert off < 1e-12


def test_capsule_slides_below_rolling_friction():
    mu = 0.05
    assert mu < K * math.tan(SLOPE) / (1 + K)
    accel, spin, off = _roll(mu)
    assert accel == pytest.approx(G * (math.sin(SLOPE) - mu * math.cos(SLOPE)), rel=1e-3)
    # mu m g cos(a) r / (k m r^2)
    assert spin / DURATION == pytest.approx(mu * G * math.cos(SLOPE) / (K * RADIUS), rel=1e-3)
    assert off < 1e-12
