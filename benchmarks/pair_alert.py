"""Benchmark: what DetectionSettings.per_pair (the alert from the smaller block of each pair
instead of the smallest free block of the model) changes on walls.

benchmarks/wall.py's 512-brick running-bond wall (25 courses of 20 bricks 0.25 x 0.065 m,
half bricks at the ends of every other course, mu = 0.6, at rest on a fixed ground). Per
setting: the alert distances [m], contacts at the
start and after --steps steps of dt = 1e-3 s, and the largest difference in block positions
between the two settings at the end [m].

    PYTHONPATH=src python benchmarks/pair_alert.py
"""

import argparse

import numpy as np

import saxum as sx
from saxum.structures import running_bond_wall


def _run(model, per_pair: bool, steps: int) -> tuple[dict, np.ndarray]:
    sim = sx.Simulation(model, dt=1e-3, detection=sx.DetectionSettings(per_pair=per_pair))
    state = sim.initial_state()
    start = sim.detector.contacts_at(state.body_q).count
    for _ in range(steps):
        sim.step(state)
    d = sim.detector
    pair = d._body_alert[model.body_kind == sx.BodyKind.FREE]
    return {"alert [m]": (f"{pair.min():.5f}..{pair.max():.5f}" if per_pair
                          else f"{d.alert:.5f}"),
            "contacts at start": start, f"contacts after {steps} steps": int(sim.log.contacts[-1]),
            "unconverged steps": int((~np.asarray(sim.log.converged)).sum())}, state.body_q


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200)
    args = parser.parse_args()
    walls = {"running-bond wall 25 x 20": running_bond_wall(
        courses=25, bricks=20, brick_length=0.25, brick_height=0.065, density=1800.0,
        friction=0.6)}
    for name, model in walls.items():
        rows = {}
        for per_pair in (False, True):
            rows[per_pair], q = _run(model, per_pair, args.steps)
            rows[per_pair]["q"] = q
        gap = float(np.abs(rows[True].pop("q") - rows[False].pop("q"))[:, :2].max())
        print(name)
        for per_pair, row in rows.items():
            print(f"  per_pair={per_pair}: " + ", ".join(f"{k} {v}" for k, v in row.items()))
        print(f"  largest difference in positions at the end: {gap:.3g} m")


if __name__ == "__main__":
    main()
