"""Benchmark: the default plan of threads and domains (issue 16, saxum.solver.nlgs.step_plan) on
running-bond walls at rest of growing size, 0.25 x 0.065 m bricks, one sweep a step: the case
where the parallel step's fixed costs (parallel regions, packing in the domains' order) weigh
the most. Variants: the serial step (NLGS threads 1, domains 1); 2 threads with 2 domains
(where that pays against the serial step sets the size from which the default cuts a model
into domains, _PARALLEL_BODIES); and the model's default domains (default_domains: one below
4096 free blocks, a function of the model only) on one thread and on the default threads
(all cores where there are two domains or more). Per wall and variant, interleaved --repeats
times, after 5 steps: wall and CPU time per step, and the thread-time estimate of
benchmarks/parallel_nlgs.py (the stepping thread's CPU time plus the busiest other thread's:
the step on idle cores under NUMBA_THREADING_LAYER=workqueue, which a loaded machine changes
less than the wall time); medians over the repeats; whether the default's and the one-thread
run's final positions are the same bits.

    python benchmarks/thread_default.py
    python benchmarks/thread_default.py --sizes 100x160 --variants "1 thread,default"
    NUMBA_THREADING_LAYER=workqueue python benchmarks/thread_default.py --repeats 3
"""

import argparse
import os
import statistics
import sys
from pathlib import Path

import numba
import numpy as np

import saxum as sx
from saxum.solver.nlgs import step_plan

sys.path.insert(0, str(Path(__file__).parent))
from parallel_nlgs import _run, _wall  # noqa: E402  (benchmarks/ is not a package)

SIZES = "10x24,16x32,20x50,40x50,80x50,160x50"
"""courses x bricks per course: 245 to 8080 free blocks."""
VARIANTS = {"serial": {"threads": 1, "domains": 1}, "2 threads 2 domains": {"threads": 2,
                                                                            "domains": 2},
            "1 thread": {"threads": 1}, "default": {}}
"""NLGS's settings of each variant (absent: the default)."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--sizes", default=SIZES, help=f"walls (default {SIZES})")
    parser.add_argument("--variants", default=",".join(VARIANTS),
                        help=f"of {', '.join(VARIANTS)}")
    args = parser.parse_args()
    variants = {name: VARIANTS[name] for name in args.variants.split(",")}
    print(f"numba threads available: {numba.config.NUMBA_NUM_THREADS}, threading layer "
          f"requested {os.environ.get('NUMBA_THREADING_LAYER', 'default')}; load average "
          f"{os.getloadavg()[0]:.1f} at the start", flush=True)
    for settings in variants.values():  # compile (or load) every kernel first
        _run(_wall((4, 3), 0.0), {"threads": 2, "domains": 2, **settings}, 1, 1)
    print("| wall | free blocks | variant (threads, domains) | wall (CPU) per step [ms] | "
          "thread-time estimate [ms] | load |")
    print("|---|---|---|---|---|---|")
    for size in args.sizes.split(","):
        model = _wall(tuple(int(n) for n in size.split("x")), 0.0)
        rows = {label: [] for label in variants}
        q = {}
        for _ in range(args.repeats):
            for label, settings in variants.items():
                *row, q[label] = _run(model, settings, 5, args.steps)
                rows[label].append(row[0])
        free = int((model.body_kind == sx.BodyKind.FREE).sum())
        for label, settings in variants.items():
            wall, cpu = (statistics.median(r["step"][i] for r in rows[label]) for i in (0, 1))
            spent = np.median([r["threads"] for r in rows[label]], axis=0)
            plan = step_plan(settings.get("threads"), settings.get("domains"), model)
            print(f"| {size} | {free} | {label} {plan} | {1e3 * wall:.2f} ({1e3 * cpu:.2f}) | "
                  f"{1e3 * (spent[0] + spent[1]):.2f} | {os.getloadavg()[0]:.1f} |", flush=True)
        if {"1 thread", "default"} <= set(q):
            print(f"default and 1 thread the same bits: "
                  f"{np.array_equal(q['1 thread'], q['default'])}")
    print(f"threading layer: {numba.threading_layer()}")


if __name__ == "__main__":
    main()
