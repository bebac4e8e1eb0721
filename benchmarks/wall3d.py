"""Benchmark: a 3D running-bond brick wall of about 2000 bricks at rest (saxum.structures.wall3d).

What it measures (wall-clock, time.perf_counter, single thread, in this process after the
kernels were compiled or loaded on a tiny wall):

1. An L-shaped wall (two walls one brick thick meeting at an interlocking corner; bricks
   0.25 x 0.12 x 0.065 m, 1800 kg/m^3, mu = 0.6, default gap-based law and NLGS, dt = 1e-3 s)
   standing on a fixed ground slab: time per step (step 1 apart: a cold start of the solver
   from zero impulses), NLGS sweeps per step, rest-solution attempts and successes
   (saxum.solver.equilibrium; --rest-after 0: NLGS alone), the time inside the NLGS solve per
   single-contact update (solve time / sum of sweeps x active contacts: an upper bound of the
   update kernel's cost, as in benchmarks/wall.py), the time inside detection per step, peak
   memory (ru_maxrss, and the numpy arrays the model and simulation hold), drift and
   interpenetration. The stages are timed by wrapping methods of the Simulation instance, as
   benchmarks/wall.py does (its helpers are reused).
2. Detection alone on the initial configuration of walls of about 500, 2000 and 8000 bricks,
   broad phase forced at every call and not (narrow phase on the cached pair list): time per
   call and per brick (O(N) expected).

    python benchmarks/wall3d.py                       # about 2 minutes on 2 cores
    python benchmarks/wall3d.py --duration 0.5 --json /tmp/wall3d.json
    python benchmarks/wall3d.py --rest-after 0        # NLGS alone
"""

import argparse
import datetime
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import wall as wall2d  # noqa: E402  (the 2D benchmark's helpers: timers, stats, machine info)

DEFAULT_JSON = HERE / "results" / "wall3d.json"
COURSES = 40
LENGTH = 6.0  # m, each of the two walls of the L: ~24 bricks per wall and course
SIZES = [(20, 3.0), (40, 6.0), (80, 12.0)]  # ~500, ~2000, ~8000 bricks


def _wall(courses: int, length: float):
    from saxum.structures import wall3d

    return wall3d(courses=courses, length=length, return_length=length)


def _solver(rest_after: int | None):
    import saxum as sx

    return sx.NLGS() if rest_after is None else sx.NLGS(rest_after=rest_after)


def _warm_up(rest_after: int | None) -> float:
    """Compile (or load) the kernels a step uses, the rest solution's included (the cold
    start of a 10-course wall needs it)."""
    import saxum as sx

    t0 = time.perf_counter()
    sim = sx.Simulation(_wall(10, 0.75), dt=1e-3, solver=_solver(rest_after))
    state = sim.initial_state()
    for _ in range(3):
        sim.step(state)
    return time.perf_counter() - t0


def run_wall(duration: float, dt: float, rest_after: int | None = None) -> dict:
    import saxum as sx
    from saxum.model import BodyKind

    warm = _warm_up(rest_after)
    rss_before = wall2d._peak_rss_mib()
    t0 = time.perf_counter()
    model = _wall(COURSES, LENGTH)
    sim = sx.Simulation(model, dt=dt, solver=_solver(rest_after))
    state = sim.initial_state()
    t_build = time.perf_counter() - t0
    detect = sim.detector.detect = wall2d._Timed(sim.detector.detect)
    solve = sim.solver.solve = wall2d._Timed(sim.solver.solve)
    steps = round(duration / dt)
    step_time, detect_time, solve_time = (np.empty(steps) for _ in range(3))
    visited = np.empty(steps, dtype=np.int64)
    q0 = state.body_q.copy()
    for k in range(steps):
        s0 = time.perf_counter()
        sim.step(state)
        step_time[k] = time.perf_counter() - s0
        detect_time[k] = detect.last
        solve_time[k] = solve.last
        visited[k] = int(sim.problem.active[: sim.problem.count].sum())
    log = sim.log
    iterations = log.iterations.astype(np.int64)
    updates = iterations * visited
    free = model.body_kind == BodyKind.FREE
    drift = np.linalg.norm(state.body_q[free, :3] - q0[free, :3], axis=1)
    rest = slice(1, None)

    def ns_per_update(sl):
        n = int(updates[sl].sum())
        return float(solve_time[sl].sum() / n * 1e9) if n else math.nan

    return {
        "courses": COURSES, "wall_length_m": LENGTH, "return_length_m": LENGTH,
        "bricks": int(free.sum()), "dt_s": dt, "steps": steps, "build_s": t_build,
        "jit_warm_up_s": warm,
        "contacts": wall2d._stats(log.contacts[rest].tolist()),
        "contacts_visited_by_nlgs": wall2d._stats(visited[rest].tolist()),
        "first_step": {"time_s": float(step_time[0]), "iterations": int(iterations[0]),
                       "converged": bool(log.converged[0]), "contacts": int(log.contacts[0])},
        "step_time_s": wall2d._stats(step_time[rest].tolist()),
        "detection_time_s": wall2d._stats(detect_time[rest].tolist()),
        "nlgs_time_s": wall2d._stats(solve_time[rest].tolist()),
        "iterations": wall2d._stats(iterations[rest].tolist()),
        "non_converged_steps": int((~log.converged).sum()),
        "rest_after": getattr(sim.solver, "rest_after", None),
        "rest_attempts": getattr(sim.solver, "rest_attempts", None),
        "rest_solutions": getattr(sim.solver, "rest_solutions", None),
        "ns_per_contact_update": ns_per_update(rest),
        "ns_per_contact_update_incl_first_step": ns_per_update(slice(None)),
        "drift_m": float(drift.max()),
        "max_interpenetration_m": float(log.max_interpenetration.max()),
        "peak_rss_mib": wall2d._peak_rss_mib(), "peak_rss_before_model_mib": rss_before,
        "numpy_arrays_mib": wall2d._numpy_bytes(model, sim, sim.detector, sim.problem,
                                                sim.solver, state, state.contacts,
                                                sim._spare) / 2.0**20,
    }


