"""Benchmark: NLGS on 1 and 2 numba threads (issue 16), the coloured sweep
(saxum.solver.nlgs.nlgs_2d_coloured) against the serial one (nlgs_2d), in one process.

Cases (dt 1e-3 s, running-bond walls of 0.25 x 0.065 m bricks, 1800 kg/m^3, mu 0.6, on a
fixed ground, saxum.NLGS): a 160 x 100 wall (about 16 000 bricks) at rest, and a 50 x 40
wall (2025 bricks) on a base shaken at 0.7 g, 2 Hz (it slides on its base). Per case and
solver (serial, coloured on 1 thread, coloured on 2), interleaved --repeats times: wall and
CPU time (time.process_time: all threads) of the contact solve per step, and sweeps per step,
after the first steps of that simulation (the kernels compiled before, on a separate one). The
colouring (colour_contacts_2d, when the active contacts change) is inside the solve's time. On
a shared machine only ratios from one run mean anything; CPU time changes less with load than
wall time, but omp's threads spin while they wait (CPU time that is not work): compare the
layers with NUMBA_THREADING_LAYER.

    python benchmarks/parallel_nlgs.py                    # both cases
    python benchmarks/parallel_nlgs.py --steps 10 --repeats 1
    NUMBA_THREADING_LAYER=workqueue python benchmarks/parallel_nlgs.py
    NUMBA_THREADING_LAYER=omp python benchmarks/parallel_nlgs.py
"""

import argparse
import dataclasses
import statistics
import time

import numba
import numpy as np

import saxum as sx
from saxum.ground import harmonic
from saxum.structures import running_bond_wall

CASES = {"rest 160x100": ((160, 100), 0.0, 5), "shaken 50x40": ((50, 40), 0.7, 150)}
"""name: ((courses, bricks), base acceleration [g], steps before the timed ones: at 0.7 g the
wall slides from about 0.1 s on)"""
SOLVERS = {"serial": None, "coloured 1": 1, "coloured 2": 2}


def _model(size, amplitude_g):
    model = running_bond_wall(courses=size[0], bricks=size[1], brick_length=0.25,
                              brick_height=0.065, density=1800.0, friction=0.6)
    if amplitude_g > 0.0:
        load = harmonic(amplitude_g * 9.81, 0.5, 4.0).inertial_load()
        model = dataclasses.replace(model, accelerations=(load,))
    return model


def _run(model, threads, warm, steps):
    """(wall s, CPU s, sweeps) per step of the solve, mean over `steps` after `warm`."""
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(threads=threads))
    state = sim.initial_state()
    for _ in range(warm):
        sim.step(state)
    solve = sim.solver.solve
    spent = [0.0, 0.0]

    def timed(*args):
        w, c = time.perf_counter(), time.process_time()
        out = solve(*args)
        spent[0] += time.perf_counter() - w
        spent[1] += time.process_time() - c
        return out

    sim.solver.solve = timed
    for _ in range(steps):
        sim.step(state)
    sweeps = float(np.mean(sim.log.iterations[warm:]))
    return spent[0] / steps, spent[1] / steps, sweeps, state.body_q.copy()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--cases", default=",".join(CASES), help="comma-separated names")
    args = parser.parse_args()
    print(f"numba threads available: {numba.config.NUMBA_NUM_THREADS}", flush=True)
    for name in args.cases.split(","):
        size, amplitude, warm = CASES[name]
        model = _model(size, amplitude)
        bricks = int((model.body_kind == sx.BodyKind.FREE).sum())
        for threads in SOLVERS.values():  # compile (or load) every kernel first
            _run(_model((4, 3), amplitude), threads, 1, 1)
        rows = {s: [] for s in SOLVERS}
        q = {}
        for _ in range(args.repeats):
            for label, threads in SOLVERS.items():
                *row, q[label] = _run(model, threads, warm, args.steps)
                rows[label].append(row)
        same = np.array_equal(q["coloured 1"], q["coloured 2"])
        print(f"{name} ({bricks} bricks, {args.steps} steps after {warm}, "
              f"median of {args.repeats}); coloured 1 == coloured 2 bit for bit: {same}")
        base = statistics.median(r[0] for r in rows["coloured 1"])
        for label, r in rows.items():
            wall = statistics.median(x[0] for x in r)
            cpu = statistics.median(x[1] for x in r)
            print(f"  {label:11s} solve {1e3 * wall:8.2f} ms/step wall, {1e3 * cpu:8.2f} ms "
                  f"CPU, {r[0][2]:7.1f} sweeps/step, {1e9 * wall / bricks / r[0][2]:6.1f} "
                  f"ns/brick/sweep; coloured 1 / this: {base / wall:.2f}", flush=True)
    print(f"threading layer: {numba.threading_layer()}")


if __name__ == "__main__":
    main()
