"""A warm start that follows the loads of an assembly at rest (our choice).

An assembly that stays at rest relative to its supports while its loads change from step to
step (a wall on a shaking base: weight plus the ground's inertial force -M a_g(t), or a driven
base) needs at each step impulses R_k in the Coulomb cones with H R_k = f_k, f_k = M (V - v_free)
the loads of the step (saxum.solver.equilibrium). A warm start from R_k-1 is off by the change
of the loads, which Gauss-Seidel spreads through the assembly only as fast as it relaxes the
softest mode, so every such step ends in the rest solution's Newton iterations.

Instead, after a step that ended at rest, the next step starts from
    R = R_k-1 + dR,   H dR = f_k - f_k-1,
which balances this step's loads exactly (H is the same: the assembly has not moved relative to
its supports); when R lies inside every cone it is the step's rest solution and NLGS's first
sweep confirms it (it changes nothing beyond round-off). dR comes from the last rest solution's
Newton system (equilibrium.LoadResponse: one solve with its factorization, an impulse change
that spares the contacts near their cone's boundary), and is reused: the loads of a rigid
assembly at rest change along the ground motion's components only (f is affine in a_g(t)), so
a load change that is a combination sum_j lambda_j df_j of the changes already answered (to
_FIT x the solver's tolerance, relative to |f_k|, in the norm |.|_M^-1) takes
dR = sum_j lambda_j dR_j (the least-squares fit, kept orthonormal in the load changes, over at
most _DEPTH of them) without any solve; a misfit is answered by one solve, which adds its
direction.
When R leaves a cone, the sweep does not confirm it and the solver goes on as without it
(sweeps, then a new rest solution, whose system answers the next steps). A load change below
the solver's tolerance needs nothing: the plain warm start then is already at rest; on two
steps in a row, the following stops until a step needs the rest solution again (an assembly
at rest under constant loads pays nothing for it).
"""

import math

import numba as nb
import numpy as np

from .equilibrium import LoadResponse, rest_hypothesis
from .problem import _apply

__all__ = ["START_MARGIN", "LoadFollowing"]

_DEPTH = 3
"""Load changes answered and kept (a ground motion has up to 3 components)."""
START_MARGIN = 0.01
"""The rest solution's starting margin (saxum.solver.equilibrium) after a start of this module
that the sweep did not confirm: that start balances the loads and leaves the cones only
slightly, so the Newton iterations start near it (0.01 r0 instead of 0.1 r0: 1.4 instead of 2
to 3 factorizations per rest solution on the 0.3 g wall of benchmarks/shaken_wall.py)."""
_FIT = 1e-2
"""Misfit of the loads, as a fraction of the solver's tolerance (relative to |f|_M^-1), below
which a combination of the kept answers is used: its impulses then balance the step's loads
more closely than the convergence criterion can tell."""


