"""NLGS's refinement (saxum.solver.NLGS.refine, saxum.solver.nlgs.Refinement): an onset (a slow
step from a warm start after a cheap one) and the cheap steps after it sweep on towards
tolerance / refine; other steps stay at the tolerance; off (0, 1), NLGS is as before."""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

import saxum as sx
from saxum.errors import InputError
from saxum.ground import harmonic
from saxum.solver.nlgs import Refinement
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


def _refined(steps, **options):
    """Refinement.step on `steps` of (sweeps, converged, cold start) with an NLGS of
    `options`, each step's error at the tolerance: the sweeps each refinement may run."""
    solver = sx.NLGS(**options)
    refinement = Refinement()
    impulse = np.zeros((1, 2))
    budgets = []

    def sweeps(target, count):
        budgets.append(count)
        return 1, target

    for iterations, converged, cold in steps:
        impulse[0, 0] = 0.0 if cold else 1.0
        refinement.start(SimpleNamespace(count=1), impulse)
        before = len(budgets)
        refinement.step(solver, sweeps, iterations, solver.tolerance, converged)
        if len(budgets) == before:
            budgets.append(0)
    return budgets


def test_an_onset_and_the_steps_after_it_are_refined():
    """The 0.7 g wall's pattern (BENCHMARKS.md, "Refinement"): a cold start (800 sweeps) is
    not an onset; at rest (8 sweeps) nothing is refined after it; an onset from a warm start
    after a cheap step (692) is, with every step of the slide after it that converges within
    refine_sweeps (1, 13, 25, 300, 8), until one that takes more (3354); a slow step after it
    (8 then 3354 is not an onset: above refine_sweeps), nor a step not converged, starts
    another."""
    steps = [(800, True, True), (8, True, False), (692, True, False), (1, True, False),
             (13, True, False), (25, True, False), (300, True, False), (8, True, False),
             (3354, True, False), (8, True, False), (5000, False, False), (1, True, False)]
    budgets = _refined(steps)
    refined = [i for i, count in enumerate(budgets) if count]
    assert refined == [2, 3, 4, 5, 6, 7]
    assert budgets[2] == sx.NLGS().refine_sweeps
    assert budgets[6] == sx.NLGS().refine_sweeps
    assert _refined(steps, refine=0) == [0] * len(steps)


def test_a_new_solver_refines_only_the_cheap_steps():
    """A new solver (no onset yet) refines its first steps while each converges within 20
    sweeps (at rest: nothing to do), and stops at the first that takes more: steps that do
    work of their own without an onset (a collapsing arch) are not refined."""
    budgets = _refined([(1, True, False), (50, True, False), (8, True, False),
                        (150, True, False)])
    assert [bool(b) for b in budgets] == [True, False, False, False]


@pytest.mark.parametrize("solver", [sx.NLGS, sx.Hybrid])
def test_checkpoints_hold_the_refinement(solver):
    """The refinement's flags (carrying, cheap, sliding) are state that checkpoints hold
    (ContactSolver.checkpoint, restore; saxum.results); a checkpoint without them (a file
    written before they were stored) restores a new solver's."""
    s = solver()
    assert s.checkpoint()["refinement"].tolist() == [1, 1, 0]
    s._refinement.step(s, None, 50, s.tolerance, True)  # does work: refines nothing
    assert s.checkpoint()["refinement"].tolist() == [0, 0, 0]
    s._refinement.step(s, lambda target, count: (1, target), 1, s.tolerance, True)
    s._refinement.step(s, lambda target, count: (1, target), 692, s.tolerance, True)  # onset
    saved = s.checkpoint()
    assert saved["refinement"].tolist() == [1, 0, 1]
    restored = solver()
    restored.restore(saved)
    assert restored.checkpoint()["refinement"].tolist() == [1, 0, 1]
    restored.restore({})
    assert restored.checkpoint()["refinement"].tolist() == [1, 1, 0]


def test_a_slide_without_an_onset_is_not_refined():
    """The 20-brick wall's slide starts in 29-119 sweeps (below the onset's 200): the default
    refinement leaves it bit for bit as refine 0 does (its drift stays within
    tests/validation/test_shaken_wall.py's bound without refinement)."""
    a = _sliding_wall_log(refine=0)
    b = _sliding_wall_log()
    assert 100 <= a.iterations.max() < 200
    assert np.array_equal(a.iterations, b.iterations)
    assert np.array_equal(a.error, b.error)


@pytest.mark.parametrize("options, name", [({"refine": 0.5}, "solver.refine"),
                                           ({"refine_sweeps": -1}, "solver.refine_sweeps")])
def test_bad_refinement_is_named(options, name):
    with pytest.raises(InputError, match=name):
        sx.NLGS(**options)
