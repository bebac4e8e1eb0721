"""The rest solution of a step (saxum.solver.equilibrium) exists exactly when the blocks can
stand: static thresholds from closed forms and from an independent limit analysis.

By the lower-bound theorem of limit analysis for rigid blocks with Coulomb joints, a step from
rest has a rest solution exactly when contact impulses inside the friction cones balance the
loads of the step; so the rest solution must exist below each threshold and not above it.
References:
- a block on a slope a (gravity turned by a): it stays if tan a < mu (Coulomb); a wide block
  (b/h = 4) so that it slides before it tips; checked on random slopes and friction
  coefficients at least 1e-5 (relative) from the threshold;
- a block b/h = 0.2, mu = 1, under a horizontal acceleration a: it stays if a < g b/h
  (Housner, BSSA 53, 1963; test_rocking_threshold.py), checked at 0.999 and 1.001 g b/h;
- the 15-voussoir semicircular arch, t/R = 0.15, mu = 1, under a horizontal load factor
  lambda: it stands if lambda < lambda_c, the least four-hinge mechanism computed
  independently of saxum (limit_analysis.py: kinematic theorem, which for no sliding gives the
  same lambda_c as the static one), checked at 0.999 and 1.001 lambda_c.
(Observed by bisection: the rest solution stops existing at tan a / mu = 1 - 1.5e-8 and at
lambda / lambda_c = 1 - 2e-7: the barrier needs room inside the cones.)
With load_path, the rest solution tries the static load path first (equilibrium._load_path),
which must give the same verdicts. When it exists: every impulse strictly inside its cone, the
loads balanced, the blocks at rest and one NLGS sweep from it changes nothing; when it does
not: the impulses and velocities left as they were (rest_check.py, with the tolerances).
"""

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from limit_analysis import semicircular_four_hinge, with_load_factor
from rest_check import DT, check, first_step

import saxum as sx
from saxum.solver import SolverReport
from saxum.structures import add_wall, running_bond_wall, semicircular_arch

G = 9.81


