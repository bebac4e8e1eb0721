"""Benchmark: where the default thread count pays (issue 16, saxum.solver.nlgs.step_plan): the
serial step (NLGS threads 1, domains 1) against the step on 2 threads with 2 domains (what
the default runs on 2 cores from 2 x _DOMAIN_BODIES free blocks on) on running-bond walls at
rest of growing size, 0.25 x 0.065 m bricks, one sweep a step: the case where the parallel step's
fixed costs (parallel regions, packing in the domains' order) weigh the most. Per wall and
variant, interleaved --repeats times, after 5 steps: wall and CPU time per step, and the
thread-time estimate of benchmarks/parallel_nlgs.py (the stepping thread's CPU time plus the
busiest other thread's: the step on idle cores under NUMBA_THREADING_LAYER=workqueue, which a
loaded machine changes less than the wall time); medians over the repeats.

    python benchmarks/thread_default.py
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

SIZES = ((10, 24), (16, 32), (20, 50), (40, 50), (80, 50), (160, 50))
"""(courses, bricks per course): 245 to 8080 free blocks."""
VARIANTS = {"serial": {"threads": 1, "domains": 1}, "2 threads": {"threads": 2, "domains": 2}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    print(f"numba threads available: {numba.config.NUMBA_NUM_THREADS}, threading layer "
          f"requested {os.environ.get('NUMBA_THREADING_LAYER', 'default')}; load average "
          f"{os.getloadavg()[0]:.1f} at the start", flush=True)
    for settings in VARIANTS.values():  # compile (or load) every kernel first
        _run(_wall((4, 3), 0.0), settings, 1, 1)
    print("| wall | free blocks | domains | serial wall (CPU) [ms] | 2 threads wall (CPU) [ms] "
          "| serial / 2 threads, wall | thread-time estimate serial / 2 threads | load |")
    print("|---|---|---|---|---|---|---|---|")
    for size in SIZES:
        model = _wall(size, 0.0)
        rows = {label: [] for label in VARIANTS}
        for _ in range(args.repeats):
            for label, settings in VARIANTS.items():
                rows[label].append(_run(model, settings, 5, args.steps)[0])
        step = {label: [statistics.median(r["step"][i] for r in rows[label]) for i in (0, 1)]
                for label in VARIANTS}
        spent = {label: np.median([r["threads"] for r in rows[label]], axis=0)
                 for label in VARIANTS}
        estimate = {label: s[0] + s[1] for label, s in spent.items()}
        free = int((model.body_kind == sx.BodyKind.FREE).sum())
        domains = step_plan(**VARIANTS["2 threads"], model=model)[1]
        (sw, sc), (pw, pc) = step["serial"], step["2 threads"]
        print(f"| {size[0]} x {size[1]} | {free} | {domains} | {1e3 * sw:.2f} ({1e3 * sc:.2f}) "
              f"| {1e3 * pw:.2f} ({1e3 * pc:.2f}) | {sw / pw:.2f} | "
              f"{estimate['serial'] / estimate['2 threads']:.2f} | {os.getloadavg()[0]:.1f} |",
              flush=True)
    print(f"threading layer: {numba.threading_layer()}")


if __name__ == "__main__":
    main()
