"""saxum's command line. Exit codes: 0 done, 1 failed with a message, 2 bad input (the
message names the key, file or option), 130 Ctrl-C outside a run's own handling.
SI units throughout; in 2D, forces and masses are per metre of depth.

    saxum run SCENARIO [-o RESULTS] [--overwrite] [--set KEY=VALUE ...] [--unset KEY ...]
              [--quiet]
    saxum resume RESULTS [--quiet]
    saxum demo NAME [-o PICTURE] [--duration T]      (NAME: arch, wall)
    saxum collapse SCENARIO --vary KEY --stands A --collapses B [--set KEY=VALUE ...]
                   [--unset KEY ...]
    saxum collapse-curve SCENARIO --periods T1,T2,... --stands A --collapses B [-o PNG]
    saxum ensemble SCENARIO [--records SET|FOLDER] [--scales A:B:STEP] [--ida]
                   [--scheduler tcp://HOST:8786 | --workers N] [-o ENSEMBLE.h5]
    saxum fclib solve FILE...
    saxum info RESULTS | ENSEMBLE.h5
    saxum plot RESULTS [--frame K | --collapse | --histories [--body NAME]] [--thrust-line]
    saxum plot ENSEMBLE.h5 [--edp NAME] [--threshold X]
    saxum animate RESULTS [-o GIF|MP4] [--fps N]
    saxum export-vtk RESULTS [-o FOLDER]
    saxum view RESULTS [-o HTML] [--no-open] [--every N] [--blocks PATTERN]
    saxum import-lmgc90 DATBOX -o SCENARIO [--duration T] [--dt H] [--overlap-tolerance D]
                        [--impulses VLOC_RLOC]
    saxum export-lmgc90 SCENARIO -o DATBOX [--precision lmgc90|full] [--polyhedra POLYR|POLYF]

`saxum COMMAND --help` gives a command's options; documentation: docs/README.md in the
source repository.
"""

import argparse
import contextlib
import logging
import math
import os
import signal
import sys
import threading
import warnings
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ._version import __version__
from .errors import InputError, ResultsWriteError, SolverWarning
from .laws import LawKind
from .steplog import bonds_note, natural_map_note

__all__ = ["main"]


def _run(args) -> None:
    from .runner import describe, run_scenario
    from .scenario import load_scenario

    threads = [] if args.threads is None else [f"solver.threads={args.threads}"]
    scenario = load_scenario(args.scenario, [*args.set, *threads])
    output = args.output or Path(args.scenario).with_suffix(".h5")
    summary = run_scenario(scenario, output, quiet=args.quiet, overwrite=args.overwrite,
                           scenario_text=Path(args.scenario).read_text(encoding="utf-8"))
    print(describe(summary))


def _resume(args) -> None:
    from .runner import describe, resume_run

    print(describe(resume_run(args.results, quiet=args.quiet)))


def _demo(args) -> None:
    from .precompile import start

    # both demos are 2D: their kernels compile, if need be, while the demo loads (matplotlib...)
    # (a first run's experience; with a filled cache the second process is soon stopped)
    start(2)
    from .demos import DEMOS

    output = args.output or Path(f"saxum-demo-{args.name}.png")
    DEMOS[args.name](output, duration=args.duration)


def _collapse(args) -> None:
    from .collapse import (
        DYNAMIC_FRACTION,
        CollapseCriterion,
        scenario_critical_value,
        solver_failures,
    )
    from .mechanism import mechanism
    from .plot import plot_frame
    from .results import Results
    from .runner import run_scenario
    from .scenario import load_scenario

    if args.fraction is None:
        dynamic = load_scenario(args.scenario, args.set).loads.ground_motion is not None
        args.fraction = DYNAMIC_FRACTION if dynamic else CollapseCriterion.fraction
    result = scenario_critical_value(
        args.scenario, args.vary, args.stands, args.collapses, overrides=tuple(args.set),
        tolerance=args.tolerance, criterion=CollapseCriterion(duration=args.duration,
                                                              fraction=args.fraction,
                                                              per_block=not args.structure_ratio))
    print(f"{args.vary}: stands at {result.stands:.6g}, collapses at {result.collapses:.6g} "
          f"(critical value {result.value:.6g}, {len(result.trials)} trials)")
    _warn_failures(solver_failures(result.trials), len(result.trials),
                   load_scenario(args.scenario, args.set).solver)
    scenario = load_scenario(args.scenario, [*args.set, f"{args.vary}={result.collapses!r}"])
    dim = scenario.structure.dim
    if args.vary == "loads.horizontal_acceleration":
        g = float(np.linalg.norm(scenario.loads.gravity_for(dim)))
        print(f"horizontal load factor lambda = a/g: {result.value / g:.4g} "
              f"(bracket {result.stands / g:.4g} .. {result.collapses / g:.4g})")
    uncertified = [t.value for t in result.trials if not t.certified]
    if uncertified:
        sim = result.trials[0].simulation
        if sim.fe is not None or sim.problem.joint_laws:  # (collapse._certifier's None)
            why = ("no equilibrium certificate for a model with "
                   + ("deformable blocks" if sim.fe is not None else "joint laws")
                   + ": at rest by the force ratio alone, or, neither at rest nor moved away "
                   "within --duration, judged by its energy")
        else:
            why = ("a trial that neither came to rest nor moved away within "
                   f"{1.0 + CollapseCriterion.run_on:g} x --duration and was judged by its "
                   "energy")
        warnings.warn(f"{len(uncertified)} of the {len(result.trials)} verdicts are not "
                      f"certified ({why}): {', '.join(f'{v:.6g}' for v in uncertified)}; the "
                      "bracket may then miss the critical value (docs/collapse.md)",
                      SolverWarning, stacklevel=1)
    if args.check_limit:
        _check_limit(args, result)
    trial = result.collapse()
    motion = scenario.loads.ground_motion
    if motion is not None:  # the state when the collapsing motion began
        at, when = trial.at_collapse, "when the collapsing motion began"
        print(f"time of collapse: t = {trial.collapse_time:.4g} s (a block moved by more "
              f"than {args.fraction:g} x the smallest block's size; the ground motion ends at "
              f"{float(motion.motion(dim).time[-1]):.4g} s)")
    else:
        trial.simulation.run(trial.state, 0.05)  # let the mechanism develop so hinges show
        at, when = trial.state, "0.05 s after the verdict"
        print(f"time of collapse: t = {trial.collapse_time:.4g} s (a block moved by more "
              f"than {args.fraction:g} x the smallest block's size)")
    print(f"mechanism at {args.vary} = {result.collapses:.6g}, t = {at.time:.4g} s "
          f"({when}):")
    mech = mechanism(trial.simulation.model, at, trial.simulation.integrator.dt)
    print(mech.text())
    output = args.output or Path(args.scenario).with_name(Path(args.scenario).stem
                                                          + "-collapse.h5")
    scenario = scenario.model_copy(update={"output": scenario.output.model_copy(
        update={"duration": at.time, "interval": at.time / 20})})
    run_scenario(scenario, output, quiet=True, overwrite=True)  # this command's own output
    title = f"{scenario.title or Path(args.scenario).stem}, {args.vary} = {result.collapses:.6g}"
    with Results(output) as r:
        picture = output.with_suffix(".png")
        wall = any(j.courses for j in mech.joints)  # a thrust line is an arch's (in section)
        plot_frame(r, -1, picture, thrust_line=not wall and dim == 2, mechanism=mech,
                   title=title)
    print(f"results of the collapsing case: {output}\npicture: {picture.resolve()}")


