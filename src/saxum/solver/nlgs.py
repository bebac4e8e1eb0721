"""Nonlinear Gauss-Seidel (NLGS) over the contacts, in "exchange local-global" form.

Each sweep visits the contacts in order; for contact alpha it computes the local velocity from
the current body velocities, removes its own contribution (u = U - W_aa R_a), solves the
single-contact problem exactly with W_aa, relaxes R_a <- omega R_new + (1 - omega) R_a, and
pushes the change straight into the body velocities, v += M^-1 H_a dR. W is never assembled, so
a sweep costs O(contacts) (M. Jean, CMAME 177, 1999; NSCD.md).

Convergence: LMGC90's "Quad" criterion compares a quadratic mean of the impulse change over a
sweep with the impulses. Here the quadratic form is the Delassus one, dR^T W dR = |H dR|^2_M^-1,
evaluated through the body velocities (which the sweep keeps anyway):
    error = sqrt( sum_b |v_b - v_b^prev|^2_M / sum_b |v_b - v_b^free|^2_M ),   |x|^2_M = x^T M x,
(plus a round-off floor 1e-14 |v|_M in the denominator),
v^prev the velocities before the sweep, M the bodies' masses and inertias (zero for bodies that
no impulse moves). It is the W-norm of the sweep's impulse change relative to the W-norm of the
impulse, and unlike a per-contact norm it ignores self-equilibrated impulse changes (H dR = 0),
which are indeterminate for rigid blocks and do not move anything; so a statically
indeterminate wall at rest converges instead of wandering in that null space.
The solve stops when error <= tolerance or after max_iterations sweeps.

Slow steps. A sweep shrinks each deformation mode of the assembly by a factor, the sweep's
spectral radius for that mode, which is close to 1 for modes of small Delassus eigenvalue: a
stack-bond tower of 40 courses x 2 bricks has eigenvalues of W down to 1.3e-6 of the largest
(its bending) and a radius of 1 - 1.4e-5 (70 000 sweeps per factor e; over-relaxation, omega up
to 1.95, or symmetric sweeps do not change that order). The change per sweep is then 1 - rho
times the distance to the solution, so the criterion can stop a distance tol / (1 - rho) away,
or not stop within the cap: from a cold start, or after joints open and close, the tower's
steps hit the cap, and the velocities their errors leave open and close joints again.
A step that has not converged after rest_after sweeps therefore tries the rest solution
(saxum.solver.equilibrium, for 2D and 3D rigid blocks: every free body at rest relative to its
supports, an exact solution of the step's problem when the impulses can balance the loads
inside the Coulomb cones), and sweeps on from it: when it exists the next sweep changes nothing
beyond round-off and the step converges by the same criterion; when it does not (a mechanism),
the sweeps go on from where they were.

Parallel sweep (NLGS.threads, NLGS.domains; nlgs_2d_domains, nlgs_3d_domains). The free blocks,
in the model's order, are cut into domains (body_domains: bands of courses for the walls of
saxum.structures); a sweep takes the domains' own contacts in parallel, then the contacts
across the even cuts between domains in parallel, then the odd cuts, then any across two
cuts, each group in the serial order (partition_contacts). Groups swept together share no
free block, so each update still reads the velocities that every update before it in the
partition's order has left: a Gauss-Seidel sweep in a fixed order, a function of the model and
the number of domains only, so the same bits on any number of threads. The number of domains
is itself a function of the model only (step_plan: one below _PARALLEL_BODIES free blocks, which
is the serial sweep, nlgs_2d's or nlgs_3d's order), never of the machine, so a model gives the
same bits on machines of any number of cores; the threads change the speed only. The
decomposition follows the domain-wise sequential NLGS of Shojaaee, Shaebani, Brendel, Torok &
Wolf (J. Comput. Phys. 231, 612-628, 2012), with one difference: there the contacts at the
domains' boundaries are updated in parallel and the domains exchange their velocities after
each iteration (a Jacobi step at the boundaries, which costs extra iterations and makes the
iterates depend on the decomposition, load-balanced as the run goes), here they are swept
after the domains, in order, so the sweep stays Gauss-Seidel and the result depends on the
domains only.
"""

import math
import os
from dataclasses import dataclass

import numba as nb
import numpy as np

from ..errors import InputError
from .atomic import claim, load_acquire, relax, store_release
from .base import ContactSolver, SolverReport, error_trend, prefixed, unprefixed
from .equilibrium import rest_solution
from .laws_local import law_solve_2d, law_solve_3d
from .load_following import START_MARGIN, LoadFollowing
from .local2d import factorize_contact_2d, solve_factored_contact_2d
from .local3d import open_or_stick_3d, solve_contact_3d
from .nlgs_fe import nlgs_fe_2d, nlgs_fe_3d
from .problem import ContactProblem
from .sticking import sticking_solution
from .velocity_change import change_ratio, change_sums

__all__ = ["CRITERIA", "NLGS"]

CRITERIA = ("delassus", "quad", "maxm", "qm/16")
"""NLGS's convergence criteria: saxum's (module doc) and LMGC90's (_check_error), in the
order of _check_error's codes."""

_REST_WORK = 20_000
"""Single-contact updates that cost about as much as an attempt at the rest solution does at
least (a few calls into the kernels and scipy's SuperLU, ~0.3 ms): a step tries it only once
its sweeps have done that much work, so that where sweeps are cheap (a few dozen contacts)
NLGS alone goes on."""


_REST_BACKOFF = 8
"""Most times rest_after (or _REST_WORK's least) sweeps by which a slow step puts off the
rest solution after attempts in a row that did not pay: after the k-th, a slow step sweeps
min(2^(k-1), _REST_BACKOFF) times as many again before it tries; a step that converges in
them has saved the attempt, one that does not tries after all. An attempt does not pay when
it finds none (an assembly in motion, a wall sliding on a moving ground, has none), or when
the rest solution it found served no later step: the next step converged from its plain warm
start without the first sweep confirming it, which drops the anchor
(saxum.solver.load_following), so that each rest solution bought one step. An attempt that
pays ends the putting off. 0: every slow step tries at once (saxum before issue 18;
benchmarks/rest_cost.py)."""


_DOMAIN_BODIES = 2048
"""The fewest free bodies per domain of nlgs_2d_domains, nlgs_3d_domains by default
(default_domains): smaller domains would leave more of the contacts on their cuts, and the
parallel step's fixed costs would weigh more."""
_PARALLEL_BODIES = 2 * _DOMAIN_BODIES
"""The fewest free bodies of a model that the default cuts into domains (default_domains), and
so runs on all cores by default (step_plan); below, one domain: the serial sweep on one
thread, the serial kernels. On 2 cores the parallel step of a wall at rest (one sweep a step:
its fixed costs weigh the most) paid from about 4000 free blocks and cost up to 3.5 times the
serial step's thread time below 1000 (benchmarks/thread_default.py, BENCHMARKS.md "The default
thread count"; a loaded machine, so a conservative choice)."""


_TREND_SWEEPS = 1000
"""The last sweeps of a solve that can end at its cap, run as _TREND_WINDOWS windows whose
errors give the error's trend where it does not converge (SolverReport.rate and stalled,
saxum.solver.base.error_trend): the same sweeps bit for bit, in ten calls instead of one."""
_TREND_WINDOWS = 10
_NO_TREND = (math.nan, False)


