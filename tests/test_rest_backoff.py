"""The rest solution backs off where it does not pay (issue 18, item 6; saxum.solver.nlgs
_REST_BACKOFF): a wall sliding under a constant 0.7 g (mu = 0.6, so no rest solution exists)
no longer looks for it on every slow step, and steps the same bit for bit (an attempt that
finds nothing leaves the iterate as it was); the same wall at rest still finds it."""

import dataclasses

import numpy as np
import pytest

import saxum as sx
import saxum.solver.nlgs as nlgs_module
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