def _check_limit(args, result) -> None:
    """--check-limit: the static critical value beside the dynamic bracket, and a warning
    when it lies outside the bracket by more than --tolerance (relative)."""
    from .limit import static_critical_value

    static = static_critical_value(args.scenario, args.vary, args.stands, args.collapses,
                                   overrides=tuple(args.set))
    lo, hi = sorted((result.stands, result.collapses))
    print(f"limit analysis (static, associative friction): {args.vary} = {static:.6g}; "
          f"dynamic bracket {result.stands:.6g} .. {result.collapses:.6g}")
    slack = args.tolerance * max(abs(lo), abs(hi))
    if not lo - slack <= static <= hi + slack:
        warnings.warn(f"the limit analysis ({static:.6g}) and the dynamic bisection "
                      f"({result.value:.6g}) differ by more than the tolerance "
                      f"{args.tolerance:g}: with sliding joints the dynamics follow "
                      "non-associative friction, which may fail below the static value; "
                      "check the mechanism (docs/collapse.md)", SolverWarning, stacklevel=1)


def _limit(args) -> None:
    from .limit import scenario_limit_analysis
    from .plot import plot_limit
    from .plot3d import plot_limit_3d
    from .scenario import load_scenario

    result = scenario_limit_analysis(args.scenario, overrides=tuple(args.set), live=args.live,
                                     friction=args.friction)
    print(result.text())
    picture = args.output or Path(args.scenario).with_name(Path(args.scenario).stem
                                                           + "-limit.png")
    scenario = load_scenario(args.scenario, args.set)
    draw = plot_limit if result.model.dim == 2 else plot_limit_3d
    draw(result, picture, title=scenario.title or Path(args.scenario).stem)
    print(f"picture: {picture.resolve()}")


def _warn_failures(failures, trials: int, solver, where: str = "") -> None:
    """A SolverWarning when some trial steps did not converge (saxum.collapse.SolverFailures);
    solver: the scenario's SolverSpec."""
    if failures.steps:
        after = "" if solver.kind == "nlgs" else ", and the hybrid's attempts where it ran"
        warnings.warn(f"the contact solver did not converge (NLGS's cap of "
                      f"{solver.max_iterations} sweeps{after}) "
                      f"at {failures.steps} step(s) in {failures.trials} of the "
                      f"{trials} trials{where} (largest error there {failures.worst_error:.2g}, "
                      f"tolerance {solver.tolerance:g}); if that is far above the tolerance, "
                      "the verdicts may be wrong: raise solver.max_iterations or lower "
                      "solver.dt", SolverWarning, stacklevel=1)


def _collapse_curve(args) -> None:
    from .collapse import CollapseCriterion, collapse_curve
    from .plot import plot_collapse_curve
    from .scenario import load_scenario

    rows = collapse_curve(args.scenario, args.periods, args.stands, args.collapses,
                          overrides=tuple(args.set), tolerance=args.tolerance,
                          criterion=CollapseCriterion(duration=args.duration,
                                                      fraction=args.fraction),
                          processes=args.processes)
    scenario = load_scenario(args.scenario, args.set)
    for p in rows:
        _warn_failures(p.failures, p.trials, scenario.solver, f" at T_p = {p.period:g} s")
    g = float(np.linalg.norm(scenario.loads.gravity_for(scenario.structure.dim)))  # [m/s^2]
    print("period [s]  collapse amplitude [m/s^2]  (stands .. collapses)   [g]      trials"
          "  collapse at [s]")
    for p in rows:
        if p.note:
            print(f"{p.period:10.4g}  not found: {p.note}")
            continue
        print(f"{p.period:10.4g}  {p.amplitude:26.4g}  ({p.stands:.4g} .. {p.collapses:.4g})"
              f"  {p.amplitude / g:7.4f}  {p.trials:6d}  {p.collapse_time:15.4g}")
    for p in rows:
        if p.note or p.mechanism is None:  # (no collapse, or a 3D model)
            continue
        print(f"\nmechanism at T_p = {p.period:g} s, amplitude {p.collapses:.4g} m/s^2, "
              f"collapsing from t = {p.mechanism_time:.4g} s:")
        print("  " + p.mechanism.text().replace("\n", "\n  "))
    picture = args.output or Path(args.scenario).with_name(Path(args.scenario).stem
                                                           + "-curve.png")
    plot_collapse_curve(rows, picture, g=g, title=f"{Path(args.scenario).stem}: collapse "
                                                  "curve")
    table = picture.with_suffix(".csv")
    with open(table, "w") as f:
        f.write("period_s,stands_m_s2,collapses_m_s2,amplitude_g,trials,collapse_time_s,"
                "hinges,sliding_joints,moving_blocks,note\n")
        for p in rows:
            m = p.mechanism
            joints = [" | ".join(j.bodies) for j in m.hinges] if m else []
            slides = [" | ".join(j.bodies) for j in m.sliding] if m else []
            f.write(f"{p.period!r},{p.stands!r},{p.collapses!r},{p.amplitude / g:.6g},"
                    f"{p.trials},{p.collapse_time!r},\"{'; '.join(joints)}\","
                    f"\"{'; '.join(slides)}\",\"{'; '.join(m.moving if m else [])}\","
                    f"\"{p.note}\"\n")
    print(f"\npicture: {picture.resolve()}\ntable: {table.resolve()}")


