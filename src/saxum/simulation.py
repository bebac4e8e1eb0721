"""The time loop: a fixed sequence of named stages per step (NSCD.md, Moreau-Jean):

    forces -> free velocity -> driven velocities -> predicted configuration -> detection
    -> warm start (and the joint laws' state; the _g0 laws' initial gaps, set on the first
    step) -> local problem -> contact solve
    -> joint state (slip, damage: saxum.solver.laws_local) -> position update
    -> projection (gap-based law) -> report

The stages call compiled kernels over the model's and state's arrays; this module only
orchestrates them. What depends on how the bodies move (free velocity, driven velocities,
predicted and updated positions, rows of H*, kinetic energy) comes from the body kind's module
(saxum.bodies), so a new kind of body is one module, not a change of the loop.
"""

import logging
import math
import warnings

import numba as nb
import numpy as np

from .bodies import rigid as rigid_kind
from .bodies.fe import FEKind
from .contacts import Contacts
from .detection import DetectionSettings, detector_for
from .errors import InputError, SimulationError, SolverWarning, UndampedJointWarning
from .integrator import MoreauJean
from .laws import LawKind, undamped_springs
from .model import BodyKind, Model
from .solver import (
    NLGS,
    SOLVER_NAMES,
    ContactProblem,
    ContactSolver,
    Hybrid,
    PositionProjection,
)
from .solver.laws_local import update_joints
from .solver.nlgs import step_plan
from .state import State
from .steplog import STEP_OUTCOMES, StepLog, StepReport, natural_map_note

__all__ = ["Simulation"]

_log = logging.getLogger(__name__)


_OUTCOME = {(False, True): STEP_OUTCOMES.index("stalled"),
            (False, False): STEP_OUTCOMES.index("out of sweeps"),
            (True, False): STEP_OUTCOMES.index("projection"),
            (True, True): STEP_OUTCOMES.index("projection")}
"""A step's outcome where it did not converge, by (contact solve converged, its error
stalled)."""


def _theta_for(model: Model, theta: float | None) -> float:
    """theta as given, or by the rule of Simulation's doc; says which laws made it 1 (the run's
    log) or warns about theta = 1/2 given with them."""
    ringing = undamped_springs(model.laws)
    names = ", ".join(dict.fromkeys(law.name or law.kind.name for law in ringing))
    if theta is None:
        if not ringing:
            return 0.5
        _log.info(f"theta = 1 (not given): the joint laws {names} have springs that nothing "
                  "damps, which theta = 1/2 would leave vibrating for the whole run under the "
                  "loads applied at t = 0; give theta (solver.theta) to choose")
        return 1.0
    # 1/2 up to round-off: any theta above it damps a spring's vibration, if slowly
    if ringing and theta - 0.5 < 1e-9:
        warnings.warn(
            f"theta = {theta:g} with the joint laws {names}, whose springs nothing damps: "
            "theta = 1/2 keeps a spring's energy, so a load applied at once (the weight at "
            "t = 0) leaves the joints vibrating for the whole run, and NLGS works at every "
            "step (docs/method.md). Use theta = 1 (the default for such laws: leave theta "
            "out), or for an elastic joint without k_t a normal damping c_n > 0, or apply the "
            "loads gradually", UndampedJointWarning, stacklevel=3)
    return theta


