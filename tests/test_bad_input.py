"""Bad input is rejected early with an InputError (OverlapError for interpenetrating blocks)
whose message names the block, parameter, pair or groups at fault (saxum.errors)."""

import math
import re
import warnings

import numpy as np
import pytest

import saxum as sx
from saxum.structures import running_bond_wall

SQUARE = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]


def _one_block_model(**kwargs):
    b = sx.ModelBuilder(**kwargs)
    b.add_block(SQUARE, density=1000.0, name="cube")
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    return b.finalize()


# --- blocks -----------------------------------------------------------------------------------


@pytest.mark.parametrize(("vertices", "words"), [
    ([(0, 0), (2, 0), (1, 0.5), (2, 2), (0, 2)], "not strictly convex"),
    ([(0, 0), (1, 0)], "at least 3 vertices"),
    ([(0, 0), (1, 1), (3, 3)], "zero area"),
    ([(0, 0), (1, 0), (1, math.nan), (0, 1)], "NaN"),
    ([(0, 0), (1, 0), (1, 1), (1, 1), (0, 1)], "coincide"),
])
def test_bad_polygon_names_the_block(vertices, words):
    b = sx.ModelBuilder()
    b.add_block(SQUARE, density=1.0, name="good one")
    with pytest.raises(sx.InputError, match=re.escape(words)) as info:
        b.add_block(vertices, density=1000.0, name="voussoir 7")
    assert "voussoir 7" in str(info.value)
    assert b.body_count == 1  # the bad block was not added


def test_unnamed_bad_block_is_named_by_its_index():
    b = sx.ModelBuilder()
    b.add_block(SQUARE, density=1.0)
    with pytest.raises(sx.InputError, match="block 1"):
        b.add_block([(0, 0), (2, 0), (1, 0.5), (2, 2), (0, 2)], density=1.0)


@pytest.mark.parametrize("density", [0.0, -2000.0, math.nan, math.inf])
def test_free_block_needs_positive_density(density):
    b = sx.ModelBuilder()
    with pytest.raises(sx.InputError) as info:
        b.add_block(SQUARE, density=density, name="brick c1b1")
    assert "brick c1b1" in str(info.value)
    assert "density" in str(info.value)


def test_fixed_block_needs_no_density():
    b = sx.ModelBuilder()
    ground = b.add_block(SQUARE, kind=sx.BodyKind.FIXED, group="ground")
    b.add_block([(0, 1), (1, 1), (1, 2), (0, 2)], density=1.0)
    b.set_law("block", "ground", sx.ContactLaw(friction=0.5))
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    model = b.finalize()
    assert model.body_mass[ground] == 0.0
    assert np.all(model.body_inv_mass[ground] == 0.0)


def test_driven_block_needs_motion_and_only_driven_blocks_take_one():
    b = sx.ModelBuilder()
    with pytest.raises(sx.InputError, match="shaker.*motion"):
        b.add_block(SQUARE, kind=sx.BodyKind.DRIVEN, name="shaker")
    with pytest.raises(sx.InputError, match="table.*motion"):
        b.add_block(SQUARE, kind=sx.BodyKind.FIXED, motion=lambda t: (0, 0, 0), name="table")


def test_clockwise_vertices_are_accepted_and_normalized():
    b = sx.ModelBuilder()
    ccw = b.add_block(SQUARE, density=1000.0, name="ccw")
    cw = b.add_block([(x + 2.0, y) for x, y in SQUARE[::-1]], density=1000.0, name="cw")
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    m = b.finalize()
    assert m.body_mass[cw] == m.body_mass[ccw] == pytest.approx(1000.0)
    assert m.body_inertia[cw] == pytest.approx(m.body_inertia[ccw], rel=1e-14)
    assert m.body_q0[cw] == pytest.approx([2.5, 0.5, 0.0])
    v = m.vertices(cw)
    signed = 0.5 * np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1])
    assert signed == pytest.approx(1.0)  # stored counter-clockwise


def test_gravity_must_be_two_finite_numbers():
    with pytest.raises(sx.InputError, match="gravity"):
        sx.ModelBuilder(gravity=(0.0, math.nan))
    with pytest.raises(sx.InputError, match="gravity"):
        sx.ModelBuilder(gravity=(0.0, -9.81, 0.0))


def test_empty_model():
    with pytest.raises(sx.InputError, match="no blocks"):
        sx.ModelBuilder().finalize()


def test_force_on_unknown_body():
    b = sx.ModelBuilder()
    b.add_block(SQUARE, density=1.0)
    with pytest.raises(sx.InputError, match="index 3"):
        b.add_force([0, 3], lambda t: (0.0, 0.0, 0.0))


# --- laws -------------------------------------------------------------------------------------


@pytest.mark.parametrize("mu", [-0.1, math.nan, math.inf])
def test_friction_must_be_finite_and_non_negative(mu):
    with pytest.raises(sx.InputError, match="friction"):
        sx.ContactLaw(friction=mu)


@pytest.mark.parametrize("e", [-0.1, 1.5, math.nan])
def test_restitution_must_be_in_unit_interval(e):
    with pytest.raises(sx.InputError, match="restitution"):
        sx.ContactLaw(friction=0.5, kind=sx.LawKind.RESTITUTION_COULOMB, restitution=e)


def test_restitution_only_with_restitution_law():
    with pytest.raises(sx.InputError, match="RESTITUTION_COULOMB"):
        sx.ContactLaw(friction=0.5, restitution=0.5)


