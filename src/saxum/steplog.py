"""Per-step record of what the solver did, kept with the results."""

import math
import operator
from dataclasses import dataclass

import numpy as np

__all__ = ["STEP_DTYPES", "STEP_OUTCOMES", "StepLog", "StepReport", "bonds_note",
           "natural_map_note", "why_not_converged"]

STEP_OUTCOMES = ("converged", "stalled", "out of sweeps", "projection")
"""How a step's solve ended (StepReport.outcome is the index): converged; not converged
because the error had stalled (stopped falling: saxum.solver.base.error_trend) or because
the sweeps ran out while it was still falling; or the contact solve converged and the
gap-based law's position projection did not."""


# slotted, not frozen: one is made every step, and a frozen dataclass's __init__ sets each of
# its fields through object.__setattr__ (several us a step on a small model); read-only by use
@dataclass(slots=True)
class StepReport:
    """One step: end time [s], solver sweeps, final error [-], converged (the contact solve and
    the projection, if any), contacts found, contacts carrying load (R_n > 0), largest
    interpenetration at the end [m], kinetic energy [J/m], sweeps of the gap-based law's
    position projection (0 when none was needed; saxum.solver.projection), the solver that
    finished the contact solve (index into saxum.solver.SOLVER_NAMES: 0 NLGS, 1 the conic
    fixed point, 2 semismooth Newton, 3 smoothing Newton, 4 the proximal point, the last four
    of saxum.solver.hybrid), for a contact solve that
    ended above its tolerance the natural-map error of its impulses [-]
    (saxum.solver.SolverReport.natural_map: how far from a solution; nan where not measured),
    how the step ended (index into STEP_OUTCOMES) and, where the contact solve did not
    converge, its error's factor per sweep over its last sweeps (rate [-], nan where not
    measured or converged), and for cohesive joints (saxum.laws COHESIVE) the contact points
    whose bond was lost in the step (damage reached 1: bonds_lost) and those partly damaged
    (0 < d < 1) at its end (damaged); 0 without cohesive joints."""

    step: int
    time: float
    iterations: int
    error: float
    converged: bool
    contacts: int
    active_contacts: int
    max_interpenetration: float
    kinetic_energy: float
    projection_iterations: int = 0
    solver: int = 0
    natural_map: float = math.nan
    outcome: int = 0
    rate: float = math.nan
    bonds_lost: int = 0
    damaged: int = 0


STEP_DTYPES = {
    "step": np.int64,
    "time": np.float64,
    "iterations": np.int64,
    "error": np.float64,
    "converged": np.bool_,
    "contacts": np.int64,
    "active_contacts": np.int64,
    "max_interpenetration": np.float64,
    "kinetic_energy": np.float64,
    "projection_iterations": np.int64,
    "solver": np.int8,
    "natural_map": np.float64,
    "outcome": np.int8,
    "rate": np.float64,
    "bonds_lost": np.int64,
    "damaged": np.int64,
}


_BATCH = 256
"""Reports held before they are written into the columns: one write per column for the batch
costs less than 16 scalar writes per step, which are most of a small model's step log."""
_FIELDS = operator.attrgetter(*STEP_DTYPES)


