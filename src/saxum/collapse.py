"""Loading to collapse: is the structure at rest or collapsing under a given load, and the
critical value of a load parameter found by bisection.

A trial runs a simulation of the structure under a fixed value of the parameter (a horizontal
load factor, a point load, a settlement, a thickness...) from rest, and decides:

- **at rest** when, for `settle` seconds in a row, the unbalanced force ratio
      UFR = sum_b |m_b (v_b+ - v_b-) / h| / sum_b (|F_ext,b| + sum_(alpha at b) |R_alpha| / h)
  (net force on the free blocks over the forces acting on them: weight and loads plus contact
  forces) stays below `force_ratio`, and the kinetic energy below `energy` times the potential
  energy scale m g L (L the structure's height). A mechanism that has started, however slowly,
  has a net force m a on its blocks, so UFR = a/g-ish stays above the threshold;
- **collapsed** as soon as a free block has moved by more than `displacement` [m] from its
  initial position;
- after `duration` seconds with neither (counted from `not_before`, the end of a pulse),
  collapsed if over the second half of that time both the kinetic energy and the largest
  displacement grew (a mechanism that keeps going), standing otherwise (e.g. a block still
  rocking after a pulse, back and forth about its initial position).

For rigid blocks with unilateral frictional contacts a load below the collapse load is carried
with no motion at all (a statically admissible set of contact forces exists and v = 0 solves
every step), so loading from rest to a fixed value and bisecting on that value gives the
static collapse load; `critical_value` does it to a requested relative accuracy and returns
the bracket.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError
from .model import BodyKind
from .simulation import Simulation
from .state import State

__all__ = ["CollapseCriterion", "CriticalValue", "Trial", "collapse_curve", "critical_value",
           "run_trial", "scenario_critical_value", "unbalanced_force_ratio"]


@dataclass(frozen=True)
class CollapseCriterion:
    """Thresholds of a trial (see the module doc): displacement [m] (default: `fraction` of
    the smallest free block's size, 1 %: the start of a mechanism under a static load; under
    a pulse a block may rock far and come back, so collapse curves use 50 %), duration [s]
    (after not_before), settle [s], force_ratio [-], energy [-];
    not_before [s]: no verdict before this time (the end of a pulse or record: a structure
    is at rest before a pulse has risen, and a block that rocks far during a pulse may be
    brought back by it; what counts is where it is once the ground is still)."""

    displacement: float | None = None
    fraction: float = 0.01
    duration: float = 1.0
    settle: float = 0.05
    force_ratio: float = 1e-4
    energy: float = 1e-9
    not_before: float = 0.0

    def __post_init__(self) -> None:
        for name in ("fraction", "duration", "settle", "force_ratio", "energy"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise InputError(f"collapse criterion {name} must be > 0, got {value}")
        if self.displacement is not None and not self.displacement > 0.0:
            raise InputError(f"collapse criterion displacement must be > 0 [m], got "
                             f"{self.displacement}")


@dataclass
class Trial:
    """Outcome of one trial: the parameter value, collapsed or at rest, the time it was
    decided [s], the largest displacement of a free block [m], the last unbalanced force ratio,
    the kinetic energy at the end [J/m], and the simulation and state at the end."""

    value: float
    collapsed: bool
    time: float
    displacement: float
    force_ratio: float
    kinetic_energy: float
    simulation: Simulation = field(repr=False)
    state: State = field(repr=False)


def unbalanced_force_ratio(sim: Simulation, state: State, v_before: np.ndarray) -> float:
    """UFR of the last step (module doc): net force over acting forces on the free blocks;
    v_before: the velocities at the start of the step [m/s, rad/s]."""
    m = sim.model
    h = sim.integrator.dt
    d = m.dim
    free = m.body_kind == BodyKind.FREE
    net = np.linalg.norm(state.body_v[free, :d] - v_before[free, :d], axis=1) * m.body_mass[
        free] / h
    force = np.empty_like(state.body_v)
    sim.external_force(state.time, force)
    applied = np.linalg.norm(force[free, :d], axis=1)
    c = state.contacts
    r = np.linalg.norm(c.impulse[: c.count], axis=1) / h
    contact = (np.bincount(c.candidate[: c.count], r, m.body_count)
               + np.bincount(c.antagonist[: c.count], r, m.body_count))[free]
    acting = float(applied.sum() + contact.sum())
    return float(net.sum()) / acting if acting > 0.0 else 0.0


def run_trial(sim: Simulation, value: float = math.nan,
              criterion: CollapseCriterion | None = None) -> Trial:
    """Run `sim` from rest until it is judged at rest or collapsed (module doc)."""
    crit = criterion or CollapseCriterion()
    m = sim.model
    free = m.body_kind == BodyKind.FREE
    if not free.any():
        raise InputError("a collapse trial needs at least one free block")
    limit = crit.displacement or crit.fraction * float(m.body_size[free].min())
    h = sim.integrator.dt
    up = m.dim - 1  # the vertical axis: y in 2D, z in 3D
    height = float(np.ptp(m.vertex_local[:, up]) + np.ptp(m.body_q0[:, up]))
    g = float(np.linalg.norm(m.gravity)) or 1.0
    energy_scale = float(m.body_mass[free].sum()) * g * height
    state = sim.initial_state()
    steps = round((crit.not_before + crit.duration) / h)
    first = min(round(crit.not_before / h), steps - 1)  # the window the verdicts look at
    settle = max(1, round(crit.settle / h))
    quiet = 0
    energies = np.zeros(steps)
    displacements = np.zeros(steps)
    moved = ratio = 0.0
    v_before = np.empty_like(state.body_v)
    for k in range(steps):
        v_before[:] = state.body_v
        report = sim.step(state)
        energies[k] = report.kinetic_energy
        moved = float(np.linalg.norm(state.body_q[free, : m.dim] - m.body_q0[free, : m.dim],
                                     axis=1).max())
        displacements[k] = moved
        if moved > limit and state.time >= crit.not_before:
            return Trial(value, True, state.time, moved, ratio, report.kinetic_energy, sim,
                         state)
        ratio = unbalanced_force_ratio(sim, state, v_before)
        rest = ratio <= crit.force_ratio and report.kinetic_energy <= crit.energy * energy_scale
        quiet = quiet + 1 if rest else 0
        if quiet >= settle and state.time >= crit.not_before:
            return Trial(value, False, state.time, moved, ratio, report.kinetic_energy, sim,
                         state)
    half = (first + steps) // 2
    growing = (energies[half:].mean() > energies[first:half].mean()
               and displacements[half:].max() > displacements[first:half].max())
    return Trial(value, bool(growing), state.time, moved, ratio, float(energies[-1]), sim,
                 state)


@dataclass
class CriticalValue:
    """The critical value of a parameter, bracketed: the value closest to it at which the
    structure stood (`stands`) and at which it collapsed (`collapses`), and every trial."""

    stands: float
    collapses: float
    trials: list[Trial]

    @property
    def value(self) -> float:
        """Midpoint of the bracket."""
        return 0.5 * (self.stands + self.collapses)

    def collapse(self) -> Trial:
        """The trial at `collapses`: the structure failing just past the critical value."""
        return next(t for t in reversed(self.trials) if t.value == self.collapses)


def critical_value(make_simulation: Callable[[float], Simulation], stands: float,
                   collapses: float, *, tolerance: float = 0.005,
                   criterion: CollapseCriterion | None = None) -> CriticalValue:
    """Bisect on a parameter x: make_simulation(x) builds the structure under the load x
    (or with the geometry x). The structure must stand at x = `stands` and collapse at
    x = `collapses` (either may be the larger: a load factor collapses above, a thickness
    below), which is checked first. Stops when the bracket is narrower than tolerance times
    the larger magnitude of its ends."""
    if not (tolerance > 0.0):
        raise InputError(f"tolerance must be > 0, got {tolerance}")
    trials: list[Trial] = []

    def collapsed(x: float) -> bool:
        trial = run_trial(make_simulation(x), x, criterion)
        trials.append(trial)
        return trial.collapsed

    if collapsed(stands):
        raise InputError(f"the structure already collapses at {stands:g}; start the bracket "
                         "at a value where it stands")
    if not collapsed(collapses):
        raise InputError(f"the structure still stands at {collapses:g}; widen the bracket")
    while abs(collapses - stands) > tolerance * max(abs(stands), abs(collapses)):
        mid = 0.5 * (stands + collapses)
        if collapsed(mid):
            collapses = mid
        else:
            stands = mid
    return CriticalValue(stands, collapses, trials)


def scenario_critical_value(path, key: str, stands: float, collapses: float, *,
                            overrides: tuple[str, ...] = (), tolerance: float = 0.005,
                            criterion: CollapseCriterion | None = None) -> CriticalValue:
    """critical_value over the scenario key `key` (dotted, e.g. loads.horizontal_acceleration,
    structure.thickness or loads.ground_motion.amplitude) of the scenario file at `path`, other
    keys overridden by `overrides` ("key=value"). With a ground motion, no trial is judged at
    rest before the motion has ended."""
    from .scenario import load_scenario

    def make(x: float) -> Simulation:
        return load_scenario(path, [*overrides, f"{key}={x!r}"]).build_simulation()

    crit = criterion or CollapseCriterion()
    scenario = load_scenario(path, list(overrides))
    ground = scenario.loads.ground_motion
    if ground is not None:
        end = float(ground.motion(scenario.structure.dim).time[-1])
        crit = dataclasses.replace(crit, not_before=max(crit.not_before, end))
    return critical_value(make, stands, collapses, tolerance=tolerance, criterion=crit)


def _curve_point(args) -> tuple[float, float, float, int]:
    path, period, stands, collapses, overrides, tolerance, criterion = args
    result = scenario_critical_value(
        path, "loads.ground_motion.amplitude", stands, collapses,
        overrides=(*overrides, f"loads.ground_motion.period={period!r}"), tolerance=tolerance,
        criterion=criterion)
    return period, result.stands, result.collapses, len(result.trials)


def collapse_curve(path, periods, stands: float, collapses: float, *,
                   overrides: tuple[str, ...] = (), tolerance: float = 0.01,
                   criterion: CollapseCriterion | None = None,
                   processes: int | None = None) -> list[tuple[float, float, float, int]]:
    """For a scenario with a pulse (`[loads.ground_motion]` with `pulse`): for each period
    T_p [s], the smallest pulse amplitude [m/s^2] that collapses the structure, bracketed by
    bisection between `stands` and `collapses`; the periods run in parallel processes.
    Returns (period, stands at, collapses at, trials) per period, in the order given."""
    jobs = [(str(path), float(p), stands, collapses, tuple(overrides), tolerance, criterion)
            for p in periods]
    if processes == 1 or len(jobs) == 1:
        return [_curve_point(job) for job in jobs]
    with concurrent.futures.ProcessPoolExecutor(max_workers=processes) as pool:
        return list(pool.map(_curve_point, jobs))
