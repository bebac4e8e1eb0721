"""The rest solution backs off where it does not pay (issue 18, item 6; saxum.solver.nlgs
_REST_BACKOFF): a wall sliding under a constant 0.7 g (mu = 0.6, so no rest solution exists)
no longer looks for it on every slow step, and steps the same bit for bit (an attempt that
finds nothing leaves the iterate as it was); the same wall at rest still finds it."""

import dataclasses

import numpy as np
import pytest

import saxum as sx
import saxum.solver.nlgs as nlgs_module
from saxum.results import _pack_state, _unpack_state
from saxum.structures import running_bond_wall


def _run(monkeypatch, backoff: int, acceleration: float, duration: float):
    monkeypatch.setattr(nlgs_module, "_REST_BACKOFF", backoff)
    model = running_bond_wall(courses=25, bricks=2)
    g = float(np.hypot(*model.gravity))
    model = dataclasses.replace(model, accelerations=((lambda t: (acceleration * g, 0.0)),))
    solver = sx.NLGS(refine=0)  # the case of issue 18: without NLGS.refine
    sim = sx.Simulation(model, dt=1e-3, solver=solver)
    state = sim.initial_state()
    sim.run(state, duration)
    return solver, sim.log, state


# its steps in motion hit the sweep cap in both variants (benchmarks/convergence.py's
# wall512-shaken), which the warning reports
@pytest.mark.filterwarnings("ignore::saxum.SolverWarning")
def test_sliding_wall_stops_trying_and_steps_the_same(monkeypatch):
    every, log_every, state_every = _run(monkeypatch, 0, 0.7, 0.05)
    backs, log_backs, state_backs = _run(monkeypatch, 8, 0.7, 0.05)
    # every slow step tried (one of two steps or more), none found: the case of the issue
    assert every.rest_solutions == 0 and every.rest_attempts >= 20
    assert backs.rest_solutions == 0 and backs.rest_attempts <= every.rest_attempts // 2
    assert np.array_equal(state_every.body_q, state_backs.body_q)
    assert np.array_equal(log_every.iterations, log_backs.iterations)


def test_wall_at_rest_still_finds_the_rest_solution(monkeypatch):
    every, log_every, state_every = _run(monkeypatch, 0, 0.0, 0.05)
    backs, log_backs, state_backs = _run(monkeypatch, 8, 0.0, 0.05)
    assert backs.rest_solutions >= 1
    assert (backs.rest_attempts, backs.rest_solutions) == (every.rest_attempts,
                                                          every.rest_solutions)
    assert np.array_equal(state_every.body_q, state_backs.body_q)
    assert log_backs.converged.all()


@pytest.mark.filterwarnings("ignore::saxum.SolverWarning")
def test_a_restored_solver_backs_off_as_the_original():
    """The back-off is solver state that checkpoints hold (ContactSolver.checkpoint, "rest",
    packed as a results file packs it): a solver restored from it after 20 steps of the
    sliding wall steps on as the original, bit for bit and with the same attempts at the rest
    solution; one restored without it tries on slow steps at once again (measured: 1 attempt
    in the next 10 steps where the original made none; the same bits, as none finds a rest
    solution)."""
    model = running_bond_wall(courses=25, bricks=2)
    g = float(np.hypot(*model.gravity))
    model = dataclasses.replace(model, accelerations=((lambda t: (0.7 * g, 0.0)),))

    def simulation():
        return sx.Simulation(model, dt=1e-3, solver=sx.NLGS(refine=0))

    sim = simulation()
    state = sim.initial_state()
    sim.run(state, 0.02)
    saved = _unpack_state(_pack_state(sim.solver.checkpoint()))
    assert saved["rest"][0] == 8  # putting off the longest (_REST_BACKOFF)
    runs = []
    for restored in (saved, {k: v for k, v in saved.items() if k != "rest"}):
        fresh = simulation()
        fresh.detector.restore(sim.detector.checkpoint())
        fresh.solver.restore(restored)
        runs.append((fresh, state.copy()))
    before = sim.solver.rest_attempts
    for s, st in [(sim, state), *runs]:
        s.run(st, 0.01)
    (whole, whole_state), (bare, bare_state) = runs
    assert whole.solver.rest_attempts == sim.solver.rest_attempts - before
    assert bare.solver.rest_attempts > whole.solver.rest_attempts
    assert np.array_equal(whole_state.body_q, state.body_q)
    assert np.array_equal(whole.log.iterations, sim.log.iterations[-10:])