class StepLog:
    """Growable column arrays of StepReport fields; `log.iterations` etc. give numpy views.
    Appended reports are written into the columns by batches, and on any read."""

    def __init__(self) -> None:
        self._n = 0
        self._cols = {k: np.zeros(_BATCH, dtype=t) for k, t in STEP_DTYPES.items()}
        self._held: list[StepReport] = []

    def __len__(self) -> int:
        return self._n + len(self._held)

    def append(self, r: StepReport) -> None:
        self._held.append(r)
        if len(self._held) == _BATCH:
            self._write()

    def _write(self) -> None:
        """Write the held reports into the columns (grown by doubling)."""
        held, n = self._held, self._n
        if not held:
            return
        size = len(self._cols["time"])
        if n + len(held) > size:
            grown = max(2 * size, n + len(held))
            self._cols = {k: np.concatenate([a, np.zeros(grown - size, dtype=a.dtype)])
                          for k, a in self._cols.items()}
        rows = zip(*map(_FIELDS, held), strict=True)  # (a column of values per field)
        for col, values in zip(self._cols.values(), rows, strict=True):
            col[n: n + len(held)] = values
        self._n += len(held)
        self._held = []

    def __getattr__(self, name: str) -> np.ndarray:
        if name in self.__dict__.get("_cols", {}):
            self._write()  # (which may grow the columns: read them after it)
            return self._cols[name][: self._n]
        raise AttributeError(name)

    def non_converged(self) -> np.ndarray:
        """Step numbers at which the solver stopped on its iteration cap."""
        return self.step[~self.converged]

    def why(self, first: int = 0) -> str:
        """Why the steps from index `first` on that did not converge did not
        (why_not_converged)."""
        return why_not_converged(*(getattr(self, k)[first:] for k in
                                   ("step", "converged", "outcome", "rate", "error")))

    def summary(self) -> str:
        """One line: steps, iterations (mean, max), non-converged steps, bonds lost (if any),
        worst interpenetration."""
        if len(self) == 0:
            return "no steps"
        bad = self.non_converged()
        conic = int(np.count_nonzero(self.solver == 1))
        newton = int(np.count_nonzero(self.solver == 2))
        proximal = int(np.count_nonzero(self.solver == 4))
        return (
            f"{len(self)} steps, NLGS sweeps mean {self.iterations.mean():.1f} max "
            f"{self.iterations.max()}, not converged at {bad.size} step(s)"
            + (f" ({self.why()})" if bad.size else "")
            + natural_map_note(self.natural_map[~self.converged])
            + (f", finished by the conic solver at {conic} step(s)" if conic else "")
            + (f", finished by semismooth Newton at {newton} step(s)" if newton else "")
            + (f", finished by the proximal point at {proximal} step(s)" if proximal else "")
            + bonds_note(self.step, self.bonds_lost)
            + f", largest interpenetration {self.max_interpenetration.max():.3g} m"
        )


def bonds_note(step: np.ndarray, bonds_lost: np.ndarray) -> str:
    """', N bond(s) cracked (first at step S)' from the step log's bonds_lost column; "" if
    none cracked."""
    cracked = np.flatnonzero(bonds_lost)
    if cracked.size == 0:
        return ""
    return (f", {int(bonds_lost.sum())} bond(s) cracked (first at step "
            f"{int(step[cracked[0]])})")


def natural_map_note(values: np.ndarray) -> str:
    """', no solution reached: natural-map error of their impulses up to X' where the solver
    measured it (the hybrid, on the steps it did not converge: the step's problem may have a
    solution that no solver reached, benchmarks/capped_steps.py --existence)."""
    measured = values[np.isfinite(values)]
    if measured.size == 0:
        return ""
    return (f", no solution reached: natural-map error of their impulses up to "
            f"{measured.max():.3g}")


def why_not_converged(step: np.ndarray, converged: np.ndarray, outcome: np.ndarray,
                      rate: np.ndarray, error: np.ndarray) -> str:
    """The step log's columns of the steps that did not converge, summed up by outcome
    (STEP_OUTCOMES): how many stalled and their largest error, how many ran out of sweeps
    with the error still falling and its slowest rate per sweep, how many failed in the
    position projection; "" if every step converged."""
    parts = []
    for code, name in enumerate(STEP_OUTCOMES[1:], start=1):
        k = ~converged & (outcome == code)
        if not k.any():
            continue
        n, first = int(k.sum()), int(step[k][0])
        if name == "stalled":
            parts.append(f"{n} stalled (the error stopped falling; largest error "
                         f"{error[k].max():.2g}; first at step {first})")
        elif name == "out of sweeps":
            rates = rate[k][np.isfinite(rate[k])]
            trend = (f"error still falling, slowest rate {rates.max():.6f} per sweep"
                     if rates.size else "the error's trend not measured")
            parts.append(f"{n} ran out of sweeps ({trend}; largest error "
                         f"{error[k].max():.2g}; first at step {first})")
        else:
            parts.append(f"{n} in the position projection (first at step {first})")
    return "; ".join(parts)
