"""saxum: Non-Smooth Contact Dynamics for masonry structures of rigid blocks.

The pipeline: a ModelBuilder collects blocks and contact laws -> finalize() gives a Model ->
Simulation(model, dt=...) steps a State with Moreau-Jean time stepping and NLGS.

The names below (and the subpackages, saxum.structures...) load on first use, so that
`import saxum` itself takes no time: the command line's start-up, where a Ctrl-C must still
find saxum.__main__'s handler, and a child process that only compiles kernels need it light.
"""

import importlib.util

from . import _shipped_cache
from ._version import __version__ as __version__

# the kernels compiled when the package was built: numba finds them once it is imported
_shipped_cache.install()

_EXPORTS = {
    "NLGS": "solver",
    "BodyKind": "model",
    "ConicSolver": "solver",
    "ContactLaw": "laws",
    "ContactSolver": "solver",
    "Contacts": "contacts",
    "DetectionSettings": "detection",
    "Elastic": "fe",
    "Ensemble": "ensemble",
    "EnsembleSpec": "scenario",
    "FloodLoad": "flood",
    "Fragility": "fragility",
    "Hybrid": "solver",
    "InputError": "errors",
    "LawKind": "laws",
    "LimitAnalysis": "limit",
    "NO_CONTACT": "laws",
    "Model": "model",
    "ModelBuilder": "model",
    "MoreauJean": "integrator",
    "OverlapError": "errors",
    "Results": "results",
    "Scenario": "scenario",
    "Shape": "model",
    "Simulation": "simulation",
    "SimulationError": "errors",
    "SolverWarning": "errors",
    "UndampedJointWarning": "errors",
    "State": "state",
    "STEP_OUTCOMES": "steplog",
    "StepLog": "steplog",
    "StepReport": "steplog",
    "capsule_axis": "model",
    "capsule_properties": "model",
    "ContactForce": "warmstart",
    "apply_warm_start": "warmstart",
    "contact_forces": "warmstart",
    "read_warm_start": "warmstart",
    "write_warm_start": "warmstart",
    "export_lmgc90": "lmgc90",
    "fit_capacities": "fragility",
    "fit_stripes": "fragility",
    "import_lmgc90": "lmgc90",
    "limit_analysis": "limit",
    "load_scenario": "scenario",
    "read_ensemble": "ensemble",
    "run_ensemble": "ensemble",
    "run_scenario": "runner",
    "spherocylinder_properties": "model",
    "view_html": "view",
    "write_view": "view",
}
"""Each public name: the module that defines it."""

__all__ = sorted(_EXPORTS)


def _lazy_names(package: str, exports: dict[str, str], namespace: dict):
    """(__getattr__, __dir__) of a package whose public names `exports` ({name: module})
    are imported from their modules on first use, then kept in `namespace`."""

    def getattr_(name: str):
        if name in exports:
            value = getattr(importlib.import_module(f".{exports[name]}", package), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def dir_() -> list[str]:
        return sorted({*namespace, *exports})

    return getattr_, dir_


_export, __dir__ = _lazy_names(__name__, _EXPORTS, globals())


def __getattr__(name: str):
    """A public name, or a subpackage (saxum.structures...), imported on first use."""
    if (name not in _EXPORTS and not name.startswith("_")
            and importlib.util.find_spec(f"{__name__}.{name}") is not None):
        return importlib.import_module(f".{name}", __name__)
    return _export(name)
