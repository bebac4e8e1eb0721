"""Benchmark: the cost of detection over contactors for clusters (ModelBuilder.add_cluster).

The 3D wall of benchmarks/wall3d.py (40 courses, an L of two 6 m walls, 1920 bricks on a
fixed ground) built twice from the same bricks: (a) every brick a block; (b) the bricks
taken two by two along each course (consecutive body indices, which wall3d lays along the
course) as 960 two-part clusters, the bricks their parts. Detection (saxum.detection) on the
initial configuration, broad phase forced at every call and not (narrow phase on the cached
pair list), the two models alternately in this one process (the machine's load changes
both alike): the median time per call of each over `--repeats` rounds of `--calls` calls,
and their ratio. (b) tests the same parts less the pairs inside a cluster, and adds the
contactors' coordinates (saxum.bodies.rigid3d.contactor_coordinates) and the mapping of the
contacts to bodies.

With `--against SRC` (another saxum's source folder, e.g. main's), first: models without
clusters, this tree against SRC, each in its own process, alternately `--rounds` times: the
median CPU time (time.process_time) per step and per detection of the 3D wall above at rest
(60 steps) and of benchmarks/wall.py's 25 x 20 2D wall (400 steps), after a warm-up; the
smallest and the median over the rounds of each, and their ratios.

    python benchmarks/clusters.py                    # about a minute on 2 cores
    python benchmarks/clusters.py --against /work/main/src --rounds 4
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def _models():
    import saxum as sx
    from saxum.model import BodyKind
    from saxum.structures import wall3d

    walls = wall3d(courses=40, length=6.0, return_length=6.0)
    law = walls.laws[0]
    built = []
    for paired in (False, True):
        b = sx.ModelBuilder(dim=3)
        free = [k for k in range(walls.body_count) if walls.body_kind[k] == BodyKind.FREE]
        for k in range(walls.body_count):
            if walls.body_kind[k] != BodyKind.FREE:
                b.add_block(walls.vertices(k), kind=BodyKind(int(walls.body_kind[k])),
                            group="ground", name=walls.body_name[k])
        if paired:
            for i in range(0, len(free) - 1, 2):
                b.add_cluster([walls.vertices(free[i]), walls.vertices(free[i + 1])],
                              density=float(walls.body_density[free[i]]))
        else:
            for k in free:
                b.add_block(walls.vertices(k), density=float(walls.body_density[k]))
        b.set_law("block", "ground", law)
        b.set_law("block", "block", law)
        built.append(b.finalize())
    return built


def _per_step(model, steps: int) -> tuple[float, float]:
    """Median CPU time per step and per detection [s] of `model` over `steps` steps."""
    import saxum as sx

    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    for _ in range(3):
        sim.step(state)
    detect, inner = [], sim.detector.detect

    def timed(*args, **kwargs):
        t0 = time.process_time()
        inner(*args, **kwargs)
        detect.append(time.process_time() - t0)

    sim.detector.detect = timed
    step = []
    for _ in range(steps):
        t0 = time.process_time()
        sim.step(state)
        step.append(time.process_time() - t0)
    return float(np.median(step)), float(np.median(detect))


def _plain_models() -> dict:
    """The worker of --against: per-step numbers of the two walls without clusters."""
    from saxum.structures import running_bond_wall, wall3d

    _per_step(wall3d(courses=10, length=0.75, return_length=0.75), 3)  # compile or load
    _per_step(running_bond_wall(courses=3, bricks=3), 3)
    return {"3d": _per_step(wall3d(courses=40, length=6.0, return_length=6.0), 60),
            "2d": _per_step(running_bond_wall(courses=25, bricks=20), 400)}


def _against(other: str, rounds: int) -> dict:
    """This tree against the saxum at `other` on models without clusters (module doc)."""
    mine = str(HERE.parent / "src")
    runs: dict[str, list] = {"this": [], "other": []}
    for _ in range(rounds):
        for name, src in (("other", other), ("this", mine)):
            env = {**os.environ, "PYTHONPATH": src}
            done = subprocess.run([sys.executable, __file__, "--worker"], env=env, check=True,
                                  capture_output=True, text=True)
            runs[name].append(json.loads(done.stdout.splitlines()[-1]))
    out = {}
    for dim, k, label in (("3d", 0, "3D wall, step"), ("3d", 1, "3D wall, detection"),
                          ("2d", 0, "2D wall, step"), ("2d", 1, "2D wall, detection")):
        a, b = (np.array([r[dim][k] for r in runs[n]]) * 1e3 for n in ("other", "this"))
        out[label] = {"other_ms": [float(a.min()), float(np.median(a))],
                      "this_ms": [float(b.min()), float(np.median(b))],
                      "ratio": [float(b.min() / a.min()), float(np.median(b) / np.median(a))]}
        print(f"{label}: other min {a.min():.4f} median {np.median(a):.4f} ms, this min "
              f"{b.min():.4f} median {np.median(b):.4f} ms, ratio min "
              f"{b.min() / a.min():.3f} median {np.median(b) / np.median(a):.3f}")
    return out


def _time(detector, q, contacts, forced: bool, calls: int) -> float:
    times = []
    for _ in range(calls):
        detector._since_refresh = detector.refresh_every if forced else 0
        t0 = time.perf_counter()
        detector.detect(q, contacts)
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--calls", type=int, default=20)
    parser.add_argument("--json", type=Path, default=None, help="also write the numbers here")
    parser.add_argument("--against", help="another saxum's src folder (module doc)")
    parser.add_argument("--rounds", type=int, default=4)
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        print(json.dumps(_plain_models()))
        return 0
    out = {"against": _against(args.against, args.rounds)} if args.against else {}
    from saxum.contacts import Contacts
    from saxum.detection import detector_for

    models = _models()
    detectors = [detector_for(m) for m in models]
    contacts = [Contacts(3) for _ in models]
    for d, m, c in zip(detectors, models, contacts, strict=True):  # compile or load
        d.detect(m.body_q0, c)
    for forced in (True, False):
        rows = [[], []]
        for _ in range(args.repeats):
            for k in range(2):
                rows[k].append(_time(detectors[k], models[k].body_q0, contacts[k], forced,
                                     args.calls))
        blocks, clusters = (float(np.median(r)) for r in rows)
        key = "forced_broad_phase" if forced else "narrow_phase_only"
        out[key] = {"blocks_ms": 1e3 * blocks, "clusters_ms": 1e3 * clusters,
                    "ratio": clusters / blocks}
    out["bodies"] = [m.body_count for m in models]
    out["contacts"] = [int(c.count) for c in contacts]
    for key in ("forced_broad_phase", "narrow_phase_only"):
        r = out[key]
        print(f"{key}: blocks {r['blocks_ms']:.2f} ms, clusters {r['clusters_ms']:.2f} ms, "
              f"ratio {r['ratio']:.3f}")
    print(f"bodies {out['bodies']}, contacts {out['contacts']}")
    if args.json is not None:
        args.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
