"""Contact solvers: the local problem of a step and the algorithms that solve it."""

from .base import ContactSolver, SolverReport
from .nlgs import NLGS
from .problem import ContactProblem
from .projection import PositionProjection

__all__ = ["NLGS", "ContactProblem", "ContactSolver", "PositionProjection", "SolverReport"]