@dataclass
class NLGS(ContactSolver):
    """tolerance [-] on the relative change per sweep (see module doc), max_iterations sweeps
    per step, relaxation omega in (0, 1]; rest_after: sweeps after which a step that has not
    converged tries the rest solution (saxum.solver.equilibrium) and sweeps on from it if
    there is one (0: never; at least 20 000 / contacts sweeps, _REST_WORK); follow_loads: a
    step that follows steps which ended at rest starts from their rest solutions extrapolated
    to its loads (saxum.solver.load_following). domains: how many runs of the blocks' order
    rigid dry contacts are swept by (nlgs_2d_domains, nlgs_3d_domains: the domains' own
    contacts in parallel, then those across their cuts: module doc, "Parallel sweep"), which
    fixes the sweep's order and so the result; None (the default): a function of the model
    only (default_domains: one below 4096 free blocks; SAXUM_DOMAINS, if set, replaces it);
    1: nlgs_2d's (nlgs_3d's) serial order. threads: numba's threads for the sweep (and the
    step's parallel kernels: saxum.simulation), which change the speed, never the result;
    None (the default): all cores where the model makes two domains or more, else one, the
    serial kernels (step_plan; SAXUM_THREADS, if set, replaces it); 0: all cores.
    Deformable models ignore both. criterion: the error compared with the tolerance,
    "delassus" (saxum's, module doc) or LMGC90's "quad", "maxm", "qm/16" (_check_error,
    docs/criteria.md; rigid blocks, swept in the serial order whatever threads says).
    refine [-]: a rigid step that is an onset (it converged from a warm start in 200 to
    refine_sweeps sweeps after a step within 20) or follows one, each step since converged
    within refine_sweeps (a slide), sweeps on towards tolerance / refine, for at most
    refine_sweeps more (the defaults 100 and 3000; 0 or 1: off; Refinement, docs/method.md,
    "Refinement"); so do a new solver's first steps while each converges within 20 sweeps.
    It is still converged at the tolerance, and a refinement whose last sweep changed more
    than the tolerance sweeps on to it. Why: a step stopped at the criterion leaves velocity
    errors up to tol / (1 - rho) (module doc), which the next steps damp where the assembly
    is at rest but not where it slides with every joint at mu N (docs/method.md, "A sliding
    wall"): there an onset's error stays in the slide's velocities (the courses slide apart)
    and the steps after it add their own. Steps that do work of their own without an onset
    (a collapsing arch: 30-145 sweeps) are not refined: their accuracy is overtaken by the
    motion, and refining them cost 1.2-1.9 times the sweeps for nothing.
    accelerate: the refinement's sweeps of a rigid model of dry contacts, swept serially by
    saxum's criterion, with restarted Anderson acceleration (nlgs_2d_anderson,
    nlgs_3d_anderson): the same criterion on plain sweeps, reached in 2 to 2.5 times fewer on
    the onsets of the 0.7 g wall (docs/method.md, "Anderson acceleration of the refinement"),
    in 3D at most one cycle of sweeps more than plain ones ("Anderson acceleration in 3D")."""

    tolerance: float = 1e-6
    max_iterations: int = 5000
    relaxation: float = 1.0
    rest_after: int = 50
    follow_loads: bool = True
    threads: int | None = None
    criterion: str = "delassus"
    domains: int | None = None
    refine: float = 100.0
    refine_sweeps: int = 3000
    accelerate: bool = True

    def __post_init__(self) -> None:
        if not (math.isfinite(self.tolerance) and self.tolerance > 0.0):
            raise InputError(f"solver.tolerance must be > 0, got {self.tolerance}")
        if self.max_iterations < 1:
            raise InputError(f"solver.max_iterations must be >= 1, got {self.max_iterations}")
        if not (0.0 < self.relaxation <= 1.0):
            raise InputError(f"solver.relaxation must be in (0, 1], got {self.relaxation}")
        if self.rest_after < 0:
            raise InputError(f"solver.rest_after must be >= 0 (0: never), got {self.rest_after}")
        if self.criterion not in CRITERIA:
            raise InputError(f"solver.criterion must be one of {', '.join(CRITERIA)}, got "
                             f"{self.criterion!r}")
        check_refinement(self)
        self._sums = None if self.criterion == "delassus" else np.zeros(8)
        self._criterion = CRITERIA.index(self.criterion)
        """The criterion's index for the kernels (_check_error)."""
        if self.threads is not None and not 0 <= self.threads <= nb.config.NUMBA_NUM_THREADS:
            raise InputError(f"solver.threads must be in 0..{nb.config.NUMBA_NUM_THREADS} "
                             f"(0: all cores; the machine's numba threads), got {self.threads}")
        if self.domains is not None and self.domains < 1:
            raise InputError(f"solver.domains must be >= 1 (or absent: from the model's size), "
                             f"got {self.domains}")
        self.rest_attempts = 0
        """Solves (steps and projections) that looked for a rest solution..."""
        self.rest_solutions = 0
        """... and those that found one and swept on from it."""
        self._v_prev = np.empty((0, 0))
        self._work = np.empty((0, 18))
        self._inv_mass = None
        self._mass = np.empty((0, 0))
        self._following = LoadFollowing()
        self._refinement = Refinement()
        self._accelerate_all = False
        """Every sweep of the solves with acceleration where accelerate allows it (Hybrid's
        refinement, whose sweeps are a solve of its own)."""
        self._history = (np.empty((0, 0, 0)), np.empty((0, 0, 2)))
        """nlgs_2d_anderson's (nlgs_3d_anderson's) work memory (history_v, history_r)."""
        self._trend = True
        """Measure the error's trend at the cap (saxum.solver.hybrid measures its own)."""
        self._sticking_failed = False
        self._rest_backoff = 0
        """How many times its first sweeps a slow step sweeps before the rest solution
        (_REST_BACKOFF)."""
        self._rest_found = False
        """Whether the last step found a rest solution (_REST_BACKOFF)."""
        self._plan = (1, 1)
        """step_plan's (threads, domains) of the model solved."""
        self._split = False
        """Whether rigid dry contacts are swept by domains (nlgs_2d_domains, nlgs_3d_domains):
        more than one domain, by saxum's criterion."""
        self._domains = None
        """body_domains' (domain, n), ghost and inv_mass_x (nlgs_2d_domains, nlgs_3d_domains),
        of the model solved."""
        self._fixed = np.empty(0, dtype=np.int64)
        """The fixed bodies' indices, in the order of their ranks in ghost."""
        self._pairs = np.full((3, 0), -1)
        """The active contacts' candidates, antagonists and flags of the last partition."""
        self._partitioned = None
        """partition_contacts's (order, groups) and in 2D change_runs_2d's (runs, run_start)
        for _pairs: _partition."""
        self._own = (np.empty((0, 18)), np.empty((2, 0), dtype=np.int64), np.empty((0, 2)),
                     np.empty((0, 3)))
        """nlgs_2d_domains' (nlgs_3d_domains') work memory (rows, own, own_impulse, vx;
        nlgs_2d_domains uses no own_impulse)."""

    def checkpoint(self) -> dict[str, np.ndarray]:
        # "rest": the rest solution's back-off (_REST_BACKOFF), whether the last step found
        # one, whether the last sticking start failed (_solve_deformable)
        return {"refinement": self._refinement.flags(),
                "rest": np.array([self._rest_backoff, self._rest_found, self._sticking_failed],
                                 dtype=np.int64),
                **prefixed("following", self._following.checkpoint())}

    def restore(self, saved: dict) -> None:
        self._refinement = Refinement.from_flags(saved.get("refinement"))
        backoff, found, failed = saved.get("rest", (0, 0, 0))
        self._rest_backoff, self._rest_found, self._sticking_failed = (
            int(backoff), bool(found), bool(failed))
        self._following = LoadFollowing.restored(unprefixed(saved, "following"))

    def solve(self, problem: ContactProblem, impulse: np.ndarray, v_free: np.ndarray,
              v: np.ndarray) -> SolverReport:
        c = problem.contacts
        inv_mass = problem.model.body_inv_mass
        if self._inv_mass is not inv_mass:
            self._inv_mass = inv_mass
            self._mass = np.divide(1.0, inv_mass, out=np.zeros_like(inv_mass),
                                   where=inv_mass > 0.0)
            self._domains = self._partitioned = None
            self._plan = step_plan(self.threads, self.domains, problem.model)
            self._split = self._plan[1] > 1 and self._sums is None
        if getattr(problem, "fe", None) is not None:
            if self._sums is not None:
                raise InputError(f"solver.criterion {self.criterion!r} is for rigid blocks: "
                                 "a model with deformable blocks takes 'delassus'")
            return self._solve_deformable(problem, impulse, v_free, v)
        if self._v_prev.shape != v.shape:
            self._v_prev = np.empty_like(v)
        dim = problem.model.dim
        width = 18 if dim == 2 else 38  # the packed row of nlgs_2d / nlgs_3d
        if len(self._work) < problem.count or self._work.shape[1] != width:
            self._work = np.empty((max(problem.count, 2 * len(self._work)), width))
        # joint laws (saxum.solver.laws_local) change the local problems; a problem without
        # them (the projection's) has none, and a sweep without them is compiled without their
        # code (nlgs_2d)
        joints = getattr(problem, "joint_laws", False)
        active, law_map, joint = problem.active, None, None
        if joints:
            law_map = problem.law_map
            flagged = law_map[: problem.count, 0] != 0.0
            joint = np.flatnonzero(active[: problem.count] & flagged).astype(np.int64)
            active = active[: problem.count] & ~flagged
        sweep = nlgs_3d if dim == 3 else nlgs_2d
        args = (c.candidate, c.antagonist, problem.h_cand, problem.h_ant, problem.delassus,
                problem.bias, problem.friction, active, problem.count, inv_mass,
                self._mass, v_free, v, self._v_prev, impulse, self._work, joint, law_map)
        if self._split:
            nb.set_num_threads(self._plan[0])
            sweep = nlgs_3d_domains if dim == 3 else nlgs_2d_domains
            args += self._partition(problem.model, c.candidate, c.antagonist, active,
                                    problem.count, width)
        else:
            args += (self._sums, self._criterion)
        args += (self.tolerance,)
        # the refinement's sweeps with Anderson acceleration (accelerate), where they are
        # nlgs_2d's or nlgs_3d's of dry contacts by saxum's criterion
        # (a model with joint laws whose step has none of their contacts sweeps as a dry one,
        # so it is accelerated alike: the same bits as the dry path)
        accelerated = (self.accelerate and sweep in (nlgs_2d, nlgs_3d)
                       and (joint is None or len(joint) == 0) and self._sums is None)
        if accelerated and self._accelerate_all:
            sweep = self._anderson(v, problem.count)
        # the step's own problem (the projection's has no v_begin and no rest solution); the
        # rest solution is that of rigid joints, so not with joint laws
        rest_after = 0 if joints else self.rest_after
        own = getattr(problem, "v_begin", None) is not None
        if own:
            self._refinement.start(problem, impulse)
        follow = self.follow_loads and rest_after > 0 and own
        followed = follow and self._following.start(problem, impulse, v_free, v,
                                                     self.tolerance)
        first = self.max_iterations
        if rest_after > 0 and problem.count > 0:
            # after a start that follows a step at rest, the rest solution is likely: it is
            # looked for as soon as the sweeps have done _REST_WORK, if the first one does
            # not confirm the start
            least = -(-_REST_WORK // problem.count)
            first = min(least if followed else max(rest_after, least), first)
        if first == self.max_iterations:  # the sweeps can end the step at its cap
            iterations, error, trend = self._sweeps(sweep, args, first)
        else:
            iterations, error = sweep(*args, first, self.relaxation)
            trend = _NO_TREND
        confirmed = iterations == 1 and error <= self.tolerance
        followed = followed and not confirmed
        found = attempted = False
        slow = error > self.tolerance and iterations < self.max_iterations
        if slow and not followed and self._rest_backoff > 0:
            # putting off (_REST_BACKOFF); a start that follows the loads comes from a rest
            # solution that paid, and tries at once
            more, error = sweep(*args, min(first * self._rest_backoff,
                                           self.max_iterations - iterations), self.relaxation)
            iterations += more
            slow = error > self.tolerance and iterations < self.max_iterations
        if slow or (followed and iterations < self.max_iterations):
            # slow (module doc), or a start that follows the loads which the first sweep did
            # not confirm: sweep on from the rest solution if there is one
            self.rest_attempts += 1
            attempted = True
            if follow:
                found = rest_solution(problem, impulse, v_free, v, self._following.response,
                                      *((START_MARGIN,) if followed else ()),
                                      load_path=not followed)
            else:
                found = rest_solution(problem, impulse, v_free, v, load_path=True)
            if found:
                self.rest_solutions += 1
            else:
                self._back_off()
            more, error, trend = self._sweeps(sweep, args, self.max_iterations - iterations)
            iterations += more
        converged = error <= self.tolerance
        if follow:
            self._following.record(problem, impulse, v_free, confirmed and converged,
                                   found and converged)
        if self._rest_found and not attempted and not (confirmed and converged):
            self._back_off()  # the last step's rest solution served nothing (_REST_BACKOFF)
        elif found or confirmed:
            self._rest_backoff = 0
        # a rest solution serves later steps as an anchor: only where the loads are followed
        self._rest_found = follow and found and converged
        if own:
            # class doc (refine): the errors of a sliding assembly's steps add up
            more, error = self._refinement.step(self, lambda target, count: (
                self._anderson(v, problem.count) if accelerated else sweep)(
                *args[:-1], target, count, self.relaxation), iterations, error, converged)
            iterations += more
            if more and error > self.tolerance:  # the refinement's last sweep changed more
                more, error, trend = self._sweeps(sweep, args, self.max_iterations - iterations)
                iterations += more
                converged = error <= self.tolerance
        rate, stalled = trend
        return SolverReport(iterations, error, converged, "nlgs", rate=rate, stalled=stalled)

    def _anderson(self, v: np.ndarray, count: int):
        """nlgs_2d_anderson (nlgs_3d_anderson) on nlgs_2d's (nlgs_3d's) arguments, with its
        work memory for velocities like v and count contacts."""
        history_v, history_r = self._history
        dim = 2 if v.shape[1] == 3 else 3
        if (history_v.shape[1:] != v.shape or history_r.shape[1] < count
                or history_r.shape[2] != dim):
            shape = (_ANDERSON_DEPTH + 2,)
            self._history = history_v, history_r = (
                np.empty(shape + v.shape),
                np.empty(shape + (max(count, 2 * history_r.shape[1]), dim)))
        kernel = nlgs_2d_anderson if dim == 2 else nlgs_3d_anderson

        def sweeps(*args):
            return kernel(*args[:16], history_v, history_r, *args[-3:])
        return sweeps

    def _back_off(self) -> None:
        """An attempt at the rest solution that did not pay: slow steps put it off longer
        (_REST_BACKOFF)."""
        self._rest_backoff = min(max(1, 2 * self._rest_backoff), _REST_BACKOFF)

    def _partition(self, model, cand, ant, active, count, width) -> tuple:
        """nlgs_2d_domains' (nlgs_3d_domains') arguments from order to inv_mass_x, width the
        length of a packed row: the partition reused while the active contacts' pairs have not
        changed (comparing them costs less than partitioning them)."""
        if self._domains is None:
            inv_mass = model.body_inv_mass
            fixed = ~(inv_mass > 0.0).any(axis=1)
            domain, n = body_domains(~fixed, self._plan[1])
            ghost = np.full(len(fixed), -1, dtype=np.int64)
            ghost[fixed] = np.arange(fixed.sum())
            inv_mass_x = np.zeros((len(fixed) + 2 * n * int(fixed.sum()), inv_mass.shape[1]))
            inv_mass_x[: len(fixed)] = inv_mass
            self._domains = (domain, n, ghost, inv_mass_x)
            self._fixed = np.flatnonzero(fixed)
        if self._pairs.shape[1] < count:
            self._pairs = np.full((3, max(count, 2 * self._pairs.shape[1])), -1)
            self._partitioned = None
        if not _same_pairs(cand, ant, active, count, self._pairs) or self._partitioned is None:
            order, groups = partition_contacts(cand, ant, active, count, *self._domains[:2])
            # nlgs_3d_domains sums its error serially: no runs
            runs = (change_runs_2d(cand, ant, order, groups, *self._domains[:2])
                    if model.dim == 2 else ())
            self._partitioned = (order, groups, runs)
        order, groups, runs = self._partitioned
        domain, n, ghost, inv_mass_x = self._domains
        rows, own, own_impulse, vx = self._own
        if (len(rows) < len(order) or own.shape[1] < count or vx.shape != inv_mass_x.shape
                or rows.shape[1] != width):
            size = max(len(order), count, 2 * len(rows))
            self._own = rows, own, own_impulse, vx = (
                np.empty((size, width)), np.empty((2, size), dtype=np.int64),
                np.empty((size, model.dim)), np.empty_like(inv_mass_x))
        if model.dim == 2:  # nlgs_2d_domains sweeps the impulses in place
            return (order, groups, *runs, ghost, self._fixed, rows, own, vx, inv_mass_x,
                    nb.get_num_threads())
        return order, groups, *runs, ghost, rows, own, own_impulse, vx, inv_mass_x

    def _sweeps(self, sweep, args, count: int):
        """The last `count` sweeps of a solve, of `sweep` (nlgs_2d, nlgs_3d) on `args`,
        stopping at the tolerance; the last ones in windows whose errors give the trend
        (_TREND_SWEEPS). Returns (sweeps, error, (rate, stalled))."""
        if not self._trend:
            done, error = sweep(*args, count, self.relaxation)
            return done, error, _NO_TREND
        window = min(count, _TREND_SWEEPS) // _TREND_WINDOWS
        if window == 0:
            done, error = sweep(*args, count, self.relaxation)
            return done, error, _NO_TREND
        done, error = 0, math.inf
        if count > window * _TREND_WINDOWS:
            done, error = sweep(*args, count - window * _TREND_WINDOWS, self.relaxation)
        errors = []
        while error > self.tolerance and done < count:
            more, error = sweep(*args, window, self.relaxation)
            done += more
            errors.append(error)
        if error <= self.tolerance:
            return done, error, _NO_TREND
        return done, error, error_trend(errors, window)


    def _solve_deformable(self, problem: ContactProblem, impulse: np.ndarray,
                          v_free: np.ndarray, v: np.ndarray) -> SolverReport:
        """Sweeps of a model with deformable blocks (saxum.solver.nlgs_fe); no rest solution
        and no load following (both are for rigid blocks; Simulation logs it): a step not
        converged after min(rest_after, _FE_FIRST) sweeps sweeps on from the sticking solution
        (saxum.solver.sticking), counted in rest_attempts (and in rest_solutions where its
        statuses settled, or nearly, and it was taken)."""
        if self._v_prev.shape != v.shape:
            self._v_prev = np.empty_like(v)
        c = problem.contacts
        kind = problem.fe
        b = kind.blocks
        sweep = nlgs_fe_2d if problem.model.dim == 2 else nlgs_fe_3d
        args = (c.candidate, c.antagonist, problem.h_cand, problem.h_ant, problem.delassus,
                problem.bias, problem.friction, problem.active, problem.count, self._inv_mass,
                self._mass, v_free, v, self._v_prev, impulse, c.side_kind, c.side_node,
                c.side_weight, b.node_block, b.node_start, b.inv_start, b.inv, kind.rotation,
                np.repeat(b.node_mass[:, None], b.dim, axis=1), kind.v_free, kind.v,
                np.empty_like(kind.v), problem.law_map, self.tolerance)
        # the sticking start is written for dry contacts: those with joint laws sweep alone
        sticking = self.rest_after > 0 and not getattr(problem, "joint_laws", False)
        first = (min(self.rest_after, _FE_FIRST, self.max_iterations) if sticking
                 else self.max_iterations)
        iterations, error = sweep(*args, first, self.relaxation)
        # a step after one whose sticking start was not taken does not try (its statuses
        # are likely changing still: under a pulse, most steps)
        if error > self.tolerance and iterations < self.max_iterations:
            if self._sticking_failed:
                self._sticking_failed = False
            else:
                self.rest_attempts += 1
                found = sticking_solution(problem, impulse, v_free, v)
                self.rest_solutions += found
                self._sticking_failed = not found
            more, error = sweep(*args, self.max_iterations - iterations, self.relaxation)
            iterations += more
        else:
            self._sticking_failed = False
        return SolverReport(iterations=iterations, error=error,
                            converged=error <= self.tolerance)


def check_refinement(solver) -> None:
    """InputError unless solver.refine (NLGS, Hybrid) is 0 or >= 1 and solver.refine_sweeps
    >= 0."""
    if not (solver.refine == 0.0 or solver.refine >= 1.0):
        raise InputError(f"solver.refine must be 0 (off) or >= 1, got {solver.refine}")
    if solver.refine_sweeps < 0:
        raise InputError(f"solver.refine_sweeps must be >= 0, got {solver.refine_sweeps}")


_ONSET_SWEEPS = 200
"""Sweeps from a warm start, after a step that converged within _CARRY_SWEEPS, that make a
step an onset for the refinement (NLGS.refine): a change of the contacts' states (sticking to
sliding), whose Gauss-Seidel factor rho is near 1, so whose stop at the tolerance leaves the
most, tol / (1 - rho). The 0.7 g wall's two onsets took 692 and 440 sweeps after steps of 8
(BENCHMARKS.md, "Refinement"); steps in motion that keep working take 30-145 on the
collapsing arch of benchmarks/convergence.py and 40-150, growing, on its shaken stack, whose
one slow step after a cheap one took 161 (where rules that refined its steps took 1.07-1.85
times the sweeps for the same motion: BENCHMARKS.md)."""
_CARRY_SWEEPS = 20
"""Sweeps within which a new solver's first steps converge while they are refined (at rest
they are within tolerance / refine already); a step that takes more ends that refinement
until an onset. (After an onset, every step that converges within refine_sweeps is refined:
on the 0.7 g wall of benchmarks/shaken_wall.py the later slides' steps take 20-500 sweeps,
and ending the refinement there, as this bound did, let the courses drift apart slide after
slide until the steps stuck between the slides no longer found their rest solution and
ended at the cap: BENCHMARKS.md, "0.7 g over 2 s".)"""


class Refinement:
    """The refinement of a solver's steps (NLGS, Hybrid: NLGS's doc, refine): where a step is
    an onset (_ONSET_SWEEPS) or one of the steps that follow it, each converged within
    refine_sweeps (a slide), it sweeps on towards tolerance / refine for at most
    refine_sweeps. A new one refines its first steps while each converges within
    _CARRY_SWEEPS (a run's first steps, and a run resumed from a file whose checkpoints do not
    hold the flags); checkpoints hold the flags (flags(), from_flags()), so that a run resumed
    inside a slide refines as the run in one go does. A cold start (zero
    impulses) is never an onset, as its sweeps measure the distance from zero, not the
    problem."""

    def __init__(self) -> None:
        self.carrying = True
        """Whether the steps since the start all converged within _CARRY_SWEEPS, or those
        since the last onset within refine_sweeps (sliding)..."""
        self.cheap = True
        """... whether the last step converged within _CARRY_SWEEPS..."""
        self.sliding = False
        """... and whether an onset started the carrying."""
        self._cold = False
        """Whether the step under way started cold (set by start() before every step: no
        checkpoint needs it)."""

    def flags(self) -> np.ndarray:
        """(carrying, cheap, sliding) as 0 or 1 (int8): what a checkpoint holds
        (saxum.results)."""
        return np.array([self.carrying, self.cheap, self.sliding], dtype=np.int8)

    @classmethod
    def from_flags(cls, flags: np.ndarray | None) -> "Refinement":
        """The refinement whose flags() were `flags`; a new one for None (a checkpoint of a
        file written before they were stored) or -1s (written without a solver that has
        one)."""
        refinement = cls()
        if flags is not None and min(flags) >= 0:
            refinement.carrying, refinement.cheap, refinement.sliding = (bool(f) for f in flags)
        return refinement

    def start(self, problem, impulse: np.ndarray) -> None:
        """Before a step's sweeps: whether it starts cold (impulses all zero)."""
        # only the step's contacts: rows past count are stale
        self._cold = not _any_impulse(impulse, problem.count)

    def step(self, solver, sweeps, iterations: int, error: float,
             converged: bool) -> tuple[int, float]:
        """After a step of `solver` that took `iterations` sweeps to `error`: the refinement,
        sweeps(tolerance, count), which runs at most count sweeps, stopping at tolerance,
        and returns (sweeps done, error). Returns (sweeps done, error); (0, error) where the
        step is not refined or is already there. (A stop where the error falls slowly was
        tried: on the 0.7 g wall of benchmarks/shaken_wall.py it cut the slide's refinement
        short, and the steps after it cost 1.5 to 6 times as many sweeps.)"""
        cheap = converged and iterations <= _CARRY_SWEEPS
        onset = (converged and self.cheap and not self._cold
                 and _ONSET_SWEEPS <= iterations <= solver.refine_sweeps)
        # after an onset, every step that converges within refine_sweeps carries on
        self.sliding = onset or (self.sliding and converged
                                 and iterations <= solver.refine_sweeps)
        self.carrying = self.sliding or (self.carrying and cheap)
        self.cheap = cheap
        if not (self.carrying and solver.refine > 1.0
                and error > solver.tolerance / solver.refine):
            return 0, error
        budget = min(solver.refine_sweeps, solver.max_iterations - iterations)
        if budget <= 0:
            return 0, error
        return sweeps(solver.tolerance / solver.refine, budget)


@nb.njit(cache=True)
def _any_impulse(impulse, count):
    """Whether any of the first count rows of impulse is nonzero, stopping at the first: after
    a warm start the first rows settle it (numpy's any reads them all, ~40 us on a wall of
    16 000 bricks, and costs a few us a call on a small one)."""
    for a in range(count):
        for r in range(impulse.shape[1]):
            if impulse[a, r]:  # a cold start's impulses are zeros, set, not computed
                return True
    return False


_FE_FIRST = 5
"""Sweeps of a step with deformable blocks before its sticking start (at most
rest_after): a sweep of the 210-brick wall costs about a seventh of one of the start's LU
(benchmarks/wall_fe.py), and steps that converge in a few sweeps (free flight, light
contact) need no start."""


@nb.njit(cache=True)
def nlgs_2d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass, mass,
            v_free, v, v_prev, impulse, work, joints, law_map, sums, criterion, tolerance,
            max_iterations, relaxation):
    """Run NLGS sweeps; returns (sweeps done, final error). Updates v and impulse in place;
    mass [kg, kg m^2] per dof is 1 / inv_mass (0 where inv_mass is 0); v_prev (like v) and
    work (at least count x 18) are work memory. active: the contacts of dry laws in the
    solve; joints: the indices of those of joint laws, with their local problems in law_map
    (saxum.solver.laws_local), or None for both in a solve without joint laws: numba then
    compiles the kernel without the joints' code (it prunes the branches on `joints is not
    None` for that argument type), in less than half the time (a first run). Each sweep
    visits the dry contacts, then the joints: the dry contacts' loop is the same with or
    without joints, bit for bit and as fast.

    Written out for 2D rigid bodies (3 dof, frame (t, n)), whose rows of H* are
    [t, l_c x t], [n, l_c x n] on the candidate and [-t, -(l_a x t)], [-n, -(l_a x n)] on the
    antagonist: before the sweeps, each active contact's t, n, the four moment arms, W, the
    factors of its single-contact solve (factorize_contact_2d: the divisions, once per step;
    on W' for a joint) and b_n, mu go into one row of `work`, which the sweeps read in
    order."""
    if _pack_all_2d(h_cand, h_ant, delassus, bias, friction, active, count, work, joints,
                    law_map) == 0:
        return 0, 0.0
    error = np.inf
    it = 0
    # v_prev = v by _relative_change's loop (a slice copy would compile its error message's
    # string formatting, ~1 s of a first run)
    _relative_change(v, v_prev, v_free, mass)
    while it < max_iterations:
        it += 1
        _dry_sweep_2d(cand, ant, active, count, work, v, impulse, inv_mass, relaxation, sums)
        error = _end_sweep_2d(cand, ant, v, v_prev, v_free, mass, impulse, work, joints,
                              law_map, inv_mass, relaxation, sums, criterion)
        if error <= tolerance:
            break
    return it, error



