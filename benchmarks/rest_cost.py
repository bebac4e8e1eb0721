"""What the rest solution costs and saves (issue 18, item 6): NLGS with its back-off after
attempts that do not pay (saxum.solver.nlgs._REST_BACKOFF) against every slow step trying
(_REST_BACKOFF = 0, saxum before), back to back in one process on each case.

    python benchmarks/rest_cost.py
    python benchmarks/rest_cost.py --cases wall512-slides --duration 0.3

Cases (dt = 1e-3 s, NLGS with its defaults: tolerance 1e-6, rest_after 50, unless said):
- wall512-slides: the 512-brick running-bond wall of benchmarks/convergence.py under a
  constant horizontal acceleration of 0.7 g (mu = 0.6: it slides, no rest solution exists);
- wall512-shaken: the same wall on a base shaken at 0.7 g, 2 Hz (benchmarks/shaken_wall.py:
  it slides in part of each cycle and rests in between);
- wall512: the wall at rest;
- vault: a barrel vault (saxum.structures.arch3d, semicircular, span 4 m, thickness 0.3 m,
  15 voussoirs, 2 m deep in 4 staggered pieces, 70 blocks) at rest, tolerance 1.666e-4
  (LMGC90's examples' tolerance).
Per case and variant: rest solutions found / attempted, sweeps per step (mean), steps not
converged, time per step (mean, median; the CPU time of the stepping thread, mean, which a
loaded machine changes less), and whether the final positions are the same bit
for bit in both variants. Kernels are compiled by a short run first. JSON:
benchmarks/results/rest_cost.json.
"""

import argparse
import dataclasses
import json
import time
import warnings
from pathlib import Path

import numpy as np

import saxum as sx
import saxum.solver.nlgs as nlgs_module
from saxum.ground import harmonic
from saxum.structures import arch3d, running_bond_wall
from saxum.structures.arch import ArchShape

DT = 1e-3


def _wall():
    return running_bond_wall(courses=25, bricks=20)


def _sliding():
    model = _wall()
    g = float(np.hypot(*model.gravity))
    return dataclasses.replace(model, accelerations=((lambda t: (0.7 * g, 0.0)),))


def _shaken():
    model = _wall()
    g = float(np.hypot(*model.gravity))
    motion = harmonic(0.7 * g, 0.5, 2, samples_per_cycle=4000)
    return dataclasses.replace(model, accelerations=(motion.inertial_load(),))


def _vault():
    return arch3d(ArchShape.semicircular(span=4.0, thickness=0.3), voussoirs=15, depth=2.0,
                  pieces=4, stagger=True)


CASES = {"wall512-slides": (_sliding, 1e-6), "wall512-shaken": (_shaken, 1e-6),
         "wall512": (_wall, 1e-6), "vault": (_vault, 1.666e-4)}


def run(case: str, duration: float, backoff: int) -> dict:
    build, tolerance = CASES[case]
    model = build()
    nlgs_module._REST_BACKOFF = backoff
    solver = sx.NLGS(tolerance=tolerance)
    sim = sx.Simulation(model, dt=DT, solver=solver)
    state = sim.initial_state()
    times, cpu = [], []
    clock = [time.perf_counter(), time.thread_time()]

    def after_step(state, report):
        now, now_cpu = time.perf_counter(), time.thread_time()
        times.append(now - clock[0])
        cpu.append(now_cpu - clock[1])
        clock[0], clock[1] = now, now_cpu

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sx.SolverWarning)
        sim.run(state, duration, callback=after_step)
    sweeps = np.asarray(sim.log.iterations)
    return {"case": case, "backoff": backoff, "rest_attempts": solver.rest_attempts,
            "rest_solutions": solver.rest_solutions, "sweeps_mean": float(sweeps.mean()),
            "not_converged": int(np.count_nonzero(~np.asarray(sim.log.converged))),
            "ms_per_step_mean": 1e3 * float(np.mean(times)),
            "ms_per_step_median": 1e3 * float(np.median(times)),
            "cpu_ms_per_step_mean": 1e3 * float(np.mean(cpu)),
            "positions": state.body_q.copy()}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cases", default=",".join(CASES))
    p.add_argument("--duration", type=float, default=0.3)
    p.add_argument("--json", default="benchmarks/results/rest_cost.json")
    args = p.parse_args()
    default = nlgs_module._REST_BACKOFF
    for case in CASES:  # compile before the clock
        run(case, 0.003, default)
    rows = []
    print(f"{'case':15} {'variant':14} {'rest':>9} {'sweeps':>8} {'not conv':>8} "
          f"{'ms/step':>8} {'median':>7} {'cpu ms':>7} same")
    for case in args.cases.split(","):
        before = run(case, args.duration, 0)
        after = run(case, args.duration, default)
        same = bool(np.array_equal(before["positions"], after["positions"]))
        for r, name in ((before, "every step"), (after, f"back-off {default}")):
            r["variant"] = name
            r["same_positions"] = same
            r.pop("positions")
            rows.append(r)
            print(f"{case:15} {name:14} {r['rest_solutions']:4d}/{r['rest_attempts']:<4d} "
                  f"{r['sweeps_mean']:8.1f} {r['not_converged']:8d} "
                  f"{r['ms_per_step_mean']:8.2f} {r['ms_per_step_median']:7.2f} "
                  f"{r['cpu_ms_per_step_mean']:7.2f} {same}",
                  flush=True)
    nlgs_module._REST_BACKOFF = default
    out = Path(args.json)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"rows": rows, "duration_s": args.duration}, indent=1))


if __name__ == "__main__":
    main()
