"""Model building: properties from geometry, body kinds, laws per pair of groups, loads."""

import numpy as np
import pytest

import saxum as sx


def _box(x0, y0, w, h):
    return [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]


def test_mass_centre_and_inertia_come_from_the_geometry():
    b = sx.ModelBuilder()
    k = b.add_block(_box(1.0, 2.0, 0.4, 0.2), density=2500.0)
    b.set_law("block", "block", sx.ContactLaw(0.5))
    m = b.finalize()
    mass = 2500.0 * 0.4 * 0.2
    assert m.body_mass[k] == pytest.approx(mass, rel=1e-14)
    assert m.body_inertia[k] == pytest.approx(mass * (0.4**2 + 0.2**2) / 12.0, rel=1e-12)
    assert m.body_q0[k] == pytest.approx([1.2, 2.1, 0.0], abs=1e-14)
    assert m.body_inv_mass[k] == pytest.approx([1 / mass, 1 / mass, 1 / m.body_inertia[k]])
    assert np.allclose(m.vertices(k), _box(1.0, 2.0, 0.4, 0.2), atol=1e-14)


def test_laws_are_looked_up_per_pair_of_groups():
    b = sx.ModelBuilder()
    b.add_block(_box(-1, -0.1, 2, 0.1), kind=sx.BodyKind.FIXED, group="support")
    b.add_block(_box(0, 0, 0.2, 0.2), density=2000.0, group="stone")
    b.add_block(_box(0, 0.2, 0.2, 0.2), density=1800.0, group="brick")
    stone_support = sx.ContactLaw(0.7)
    b.set_law("stone", "support", stone_support)
    b.set_law("brick", "stone", sx.ContactLaw(0.4))
    b.set_law("brick", "brick", sx.ContactLaw(0.4))
    b.set_law("stone", "stone", sx.ContactLaw(0.4))
    b.set_law("brick", "support", sx.ContactLaw(0.3))
    m = b.finalize()
    g = {name: i for i, name in enumerate(m.group_names)}
    assert m.laws[m.group_law[g["stone"], g["support"]]] == stone_support
    assert m.law_friction[m.group_law[g["brick"], g["stone"]]] == 0.4
    assert m.group_law[g["stone"], g["brick"]] == m.group_law[g["brick"], g["stone"]]
    assert m.group_law[g["support"], g["support"]] == -1  # fixed-fixed never meets


def test_fixed_and_driven_bodies_have_no_inverse_mass():
    b = sx.ModelBuilder()
    b.add_block(_box(0, 0, 1, 1), kind=sx.BodyKind.FIXED)
    b.add_block(_box(2, 0, 1, 1), kind=sx.BodyKind.DRIVEN, motion=lambda t: (0.0, 0.0, 0.0))
    b.set_law("block", "block", sx.ContactLaw(0.5))
    m = b.finalize()
    assert np.all(m.body_inv_mass == 0.0)
    assert list(m.body_motion) == [-1, 0]


def test_driven_platform_carries_a_block_by_friction():
    """A platform driven at 0.1 m/s (imposed from t = 0) carries a block resting on it:
    with mu = 0.8 and an impulsive start the block first slides, then sticks; afterwards it
    moves at the platform's velocity (Coulomb: it cannot slip once relative motion stops)."""
    speed = 0.1
    b = sx.ModelBuilder()
    b.add_block(_box(-2, -0.1, 4, 0.1), kind=sx.BodyKind.DRIVEN, group="platform",
                motion=lambda t: (speed, 0.0, 0.0))
    b.add_block(_box(0, 0, 0.2, 0.2), density=2000.0)
    law = sx.ContactLaw(0.8)
    b.set_law("block", "platform", law)
    b.set_law("block", "block", law)
    m = b.finalize()
    sim = sx.Simulation(m, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 1.0)
    assert state.body_q[0, 0] - m.body_q0[0, 0] == pytest.approx(speed * 1.0, rel=1e-9)
    assert state.body_v[1, 0] == pytest.approx(speed, rel=1e-6)
    # the block reached the platform speed after sliding for v / (mu g) = 12.7 ms
    slip = speed * speed / (2 * 0.8 * 9.81)
    assert state.body_q[1, 0] - m.body_q0[1, 0] == pytest.approx(speed * 1.0 - slip, rel=2e-2)


def test_applied_force_accelerates_a_free_body():
    b = sx.ModelBuilder(gravity=(0.0, 0.0))
    k = b.add_block(_box(0, 0, 0.5, 0.5), density=1000.0)
    b.set_law("block", "block", sx.ContactLaw(0.5))
    b.add_force([k], lambda t: (10.0 * t, 0.0, 2.0))
    m = b.finalize()
    sim = sx.Simulation(m, dt=1e-2)
    state = sim.initial_state()
    sim.run(state, 1.0)
    mass, inertia = m.body_mass[k], m.body_inertia[k]
    # F = 10 t: v = 5 t^2 / m (the theta = 0.5 average of a linear force is exact)
    assert state.body_v[k, 0] == pytest.approx(5.0 / mass, rel=1e-12)
    assert state.body_v[k, 2] == pytest.approx(2.0 / inertia, rel=1e-12)