_ANDERSON_DEPTH = 10
"""Differences of residuals that an Anderson mix of nlgs_2d_anderson combines (m)..."""
_ANDERSON_CYCLE = 20
"""... and the sweeps between two mixes, of which the last _ANDERSON_DEPTH + 1 are kept
(restarted Anderson: a mix starts the history anew). On the onset of the 0.7 g wall of
benchmarks/shaken_wall.py (step 82, from its warm start to 1e-8): 7662 sweeps without,
4165 with (5, 10), 3981 with (10, 20), 3987 with (20, 30); on the step after it 2581, 1224,
1448, 950 (docs/method.md, "Anderson acceleration of the refinement")."""
_ANDERSON_GUARD = 100.0
"""A mix after which the cycle's last sweep changes more than this times the least change
before any mix is undone, and the sweeps go on without mixes (a guard against a mix that
throws the iterate away; the change per sweep is not monotone: after a good mix its first
sweeps change up to ~25 times what the sweeps before it did, then less, on the 0.7 g wall)."""
_ANDERSON_GUARD_3D = 1.0
"""_ANDERSON_GUARD for 3D contacts (nlgs_3d_anderson): a mix is undone where the cycle after it
ends above the least error at the end of a cycle. With 100, as in 2D, the mixes go on near the
solution and hold the error there: the shaken 3D L wall's cold first step (768 contacts) then
reaches 1e-6 in 1283 sweeps against plain sweeps' 2227, but stalls at 1.9e-6 on the way to
1e-8 (plain: 29866 sweeps); with 1, 2290 and 21680 (docs/method.md, "Anderson acceleration
in 3D")."""
_ANDERSON_DROP = 1e-10
"""A difference of residuals that is within this (relative) of the span of the earlier
ones is left out of the mix (its coefficient would be round-off)."""


@nb.njit(cache=True)
def nlgs_2d_anderson(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count,
                     inv_mass, mass, v_free, v, v_prev, impulse, work, history_v, history_r,
                     tolerance, max_iterations, relaxation):
    """nlgs_2d's sweeps of dry contacts by saxum's criterion, with restarted Anderson
    acceleration (_anderson_sweeps). history_v (m + 2, bodies, 3), history_r (m + 2, >= count,
    2): work memory. Returns (sweeps done, final error)."""
    if _pack_all_2d(h_cand, h_ant, delassus, bias, friction, active, count, work, None,
                    None) == 0:
        return 0, 0.0
    return _anderson_sweeps(cand, ant, delassus, active, count, inv_mass, mass, v_free, v,
                            v_prev, impulse, work, history_v, history_r, None, tolerance,
                            max_iterations, relaxation)


