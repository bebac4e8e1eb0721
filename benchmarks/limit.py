"""Benchmark of saxum.limit against the dynamic bisection (saxum.collapse) on the same models.

    python benchmarks/limit.py [--json benchmarks/results/limit.json] [--repeats 5]
                               [--wall-repeats 1]
                               [--parts arch,wall,wall-vertex,wall-bisection]

For the semicircular arch (R = 1 m, t/R = 0.15, 15 voussoirs, mu = 0.8) and a running-bond
wall of 2000 bricks and halves (40 courses of 50 bricks, 0.25 x 0.065 m, mu = 0.6) under a
horizontal load factor: the limit analysis (detection at the initial configuration, the
linear programme with HiGHS, the mechanism; the fastest of --repeats runs, --wall-repeats
for the wall, after a warm-up on a small wall; wall and CPU time; the wall's programme is
above saxum.limit._LARGE and goes to Clarabel: the part "wall-vertex" solves it again with
HiGHS's vertex, as smaller ones are, for comparison) and the load-to-collapse
bisection on the same model (certified verdicts, to 0.5 %; the wall's only with the part
"wall-bisection", which takes minutes), with the factors each finds. Kernels are compiled
(a warm-up run) before the clock starts.
"""

import argparse
import dataclasses
import json
import os
import platform
import time
from pathlib import Path
from unittest import mock

import numpy as np

import saxum as sx
from saxum import limit
from saxum.collapse import CollapseCriterion, critical_value, run_trial
from saxum.limit import limit_analysis
from saxum.structures import running_bond_wall, semicircular_arch


def _timed(fn, repeats: int):
    """(result, best wall [s], its CPU [s]) over `repeats` calls."""
    result = None
    best = (np.inf, np.inf)
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        result = fn()
        best = min(best, (time.perf_counter() - t0, time.process_time() - c0))
    return result, *best


def _bisection(model, stands: float, collapses: float) -> dict:
    g = float(np.linalg.norm(model.gravity))

    def make(factor):
        loaded = dataclasses.replace(model, accelerations=((lambda t: (factor * g, 0.0)),))
        return sx.Simulation(loaded, dt=1e-3)

    run_trial(make(stands), stands, CollapseCriterion(duration=0.01))  # compile
    t0, c0 = time.perf_counter(), time.process_time()
    result = critical_value(make, stands, collapses, tolerance=0.005)
    return {"bisection_factor": result.value, "bracket": [result.stands, result.collapses],
            "trials": len(result.trials),
            "simulated_s": sum(t.time for t in result.trials),
            "bisection_wall_s": time.perf_counter() - t0,
            "bisection_cpu_s": time.process_time() - c0}


def case(name: str, model, repeats: int, bisect: bool, vertex: bool = False) -> dict:
    with mock.patch.object(limit, "_LARGE", np.inf if vertex else limit._LARGE):
        result, wall, cpu = _timed(lambda: limit_analysis(model), repeats)
    out = {"case": name, "blocks": int((model.body_kind == sx.BodyKind.FREE).sum()),
           "contacts": result.contacts.count, "factor": result.factor,
           "hinges": len(result.mechanism.hinges), "sliding": len(result.mechanism.sliding),
           "moving": len(result.mechanism.moving),
           "limit_wall_s": wall, "limit_cpu_s": cpu}
    if bisect:
        out |= _bisection(model, 0.5 * result.factor, 1.5 * result.factor)
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--json", type=Path, default=Path("benchmarks/results/limit.json"))
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--wall-repeats", type=int, default=1)
    p.add_argument("--parts", default="arch,wall")
    args = p.parse_args()
    parts = args.parts.split(",")
    limit_analysis(running_bond_wall(courses=2, bricks=3))  # compile detection, load HiGHS
    rows = []
    if "arch" in parts:
        rows.append(case("arch 15 voussoirs", semicircular_arch(
            radius=1.0, thickness=0.15, voussoirs=15, friction=0.8), args.repeats, True))
        print(json.dumps(rows[-1]), flush=True)
    wall = running_bond_wall(courses=40, bricks=50)
    if "wall-vertex" in parts:
        rows.append(case("wall 40 x 50, HiGHS vertex", wall, args.wall_repeats, False, True))
        print(json.dumps(rows[-1]), flush=True)
    if "wall" in parts or "wall-bisection" in parts:
        rows.append(case("wall 40 x 50", wall, args.wall_repeats, "wall-bisection" in parts))
        print(json.dumps(rows[-1]), flush=True)
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps({"machine": platform.processor() or platform.machine(),
                                     "cpus": os.cpu_count(), "load": os.getloadavg(),
                                     "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
