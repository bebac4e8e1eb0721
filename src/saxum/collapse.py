"""Loading to collapse: is the structure at rest or collapsing under a given load, and the
critical value of a load parameter found by bisection.

A trial runs a simulation of the structure under a fixed value of the parameter (a horizontal
load factor, a point load, a settlement, a thickness...) from rest, and decides:

- **at rest** when, for `settle` seconds in a row, the unbalanced force ratio of every free
  block b,
      UFR_b = |m_b (v_b+ - v_b-) / h| / (|F_ext,b| + sum_(alpha at b) |R_alpha| / h)
  (its net force over the forces acting on it: weight and loads plus contact forces), stays
  below `force_ratio`, and the kinetic energy below `energy` times the potential energy scale
  m g L (L the structure's height). A mechanism that has started, however slowly, has a net
  force m a on its blocks, so UFR = a/g-ish, above the threshold unless it starts very
slowly (below). (The ratio of the sums
  over the whole structure, `per_block=False`, hides a small part, a parapet, that starts to
  move slowly on a large structure: its net force is tiny next to the forces on the rest.)
  That quiet is only the trigger: the verdict needs an equilibrium certificate, a rest
  solution of the last step found by the static programme (saxum.limit.rest_certificate);
  a mechanism just past its limit starts too slowly for the force ratio to see it and has
  none, so the trial runs on (up to `run_on` x `duration` more) until it moves away. Models
  without a certificate (deformable blocks, joint laws) are judged by the quiet alone
  (Trial.certified False);
- **collapsed** as soon as a free block has moved by more than `displacement` [m] from its
  initial position;
- after `duration` seconds with neither (counted from `not_before`, the end of a pulse;
  with a certificate, `duration` x (1 + `run_on`)), uncertified: collapsed if over the
  second half of that time both the kinetic energy and the largest displacement grew (a
  mechanism that keeps going), standing otherwise (e.g. a block still rocking after a
  pulse, back and forth about its initial position).

Under an imposed settlement (`after_motion`, with `not_before` the end of the settlement)
the blocks carried by the moving support move with it without collapsing, so a trial is
judged instead:

- **collapsed during the settlement** as soon as a free block's kinetic energy exceeds
  m_b |g| d, d the displacement threshold: the block moves as fast as after falling freely
  by d, sqrt(2 |g| d) (0.3 m/s for d = 4.5 mm), while a structure that follows a slow
  settlement quasi-statically moves at the support's speed times a lever ratio of order one;
- then, with displacements measured from where the blocks are when the support stops:
  **at rest** as above (the settlement is accommodated, usually with a mechanism: joints
  opened, blocks moved with the support), **collapsed** if a block moves on by more than d
  (a block falling, a mechanism that keeps going).

The settlement must then be slow and start and stop smoothly (saxum.scenario Settlement
with profile = "smooth"), so that no block is thrown by the support's own motion.

Deformable blocks (saxum.bodies.fe) are watched with the free ones: a deformable block's
displacement is that of its body row, the centre of mass of its nodes (the co-rotated
frame's centroid: the rigid block's centre plus the mean of its elastic displacement, which
at masonry stiffnesses is far below the 1 % threshold; for soft blocks, E ~ 10 MPa, the
sway under the load may reach it: raise `displacement` above it), its force ratio that of
its momentum (unbalanced_force_ratio) and its kinetic energy 1/2 v^T M v of its nodes. No
equilibrium certificate exists for them, so their verdicts at rest are uncertified
(Trial.certified).

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
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from .errors import InputError
from .mechanism import CREEP
from .model import BodyKind
from .simulation import Simulation
from .state import State

__all__ = ["DYNAMIC_FRACTION", "ONSET", "BracketError", "CollapseCriterion", "CollapseEvent",
           "CriticalValue", "CurvePoint", "SolverFailures", "Trial", "bisect", "collapse_curve",
           "critical_value", "find_collapse", "run_trial", "scenario_critical_value",
           "solver_failures", "unbalanced_force_ratio"]

DYNAMIC_FRACTION = 0.5
"""Under ground motion a block may rock far and come back: a structure has collapsed when a
free block has moved by this fraction of the smallest free block's size [-] and stays so."""
ONSET = 0.2
"""The mechanism at collapse is taken when the collapsing motion began: when a block last
moved past this fraction of the collapse displacement [-] before the collapse (by the time a
block has moved half its size, extra hinges open as the blocks fall apart); find_collapse
goes back from there to where that motion started growing (module doc of find_collapse)."""