def _ensemble(args) -> None:
    import json

    from .ensemble import describe, run_ensemble
    from .records import SETS
    from .scenario import load_scenario

    extra = []
    if args.records is not None:
        folder = args.records if args.records in SETS else str(Path(args.records).resolve())
        extra.append(f"ensemble.records={json.dumps(folder)}")
    if args.scales is not None:
        extra.append(f"ensemble.scales={json.dumps(args.scales)}")
    for key in ("ida", "tolerance", "measure", "after"):
        value = getattr(args, key)
        if value is not None:
            extra.append(f"ensemble.{key}={json.dumps(value)}")
    if args.blocks is not None:
        extra.append(f"ensemble.blocks={json.dumps(args.blocks.split(','))}")
    scenario = load_scenario(args.scenario, [*args.set, *extra])
    if scenario.ensemble is None:
        raise InputError(f"{args.scenario}: no [ensemble] table; give --records and --scales "
                         "(docs/ensemble.md)")
    output = args.output or Path(args.scenario).with_suffix(".ensemble.h5")
    summary = run_ensemble(scenario, output, scheduler=args.scheduler, workers=args.workers,
                           quiet=args.quiet, overwrite=args.overwrite,
                           scenario_text=Path(args.scenario).read_text(encoding="utf-8"))
    print(describe(summary))
    if summary.interrupted:
        raise KeyboardInterrupt  # (exit code 130; the file holds the runs made)
    _fragility_lines(summary.path)
    if summary.bad_records:
        raise InputError(f"{len(summary.bad_records)} record(s) left out, the others ran: "
                         + "; ".join(why for _, why in summary.bad_records))


def _fragility_lines(path) -> None:
    """The collapse fragility of an ensemble file, or why there is none."""
    from .ensemble import read_ensemble

    ensemble = read_ensemble(path)
    try:
        fit = ensemble.fragility()
    except InputError as err:
        print(f"collapse fragility: none ({err})")
        return
    band = fit.interval()
    print(f"collapse fragility (lognormal, Baker 2015): median {fit.theta:.4g} "
          f"(95 % {band['theta'][0]:.4g} .. {band['theta'][1]:.4g}), beta {fit.beta:.3g} "
          f"({band['beta'][0]:.3g} .. {band['beta'][1]:.3g}) from {fit.observations} "
          f"{'records' if fit.method == 'capacities' else 'runs'}\n"
          f"picture: saxum plot {path}")


def _fclib_solve(args) -> None:
    from .fclib import format_table, solve_fclib_files

    bad = []

    def skip(path, err):  # named now, and the others are solved
        print(f"saxum: bad input: {err} (left out)", file=sys.stderr)
        bad.append(str(path))

    rows = solve_fclib_files(args.files, tolerance=args.tolerance,
                             max_iterations=args.max_iterations, relaxation=args.relaxation,
                             solver=args.solver, on_error=skip)
    if rows:
        print(format_table(rows))
    unsolved = [r.name for r in rows if not r.solved]
    if bad:
        raise InputError(f"{len(bad)} of {len(args.files)} file(s) left out: {', '.join(bad)}"
                         + (f"; not solved to {args.tolerance:g}: {', '.join(unsolved)}"
                            if unsolved else ""))
    if unsolved:
        raise RuntimeError(f"not solved to {args.tolerance:g}: {', '.join(unsolved)}")


def _info(args) -> None:
    from .errors import ResultsDamageWarning
    from .results import Results

    if _is_ensemble(args.results):
        from .ensemble import read_ensemble

        e = read_ensemble(args.results)
        col = e.runs["collapsed"]
        bad = [f"{n}: {why}" for n, why in zip(e.record_names, e.record_errors, strict=True)
               if why]
        print(f"ensemble: {args.results} ({'IDA' if e.spec.ida else 'multiple stripes'}, "
              f"records {e.spec.records}, scales {', '.join(f'{s:g}' for s in e.spec.scales)})"
              f"\nrecords: {len(e.record_names)}" + (f", left out: {'; '.join(bad)}" if bad
                                                      else "")
              + f"\nruns: {col.size} ({int((col == 1).sum())} collapsed, "
              f"{int((col == 0).sum())} stood, {int((col < 0).sum())} failed)")
        _fragility_lines(args.results)
        return
    with warnings.catch_warnings():  # info_text says what is damaged
        warnings.simplefilter("ignore", ResultsDamageWarning)
        r = Results(args.results)
    with r:
        print(info_text(r))


def info_text(r) -> str:
    """What the run was and what the solver did, for `saxum info`."""
    from .collapse import _moving_kind
    from .model import BodyKind

    s = r.steps
    status = r.message if r.message.startswith(r.status) else (
        r.status + (f" - {r.message}" if r.message else ""))
    lines = [f"results: {r.path} (saxum {r.version})", f"status: {status}"]
    lines += [f"damaged: {d}" for d in r.damage]
    sc = None
    if r.scenario_json:
        from .scenario import Scenario

        sc = Scenario.model_validate_json(r.scenario_json)
        st = sc.structure
        lines.append(f"scenario: {sc.title or '(untitled)'}; structure {st.type} "
                     + ", ".join(f"{k}={v}" for k, v in st.model_dump().items()
                                 if k != "type" and v is not None))
        lines.append(f"duration {sc.output.duration:g} s, output every {sc.output.interval:g} s,"
                     f" checkpoints every {sc.output.checkpoint_interval:g} s")
    n_bodies = len(r.body_name)
    free = int(np.sum(r.model["body_kind"] == BodyKind.FREE))
    deformable = int(np.sum(r.model["body_kind"] == BodyKind.DEFORMABLE))
    lines.append(f"model: {n_bodies} bodies ({free} free"
                 + (f", {deformable} deformable" if deformable else "")
                 + f"), dt = {r.dt:g} s, theta = {r.theta:g}")
    last = r.time[-1] if r.frame_count else float("nan")
    lines.append(f"frames: {r.frame_count} (t = 0 .. {last:g} s); checkpoints at steps "
                 f"{', '.join(str(x) for x in r.checkpoint_steps[-5:])}"
                 + (" (last 5)" if r.checkpoint_steps.size > 5 else ""))
    if s["step"].size:
        bad = s["step"][~s["converged"]]
        nlgs = (f" (tolerance {sc.solver.tolerance:g}, at most {sc.solver.max_iterations} "
                "sweeps)" if sc else "")
        lines.append(
            f"steps: {s['step'].size}; NLGS sweeps mean {s['iterations'].mean():.1f}, max "
            f"{s['iterations'].max()}; not converged at {bad.size} step(s)"
            + (f" (first: {', '.join(str(x) for x in bad[:5])})" if bad.size else "") + nlgs
            + (natural_map_note(s["natural_map"][~s["converged"]]) if "natural_map" in s
               else ""))
        if bad.size and "outcome" in s:  # (files before the outcome column: no why)
            from .steplog import why_not_converged

            lines.append("why: " + why_not_converged(
                s["step"], s["converged"], s["outcome"], s["rate"], s["error"]))
        if "solver" in s:
            from .solver import SOLVER_NAMES

            finished = np.bincount(s["solver"], minlength=len(SOLVER_NAMES))
            lines.append("steps finished by: " + ", ".join(
                f"{name} {n}" for name, n in zip(SOLVER_NAMES, finished, strict=False))
                + f"; error at the end of a step: max {s['error'].max():.3g}")
        if "bonds_lost" in s and np.isin(r.model["law_kind"], LawKind.COHESIVE).any():
            lost, damaged = s["bonds_lost"], s["damaged"]
            lines.append("cohesive joints: " + (
                bonds_note(s["step"], lost)[2:] + " over the run" if lost.any()
                else "no bond cracked") + f"; {damaged[-1]} point(s) partly damaged at the end")
        free = _moving_kind(r.model["body_kind"])
        size = float(r.body_size[free].min()) if free.any() else math.nan
        worst = float(s["max_interpenetration"].max())
        lines.append(
            f"contacts: up to {s['contacts'].max()} ({s['active_contacts'].max()} loaded); "
            f"largest interpenetration {worst:.3g} m ({100.0 * worst / size:.2g} % of the "
            f"smallest block's size); position projection used at "
            f"{int(np.count_nonzero(s['projection_iterations']))} step(s); kinetic energy at the "
            f"end {s['kinetic_energy'][-1]:.3g} {r.units['kinetic_energy']}")
    lines += _collapse_lines(r, sc.loads.ground_motion if sc else None)
    return "\n".join(lines)