@nb.njit(cache=True)
def nlgs_3d_anderson(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count,
                     inv_mass, mass, v_free, v, v_prev, impulse, work, history_v, history_r,
                     tolerance, max_iterations, relaxation):
    """nlgs_3d's sweeps of dry contacts by saxum's criterion, with restarted Anderson
    acceleration (_anderson_sweeps; the mixed impulses projected onto the 3D Coulomb cones).
    history_v (m + 2, bodies, 6), history_r (m + 2, >= count, 3): work memory. Returns
    (sweeps done, final error)."""
    if _pack_dry_3d(h_cand, h_ant, delassus, bias, friction, active, count, work) == 0:
        return 0, 0.0
    return _anderson_sweeps(cand, ant, delassus, active, count, inv_mass, mass, v_free, v,
                            v_prev, impulse, work, history_v, history_r, np.empty((2, 3)),
                            tolerance, max_iterations, relaxation)


@nb.njit(cache=True)
def _anderson_sweeps(cand, ant, delassus, active, count, inv_mass, mass, v_free, v, v_prev,
                     impulse, work, history_v, history_r, local3d, tolerance, max_iterations,
                     relaxation):
    """Sweeps of dry contacts (nlgs_2d's where local3d is None, nlgs_3d's else: local3d (2, 3)
    its single-contact work memory; `work` packed) by saxum's criterion, with restarted
    Anderson acceleration (type II; D. G. Anderson, J. ACM 12, 1965; H. F. Walker and P. Ni,
    SIAM J. Numer. Anal. 49, 2011): after every _ANDERSON_CYCLE sweeps, from the last m + 1
    sweeps' iterates y_0 .. y_m+1 (y_i+1 = G(y_i), G a sweep) and residuals f_i = y_i+1 - y_i
    measured as the criterion does, in the M-norm of the velocities,
        gamma = argmin |f_m - sum_l gamma_l (f_l+1 - f_l)|_M,
        y = y_m+1 - sum_l gamma_l (y_l+2 - y_l+1),
    for the impulses and the velocities alike (v is affine in R: v = v_free + M^-1 H R), then
    each impulse projected onto its Coulomb cone (its change pushed into v). Where a sweep's
    change converges like rho^k with rho near 1 (Gauss-Seidel on an assembly's slowest modes:
    the onset of a slide), the mix removes the m slowest directions at once. Safeguard
    (_ANDERSON_GUARD): a mix after which the cycle's last sweep changes too much is undone and
    the sweeps go on without mixes. Every sweep is a plain sweep and the error is that of the
    last one: no mix after the last sweep allowed. Returns (sweeps done, final error)."""
    depth = history_v.shape[0] - 2
    lead = _ANDERSON_CYCLE - depth - 1
    guard = _ANDERSON_GUARD if local3d is None else _ANDERSON_GUARD_3D
    error = np.inf
    least = np.inf  # the least error at the end of a cycle, before its mix...
    mixed = np.inf  # ... and that of the last (the sweep that gave its y_m+1)
    mixing = True
    it = 0
    k = 0  # sweeps since the last mix
    no_order = np.empty(0, dtype=np.int64)  # _dry_sweep_3d's, unread in nlgs_3d's order
    _relative_change(v, v_prev, v_free, mass)
    while it < max_iterations:
        it += 1
        k += 1
        if local3d is None:
            _dry_sweep_2d(cand, ant, active, count, work, v, impulse, inv_mass, relaxation,
                          None)
        else:
            _dry_sweep_3d(0, count, False, active, no_order, cand, ant, work, delassus, v,
                          impulse, inv_mass, relaxation, None, local3d[0], local3d[1])
        error = _relative_change(v, v_prev, v_free, mass)
        if error <= tolerance:
            break
        if k == _ANDERSON_CYCLE and error > guard * least:
            # the last mix made things worse by more than the sweeps' own ups and downs:
            # back to where it started, and no more mixes
            _copy_iterate(history_v[depth + 1], history_r[depth + 1], v, impulse, active,
                          count)
            _relative_change(v, v_prev, v_free, mass)
            error = mixed
            mixing = False
        if not mixing:
            continue
        if k >= lead:
            _copy_iterate(v, impulse, history_v[k - lead], history_r[k - lead], active,
                          count)
        if k == _ANDERSON_CYCLE and it < max_iterations:
            _anderson_mix(cand, ant, work, v, impulse, inv_mass, mass, active, count,
                          history_v, history_r, local3d)
            _relative_change(v, v_prev, v_free, mass)
            mixed = error
            least = min(least, error)
            k = 0
    return it, error


@nb.njit(cache=True)
def _copy_iterate(v, impulse, to_v, to_r, active, count):
    """to_v = v; to_r = impulse on the active contacts."""
    for i in range(v.shape[0]):
        for j in range(v.shape[1]):
            to_v[i, j] = v[i, j]
    for a in range(count):
        if active[a]:
            for j in range(impulse.shape[1]):
                to_r[a, j] = impulse[a, j]


@nb.njit(cache=True)
def _anderson_mix(cand, ant, work, v, impulse, inv_mass, mass, active, count, history_v,
                  history_r, local3d):
    """v, impulse = _anderson_sweeps's mix of the iterates in history_v, history_r, the
    impulses projected onto their cones (2D where local3d is None, else 3D, local3d[1] work
    memory)."""
    depth = history_v.shape[0] - 2
    nb_, dof = v.shape[0], v.shape[1]
    rows = nb_ * dof
    # the differences of the residuals, in the M-norm, as columns; b = f_m
    diff = np.zeros((depth, rows))
    b = np.zeros(rows)
    for i in range(nb_):
        for j in range(dof):
            w = math.sqrt(mass[i, j])
            if not w > 0.0:  # a fixed body (mass 0): no row
                continue
            r = i * dof + j
            f0 = history_v[1, i, j] - history_v[0, i, j]
            for c in range(depth):
                f1 = history_v[c + 2, i, j] - history_v[c + 1, i, j]
                diff[c, r] = w * (f1 - f0)
                f0 = f1
            b[r] = w * f0
    # least squares by modified Gram-Schmidt, leaving out dependent columns
    q = np.zeros((depth, rows))
    tri = np.zeros((depth, depth))
    kept = np.zeros(depth, dtype=np.bool_)
    for c in range(depth):
        norm0 = math.sqrt(np.dot(diff[c], diff[c]))
        col = diff[c].copy()
        for p in range(c):
            if kept[p]:
                tri[p, c] = np.dot(q[p], col)
                col -= tri[p, c] * q[p]
        norm = math.sqrt(np.dot(col, col))
        if norm > _ANDERSON_DROP * norm0 and norm > 0.0:
            kept[c] = True
            tri[c, c] = norm
            q[c] = col / norm
    gamma = np.zeros(depth)
    for c in range(depth - 1, -1, -1):
        if not kept[c]:
            continue
        s = np.dot(q[c], b)
        for p in range(c + 1, depth):
            if kept[p]:
                s -= tri[c, p] * gamma[p]
        gamma[c] = s / tri[c, c]
    # y = y_m+1 - sum gamma_l (y_l+2 - y_l+1)
    for i in range(nb_):
        for j in range(dof):
            y = history_v[depth + 1, i, j]
            for c in range(depth):
                y -= gamma[c] * (history_v[c + 2, i, j] - history_v[c + 1, i, j])
            v[i, j] = y
    for a in range(count):
        if not active[a]:
            continue
        for j in range(impulse.shape[1]):
            y = history_r[depth + 1, a, j]
            for c in range(depth):
                y -= gamma[c] * (history_r[c + 2, a, j] - history_r[c + 1, a, j])
            impulse[a, j] = y
        if local3d is None:
            _project_2d(a, cand, ant, work[a], v, impulse, inv_mass)
        else:
            _project_3d(a, cand, ant, work[a], v, impulse, inv_mass, local3d[1])


@nb.njit(inline="always")
def _project_2d(a, cand, ant, row, v, impulse, inv_mass):
    """Contact a's impulse [N s] projected onto its Coulomb cone |r_t| <= mu r_n (mu row[17],
    the row of nlgs_2d's `work`), its change pushed into v."""
    rt = impulse[a, 0]
    rn = impulse[a, 1]
    mu = row[17]
    if abs(rt) <= mu * rn:
        return
    pt = pn = 0.0  # the polar cone: the origin
    if mu * abs(rt) > -rn:  # onto the cone's edge on rt's side
        t = (mu * abs(rt) + rn) / (1.0 + mu * mu)
        pt = math.copysign(mu * t, rt)
        pn = t
    _push_2d(a, cand, ant, row, v, impulse, inv_mass, 1.0, pt, pn)


@nb.njit(inline="always")
def _project_3d(a, cand, ant, row, v, impulse, inv_mass, rr):
    """Contact a's impulse (t, n, s) [N s] projected onto its Coulomb cone
    |(r_t, r_s)| <= mu r_n (mu row[37], the row of nlgs_3d's `work`), its change pushed into
    v; rr: a 3-vector, work memory."""
    rt = impulse[a, 0]
    rn = impulse[a, 1]
    rs = impulse[a, 2]
    mu = row[37]
    slip = math.sqrt(rt * rt + rs * rs)
    if slip <= mu * rn:
        return
    rr[0] = rr[1] = rr[2] = 0.0  # the polar cone: the origin
    if mu * slip > -rn:  # onto the cone's edge along (r_t, r_s)
        t = (mu * slip + rn) / (1.0 + mu * mu)
        scale = mu * t / slip
        rr[0] = scale * rt
        rr[1] = t
        rr[2] = scale * rs
    _push_3d(a, cand, ant, row, v, impulse, inv_mass, 1.0, rr)


@nb.njit(inline="always")
def _dry_sweep_2d(cand, ant, active, count, work, v, impulse, inv_mass, relaxation, sums):
    """One sweep of nlgs_2d over the active dry contacts, in its order (the last first)."""
    for k in range(count):
        a = count - 1 - k
        if not active[a]:
            continue
        _update_dry_2d(a, cand, ant, work[a], v, impulse, inv_mass, relaxation, sums)


