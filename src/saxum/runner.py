"""Running a scenario to a results file: output frames, checkpoints, progress, Ctrl-C, resume.

The run writes the initial state as frame 0 and a checkpoint at step 0, then a frame every
`output.interval` and a checkpoint every `output.checkpoint_interval` (both rounded to whole
steps), and both at the end. Ctrl-C (SIGINT) stops after the current step: the state is written
as a frame and a checkpoint, the file is marked "interrupted", and `saxum resume FILE`
continues. A resumed run writes exactly what the same run made in one go writes (the checkpoint
holds the state, the contacts with their impulses, the broad phase's pair list and the
solver's state: ContactSolver.checkpoint).
"""

from __future__ import annotations

import math
import signal
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from ._version import __version__
from .errors import InputError, ResultsDamageWarning, ResultsWriteError, SimulationError
from .precompile import precompile
from .results import Results, ResultsWriter
from .scenario import Scenario
from .warmstart import apply_warm_start, read_warm_start

__all__ = ["RunSummary", "resume_run", "run_scenario"]


@dataclass(frozen=True)
class RunSummary:
    """What a run did: results path, status ("finished" or "interrupted"), the step reached,
    the simulated time reached [s], steps that did not converge, wall time [s], and the step
    this call started from (0, or the checkpoint of a resumed run)."""

    path: Path
    status: str
    steps: int
    time: float
    non_converged: int
    wall_time: float
    first_step: int = 0


def run_scenario(scenario: Scenario, output: str | Path, *, quiet: bool = False,
                 scenario_text: str = "", overwrite: bool = False) -> RunSummary:
    """Run `scenario` from t = 0, writing results to `output`. An existing `output` is an
    InputError unless `overwrite` (it may hold a run that saxum resume would continue); so is
    an `output` that another process is writing."""
    precompile(scenario.structure.dim)
    sim = scenario.build_simulation()
    state = sim.initial_state()
    if scenario.solver.warm_start is not None:
        _warm_start(sim, state, scenario.solver.warm_start)
    writer = ResultsWriter(output, sim.model, dt=scenario.solver.dt,
                           theta=sim.integrator.theta, scenario=scenario_text,
                           scenario_json=scenario.model_dump_json(), version=__version__,
                           histories=scenario.output.history_bodies(sim.model),
                           ground=scenario.loads.ground_motion is not None,
                           overwrite=overwrite)
    return _advance(scenario, sim, state, writer, quiet, initial=True)


def _warm_start(sim, state, path: str) -> None:
    """The first step's warm start from the contact forces of `path` (saxum.warmstart); a
    force that matches no contact is an InputError: the file is not of this model."""
    unmatched = apply_warm_start(sim, state, read_warm_start(path))
    if unmatched:
        lines = [f"  {f}: {why}" for f, why in unmatched[:10]]
        more = [f"  ... and {len(unmatched) - 10} more"] if len(unmatched) > 10 else []
        raise InputError(f"solver.warm_start = {path!r}: {len(unmatched)} contact force(s) "
                         "match no contact of the model at the start (was the model "
                         "changed? remove them or the key):\n" + "\n".join(lines + more))


def resume_run(path: str | Path, *, quiet: bool = False) -> RunSummary:
    """Continue the run of results file `path` from its last intact checkpoint (saxum.results:
    a damaged file's damaged checkpoints are not used) to its duration."""
    with warnings.catch_warnings():  # ResultsWriter.resume says what was lost
        warnings.simplefilter("ignore", ResultsDamageWarning)
        with Results(path) as res:
            if not res.scenario_json:
                raise InputError(f"{path}: the run was not made from a scenario; it cannot be "
                                 "resumed (its model is not stored in a rebuildable form)")
            scenario = Scenario.model_validate_json(res.scenario_json)
            k = res.resumable - 1
            saved = res.checkpoint(k) if k >= 0 else None
    writer, _ = ResultsWriter.resume(
        path, k, frame_every=_every(scenario.output.interval, scenario.solver.dt))
    try:
        precompile(scenario.structure.dim)
        sim = scenario.build_simulation()
        state = sim.restore(saved)
    except BaseException:
        writer.close()
        raise
    return _advance(scenario, sim, state, writer, quiet)


