"""Benchmark: the 512-brick running-bond wall of benchmarks/wall.py on a shaking base, saxum vs
pymunk (its defaults, and 100 iterations), with the wall at rest in the same run.

Cases (dt 1e-3 s, wall 25 courses x 20 bricks 0.25 x 0.065 m, 1800 kg/m^3, mu 0.6 everywhere,
on a fixed ground): base acceleration a_g(t) = A sin(2 pi f t), f = 2 Hz, for --duration
seconds (4 cycles in 2 s), A = 0 (the wall at rest), 0.3 g (the wall follows the base: nothing
slides, mu g = 0.6 g) and 0.7 g (the wall slides on its base). The base motion acts as the
inertial force -m a_g of the ground's frame (saxum.ground.GroundMotion.inertial_load, with its
exact mean over each step; in pymunk the same mean, (v_g(t1) - v_g(t0)) / h, as a horizontal
gravity set before each step), so positions are relative to the base.

Per case and engine: time per step (mean, median; the first step apart; and the CPU time of
the stepping thread per step, mean, which a loaded machine changes less), saxum's NLGS sweeps
per step and steps at the sweep cap, rest solutions looked for and found, the CPU time spent
looking for them [s] and their factorizations (first step included), the final
displacement relative to the base (largest horizontal displacement of any brick, and the mean
over the bottom course), the largest rotation. Every case runs in its own subprocess, the
engines interleaved --repeats times (the median run by mean time per step is reported): on a
shared machine only ratios measured in one run mean anything. --main PATH also runs saxum from
another source tree (e.g. /work/main/src, PYTHONPATH) in the same interleaved loop. --solvers
nlgs,hybrid runs saxum with each (saxum.NLGS, saxum.Hybrid), --tolerance 1e-6,1e-7 each
solver with each tolerance (and --refine 0,10 with each
refinement, NLGS.refine); saxum's displacements are also sampled every 0.025 s (the JSON's
"history"), and its sweeps and convergence are kept per step.

    python benchmarks/shaken_wall.py                            # 0, 0.3 g, 2 s, 3 repeats
    python benchmarks/shaken_wall.py --amplitudes 0,0.3,0.7 --repeats 1
    python benchmarks/shaken_wall.py --main /work/main/src --amplitudes 0,0.3
    python benchmarks/shaken_wall.py --amplitudes 0,0.7 --duration 0.5 --solvers nlgs,hybrid
    python benchmarks/shaken_wall.py --amplitudes 0,0.7 --duration 0.5 --tolerance 1e-6,1e-7,1e-8
    python benchmarks/shaken_wall.py --amplitudes 0,0.3,0.7 --duration 0.5 --skip-pymunk \
        --refine 0,10 --main /work/main/src
    python benchmarks/shaken_wall.py --amplitudes 0,0.3,0.7 --duration 0.5 --skip-pymunk \
        --solvers nlgs,nlgs:quad --tolerance 1e-6,1e-4
"""

import argparse
import datetime
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from wall import (  # noqa: E402  (benchmarks/ is not a package)
    BRICK_HEIGHT,
    BRICK_LENGTH,
    DENSITY,
    FRICTION,
    GRAVITY,
    SMALL,
    _pymunk_wall,
    _stats,
    machine_info,
)

DEFAULT_JSON = HERE / "results" / "shaken_wall.json"
FREQUENCY = 2.0  # Hz
SAMPLE = 0.025  # [s] between two samples of saxum's displacement history


def _motion(amplitude_g: float, duration: float):
    from saxum.ground import harmonic

    return harmonic(amplitude_g * GRAVITY, 1.0 / FREQUENCY, duration * FREQUENCY)


