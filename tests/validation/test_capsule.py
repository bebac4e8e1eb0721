"""A capsule (2D stadium, 3D spherocylinder (LMGC90's CYLND): a segment of length L with round
ends of radius r) on planes, against closed forms of rigid-body statics and dynamics (e.g. J. L.
Meriam, L. G. Kraige, Engineering Mechanics: Dynamics, a block on an incline, rolling of a
wheel on an incline; Coulomb's law as in NSCD.md).

- Lying on a horizontal plane (3D: along a skew horizontal axis), it touches it at its two end
  circles (spheres) and holds: zero drift (below 1e-12 m, round-off of the positions), and the
  two contacts' normal impulses over a step sum to m g dt within 1e-9 relative (statics, NLGS
  tolerance 1e-12).
- A block lying on a fixed capsule's flat side holds on its two bottom corners, the same
  statics (there the capsule is the candidate: it takes -m g dt).
- Dropped flat from a height h, it lands at the free-fall time sqrt(2 h / g) within one step
  dt (the time stepping closes a gap at the end of a step), without turning (2D and 3D).
- Lying along a plane of slope a, both ends touching so that it cannot roll: it sticks when
  mu > tan(a) (no motion beyond 1e-12 m), and with mu < tan(a) slides at g (sin a - mu cos a)
  within 1e-3 relative (issue 18's tolerance; theta = 0.5 integrates the constant forces
  exactly, so the agreement is to round-off in practice).
- 3D, lying on that plane with its axis horizontal: with I = k m r^2 its moment of inertia
  about its axis (k from saxum.spherocylinder_properties: (V_c / 2 + 2/5 V_s) / (V_c + V_s),
  V_c = pi r^2 L the cylinder's volume, V_s = 4/3 pi r^3 the ends'; 0.486 here), it rolls
  without slipping when mu >= k tan(a) / (1 + k), its centre accelerating at g sin(a) / (1 +
  k) and spinning at v / r; with a smaller mu it slides at g (sin a - mu cos a) while friction
  spins it up at mu m g cos(a) r / I; 1e-3 relative on the accelerations after 0.3 s.
"""

import math

import numpy as np
import pytest
from slope_run import run_on_slope

import saxum as sx

G = 9.81
DT = 1e-3
LENGTH, RADIUS, DENSITY = 0.4, 0.05, 2000.0
SLOPE = 0.3  # [rad]; tan = 0.309
DURATION = 0.3  # [s] on the slope
VOLUME, AXIAL, _ = sx.spherocylinder_properties(LENGTH, RADIUS)
K = AXIAL / (VOLUME * RADIUS**2)  # 3D: I_axis / (m r^2)
SKEW = np.array([1.0, 2.0, 0.0]) / math.sqrt(5.0)  # a horizontal axis in 3D


def _capsule_on_plane(slope=0.0, lift=0.0, mu=0.5, dim=2, axis=(0.0, 1.0, 0.0)):
    """A fixed plane tilted by `slope` down +x and a capsule lying on it, `lift` [m] above:
    2D along the slope, 3D along `axis` (horizontal); returns (model, capsule, unit vector
    down the slope, unit normal)."""
    c, s = math.cos(slope), math.sin(slope)
    down, normal = np.array([c, -s]), np.array([s, c])
    builder = sx.ModelBuilder(dim=dim)
    if dim == 3:
        down, normal = np.array([c, 0.0, -s]), np.array([s, 0.0, c])
        builder.add_plane(np.zeros(3), normal, (3.0, 3.0), group="plane", name="plane")
        turn = {"axis": axis}
    else:
        builder.add_plane((0.0, 0.0), normal, 3.0, group="plane", name="plane")
        turn = {"angle": -slope}
    body = builder.add_capsule((RADIUS + lift) * normal, LENGTH, RADIUS, **turn,
                               density=DENSITY, name="capsule")
    builder.set_law("block", "plane", sx.ContactLaw(friction=mu))
    builder.set_law("block", "block", sx.ContactLaw(friction=mu))
    return builder.finalize(), body, down, normal


