"""Benchmark of saxum ensemble: the 15-voussoir arch of examples/shake_table_arch.toml through
N FEMA P695 far-field components x M scale factors (multiple stripes), on a local Dask
cluster of 1 and of 2 worker processes, back to back.

    python benchmarks/ensemble.py [--records 4] [--scales 0.5,1,1.5] [--end 5 | --whole]
                                  [--workers 1,2] [--json benchmarks/results/ensemble.json]

Each record is cut to its first `--end` seconds (loads.ground_motion.end), or kept whole
(`--whole`: 20 to 100 s), and each run lasts that plus 1 s (or until the arch collapses).
Prints and writes as JSON, per worker count: the wall time of the ensemble (from the
cluster's start to the last row written), runs per second, the CPU time (user + sys) of the
client and of the worker processes (and the part of it spent starting the cluster), the
collapses found, the steps run and the CPU time per step (after the cluster's start: each
run's own costs, building its model and its demand, included); and the speed-up from the
first worker count to the others. Then the time that the whole far-field set (44
components, whole records) at `--estimate` scales would take on as many idle cores as the
largest worker count, at the CPU per step measured here: an upper bound, every run lasting
its record plus 1 s (a collapse ends a run early). The kernels are compiled before (a
warm-up run in this process, which fills numba's cache for the workers).

    python benchmarks/ensemble.py --stages [--records 1] [--scales 0.4] [--end 8 | --whole]

instead runs the first record at the first scale once in this process (after a warm-up run)
and prints the CPU time (of the thread that steps) per step of the run, and where it
goes in a second run timed by stages: the run
(ensemble._advance: the steps, the output frames, the demand), the steps, and the stages
of a step, timed by wrapping methods of the run's Simulation and the NLGS sweep kernel
(nlgs_2d; the calls' dispatch included). The contact solve includes the NLGS sweeps, and
the projection's solves are counted in it and in the projection. Then the run's results,
every digit (the row's demand: two versions of saxum that step alike print the same).
"""

import argparse
import functools
import json
import os
import platform
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import psutil

from saxum import ensemble as ens
from saxum.records import fema_p695_records
from saxum.scenario import load_scenario
from saxum.solver import nlgs

STAGES = {"forces": (None, "_step_force"), "detection": ("detector", "detect"),
          "assembly": ("problem", "assemble"), "contact solve": ("solver", "solve"),
          "end gaps": ("problem", "end_gaps"), "projection": ("projection", "project"),
          "step log": ("log", "append")}
"""The stages timed by --stages: (attribute of the Simulation or None, method)."""

ARCH = Path(__file__).resolve().parents[1] / "examples" / "shake_table_arch.toml"


def _cpu(process: psutil.Process) -> float:
    """User + sys CPU time [s] of a process and of its living descendants."""
    total = 0.0
    for p in [process, *process.children(recursive=True)]:
        try:
            t = p.cpu_times()
            total += t.user + t.system
        except psutil.NoSuchProcess:
            pass
    return total


def measure(scenario, records, workers: int, folder: Path) -> dict:
    me = psutil.Process()
    cpu0 = _cpu(me)
    start = time.perf_counter()
    client = ens.connect(workers=workers)
    started = _cpu(me) - cpu0  # (the cluster's start: its processes import saxum and dask)
    try:
        summary = ens.run_ensemble(scenario, folder / f"arch-{workers}.h5", records=records,
                                   client=client, quiet=True, overwrite=True)
        wall = time.perf_counter() - start
        cpu = _cpu(me) - cpu0  # (before the workers end: their time is counted while alive)
    finally:
        cluster = client.cluster
        client.close()
        cluster.close()
    runs = ens.read_ensemble(summary.path).runs
    steps = int(runs["steps"].sum())
    return {"workers": workers, "runs": summary.runs, "failed": summary.failed,
            "wall_s": round(wall, 2), "runs_per_s": round(summary.runs / wall, 3),
            "cpu_s": round(cpu, 2), "collapses": int((runs["collapsed"] == 1).sum()),
            "start_cpu_s": round(started, 2), "steps": steps,
            "cpu_ms_per_step": round(1e3 * (cpu - started) / steps, 4)}


def _timed(f, times: dict, name: str):
    """f, adding the CPU time of this thread [s] spent in it to times[name]."""
    @functools.wraps(f)
    def timed(*args, **kwargs):
        start = time.thread_time()
        try:
            return f(*args, **kwargs)
        finally:
            times[name] += time.thread_time() - start
    return timed


