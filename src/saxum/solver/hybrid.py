"""Time-step solvers beyond NLGS: the conic fixed point alone (ConicSolver) and the hybrid
(Hybrid) that runs NLGS and, where NLGS stalls or at its cap, accepts NLGS's iterate by the
natural map or tries Fischer-Burmeister Newton (3D), or the conic fixed point and Alart-Curnier
Newton (2D).

ConicSolver assembles the rows H* of the step's active contacts (saxum.solver.assembled),
solves the step by De Saxce's fixed point with Clarabel in body space (saxum.solver.conic's
body_conic: the free bodies' velocities as unknowns, W never formed) from the step's warm
start, writes R and v = v_free + M^-1 H R, and confirms with NLGS sweeps from
there: the reported error is NLGS's own criterion (saxum.solver.nlgs), the same as a step
solved by NLGS alone reports, so that every step is judged alike.

Hybrid: NLGS exactly as saxum.solver.NLGS runs it (the same sweeps, the same rest solution),
in windows of `window` sweeps, never ending a step worse than NLGS's iterate by NLGS's own
criterion or by the natural map. After each window it compares NLGS's error with the least at
the end of the windows before. Only a measured stall (no new least error for _PATIENCE = 10
windows in a row: NLGS's error oscillates, and rises for a few windows on steps it then
finishes) or the sweep cap makes it look further, once per solve; a rate that predicts the
cap does not (NLGS finishes such steps, slowly: docs/method.md). There it first measures the
natural-map error of NLGS's iterate (saxum.solver.residual, on the assembled problem): where
it is within the tolerance the step ends there, converged, reporting that error (the shaken
3D L wall: 37 of its 75 steps above NLGS's criterion are such steps). Else it tries other
solvers. In 3D, where that error is within _REACH times the tolerance or NLGS's error was not
crawling (_CRAWL), Fischer-Burmeister Newton (saxum.solver.fischer) from NLGS's iterate, kept
where the natural-map error of its result is within the tolerance (the step ends converged,
finished by "newton", reporting that error); then, where that error is within _PROXIMAL_REACH
times the tolerance (whether NLGS crawled or not), the proximal point from NLGS's iterate
(saxum.solver.newton.proximal_point, then Fischer-Burmeister Newton from its iterate), kept the
same way (finished by "proximal"): its regularized subproblems move the impulses where the
merit of Newton's line search does not let it go (docs/method.md, (f)); Fischer-Burmeister
Newton dominates the others there (docs/method.md:
the conic fixed point and Alart-Curnier Newton from zero were never kept on the shaken L wall,
and the fixed point fails on three FCLIB 3D problems it solves), which 3D no longer tries; then,
where Hybrid.smoothing (off by default), on every 3D attempt (whether or not that one ran, so
also where NLGS crawls far from the tolerance), smoothing Newton from NLGS's iterate
(saxum.solver.fischer.smoothing_newton, at most _SMOOTHING_SOLVES factorizations), kept the
same way (finished by "smoothing"): it follows the smoothed problems' solutions past the
stationary points where Fischer-Burmeister Newton and NLGS crawl (docs/method.md). In
2D, the conic fixed point from NLGS's iterate, judged by one NLGS sweep from its result: it is
kept, and NLGS sweeps on from it with the sweeps left, only where that sweep converged or its
error (the relative change NLGS reports) is below half NLGS's last sweep's; then semismooth
Newton on Alart-Curnier's function from zero impulses (from NLGS's iterate it crawls as NLGS
does at the friction threshold; the Fischer-Burmeister one does not help in 2D:
docs/method.md), judged the same way. Where none is kept NLGS's iterate is put back bit for
bit and NLGS goes on as if alone (at the cap: the step ends as NLGS alone ends it). Where
NLGS's sweeps from a kept conic iterate end above that iterate's error, the step ends at it.
After k attempts in a row that were rejected or did not end their solve converged, the next
2^k - 1 solves (k at most 6) try no other solver (the natural-map test still runs): on the
friction threshold the other solvers crawl too, and each attempt costs seconds on a few
hundred contacts. Except in 3D where NLGS's iterate is within _PROXIMAL_REACH times the
tolerance: such a step is tried whatever the attempts before it did (the shaken 3D L wall's
steps 41-46 were skipped after the rejected attempts on 33-39, and tried they end converged:
docs/method.md, (g)). Where NLGS converges without such a stall the
hybrid is NLGS: the same iterates bit for bit, one more Python call per window. A solve that
ends above the tolerance reports the natural-map error of the impulses it ends with
(SolverReport.natural_map): how far they are from a solution, which NLGS's criterion (a
sweep's change) does not say; the step log calls them "no solution reached" (whether the
step's problem has a solution: benchmarks/capped_steps.py --existence).
"""

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError
from .assembled import assemble_local
from .base import SOLVER_NAMES, ContactSolver, SolverReport, error_trend, prefixed, unprefixed
from .conic import body_conic
from .fischer import fischer_burmeister_newton, smoothing_newton
from .newton import alart_curnier_newton, proximal_point
from .nlgs import _REST_WORK, _TREND_WINDOWS, NLGS, Refinement, check_refinement
from .problem import ContactProblem

