"""The interface every contact solver implements, and what it reports."""

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from .problem import ContactProblem

__all__ = ["SOLVER_NAMES", "STALLED", "ContactSolver", "SolverReport", "error_trend"]

SOLVER_NAMES = ("nlgs", "conic", "newton", "smoothing", "proximal")
"""Solvers that can finish a step; the step log stores the index (StepReport.solver)."""

STALLED = 1e-5
"""An error that falls by less than this fraction per sweep (0.5 % over 500 sweeps) has
stalled; above it the error is still falling and more sweeps would have gone on."""


def error_trend(errors: list[float], sweeps: int) -> tuple[float, bool]:
    """(rate, stalled) of a solve that did not converge, from its error [-] at the end of
    windows of `sweeps` sweeps each, oldest first: rate is the least error's factor per sweep
    from the first half of the windows to the second (the least, not the last: NLGS's error
    oscillates from sweep to sweep at the friction threshold), stalled that it is above
    1 - STALLED. (nan, False) with fewer than two windows."""
    half = len(errors) // 2
    if half == 0 or sweeps < 1:
        return math.nan, False
    before, after = min(errors[-2 * half:-half]), min(errors[-half:])
    if not (before > 0.0 and math.isfinite(before) and math.isfinite(after)):
        return math.nan, False
    rate = (after / before) ** (1.0 / (half * sweeps))
    return rate, rate > 1.0 - STALLED


@dataclass(slots=True)  # made every step: slotted, not frozen (saxum.steplog.StepReport)
class SolverReport:
    """What a solver did on one step: iterations (Gauss-Seidel sweeps), final error,
    converged or not, and which solver finished the step (an entry of SOLVER_NAMES: "nlgs",
    or "conic" / "newton" when saxum.solver.hybrid's attempt with the conic fixed point or
    semismooth Newton was kept). natural_map: the natural-map error ||F_nat(R)|| / ||q|| of
    the impulses it returned (saxum.solver.residual: how far they are from a solution of the
    step's problem, whatever the solver's own criterion), where it did not converge or where
    the hybrid ended the step by it (then also `error`); nan where not measured (NLGS alone,
    steps converged by NLGS's criterion); rate, the error's factor per sweep over its last sweeps
    (nan where not measured), and stalled, whether the error had stopped falling there
    (error_trend) rather than the sweeps running out."""

    iterations: int
    error: float
    converged: bool
    solver: str = "nlgs"
    natural_map: float = math.nan
    rate: float = math.nan
    stalled: bool = False


def prefixed(prefix: str, state: dict) -> dict:
    """The entries of `state` (a part's checkpoint()) named "prefix.name", for a checkpoint
    that holds several parts' (unprefixed takes them out)."""
    return {f"{prefix}.{name}": value for name, value in state.items()}


def unprefixed(saved: dict, prefix: str) -> dict:
    """The entries of `saved` named "prefix.name", as "name"."""
    start = len(prefix) + 1
    return {name[start:]: value for name, value in saved.items()
            if name.startswith(prefix + ".")}


class ContactSolver(ABC):
    """Finds the impulses R of a ContactProblem and the end-of-step velocities v."""

    @abstractmethod
    def solve(self, problem: ContactProblem, impulse: np.ndarray, v_free: np.ndarray,
              v: np.ndarray) -> SolverReport:
        """impulse [N s] (count, dim): the starting guess, overwritten with the solution;
        v_free [m/s, rad/s] (bodies, dof): the free velocity; v: v_free + M^-1 H impulse on
        entry, the end-of-step velocity v_free + M^-1 H R on return."""

    def checkpoint(self) -> dict[str, np.ndarray]:
        """Everything the solver carries from one step to the next, as named arrays that a
        checkpoint holds (saxum.results: _SOLVER_FIELDS, and the others packed in
        _SOLVER_STATE), which restore() puts back, so that a run resumed from a checkpoint
        steps as the run made in one go, bit for bit: none by default; NLGS: its refinement's
        flags (saxum.solver.nlgs.Refinement), the rest solution's back-off and the anchors of
        the loads it follows (saxum.solver.load_following); Hybrid: also its switches'
        back-off."""
        return {}

    def restore(self, saved: dict) -> None:
        """The solver as it was at the checkpoint `saved` (saxum.results.Results.checkpoint)
        that checkpoint() wrote; what `saved` lacks (a file written before it was stored) as
        a new solver's."""
        return None