def stages(scenario, record, folder: Path, timers: bool = True) -> tuple[dict, dict]:
    """One run of `record` in this process: its row (saxum.ensemble.COLUMNS) and the CPU time
    [s] of the run and, with `timers`, of its steps and of their stages (module doc)."""
    times = defaultdict(float)
    rows = []
    advance, sweep = ens._advance, nlgs.nlgs_2d

    def run(sim, model, *args):
        if timers:
            for name, (owner, method) in STAGES.items():
                obj = sim if owner is None else getattr(sim, owner)
                setattr(obj, method, _timed(getattr(obj, method), times, name))
            sim.step = _timed(sim.step, times, "steps")
        rows.append(_timed(advance, times, "run")(sim, model, *args))
        return rows[-1]

    ens._advance = run
    if timers:
        nlgs.nlgs_2d = _timed(sweep, times, "NLGS sweeps (nlgs_2d)")
    try:
        ens.run_ensemble(scenario, folder / "stages.h5", records=[record], workers=1,
                         processes=False, quiet=True, overwrite=True)
    finally:
        ens._advance, nlgs.nlgs_2d = advance, sweep
    return rows[0], dict(times)


def whole_set_steps(scenario, after: float) -> int:
    """Time steps of the whole far-field set at one scale, each run its record plus `after`
    [s] (none ended by a collapse)."""
    dt = scenario.solver.dt
    return sum(round((float(r.motion.time[-1]) + after) / dt)
               for r in ens.ensemble_records("far-field"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--records", type=int, default=4)
    parser.add_argument("--scales", default="0.5,1,1.5")
    parser.add_argument("--end", type=float, default=5.0)
    parser.add_argument("--whole", action="store_true", help="whole records (no --end)")
    parser.add_argument("--workers", default="1,2")
    parser.add_argument("--estimate", type=int, default=10,
                        help="scales of the whole far-field set to estimate the time of")
    parser.add_argument("--stages", action="store_true",
                        help="one run in this process: where its CPU time goes")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    cut = [] if args.whole else [f"loads.ground_motion.end={args.end!r}"]
    scenario = load_scenario(ARCH, [*cut, 'ensemble.records="far-field"',
                                    f'ensemble.scales="{args.scales}"', "ensemble.after=1.0"])
    infos = fema_p695_records("far-field")[: args.records]
    every = ens.ensemble_records("far-field")
    records = [r for r in every if r.source in {f"{i.set} {i.id}{i.component}"
                                                for i in infos}]
    if args.stages:
        one = scenario.model_copy(update={"ensemble": scenario.ensemble.model_copy(
            update={"scales": scenario.ensemble.scales[:1]})})
        with tempfile.TemporaryDirectory() as tmp:
            stages(one, records[0], Path(tmp))  # (warm-up: compiles or loads the kernels)
            row, bare = stages(one, records[0], Path(tmp), timers=False)
            _, times = stages(one, records[0], Path(tmp))
        steps = row["steps"]
        print(f"{records[0].name} x {one.ensemble.scales[0]:g}: {steps} steps; the run "
              f"without the timers: {1e6 * bare['run'] / steps:.1f} us of CPU per step; with "
              "them, per step:")
        for name, seconds in sorted(times.items(), key=lambda item: -item[1]):
            print(f"  {name:22s} {1e6 * seconds / steps:7.1f} us")
        # (to compare two versions bit for bit: every digit of the run's results)
        print("row:", {k: row[k] for k in ("collapsed", "collapse_time", "peak_displacement",
                                           "peak_rotation", "residual_displacement", "block",
                                           "mechanism", "non_converged", "steps")})
        return
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        # warm-up: compile the kernels here (numba's cache, which the workers load)
        warm = scenario.model_copy(update={"ensemble": scenario.ensemble.model_copy(
            update={"scales": [min(scenario.ensemble.scales)]})})
        ens.run_ensemble(warm, folder / "warm.h5", records=records[:1], workers=1,
                         processes=False, quiet=True)
        rows = [measure(scenario, records, int(w), folder) for w in args.workers.split(",")]
    base = rows[0]["wall_s"]
    for row in rows:
        row["speed_up"] = round(base / row["wall_s"], 2)
        print(f"{row['workers']} worker(s): {row['runs']} runs ({row['collapses']} collapsed, "
              f"{row['failed']} failed) in {row['wall_s']} s wall, {row['runs_per_s']} runs/s, "
              f"CPU {row['cpu_s']} s, of which {row['start_cpu_s']} s the cluster's start; "
              f"{row['steps']} steps, {row['cpu_ms_per_step']} ms of CPU per step after the "
              f"start; speed-up {row['speed_up']}x")
    per_step = min(row["cpu_ms_per_step"] for row in rows) * 1e-3
    cores = max(row["workers"] for row in rows)
    steps = whole_set_steps(scenario, scenario.ensemble.after) * args.estimate
    estimate = steps * per_step / cores
    print(f"whole far-field set x {args.estimate} scales: at most {steps} steps, "
          f"{steps * per_step / 60:.1f} min of CPU at {1e3 * per_step:.4f} ms per step, "
          f"{estimate / 60:.1f} min on {cores} idle cores")
    out = {"records": args.records, "scales": args.scales,
           "end_s": None if args.whole else args.end,
           "machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
           "load_average": os.getloadavg(), "rows": rows,
           "estimate": {"scales": args.estimate, "steps": steps, "cores": cores,
                        "minutes": round(estimate / 60, 1)}}
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
