"""saxum: Non-Smooth Contact Dynamics for masonry structures of rigid blocks.

The pipeline: a ModelBuilder collects blocks and contact laws -> finalize() gives a Model ->
Simulation(model, dt=...) steps a State with Moreau-Jean time stepping and NLGS.
"""

from ._version import __version__ as __version__
from .contacts import Contacts
from .detection import DetectionSettings
from .errors import InputError, OverlapError, SimulationError, SolverWarning
from .flood import FloodLoad
from .integrator import MoreauJean
from .laws import ContactLaw, LawKind
from .model import BodyKind, Model, ModelBuilder
from .results import Results
from .runner import run_scenario
from .scenario import Scenario, load_scenario
from .simulation import Simulation
from .solver import NLGS, ConicSolver, ContactSolver, Hybrid
from .state import State
from .steplog import StepLog, StepReport

__all__ = [
    "NLGS",
    "BodyKind",
    "ConicSolver",
    "ContactLaw",
    "ContactSolver",
    "Contacts",
    "DetectionSettings",
    "FloodLoad",
    "Hybrid",
    "InputError",
    "LawKind",
    "Model",
    "ModelBuilder",
    "MoreauJean",
    "OverlapError",
    "Results",
    "Scenario",
    "Simulation",
    "SimulationError",
    "SolverWarning",
    "State",
    "StepLog",
    "StepReport",
    "load_scenario",
    "run_scenario",
]