__all__ = ["ConicSolver", "Hybrid"]

_PATIENCE = 10
"""Windows in a row without a new least error after which NLGS's error has stalled. NLGS's
error oscillates on steps it then finishes: on the Burnum ramp and record under NLGS alone
(15 000 steps, windows of 100 sweeps), converged steps went up to 7 windows without a new
least error (155 steps 1 window, 9 steps 2 to 7), and the two steps that stalled at the cap
30 and 40 windows (docs/method.md)."""
_BETTER = 0.5
"""A conic iterate is kept where one sweep from it changes the velocities by less than this
times NLGS's last sweep (or converges): NLGS's error varies by more than that from window to
window on stalled steps, and a step left at a near-equal iterate changes the run for no gain
(on the Burnum ramp the fixed point ended a capped step at 3.5247e-6 against NLGS's 3.53e-6)."""
_NEWTON_ITERATIONS = 60
"""Newton iterations at most per attempt (the shaken stack's capped step: 40 to 2.4e-9 from
zero impulses, 1 s on 78 contacts; on 770 contacts of the shaken 3D L wall each costs ~0.2 s)."""
_FISCHER_ITERATIONS = 10
"""Fischer-Burmeister Newton iterations at most per attempt (3D): on the shaken 3D L wall's
steps above the tolerance it brings those it solves under 1e-6 in 1 to 7 (0.8-4.5 s on 685-771
contacts, a loaded machine), and the others only halfway in 20 (9-47 s each); it stops earlier
where its merit stalls (saxum.solver.fischer)."""
_SMOOTHING_SOLVES = 150
"""LU factorizations at most per smoothing Newton attempt (3D): on the small shaken L wall's
seven capped steps it reaches 1e-6 in 61-118 (0.7-1.9 s of CPU on 280 contacts); on the 3D L
wall's first onset step (19, 770 contacts) it uses all 150 (9.8 s of CPU) without a better
iterate (docs/method.md)."""
_REACH = 3.0
"""In 3D, Fischer-Burmeister Newton runs only where NLGS's iterate is within this factor of
the tolerance by the natural map: on the shaken 3D L wall's 38 steps above it (NLGS's iterate
at 1.04e-6 to 3.9e-5) it brought under it only steps that started at most 2.33 times above
(14 of the 18 within 3 times, in 1 to 7 iterations), and none of the 20 above 3 times
(3.1e-6 to 3.9e-5), whose error it halved in 10 iterations at 10-60 s each (BENCHMARKS.md,
fb13), all of them where NLGS's error crawled (_CRAWL)."""
_PROXIMAL_REACH = 10.0
"""In 3D, where Fischer-Burmeister Newton from NLGS's iterate did not finish the step, the
proximal point (saxum.solver.newton.proximal_point) runs from it where it is within this
factor of the tolerance by the natural map: on the shaken 3D L wall's steps above the
tolerance it brings the later ones (NLGS's iterate at 7.3e-6 to 8.7e-6, 1.2-1.7 s) and step 41
(3.1e-6) under 1e-6, and none of the onset's farther than 1e-5 (docs/method.md, (f)). Such a
step is tried also where the back-off would skip it: an attempt there costs at most
_PROXIMAL_OUTER outer iterations and two Fischer-Burmeister Newton runs (3-10 s on 770
contacts, a loaded machine), and on the L wall's steps 41-46 the back-off from the failures at
33-39 skipped 6 steps that such attempts finish (docs/method.md, (g))."""
_PROXIMAL_OUTER = 20
"""Proximal outer iterations at most per attempt: those it finished took 4 to 20."""
_CRAWL = 1e-3
"""NLGS's error falling by less than this fraction per sweep crawls (the L wall's capped steps:
1e-5 per sweep and less; a cold start cut by a small cap: 0.04 to 0.25)."""
_NEWTON_TOLERANCE = 1e-2
"""Newton's natural-map tolerance relative to the hybrid's: its last iterations are quadratic
and cheap, and the judging sweep must converge from its result."""
_BACKOFF = 6
"""Failed switches in a row after which the hybrid waits the longest, 2^6 - 1 solves."""