_STILL_MOVING = 1e-3
"""[1/s]: a block faster than this times the smallest block's size per second is still
moving (a structure at rest: round-off)."""


def _collapse_lines(r, ground) -> list[str]:
    """When the run collapsed (saxum.collapse.find_collapse) and the mechanism then; under a
    harmonic motion with a ramp, its amplitude then (GroundMotionSpec `ground`)."""
    from .collapse import DYNAMIC_FRACTION, ONSET, _moving_kind, find_collapse
    from .mechanism import frame_mechanism

    free = _moving_kind(r.model["body_kind"])
    if r.frame_count == 0 or not free.any():
        return []
    d = r.dim
    moved = np.linalg.norm(r.body_q[:, free, :d] - r.model["body_q0"][free, :d],
                           axis=-1).max(axis=1)
    peak = int(np.argmax(moved))
    event = find_collapse(r)
    if event is None:
        lines = [f"collapse: none (at the end no free block has moved by more than "
                 f"{DYNAMIC_FRACTION:g} x the smallest block's size); largest displacement of "
                 f"a free block {moved[peak]:.3g} m at t = {r.time[peak]:.4g} s, "
                 f"{moved[-1]:.3g} m at the end"]
        size = float(r.body_size[free].min())
        speed = np.linalg.norm(r.body_v[-1][free, :d], axis=1)
        fastest = int(np.argmax(speed))
        if speed[fastest] > _STILL_MOVING * size:
            name = np.asarray(r.body_name, dtype=object)[free][fastest]
            lines.append(f"  but blocks were still moving at the end ({name!r} at "
                         f"{speed[fastest]:.3g} m/s): the run may end before a collapse; run "
                         f"it longer (output.duration) to know")
        return lines
    text = frame_mechanism(r, event.onset_frame).text().replace("\n", "\n  ")
    began = float(r.time[event.onset_frame])
    lines = [f"collapse at t = {event.time:.4g} s (frame {event.frame}): {event.block!r} moved "
             f"by more than {event.limit:.3g} m ({DYNAMIC_FRACTION:g} x the smallest block's "
             f"size) and did not come back ({event.displacement:.3g} m at the end)",
             f"mechanism at collapse (when the collapsing motion began, t = {began:.4g} s, "
             f"frame {event.onset_frame}):\n  " + text,
             f"large motion began at t = {r.time[event.large_frame]:.4g} s (frame "
             f"{event.large_frame}: a free block first moved by more than "
             f"{ONSET * event.limit:.3g} m; under shaking a time that round-off hardly moves, "
             "unlike the two above)"]
    if ground is not None and ground.pulse == "harmonic" and ground.ramp > 0.0:
        g = float(np.linalg.norm(r.model["gravity"]))

        def amplitude(t):
            return ground.scale * ground.amplitude * min(1.0, (t + ground.start) / ground.ramp)

        large = float(r.time[event.large_frame])
        lines.append(f"harmonic amplitude A min(1, t/ramp): {amplitude(large):.4g} m/s^2 "
                     f"({amplitude(large) / g:.3g} g) when large motion began, "
                     f"{amplitude(began):.4g} m/s^2 "
                     f"({amplitude(began) / g:.3g} g) when the collapsing motion began, "
                     f"{amplitude(event.time):.4g} m/s^2 ({amplitude(event.time) / g:.3g} g) "
                     "at collapse")
    lines.append(f"picture: saxum plot {r.path} --collapse")
    return lines


def _plot(args) -> None:
    from .plot import plot_frame, plot_histories
    from .results import Results

    if _is_ensemble(args.results):
        from .ensemble import read_ensemble
        from .plot_ensemble import plot_ensemble

        out = args.output or Path(args.results).with_suffix(".png")
        plot_ensemble(read_ensemble(args.results), out, edp=args.edp,
                      threshold=args.threshold, title=Path(args.results).stem)
        print(f"picture: {Path(out).resolve()}")
        return
    with Results(args.results) as r:
        if args.thrust_line and r.dim != 2:
            raise InputError(f"{args.results}: --thrust-line is drawn for 2D results (an arch "
                             "in section) and this is a 3D model: leave out --thrust-line")
        if args.histories:
            out = args.output or Path(args.results).with_suffix(".histories.png")
            plot_histories(r, out, body=args.body)
        elif args.collapse:
            from .collapse import find_collapse
            from .mechanism import frame_mechanism

            event = find_collapse(r)
            if event is None:
                raise InputError(f"{args.results}: no collapse (saxum info says why)")
            out = args.output or Path(args.results).with_suffix(".collapse.png")
            # 3D: the mechanism's sliding joints too (2D pictures show hinges and open points)
            mech = frame_mechanism(r, event.onset_frame) if r.dim == 3 else None
            plot_frame(r, event.onset_frame, out, thrust_line=args.thrust_line,
                       title=f"{Path(args.results).stem}: mechanism at collapse",
                       mechanism=mech)
        else:
            out = args.output or Path(args.results).with_suffix(".png")
            plot_frame(r, args.frame, out, thrust_line=args.thrust_line)
    print(f"picture: {Path(out).resolve()}")


