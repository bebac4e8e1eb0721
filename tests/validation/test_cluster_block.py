"""A non-convex rigid block as a cluster of convex parts (ModelBuilder.add_cluster), against
closed forms of rigid-body statics and dynamics.

- Mass properties of an L block (two boxes) against the parallel-axis theorem written out by
  hand (Meriam and Kraige, Engineering Mechanics: Dynamics, appendix B: a box's moments
  m (b^2 + c^2) / 12 about its centre, moved by m (|d|^2 1 - d d^T)); tolerance 1e-12
  relative: the same sums in another order, round-off only.
- Statics of the L block resting on the ground on its foot: the normal contact forces sum to
  its weight m g and their resultant passes through its centre of mass (moment equilibrium),
  within 1e-6 relative (the NLGS tolerance 1e-10 leaves round-off-sized residuals; 1e-6 is
  above them and far below any physical error: a missed part would be off by tens of per cent).
- Overturning of a Gamma block (a stem standing on the ground, an arm over the void) with
  friction enough not to slide: it stands exactly when its centre of mass lies above the stem's
  foot, x_G < t, and tips over when x_G > t (statics of a rigid block on a rigid base: the
  moment of its weight about the foot's edge; Housner 1963's rocking block at rest). Arms that
  put x_G 3 % inside and 3 % outside the foot: at rest (displacement below 1e-9 m over 0.4 s)
  or turning about the foot's edge as the linearized rocking block, theta = (e / z_G)
  (cosh(p t) - 1), within 1e-4 (_rocking_angle).
- The L block sliding down a plane (gravity tilted by the slope a, as
  tests/validation/test_incline3d.py's "rotated gravity"): acceleration g (sin a - mu cos a)
  (Coulomb friction, closed form), velocity within 1e-3 of a_s t at every step after the
  fifth (the requirement of issue 18).
Mass properties in 2D (polygons, per metre of depth) and 3D (polyhedra); statics, sliding
and overturning run in 3D, overturning also in 2D.
"""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.geometry3d import relative_quaternions, rotation_matrix

G = 9.81
RHO = 2000.0
DT = 1e-3


def _box(x0, x1, y0, y1, z0, z1):
    return [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]