@dataclass
class ConicSolver(ContactSolver):
    """tolerance [-]: NLGS's criterion, which the confirming sweeps (at most `confirm`) must
    reach; fixed_points: fixed-point iterations at most; conic_tolerance [-]: natural-map
    error ||F_nat|| / ||q|| at which the fixed point stops (None: `tolerance`; on the
    512-brick wall's first step under 0.7 g a natural-map error of 4.7e-7 gave a confirming
    sweep's error of 6.3e-8); relaxation of the sweeps."""

    tolerance: float = 1e-6
    fixed_points: int = 30
    conic_tolerance: float | None = None
    confirm: int = 200
    relaxation: float = 1.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.tolerance) and self.tolerance > 0.0):
            raise InputError(f"solver.tolerance must be > 0, got {self.tolerance}")
        if self.fixed_points < 1 or self.confirm < 1:
            raise InputError("solver.fixed_points and solver.confirm must be >= 1")
        self.fixed_point_iterations = 0
        """Fixed-point iterations done, in all."""
        self.natural_map_error = math.nan
        """The conic solution's natural-map error on the last solve."""
        self._nlgs = NLGS(self.tolerance, self.confirm, self.relaxation, rest_after=0,
                          refine=0.0)

    def solve(self, problem: ContactProblem, impulse: np.ndarray, v_free: np.ndarray,
              v: np.ndarray) -> SolverReport:
        self.conic(problem, impulse, v_free, v)
        report = self._nlgs.solve(problem, impulse, v_free, v)
        return SolverReport(report.iterations, report.error, report.converged, "conic",
                            rate=report.rate, stalled=report.stalled)

    def conic(self, problem: ContactProblem, impulse: np.ndarray, v_free: np.ndarray,
              v: np.ndarray) -> None:
        """The fixed point from the current impulses; writes impulse and v."""
        local = assemble_local(problem, v_free)
        if local.active.size == 0:
            return
        free = local.inv_mass > 0.0
        hstar = local.hstar[:, free]
        v_free_free = v_free.ravel()[free]
        result = body_conic(hstar, 1.0 / local.inv_mass[free], v_free_free,
                            local.q - hstar @ v_free_free, local.mu, problem.model.dim,
                            local.impulses(impulse),
                            self.tolerance if self.conic_tolerance is None
                            else self.conic_tolerance, self.fixed_points)
        self.fixed_point_iterations += result.iterations
        self.natural_map_error = result.error
        local.scatter(result.r, v_free, impulse, v)


