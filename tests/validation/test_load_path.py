"""The static load path (saxum.solver.equilibrium._load_path): a rest solution of a stack
without any sparse factorization, which NLGS tries first on a step it does not follow from
an earlier rest solution (issue 16: the cold start of a 125 000-brick wall).

- A column of identical blocks, centred, on a fixed ground (statics of a stack, J. Heyman,
  "The Stone Skeleton", Cambridge University Press, 1995: each bed joint carries the weight of
  the blocks above it, through their common vertical axis): each of a joint's two points carries
  half of it, R_n = k m g dt / 2 for k blocks above, R_t = 0, to 1e-12 relative (round-off of
  k sums and a 3 x 3 Cholesky solve per block: observed 2e-16).
- The first step of the 25 x 20 running-bond wall of test_wall_rest.py, a cold start: the
  load path is a rest solution by the checks of rest_check.py (impulses in the cones, loads
  balanced to 1e-10, bricks at rest, one sweep changes nothing) and takes no factorization
  (so does the 3D wall with a corner of test_wall_rest3d.py); with default NLGS the step
  converges to the solver's tolerance after rest_after sweeps and one more that confirms it,
  like the Newton method's rest solution (the load path turned off), and both leave the
  bricks at rest to 1e-9 of the velocity of one step of gravity.
  Their impulses differ (a wall is statically indeterminate: which rest solution is found
  depends on the method), their resultant on every brick does not (1e-10, the solver's
  acceptance of a rest solution, equilibrium._FEASIBLE).
The verdicts of the rest solution with the load path tried first against closed forms and
limit analysis (a rocking block, a wall sliding on its ground, the 15-voussoir arch) are in
test_rest_solution.py.
"""

import numpy as np
import pytest
from rest_check import DT, check, first_step

import saxum as sx
import saxum.solver.equilibrium as equilibrium
from saxum.structures import running_bond_wall, wall3d

G = 9.81


@pytest.fixture
def no_factorization(monkeypatch):
    """Fails the test if the rest solution factorizes its Newton system."""

    def refuse(*args):
        raise AssertionError("the load path was expected to need no factorization")

    monkeypatch.setattr(equilibrium, "_factorize", refuse)


def test_column_of_blocks_carries_the_weight_above_each_joint(no_factorization):
    blocks, width, height, density = 5, 0.4, 0.2, 2000.0
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-1.0, -0.2), (1.0, -0.2), (1.0, 0.0), (-1.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground", name="ground")
    for k in range(blocks):
        y = k * height
        b.add_block([(0.0, y), (width, y), (width, y + height), (0.0, y + height)],
                    density=density, name=f"block{k}")
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = b.finalize()
    solver = first_step(model, load_path=True)
    check(solver, model, True)
    weight = density * width * height * G * DT  # one block's weight over the step [N s]
    y = model.body_q0[:, 1]
    cand, ant = solver.bodies
    upper = np.where(y[cand] > y[ant], cand, ant)
    above = np.array([np.count_nonzero(y >= y[u]) for u in upper])  # ground: lowest
    assert len(upper) == 2 * blocks
    assert np.abs(solver.impulse[:, 1] - above * weight / 2.0).max() <= 1e-12 * blocks * weight
    assert np.abs(solver.impulse[:, 0]).max() <= 1e-12 * blocks * weight


@pytest.fixture(scope="module")
def wall():
    return running_bond_wall(courses=25, bricks=20)


def test_load_path_of_a_wall_is_a_rest_solution(wall, no_factorization):
    check(first_step(wall, load_path=True), wall, True)


def test_load_path_of_a_3d_wall_with_a_corner_is_a_rest_solution(no_factorization):
    model = wall3d(courses=8, length=1.5, return_length=0.75)  # test_wall_rest3d.py's
    check(first_step(model, load_path=True), model, True)


def _first_step(model, monkeypatch, load_path: bool):
    """The first step with default NLGS (rest_after 50); the load path turned off if not
    `load_path`. Returns (simulation, state, factorizations)."""
    factorize = equilibrium._factorize
    calls = []

    def counted(*args):
        calls.append(1)
        return factorize(*args)

    with monkeypatch.context() as patch:
        patch.setattr(equilibrium, "_factorize", counted)
        if not load_path:
            patch.setattr(equilibrium, "_load_path", lambda *args: False)
        sim = sx.Simulation(model, dt=DT)
        state = sim.initial_state()
        sim.step(state)
    return sim, state, len(calls)


def test_first_step_of_a_wall_from_the_load_path_matches_the_newton_method(wall, monkeypatch):
    runs = {path: _first_step(wall, monkeypatch, path) for path in (True, False)}
    free = wall.body_kind == sx.BodyKind.FREE
    mass = 1.0 / wall.body_inv_mass[free]
    for path, (sim, state, factorizations) in runs.items():
        assert sim.log.converged[-1] and sim.solver.rest_solutions == 1
        assert sim.log.iterations[-1] == sim.solver.rest_after + 1
        assert (factorizations == 0) is path
        assert np.abs(state.body_v[free]).max() <= 1e-9 * G * DT
    # the resultant of the impulses on a brick is M (v - v_free), v_free the same in both
    gravity = np.zeros_like(mass)
    gravity[:, 1] = G * DT
    diff = runs[True][1].body_v[free] - runs[False][1].body_v[free]
    assert np.sqrt(np.sum(mass * diff**2)) <= 1e-10 * np.sqrt(np.sum(mass * gravity**2))
