"""Errors raised on bad input. Each message names the block, parameter or pair at fault."""

__all__ = ["InputError", "OverlapError", "ResultsDamageWarning", "ResultsWriteError",
           "SimulationError", "SolverWarning", "UndampedJointWarning", "plain"]


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


class UndampedJointWarning(UserWarning):
    """theta = 1/2 was given for a model whose joint springs nothing damps: they will vibrate
    for the whole run; the message names the laws and what to do."""


def plain(value) -> str:
    """repr of a value for a message, numpy scalars and arrays (also inside tuples and lists)
    as Python numbers: numpy 2 writes np.float64(0.5) where a user gave 0.5."""
    if hasattr(value, "tolist"):  # a numpy scalar or array
        return repr(value.tolist())
    if isinstance(value, tuple | list):
        inner = ", ".join(plain(v) for v in value)
        return f"({inner},)" if isinstance(value, tuple) and len(value) == 1 else (
            f"({inner})" if isinstance(value, tuple) else f"[{inner}]")
    return repr(value)
