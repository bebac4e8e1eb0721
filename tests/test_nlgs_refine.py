"""NLGS's refinement (saxum.solver.NLGS.refine, off by default): a step that converged in few
sweeps sweeps on towards tolerance / refine; the slow ones stay at the tolerance; off (0, 1),
NLGS is as before."""

import dataclasses

import numpy as np
import pytest

import saxum as sx
from saxum.errors import InputError
from saxum.ground import harmonic
from saxum.structures import running_bond_wall


def _sliding_wall_log(**options):
    """The 5-course x 4-brick wall of tests/validation/test_shaken_wall.py under 0.7 g at
    2 Hz (mu 0.6: it slides from 0.082 s), its first 0.15 s; the step log."""
    model = running_bond_wall(courses=5, bricks=4, brick_length=0.25, brick_height=0.065,
                              density=1800.0, friction=0.6)
    g = float(np.hypot(*model.gravity))
    motion = harmonic(0.7 * g, 0.5, 1, samples_per_cycle=4000)
    model = dataclasses.replace(model, accelerations=(motion.inertial_load(),))
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(**options))
    sim.run(sim.initial_state(), 0.15)
    return sim.log


def test_refined_steps_reach_a_tenth_of_the_tolerance():
    tol = 1e-6
    plain = _sliding_wall_log(tolerance=tol, refine=0)
    refined = _sliding_wall_log(tolerance=tol, refine=10.0)
    assert plain.converged.all() and refined.converged.all()
    # without it, sliding steps stop between tol / 10 and tol (so the test tells them apart)
    assert (plain.error > tol / 10).sum() >= 10
    # with it, every step within the sweeps budget reaches tol / 10; none sweeps less
    cheap = refined.iterations <= 1000
    assert cheap.all()
    assert (refined.error[cheap] <= tol / 10).all()
    assert refined.iterations.sum() > plain.iterations.sum()


def test_refine_off_is_one_of_two_equal_runs():
    """refine 0 and refine 1 both leave NLGS as it was: the same steps bit for bit."""
    a = _sliding_wall_log(refine=0)
    b = _sliding_wall_log(refine=1.0)
    assert np.array_equal(a.iterations, b.iterations)
    assert np.array_equal(a.error, b.error)


def test_slow_steps_are_not_refined():
    """refine_sweeps 1: only a step that converged in one sweep is refined; the sliding
    steps (tens of sweeps) stop at the tolerance as without refinement."""
    tol = 1e-6
    log = _sliding_wall_log(tolerance=tol, refine=10.0, refine_sweeps=1)
    assert log.converged.all()
    slow = log.iterations > 1
    assert (log.error[slow] > tol / 10).sum() >= 10


@pytest.mark.parametrize("options, name", [({"refine": 0.5}, "solver.refine"),
                                           ({"refine_sweeps": -1}, "solver.refine_sweeps")])
def test_bad_refinement_is_named(options, name):
    with pytest.raises(InputError, match=name):
        sx.NLGS(**options)
