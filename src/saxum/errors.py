"""Errors raised on bad input. Each message names the block, parameter or pair at fault."""

__all__ = ["InputError", "OverlapError", "ResultsDamageWarning", "ResultsWriteError",
           "SimulationError", "SolverWarning"]


class InputError(ValueError):
    """Bad model, load or solver input; the message says what is wrong and what to do."""


class OverlapError(InputError):
    """Two blocks interpenetrate at the start of a run."""


class SimulationError(RuntimeError):
    """The time integration broke down (NaN or infinite velocities); the message gives the step."""


class ResultsWriteError(OSError):
    """A results file could not be written (a full disk, a file-size limit); the message says
    up to where the file is readable and how to continue."""


class ResultsDamageWarning(UserWarning):
    """A results file is truncated or damaged: what was lost and what is read."""


class SolverWarning(UserWarning):
    """The contact solver did not converge at some steps; the step log says which."""