@nb.njit(parallel=True, cache=True)
def nlgs_2d_domains(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count,
                    inv_mass, mass, v_free, v, v_prev, impulse, work, joints, law_map, order,
                    groups, runs, run_start, ghost, fixed, rows, own, vx, inv_mass_x, threads,
                    tolerance, max_iterations, relaxation):
    """nlgs_2d with its dry contacts swept domain by domain (partition_contacts): the
    domains' own contacts in parallel (numba threads), then the contacts across the even cuts
    between domains in parallel, then those across the odd cuts, then the rest; each group's
    contacts in nlgs_2d's order, by nlgs_2d's serial loop (_sweep_range_2d) on rows packed
    in that order. It is still a Gauss-Seidel sweep, in the partition's order (not
    nlgs_2d's): the groups swept together write the velocities of disjoint free bodies, and
    each group has its own copy of the fixed bodies' velocities (which a push changes by
    0 x dR: read by all, written by each into its own), so the result is the same bit for bit
    whatever the number of threads. The error's sums go by the runs of bodies of
    change_runs_2d: each domain's own right after its sweep, then the others (the bodies of
    the contacts across the cuts), added in that order; with joints, by fixed blocks of
    _SUM_BODIES bodies after them, added in the blocks' order. One domain gives nlgs_2d's
    order and arithmetic. The joints are swept after, in order, as nlgs_2d does. Each
    group's rows are packed by the first sweep, right before it sweeps them, and a domain's
    bodies' velocities copied by the task that sweeps it (_first_sweep_2d), the impulses
    swept in place.

    All the sweeps run in one parallel region (_sweep_tasks_2d): the pieces of a sweep are
    tasks in stages (_stages_2d), which the threads claim (saxum.solver.atomic) and wait for
    before the next stage, so that a sweep costs no region's start and end (the 2025-brick
    wall shaken at 0.7 g sweeps 5000 times a step: BENCHMARKS.md, issue 16). Which thread
    runs a task does not change what it computes; a thread waits only for tasks that another
    thread has claimed and is running, so the sweeps end under any threading layer and any
    number of threads, one included.

    order, groups from partition_contacts, runs and run_start from change_runs_2d;
    ghost [int] per body: -1 for a free body, a fixed one's rank among the fixed ones
    (fixed: their indices in that order, nfixed in all), whose copy for group g is row
    n + g nfixed + rank of vx (n bodies) and of inv_mass_x (inv_mass, then zeros). Work
    memory: rows (at least len(order) x 18), the dry contacts' in the sweep's order; own
    (int64, 2 x at least count: each swept contact's candidate and antagonist as rows of
    vx); vx (as inv_mass_x). threads: numba's (any number >= 1 gives the same result; the
    kernel does not ask numba, so that it can be cached)."""
    ndomains = groups.shape[0] // 2
    n = v.shape[0]
    packed = order.shape[0]
    if joints is not None:
        packed += _pack_joints_2d(h_cand, h_ant, delassus, bias, friction, work, joints,
                                  law_map)
    if packed == 0 or max_iterations < 1:
        return 0, 0.0
    nfixed = fixed.shape[0]
    # before the sweeps' region: the bodies that domains share (those of the cuts'
    # contacts, in run_start[ndomains]'s runs) and the fixed ones with their copies
    _copy_runs(runs, run_start[ndomains], run_start[ndomains + 1], v, vx, v_prev)
    for k in range(nfixed):
        b = fixed[k]
        for d in range(3):
            vx[b, d] = v_prev[b, d] = v[b, d]
        for g in range(2 * ndomains):
            for d in range(3):
                vx[n + g * nfixed + k, d] = v[b, d]
    blocks = -(-n // _SUM_BODIES) if joints is not None else 0
    stage_start, stage_kind, stage_group, flags, error, sums, run_sums = _stages_2d(
        ndomains, blocks)
    workers = max(1, min(threads, np.max(np.diff(stage_start))))
    # the sweeps and the error as each thread saw them, written in the loop itself: reads
    # after the region of what only functions called in it wrote were found stale (a getitem
    # moved before the loop; numba 0.68)
    ends = np.empty((workers, 2))
    for k in nb.prange(workers):
        ends[k, 0], ends[k, 1] = _sweep_tasks_2d(
            k, workers, stage_start, stage_kind, stage_group, flags, error, tolerance,
            max_iterations, cand, ant, h_cand, h_ant, delassus, bias, friction, inv_mass, mass,
            v_free, v, v_prev, impulse, work, joints, law_map, order, groups, runs, run_start,
            ghost, nfixed, rows, own, vx, inv_mass_x, relaxation, sums, run_sums)
    blocks = max(1, -(-n // _ROW_BLOCK))
    for k in nb.prange(blocks):  # the velocities back
        lo, hi = _share(k, blocks, n)
        for b in range(lo, hi):
            for d in range(3):
                v[b, d] = vx[b, d]
    return int(ends[0, 0]), ends[0, 1]


_ROW_BLOCK = 4096
"""Contacts per block of _same_pairs, bodies per block (at most) of nlgs_2d_domains' copy of
the velocities back, and packed rows per block (at most) of nlgs_3d_domains' packing and
copy back."""


@nb.njit(inline="always")
def _share(k, blocks, size):
    """Block k's range [lo, hi) of `blocks` nearly equal blocks of range(size)."""
    return k * size // blocks, (k + 1) * size // blocks


@nb.njit(inline="always")
def _copy_runs(runs, lo, hi, v, vx, v_prev):
    """vx = v_prev = v over the runs of bodies runs[lo:hi] (change_runs_2d)."""
    for r in range(lo, hi):
        for b in range(runs[r, 0], runs[r, 1]):
            for d in range(3):
                vx[b, d] = v_prev[b, d] = v[b, d]


@nb.njit(inline="always")
def _runs_change(runs, lo, hi, v, v_prev, v_free, mass):
    """change_sums (from zero) over the runs of bodies runs[lo:hi] (change_runs_2d), in
    order."""
    num = den = size = 0.0
    for r in range(lo, hi):
        b, e = runs[r, 0], runs[r, 1]
        num, den, size = change_sums(v[b:e], v_prev[b:e], v_free[b:e], mass[b:e], num, den,
                                     size)
    return num, den, size


_PAD = 8
"""int64 per flag of nlgs_2d_domains' tasks: 64 bytes, a cache line."""
_SPINS = 1 << 14
"""Reads of a flag after which a thread that waits for another lets other threads of its
core run between reads (saxum.solver.atomic.relax): longer than a domain's sweep of a few
thousand contacts (~0.1 ms), so that on idle cores the threads only spin."""

_DOMAIN, _CUT, _LAST, _BLOCK, _ERROR = range(5)
"""The tasks of nlgs_2d_domains' sweeps (_task_2d): a domain's own contacts; a cut's; the
phases of one cut, the last group and the joints, and without joints the error; with joints
the error's sums over a block of bodies, and the error from them."""


@nb.njit(cache=True)
def _stages_2d(ndomains, blocks):
    """The stages of a sweep of nlgs_2d_domains, in order: the domains, the even cuts and
    the odd ones where a phase has two cuts or more, then the last task (_LAST: with the
    phases of one cut or none; never before a phase of two: the even cuts are as many as the
    odd ones or one more), then, with joints, the blocks of bodies of the error's sums and
    the error (blocks: how many; 0 without joints). Returns (stage_start: stage i's tasks are
    stage_start[i] .. stage_start[i + 1] - 1; stage_kind; stage_group: the group or block of
    a stage's first task, the next tasks' the next ones), and the sweeps' memory: flags
    (_sweep_tasks_2d), error, the error's sums by blocks and by domains. (Made here, not in
    nlgs_2d_domains: an array made there by np.zeros, itself one of numba's parallel loops,
    read 0 after the region where only functions called in it had written it; numba 0.68.)"""
    even = ndomains + ndomains // 2  # the phases: [ndomains, even), [even, last), last
    last = 2 * ndomains - 1
    kinds = [_DOMAIN]
    sizes = [ndomains]
    first = [0]
    for lo, hi in ((ndomains, even), (even, last)):
        if hi - lo > 1:
            kinds.append(_CUT)
            sizes.append(hi - lo)
            first.append(lo)
    kinds.append(_LAST)
    sizes.append(1)
    first.append(0)
    if blocks > 0:
        kinds += [_BLOCK, _ERROR]
        sizes += [blocks, 1]
        first += [0, 0]
    stage_start = np.zeros(len(kinds) + 1, dtype=np.int64)
    for i in range(len(kinds)):
        stage_start[i + 1] = stage_start[i] + sizes[i]
    ntasks = stage_start[-1]
    # each task's claim, then each one's last sweep done, then the solve's last sweep: one
    # cache line each (_PAD), so that threads at neighbouring tasks write different lines
    flags = np.zeros((2 * ntasks + 1) * _PAD, dtype=np.int64)
    return (stage_start, np.array(kinds), np.array(first), flags, np.zeros(1),
            np.empty((blocks, 3)), np.empty((ndomains + 1, 3)))


@nb.njit(cache=True)
def _sweep_tasks_2d(k, workers, stage_start, stage_kind, stage_group, flags, error,
                    tolerance, max_iterations, cand, ant, h_cand, h_ant, delassus, bias,
                    friction, inv_mass, mass, v_free, v, v_prev, impulse, work, joints, law_map,
                    order, groups, runs, run_start, ghost, nfixed, rows, own, vx, inv_mass_x,
                    relaxation, sums, run_sums):
    """Thread k of `workers` in nlgs_2d_domains' region: sweep after sweep, stage after
    stage, it claims each task of the stage not yet claimed for this sweep (its share of
    them first), runs it (_task_2d) and marks it done; then it waits until every task of
    the stage is done. flags: per task t, at t _PAD the sweep it was claimed for, at
    (tasks + t) _PAD the last sweep it is done for; at 2 tasks _PAD the sweep after which
    the solve stops (0 until then: _task_2d sets it). Returns (that sweep, its error) once
    it is there."""
    ntasks = stage_start[-1]
    stop = 2 * ntasks * _PAD
    s = 0
    while True:
        s += 1
        for st in range(stage_kind.shape[0]):
            lo = stage_start[st]
            m = stage_start[st + 1] - lo
            begin = k * m // workers
            for j in range(m):
                t = lo + (begin + j) % m
                if claim(flags, t * _PAD, s - 1, s):
                    _task_2d(stage_kind[st], stage_group[st] + t - lo, s, flags, stop, error,
                             tolerance, max_iterations, cand, ant, h_cand, h_ant, delassus,
                             bias, friction, inv_mass, mass, v_free, v, v_prev, impulse, work,
                             joints, law_map, order, groups, runs, run_start, ghost, nfixed,
                             rows, own, vx, inv_mass_x, relaxation, sums, run_sums)
                    store_release(flags, (ntasks + t) * _PAD, s)
            for t in range(lo, lo + m):
                spins = 0
                while load_acquire(flags, (ntasks + t) * _PAD) < s:
                    spins += 1
                    if spins > _SPINS:
                        relax()
        if 0 < load_acquire(flags, stop) <= s:
            return s, error[0]


@nb.njit(cache=True)
def _task_2d(kind, g, s, flags, stop, error, tolerance, max_iterations, cand, ant, h_cand,
             h_ant, delassus, bias, friction, inv_mass, mass, v_free, v, v_prev, impulse, work,
             joints, law_map, order, groups, runs, run_start, ghost, nfixed, rows, own, vx,
             inv_mass_x, relaxation, sums, run_sums):
    """Task g of kind `kind` (_DOMAIN ...) of sweep s of nlgs_2d_domains; the task that ends
    the sweep writes its error into error[0] and, where the solve stops there (error <=
    tolerance, or s = max_iterations), s into flags[stop]."""
    ndomains = groups.shape[0] // 2
    n = v.shape[0]
    v_own = vx[:n]
    first = s == 1
    if kind == _DOMAIN or kind == _CUT:
        if first and kind == _DOMAIN:
            _copy_runs(runs, run_start[g], run_start[g + 1], v, vx, v_prev)
        _sweep_group_2d(g, first, groups, order, cand, ant, h_cand, h_ant, delassus, bias,
                        friction, ghost, nfixed, n, rows, own, vx, impulse, inv_mass_x,
                        relaxation)
        if kind == _DOMAIN and joints is None:
            run_sums[g, 0], run_sums[g, 1], run_sums[g, 2] = _runs_change(
                runs, run_start[g], run_start[g + 1], v_own, v_prev, v_free, mass)
    elif kind == _LAST:
        even = ndomains + ndomains // 2
        last = 2 * ndomains - 1
        for lo, hi in ((ndomains, even), (even, last)):
            if hi - lo == 1:  # (phases of two groups or more are stages of their own)
                _sweep_group_2d(lo, first, groups, order, cand, ant, h_cand, h_ant, delassus,
                                bias, friction, ghost, nfixed, n, rows, own, vx, impulse,
                                inv_mass_x, relaxation)
        _sweep_group_2d(last, first, groups, order, cand, ant, h_cand, h_ant, delassus, bias,
                        friction, ghost, nfixed, n, rows, own, vx, impulse, inv_mass_x,
                        relaxation)
        if joints is not None:
            _joint_sweep_2d(cand, ant, v_own, impulse, work, joints, law_map, inv_mass,
                            relaxation, None)
        else:
            run_sums[ndomains, 0], run_sums[ndomains, 1], run_sums[ndomains, 2] = (
                _runs_change(runs, run_start[ndomains], run_start[ndomains + 1], v_own,
                             v_prev, v_free, mass))
            _end_sweep(_sum_rows(run_sums), s, flags, stop, error, tolerance, max_iterations)
    elif kind == _BLOCK:
        lo = g * _SUM_BODIES
        hi = min(n, lo + _SUM_BODIES)
        sums[g, 0], sums[g, 1], sums[g, 2] = change_sums(
            v_own[lo:hi], v_prev[lo:hi], v_free[lo:hi], mass[lo:hi], 0.0, 0.0, 0.0)
    else:
        _end_sweep(_sum_rows(sums), s, flags, stop, error, tolerance, max_iterations)


@nb.njit(inline="always")
def _end_sweep(end, s, flags, stop, error, tolerance, max_iterations):
    """Sweep s of nlgs_2d_domains ends with error `end`: into error[0], and s into
    flags[stop] where the solve stops there."""
    error[0] = end
    if end <= tolerance or s >= max_iterations:
        store_release(flags, stop, s)


@nb.njit(inline="always")
def _sum_rows(sums):
    """change_ratio of the sums of the rows of sums (num, den, size), added in order."""
    num = den = size = 0.0
    for k in range(sums.shape[0]):
        num += sums[k, 0]
        den += sums[k, 1]
        size += sums[k, 2]
    return change_ratio(num, den, size)


@nb.njit(inline="always")
def _sweep_group_2d(g, first, groups, order, cand, ant, h_cand, h_ant, delassus, bias,
                    friction, ghost, nfixed, n, rows, own, v, impulse, inv_mass, relaxation):
    """Group g's sweep of nlgs_2d_domains: the first packs (_first_sweep_2d), the others
    read the rows (_sweep_range_2d)."""
    if first:
        _first_sweep_2d(groups[g], groups[g + 1], n + g * nfixed, order, cand, ant, h_cand,
                        h_ant, delassus, bias, friction, ghost, rows, own, v, impulse,
                        inv_mass, relaxation)
    else:
        _sweep_range_2d(groups[g], groups[g + 1], order, own, rows, v, impulse, inv_mass,
                        relaxation)


@nb.njit(cache=True)
def _first_sweep_2d(lo, hi, base, order, cand, ant, h_cand, h_ant, delassus, bias, friction,
                    ghost, rows, own, v, impulse, inv_mass, relaxation):
    """The first sweep of the dry contacts order[lo:hi] of nlgs_2d_domains: their rows and
    bodies (own, by contact: a fixed body as its group's copy, row base + its rank), then
    _sweep_range_2d. (Packing each row right before its update, in one loop, cost 1.6x as
    much on one thread: the update's chain through the velocities then holds up the
    packing's independent work.)"""
    own_cand = own[0]
    own_ant = own[1]
    for i in range(lo, hi):
        a = order[i]
        _pack_2d(rows, i, h_cand, h_ant, delassus, bias, friction, a)
        c = cand[a]
        b = ant[a]
        own_cand[a] = c if ghost[c] < 0 else base + ghost[c]
        own_ant[a] = b if ghost[b] < 0 else base + ghost[b]
    _sweep_range_2d(lo, hi, order, own, rows, v, impulse, inv_mass, relaxation)


@nb.njit(cache=True)
def _sweep_range_2d(lo, hi, order, own, rows, v, impulse, inv_mass, relaxation):
    """Single-contact updates of the dry contacts order[lo:hi] (rows lo .. hi - 1) in order
    (nlgs_2d_domains), as nlgs_2d's loop: a function of its own, so that the loop compiles
    as nlgs_2d's does whichever parallel region calls it."""
    cand = own[0]
    ant = own[1]
    for i in range(lo, hi):
        _update_dry_2d(order[i], cand, ant, rows[i], v, impulse, inv_mass, relaxation, None)


_SUM_BODIES = 256
"""Bodies per block of _parallel_change's sums (3D) and of nlgs_2d_domains' with joint laws
(its _BLOCK tasks): a fixed number, so that the sums and the error do not depend on the
threads; small enough that a wall of a few thousand blocks, whose sweeps are short, has its
sums on every thread (at 2048, the 2025-brick wall's were one block, on one thread, every
sweep)."""


@nb.njit(parallel=True, cache=True)
def _parallel_change(v, v_prev, v_free, mass, sums):
    """_relative_change on threads: change_sums over blocks of _SUM_BODIES bodies in
    parallel into sums (a row per block), then added in the blocks' order."""
    for k in nb.prange(sums.shape[0]):
        lo = k * _SUM_BODIES
        hi = min(v.shape[0], lo + _SUM_BODIES)
        sums[k, 0], sums[k, 1], sums[k, 2] = change_sums(
            v[lo:hi], v_prev[lo:hi], v_free[lo:hi], mass[lo:hi], 0.0, 0.0, 0.0)
    num = den = size = 0.0
    for k in range(sums.shape[0]):
        num += sums[k, 0]
        den += sums[k, 1]
        size += sums[k, 2]
    return change_ratio(num, den, size)


def body_domains(free: np.ndarray, domains: int | None) -> tuple[np.ndarray, int]:
    """The domains of partition_contacts: the free bodies, in the model's order, cut into
    n runs of as many bodies, n = domains (at most one per free body), or where it is None
    default_domains'. The structures of saxum.structures number their blocks course by course, so a
    domain is a band of courses whose velocities lie together in memory, and the cuts between
    domains cross few joints; blocks numbered at random give domains that share most
    contacts (then swept in order, on one thread). Returns (domain per body, fixed bodies
    -1; n): a function of the model and `domains` only, not of the threads."""
    index = np.flatnonzero(free)
    domain = np.full(len(free), -1, dtype=np.int64)
    n = _domain_count(len(index), domains)
    domain[index] = np.arange(len(index)) * n // max(1, len(index))
    return domain, n


def default_domains(free: int) -> int:
    """The default number of domains of a model of `free` free bodies, a function of the model
    only (so the same bits on machines of any cores): 1 below _PARALLEL_BODIES, else the
    largest power of two of at least _DOMAIN_BODIES bodies each (2 from 4096, 4 from 8192, 8
    from 16 384, ...): powers of two share out evenly on the usual core counts, and the step
    of a large model can use as many cores as it has domains."""
    if free < _PARALLEL_BODIES:
        return 1
    return 1 << (free // _DOMAIN_BODIES).bit_length() - 1



def _domain_count(free: int, domains: int | None) -> int:
    """body_domains' n for `free` free bodies: `domains` (default_domains' where None), at
    least 1 and at most one per free body."""
    return max(1, min(default_domains(free) if domains is None else domains, free))


def step_plan(threads: int | None, domains: int | None, model) -> tuple[int, int]:
    """(numba threads, domains) of the steps of `model` under NLGS's settings `threads` and
    `domains`. The domains fix NLGS's order and so the result: where None, SAXUM_DOMAINS if
    set, else default_domains (the model's free blocks only, never the machine). The threads
    change the speed only (the sweep by domains and the parallel kernels give the same bits
    on any number): where None, SAXUM_THREADS if set, else all cores (numba's
    NUMBA_NUM_THREADS) where there are two domains or more and no deformable blocks (whose
    NLGS, nlgs_fe, has no sweep by domains), else one: a small model keeps the serial kernels.
    0: all cores. The step runs the parallel kernels on more than one thread, NLGS by domains
    with more than one domain."""
    cores = nb.config.NUMBA_NUM_THREADS
    threads = _from_environment("SAXUM_THREADS", threads, 0, cores)
    domains = _from_environment("SAXUM_DOMAINS", domains, 1, None)
    free = int((model.body_inv_mass > 0.0).any(axis=1).sum())
    n = _domain_count(free, domains)
    if threads is None:
        threads = cores if n >= 2 and model.fe is None else 1
    return threads or cores, n


def _from_environment(name: str, value: int | None, least: int, most: int | None):
    """value, or where it is None the environment variable `name` (an integer in
    least..most) if set, else None."""
    text = os.environ.get(name, "").strip()
    if value is not None or not text:
        return value
    if not text.isdigit() or int(text) < least or (most is not None and int(text) > most):
        bound = f"{least}..{most}" if most is not None else f">= {least}"
        raise InputError(f"environment variable {name}={text!r}: an integer {bound} is "
                         f"expected (or unset it)")
    return int(text)


@nb.njit(parallel=True, cache=True)
def _same_pairs(cand, ant, active, count, pairs):
    """Whether the first `count` contacts' candidates, antagonists and active flags are those
    in pairs (3 x at least count, then -1 beyond count); if not, they are copied there. By
    blocks of _ROW_BLOCK contacts on numba's threads."""
    blocks = -(-count // _ROW_BLOCK)
    differ = np.zeros(blocks, dtype=np.bool_)
    for k in nb.prange(blocks):
        for a in range(k * _ROW_BLOCK, min(count, (k + 1) * _ROW_BLOCK)):
            if pairs[0, a] != cand[a] or pairs[1, a] != ant[a] or pairs[2, a] != active[a]:
                differ[k] = True
                break
    if (count == pairs.shape[1] or pairs[0, count] == -1) and not differ.any():
        return True
    for k in nb.prange(-(-pairs.shape[1] // _ROW_BLOCK)):
        for a in range(k * _ROW_BLOCK, min(pairs.shape[1], (k + 1) * _ROW_BLOCK)):
            if a < count:
                pairs[0, a] = cand[a]
                pairs[1, a] = ant[a]
                pairs[2, a] = active[a]
            else:
                pairs[0, a] = pairs[1, a] = pairs[2, a] = -1
    return False


@nb.njit(cache=True)
def partition_contacts(cand, ant, active, count, domain, ndomains):
    """The groups of nlgs_2d_domains and nlgs_3d_domains: the active dry contacts whose free
    bodies lie in one domain d (body_domains) go to group d, those across the cut between
    domains d and d + 1 to group ndomains + d // 2 (d even) or ndomains + ndomains // 2 + d // 2
    (d odd), the others (across two cuts or more) to the last group, 2 ndomains - 1; each
    group keeps the serial sweep's order (last first). Groups of one phase share no free
    body: two domains do not, and a cut's contacts have their free bodies in its two
    domains, which the other cuts of its parity do not touch. Returns (order, groups): group
    g is order[groups[g]:groups[g + 1]]; a function of the contacts and the domains, not of the
    threads."""
    last = 2 * ndomains - 1
    group = np.empty(count, dtype=np.int64)
    size = np.zeros(2 * ndomains + 1, dtype=np.int64)
    for a in range(count):
        if active[a]:
            dc = domain[cand[a]]
            da = domain[ant[a]]  # a fixed body's is -1
            if dc < 0 or da < 0 or dc == da:
                g = max(dc, da, 0)
            elif abs(dc - da) == 1:
                d = min(dc, da)
                g = ndomains + d // 2 + (ndomains // 2 if d % 2 else 0)
            else:
                g = last
            group[a] = g
            size[g + 1] += 1
    for g in range(2 * ndomains):
        size[g + 1] += size[g]
    order = np.empty(size[-1], dtype=np.int64)
    fill = size[:-1].copy()
    for k in range(count):
        a = count - 1 - k
        if active[a]:
            order[fill[group[a]]] = a
            fill[group[a]] += 1
    return order, size


@nb.njit(cache=True)
def change_runs_2d(cand, ant, order, groups, domain, ndomains):
    """Where nlgs_2d_domains sums its error: domain d's free bodies (body_domains) that no
    contact across a cut touches (partition_contacts's order, groups), right after the
    sweep of d, and the other free bodies after the cuts. Returns (runs, run_start): runs
    (int64, r x 2) of consecutive bodies [b, e), those of domain d runs[run_start[d]:
    run_start[d + 1]] and the others runs[run_start[ndomains]:run_start[ndomains + 1]], each
    in the bodies' order; a function of the contacts and the domains, not of the threads."""
    n = domain.shape[0]
    where = domain.copy()  # -1: fixed, in no run
    for i in range(groups[ndomains], groups[2 * ndomains]):
        for b in (cand[order[i]], ant[order[i]]):
            if where[b] >= 0:
                where[b] = ndomains
    run_start = np.zeros(ndomains + 2, dtype=np.int64)
    runs = np.empty((0, 2), dtype=np.int64)
    for fill in range(2):  # count the runs, then write them
        at = run_start[:-1].copy()
        b = 0
        while b < n:
            e = b + 1
            while e < n and where[e] == where[b]:
                e += 1
            if where[b] >= 0:
                if fill:
                    runs[at[where[b]], 0] = b
                    runs[at[where[b]], 1] = e
                    at[where[b]] += 1
                else:
                    run_start[where[b] + 1] += 1
            b = e
        if not fill:
            for k in range(ndomains + 1):
                run_start[k + 1] += run_start[k]
            runs = np.empty((run_start[-1], 2), dtype=np.int64)
    return runs, run_start


@nb.njit(inline="always")
def _pack_all_2d(h_cand, h_ant, delassus, bias, friction, active, count, work, joints,
                 law_map):
    """The rows of `work` of the active dry contacts and of the joints (nlgs_2d); returns
    how many."""
    nactive = 0
    for a in range(count):
        if active[a]:
            nactive += 1
            _pack_2d(work, a, h_cand, h_ant, delassus, bias, friction, a)
    if joints is not None:
        nactive += _pack_joints_2d(h_cand, h_ant, delassus, bias, friction, work, joints,
                                   law_map)
    return nactive


@nb.njit(inline="always")
def _pack_joints_2d(h_cand, h_ant, delassus, bias, friction, work, joints, law_map):
    """The joints' rows of `work` (nlgs_2d), with the factors of W'; returns how many."""
    for j in range(joints.shape[0]):
        a = joints[j]
        _pack_2d(work, a, h_cand, h_ant, delassus, bias, friction, a)
        m = law_map[a]
        _factorize_2d(work, a, m[1], m[2], m[4], friction[a])  # on W'
    return joints.shape[0]


@nb.njit(inline="always")
def _update_dry_2d(a, cand, ant, row, v, impulse, inv_mass, relaxation, sums):
    """One single-contact update of a dry contact a (nlgs_2d), row its row of `work`; sums:
    None, or LMGC90's check sums to add its change to (_check_sums)."""
    ut, un = _local_velocity_2d(a, cand, ant, row, v, impulse)
    rt, rn = solve_factored_contact_2d(row[8], row[9], row[10], row[11], row[12], row[13],
                                       row[14], row[15], ut, un, row[17])
    if sums is not None:
        _check_sums_2d(sums, row, impulse[a, 0], impulse[a, 1], rt, rn)
    _push_2d(a, cand, ant, row, v, impulse, inv_mass, relaxation, rt, rn)


@nb.njit(inline="always")
def _end_sweep_2d(cand, ant, v, v_prev, v_free, mass, impulse, work, joints, law_map,
                  inv_mass, relaxation, sums, criterion):
    """The end of a sweep of nlgs_2d: the joints (if any, in order), then the error
    (_relative_change: v_prev = v; or with sums, LMGC90's criterion: _check_error)."""
    if joints is not None:
        _joint_sweep_2d(cand, ant, v, impulse, work, joints, law_map, inv_mass, relaxation,
                        sums)
    if sums is not None:
        return _check_error(sums, criterion)
    return _relative_change(v, v_prev, v_free, mass)


@nb.njit(inline="always")
def _joint_sweep_2d(cand, ant, v, impulse, work, joints, law_map, inv_mass, relaxation, sums):
    """One sweep over the joints of nlgs_2d, in order."""
    for j in range(joints.shape[0]):
        a = joints[j]
        row = work[a]
        ut, un = _local_velocity_2d(a, cand, ant, row, v, impulse)
        rt, rn = law_solve_2d(law_map[a], ut, un, row[16], row[11], row[12], row[13],
                              row[14], row[15], row[17])
        if sums is not None:
            _check_sums_2d(sums, row, impulse[a, 0], impulse[a, 1], rt, rn)
        _push_2d(a, cand, ant, row, v, impulse, inv_mass, relaxation, rt, rn)


@nb.njit(inline="always")
def _check_sums_2d(sums, row, rt0, rn0, rt, rn):
    """_check_sums for a 2D contact: W its Delassus block row[8:11], R its impulse before
    the update (rt0, rn0) and the single-contact solution (rt, rn) [N s], unrelaxed."""
    wt0 = row[8] * rt0 + row[9] * rn0
    wn0 = row[9] * rt0 + row[10] * rn0
    wt1 = row[8] * rt + row[9] * rn
    wn1 = row[9] * rt + row[10] * rn
    _check_sums(sums, wt0 - wt1, wn0 - wn1, 0.0, 0.5 * (rt0 + rt), 0.5 * (rn0 + rn), 0.0,
                0.5 * ((wt0 * rt0 + wn0 * rn0) + (wt1 * rt + wn1 * rn)),
                0.5 * ((wt0 * wt0 + wn0 * wn0) + (wt1 * wt1 + wn1 * wn1)))


@nb.njit(inline="always")
def _check_sums(sums, dv0, dv1, dv2, r0, r1, r2, wrr, wrwr):
    """Adds a contact's update to LMGC90's check sums (M. Jean's NLGS, mod_nlgs.f90
    'after iter check'): dv = W_aa (R - R_new) [m/s] the local velocity change the update
    makes, r = (R + R_new) / 2 [N s], wrr = (W R . R + W R_new . R_new) / 2 [J],
    wrwr = (|W R|^2 + |W R_new|^2) / 2 [m^2/s^2]. sums: [sum |dv|^2, max |dv|^2,
    sum |dv|^2 |r|^2, max |dv|^2 |r|^2, sum r . dv, sum wrr, sum wrwr, contacts with r != 0]."""
    dvdv = dv0 * dv0 + dv1 * dv1 + dv2 * dv2
    rr = r0 * r0 + r1 * r1 + r2 * r2
    sums[0] += dvdv
    sums[1] = max(sums[1], dvdv)
    sums[2] += dvdv * rr
    sums[3] = max(sums[3], dvdv * rr)
    sums[4] += r0 * dv0 + r1 * dv1 + r2 * dv2
    sums[5] += wrr
    sums[6] += wrwr
    if rr != 0.0:
        sums[7] += 1.0


_QM16 = 16.666
"""LMGC90's bound on the max-norm ratios under 'QM/16' (mod_nlgs.f90)."""


@nb.njit(cache=True)
def _check_error(sums, criterion):
    """LMGC90's convergence measure of a sweep from _check_sums' sums (then zeroed), with n
    the contacts with r != 0: QuadWR = sqrt(sum wrwr / n), MeanWRR = sum wrr / n,
    QuadDV = sqrt(sum |dv|^2 / n) / QuadWR, MaxmDV = max |dv| / QuadWR,
    QuadDVR = sqrt(sum |dv|^2 |r|^2 / n) / MeanWRR, MaxmDVR = max |dv| |r| / MeanWRR,
    MeanDVoR = sum r . dv / sum wrr. LMGC90 stops when each of its criterion's ratios is below
    1 after division by the tolerance; returned here is the largest ratio itself (compared
    with the tolerance): criterion 1 'Quad': |MeanDVoR|, QuadDV, QuadDVR; 2 'Maxm': |MeanDVoR|,
    MaxmDV, MaxmDVR; 3 'QM/16': Quad's and the Maxm ones / 16.666. 0 where nothing pushes
    (LMGC90's floor: n = 0 or the sums of W R below 1e-18)."""
    n = sums[7]
    error = 0.0
    if n >= 1.0 and sums[5] > 1e-18 and sums[6] > 1e-18:
        quad_wr = math.sqrt(sums[6] / n)
        mean_wrr = sums[5] / n
        error = abs(sums[4] / sums[5])
        if criterion == 2:
            error = max(error, math.sqrt(sums[1]) / quad_wr, math.sqrt(sums[3]) / mean_wrr)
        else:
            error = max(error, math.sqrt(sums[0] / n) / quad_wr,
                        math.sqrt(sums[2] / n) / mean_wrr)
            if criterion == 3:
                error = max(error, math.sqrt(sums[1]) / quad_wr / _QM16,
                            math.sqrt(sums[3]) / mean_wrr / _QM16)
    sums[:] = 0.0
    return error


@nb.njit(inline="always")
def _pack_2d(rows, i, h_cand, h_ant, delassus, bias, friction, a):
    """Contact a's row of nlgs_2d's `work`, with the factors of W: rows[i] (indexed in place,
    as _pack_3d's)."""
    rows[i, 0] = h_cand[a, 0, 0]
    rows[i, 1] = h_cand[a, 0, 1]
    rows[i, 2] = h_cand[a, 1, 0]
    rows[i, 3] = h_cand[a, 1, 1]
    rows[i, 4] = h_cand[a, 0, 2]
    rows[i, 5] = h_cand[a, 1, 2]
    rows[i, 6] = h_ant[a, 0, 2]
    rows[i, 7] = h_ant[a, 1, 2]
    rows[i, 8] = delassus[a, 0, 0]
    rows[i, 9] = delassus[a, 0, 1]
    rows[i, 10] = delassus[a, 1, 1]
    _factorize_2d(rows, i, rows[i, 8], rows[i, 9], rows[i, 10], friction[a])
    rows[i, 16] = bias[a]
    rows[i, 17] = friction[a]


@nb.njit(inline="always")
def _factorize_2d(rows, i, wtt, wtn, wnn, mu):
    """The factors of the single-contact solve on [[wtt, wtn], [wtn, wnn]] into
    rows[i, 11:16]."""
    f = factorize_contact_2d(wtt, wtn, wnn, mu)
    for k in range(5):
        rows[i, 11 + k] = f[k]


@nb.njit(inline="always")
def _local_velocity_2d(a, cand, ant, row, v, impulse):
    """First half of a single-contact update of nlgs_2d: contact a's local velocity (u_t,
    u_n + b_n) [m/s] from the others' impulses (its own removed: u = U - W R_a); row: its row
    of `work`."""
    c = cand[a]
    b = ant[a]
    rt0 = impulse[a, 0]
    rn0 = impulse[a, 1]
    # Sums as balanced trees, the impulse and shift terms apart: the velocities of one
    # contact depend on those the previous one wrote, so this chain's latency counts.
    dx = v[c, 0] - v[b, 0]
    dy = v[c, 1] - v[b, 1]
    ut = (((row[0] * dx + row[1] * dy) + (row[4] * v[c, 2] + row[6] * v[b, 2]))
          - (row[8] * rt0 + row[9] * rn0))
    un = (((row[2] * dx + row[3] * dy) + (row[5] * v[c, 2] + row[7] * v[b, 2]))
          + (row[16] - (row[9] * rt0 + row[10] * rn0)))
    return ut, un


@nb.njit(inline="always")
def _push_2d(a, cand, ant, row, v, impulse, inv_mass, relaxation, rt, rn):
    """Second half: contact a's new impulse (rt, rn) [N s], relaxed, and its change pushed
    into the velocities."""
    c = cand[a]
    b = ant[a]
    rt0 = impulse[a, 0]
    rn0 = impulse[a, 1]
    if relaxation != 1.0:
        rt = relaxation * rt + (1.0 - relaxation) * rt0
        rn = relaxation * rn + (1.0 - relaxation) * rn0
    dt = rt - rt0
    dn = rn - rn0
    # v += M^-1 H_a (dt, dn) on the candidate c and the antagonist b (also when dR = 0:
    # a branch on it is mispredicted more often than the stores cost)
    fx = row[0] * dt + row[2] * dn
    fy = row[1] * dt + row[3] * dn
    mc, mb = inv_mass[c], inv_mass[b]
    v[c, 0] = v[c, 0] + mc[0] * fx
    v[c, 1] = v[c, 1] + mc[1] * fy
    v[c, 2] = v[c, 2] + mc[2] * (row[4] * dt + row[5] * dn)
    v[b, 0] = v[b, 0] - mb[0] * fx
    v[b, 1] = v[b, 1] - mb[1] * fy
    v[b, 2] = v[b, 2] + mb[2] * (row[6] * dt + row[7] * dn)
    impulse[a, 0] = rt
    impulse[a, 1] = rn


@nb.njit(cache=True)
def _relative_change(v, v_prev, v_free, mass):
    """sqrt(|v - v_prev|^2_M / (|v - v_free|^2_M + (1e-14 |v|_M)^2)), 0 when nothing changed;
    then v_prev = v, ready for the next sweep. The second term of the denominator is the
    round-off floor: a change below ~1e-14 of the velocities themselves cannot be resolved in
    double precision, so a contact with a tiny impulse on a fast body must not keep the solver
    sweeping."""
    num, den, size = change_sums(v, v_prev, v_free, mass, 0.0, 0.0, 0.0)
    return change_ratio(num, den, size)


@nb.njit(cache=True)
def nlgs_3d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass, mass,
            v_free, v, v_prev, impulse, work, joints, law_map, sums, criterion, tolerance,
            max_iterations, relaxation):
    """nlgs_2d for 3D rigid bodies (6 dof, frame (t, n, s)); the single-contact problem on the
    Coulomb cone is solved exactly by saxum.solver.local3d (its open and stick cases inlined
    here on scalars, solve_contact_3d called for slides); active, joints and law_map as in
    nlgs_2d.

    Written out like nlgs_2d: before the sweeps each active contact's rows of H* go into one
    row of `work` (at least count x 38): the candidate's three rows (6 dof each), the
    antagonist's rotational parts (its translational rows are minus the candidate's, as for
    any rigid 3D contact: saxum.bodies.rigid3d.contact_jacobians), W, b_n and mu."""
    nactive = _pack_dry_3d(h_cand, h_ant, delassus, bias, friction, active, count, work)
    if joints is not None:
        nactive += _pack_joints_3d(h_cand, h_ant, delassus, bias, friction, work, joints)
    if nactive == 0:
        return 0, 0.0
    u = np.empty(3)
    rr = np.empty(3)
    wp = np.empty((3, 3))
    no_order = np.empty(0, dtype=np.int64)
    error = np.inf
    it = 0
    # v_prev = v by _relative_change's loop (a slice copy would compile its error message's
    # string formatting, ~1 s of a first run)
    _relative_change(v, v_prev, v_free, mass)
    while it < max_iterations:
        it += 1
        _dry_sweep_3d(0, count, False, active, no_order, cand, ant, work, delassus, v,
                      impulse, inv_mass, relaxation, sums, u, rr)
        if joints is not None:
            _joint_sweep_3d(cand, ant, v, impulse, work, joints, law_map, inv_mass, relaxation,
                            sums, u, rr, wp)
        if sums is not None:
            error = _check_error(sums, criterion)
        else:
            error = _relative_change(v, v_prev, v_free, mass)  # and v_prev = v
        if error <= tolerance:
            break
    return it, error


@nb.njit(inline="always")
def _pack_dry_3d(h_cand, h_ant, delassus, bias, friction, active, count, work):
    """The active dry contacts' rows of nlgs_3d's `work`; returns how many."""
    nactive = 0
    for a in range(count):
        if active[a]:
            nactive += 1
            _pack_3d(work, a, h_cand, h_ant, delassus, bias, friction, a)
    return nactive


@nb.njit(inline="always")
def _check_sums_3d(sums, row, r0, r1):
    """_check_sums for a 3D contact: W its Delassus block row[27:36], r0 its impulse before
    the update and r1 the single-contact solution [N s] (3-vectors), unrelaxed."""
    wt0, wn0, ws0 = _w_times_3d(row, r0[0], r0[1], r0[2])
    wt1, wn1, ws1 = _w_times_3d(row, r1[0], r1[1], r1[2])
    _check_sums(sums, wt0 - wt1, wn0 - wn1, ws0 - ws1, 0.5 * (r0[0] + r1[0]),
                0.5 * (r0[1] + r1[1]), 0.5 * (r0[2] + r1[2]),
                0.5 * ((wt0 * r0[0] + wn0 * r0[1] + ws0 * r0[2])
                       + (wt1 * r1[0] + wn1 * r1[1] + ws1 * r1[2])),
                0.5 * ((wt0 * wt0 + wn0 * wn0 + ws0 * ws0) + (wt1 * wt1 + wn1 * wn1 + ws1 * ws1)))


@nb.njit(inline="always")
def _w_times_3d(row, rt, rn, rs):
    """W R of a 3D contact, W its Delassus block row[27:36] (nlgs_3d)."""
    return (row[27] * rt + row[28] * rn + row[29] * rs,
            row[30] * rt + row[31] * rn + row[32] * rs,
            row[33] * rt + row[34] * rn + row[35] * rs)


@nb.njit(inline="always")
def _pack_3d(rows, i, h_cand, h_ant, delassus, bias, friction, a):
    """Contact a's row of nlgs_3d's `work`: rows[i] (indexed in place: a row's view passed
    per contact made numba count references per contact)."""
    for r in range(3):
        for d in range(6):
            rows[i, 6 * r + d] = h_cand[a, r, d]
        for d in range(3):
            rows[i, 18 + 3 * r + d] = h_ant[a, r, 3 + d]
        for s in range(3):
            rows[i, 27 + 3 * r + s] = delassus[a, r, s]
    rows[i, 36] = bias[a]
    rows[i, 37] = friction[a]


@nb.njit(inline="always")
def _local_velocity_3d(a, cand, ant, row, v, impulse, u):
    """First half of a single-contact update of nlgs_3d, as _local_velocity_2d: contact a's
    (u_t, u_n + b_n, u_s) [m/s] into u (a 3-vector, work memory)."""
    c = cand[a]
    b = ant[a]
    vc3, vc4, vc5 = v[c, 3], v[c, 4], v[c, 5]
    vb3, vb4, vb5 = v[b, 3], v[b, 4], v[b, 5]
    dx = v[c, 0] - v[b, 0]
    dy = v[c, 1] - v[b, 1]
    dz = v[c, 2] - v[b, 2]
    rt0 = impulse[a, 0]
    rn0 = impulse[a, 1]
    rs0 = impulse[a, 2]
    for r in range(3):
        o = 6 * r
        p = 18 + 3 * r
        q = 27 + 3 * r
        u[r] = (((row[o] * dx + row[o + 1] * dy + row[o + 2] * dz)
                 + (row[o + 3] * vc3 + row[o + 4] * vc4 + row[o + 5] * vc5))
                + (row[p] * vb3 + row[p + 1] * vb4 + row[p + 2] * vb5)) - (
            row[q] * rt0 + row[q + 1] * rn0 + row[q + 2] * rs0)
    u[1] += row[36]


@nb.njit(inline="always")
def _push_3d(a, cand, ant, row, v, impulse, inv_mass, relaxation, rr):
    """Second half: contact a's new impulse rr [N s], relaxed (in place), and its change
    pushed into the velocities."""
    c = cand[a]
    b = ant[a]
    rt0 = impulse[a, 0]
    rn0 = impulse[a, 1]
    rs0 = impulse[a, 2]
    if relaxation != 1.0:
        rr[0] = relaxation * rr[0] + (1.0 - relaxation) * rt0
        rr[1] = relaxation * rr[1] + (1.0 - relaxation) * rn0
        rr[2] = relaxation * rr[2] + (1.0 - relaxation) * rs0
    dt = rr[0] - rt0
    dn = rr[1] - rn0
    ds = rr[2] - rs0
    # v += M^-1 H_a dR on the candidate c and the antagonist b
    mc = inv_mass[c]
    mb = inv_mass[b]
    for d in range(3):
        f = row[d] * dt + row[6 + d] * dn + row[12 + d] * ds
        v[c, d] += mc[d] * f
        v[b, d] -= mb[d] * f
        v[c, 3 + d] += mc[3 + d] * (row[3 + d] * dt + row[9 + d] * dn + row[15 + d] * ds)
        v[b, 3 + d] += mb[3 + d] * (row[18 + d] * dt + row[21 + d] * dn + row[24 + d] * ds)
    impulse[a, 0] = rr[0]
    impulse[a, 1] = rr[1]
    impulse[a, 2] = rr[2]


@nb.njit(inline="always")
def _pack_joints_3d(h_cand, h_ant, delassus, bias, friction, work, joints):
    """The joints' rows of `work` (nlgs_3d); returns how many."""
    for j in range(joints.shape[0]):
        _pack_3d(work, joints[j], h_cand, h_ant, delassus, bias, friction, joints[j])
    return joints.shape[0]


@nb.njit(cache=True)
def _dry_sweep_3d(lo, hi, packed, active, order, cand, ant, rows, delassus, v, impulse,
                  inv_mass, relaxation, sums, u, rr):
    """Single-contact updates of dry contacts: not packed (nlgs_3d), the active ones of
    lo .. hi - 1, the last first, each with its own row of `rows` and W (order unread);
    packed (nlgs_3d_domains), the rows lo .. hi - 1 in order, W of the contact order[i]
    (active unread). sums as _update_dry_2d's; u, rr: 3-vectors, work memory. One compiled
    loop for both: a per-contact inline function taking a row's view and twelve arrays made
    numba count references per contact (2.4x the sweep's time on a 3D pier at rest,
    2cb2a1a)."""
    for k in range(lo, hi):
        if not packed:
            a = hi - 1 - (k - lo)
            if not active[a]:
                continue
            da = a
        else:
            a = k
            da = order[k]
        row = rows[a]
        _local_velocity_3d(a, cand, ant, row, v, impulse, u)
        case, rr[0], rr[1], rr[2] = open_or_stick_3d(
            row[27], row[28], row[29], row[30], row[31], row[32], row[33], row[34], row[35],
            u[0], u[1], u[2], row[37])
        if case < 0:  # a slide: the full solve, from the current impulse
            for r in range(3):
                rr[r] = impulse[a, r]
            solve_contact_3d(delassus[da], u, row[37], rr)
        if sums is not None:
            _check_sums_3d(sums, row, impulse[a], rr)
        _push_3d(a, cand, ant, row, v, impulse, inv_mass, relaxation, rr)


@nb.njit(inline="always")
def _joint_sweep_3d(cand, ant, v, impulse, work, joints, law_map, inv_mass, relaxation, sums,
                    u, rr, wp):
    """One sweep over the joints of nlgs_3d, in order; u, rr (3), wp (3 x 3): work memory."""
    for j in range(joints.shape[0]):
        a = joints[j]
        row = work[a]
        _local_velocity_3d(a, cand, ant, row, v, impulse, u)
        for r in range(3):  # the dry part's starting guess
            rr[r] = impulse[a, r]
        law_solve_3d(law_map[a], u, row[36], row[37], wp, rr)
        if sums is not None:
            _check_sums_3d(sums, row, impulse[a], rr)
        _push_3d(a, cand, ant, row, v, impulse, inv_mass, relaxation, rr)


@nb.njit(parallel=True, cache=True)
def nlgs_3d_domains(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count,
                    inv_mass, mass, v_free, v, v_prev, impulse, work, joints, law_map, order,
                    groups, ghost, rows, own, own_impulse, vx, inv_mass_x, tolerance,
                    max_iterations, relaxation):
    """nlgs_3d with its dry contacts swept domain by domain, as nlgs_2d_domains sweeps
    nlgs_2d's (the same partition, partition_contacts, the same phases and the same bits
    whatever the number of threads): rows (at least len(order) x 38) and own_impulse
    (len(order) x 3) in nlgs_3d's layout. One domain gives nlgs_3d's order and arithmetic."""
    ngroups = groups.shape[0] - 1
    ndomains = ngroups // 2
    n = v.shape[0]
    nfixed = (vx.shape[0] - n) // ngroups
    # one parallel region, as nlgs_2d_domains': the rows by blocks (not by groups: with two
    # domains both domains' groups would go to one thread), and in as many blocks the
    # bodies' vx = v (with the fixed ones' copies) and v_prev = v
    blocks = max(1, -(-order.shape[0] // _ROW_BLOCK))
    for k in nb.prange(blocks):
        lo, hi = _share(k, blocks, order.shape[0])
        g = 0
        while lo < hi:
            while groups[g + 1] <= lo:
                g += 1
            end = min(hi, groups[g + 1])
            _pack_range_3d(lo, end, n + g * nfixed, order, cand, ant, h_cand, h_ant,
                           delassus, bias, friction, impulse, ghost, rows, own, own_impulse)
            lo = end
        lo, hi = _share(k, blocks, n)
        _spread_range(lo, hi, v, vx, v_prev, ghost, ngroups)
    packed = order.shape[0]
    if joints is not None:
        packed += _pack_joints_3d(h_cand, h_ant, delassus, bias, friction, work, joints)
    if packed == 0:
        return 0, 0.0
    v_own = vx[:n]
    # the phases' groups (partition_contacts): the domains, the even cuts, the odd cuts,
    # the contacts across two cuts or more
    phases = np.array([0, ndomains, ndomains + ndomains // 2, ngroups - 1, ngroups])
    sums = np.empty((-(-n // _SUM_BODIES), 3))
    u = np.empty(3)
    rr = np.empty(3)
    wp = np.empty((3, 3))
    error = np.inf
    it = 0
    while it < max_iterations:
        it += 1
        for p in range(4):
            if phases[p + 1] - phases[p] > 1:
                for g in nb.prange(phases[p], phases[p + 1]):
                    _sweep_range_3d(groups[g], groups[g + 1], own, rows, order, delassus, vx,
                                    own_impulse, inv_mass_x, relaxation)
            elif phases[p + 1] > phases[p]:  # one group: no parallel region
                _sweep_range_3d(groups[phases[p]], groups[phases[p + 1]], own, rows, order,
                                delassus, vx, own_impulse, inv_mass_x, relaxation)
        if joints is not None:
            _joint_sweep_3d(cand, ant, v_own, impulse, work, joints, law_map, inv_mass,
                            relaxation, None, u, rr, wp)
        error = _parallel_change(v_own, v_prev, v_free, mass, sums)
        if error <= tolerance:
            break
    for k in nb.prange(blocks):  # back, by the same blocks
        lo, hi = _share(k, blocks, order.shape[0])
        for i in range(lo, hi):
            for r in range(3):
                impulse[order[i], r] = own_impulse[i, r]
        lo, hi = _share(k, blocks, n)
        for b in range(lo, hi):
            for d in range(6):
                v[b, d] = vx[b, d]
    return it, error


@nb.njit(cache=True)
def _pack_range_3d(lo, hi, base, order, cand, ant, h_cand, h_ant, delassus, bias, friction,
                   impulse, ghost, rows, own, own_impulse):
    """The rows, bodies and impulses of the dry contacts order[lo:hi] of nlgs_3d_domains, as
    _pack_range_2d's."""
    for i in range(lo, hi):
        _pack_3d(rows, i, h_cand, h_ant, delassus, bias, friction, order[i])
        _own_contact(i, order[i], base, cand, ant, impulse, ghost, own, own_impulse)


@nb.njit(inline="always")
def _own_contact(i, a, base, cand, ant, impulse, ghost, own, own_impulse):
    """Contact a as packed row i of a sweep by domains: its bodies into own[:, i], a fixed
    one as its group's copy (row base + its rank, ghost), and its impulse into
    own_impulse[i]."""
    c = cand[a]
    b = ant[a]
    own[0, i] = c if ghost[c] < 0 else base + ghost[c]
    own[1, i] = b if ghost[b] < 0 else base + ghost[b]
    for r in range(impulse.shape[1]):
        own_impulse[i, r] = impulse[a, r]


@nb.njit(cache=True)
def _sweep_range_3d(lo, hi, own, rows, order, delassus, v, impulse, inv_mass, relaxation):
    """Single-contact updates of the packed dry contacts lo .. hi - 1 in order
    (nlgs_3d_domains), as nlgs_3d's loop (a function of its own as _sweep_range_2d)."""
    _dry_sweep_3d(lo, hi, True, np.empty(0, dtype=np.bool_), order, own[0], own[1], rows,
                  delassus, v, impulse, inv_mass, relaxation, None, np.empty(3), np.empty(3))


@nb.njit(inline="always")
def _spread_range(lo, hi, v, vx, v_prev, ghost, ngroups):
    """vx = v_prev = v for the bodies lo .. hi - 1, and each fixed body's velocity (ghost[b]
    >= 0) into its copy for each of ngroups groups (nlgs_3d_domains' vx, whose first len(v)
    rows are the bodies')."""
    n = v.shape[0]
    nfixed = (vx.shape[0] - n) // ngroups
    for b in range(lo, hi):
        for d in range(v.shape[1]):
            vx[b, d] = v_prev[b, d] = v[b, d]
        if ghost[b] >= 0:
            for g in range(ngroups):
                for d in range(v.shape[1]):
                    vx[n + g * nfixed + ghost[b], d] = v[b, d]