def _simulation(model):
    return sx.Simulation(model, dt=DT, solver=sx.NLGS(tolerance=1e-12, max_iterations=1000))


@pytest.mark.parametrize("dim", [2, 3])
def test_capsule_lying_on_a_plane_holds_on_its_two_ends(dim):
    model, body, _, _ = _capsule_on_plane(dim=dim, axis=SKEW)
    sim = _simulation(model)
    state = sim.initial_state()
    sim.run(state, 0.2)
    c = state.contacts
    mine = np.flatnonzero(c.candidate[: c.count] == body)
    assert np.all(sim.log.converged)
    assert np.abs(state.body_q - model.body_q0).max() < 1e-12
    assert len(mine) == 2
    axis = SKEW if dim == 3 else np.array([1.0, 0.0])
    assert c.point[mine] == pytest.approx(np.outer([-0.5 * LENGTH, 0.5 * LENGTH], axis),
                                          abs=1e-12)
    mass = DENSITY * (VOLUME if dim == 3 else 2.0 * RADIUS * LENGTH + math.pi * RADIUS**2)
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


@pytest.mark.parametrize("dim", [2, 3])
def test_capsule_dropped_flat_lands_at_the_free_fall_time(dim):
    height = 0.1
    model, body, _, _ = _capsule_on_plane(lift=height, dim=dim)
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
    # flat: both ends land together; no bounce (restitution 0)
    assert np.abs(state.body_v[body, dim:]).max() < 1e-12
    assert abs(state.body_q[body, dim - 1] - RADIUS) < 1e-6  # at rest on the plane


def _slide(mu, dim=2):
    """(displacement down the slope [m], velocity down it [m/s], largest motion normal to the
    plane [m], the body's angular velocity) of the capsule after DURATION: 2D lying along the
    slope (it cannot roll), 3D across it (the body frame's z, its axis, is the world's y)."""
    model, body, down, normal = _capsule_on_plane(SLOPE, mu=mu, dim=dim)
    sim = _simulation(model)
    state = sim.initial_state()
    x0 = state.body_q[body, :dim].copy()
    off = run_on_slope(sim, state, body, down, normal, DURATION)
    if dim == 2:
        assert abs(state.body_q[body, 2] - model.body_q0[body, 2]) < 1e-12  # it cannot roll
    return (float((state.body_q[body, :dim] - x0) @ down),
            float(state.body_v[body, :dim] @ down), off, state.body_v[body, dim:])


def test_capsule_on_a_slope_sticks_above_tan():
    mu = 0.5
    assert mu > math.tan(SLOPE)
    moved, _, off, _ = _slide(mu)
    assert abs(moved) < 1e-12 and off < 1e-12


def test_capsule_on_a_slope_slides_below_tan():
    mu = 0.2
    assert mu < math.tan(SLOPE)
    _, speed, off, _ = _slide(mu)
    assert speed / DURATION == pytest.approx(G * (math.sin(SLOPE) - mu * math.cos(SLOPE)),
                                             rel=1e-3)
    assert off < 1e-12


def test_capsule_rolls_without_slipping():
    mu = 0.5
    assert mu > K * math.tan(SLOPE) / (1 + K)
    _, speed, off, turn = _slide(mu, dim=3)
    accel = speed / DURATION
    assert accel == pytest.approx(G * math.sin(SLOPE) / (1 + K), rel=1e-3)
    assert turn[2] * RADIUS == pytest.approx(speed, rel=1e-3)  # v = omega r
    assert off < 1e-12


def test_capsule_rolls_and_slides_below_rolling_friction():
    mu = 0.05
    assert mu < K * math.tan(SLOPE) / (1 + K)
    _, speed, off, turn = _slide(mu, dim=3)
    assert speed / DURATION == pytest.approx(G * (math.sin(SLOPE) - mu * math.cos(SLOPE)),
                                             rel=1e-3)
    # mu m g cos(a) r / (k m r^2)
    assert turn[2] / DURATION == pytest.approx(mu * G * math.cos(SLOPE) / (K * RADIUS),
                                               rel=1e-3)
    assert off < 1e-12