class Simulation:
    """Steps a Model with Moreau-Jean time stepping and a contact solver (by default the
    hybrid: NLGS, and the conic fixed point where NLGS stalls; saxum.solver.Hybrid; NLGS for
    a model with joint laws, which only NLGS solves: saxum.solver.laws_local).

    dt [s]: time step; theta [-]: Moreau-Jean parameter in [0.5, 1]; None (the default): 1/2,
    which keeps the energy of free flight and of springs, or 1 for a model with joint springs
    that nothing damps (saxum.laws.undamped_springs: cohesive joints, elastic ones without
    c_n), which theta = 1/2 would leave vibrating for the whole run under a load applied at
    once; theta = 1/2 given for such a model warns (UndampedJointWarning).
    Every step appends a StepReport to `self.log`.
    """

    def __init__(
        self,
        model: Model,
        *,
        dt: float,
        theta: float | None = None,
        solver: ContactSolver | None = None,
        detection: DetectionSettings | None = None,
    ) -> None:
        self.model = model
        theta = _theta_for(model, theta)
        self.kinematics = rigid_kind(model.dim)
        self.integrator = MoreauJean(dt, theta)
        self.problem = ContactProblem(model)
        if solver is None:
            solver = NLGS() if self.problem.joint_laws or model.fe is not None else Hybrid()
        self.solver = solver
        self._threads = (step_plan(solver.threads, solver.domains, model)[0]
                         if hasattr(solver, "threads") else 1)
        """numba's threads for the step's parallel kernels (from the solver's threads and
        domains, saxum.solver.nlgs.step_plan; a solver without them: one); on one thread,
        the serial kernels (the same numbers)."""
        self.problem.parallel = self._threads > 1
        self.detector = detector_for(model, detection)
        self.detector.parallel = self.problem.parallel
        self.projection = PositionProjection(model, self.detector.interpenetration)
        self.log = StepLog()
        self._check_step()
        self.fe = None if model.fe is None else FEKind(model.fe, dt, theta, model.body_q0)
        """The deformable blocks' body kind (saxum.bodies.fe), None without them."""
        self.problem.fe = self.fe
        if self.fe is not None:
            if not isinstance(self.solver, NLGS):
                raise InputError("a model with deformable blocks is solved by NLGS only; "
                                 "use solver.kind = \"nlgs\" (the default for them)")
            _log.info("deformable blocks: the rest solution, load following and the position "
                      "projection are skipped (they are written for rigid blocks)")
        if self.problem.joint_laws and not isinstance(self.solver, NLGS):
            raise InputError(
                f"the joint laws (elastic, viscous, cohesive) are solved by NLGS only, not by "
                f"{type(self.solver).__name__}; use solver.kind = \"nlgs\"")
        n, dof = model.body_count, model.dof
        self._force = np.zeros((n, dof))
        self._v = np.zeros((n, dof))
        self._v_free = np.zeros((n, dof))
        self._q_pred = np.zeros_like(model.body_q0)
        self._spare = Contacts(model.dim)
        free = model.body_kind == BodyKind.FREE
        self._free_mass = np.where(free, model.body_mass, 0.0)
        gravity = np.concatenate((model.gravity, np.zeros(dof - model.dim)))
        self._weight = self._free_mass[:, None] * gravity[None, :]
        self._driven = [np.flatnonzero(model.body_motion == k) for k in range(len(model.motions))]
        self._bond_at = np.array([getattr(law, "bond_at", 0.0)
                                  if k == LawKind.COHESIVE else -1.0
                                  for law, k in zip(model.laws, model.law_kind, strict=True)])
        """Per law: when its joints bond [s] (ContactLaw.bond_at; -1: not a cohesive law)."""
        self._last_bond = float(self._bond_at.max(initial=-1.0))
        """The last bond_at [s]: no step that starts at or after it bonds joints."""
        self._signed_g0 = model.law_initial_gap & (model.law_kind
                                                   == LawKind.GAP_SIGNORINI_COULOMB)
        """Per law: a _g0 law whose g0 is the signed gap (GAP_SGR_CLB_g0; the others' g0 is
        max(g, 0), saxum.laws)."""

    def _check_step(self) -> None:
        g = float(np.linalg.norm(self.model.gravity))
        h = self.integrator.dt
        law_alert = self.detector.law_alert
        given = law_alert[~np.isnan(law_alert)]  # NaN: per_pair, 2 % of a block's size
        alert = float(given.min(initial=np.inf)) if len(given) == len(law_alert) > 0 else min(
            float(given.min(initial=np.inf)), self.detector.alert)
        if g * h * h > alert:
            raise InputError(
                f"dt = {h:g} s is too large for the alert distance {alert:.3g} m: one step of "
                f"gravity moves a block by |g| dt^2 = {g * h * h:.3g} m, so contacts can be "
                f"missed; use dt <= {math.sqrt(alert / g):.3g} s or a larger detection.alert "
                "(or the laws' alert)"
            )

    def initial_state(self, *, check_overlaps: bool = True) -> State:
        """The model at rest at t = 0; raises OverlapError if blocks interpenetrate."""
        state = State.initial(self.model)
        if check_overlaps:
            self.detector.check_overlaps(state.body_q)
        if (self.model.law_kind == LawKind.COHESIVE).any():
            state.contacts = self._bonds(state.body_q, self._bond_at == 0.0)
        return state

    def _bonds(self, q: np.ndarray, bonding: np.ndarray, previous: Contacts | None = None,
               node_x: np.ndarray | None = None) -> Contacts:
        """The contacts at configuration q [m, rad] (node positions node_x [m]): those of the
        cohesive laws in `bonding` (per law) that are closed (gap within the detector's
        closed_gap) bonded, intact (damage, history, crush, slip 0), their open ones fully damaged;
        the others carried from `previous` (Contacts.warm_start_from), or with none, at the
        start, the other cohesive laws' never bonded. Raises InputError for a law in `bonding`
        that bonds no joint."""
        m = self.model
        contacts = self.detector.contacts_at(q, node_x)
        n = contacts.count
        law = contacts.law[:n]
        if previous is None:
            contacts.damage[:n] = np.where(m.law_kind[law] == LawKind.COHESIVE, 1.0, 0.0)
        else:
            contacts.warm_start_from(previous, m.law_kind)
        mine = bonding[law]
        closed = contacts.gap[:n] <= self.detector.closed_gap
        contacts.damage[:n][mine] = np.where(closed[mine], 0.0, 1.0)
        contacts.history[:n][mine] = 0.0
        contacts.crush[:n][mine] = 0.0
        contacts.slip[:n][mine] = 0.0
        bonded = set(law[mine & closed].tolist())
        for k in np.flatnonzero(bonding):
            if k not in bonded:
                pairs = [f"({m.group_names[i]}, {m.group_names[j]})"
                         for i, j in zip(*np.nonzero(np.triu(m.group_law == k)), strict=True)]
                when = "at the start" if previous is None else f"at t = {m.laws[k].bond_at:g} s"
                raise InputError(
                    f"{m.laws[k].name or 'a cohesive law'}: the groups it is given to, "
                    f"{', '.join(pairs)}, have no closed joint {when}, so it would bond "
                    "nothing; give it (the key `groups`) to groups of blocks that touch then")
        return contacts

    @property
    def free_velocity(self) -> np.ndarray:
        """v_free of the last step [m/s, rad/s] (bodies, dof); read-only view."""
        view = self._v_free.view()
        view.flags.writeable = False
        return view

    @property
    def previous_contacts(self) -> Contacts:
        """The contacts of the step before the last, with their impulses: what the last
        step's solve was warm-started from (do not modify)."""
        return self._spare

    def restore(self, saved: dict) -> State:
        """The state of a checkpoint (saxum.results.Results.checkpoint), with the detector and
        the solver (ContactSolver.restore) put back as they were, so that stepping on gives bit
        for bit what the original run gave."""
        contacts = Contacts(self.model.dim, max(len(saved["contacts"]["key"]), 1))
        contacts.count = len(saved["contacts"]["key"])
        for name, values in saved["contacts"].items():
            getattr(contacts, name)[: contacts.count] = values
        self.detector.restore(saved)
        self.solver.restore(saved)
        time, step = float(saved["time"]), int(saved["step"])
        # exact for runs from t = 0 (time is then the float k h itself)
        start = time - step * self.integrator.dt
        state = State(time=time, body_q=np.array(saved["body_q"]),
                      body_v=np.array(saved["body_v"]), contacts=contacts,
                      step=step, start_time=start)
        if self.fe is not None:
            state.node_x = np.array(saved["node_x"])
            state.node_v = np.array(saved["node_v"])
        return state

    def external_force(self, t: float, out: np.ndarray, q: np.ndarray | None = None) -> None:
        """out = F(t) [N, N m] per body and dof: weight, uniform accelerations, applied forces
        (3D: moments in the world frame) and field loads at coordinates q (default: the
        initial ones)."""
        self._step_force(t, t, out, self.model.body_q0 if q is None else q)

    def _step_force(self, t0: float, t1: float, out: np.ndarray, q: np.ndarray) -> None:
        """out = the force of the step [t0, t1]: (1 - theta) F(t0) + theta F(t1), except for
        loads that know their exact mean over an interval (`mean_over(t0, t1)`, e.g. ground
        motion as inertial forces), which use it; t0 == t1 gives F(t0). Field loads (which
        depend on positions, e.g. water) are explicit: evaluated at the beginning-of-step
        coordinates q and at t0 + theta (t1 - t0), once per step."""
        theta = self.integrator.theta
        out[:] = self._weight
        for acc in self.model.accelerations:
            a = self._step_acceleration(acc, t0, t1)
            out[:, : self.model.dim] += np.multiply.outer(self._free_mass, a)
        for bodies, force in self.model.forces:
            f0 = np.asarray(force(t0), dtype=np.float64)
            f1 = np.asarray(force(t1), dtype=np.float64)
            np.add.at(out, bodies, (1.0 - theta) * f0 + theta * f1)
        for load in self.model.field_loads:
            load.add(self.model, q, t0 + theta * (t1 - t0), out)

    def _step_acceleration(self, acc, t0: float, t1: float):
        """A uniform acceleration's value for the step [t0, t1] [m/s^2] (see _step_force)."""
        if t1 > t0 and hasattr(acc, "mean_over"):
            return acc.mean_over(t0, t1)
        theta = self.integrator.theta
        a0, a1 = acc(t0), acc(t1)
        return [(1.0 - theta) * a0[d] + theta * a1[d] for d in range(self.model.dim)]

    def _node_acceleration(self, t0: float, t1: float) -> np.ndarray:
        """Gravity plus the model's uniform accelerations over the step [m/s^2], which act on
        the deformable blocks' nodes (forces and field loads act on rigid blocks only)."""
        a = self.model.gravity.copy()
        for acc in self.model.accelerations:
            a += np.asarray(self._step_acceleration(acc, t0, t1), dtype=np.float64)
        return a

    def step(self, state: State) -> StepReport:
        """Advance `state` in place by one time step; returns the step's report."""
        m = self.model
        h = self.integrator.dt
        theta = self.integrator.theta
        t0, t1 = state.time, state.start_time + (state.step + 1) * h
        if self.problem.parallel:
            nb.set_num_threads(self._threads)

        if self.model.accelerations or self.model.forces or self.model.field_loads:
            self._step_force(state.time, t1, self._force, state.body_q)
        else:
            self._force[:] = self._weight
        kin = self.kinematics
        kin.free_velocity(state.body_q, state.body_v, m.body_inertia, m.body_inv_mass,
                          self._force, h, self._v_free)
        for k, driven in enumerate(self._driven):
            self._v_free[driven] = np.asarray(m.motions[k](t1), dtype=np.float64)
            kin.driven_velocity(state.body_q, driven, self._v_free)
        self._v[:] = self._v_free
        kin.predict_positions(state.body_q, state.body_v, (1.0 - theta) * h, self._q_pred)
        fe = self.fe
        if fe is not None:
            fe.free_velocity(state.node_x, state.node_v, self._node_acceleration(state.time, t1))
            fe.predict(state.node_x, state.node_v)

        contacts = self._spare
        if fe is None:
            self.detector.detect(self._q_pred, contacts)
        else:
            self.detector.detect(self._q_pred, contacts, fe.x_pred)
        contacts.warm_start_from(state.contacts, m.law_kind, parallel=self.problem.parallel)
        if state.step == 0 and m.law_initial_gap.any():
            self._initial_gaps(contacts)
        problem = self.problem
        problem.assemble(contacts, self._q_pred, state.body_v, h, theta,
                         self.detector.closed_gap, self._v)
        solved = self.solver.solve(problem, contacts.impulse, self._v_free, self._v)
        lost = damaged = 0
        if problem.joint_laws:
            c = contacts
            problem.local_velocities(self._v, problem.u_end)
            lost, damaged = update_joints(
                c.law, c.gap, c.area, c.impulse, problem.active, c.slip, c.damage, c.history,
                c.crush, c.count, problem.u_begin, problem.u_end, m.law_kind, m.law_friction,
                m.law_parameter, h, theta, problem.law_map)

        kin.update_positions(state.body_q, state.body_v, self._v, h, theta)
        loaded, depth = problem.end_gaps(contacts.impulse, self._v, h, theta)
        if fe is None:
            projected = self.projection.project(problem, self.solver, h, depth)
        else:
            fe.update(state.node_x, state.node_v, state.body_q)
            projected = None
        if projected is not None:
            w = self.projection.pseudo_velocity
            kin.update_positions(state.body_q, w, w, h, 1.0)
            loaded, depth = problem.end_gaps(contacts.impulse, self._v, h, theta, w)
        state.body_v[:] = self._v
        self._spare, state.contacts = state.contacts, contacts
        state.time = t1
        state.step += 1
        if t0 < self._last_bond:
            bonding = (self._bond_at > t0) & (self._bond_at <= t1)
            if bonding.any():  # joints that bond after a settling phase (ContactLaw.bond_at)
                state.contacts = self._bonds(state.body_q, bonding, state.contacts,
                                             None if fe is None else state.node_x)

        energy = kin.kinetic_energy(state.body_v, m.body_mass, m.body_inertia, m.body_inv_mass)
        if fe is not None:
            energy += fe.kinetic_energy(state.node_v)
        if not math.isfinite(energy):
            raise SimulationError(
                f"velocities became NaN or infinite at step {state.step} (t = {t1:g} s); "
                "reduce dt or check the loads"
            )
        converged = solved.converged and (projected is None or projected.converged)
        outcome, rate = 0, math.nan  # STEP_OUTCOMES: converged
        if not converged:
            outcome = _OUTCOME[(solved.converged, solved.stalled)]
            rate = math.nan if solved.converged else solved.rate
        report = StepReport(state.step, t1, solved.iterations, solved.error, converged,
                            contacts.count, loaded, depth, energy,
                            0 if projected is None else projected.iterations,
                            SOLVER_NAMES.index(solved.solver), solved.natural_map, outcome,
                            rate, lost, damaged)
        self.log.append(report)
        return report

    def _initial_gaps(self, contacts: Contacts) -> None:
        """Set g0 [m] of the _g0 laws' contacts from their gaps on the first step's predicted
        configuration, as LMGC90 does on its first step (saxum.laws); 0 for the others."""
        n = contacts.count
        law = contacts.law[:n]
        gap = contacts.gap[:n]
        contacts.initial_gap[:n] = np.where(
            self._signed_g0[law], gap,
            np.where(self.model.law_initial_gap[law], np.maximum(gap, 0.0), 0.0))

    def run(self, state: State, duration: float, *, callback=None) -> StepLog:
        """Step `state` for `duration` [s] (rounded to whole steps). callback(state, report) is
        called after each step. Warns (SolverWarning) if the solver failed to converge."""
        if not (math.isfinite(duration) and duration >= 0.0):
            raise InputError(f"duration must be a finite number >= 0 [s], got {duration}")
        first = len(self.log)
        for _ in range(round(duration / self.integrator.dt)):
            report = self.step(state)
            if callback is not None:
                callback(state, report)
        ran = slice(first, len(self.log))
        bad = self.log.step[ran][~self.log.converged[ran]]
        if bad.size:
            warnings.warn(
                f"the contact solver did not converge at {bad.size} of "
                f"{len(self.log) - first} steps: {self.log.why(first)}"
                f"{natural_map_note(self.log.natural_map[ran][~self.log.converged[ran]])}"
                "; see Simulation.log", SolverWarning, stacklevel=2
            )
        return self.log