def _every(interval: float, dt: float) -> int:
    return max(1, round(interval / dt))


def _advance(scenario, sim, state, writer: ResultsWriter, quiet: bool,
             initial: bool = False) -> RunSummary:
    """Step from `state` to the scenario's duration, writing frames, checkpoints and the
    status; `initial`: write the initial state first (frame 0, checkpoint at step 0)."""
    out = scenario.output
    dt = scenario.solver.dt
    total = round(out.duration / dt)
    frame_every = _every(out.interval, dt)
    checkpoint_every = _every(out.checkpoint_interval, dt)
    spec = scenario.loads.ground_motion
    ground = (spec.motion(scenario.structure.dim).acceleration_at if spec is not None
              else None)
    stop = {"now": False}

    def on_sigint(signum, frame):
        stop["now"] = True

    previous = signal.signal(signal.SIGINT, on_sigint)
    start = time.perf_counter()
    first = state.step
    bad = 0
    status = "finished"
    bar = tqdm(total=total, initial=state.step, disable=quiet, unit="step", dynamic_ncols=True,
               desc="saxum", leave=True)
    try:
        if initial:
            writer.write_frame(state)
            writer.write_checkpoint(state, sim.detector, sim.solver)
        while state.step < total:
            report = sim.step(state)
            writer.log_step(report)
            writer.log_history(state, ground(state.time) if ground else None)
            bad += not report.converged
            if state.step % frame_every == 0 and state.step < total:
                writer.write_frame(state)
            if state.step % checkpoint_every == 0 and state.step < total:
                writer.write_checkpoint(state, sim.detector, sim.solver)
            bar.update(1)
            if state.step % 20 == 0:
                bar.set_postfix_str(f"t={state.time:.3f} s NLGS={report.iterations}"
                                    + (f" not converged: {bad}" if bad else ""), refresh=False)
            if stop["now"]:
                status = "interrupted"
                break
        # the last state, unless the loop (or the start of the run) has just written it
        if state.step > first and (state.step % frame_every or state.step == total):
            writer.write_frame(state)
        if state.step > first and (state.step % checkpoint_every or state.step == total):
            writer.write_checkpoint(state, sim.detector, sim.solver)
        if status == "finished":
            writer.set_status(1, f"finished at t = {state.time:g} s")
        else:
            writer.set_status(2, f"interrupted at step {state.step} (t = {state.time:g} s)")
    except ResultsWriteError:
        raise
    except Exception as err:
        # any failure (SimulationError, or a bug) is said in the file rather than "running"
        writer.set_status(3, str(err) if isinstance(err, SimulationError)
                          else f"failed: {type(err).__name__}: {err}")
        raise
    finally:
        bar.close()
        signal.signal(signal.SIGINT, previous)
        writer.close()
    return RunSummary(Path(writer.path), status, state.step, state.time, bad,
                      time.perf_counter() - start, first)


def describe(summary: RunSummary) -> str:
    """A line for the user: what happened and where the results are."""
    done = summary.steps - summary.first_step
    if done == 0 and summary.status == "finished":
        return (f"already finished at t = {summary.time:g} s (step {summary.steps}): nothing "
                f"to resume; results: {summary.path}")
    rate = done / summary.wall_time if summary.wall_time > 0 else math.inf
    resumed = f" (from step {summary.first_step})" if summary.first_step else ""
    text = (f"{summary.status}: {summary.steps} steps{resumed}, t = {summary.time:g} s, "
            f"{summary.wall_time:.1f} s wall ({rate:.0f} steps/s); results: {summary.path}")
    if summary.non_converged:
        text += (f"; the contact solver did not converge at {summary.non_converged} step(s)"
                 " (saxum info)")
    if summary.status == "interrupted":
        text += f"\nresume with: saxum resume {summary.path}"
    return text