def _rect(x0, x1, y0, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


# The L block: foot [0, A] x [0, D] x [0, T], stem [0, T] x [0, D] x [T, H]
A, D, T, H = 1.0, 0.3, 0.2, 1.2


def _box_tensor(lo, hi, centre):
    """Inertia tensor [kg m^2] of the box lo..hi about `centre` (closed form, module doc)."""
    size = np.subtract(hi, lo)
    m = RHO * float(np.prod(size))
    own = m / 12.0 * np.diag([size[1] ** 2 + size[2] ** 2, size[0] ** 2 + size[2] ** 2,
                              size[0] ** 2 + size[1] ** 2])
    d = 0.5 * (np.add(lo, hi)) - centre
    return m, own + m * (d @ d * np.eye(3) - np.outer(d, d))


def _ground(builder, half=3.0):
    if builder.dim == 3:
        builder.add_block(_box(-half, half, -half, half, -0.2, 0.0), kind=sx.BodyKind.FIXED,
                          group="ground", name="ground")
    else:
        builder.add_block(_rect(-half, half, -0.2, 0.0), kind=sx.BodyKind.FIXED,
                          group="ground", name="ground")


def _laws(builder, mu):
    law = sx.ContactLaw(friction=mu)
    builder.set_law("block", "ground", law)
    builder.set_law("block", "block", law)


def test_mass_properties_of_an_l_block():
    b = sx.ModelBuilder(dim=3)
    body = b.add_cluster([_box(0, A, 0, D, 0, T), _box(0, T, 0, D, T, H)], density=RHO)
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = b.finalize()
    v1, v2 = A * D * T, T * D * (H - T)
    centre = (v1 * np.array([A / 2, D / 2, T / 2])
              + v2 * np.array([T / 2, D / 2, (T + H) / 2])) / (v1 + v2)
    m1, j1 = _box_tensor((0, 0, 0), (A, D, T), centre)
    m2, j2 = _box_tensor((0, 0, T), (T, D, H), centre)
    assert model.body_mass[body] == pytest.approx(m1 + m2, rel=1e-12)
    np.testing.assert_allclose(model.body_q0[body, :3], centre, rtol=1e-12)
    r = rotation_matrix(model.body_q0[body, 3:])
    tensor = r @ np.diag(model.body_inertia[body]) @ r.T
    np.testing.assert_allclose(tensor, j1 + j2, rtol=0, atol=1e-12 * np.abs(j1 + j2).max())

    # 2D: the same L in the (x, z) plane, per metre of depth: polar moment about G
    b2 = sx.ModelBuilder()
    body = b2.add_cluster([_rect(0, A, 0, T), _rect(0, T, T, H)], density=RHO)
    b2.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = b2.finalize()
    a1, a2 = A * T, T * (H - T)
    cx = (a1 * A / 2 + a2 * T / 2) / (a1 + a2)
    cy = (a1 * T / 2 + a2 * (T + H) / 2) / (a1 + a2)
    polar = (a1 * ((A**2 + T**2) / 12 + (A / 2 - cx) ** 2 + (T / 2 - cy) ** 2)
             + a2 * ((T**2 + (H - T) ** 2) / 12 + (T / 2 - cx) ** 2 + ((T + H) / 2 - cy) ** 2))
    assert model.body_mass[body] == pytest.approx(RHO * (a1 + a2), rel=1e-12)
    np.testing.assert_allclose(model.body_q0[body, :2], (cx, cy), rtol=1e-12)
    assert model.body_inertia[body] == pytest.approx(RHO * polar, rel=1e-12)


def _sim(model):
    return sx.Simulation(model, dt=DT, solver=sx.NLGS(tolerance=1e-10, max_iterations=2000))


def test_l_block_at_rest_carries_its_weight_through_its_centre_of_mass():
    b = sx.ModelBuilder(dim=3)
    _ground(b)
    body = b.add_cluster([_box(0, A, 0, D, 0, T), _box(0, T, 0, D, T, H)], density=RHO)
    _laws(b, 0.6)
    model = b.finalize()
    sim = _sim(model)
    state = sim.initial_state()
    for _ in range(100):
        sim.step(state)
    assert np.all(sim.log.converged)
    c = state.contacts
    n = c.count
    assert set(c.candidate[:n]) | set(c.antagonist[:n]) == {0, body}  # bodies, not parts
    normal = c.impulse[:n, 1] / DT  # [N], the foot's four corners
    weight = model.body_mass[body] * G
    assert normal.sum() == pytest.approx(weight, rel=1e-6)
    resultant = (normal[:, None] * c.point[:n, :2]).sum(axis=0) / normal.sum()
    np.testing.assert_allclose(resultant, state.body_q[body, :2], rtol=0,
                               atol=1e-6 * A)
    assert np.abs(state.body_q[body, :3] - model.body_q0[body, :3]).max() < 1e-9


def _gamma(arm, dim):
    """A stem [0, T] x [0, D] x [0, H] on the ground and an arm [T, arm] x [0, D] x [H - T, H]
    over the void; returns the model, the body and x_G [m]."""
    b = sx.ModelBuilder(dim=dim)
    _ground(b)
    if dim == 3:
        parts = [_box(0, T, 0, D, 0, H), _box(T, arm, 0, D, H - T, H)]
    else:
        parts = [_rect(0, T, 0, H), _rect(T, arm, H - T, H)]
    body = b.add_cluster(parts, density=RHO)
    _laws(b, 0.8)
    stem, over = T * H, (arm - T) * T
    return b.finalize(), body, (stem * T / 2 + over * (T + arm) / 2) / (stem + over)


def _arm(x_g):
    """The arm's end [m] that puts the Gamma block's centre of mass at x_g (closed form of
    x_G = (T H T/2 + (e - T) T (T + e)/2) / (T H + (e - T) T), solved for e)."""
    # (e^2 - T^2) T / 2 - x_g (e - T) T = x_g T H - T^2 H / 2
    # e^2 / 2 - x_g e + (x_g T - T^2 / 2 - x_g H + T H / 2) = 0
    c = x_g * T - T * T / 2 - x_g * H + T * H / 2
    return x_g + math.sqrt(x_g * x_g - 2.0 * c)


def _turned(model, body, q, dim):
    """Rotation angle [rad] of body from its initial orientation (2D: clockwise positive)."""
    if dim == 2:
        return -float(q[body, 2] - model.body_q0[body, 2])
    w = relative_quaternions(q[body:body + 1, 3:], model.body_q0[body:body + 1, 3:])[0, 0]
    return 2.0 * math.acos(min(1.0, abs(float(w))))


def _rocking_angle(model, body, x_g, dim, t):
    """Closed form of the rotation [rad] about the foot's edge after t [s] from rest:
    I_O theta'' = m g (e cos theta + z_G sin theta) ~ m g (e + z_G theta), e = x_G - T,
    so theta = (e / z_G) (cosh(p t) - 1), p^2 = m g z_G / I_O (Housner 1963, the rocking
    block linearized about its start), I_O = I_G + m (e^2 + z_G^2) about the edge."""
    m = float(model.body_mass[body])
    e = x_g - T
    if dim == 3:
        r = rotation_matrix(model.body_q0[body, 3:])
        i_g = float((r @ np.diag(model.body_inertia[body]) @ r.T)[1, 1])  # about y
        z_g = float(model.body_q0[body, 2])
    else:
        i_g, z_g = float(model.body_inertia[body]), float(model.body_q0[body, 1])
    p = math.sqrt(m * G * z_g / (i_g + m * (e * e + z_g * z_g)))
    return e / z_g * (math.cosh(p * t) - 1.0)


@pytest.mark.parametrize(("ratio", "dim"), [(0.97, 3), (1.03, 3), (1.03, 2)])
def test_gamma_block_stands_or_tips_as_its_centre_of_mass_lies_over_its_foot(ratio, dim):
    """Stands (moves less than 1e-9 m in 0.4 s) with x_G 3 % inside the foot; 3 % outside,
    turns about the foot's edge as the closed form (_rocking_angle) within 1e-4 relative
    (the linearization's theta^2 / 6 < 1e-5 at 0.4 s, the step's O(h^2) below it)."""
    model, body, x_g = _gamma(_arm(ratio * T), dim)
    assert x_g == pytest.approx(ratio * T, rel=1e-12)
    sim = _sim(model)
    state = sim.initial_state()
    steps = 400
    for _ in range(steps):
        sim.step(state)
    assert np.all(sim.log.converged)
    moved = np.abs(state.body_q[body, :dim] - model.body_q0[body, :dim]).max()
    if ratio < 1.0:
        assert moved < 1e-9
    else:
        expected = _rocking_angle(model, body, x_g, dim, steps * DT)
        assert math.degrees(expected) > 0.4  # far from rest: 0.42 degrees
        assert _turned(model, body, state.body_q, dim) == pytest.approx(expected, rel=1e-4)
        assert state.body_q[body, 0] > model.body_q0[body, 0]  # over the arm's side


@pytest.mark.parametrize(("slope_deg", "mu"), [(30.0, 0.3)])
def test_l_block_slides_down_a_slope_with_coulomb_acceleration(slope_deg, mu):
    slope = math.radians(slope_deg)
    down = np.array([1.0, 0.0, 0.0])
    gravity = G * (math.sin(slope) * down - math.cos(slope) * np.array([0.0, 0.0, 1.0]))
    b = sx.ModelBuilder(dim=3, gravity=gravity)
    _ground(b, half=20.0)
    # the stem at the front, down the slope: the foot's leading edge is not lifted
    body = b.add_cluster([_box(0, A, 0, D, 0, T), _box(A - T, A, 0, D, T, 0.6)], density=RHO)
    _laws(b, mu)
    model = b.finalize()
    sim = _sim(model)
    state = sim.initial_state()
    accel = G * (math.sin(slope) - mu * math.cos(slope))
    vel = []
    for _ in range(500):
        sim.step(state)
        vel.append(float(state.body_v[body, :3] @ down))
    assert np.all(sim.log.converged)
    t = DT * np.arange(1, len(vel) + 1)
    assert np.all(np.abs(np.array(vel[5:]) - accel * t[5:]) <= 1e-3 * accel * t[5:])
