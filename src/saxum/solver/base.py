"""The interface every contact solver implements, and what it reports."""

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from .problem import ContactProblem

__all__ = ["SOLVER_NAMES", "ContactSolver", "SolverReport"]

SOLVER_NAMES = ("nlgs", "conic", "newton")
"""Solvers that can finish a step; the step log stores the index (StepReport.solver)."""


@dataclass(frozen=True)
class SolverReport:
    """What a solver did on one step: iterations (Gauss-Seidel sweeps), final error,
    converged or not, and which solver finished the step (an entry of SOLVER_NAMES: "nlgs",
    or "conic" / "newton" when saxum.solver.hybrid's attempt with the conic fixed point or
    semismooth Newton was kept); natural_map: where the solve ended above the tolerance, the
    natural-map error ||F_nat(R)|| / ||q|| of the impulses it returned (saxum.solver.residual:
    how far they are from a solution of the step's problem, whatever the solver's own
    criterion), nan where not measured (a converged solve; NLGS alone)."""

    iterations: int
    error: float
    converged: bool
    solver: str = "nlgs"
    natural_map: float = math.nan


class ContactSolver(ABC):
    """Finds the impulses R of a ContactProblem and the end-of-step velocities v."""

    @abstractmethod
    def solve(self, problem: ContactProblem, impulse: np.ndarray, v_free: np.ndarray,
              v: np.ndarray) -> SolverReport:
        """impulse [N s] (count, dim): the starting guess, overwritten with the solution;
        v_free [m/s, rad/s] (bodies, dof): the free velocity; v: v_free + M^-1 H impulse on
        entry, the end-of-step velocity v_free + M^-1 H R on return."""

    def forget(self) -> None:
        """Drop what the solver carries from one step to the next (none by default; NLGS:
        the rest solutions it extrapolates), so that stepping on gives what a new solver
        would: the runner calls it at every checkpoint, which a resumed run starts from."""
        return None

    def carries_state(self) -> bool:
        """Whether the solver holds something from earlier steps that forget() would drop,
        so that stepping on differs from a new solver's steps (a checkpoint written now would
        not resume bit for bit)."""
        return False