def worker_saxum(amplitude_g: float, duration: float, dt: float, solver_name: str = "nlgs",
                 tolerance: float = 1e-6, refine: float | None = None) -> dict:
    import dataclasses

    import numpy as np

    import saxum as sx
    from saxum.structures import running_bond_wall

    model = running_bond_wall(courses=SMALL[0], bricks=SMALL[1], brick_length=BRICK_LENGTH,
                              brick_height=BRICK_HEIGHT, density=DENSITY, friction=FRICTION)
    if amplitude_g > 0.0:
        load = _motion(amplitude_g, duration).inertial_load()
        model = dataclasses.replace(model, accelerations=(load,))
    # compile (or load) the kernels on the same model, first steps of a separate simulation
    warm = sx.Simulation(model, dt=dt)
    state = warm.initial_state()
    for _ in range(3):
        warm.step(state)
    kind, _, criterion = solver_name.partition(":")  # "nlgs:quad": NLGS(criterion="quad")
    solver = {"nlgs": sx.NLGS, "hybrid": sx.Hybrid}[kind](
        tolerance=tolerance, **({"criterion": criterion} if criterion else {}),
        **({"refine": refine} if refine is not None else {}))
    rest = _time_rest_solutions()
    sim = sx.Simulation(model, dt=dt, solver=solver)
    state = sim.initial_state()
    q0 = state.body_q.copy()
    steps = round(duration / dt)
    times = np.empty(steps)
    free = model.body_kind == sx.BodyKind.FREE
    bottom = np.abs(q0[free, 1] - 0.5 * BRICK_HEIGHT) < 1e-9
    every = max(round(SAMPLE / dt), 1)
    history = []  # (t [s], bottom course's mean, largest |dx| [m]) every SAMPLE seconds
    cpu = np.empty(steps)
    for k in range(steps):
        s0, c0 = time.perf_counter(), time.thread_time()
        sim.step(state)
        times[k], cpu[k] = time.perf_counter() - s0, time.thread_time() - c0
        if (k + 1) % every == 0:
            dx = state.body_q[free, 0] - q0[free, 0]
            history.append((state.time, float(dx[bottom].mean()), float(np.abs(dx).max())))
    log = sim.log
    dx = state.body_q[free, 0] - q0[free, 0]
    return {
        "saxum": sx.__file__,
        "solver": solver_name,
        "tolerance": tolerance,
        "refine": getattr(solver, "refine", None),
        "steps": steps,
        "step_time_s": _stats(times[1:].tolist()),
        "step_cpu_s": _stats(cpu[1:].tolist()),
        "first_step_s": float(times[0]),
        "sweeps": _stats(log.iterations.tolist()),
        "sweeps_per_step": log.iterations.tolist(),
        "converged_per_step": log.converged.tolist(),
        "steps_at_cap": int((log.iterations >= solver.max_iterations).sum()),
        "not_converged": int((~log.converged).sum()),
        "rest_attempts": getattr(solver, "rest_attempts", None),
        "rest_solutions": getattr(solver, "rest_solutions", None),
        "rest_cpu_s": rest["cpu"],
        "factorizations": rest["factorizations"],
        "finished_by": {name: int((log.solver == k).sum())
                        for k, name in enumerate(sx.solver.SOLVER_NAMES)},
        "largest_error": float(log.error.max()),
        "outcomes": {name: int((log.outcome == k).sum())
                     for k, name in enumerate(getattr(sx, "STEP_OUTCOMES", ()))},
        "why": log.why() if hasattr(log, "why") else None,
        "history": history,
        "largest_displacement_m": float(np.abs(dx).max()),
        "bottom_course_displacement_m": float(dx[bottom].mean()),
        "top_displacement_m": float(dx[np.argmax(q0[free, 1])]),
        "largest_rotation_rad": float(np.abs(state.body_q[free, 2] - q0[free, 2]).max()),
    }


def _time_rest_solutions() -> dict:
    """Time the rest solutions that NLGS looks for (CPU time of this thread, wrapping
    saxum.solver.nlgs.rest_solution) and count their factorizations (equilibrium._factorize),
    summed into the returned dict, whichever saxum runs."""
    from saxum.solver import equilibrium, nlgs

    totals = {"cpu": 0.0, "factorizations": 0}
    rest_solution, factorize = nlgs.rest_solution, equilibrium._factorize

    def timed(*args, **kwargs):
        start = time.thread_time()
        try:
            return rest_solution(*args, **kwargs)
        finally:
            totals["cpu"] += time.thread_time() - start

    def counted(*args):
        totals["factorizations"] += 1
        return factorize(*args)

    nlgs.rest_solution, equilibrium._factorize = timed, counted
    return totals


