"""Position projection of the gap-based law (GAP_SIGNORINI_COULOMB): removes interpenetration
without touching the velocities.

With theta = 1/2 an inelastic impact leaves the end-of-step interpenetration (1 - theta) h U_n^-
(the first part of the step moves with the approach velocity). Turning it into a separation
velocity, as a gap target b_n = g / (theta h) in the velocity problem does, makes impacts
rebound as if elastic. Instead, after the step, the end-of-step gaps g+ = g + theta h U_n+ of
the contacts under the gap-based law are estimated and, where one is below -tolerance, the
positions are projected back onto g >= 0 (a _g0 law's onto g >= g0, saxum.laws, with g+ - g0
for g+ below): find the frictionless impulses P and the pseudo-velocity w = M^-1 H P
[m/s, rad/s] with
    g+ / h + U_n(w) >= 0,   P_n >= 0,   (g+ / h + U_n(w)) P_n = 0,
and set q+ <- q+ + h w. The velocities are left as they are, so the projection neither adds nor
removes kinetic energy (V. Acary, "Projected event-capturing time-stepping schemes for
nonsmooth mechanical systems with unilateral contact and Coulomb's friction", CMAME 256, 2013).
It is solved by the step's own contact solver on the step's own local problem (same H and W),
with friction zero.
"""

from dataclasses import dataclass

import numba as nb
import numpy as np

from ..contacts import Contacts
from ..laws import LawKind
from ..model import Model
from .base import ContactSolver, SolverReport
from .problem import ContactProblem

__all__ = ["PositionProjection"]

_GAP = int(LawKind.GAP_SIGNORINI_COULOMB)
_VISCOUS = int(LawKind.VISCOUS_COULOMB)
_COHESIVE = int(LawKind.COHESIVE)


@dataclass
class _ProjectionProblem:
    """The step's ContactProblem with the projection's shift, no friction, own active set."""

    model: Model
    contacts: Contacts
    count: int
    h_cand: np.ndarray
    h_ant: np.ndarray
    delassus: np.ndarray
    bias: np.ndarray
    friction: np.ndarray
    active: np.ndarray


class PositionProjection:
    """Projects positions so that no gap-law contact ends a step interpenetrated by more than
    `tolerance` [m]; `pseudo_velocity` [m/s, rad/s] (bodies, dof) is the last correction w."""

    def __init__(self, model: Model, tolerance: float) -> None:
        self.model = model
        self.tolerance = tolerance
        self.pseudo_velocity = np.zeros((model.body_count, model.dof))
        self._zero = np.zeros_like(self.pseudo_velocity)
        self._shifted = bool((model.law_initial_gap
                              & (model.law_kind == LawKind.GAP_SIGNORINI_COULOMB)).any())
        """Some gap law is a _g0 law: its contacts' targets are g >= g0, which the step's
        largest interpenetration (g >= 0) does not bound."""
        self._allocate(64)

    def _allocate(self, capacity: int) -> None:
        self._bias = np.zeros(capacity)
        self._friction = np.zeros(capacity)
        self._active = np.zeros(capacity, dtype=np.bool_)
        self._impulse = np.zeros((capacity, self.model.dim))

    def project(self, problem: ContactProblem, solver: ContactSolver, h: float,
                depth: float) -> SolverReport | None:
        """Fill `pseudo_velocity` (zero when no gap-law contact is interpenetrated beyond the
        tolerance) from the end-of-step gaps g+ of `problem` (ContactProblem.end_gaps, which
        returns the largest interpenetration `depth` [m] of all contacts), h [s] the step;
        returns the solver's report, or None when no projection was needed. The caller adds
        h * pseudo_velocity to the positions."""
        self.pseudo_velocity[:] = 0.0
        if depth <= self.tolerance and not self._shifted:
            return None
        k = problem.count
        if k > len(self._bias):
            self._allocate(max(k, 2 * len(self._bias)))
        c = problem.contacts
        worst = _projection_targets(c.law, problem.gap_end, c.initial_gap, k,
                                    self.model.law_kind, problem.law_map, h, self._bias,
                                    self._active)
        if worst <= self.tolerance:
            return None
        self._friction[:k] = 0.0
        self._impulse[:k] = 0.0
        view = _ProjectionProblem(self.model, c, k, problem.h_cand, problem.h_ant,
                                  problem.delassus, self._bias, self._friction, self._active)
        return solver.solve(view, self._impulse, self._zero, self.pseudo_velocity)


@nb.njit(cache=True)
def _projection_targets(law, gap_end, initial_gap, count, law_kind, law_map, h, bias, active):
    """bias = (g+ - g0) / h [m/s] (g0: a _g0 law's initial gap, else 0) for gap-law contacts,
    which include the viscous joints' contact part and the cohesive contacts that were never
    bonded (law_map flag 0: a bonded joint's closure is its compliance's,
    saxum.solver.laws_local) (the others inactive); returns the largest end-of-step
    interpenetration g0 - g+ [m] among them (0 if none)."""
    worst = 0.0
    for a in range(count):
        kind = law_kind[law[a]]
        active[a] = kind == _GAP or kind == _VISCOUS or (kind == _COHESIVE
                                                         and law_map[a, 0] == 0.0)
        if not active[a]:
            bias[a] = 0.0
            continue
        bias[a] = (gap_end[a] - initial_gap[a]) / h
        worst = max(worst, initial_gap[a] - gap_end[a])
    return worst
