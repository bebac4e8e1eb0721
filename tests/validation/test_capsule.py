"""A capsule (2D stadium: a segment of length L with round ends of radius r) on planes, against
closed forms of rigid-body statics and dynamics (e.g. J. L. Meriam, L. G. Kraige, Engineering
Mechanics: Dynamics, a block on an incline; Coulomb's law as in NSCD.md).

- Lying on a horizontal plane, it touches it at its two end circles and holds: zero drift
  (below 1e-12 m, round-off of the positions), and the two contacts' normal impulses over a
  step sum to m g dt within 1e-9 relative (statics, NLGS tolerance 1e-12).
- A block lying on a fixed capsule's flat side holds on its two bottom corners, the same
  statics (there the capsule is the candidate: it takes -m g dt).
- Dropped flat from a height h, it lands at the free-fall time sqrt(2 h / g) within one step
  dt (the time stepping closes a gap at the end of a step), without turning.
- Lying along a plane of slope a, both ends touching so that it cannot roll: it sticks when
  mu > tan(a) (no motion beyond 1e-12 m), and with mu < tan(a) slides at g (sin a - mu cos a)
  within 1e-3 relative (issue 18's tolerance; theta = 0.5 integrates the constant forces
  exactly, so the agreement is to round-off in practice).
"""

import math

import numpy as np
import pytest

import saxum as sx

G = 9.81
DT = 1e-3
LENGTH, RADIUS, DENSITY = 0.4, 0.05, 2000.0
SLOPE = 0.3  # [rad]; tan = 0.309


def _capsule_on_plane(slope=0.0, lift=0.0, mu=0.5):
    """A fixed plane tilted by `slope` down +x and a capsule lying along it, `lift` [m] above;
    returns (model, capsule, unit vector down the slope, unit normal)."""
    c, s = math.cos(slope), math.sin(slope)
    down, normal = np.array([c, -s]), np.array([s, c])
    builder = sx.ModelBuilder()
    builder.add_plane((0.0, 0.0), normal, 3.0, group="plane", name="plane")
    body = builder.add_capsule((RADIUS + lift) * normal, LENGTH, RADIUS, angle=-slope,
                               density=DENSITY, name="capsule")
    builder.set_law("block", "plane", sx.ContactLaw(friction=mu))
    builder.set_law("block", "block", sx.ContactLaw(friction=mu))
    return builder.finalize(), body, down, normal


def _simulation(model):
    return sx.Simulation(model, dt=DT, solver=sx.NLGS(tolerance=1e-12, max_iterations=1000))


def test_capsule_lying_on_a_plane_holds_on_its_two_ends():
    model, body, _, _ = _capsule_on_plane()
    sim = _simulation(model)
    state = sim.initial_state()
    sim.run(state, 0.2)
    c = state.contacts
    mine = np.flatnonzero(c.candidate[: c.count] == body)
    assert np.all(sim.log.converged)
    assert np.abs(state.body_q - model.body_q0).max() < 1e-12
    assert len(mine) == 2
    assert c.point[mine, 0] == pytest.approx([-0.5 * LENGTH, 0.5 * LENGTH], abs=1e-12)
    mass = DENSITY * (2.0 * RADIUS * LENGTH + math.pi * RADIUS**2)
    assert model.body_mass[body] == pytest.approx(mass, rel=1e-14)
    assert c.impulse[mine, 1].sum() == pytest.approx(mass * G * DT, rel=1e-9)


def test_block_on_a_capsule_holds_on_its_two_corners():
    builder = sx.ModelBuilder()
    beam = builder.add_capsule((0.0, 0.0), 1.0, RADIUS, kind=sx.BodyKind.FIXED, group="ground")
    brick = builder.add_block([(-0.2, RADIUS), (0.2, RADIUS), (0.2, RADIUS + 0.1),
                               (-0.2, RADIUS + 0.1)], density=DENSITY)
    builder.set_law("block", "ground", sx.ContactLaw(friction=0.5))
    builder.set_law("block", "block", sx.ContactLaw(friction=0.5))
    model = builder.finalize()
    sim = _simulation(model)
    state = sim.initial_state()
    sim.run(state, 0.2)
    c = state.contacts
    assert np.all(sim.log.converged)
    assert np.abs(state.body_q - model.body_q0).max() < 1e-12
    assert c.count == 2 and np.all(c.candidate[:2] == beam)
    assert sorted(c.point[:2, 0]) == pytest.approx([-0.2, 0.2], abs=1e-12)
    lift = np.einsum("ck,ckd->cd", c.impulse[:2], c.frame[:2])[:, 1].sum()
    assert -lift == pytest.approx(model.body_mass[brick] * G * DT, rel=1e-9)


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
    assert landed == pytest.approx(math.sqrt(2.0 * height / G), abs=DT)
    assert abs(state.body_v[body, 2]) < 1e-12  # flat: both ends land together
    assert abs(state.body_q[body, 1] - RADIUS) < 1e-6  # at rest on the plane


def _slide(mu, duration=0.3):
    """(displacement down the slope [m], velocity down it [m/s], largest motion normal to the
    plane [m]) of the capsule after `duration`."""
    model, body, down, normal = _capsule_on_plane(SLOPE, mu=mu)
    sim = _simulation(model)
    state = sim.initial_state()
    x0 = state.body_q[body, :2].copy()
    off = 0.0
    for _ in range(round(duration / DT)):
        sim.step(state)
        off = max(off, abs(float((state.body_q[body, :2] - x0) @ normal)))
    assert np.all(sim.log.converged)
    assert abs(state.body_q[body, 2] - model.body_q0[body, 2]) < 1e-12  # it cannot roll
    return float((state.body_q[body, :2] - x0) @ down), float(state.body_v[body, :2] @ down), off


def test_capsule_on_a_slope_sticks_above_tan():
    mu = 0.5
    assert mu > math.tan(SLOPE)
    moved, _, off = _slide(mu)
    assert abs(moved) < 1e-12 and off < 1e-12


def test_capsule_on_a_slope_slides_below_tan():
    mu = 0.2
    assert mu < math.tan(SLOPE)
    duration = 0.3
    _, speed, off = _slide(mu, duration)
    assert speed / duration == pytest.approx(G * (math.sin(SLOPE) - mu * math.cos(SLOPE)),
                                             rel=1e-3)
    assert off < 1e-12