def _block_on_slope(slope, mu):
    b = sx.ModelBuilder(gravity=(G * math.sin(slope), -G * math.cos(slope)))
    b.add_block([(-1.0, -0.2), (1.0, -0.2), (1.0, 0.0), (-1.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground", name="ground")
    b.add_block([(0.0, 0.0), (0.4, 0.0), (0.4, 0.1), (0.0, 0.1)], density=2000.0, name="block")
    b.set_law("block", "ground", sx.ContactLaw(friction=mu))
    b.set_law("block", "block", sx.ContactLaw(friction=mu))
    return b.finalize()


@given(slope=st.floats(0.0, 1.2), mu=st.floats(0.05, 1.5))
def test_block_on_a_slope_rests_exactly_below_the_friction_angle(slope, mu):
    margin = math.tan(slope) / mu - 1.0
    if abs(margin) < 1e-5:
        return
    model = _block_on_slope(slope, mu)
    check(first_step(model), model, margin < 0.0)


@pytest.mark.parametrize("load_path", [False, True])
@pytest.mark.parametrize("factor", [0.999, 1.001])
def test_block_under_horizontal_acceleration_rests_below_g_b_over_h(factor, load_path):
    width, height = 0.2, 1.0
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-2.0, -0.2), (2.0, -0.2), (2.0, 0.0), (-2.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground", name="ground")
    b.add_block([(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)], density=2000.0,
                name="rocker")
    b.set_law("block", "ground", sx.ContactLaw(friction=1.0))
    b.set_law("block", "block", sx.ContactLaw(friction=1.0))
    b.add_acceleration(lambda t: (factor * G * width / height, 0.0))
    model = b.finalize()
    check(first_step(model, load_path), model, factor < 1.0)


class _Hypothesis(sx.ContactSolver):
    """The first step's rest hypothesis (saxum.solver.equilibrium.rest_hypothesis; not the
    position projection's problem, which has none)."""

    def solve(self, problem, impulse, v_free, v):
        from saxum.solver.equilibrium import rest_hypothesis

        if not hasattr(self, "hypothesis"):
            self.hypothesis = rest_hypothesis(problem, v_free)
        return SolverReport(iterations=0, error=0.0, converged=True)


@pytest.mark.parametrize("load_path", [False, True])
@pytest.mark.parametrize("factor", [0.999, 1.001])
def test_loads_outside_the_grounds_cone_rule_the_rest_solution_out_at_once(factor, load_path):
    """A running-bond wall (4 courses x 3 bricks, b/h = 2.9: it slides before it tips) on a
    flat ground, mu = 0.6 everywhere, under a horizontal acceleration a = factor mu g: the
    ground's contacts share one Coulomb cone, which the sum of the loads leaves for a > mu g
    (Coulomb); there the rest hypothesis already says that no rest solution exists, without
    a Newton iteration, and below it the rest solution is found."""
    model = running_bond_wall(courses=4, bricks=3, friction=0.6)
    g = float(np.hypot(*model.gravity))
    model = dataclasses.replace(model, accelerations=((lambda t: (factor * 0.6 * g, 0.0)),))
    solver = _Hypothesis()
    sim = sx.Simulation(model, dt=DT, solver=solver)
    sim.step(sim.initial_state())
    assert (solver.hypothesis is None) == (factor > 1.0)
    check(first_step(model, load_path), model, factor < 1.0)


@pytest.fixture(scope="module")
def lambda_c():
    return semicircular_four_hinge(1.0, 0.15, 15)[0]


@pytest.mark.parametrize("load_path", [False, True])
@pytest.mark.parametrize("factor", [0.999, 1.001])
def test_arch_under_horizontal_load_rests_below_its_collapse_load_factor(factor, lambda_c,
                                                                         load_path):
    lam_c = lambda_c
    arch = semicircular_arch(radius=1.0, thickness=0.15, voussoirs=15, friction=1.0)
    model = with_load_factor(arch, factor * lam_c).model
    check(first_step(model, load_path), model, factor < 1.0)


def test_wall_carried_by_a_moving_ground_rests_on_it():
    """Galilean invariance: a wall on a ground that translates at a constant velocity V, its
    bricks moving with it from the start, stays at rest relative to the ground as a wall on a
    fixed ground does (test_wall_rest.py): the rest solution is sought in the frame of the
    supports. 6 courses of 5 bricks, V = (0.5, 0.1) m/s, 0.2 s: every step converged, no
    brick's position relative to the ground off by more than 1e-9 m."""
    velocity = (0.5, 0.1, 0.0)
    b = sx.ModelBuilder(gravity=(0.0, -G))
    add_wall(b, courses=6, bricks=5, ground=True)
    b.drive("ground", lambda t: velocity)
    for pair in (("brick", "brick"), ("brick", "ground")):
        b.set_law(*pair, sx.ContactLaw(friction=0.6))
    model = b.finalize()
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state()
    free = model.body_kind == sx.BodyKind.FREE
    state.body_v[free] = velocity
    sim.run(state, 0.2)
    assert np.all(sim.log.converged) and sim.solver.rest_solutions >= 1
    ground = model.body("ground")
    relative = (state.body_q[:, :2] - model.body_q0[:, :2]) - (
        state.body_q[ground, :2] - model.body_q0[ground, :2])
    assert np.abs(relative[free]).max() < 1e-9


def test_a_wall_rests_the_same_with_the_kept_factorization_analysis(monkeypatch):
    """The Newton systems are factorized with an analysis kept per pattern
    (saxum.solver.block_cholesky): a 6 x 4 wall's first-step rest solution by the Newton
    iterations (no load path) passes rest_check's checks, and a second search on the same
    contacts, with the analysis kept from the first, gives the same impulses and velocities
    bit for bit; with SuperLU's LU instead (saxum before), the same checks pass and the
    impulses agree to 1e-10 of the largest (the balance the solver accepts,
    equilibrium._FEASIBLE: the same Newton steps, other round-off; observed 1e-15)."""
    from saxum.solver import block_cholesky

    monkeypatch.setattr(block_cholesky, "_analyses", [])
    model = running_bond_wall(courses=6, bricks=4, friction=0.6)
    first = first_step(model)
    check(first, model, True)
    assert len(block_cholesky._analyses) == 1
    kept = block_cholesky._analyses[0][2]
    again = first_step(model)
    assert block_cholesky._analyses[0][2] is kept
    assert np.array_equal(again.impulse, first.impulse) and np.array_equal(again.v, first.v)
    monkeypatch.setattr(block_cholesky.BlockCholesky, "factorize",
                        classmethod(lambda cls, *args: None))  # equilibrium._factorize's LU
    lu = first_step(model)
    check(lu, model, True)
    assert np.abs(lu.impulse - first.impulse).max() <= 1e-10 * np.abs(first.impulse).max()
