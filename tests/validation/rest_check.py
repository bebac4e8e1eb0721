"""The first step's rest solution (saxum.solver.equilibrium) and the checks of what it returns,
shared by test_rest_solution.py (2D) and test_rest_solution3d.py (3D).

When a rest solution is found: every closed contact's impulse is strictly inside its Coulomb
cone (R_n > 0, |R_T| < mu R_n, R_T = R_t in 2D and (R_t, R_s) in 3D; from the static load path,
every closed contact that carries an impulse, the others R = 0), the contacts that are not
active carry nothing, the impulses balance the step's loads, sum_alpha H_alpha^T R_alpha =
-M v_free on every free body (fixed supports), computed here from the problem's rows of H*
to within 1e-10 of |M v_free| in the norm |.|_M^-1 (the solver accepts a residual of 1e-10:
equilibrium._FEASIBLE; observed: round-off, 1e-14 to 1e-13), the blocks end the step at rest
(velocities below 1e-9 of those of one step of the loads) and one NLGS sweep from it changes
nothing (error <= 1e-9). When none is found: the impulses and velocities are left as they were.
"""

import numpy as np

import saxum as sx
from saxum.solver import SolverReport
from saxum.solver.equilibrium import rest_solution

DT = 1e-3


class FirstStepRest(sx.ContactSolver):
    """Looks for the rest solution of the first step's problem (the static load path first
    if `load_path`), then sweeps once from it."""

    def __init__(self, load_path: bool = False) -> None:
        self.found = None
        self.load_path = load_path

    def solve(self, problem, impulse, v_free, v):
        if self.found is not None:
            return SolverReport(iterations=0, error=0.0, converged=True)
        before = impulse.copy(), v.copy()
        self.found = rest_solution(problem, impulse, v_free, v, load_path=self.load_path)
        k = problem.count
        self.untouched = np.array_equal(before[0], impulse) and np.array_equal(before[1], v)
        self.impulse = impulse[:k].copy()
        self.friction = problem.friction[:k].copy()
        self.active = problem.active[:k].copy()
        self.bodies = problem.contacts.candidate[:k].copy(), problem.contacts.antagonist[:k].copy()
        self.rows = problem.h_cand[:k].copy(), problem.h_ant[:k].copy()
        self.v_free = v_free.copy()
        self.v = v.copy()
        gravity = float(np.linalg.norm(problem.model.gravity))
        self.load = float(np.abs(v_free - before[1]).max()) + gravity * DT  # scale of v_free
        self.sweep = sx.NLGS(rest_after=0, max_iterations=1).solve(problem, impulse, v_free, v)
        return self.sweep


def first_step(model: sx.Model, load_path: bool = False) -> FirstStepRest:
    solver = FirstStepRest(load_path)
    sim = sx.Simulation(model, dt=DT, solver=solver)
    sim.step(sim.initial_state())
    return solver


def imbalance(solver: FirstStepRest, model: sx.Model) -> float:
    """|sum H^T R + M v_free|_M^-1 / |M v_free|_M^-1 over the free bodies [-]."""
    inv_mass = model.body_inv_mass
    free = model.body_kind == sx.BodyKind.FREE
    total = np.zeros_like(solver.v_free)
    for bodies, rows in zip(solver.bodies, solver.rows, strict=True):
        np.add.at(total, bodies, np.einsum("krd,kr->kd", rows, solver.impulse))
    load = solver.v_free[free] / inv_mass[free]
    residual = total[free] + load
    return float(np.sqrt(np.sum(inv_mass[free] * residual**2))
                 / np.sqrt(np.sum(inv_mass[free] * load**2)))


def check(solver: FirstStepRest, model: sx.Model, exists: bool) -> None:
    """The checks of the module doc."""
    assert solver.found is exists
    if not exists:
        assert solver.untouched
        return
    closed = solver.active
    r = solver.impulse
    tangential = np.abs(r[:, 0]) if r.shape[1] == 2 else np.hypot(r[:, 0], r[:, 2])
    # the load path leaves the joints that hold no body up (a wall's head joints) with R = 0,
    # the cone's apex (equilibrium._load_path), as it leaves open contacts; "zero" is within
    # 1e-12 of the largest impulse: the round-off of the sums that split a load (~1e-16 each)
    # with room for the column of ~1e3 blocks above a contact
    zero = 1e-12 * np.abs(r).max()
    carrying = (closed & np.any(np.abs(r) > zero, axis=1)) if solver.load_path else closed
    assert np.all(r[carrying, 1] > 0.0)
    assert np.all(tangential[carrying] < solver.friction[carrying] * r[carrying, 1])
    assert np.all(np.abs(r[~carrying]) <= zero)
    assert imbalance(solver, model) <= 1e-10
    free = model.body_kind == sx.BodyKind.FREE
    assert np.abs(solver.v[free]).max() <= 1e-9 * solver.load
    assert solver.sweep.iterations == 1 and solver.sweep.error <= 1e-9
