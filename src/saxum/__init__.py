"""saxum: Non-Smooth Contact Dynamics for masonry structures of rigid blocks.

The pipeline: a ModelBuilder collects blocks and contact laws -> finalize() gives a Model ->
Simulation(model, dt=...) steps a State with Moreau-Jean time stepping and NLGS.

The names below (and the subpackages, saxum.structures...) load on first use, so that
`import saxum` itself takes no time: the command line's start-up, where a Ctrl-C must still
find saxum.__main__'s handler, and a child process that only compiles kernels need it light.
"""

import importlib.util

from ._version import __version__ as __version__

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
    "Simulation": "simulation",
    "SimulationError": "errors",
    "SolverWarning": "errors",
    "State": "state",
    "STEP_OUTCOMES": "steplog",
    "StepLog": "steplog",
    "StepReport": "steplog",
    "fit_capacities": "fragility",
    "fit_stripes": "fragility",
    "limit_analysis": "limit",
    "load_scenario": "scenario",
    "read_ensemble": "ensemble",
    "run_ensemble": "ensemble",
    "run_scenario": "runner",
    "view_html": "view",
    "write_view": "view",
}
"""Each public name: the module that defines it."""

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    """A public name, or a subpackage (saxum.structures...), imported on first use."""
    if name in _EXPORTS:
        value = getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value
        return value
    if not name.startswith("_") and importlib.util.find_spec(f"{__name__}.{name}") is not None:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_EXPORTS})