class LoadFollowing:
    """The last step at rest (contact keys, impulses [N s], loads [N s]), the rest solution's
    Newton system, and the load changes answered from it."""

    def __init__(self) -> None:
        self.response = LoadResponse()
        """Filled by saxum.solver.equilibrium.rest_solution when it finds a rest solution."""
        self._q = np.empty((_DEPTH, 0, 0))
        """Orthonormal load changes M^-1/2 df_j (first _answers rows), laid out as f ..."""
        self._dr = np.empty((_DEPTH, 0, 0))
        """... and the impulse changes dR_j [N s] (count, dim) that balance them."""
        self._answers = 0
        self._last = None  # (keys, impulses, M^-1/2 f) of the last step at rest
        self._pending = None  # this step's M^-1/2 f, from start to record
        self._weight = (None, None)  # (inv_mass, M^-1/2 of the free bodies, as f is laid out)
        self._quiet = 0  # steps in a row whose loads did not change

    def clear(self) -> None:
        self.response.clear()
        self._answers = 0
        self._last = self._pending = None
        self._quiet = 0

    def _loads(self, problem, v_free: np.ndarray):
        """(closed contacts, M^-1/2 f) of the step, None if it cannot end at rest
        (saxum.solver.equilibrium.rest_hypothesis)."""
        hypothesis = rest_hypothesis(problem, v_free)
        if hypothesis is None:
            return None
        closed, slot, force = hypothesis
        inv_mass = problem.model.body_inv_mass
        if self._weight[0] is not inv_mass:
            self._weight = inv_mass, np.sqrt(inv_mass[slot >= 0])
        return closed, force * self._weight[1]

    def start(self, problem, impulse: np.ndarray, v_free: np.ndarray, v: np.ndarray,
              tolerance: float) -> bool:
        """After a step at rest on the same contacts: impulse = R_k-1 + dR (module doc) and
        v = v_free + M^-1 H impulse [m/s, rad/s]; returns True. Otherwise (nothing kept, other
        contacts, a step that cannot end at rest, loads that did not change) leaves both as they
        are and returns False; loads that did not change for the first time still let `record`
        keep the step."""
        self._pending = None
        if self._last is None:
            return False
        keys, last_impulse, last_loads = self._last
        count = problem.count
        step_loads = self._loads(problem, v_free)
        if (step_loads is None or len(keys) != count
                or not np.array_equal(keys, problem.contacts.key[:count])
                or not np.array_equal(step_loads[0], self.response.closed)):
            self.clear()
            return False
        loads = self._pending = step_loads[1]
        if self._q.shape[1:] != loads.shape or self._dr.shape[1:] != last_impulse.shape:
            self._q = np.empty((_DEPTH, *loads.shape))
            self._dr = np.empty((_DEPTH, *last_impulse.shape))
            self._answers = 0
        change = np.empty_like(loads)
        start = np.empty_like(last_impulse)
        moved, misfit, size = _combine(loads, last_loads, self._q, self._dr, self._answers,
                                       last_impulse, change, start)
        if moved <= tolerance * size:
            # the warm start is at rest already; twice in a row: loads that do not change,
            # which need no following
            self._quiet += 1
            if self._quiet > 1:
                self.clear()
            return False
        self._quiet = 0
        if misfit > _FIT * tolerance * size:  # a new direction of the loads: one solve
            dr = self.response.impulse_change(problem, change / self._weight[1])
            start += dr
            if self._answers == _DEPTH:  # drop the oldest
                self._q[:-1] = self._q[1:].copy()
                self._dr[:-1] = self._dr[1:].copy()
                self._answers -= 1
            self._q[self._answers] = change / misfit
            self._dr[self._answers] = dr / misfit
            self._answers += 1
        impulse[:count] = start
        v[:] = v_free
        c = problem.contacts
        _apply(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, problem.active, count,
               problem.model.body_inv_mass, impulse, v)
        return True

    def record(self, problem, impulse: np.ndarray, v_free: np.ndarray, confirmed: bool,
               found: bool) -> None:
        """After the solve: keep the step if it ended at rest from the start that `start` saw
        and the first sweep confirmed (`confirmed`), or from a rest solution (`found`, which
        filled `response`); otherwise forget everything."""
        if found:
            self._answers = 0
            step_loads = self._loads(problem, v_free)
            self._pending = None if step_loads is None else step_loads[1]
        elif not confirmed:
            self._pending = None
        if self._pending is None:
            self.clear()
            return
        count = problem.count
        self._last = (problem.contacts.key[:count].copy(), impulse[:count].copy(),
                      self._pending)
        self._pending = None


@nb.njit(cache=True)
def _combine(loads, last_loads, q, dr, answers, last_impulse, change, start):
    """change = loads - last_loads minus its projections lambda_j = q_j . change on the first
    `answers` kept load changes (orthonormal), start = last_impulse + sum_j lambda_j dR_j;
    returns (|loads - last_loads|, |change| (the misfit), |loads|)."""
    moved = 0.0
    size = 0.0
    for i in range(loads.shape[0]):
        for d in range(loads.shape[1]):
            change[i, d] = loads[i, d] - last_loads[i, d]
            moved += change[i, d] * change[i, d]
            size += loads[i, d] * loads[i, d]
    for a in range(last_impulse.shape[0]):
        for r in range(last_impulse.shape[1]):
            start[a, r] = last_impulse[a, r]
    for j in range(answers):
        lam = 0.0
        for i in range(loads.shape[0]):
            for d in range(loads.shape[1]):
                lam += q[j, i, d] * change[i, d]
        for i in range(loads.shape[0]):
            for d in range(loads.shape[1]):
                change[i, d] -= lam * q[j, i, d]
        for a in range(last_impulse.shape[0]):
            for r in range(last_impulse.shape[1]):
                start[a, r] += lam * dr[j, a, r]
    misfit = 0.0
    for i in range(loads.shape[0]):
        for d in range(loads.shape[1]):
            misfit += change[i, d] * change[i, d]
    return math.sqrt(moved), math.sqrt(misfit), math.sqrt(size)