def _is_ensemble(path: Path) -> bool:
    """Whether `path` is an ensemble file (saxum.ensemble) rather than a run's results."""
    import h5py

    from .ensemble import KIND

    try:
        with h5py.File(path, "r") as f:
            return f.attrs.get("kind") == KIND
    except OSError:
        return False  # (Results says what is wrong with it)


def _animate(args) -> None:
    from .plot import animate
    from .results import Results

    out = args.output or Path(args.results).with_suffix(".gif")
    with Results(args.results) as r:
        path = animate(r, out, fps=args.fps)
    print(f"animation: {Path(path).resolve()}")


def _export_vtk(args) -> None:
    from .results import Results
    from .vtk import export_vtk

    out = args.output or Path(args.results).parent
    with Results(args.results) as r:
        pvd = export_vtk(r, out)
    print(f"ParaView collection: {Path(pvd).resolve()} (open it in ParaView)")


def _view(args) -> None:
    from .errors import ResultsDamageWarning
    from .results import Results
    from .view import open_in_browser, write_view

    with warnings.catch_warnings(record=True) as caught:  # said below, and in the page
        warnings.simplefilter("always", ResultsDamageWarning)
        r = Results(args.results)
    with r:
        if r.status != "finished" or caught:
            last = f"t = {r.time[-1]:g} s" if r.frame_count else "no frame"
            why = r.message if r.message.startswith(r.status) else (
                r.status + (f" - {r.message}" if r.message else ""))
            print(f"saxum: warning: {args.results} is from a run that did not finish ({why})"
                  if r.status != "finished"
                  else f"saxum: warning: {args.results} is damaged ({'; '.join(r.damage)})",
                  file=sys.stderr)
            print(f"saxum: warning: the page shows the {r.frame_count} frame(s) it holds, up to "
                  f"{last}, and says so", file=sys.stderr)
        out = write_view(r, args.output, every=args.every, blocks=args.blocks)
    size = out.stat().st_size
    opened = "" if args.no_open else (
        ", opened in the default browser" if open_in_browser(out)
        else ": no browser could be started here; open the file in one")
    print(f"viewer: {out.resolve()} ({size / 2**20:.1f} MB){opened}")


def _import_lmgc90(args) -> None:
    from .detection import DetectionSettings
    from .lmgc90 import OVERLAP_TOLERANCE, import_lmgc90
    from .simulation import Simulation

    tolerance = args.overlap_tolerance if args.overlap_tolerance is not None else (
        OVERLAP_TOLERANCE)
    blocks = args.output.with_name(args.output.stem + ".blocks.json")
    impulses = args.output.with_name(args.output.stem + ".impulses.json")
    taken = [p for p in (args.output, blocks, impulses) if p.exists()]
    if taken and not args.overwrite:
        raise InputError(f"{taken[0]} exists; give --overwrite to replace it (and "
                         f"{blocks.name}, {impulses.name})")
    imported = import_lmgc90(args.datbox, args.impulses)
    model = imported.model()
    depth = imported.check_overlaps(model, tolerance)
    forces, extra = [], []
    if imported.impulses:  # matched as the run will: the scenario's detection settings
        sim = Simulation(model, dt=args.dt,
                         detection=DetectionSettings(initial_overlap=tolerance))
        forces, extra = imported.warm_start(sim, sim.initial_state(check_overlaps=False))
        zero = sum(e.zero for e in imported.impulses)
        print(f"{imported.impulses_file}: {len(forces)} of {len(imported.impulses)} contacts' "
              f"impulses are the first step's warm start (solver.warm_start); {zero} are 0 "
              "(open contacts: nothing to start from)")
    extra += imported.write_scenario(args.output, duration=args.duration, dt=args.dt,
                                     overlap_tolerance=tolerance, warm_start=forces)
    kinds = np.bincount(model.body_kind, minlength=3)
    print(f"{args.output}: {model.body_count} blocks ({kinds[0]} free, {kinds[1]} fixed, "
          f"{kinds[2]} driven) in {len(model.group_names)} groups, {len(model.laws)} laws, "
          f"{len(imported.no_contact)} pairs of groups without a see-table (no contact); "
          f"deepest interpenetration {depth:.3g} m (accepted up to {tolerance:g} m: "
          "detection.initial_overlap)")
    items = [*imported.untranslated, *extra]
    if items:
        print(f"not translated or approximated ({len(items)}; all are listed at the top of "
              f"{args.output}):")
        for item in items[:20]:
            print(f"  {item}")
        if len(items) > 20:
            print(f"  ... and {len(items) - 20} more")


def _export_lmgc90(args) -> None:
    from .lmgc90 import export_lmgc90
    from .scenario import load_scenario

    scenario = load_scenario(args.scenario)
    sim = scenario.build_simulation()
    folder = export_lmgc90(sim.model, args.output, precision=args.precision,
                           alert=sim.detector.alert, polyhedra=args.polyhedra)
    print(f"{folder}: {sim.model.body_count} bodies, {len(sim.model.laws)} laws "
          "(BODIES.DAT, BULK_BEHAV.DAT, TACT_BEHAV.DAT, DRV_DOF.DAT, DOF.INI, MODELS.DAT)")


def _periods(text: str) -> list[float]:
    """--periods T1,T2,...: pulse periods [s], each > 0."""
    try:
        periods = [float(p) for p in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give periods in seconds separated by "
                                         "commas, e.g. 0.5,1,2") from None
    if not all(0.0 < p < math.inf for p in periods):
        raise argparse.ArgumentTypeError(f"{text!r}: every period must be > 0 [s] and finite")
    if len(periods) > _MAX_PERIODS:
        raise argparse.ArgumentTypeError(f"{len(periods)} periods: at most {_MAX_PERIODS} (each "
                                         "is a bisection of several runs); split the list")
    return periods


def _count(limit: int, what: str):
    """An argparse type: a whole number from 1 to `limit` (`what` says why the limit)."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: give a whole number") from None
        if not 1 <= value <= limit:
            raise argparse.ArgumentTypeError(f"{text}: give a whole number from 1 to {limit} "
                                             f"({what})")
        return value
    return parse


def _demo_duration(text: str) -> float:
    """--duration of a demo [s]: > 0, at most _MAX_DEMO_DURATION."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give a time in seconds") from None
    if not 0.0 < value <= _MAX_DEMO_DURATION:
        raise argparse.ArgumentTypeError(
            f"{text}: give a time in (0, {_MAX_DEMO_DURATION:g}] s; for a longer run, copy "
            "the demo's scenario (saxum/scenarios/ in the package) and use saxum run")
    return value