@dataclass
class Hybrid(ContactSolver):
    """NLGS (tolerance, max_iterations, relaxation, rest_after: as saxum.solver.NLGS) that,
    where NLGS stalls or at its cap, ends the step where NLGS's iterate is within the tolerance
    by the natural map, else tries Fischer-Burmeister Newton and the proximal point (3D) or
    the conic fixed point and Alart-Curnier Newton (2D), and keeps what they find only where it
    is within the tolerance by the natural map or better by NLGS's own criterion (module doc);
    window: sweeps between two measurements of the error, and the sweeps that judge a conic
    iterate; threads, domains,
    refine, refine_sweeps, accelerate: NLGS's (saxum.solver.NLGS; the refinement comes once NLGS has
    converged by itself, so that where NLGS converges the hybrid is NLGS bit for bit);
    smoothing: in 3D, smoothing Newton on every attempt after Fischer-Burmeister Newton (off
    by default: on the small shaken L wall it finishes the steps NLGS leaves above the
    tolerance; on the big one's first 100 steps it finished one, yet 25 steps ended above the
    tolerance against the default's 24, at 1.4 times its CPU time: docs/method.md)."""

    tolerance: float = 1e-6
    max_iterations: int = 5000
    relaxation: float = 1.0
    rest_after: int = 50
    window: int = 100
    threads: int | None = None
    domains: int | None = None
    refine: float = 100.0
    refine_sweeps: int = 3000
    smoothing: bool = False
    accelerate: bool = True

    def __post_init__(self) -> None:
        check_refinement(self)
        if self.window < 1:
            raise InputError(f"solver.window must be >= 1, got {self.window}")
        # NLGS's refinement (NLGS.refine) comes once the step has converged (solve)
        self._first = NLGS(self.tolerance, self.max_iterations, self.relaxation,
                           self.rest_after, threads=self.threads, domains=self.domains,
                           refine=0.0)
        self._more = NLGS(self.tolerance, self.max_iterations, self.relaxation, rest_after=0,
                          threads=self.threads, domains=self.domains, refine=0.0)
        self._first._trend = self._more._trend = False  # the windows give it (solve)
        self._conic = ConicSolver(self.tolerance, relaxation=self.relaxation)
        self._conic._nlgs.threads = self.threads
        self._conic._nlgs.domains = self.domains
        self.finished = {name: 0 for name in SOLVER_NAMES}
        """Solves (steps and projections) finished by each solver."""
        self.attempts = 0
        """Solves on which other solvers ran (a stall or the cap, NLGS's iterate not within
        the tolerance by the natural map)..."""
        self.rejected = 0
        """... and those on which none of their iterates was kept (NLGS went on from its
        own)."""
        self.newton_iterations = 0
        """Semismooth Newton iterations done (Fischer-Burmeister and Alart-Curnier), in all."""
        self._failures = 0
        self._wait = 0
        self._refinement = Refinement()

    def checkpoint(self) -> dict[str, np.ndarray]:
        # "switch": the back-off that decides where to try other solvers (_failures, _wait);
        # the state of the first NLGS ("first."; the others carry none: no rest solution, no
        # refinement)
        return {"refinement": self._refinement.flags(),
                "switch": np.array([self._failures, self._wait], dtype=np.int64),
                **prefixed("first", self._first.checkpoint())}

    def restore(self, saved: dict) -> None:
        self._refinement = Refinement.from_flags(saved.get("refinement"))
        failures, wait = saved.get("switch", (0, 0))
        self._failures, self._wait = int(failures), int(wait)
        self._first.restore(unprefixed(saved, "first"))

    @property
    def rest_attempts(self) -> int:
        return self._first.rest_attempts

    @property
    def rest_solutions(self) -> int:
        return self._first.rest_solutions

    def solve(self, problem: ContactProblem, impulse: np.ndarray, v_free: np.ndarray,
              v: np.ndarray) -> SolverReport:
        # the first window: NLGS's own first phase (sweeps, the rest solution), then a window
        first = self.window
        if self.rest_after > 0 and problem.count > 0:
            first += max(self.rest_after, -(-_REST_WORK // problem.count))
        self._first.max_iterations = min(first, self.max_iterations)
        own = getattr(problem, "v_begin", None) is not None  # not a projection's
        if own:
            self._refinement.start(problem, impulse)
        report = self._first.solve(problem, impulse, v_free, v)
        done = report.iterations  # sweeps on the path kept (the cap counts these)
        judging = 0  # the sweeps that judged iterates NLGS did not keep
        solver = "nlgs"
        least = math.inf  # the least error at the end of a window...
        since = 0  # ... and the windows since it last fell
        attempt = self._wait == 0  # else NLGS alone (back-off), except near a solution (3D)
        self._wait = max(self._wait - 1, 0)
        attempted = checked = False
        errors = []  # at the end of NLGS's windows since the last iterate kept: the trend
        while not report.converged:
            if report.error < least:
                least, since = report.error, 0
            else:
                since += 1
            if not checked and (since >= _PATIENCE or done >= self.max_iterations):
                checked = True
                local = assemble_local(problem, v_free)
                natural = local.natural_map_error(impulse)
                if natural <= self.tolerance:
                    # NLGS's iterate is a solution to the tolerance by the natural map
                    report = SolverReport(report.iterations, natural, True, "nlgs", natural)
                    break
                hopeful = self._hopeful(problem, natural, errors)
                near = (problem.model.dim == 3
                        and natural <= _PROXIMAL_REACH * self.tolerance)
                if (attempt or near) and (hopeful or near
                                          or (self.smoothing and problem.model.dim == 3)):
                    attempted = True
                    self.attempts += 1
                    judged, wasted = self._attempt(problem, local, impulse, v_free, v,
                                                   report.error, hopeful, near)
                    judging += wasted
                    if judged is not None:
                        report, solver = judged, judged.solver
                        done += judged.iterations
                        kept = judged, impulse.copy(), v.copy()
                        errors.clear()
            if report.converged or done >= self.max_iterations:
                break
            self._more.max_iterations = min(self.window, self.max_iterations - done)
            report = self._more.solve(problem, impulse, v_free, v)
            done += report.iterations
            if report.iterations == self.window:
                errors.append(report.error)
        if own:
            # NLGS's refinement (NLGS.solve), only where NLGS converged by itself
            more, error = self._refinement.step(self, lambda target, count: self._sweep_to(
                problem, impulse, v_free, v, target, count), done, report.error,
                report.converged and solver == "nlgs" and not checked)
            done += more
            if error != report.error:  # (replace costs microseconds: not on every step)
                report = replace(report, error=error)
            if more and error > self.tolerance:  # the refinement's last sweep changed more
                self._more.max_iterations = self.max_iterations - done
                report = self._more.solve(problem, impulse, v_free, v)
                done += report.iterations
        if solver == "conic" and not report.converged and report.error > kept[0].error:
            # NLGS's error rose from the conic iterate's: the step ends at that iterate
            impulse[...] = kept[1]
            v[...] = kept[2]
            report = kept[0]
        if attempted:
            # back-off: after k attempts in a row that were rejected or on solves that did not
            # end converged, the next 2^k - 1 solves do not try (the fixed point crawls on
            # such steps too, and a rejected attempt costs seconds for nothing)
            won = solver != "nlgs" and report.converged
            self._failures = 0 if won else min(self._failures + 1, _BACKOFF)
            self._wait = 2 ** self._failures - 1 if self._failures else 0
        self.finished[solver] += 1
        # a step above the tolerance says how far its impulses are from a solution of its
        # problem, by the measure that does not depend on the solver (docs/method.md: on the
        # shaken 3D L wall NLGS's criterion of 1e-6 to 1e-5 at the cap is a natural-map
        # error of 1e-5 to 1e-4), and whether its error stalled or was still falling
        if report.converged:
            natural, trend = report.natural_map, (math.nan, False)
        else:
            natural = assemble_local(problem, v_free).natural_map_error(impulse)
            trend = error_trend(errors[-_TREND_WINDOWS:], self.window)
        return SolverReport(done + judging, report.error, report.converged, solver, natural,
                            *trend)  # (natural_map, rate, stalled)

    def _sweep_to(self, problem, impulse, v_free, v, tolerance: float, count: int):
        """At most `count` NLGS sweeps, stopping at `tolerance`: (sweeps, error)."""
        self._more.tolerance, self._more.max_iterations = tolerance, count
        self._more._accelerate_all = self.accelerate
        report = self._more.solve(problem, impulse, v_free, v)
        self._more.tolerance = self.tolerance
        self._more._accelerate_all = False
        return report.iterations, report.error

    def _hopeful(self, problem, natural: float, errors: list) -> bool:
        """Whether to try other solvers on a step whose NLGS iterate has the natural-map error
        `natural`, NLGS's error at the end of its windows being `errors`: in 2D always; in 3D
        where `natural` is within _REACH times the tolerance or NLGS's error was not crawling
        (falling by more than _CRAWL per sweep over its last windows, or too few windows to
        say: a small cap)."""
        rate = error_trend(errors[-_TREND_WINDOWS:], self.window)[0]
        return (problem.model.dim == 2 or natural <= _REACH * self.tolerance
                or not rate > 1.0 - _CRAWL)

    def _attempt(self, problem, local, impulse, v_free, v, error: float, hopeful: bool,
                 near: bool):
        """In 3D, Fischer-Burmeister Newton from NLGS's iterate (where `hopeful`: _hopeful),
        then the proximal point from it (where `near`: within _PROXIMAL_REACH times the
        tolerance), then smoothing Newton from it (Hybrid.smoothing), each kept where the
        natural-map error
        of its result is <= the tolerance; in 2D the conic fixed point from NLGS's
        iterate, then semismooth Newton on Alart-Curnier's function from zero impulses, each
        judged by one NLGS sweep from its result. `local`: the step's assembled
        problem. Returns (report, rejected): Fischer-Burmeister Newton's (its natural-map error
        as the error, converged) or the first judging sweep's report that converged or whose
        error is below _BETTER times NLGS's last sweep's `error` (its solver's name in
        SolverReport.solver), or None with NLGS's iterate put back (impulse and v bit for
        bit); rejected: the judging sweeps of the iterates not kept."""
        kept = impulse.copy(), v.copy()
        if problem.model.dim == 3:
            tries = (("newton", self._fischer),) if hopeful else ()
            if near:
                tries += (("proximal", self._proximal),)
            if self.smoothing:
                tries += (("smoothing", self._smoothing),)
            for name, candidate in tries:
                natural = candidate(local, impulse, v_free, v)
                if natural <= self.tolerance:
                    return SolverReport(0, natural, True, name, natural), 0
                impulse[...] = kept[0]
                v[...] = kept[1]
            candidates = ()
        else:
            candidates = (("conic", self._conic.conic), ("newton", self._newton))
        for name, candidate in candidates:
            if name == "newton":
                impulse[...] = kept[0]
                v[...] = kept[1]
            candidate(problem, impulse, v_free, v)
            self._more.max_iterations = 1
            report = self._more.solve(problem, impulse, v_free, v)
            if report.converged or report.error < _BETTER * error:
                return (SolverReport(report.iterations, report.error, report.converged, name),
                        int(name == "newton"))
        self.rejected += 1
        impulse[...] = kept[0]
        v[...] = kept[1]
        return None, len(candidates)

    def _fischer(self, local, impulse, v_free, v) -> float:
        """Fischer-Burmeister Newton (saxum.solver.fischer) from the current impulses on the
        step's assembled problem `local`; writes impulse and v, returns the natural-map error
        of the impulses written."""
        result = fischer_burmeister_newton(local.w, local.q, local.mu,
                                           local.impulses(impulse),
                                           _NEWTON_TOLERANCE * self.tolerance,
                                           _FISCHER_ITERATIONS)
        self.newton_iterations += result.iterations
        local.scatter(result.r, v_free, impulse, v)
        return local.natural_map_error(impulse)

    def _proximal(self, local, impulse, v_free, v) -> float:
        """The proximal point (saxum.solver.newton) from the current impulses on the step's
        assembled problem `local`, to the tolerance, then Fischer-Burmeister Newton from its
        iterate where that is not within it (the proximal iterates come near a solution
        linearly, Newton ends the way: on the shaken L wall's later steps 8e-7 -> 2e-7);
        writes impulse and v, returns the natural-map error of the impulses written."""
        result = proximal_point(local.w, local.q, local.mu, local.impulses(impulse),
                                self.tolerance, _PROXIMAL_OUTER)
        self.newton_iterations += result.interior_iterations
        if result.error > self.tolerance:  # Newton returns its start where it does worse
            result = fischer_burmeister_newton(local.w, local.q, local.mu, result.r,
                                               _NEWTON_TOLERANCE * self.tolerance,
                                               _FISCHER_ITERATIONS)
            self.newton_iterations += result.iterations
        local.scatter(result.r, v_free, impulse, v)
        return local.natural_map_error(impulse)

    def _smoothing(self, local, impulse, v_free, v) -> float:
        """Smoothing Newton (saxum.solver.fischer) from the current impulses on the step's
        assembled problem `local`, to the tolerance; writes impulse and v, returns the
        natural-map error of the impulses written."""
        result = smoothing_newton(local.w, local.q, local.mu, local.impulses(impulse),
                                  self.tolerance, _SMOOTHING_SOLVES)
        self.newton_iterations += result.interior_iterations
        local.scatter(result.r, v_free, impulse, v)
        return local.natural_map_error(impulse)

    def _newton(self, problem, impulse, v_free, v) -> None:
        """Semismooth Newton (saxum.solver.newton) from zero impulses on the step's assembled
        local problem; writes impulse and v. From NLGS's iterate at the friction threshold it
        crawls as NLGS does (docs/method.md)."""
        local = assemble_local(problem, v_free)
        if local.active.size == 0:
            return
        result = alart_curnier_newton(local.w, local.q, local.mu, problem.model.dim, None,
                                      _NEWTON_TOLERANCE * self.tolerance, _NEWTON_ITERATIONS)
        self.newton_iterations += result.iterations
        local.scatter(result.r, v_free, impulse, v)
