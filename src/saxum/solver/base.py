"""The interface every contact solver implements, and what it reports."""

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from .problem import ContactProblem

__all__ = ["ContactSolver", "SolverReport"]


@dataclass(frozen=True)
class SolverReport:
    """What a solver did on one step: iterations, final error, converged or not."""

    iterations: int
    error: float
    converged: bool


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
