"""Anderson acceleration of NLGS's refinement (saxum.solver.nlgs.nlgs_2d_anderson): on the onset
of a slide, the step a warm start at rest makes slow (docs/method.md, "Anderson acceleration
of the refinement"), it reaches the same criterion in a fraction of the sweeps, at the same
distance from the step's solution, the same bits from run to run."""

import dataclasses

import numpy as np
import pytest

import saxum as sx
from saxum.solver.assembled import assemble_local
from saxum.solver.nlgs import _ANDERSON_DEPTH, nlgs_2d, nlgs_2d_anderson
from saxum.structures import running_bond_wall


class _Capture(sx.NLGS):
    """NLGS that keeps its last solve's problem and start (impulses, v_free, v)."""

    def solve(self, problem, impulse, v_free, v):
        self.captured = (problem, impulse.copy(), v_free.copy(), v.copy())
        return super().solve(problem, impulse, v_free, v)


@pytest.fixture(scope="module")
def onset():
    """An 8-course x 6-brick running-bond wall (mu 0.6) at rest on its ground for 3 steps,
    then its base accelerated by 0.9 g (as the inertial force -0.9 g m, gravity tilted), past
    mu g: the first step of the slide, from the warm start of the wall at rest."""
    model = running_bond_wall(courses=8, bricks=6, brick_length=0.25, brick_height=0.065,
                              density=1800.0, friction=0.6)
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS())
    state = sim.initial_state()
    for _ in range(3):
        sim.step(state)
    g = float(np.hypot(*model.gravity))
    shaken = dataclasses.replace(model, gravity=(-0.9 * g, -g))
    solver = _Capture(refine=0)
    sx.Simulation(shaken, dt=1e-3, solver=solver).step(state)
    return solver.captured


def _solve(onset, tolerance: float, accelerated: bool):
    """Sweeps of nlgs_2d (or nlgs_2d_anderson) from the onset's start to `tolerance`:
    ((sweeps, error), v, impulse, mass)."""
    problem, impulse0, v_free, v0 = onset
    n, c = problem.count, problem.contacts
    inv_mass = problem.model.body_inv_mass
    mass = np.divide(1.0, inv_mass, out=np.zeros_like(inv_mass), where=inv_mass > 0.0)
    v, impulse = v0.copy(), impulse0.copy()
    args = (c.candidate, c.antagonist, problem.h_cand, problem.h_ant, problem.delassus,
            problem.bias, problem.friction, problem.active, n, inv_mass, mass, v_free, v,
            np.empty_like(v), impulse, np.empty((n, 18)))
    if accelerated:
        history = (np.empty((_ANDERSON_DEPTH + 2,) + v.shape),
                   np.empty((_ANDERSON_DEPTH + 2, n, 2)))
        out = nlgs_2d_anderson(*args, *history, tolerance, 100_000, 1.0)
    else:
        out = nlgs_2d(*args, None, None, None, 0, tolerance, 100_000, 1.0)
    return out, v, impulse, mass


def test_anderson_cuts_the_sweeps_of_an_onset_to_the_same_solution(onset):
    """To the refinement's target 1e-8 / 10 (tolerance 1e-9): plain sweeps 1664, Anderson 465
    (measured); asserted: at most half (the margin: the count moves with round-off in the
    order of the contacts). The step's solution: plain sweeps to 1e-13 (2800 sweeps); both
    stop at the same criterion, which leaves a distance tol / (1 - rho) from it, so the
    yardstick for Anderson's result is the plain sweeps' own distance (measured 6.4e-8
    against 1.2e-7 in the M-norm of the velocities, relative): at most twice it. The same by
    the natural map of the assembled problem (saxum.solver.residual), likewise at most twice
    the plain sweeps'."""
    (plain, plain_error), v_plain, r_plain, mass = _solve(onset, 1e-9, False)
    (fast, fast_error), v_fast, r_fast, _ = _solve(onset, 1e-9, True)
    (_, ref_error), v_ref, _, _ = _solve(onset, 1e-13, False)
    assert plain_error <= 1e-9 and fast_error <= 1e-9 and ref_error <= 1e-13
    assert fast <= plain / 2
    v_free = onset[2]
    scale = np.sqrt(np.sum(mass * (v_ref - v_free) ** 2))

    def distance(v):
        return np.sqrt(np.sum(mass * (v - v_ref) ** 2)) / scale

    assert distance(v_fast) <= 2.0 * distance(v_plain)
    local = assemble_local(onset[0], v_free)
    assert local.natural_map_error(r_fast) <= 2.0 * local.natural_map_error(r_plain)


def test_anderson_is_deterministic(onset):
    """Two runs from the same start: the same sweeps, velocities and impulses bit for bit."""
    (a, _), v_a, r_a, _ = _solve(onset, 1e-9, True)
    (b, _), v_b, r_b, _ = _solve(onset, 1e-9, True)
    assert a == b
    assert np.array_equal(v_a, v_b) and np.array_equal(r_a, r_b)


@pytest.mark.parametrize("solver", [sx.NLGS, sx.Hybrid])
def test_the_refinement_of_an_onset_is_accelerated(solver):
    """Through the solvers: an onset (a slow step after cheap ones, Refinement) refined with
    accelerate on takes fewer sweeps than with it off, both converged."""
    model = running_bond_wall(courses=8, bricks=6, brick_length=0.25, brick_height=0.065,
                              density=1800.0, friction=0.6)
    g = float(np.hypot(*model.gravity))
    shaken = dataclasses.replace(model, gravity=(-0.9 * g, -g))
    sweeps = {}
    for accelerate in (False, True):
        sim = sx.Simulation(model, dt=1e-3, solver=solver(accelerate=accelerate))
        state = sim.initial_state()
        for _ in range(3):
            sim.step(state)
        moved = sx.Simulation(shaken, dt=1e-3, solver=sim.solver)
        moved.step(state)
        assert bool(moved.log.converged[-1])
        sweeps[accelerate] = int(moved.log.iterations[-1])
    assert sweeps[True] < sweeps[False]