def _check_output(args) -> None:
    """-o must name a file in an existing folder (export-vtk: a folder, not a file)."""
    out = getattr(args, "output", None)
    if out is None:
        return
    if args.command in ("export-vtk", "export-lmgc90"):
        if out.exists() and not out.is_dir():
            raise InputError(f"-o {out}: is a file; {args.command} writes into a folder")
    elif out.is_dir():
        example = {"run": "results.h5", "view": "run.html",
                   "import-lmgc90": "model.toml",
                   "ensemble": "ensemble.h5"}.get(args.command, "out.png")
        raise InputError(f"-o {out}: is a folder; give a file name in it, e.g. {out / example}")
    elif not out.parent.is_dir():
        raise InputError(f"-o {out}: there is no folder {out.parent}; create it first")


def _unset_option(p: argparse.ArgumentParser) -> None:
    """--unset KEY: the same list as --set, as "KEY=" (the key removed: its default applies)."""
    p.add_argument("--unset", action="append", dest="set", metavar="KEY", type=lambda k: f"{k}=",
                   help="remove a scenario key, so that its default applies (for a table such "
                        "as loads.ground_motion: none), e.g. --unset loads.ground_motion "
                        "(repeatable)")


def _scenario_options(p: argparse.ArgumentParser, set_help: str, output_help: str) -> None:
    """--set, --unset and -o of a command on a scenario file."""
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help=set_help)
    _unset_option(p)
    p.add_argument("-o", "--output", type=Path, help=output_help)