def run_detection(target_s: float) -> list[dict]:
    import saxum as sx
    from saxum.contacts import Contacts

    out = []
    for courses, length in SIZES:
        model = _wall(courses, length)
        det = sx.Simulation(model, dt=1e-3).detector
        contacts = Contacts(3)
        row = {"bricks": int((model.body_kind == 0).sum())}
        for forced in (True, False):
            times = []
            start = time.perf_counter()
            refreshes = det.refresh_count
            while time.perf_counter() - start < target_s or len(times) < 3:
                det._since_refresh = det.refresh_every if forced else 0
                t0 = time.perf_counter()
                det.detect(model.body_q0, contacts)
                times.append(time.perf_counter() - t0)
            did = det.refresh_count - refreshes
            assert did == (len(times) if forced else 0), "broad phase not as intended"
            key = "forced_broad_phase" if forced else "narrow_phase_only"
            median = float(np.median(times))
            row[key] = {"median_s": median, "per_brick_us": median / row["bricks"] * 1e6,
                        "calls": len(times)}
        row["contacts"] = int(contacts.count)
        out.append(row)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Benchmark saxum on a ~2000-brick 3D wall.")
    parser.add_argument("--duration", type=float, default=0.3,
                        help="simulated time [s] (default 0.3)")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument("--detect-target", type=float, default=0.5,
                        help="seconds of repeated detection calls per size and mode")
    parser.add_argument("--rest-after", type=int, default=None,
                        help="NLGS rest_after (0: NLGS alone); default: saxum's default")
    parser.add_argument("--json", type=Path, default=DEFAULT_JSON, help="output JSON file")
    args = parser.parse_args(argv)

    result = {
        "command": " ".join([Path(sys.executable).name, *sys.argv]),
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "machine": wall2d.machine_info(),
    }
    print("3D wall ...", flush=True)
    w = result["wall"] = run_wall(args.duration, args.dt, args.rest_after)
    print(f"  {w['bricks']} bricks, {w['contacts']['median']:.0f} contacts, {w['steps']} steps "
          f"of {w['dt_s']:g} s")
    print(f"  first step (cold start): {w['first_step']['time_s']:.2f} s, "
          f"{w['first_step']['iterations']} sweeps")
    print(f"  time per step: mean {w['step_time_s']['mean'] * 1e3:.1f} ms, median "
          f"{w['step_time_s']['median'] * 1e3:.1f} ms")
    print(f"  NLGS sweeps per step: mean {w['iterations']['mean']:.1f}, median "
          f"{w['iterations']['median']:.0f}, max {w['iterations']['max']}; not converged: "
          f"{w['non_converged_steps']} step(s); rest solutions {w['rest_solutions']} of "
          f"{w['rest_attempts']} attempts")
    print(f"  single-contact update: {w['ns_per_contact_update']:.0f} ns "
          f"({w['ns_per_contact_update_incl_first_step']:.0f} ns with the first step)")
    print(f"  detection per step: mean {w['detection_time_s']['mean'] * 1e3:.2f} ms, median "
          f"{w['detection_time_s']['median'] * 1e3:.2f} ms")
    print(f"  peak memory {w['peak_rss_mib']:.0f} MiB ({w['peak_rss_before_model_mib']:.0f} "
          f"MiB before the model; numpy arrays {w['numpy_arrays_mib']:.1f} MiB)")
    print(f"  drift {w['drift_m'] * 1e3:.2e} mm, largest interpenetration "
          f"{w['max_interpenetration_m'] * 1e3:.2e} mm")
    print("detection alone ...", flush=True)
    result["detection"] = run_detection(args.detect_target)
    for row in result["detection"]:
        f, n = row["forced_broad_phase"], row["narrow_phase_only"]
        print(f"  {row['bricks']:5d} bricks: {f['median_s'] * 1e3:7.2f} ms with the broad phase "
              f"({f['per_brick_us']:.2f} us/brick), {n['median_s'] * 1e3:7.2f} ms narrow only "
              f"({n['per_brick_us']:.2f} us/brick); {row['contacts']} contacts")
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(result, indent=1))
    print(f"written: {args.json}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