def worker_pymunk(amplitude_g: float, duration: float, dt: float, iterations: int | None) -> dict:
    import numpy as np
    import pymunk

    space, bodies = _pymunk_wall(pymunk, *SMALL)
    if iterations is not None:
        space.iterations = iterations
    motion = _motion(amplitude_g, duration) if amplitude_g > 0.0 else None
    p0 = np.array([tuple(b.position) for b in bodies])
    a0 = np.array([b.angle for b in bodies])
    steps = round(duration / dt)
    times = np.empty(steps)
    cpu = np.empty(steps)
    for k in range(steps):
        s0, c0 = time.perf_counter(), time.thread_time()
        if motion is not None:  # the ground frame's inertial force, mean over the step
            dv = motion.velocity_at((k + 1) * dt)[0] - motion.velocity_at(k * dt)[0]
            space.gravity = (-dv / dt, -GRAVITY)
        space.step(dt)
        times[k], cpu[k] = time.perf_counter() - s0, time.thread_time() - c0
    p = np.array([tuple(b.position) for b in bodies])
    dx = p[:, 0] - p0[:, 0]
    bottom = np.abs(p0[:, 1] - 0.5 * BRICK_HEIGHT) < 1e-9
    return {
        "pymunk": pymunk.version,
        "iterations": space.iterations,
        "steps": steps,
        "step_time_s": _stats(times[1:].tolist()),
        "step_cpu_s": _stats(cpu[1:].tolist()),
        "largest_displacement_m": float(np.abs(dx).max()),
        "bottom_course_displacement_m": float(dx[bottom].mean()),
        "top_displacement_m": float(dx[np.argmax(p0[:, 1])]),
        "largest_rotation_rad": float(np.abs(np.array([b.angle for b in bodies]) - a0).max()),
    }


WORKERS = {"saxum": worker_saxum, "pymunk": worker_pymunk}


