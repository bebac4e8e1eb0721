"""Contact solvers: the local problem of a step and the algorithms that solve it."""

from .base import SOLVER_NAMES, ContactSolver, SolverReport
from .hybrid import ConicSolver, Hybrid
from .nlgs import NLGS
from .problem import ContactProblem
from .projection import PositionProjection

__all__ = ["NLGS", "SOLVER_NAMES", "ConicSolver", "ContactProblem", "ContactSolver", "Hybrid",
           "PositionProjection", "SolverReport"]
