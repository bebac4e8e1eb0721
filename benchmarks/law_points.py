"""Benchmark: what the contact points of laws in stresses cost a step (ContactLaw.points).

The mortared wall of examples/mortared_wall.toml (16 courses of 4 bricks with a window, bed,
head and support joints COHESIVE) with 2 points per face contact (the ends: a trapezoid rule)
and with 3 (Simpson), both built in one process and stepped in interleaved chunks of --chunk
steps after --warm steps each (numba compiled), so that both see the same machine load. Per
model: time per step [ms], NLGS sweeps per step, contacts at the end.

    PYTHONPATH=src python benchmarks/law_points.py
"""

import argparse
import time
from pathlib import Path

from saxum.scenario import load_scenario

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "mortared_wall.toml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--warm", type=int, default=20)
    parser.add_argument("--chunk", type=int, default=100)
    parser.add_argument("--chunks", type=int, default=5)
    args = parser.parse_args()
    runs = {}
    for points in (2, 3):
        scenario = load_scenario(EXAMPLE, [f"laws[{i}].points={points}" for i in range(3)])
        sim = scenario.build_simulation()
        state = sim.initial_state()
        for _ in range(args.warm):
            sim.step(state)
        runs[points] = (sim, state, {"seconds": 0.0, "sweeps": 0, "steps": 0})
    for _ in range(args.chunks):
        for sim, state, total in runs.values():
            start = time.perf_counter()
            for _ in range(args.chunk):
                total["sweeps"] += sim.step(state).iterations
            total["seconds"] += time.perf_counter() - start
            total["steps"] += args.chunk
    print("| points | ms/step | sweeps/step | contacts |")
    print("|---|---|---|---|")
    for points, (_, state, total) in runs.items():
        print(f"| {points} | {1e3 * total['seconds'] / total['steps']:.2f} | "
              f"{total['sweeps'] / total['steps']:.1f} | {state.contacts.count} |")


if __name__ == "__main__":
    main()