_MAX_PROCESSES = 4 * (os.cpu_count() or 1)
_MAX_PERIODS = 1000
_MAX_DEMO_DURATION = 1000.0  # [s]
_MAX_SWEEPS = 1_000_000_000


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="saxum", formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Non-Smooth Contact Dynamics of masonry structures.\n\n" + __doc__)
    parser.add_argument("--version", action="version", version=f"saxum {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("run", help="run a scenario file (TOML) to a results file (HDF5)")
    p.add_argument("scenario", type=Path, help="scenario file (see docs/scenario.md)")
    p.add_argument("-o", "--output", type=Path, help="results file (default: SCENARIO.h5)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing results file (without it, an existing file is "
                        "an error: it may hold a run that saxum resume continues)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scenario key, e.g. --set solver.dt=5e-4 (repeatable)")
    _unset_option(p)
    p.add_argument("--threads", type=int, default=None, metavar="N",
                   help="the step on N threads (0: all cores; default: all cores for "
                        "models of 4096 free blocks or more, else one, or SAXUM_THREADS); "
                        "the same results for every N: NLGS's domains, set by the model's "
                        "size or solver.domains, fix them; the same as --set "
                        "solver.threads=N)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_run)

    p = sub.add_parser("resume", help="continue a killed, interrupted or finished run from "
                                      "its last checkpoint")
    p.add_argument("results", type=Path, help="results file (HDF5) of saxum run")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_resume)

    from .demos import DEMOS

    p = sub.add_parser("demo", help="run a bundled demonstration (no file needed)")
    p.add_argument("name", choices=sorted(DEMOS), help="which demonstration")
    p.add_argument("-o", "--output", type=Path, help="picture (default: saxum-demo-NAME.png)")
    p.add_argument("--duration", type=_demo_duration, default=None,
                   help=f"simulated time [s] (default: the demo's own; at most "
                        f"{_MAX_DEMO_DURATION:g})")
    p.set_defaults(func=_demo)

    p = sub.add_parser("limit", help="limit analysis: the largest load factor that the "
                                     "joints can carry (a linear or conic programme) and the "
                                     "collapse mechanism")
    p.add_argument("scenario", type=Path, help="scenario file (see docs/scenario.md)")
    p.add_argument("--live", choices=("horizontal", "forces", "water", "settlement"),
                   default="horizontal",
                   help="the load multiplied by lambda: horizontal (an acceleration lambda g "
                        "on every free block, along the sign of loads.horizontal_acceleration, "
                        "which is taken out of the dead load; the default), forces (the "
                        "point loads) or water (the flood's pressures); or settlement (no "
                        "factor: the supports of loads.settlements move, and the state of "
                        "least power on them is found, e.g. the minimum thrust of an arch "
                        "on spreading supports)")
    p.add_argument("--friction", choices=("associative", "non-associative"),
                   default="associative",
                   help="associative (one programme; an upper estimate where joints slide) "
                        "or non-associative (Gilbert, Casapulla & Ahmed 2006: friction limits "
                        "fixed from the previous normal forces until they repeat)")
    _scenario_options(p, "override a scenario key (repeatable)",
                      "picture of the mechanism (default: SCENARIO-limit.png)")
    p.set_defaults(func=_limit)

    p = sub.add_parser("collapse", help="critical value of a scenario key (a load, a "
                                        "thickness...) by bisection, and the mechanism")
    p.add_argument("scenario", type=Path, help="scenario file (see docs/scenario.md)")
    p.add_argument("--vary", required=True, metavar="KEY",
                   help="scenario key to vary, e.g. loads.horizontal_acceleration [m/s^2] or "
                        "structure.thickness [m]")
    p.add_argument("--stands", type=float, required=True,
                   help="a value at which it stands (in the key's unit)")
    p.add_argument("--collapses", type=float, required=True,
                   help="a value at which it collapses (in the key's unit)")
    p.add_argument("--tolerance", type=float, default=0.005,
                   help="relative width of the final bracket (default 0.005)")
    p.add_argument("--duration", type=float, default=1.0,
                   help="longest trial [s] (default 1; under a ground motion or a settlement, "
                        "counted from its end)")
    p.add_argument("--fraction", type=float, default=None,
                   help="collapse: a block moved by this fraction of the smallest block's "
                        "size (default 0.01, and 0.5 under a ground motion, judged once it "
                        "has ended)")
    p.add_argument("--check-limit", action="store_true",
                   help="also find the critical value by limit analysis (static, constant "
                        "loads) and warn if it lies outside the dynamic bracket by more than "
                        "--tolerance")
    p.add_argument("--structure-ratio", action="store_true",
                   help="judge rest by the unbalanced force ratio of the structure as a "
                        "whole instead of every block's own (docs/collapse.md): hides a small "
                        "part (a parapet) that starts to fail slowly on a large structure")
    _scenario_options(p, "override another scenario key (repeatable)",
                      "results of the collapsing case (default: SCENARIO-collapse.h5; "
                      "replaced if it exists)")
    p.set_defaults(func=_collapse)

    p = sub.add_parser("collapse-curve", help="smallest pulse amplitude that collapses the "
                                              "structure, per pulse period (in parallel)")
    p.add_argument("scenario", type=Path, help="a scenario with [loads.ground_motion] pulse")
    p.add_argument("--periods", required=True, type=_periods, metavar="T1,T2,...",
                   help="pulse periods [s], comma separated")
    p.add_argument("--stands", type=float, required=True,
                   help="an amplitude [m/s^2] at which it stands for every period")
    p.add_argument("--collapses", type=float, required=True,
                   help="an amplitude [m/s^2] at which it collapses for every period")
    p.add_argument("--tolerance", type=float, default=0.01,
                   help="relative width of the final bracket (default 0.01)")
    p.add_argument("--duration", type=float, default=2.0,
                   help="longest trial after the pulse has ended [s] (default 2)")
    p.add_argument("--fraction", type=float, default=0.5,
                   help="collapse: a block moved by this fraction of the smallest block's "
                        "size once the pulse is over (default 0.5; a block that is still "
                        "rocking, with decaying energy, is not collapsed)")
    p.add_argument("--processes", default=None,
                   type=_count(_MAX_PROCESSES, "more worker processes than CPUs only share "
                                               "them"),
                   help=f"worker processes (default: one per CPU; at most {_MAX_PROCESSES})")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override another scenario key (repeatable)")
    _unset_option(p)
    p.add_argument("-o", "--output", type=Path,
                   help="picture of amplitude against period (default: SCENARIO-curve.png); "
                        "the table goes next to it as .csv")
    p.set_defaults(func=_collapse_curve)

    p = sub.add_parser("ensemble", help="a scenario through ground-motion records at many "
                                        "scales (IDA or multiple stripes) on a Dask cluster, "
                                        "and the fragility curve")
    p.add_argument("scenario", type=Path, help="scenario file; its [ensemble] table, if any, "
                                               "gives the defaults (docs/ensemble.md)")
    p.add_argument("--records", help="far-field or near-field (FEMA P695, needs saxum[records])"
                                     ", or a folder of .AT2/.csv records")
    p.add_argument("--scales", help="START:STOP:STEP (e.g. 0.1:2.0:0.1) or A,B,C: the scale "
                                    "factors (with --measure pga: PGAs [g])")
    p.add_argument("--ida", action="store_const", const=True, default=None,
                   help="incremental dynamic analysis: per record, scales up to the first "
                        "collapse, then bisection (default: every record at every scale)")
    p.add_argument("--tolerance", type=float, default=None,
                   help="IDA: relative width of the final bracket (default 0.01)")
    p.add_argument("--measure", choices=("scale", "pga"), default=None,
                   help="scale: a factor on each record (default); pga: each record scaled "
                        "to that peak ground acceleration [g]")
    p.add_argument("--after", type=float, default=None,
                   help="each run lasts its record plus this [s] (default 2)")
    p.add_argument("--blocks", metavar="NAME,...",
                   help="the blocks whose displacement, drift and rotation are the demand "
                        "(default: every free block)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="a running Dask scheduler, e.g. tcp://host:8786 (default: a local "
                        "cluster)")
    p.add_argument("--workers", default=None,
                   type=_count(_MAX_PROCESSES, "more worker processes than CPUs only share "
                                               "them"),
                   help=f"worker processes of the local cluster (default: one per CPU; at "
                        f"most {_MAX_PROCESSES})")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing ensemble file of another ensemble (the same "
                        "ensemble's file is resumed)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    _scenario_options(p, "override a scenario key (repeatable)",
                      "ensemble file (HDF5; default: SCENARIO.ensemble.h5)")
    p.set_defaults(func=_ensemble)

    p = sub.add_parser("fclib", help="FCLIB frictional-contact problems")
    fc = p.add_subparsers(dest="fclib_command", required=True, metavar="ACTION")
    q = fc.add_parser("solve", help="solve FCLIB problems (NLGS, switching to the conic fixed "
                                    "point where it stalls) and print, per problem: contacts, "
                                    "spacedim, solver, iterations, time, error")
    q.add_argument("files", type=Path, nargs="+", help="FCLIB .hdf5 files")
    q.add_argument("--tolerance", type=float, default=1e-8,
                   help="target natural-map error ||F_nat(r)||/||q|| (default 1e-8)")
    q.add_argument("--max-iterations", type=_count(_MAX_SWEEPS, "a cap of sweeps, not a "
                                                                 "target: the solve stops "
                                                                 "when converged"),
                   default=100_000, help="NLGS sweeps at most (default 100000, at most "
                                         f"{_MAX_SWEEPS})")
    q.add_argument("--relaxation", type=float, default=None,
                   help="NLGS relaxation omega in (0, 1] (default: 1, and 0.7 where the "
                        "hybrid finds NLGS stalling)")
    q.add_argument("--solver", choices=("hybrid", "nlgs", "conic", "newton"), default="hybrid",
                   help="hybrid (default: NLGS, the conic fixed point where NLGS stalls or is "
                        "too slow, then NLGS), nlgs or conic alone, or newton (Fischer-"
                        "Burmeister Newton, then NLGS where it stops short)")
    q.set_defaults(func=_fclib_solve)

    p = sub.add_parser("info", help="what a run was and what the solver did")
    p.add_argument("results", type=Path, help="results file (HDF5)")
    p.set_defaults(func=_info)

    p = sub.add_parser("plot", help="picture of an output frame, or the time histories")
    p.add_argument("results", type=Path, help="results file (HDF5)")
    p.add_argument("--frame", type=int, default=-1,
                   help="output frame, from 0 (default: the last; saxum info gives the count)")
    p.add_argument("--collapse", action="store_true",
                   help="the frame at which the collapse began, with its hinges (saxum info)")
    p.add_argument("--histories", action="store_true",
                   help="time histories (the output.histories blocks at every step, energy, "
                        "solver) instead of a frame")
    p.add_argument("--thrust-line", action="store_true",
                   help="draw the thrust line of an arch (joints' centres of pressure)")
    p.add_argument("--body", help="block for --histories (name or index; default: the one "
                                  "that moved most)")
    p.add_argument("--edp", default="peak_drift",
                   help="an ensemble's demand on its IDA curves: peak_drift (default), "
                        "peak_displacement, peak_horizontal, peak_rotation, "
                        "residual_displacement")
    p.add_argument("--threshold", type=float, default=None,
                   help="an ensemble's fragility of --edp above this (default: of collapse)")
    p.add_argument("-o", "--output", type=Path, help="PNG file (default: next to RESULTS)")
    p.set_defaults(func=_plot)

    p = sub.add_parser("animate", help="animation of the output frames (GIF, or MP4 with "
                                       "ffmpeg)")
    p.add_argument("results", type=Path, help="results file (HDF5)")
    p.add_argument("-o", "--output", type=Path, help="GIF or MP4 file (default: RESULTS.gif)")
    p.add_argument("--fps", type=_count(1000, "frames per second of a film"), default=20,
                   help="animation frames per second (default 20; one per output frame)")
    p.set_defaults(func=_animate)

    p = sub.add_parser("export-vtk", help="ParaView time series (.pvd + .vtu) of the frames")
    p.add_argument("results", type=Path, help="results file (HDF5)")
    p.add_argument("-o", "--output", type=Path,
                   help="folder for NAME.pvd and NAME/*.vtu (default: the results' folder)")
    p.set_defaults(func=_export_vtk)

    p = sub.add_parser("view", help="interactive 3D viewer of a run in one HTML file (no server, "
                                    "works offline), opened in the default browser")
    p.add_argument("results", type=Path, help="results file (HDF5)")
    p.add_argument("-o", "--output", type=Path, help="HTML file (default: RESULTS.html)")
    p.add_argument("--no-open", action="store_true", help="write the file, do not open it")
    p.add_argument("--every", type=_count(10**9, "a stride of output frames"), default=1,
                   help="every N-th output frame and the last (default 1: all): for a long run")
    p.add_argument("--blocks", metavar="PATTERN",
                   help="only the blocks whose name or group matches this glob (e.g. "
                        "'parapet*'), and the supports: for a large model")
    p.set_defaults(func=_view)

    p = sub.add_parser("import-lmgc90", help="translate an LMGC90 DATBOX folder into a "
                                             "scenario (docs/lmgc90.md)")
    p.add_argument("datbox", type=Path, help="the DATBOX folder (BODIES.DAT, TACT_BEHAV.DAT...)")
    p.add_argument("-o", "--output", type=Path, required=True,
                   help="scenario file to write (TOML; its blocks go to STEM.blocks.json)")
    p.add_argument("--duration", type=float, default=1.0,
                   help="output.duration [s] (default 1; also the time of the drives)")
    p.add_argument("--dt", type=float, default=1e-3, help="solver.dt [s] (default 1e-3)")
    p.add_argument("--overlap-tolerance", type=float, default=None, metavar="D",
                   help="deepest interpenetration accepted in the imported state [m] "
                        "(default 1e-5: LMGC90 states carry micrometre ones)")
    p.add_argument("--impulses", type=Path, default=None, metavar="FILE",
                   help="a Vloc_Rloc file whose impulses start the first step (default: "
                        "DATBOX/Vloc_Rloc.INI, else OUTBOX/Vloc_Rloc.OUT beside it, if any)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing scenario and its blocks file")
    p.set_defaults(func=_import_lmgc90)

    p = sub.add_parser("export-lmgc90", help="write a scenario's model as an LMGC90 DATBOX")
    p.add_argument("scenario", type=Path, help="scenario file (see docs/scenario.md)")
    p.add_argument("-o", "--output", type=Path, required=True, help="DATBOX folder to write")
    p.add_argument("--precision", choices=("lmgc90", "full"), default="lmgc90",
                   help="lmgc90: LMGC90's fixed columns, 7 digits (default); full: 17 digits, "
                        "exact for saxum import-lmgc90")
    p.add_argument("--polyhedra", choices=("POLYR", "POLYF"), default="POLYR",
                   help="LMGC90 contactor of 3D blocks: POLYR (default) or POLYF (a patch "
                        "per face)")
    p.set_defaults(func=_export_lmgc90)
    return parser


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings (a step where NLGS did not converge...) as one line, without Python's
    file and source line."""
    print(f"saxum: warning: {message}", file=sys.stderr)


_CTRL_C_AGAIN = 0.05
"""[s] after a dropped Ctrl-C (_ctrl_c_not_dropped) at which it is sent again."""


@contextlib.contextmanager
def _ctrl_c_not_dropped() -> Iterator[None]:
    """A Ctrl-C whose KeyboardInterrupt Python drops is sent again until one is not dropped.

    While numba compiles (a kernel on its first call: those that saxum.precompile does not
    list, and 3D ones), Python often runs its SIGINT handler inside llvmlite's ctypes callback,
    where a KeyboardInterrupt is printed ("Exception ignored on calling ctypes callback", with
    a traceback) and dropped: the command went on. Here such a one is not printed, and SIGINT
    is sent again _CTRL_C_AGAIN later, as a user would press Ctrl-C again; a run's own handler
    (saxum.runner) then stops it after the step, Python's default one raises it where it
    lands."""
    previous = sys.unraisablehook
    timers: list[threading.Timer] = []

    def dropped(unraisable) -> None:
        if not isinstance(unraisable.exc_value, KeyboardInterrupt):
            previous(unraisable)
            return
        again = threading.Timer(_CTRL_C_AGAIN, os.kill, (os.getpid(), signal.SIGINT))
        again.daemon = True
        timers.append(again)
        again.start()

    sys.unraisablehook = dropped
    try:
        yield
    finally:
        sys.unraisablehook = previous
        for again in timers:
            again.cancel()


@contextlib.contextmanager
def _notes_on_stderr():
    """saxum's own log records (logger "saxum", INFO and up: what a run leaves out and why,
    as saxum.simulation's for deformable blocks) printed as "saxum: note: ..." lines."""
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("saxum: note: %(message)s"))
    logger = logging.getLogger("saxum")
    level = logger.level
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    try:
        yield
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)


def main(argv: list[str] | None = None) -> int:
    try:
        args = _parser().parse_args(argv)
        _check_output(args)
        with warnings.catch_warnings(), _ctrl_c_not_dropped(), _notes_on_stderr():
            warnings.showwarning = _show_warning
            args.func(args)
    except KeyboardInterrupt:  # Ctrl-C outside a run's own handling (start-up, a picture)
        print("saxum: interrupted", file=sys.stderr)
        return 130
    except InputError as err:
        print(f"saxum: bad input: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into a program that stopped reading (| head)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no error at exit
        return 0
    except ResultsWriteError as err:
        print(f"saxum: failed: {err}", file=sys.stderr)
        return 1
    except Exception as err:  # noqa: BLE001 - any failure is reported as exit code 1
        print(f"saxum: failed: {type(err).__name__}: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