@dataclass(frozen=True)
class CollapseCriterion:
    """Thresholds of a trial (see the module doc): displacement [m] (default: `fraction` of
    the smallest free block's size, 1 %: the start of a mechanism under a static load; under
    a pulse a block may rock far and come back, so collapse curves use 50 %), duration [s]
    (after not_before), settle [s], force_ratio [-], energy [-];
    not_before [s]: no verdict before this time (the end of a pulse or record: a structure
    is at rest before a pulse has risen, and a block that rocks far during a pulse may be
    brought back by it; what counts is where it is once the ground is still);
    after_motion: a settlement ends at not_before: before it, collapse when a block moves as
    fast as after a free fall by the displacement threshold; after it, displacements count
    from the configuration at not_before instead of the initial one (module doc);
    per_block: the force ratio is the largest over the free blocks of each block's own (its
    net force over the forces acting on it, the default) or, if False, the structure's (sums
    over all free blocks), which calls a small part that starts to move slowly on a large
    structure (a parapet) at rest, its net force being tiny next to the forces on the rest;
    run_on: a trial still undecided after `duration` (neither certified at rest nor moved by
    the displacement threshold) runs on for up to run_on x duration more before the energy
    rule decides it, uncertified (module doc)."""

    displacement: float | None = None
    fraction: float = 0.01
    duration: float = 1.0
    settle: float = 0.05
    force_ratio: float = 1e-4
    energy: float = 1e-9
    not_before: float = 0.0
    after_motion: bool = False
    per_block: bool = True
    run_on: float = 4.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.run_on) and self.run_on >= 0.0):
            raise InputError(f"collapse criterion run_on must be >= 0, got {self.run_on}")
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
    decided [s], the largest displacement of a free block [m] (from the initial position, or
    from that at not_before with after_motion), the last unbalanced force ratio, the kinetic
    energy at the end [J/m], and the simulation and state at the end. For a collapse: the time
    of collapse [s], when a free block last moved past the displacement limit (under a pulse
    this may be before the verdict, which waits for the pulse to end), and the state when that
    collapsing motion began (`at_collapse`: when a block last moved past ONSET times the limit
    before it), whose mechanism (`mechanism()`) shows the hinges that formed before the blocks
    fell apart (nan and None when it stood). certified: standing with an equilibrium
    certificate (a rest solution of the last step, saxum.limit.rest_certificate), or
    collapsed with a block moved past the threshold; False for a verdict of the energy rule
    at the end of the longest trial, or at rest by the force ratio alone where no certificate
    exists (deformable blocks, joint laws)."""

    value: float
    collapsed: bool
    time: float
    displacement: float
    force_ratio: float
    kinetic_energy: float
    simulation: Simulation = field(repr=False)
    state: State = field(repr=False)
    collapse_time: float = math.nan
    at_collapse: State | None = field(default=None, repr=False)
    certified: bool = True

    def mechanism(self):
        """The saxum.mechanism.Mechanism at the time of collapse (None when it stood)."""
        from .mechanism import mechanism

        if self.at_collapse is None:
            return None
        return mechanism(self.simulation.model, self.at_collapse, self.simulation.integrator.dt)


def unbalanced_force_ratio(sim: Simulation, state: State, v_before: np.ndarray, *,
                           per_block: bool = False,
                           node_v_before: np.ndarray | None = None) -> float:
    """UFR of the last step (module doc): net force over acting forces on the free and
    deformable blocks (per_block: the largest of each block's own ratio); v_before: the body
    velocities at the start of the step [m/s, rad/s]; node_v_before: the deformable blocks'
    node velocities then [m/s] (a deformable block's net force is the change of its momentum,
    |sum_i m_i (v_i+ - v_i-)| / h, m_i its nodal masses; its applied force m_b |a|, a gravity
    and the uniform accelerations)."""
    m = sim.model
    h = sim.integrator.dt
    d = m.dim
    moving = _moving(m)
    net = np.linalg.norm(state.body_v[:, :d] - v_before[:, :d], axis=1) * m.body_mass / h
    force = np.empty_like(state.body_v)
    sim.external_force(state.time, force, state.body_q)
    applied = np.linalg.norm(force[:, :d], axis=1)
    fe = sim.fe
    if fe is not None:
        if node_v_before is None:
            raise InputError("unbalanced_force_ratio: this model has deformable blocks; give "
                             "node_v_before, their node velocities at the start of the step")
        b = fe.blocks
        change = b.node_mass[:, None] * (state.node_v - node_v_before)
        net[fe.model.body] = np.linalg.norm(
            np.add.reduceat(change, b.node_start[:-1], axis=0), axis=1) / h
        applied[fe.model.body] = _fe_masses(fe) * float(np.linalg.norm(
            sim._node_acceleration(state.time, state.time)))
    net, applied = net[moving], applied[moving]
    c = state.contacts
    r = np.linalg.norm(c.impulse[: c.count], axis=1) / h
    contact = (np.bincount(c.candidate[: c.count], r, m.body_count)
               + np.bincount(c.antagonist[: c.count], r, m.body_count))[moving]
    if per_block:
        acting = applied + contact
        return float(np.max(net / np.where(acting > 0.0, acting, np.inf), initial=0.0))
    acting = float(applied.sum() + contact.sum())
    return float(net.sum()) / acting if acting > 0.0 else 0.0


def _moving(model) -> np.ndarray:
    """The blocks a trial watches: FREE (rigid) and DEFORMABLE, [body_count] bool."""
    return _moving_kind(model.body_kind)


def _moving_kind(body_kind: np.ndarray) -> np.ndarray:
    """FREE (rigid) or DEFORMABLE, of body kinds [body_count]: bool."""
    return np.isin(body_kind, (BodyKind.FREE, BodyKind.DEFORMABLE))


def _fe_masses(fe) -> np.ndarray:
    """Mass of each deformable block [kg; 2D per its depth]: the sum of its nodal masses."""
    b = fe.blocks
    return np.add.reduceat(b.node_mass, b.node_start[:-1])


def run_trial(sim: Simulation, value: float = math.nan,
              criterion: CollapseCriterion | None = None) -> Trial:
    """Run `sim` from rest until it is judged at rest or collapsed (module doc)."""
    crit = criterion or CollapseCriterion()
    m = sim.model
    free = _moving(m)
    if not free.any():
        raise InputError("a collapse trial needs at least one free or deformable block")
    limit = crit.displacement or crit.fraction * float(m.body_size[free].min())
    h = sim.integrator.dt
    up = m.dim - 1  # the vertical axis: y in 2D, z in 3D
    height = float(np.ptp(m.vertex_local[:, up]) + np.ptp(m.body_q0[:, up]))
    g = float(np.linalg.norm(m.gravity)) or 1.0
    mass = m.body_mass.copy()
    if sim.fe is not None:
        mass[sim.fe.model.body] = _fe_masses(sim.fe)
    energy_scale = float(mass[free].sum()) * g * height
    state = sim.initial_state()
    certify = _certifier(sim)
    steps = round((crit.not_before + crit.duration * (1.0 if certify is None
                                                      else 1.0 + crit.run_on)) / h)
    first = min(round(crit.not_before / h), steps - 1)  # the window the verdicts look at
    settle = max(1, round(crit.settle / h))
    quiet = 0
    energies = np.zeros(steps)
    displacements = np.zeros(steps)
    moved = ratio = 0.0
    crossed = math.nan  # when a block last moved past the limit
    onset: State | None = None  # the state when a block last moved past ONSET * limit
    v_before = np.empty_like(state.body_v)
    node_v_before = np.empty_like(state.node_v)
    reference, anchored = m.body_q0[free, : m.dim], not crit.after_motion
    fall = mass[free] * g * limit  # [J/m] the energy of a free fall by `limit`
    for k in range(steps):
        v_before[:] = state.body_v
        node_v_before[:] = state.node_v
        report = sim.step(state)
        energies[k] = report.kinetic_energy
        if not anchored and state.time >= crit.not_before:
            reference, anchored = state.body_q[free, : m.dim].copy(), True
        moved = float(np.linalg.norm(state.body_q[free, : m.dim] - reference, axis=1).max())
        displacements[k] = moved
        thrown = not anchored and bool(np.any(_block_energy(sim, state)[free] > fall))
        if thrown:  # during a settlement the displacements say nothing: collapse now
            return Trial(value, True, state.time, moved, ratio, report.kinetic_energy, sim,
                         state, state.time, state.copy())
        before = displacements[k - 1] if k else 0.0
        if anchored and moved > ONSET * limit >= before:
            onset = state.copy()
        if anchored and moved > limit >= before:
            crossed = state.time
        if moved > limit and state.time >= crit.not_before:
            return Trial(value, True, state.time, moved, ratio, report.kinetic_energy, sim,
                         state, crossed, onset if onset is not None else state.copy())
        ratio = unbalanced_force_ratio(sim, state, v_before, per_block=crit.per_block,
                                       node_v_before=node_v_before)
        rest = ratio <= crit.force_ratio and report.kinetic_energy <= crit.energy * energy_scale
        quiet = quiet + 1 if rest else 0
        if quiet >= settle and state.time >= crit.not_before:
            if certify is None or certify():
                return Trial(value, False, state.time, moved, ratio, report.kinetic_energy,
                             sim, state, certified=certify is not None)
            quiet = 0  # quiet, but no equilibrium holds it: a slow mechanism; run on
    half = (first + steps) // 2
    growing = (energies[half:].mean() > energies[first:half].mean()
               and displacements[half:].max() > displacements[first:half].max())
    if not growing:
        return Trial(value, False, state.time, moved, ratio, float(energies[-1]), sim, state,
                     certified=False)
    over = moved > limit
    return Trial(value, True, state.time, moved, ratio, float(energies[-1]), sim, state,
                 crossed if over else state.time,
                 onset if onset is not None and moved > ONSET * limit else state,
                 certified=False)


def _certifier(sim: Simulation):
    """A function telling whether the structure can stand where it is under the last step's
    loads: a rest solution strictly inside the cones (saxum.solver.equilibrium, a few sparse
    factorizations), else one found by the static programme (saxum.limit.rest_certificate,
    which also finds those on the cones' boundary, near a limit); None for models they do
    not serve (deformable blocks, joint laws: their verdicts at rest rest on the force ratio
    alone)."""
    from .limit import rest_certificate
    from .solver.equilibrium import rest_solution

    if sim.fe is not None or sim.problem.joint_laws:
        return None

    def certify() -> bool:
        p, v_free = sim.problem, sim.free_velocity
        impulse = p.contacts.impulse.copy()
        if rest_solution(p, impulse, v_free.copy(), np.empty_like(v_free)):
            return True
        return rest_certificate(p, v_free)

    return certify


def _block_energy(sim: Simulation, state: State) -> np.ndarray:
    """Kinetic energy of each body, 1/2 (m |v|^2 + sum_k J_k omega_k^2) [J/m; 3D: J]; a
    deformable block's 1/2 v^T M v of its nodes."""
    model, v = sim.model, state.body_v
    d = model.dim
    spin = model.body_inertia.reshape(model.body_count, -1) * v[:, d:] ** 2
    energy = 0.5 * (model.body_mass * np.sum(v[:, :d] ** 2, axis=1) + spin.sum(axis=1))
    if sim.fe is not None:
        energy[sim.fe.model.body] = sim.fe.blocks.kinetic_energy(state.node_v)
    return energy


class BracketError(InputError):
    """The bracket of a bisection does not hold the critical value: the structure collapses
    at the value where it should stand, or stands where it should collapse."""


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

    return CriticalValue(*bisect(collapsed, stands, collapses, tolerance), trials)


def bisect(collapsed: Callable[[float], bool], stands: float, collapses: float,
           tolerance: float) -> tuple[float, float]:
    """The bracket (stands, collapses) of the value where the verdict collapsed(x) changes,
    narrowed by bisection to `tolerance` times the larger magnitude of its ends, after
    checking the verdicts at both ends (BracketError)."""
    if collapsed(stands):
        raise BracketError(f"the structure already collapses at {stands:g}; start the bracket "
                         "at a value where it stands")
    if not collapsed(collapses):
        raise BracketError(f"the structure still stands at {collapses:g}; widen the bracket")
    while abs(collapses - stands) > tolerance * max(abs(stands), abs(collapses)):
        mid = 0.5 * (stands + collapses)
        if collapsed(mid):
            collapses = mid
        else:
            stands = mid
    return stands, collapses


def scenario_critical_value(path, key: str, stands: float, collapses: float, *,
                            overrides: tuple[str, ...] = (), tolerance: float = 0.005,
                            criterion: CollapseCriterion | None = None) -> CriticalValue:
    """critical_value over the scenario key `key` (dotted, e.g. loads.horizontal_acceleration,
    structure.thickness or loads.ground_motion.amplitude) of the scenario file at `path`, other
    keys overridden by `overrides` ("key=value"). With a ground motion, no trial is judged at
    rest before the motion has ended; with settlements, none before they end, and
    displacements count from there (CollapseCriterion.after_motion)."""
    from .scenario import load_scenario

    def make(x: float) -> Simulation:
        return load_scenario(path, [*overrides, f"{key}={x!r}"]).build_simulation()

    crit = criterion or CollapseCriterion()
    scenario = load_scenario(path, list(overrides))
    loads = scenario.loads
    if loads.ground_motion is not None:
        crit = dataclasses.replace(crit, not_before=max(
            crit.not_before, float(loads.ground_motion.motion(scenario.structure.dim)
                                   .time[-1])))
    if loads.settlements:
        crit = dataclasses.replace(crit, after_motion=True, not_before=max(
            crit.not_before, *(s.time for s in loads.settlements)))
    return critical_value(make, stands, collapses, tolerance=tolerance, criterion=crit)


class SolverFailures(NamedTuple):
    """Steps of a set of trials at which NLGS stopped at its sweep cap without converging:
    how many, in how many trials, and the largest final error there [-]."""

    steps: int = 0
    trials: int = 0
    worst_error: float = 0.0


def solver_failures(trials: list[Trial]) -> SolverFailures:
    """The non-converged steps of `trials` (each trial's Simulation.log)."""
    failed = [int(np.count_nonzero(~t.simulation.log.converged)) for t in trials]
    worst = max((float(t.simulation.log.error[~t.simulation.log.converged].max(initial=0.0))
                 for t in trials), default=0.0)
    return SolverFailures(sum(failed), sum(map(bool, failed)), worst)


class CurvePoint(NamedTuple):
    """One period of a collapse curve: the period [s], the amplitudes [m/s^2] at which the
    structure stood and collapsed (the bracket of the critical amplitude), the number of
    trials, and for the collapsing amplitude the time of collapse [s], the time the
    collapsing motion began [s] and the mechanism then (saxum.mechanism.Mechanism). When the
    bracket did not hold the critical amplitude at this period, the amplitudes and times are
    nan, the mechanism None and `note` says why (the other periods are kept). `failures`:
    the steps of this period's trials at which NLGS did not converge."""

    period: float
    stands: float
    collapses: float
    trials: int
    collapse_time: float
    mechanism_time: float
    mechanism: object
    note: str = ""
    failures: SolverFailures = SolverFailures()

    @property
    def amplitude(self) -> float:
        """Midpoint of the bracket [m/s^2]."""
        return 0.5 * (self.stands + self.collapses)


def _curve_point(args) -> CurvePoint:
    path, period, stands, collapses, overrides, tolerance, criterion = args
    try:
        result = scenario_critical_value(
            path, "loads.ground_motion.amplitude", stands, collapses,
            overrides=(*overrides, f"loads.ground_motion.period={period!r}"),
            tolerance=tolerance, criterion=criterion)
    except BracketError as err:
        nan = math.nan
        return CurvePoint(period, nan, nan, 0, nan, nan, None, str(err))
    trial = result.collapse()
    return CurvePoint(period, result.stands, result.collapses, len(result.trials),
                      trial.collapse_time, trial.at_collapse.time, trial.mechanism(),
                      failures=solver_failures(result.trials))


def collapse_curve(path, periods, stands: float, collapses: float, *,
                   overrides: tuple[str, ...] = (), tolerance: float = 0.01,
                   criterion: CollapseCriterion | None = None,
                   processes: int | None = None) -> list[CurvePoint]:
    """For a scenario with a pulse (`[loads.ground_motion]` with `pulse`): for each period
    T_p [s], the smallest pulse amplitude [m/s^2] that collapses the structure, bracketed by
    bisection between `stands` and `collapses`; the periods run in parallel processes.
    Returns a CurvePoint per period (with the mechanism at collapse), in the order given."""
    from .scenario import load_scenario

    motion = load_scenario(path, list(overrides)).loads.ground_motion
    if motion is None or motion.pulse is None:
        raise InputError(f"{path}: a collapse curve varies the period of a pulse, and this "
                         "scenario has none: give it a [loads.ground_motion] table with pulse "
                         "= \"one_sine\" (or another pulse, docs/ground-motion.md), as in "
                         "examples/shake_table_arch.toml")
    jobs = [(str(path), float(p), stands, collapses, tuple(overrides), tolerance, criterion)
            for p in periods]
    if processes == 1 or len(jobs) == 1:
        return [_curve_point(job) for job in jobs]
    with concurrent.futures.ProcessPoolExecutor(max_workers=processes,
                                                initializer=_one_thread) as pool:
        return list(pool.map(_curve_point, jobs))


def _one_thread() -> None:
    """A worker process of collapse_curve, one per core: one thread each by default (the
    same results: saxum.solver.nlgs.step_plan)."""
    os.environ.setdefault("SAXUM_THREADS", "1")


@dataclass(frozen=True)
class CollapseEvent:
    """A run's collapse: the time [s] and output frame from which a free block stayed moved
    by more than `limit` [m] to the end of the run, that block, the largest displacement of a
    free block at the end [m], the output frame at which that collapsing motion began
    (find_collapse), whose mechanism is the mechanism at collapse, and the first output frame
    at which a free block had moved by more than ONSET * limit (`large_frame`: where large
    motion began; under a growing shaking, a time that round-off hardly moves, while the
    onset and the time of collapse of a rocking structure move by seconds:
    docs/applications.md)."""

    time: float
    frame: int
    block: str
    limit: float
    displacement: float
    onset_frame: int
    large_frame: int


def find_collapse(results, fraction: float = DYNAMIC_FRACTION) -> CollapseEvent | None:
    """When the run of saxum.results.Results collapsed, judged on its output frames: a free
    block moved by more than `fraction` of the smallest free block's size (DYNAMIC_FRACTION:
    a rocking block that comes back has not collapsed) and did not come back by the end.
    The collapsing motion began at the first of the frames before it in which the largest
    displacement of a free block grew frame after frame, up to where it last passed ONSET *
    limit, and some free block moved faster than CREEP times the smallest block's size per
    second: the start of a slow slide or of the last swing of a rocking structure.
    None when no block is that far at the end. Deformable blocks count with the free ones
    (their body rows: the centre of mass of their nodes, its velocity their mass-weighted
    mean)."""
    free = _moving_kind(results.model["body_kind"])
    if not free.any() or results.frame_count == 0:
        return None
    limit = fraction * float(results.body_size[free].min())
    d = results.dim
    moved = np.linalg.norm(results.body_q[:, free, :d] - results.model["body_q0"][free, :d],
                           axis=-1)
    largest = moved.max(axis=1)
    if largest[-1] <= limit:
        return None
    below = np.flatnonzero(largest <= limit)
    k = int(below[-1]) + 1 if below.size else 0
    block = results.body_name[int(np.flatnonzero(free)[np.argmax(moved[k])])]
    still = np.flatnonzero(largest[:k] <= ONSET * limit)
    onset = int(still[-1]) + 1 if still.size else 0
    # A slow start (a parapet that begins to slide as the flood rises) passes ONSET * limit
    # long after it began: go back over the frames in which that motion was already growing,
    # down to the last frame at rest (every free block slower than CREEP sizes per second).
    speed = np.linalg.norm(results.body_v[:, free, :d], axis=-1).max(axis=1)
    creep = CREEP * float(results.body_size[free].min())
    while onset > 0 and largest[onset - 1] < largest[onset] and speed[onset - 1] > creep:
        onset -= 1
    large = int(np.argmax(largest > ONSET * limit))
    return CollapseEvent(float(results.time[k]), k, block, limit, float(largest[-1]), onset,
                         large)