def _spawn(name: str, args: list, src: str | None) -> dict:
    """WORKERS[name](*args) in a fresh interpreter (saxum from `src` if given)."""
    env = dict(os.environ)
    if src is not None:
        env["PYTHONPATH"] = src
    with tempfile.NamedTemporaryFile("r", suffix=".json", delete=False) as f:
        out = f.name
    try:
        cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", name,
               "--worker-args", json.dumps(args), "--worker-out", out]
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if proc.returncode != 0:
            sys.stderr.write(proc.stdout + proc.stderr)
            raise RuntimeError(f"worker {name} {args} failed ({proc.returncode})")
        with open(out) as f:
            return json.load(f)
    finally:
        os.unlink(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--amplitudes", default="0,0.3",
                        help="base accelerations A / g, comma-separated (0: at rest)")
    parser.add_argument("--duration", type=float, default=2.0, help="[s] (default 2)")
    parser.add_argument("--dt", type=float, default=1e-3, help="[s] (default 1e-3)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--main", default=None,
                        help="another saxum source tree to run alongside (PYTHONPATH)")
    parser.add_argument("--solvers", default="nlgs",
                        help="saxum's solvers, comma-separated: nlgs, hybrid, nlgs:CRITERION "
                             "(NLGS with LMGC90's quad, maxm or qm/16; default nlgs)")
    parser.add_argument("--tolerance", default="1e-6",
                        help="saxum's solver tolerances, comma-separated: each solver runs "
                             "with each (engine name @tolerance where more than one; "
                             "default 1e-6)")
    parser.add_argument("--refine", default=None,
                        help="saxum's solver refine values (NLGS.refine), comma-separated: "
                             "each solver runs with each (engine name /rREFINE where more "
                             "than one; default: the solver's)")
    parser.add_argument("--skip-pymunk", action="store_true")
    parser.add_argument("--json", type=Path, default=DEFAULT_JSON)
    parser.add_argument("--worker", choices=sorted(WORKERS), help=argparse.SUPPRESS)
    parser.add_argument("--worker-args", default="[]", help=argparse.SUPPRESS)
    parser.add_argument("--worker-out", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        result = WORKERS[args.worker](*json.loads(args.worker_args))
        with open(args.worker_out, "w") as f:
            json.dump(result, f)
        return 0

    amplitudes = [float(a) for a in args.amplitudes.split(",")]
    solvers = args.solvers.split(",")
    tolerances = [float(t) for t in args.tolerance.split(",")]
    refines = [None] if args.refine is None else [float(r) for r in args.refine.split(",")]

    def named(base, s, tol, refine):
        name = base if s == "nlgs" else f"{base}-{s}"
        name = name if len(tolerances) == 1 else f"{name}@{tol:g}"
        return name if len(refines) == 1 else f"{name}/r{refine:g}"

    variants = [(s, t, r) for s in solvers for t in tolerances for r in refines]
    engines = [(named("saxum", *v), (None, *v)) for v in variants]
    if args.main:
        engines += [(named("saxum-main", *v), (args.main, *v)) for v in variants]
    if not args.skip_pymunk:
        engines += [("pymunk", None), ("pymunk-100", 100)]
    runs = {(a, e): [] for a in amplitudes for e, _ in engines}
    for k in range(args.repeats):
        for a in amplitudes:
            for name, extra in engines:
                print(f"run {k + 1}/{args.repeats}: {name}, A = {a:g} g ...", flush=True)
                if name.startswith("saxum"):
                    src = extra[0] or os.environ.get("PYTHONPATH")
                    r = _spawn("saxum", [a, args.duration, args.dt, *extra[1:]], src)
                else:
                    r = _spawn("pymunk", [a, args.duration, args.dt, extra], None)
                runs[(a, name)].append(r)

    def med(a, name, key="mean"):
        return statistics.median(r["step_time_s"][key] for r in runs[(a, name)])

    rest = amplitudes[0] if 0.0 in amplitudes else None
    print(f"\n512-brick wall, base {FREQUENCY:g} Hz, {args.duration:g} s, dt {args.dt:g} s; "
          f"median over {args.repeats} interleaved runs")
    print(f"{'A/g':>5} {'engine':>16} {'ms/step':>8} {'median':>7} {'/rest':>6} {'/pm100':>7} "
          f"{'cpu ms':>7} {'/rest':>6} {'median':>7} {'/rest':>6} "
          f"{'sweeps':>7} {'capped':>6} {'rest found':>10} {'rest s':>6} {'fact':>5} "
          f"{'largest dx':>11} {'bottom dx':>10}")
    table = []
    for a in amplitudes:
        for name, _ in engines:
            rs = runs[(a, name)]
            r = sorted(rs, key=lambda x: x["step_time_s"]["mean"])[(len(rs) - 1) // 2]
            t = med(a, name)
            cpu = statistics.median(r["step_cpu_s"]["mean"] for r in rs)
            cpu_rest = (statistics.median(r["step_cpu_s"]["mean"] for r in runs[(rest, name)])
                        if rest is not None else math.nan)
            cpu_median = statistics.median(r["step_cpu_s"]["median"] for r in rs)
            cpu_median_rest = (statistics.median(r["step_cpu_s"]["median"]
                                                 for r in runs[(rest, name)])
                               if rest is not None else math.nan)
            row = {"amplitude_g": a, "engine": name, "ms_per_step": t * 1e3,
                   "median_ms_per_step": med(a, name, "median") * 1e3,
                   "cpu_ms_per_step": cpu * 1e3, "cpu_over_at_rest": cpu / cpu_rest,
                   "median_cpu_ms_per_step": cpu_median * 1e3,
                   "median_cpu_over_at_rest": cpu_median / cpu_median_rest,
                   "over_saxum_at_rest": t / med(rest, name) if rest is not None else None,
                   "over_pymunk100": (t / med(a, "pymunk-100")
                                      if (a, "pymunk-100") in runs else None),
                   "run": r}
            table.append(row)
            sweeps = f"{r['sweeps']['mean']:.1f}" if "sweeps" in r else "-"
            capped = str(r.get("steps_at_cap", "-"))
            found = (f"{r['rest_solutions']}/{r['rest_attempts']}"
                     if r.get("rest_attempts") is not None else "-")
            ratio = (f"{row['over_saxum_at_rest']:.2f}" if row["over_saxum_at_rest"] is not None
                     else "-")
            pm = f"{row['over_pymunk100']:.2f}" if row["over_pymunk100"] is not None else "-"
            print(f"{a:>5g} {name:>16} {t * 1e3:>8.3f} {row['median_ms_per_step']:>7.3f} "
                  f"{ratio:>6} {pm:>7} {cpu * 1e3:>7.3f} {row['cpu_over_at_rest']:>6.2f} "
                  f"{cpu_median * 1e3:>7.3f} {row['median_cpu_over_at_rest']:>6.2f} "
                  f"{sweeps:>7} {capped:>6} {found:>10} {r.get('rest_cpu_s', math.nan):>6.3f} "
                  f"{r.get('factorizations', -1):>5} "
                  f"{r['largest_displacement_m'] * 1e3:>8.3g} mm "
                  f"{r['bottom_course_displacement_m'] * 1e3:>7.3g} mm")
    result = {"command": " ".join([Path(sys.executable).name, *sys.argv]),
              "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
              "machine": machine_info(), "frequency_hz": FREQUENCY, "duration_s": args.duration,
              "dt_s": args.dt, "table": table,
              "runs": {f"{a:g} {e}": v for (a, e), v in runs.items()}}
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(result, indent=2, default=float))
    print(f"wrote {args.json}")
    return 0 if all(math.isfinite(r["ms_per_step"]) for r in table) else 1


if __name__ == "__main__":
    sys.exit(main())