def test_missing_contact_law_names_both_groups():
    b = sx.ModelBuilder()
    b.add_block(SQUARE, kind=sx.BodyKind.FIXED, group="abutment")
    b.add_block([(0, 1), (1, 1), (1, 2), (0, 2)], density=1.0, group="voussoir")
    b.set_law("voussoir", "voussoir", sx.ContactLaw(friction=0.5))
    with pytest.raises(sx.InputError) as info:
        b.finalize()
    msg = str(info.value)
    assert "'abutment'" in msg and "'voussoir'" in msg
    assert "set_law" in msg


def test_mobile_group_needs_a_law_with_itself():
    b = sx.ModelBuilder()
    b.add_block(SQUARE, density=1.0, group="stone")
    with pytest.raises(sx.InputError, match="'stone' and 'stone'"):
        b.finalize()


def test_law_for_unknown_group():
    b = sx.ModelBuilder()
    b.add_block(SQUARE, density=1.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    b.set_law("block", "grond", sx.ContactLaw(friction=0.5))
    with pytest.raises(sx.InputError, match="'grond'"):
        b.finalize()


def test_set_law_needs_a_contact_law():
    with pytest.raises(sx.InputError, match=r"\(a, b\)"):
        sx.ModelBuilder().set_law("a", "b", 0.5)


def test_fixed_groups_need_no_law_between_them():
    b = sx.ModelBuilder()
    b.add_block(SQUARE, kind=sx.BodyKind.FIXED, group="left")
    b.add_block([(1, 0), (2, 0), (2, 1), (1, 1)], kind=sx.BodyKind.FIXED, group="right")
    b.add_block([(0, 1), (1, 1), (1, 2), (0, 2)], density=1.0)
    law = sx.ContactLaw(friction=0.5)
    for g in ("left", "right", "block"):
        b.set_law("block", g, law)
    b.finalize()  # no error: left-right never interact


# --- simulation parameters --------------------------------------------------------------------


@pytest.mark.parametrize("dt", [0.0, -1.0, math.nan, math.inf])
def test_time_step_must_be_positive(dt):
    with pytest.raises(sx.InputError, match="dt"):
        sx.Simulation(_one_block_model(), dt=dt)


@pytest.mark.parametrize("theta", [0.4, 1.1, math.nan])
def test_theta_must_be_in_range(theta):
    with pytest.raises(sx.InputError, match="theta"):
        sx.Simulation(_one_block_model(), dt=1e-3, theta=theta)


def test_too_large_time_step_for_alert_distance():
    with pytest.raises(sx.InputError, match="alert"):
        sx.Simulation(_one_block_model(), dt=0.5)


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"tolerance": 0.0}, "tolerance"), ({"tolerance": -1e-6}, "tolerance"),
    ({"tolerance": math.nan}, "tolerance"), ({"max_iterations": 0}, "max_iterations"),
    ({"relaxation": 0.0}, "relaxation"), ({"relaxation": 1.5}, "relaxation"),
    ({"rest_after": -1}, "rest_after"),
])
def test_solver_parameters(kwargs, name):
    with pytest.raises(sx.InputError, match=name):
        sx.NLGS(**kwargs)


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"alert": 0.0}, "alert"), ({"alert": -1.0}, "alert"), ({"margin": math.nan}, "margin"),
    ({"refresh_every": 0}, "refresh_every"),
])
def test_detection_parameters(kwargs, name):
    with pytest.raises(sx.InputError, match=name):
        sx.DetectionSettings(**kwargs)


@pytest.mark.parametrize("duration", [-1.0, math.nan, math.inf])
def test_run_duration(duration):
    sim = sx.Simulation(_one_block_model(), dt=1e-3)
    with pytest.raises(sx.InputError, match="duration"):
        sim.run(sim.initial_state(), duration)


# --- overlaps ---------------------------------------------------------------------------------


def _pair(dx):
    """Two unit squares side by side, the second shifted left by dx into the first."""
    b = sx.ModelBuilder(gravity=(0.0, 0.0))
    b.add_block(SQUARE, density=1000.0, name="left stone")
    b.add_block([(x + 1.0 - dx, y) for x, y in SQUARE], density=1000.0, name="right stone")
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    return sx.Simulation(b.finalize(), dt=1e-3)


def test_overlapping_blocks_name_both_and_the_depth():
    sim = _pair(0.05)
    with pytest.raises(sx.OverlapError) as info:
        sim.initial_state()
    msg = str(info.value)
    assert "'left stone'" in msg and "'right stone'" in msg
    assert re.search(r"overlap by 0\.05 m", msg), msg
    assert isinstance(info.value, sx.InputError)


def test_touching_blocks_do_not_overlap():
    sim = _pair(0.0)
    state = sim.initial_state()  # no error
    sim.step(state)
    assert sim.log.contacts[-1] == 2  # face against face: two contact points


def test_overlap_check_can_be_skipped():
    sim = _pair(0.05)
    state = sim.initial_state(check_overlaps=False)
    assert state.body_q.shape == (2, 3)


# --- non-convergence is reported, not hidden --------------------------------------------------


def test_capped_solver_reports_non_convergence_and_warns():
    model = running_bond_wall(courses=4, bricks=3)
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(tolerance=1e-6, max_iterations=1))
    state = sim.initial_state()
    with pytest.warns(sx.SolverWarning, match="did not converge"):
        sim.run(state, 0.02)
    assert not sim.log.converged[0]
    assert np.all(sim.log.iterations == 1)
    bad = sim.log.non_converged()
    assert bad.size > 0 and bad[0] == 1
    assert "not converged" in sim.log.summary()


def test_converged_run_does_not_warn():
    model = running_bond_wall(courses=4, bricks=3)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    with warnings.catch_warnings():
        warnings.simplefilter("error", sx.SolverWarning)
        sim.run(state, 0.02)
    assert np.all(sim.log.converged)
