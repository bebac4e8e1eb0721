"""Benchmark: what the hybrid solver costs where NLGS converges.

Structures at rest under gravity (--cases: wall512, the 512-brick running-bond wall of
benchmarks/wall.py; wall2025, its 2025-brick one; wall3d, the 480-brick 3D L wall of
benchmarks/convergence.py), each stepped `--steps` times (dt 1e-3 s, after the cold first
step, which is not timed) by `saxum.NLGS()` and by `saxum.Hybrid()` in turn, interleaved
`--repeats` times in one process (the same machine state for both); prints the time per step
of each run and the ratio of medians and of means. Where NLGS converges the hybrid runs the
same sweeps (tests/test_hybrid.py checks the states bit for bit); the difference is its
bookkeeping (one Python call more per window of sweeps).

    python benchmarks/hybrid_overhead.py --repeats 5
    python benchmarks/hybrid_overhead.py --repeats 5 --cases wall512,wall2025,wall3d
"""

import argparse
import statistics
import time

import saxum as sx
from saxum.structures import running_bond_wall, wall3d

SOLVERS = {"nlgs": sx.NLGS, "hybrid": sx.Hybrid}
CASES = {"wall512": lambda: running_bond_wall(courses=25, bricks=20),
         "wall2025": lambda: running_bond_wall(courses=50, bricks=40),
         "wall3d": lambda: wall3d(courses=20, length=3.0, return_length=3.0)}


def time_per_step(model, kind: str, steps: int) -> float:
    """Seconds per step of `steps` steps after the first, with a new solver of `kind`."""
    sim = sx.Simulation(model, dt=1e-3, solver=SOLVERS[kind]())
    state = sim.initial_state()
    sim.step(state)  # the cold start, apart
    start = time.perf_counter()
    for _ in range(steps):
        sim.step(state)
    return (time.perf_counter() - start) / steps


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--cases", default="wall512",
                        help=f"comma-separated subset of {', '.join(CASES)} (default wall512)")
    args = parser.parse_args(argv)
    for case in args.cases.split(","):
        model = CASES[case]()
        for kind in SOLVERS:  # compile (or load) the kernels first
            time_per_step(model, kind, 2)
        times = {kind: [] for kind in SOLVERS}
        for _ in range(args.repeats):
            for kind in SOLVERS:
                times[kind].append(time_per_step(model, kind, args.steps))
        for kind, t in times.items():
            print(f"{case} {kind:7s} ms per step: " + ", ".join(f"{1e3 * x:.4f}" for x in t))
        medians = statistics.median(times["hybrid"]) / statistics.median(times["nlgs"])
        means = statistics.mean(times["hybrid"]) / statistics.mean(times["nlgs"])
        print(f"{case} hybrid / nlgs: {medians:.3f} (medians), {means:.3f} (means)", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
