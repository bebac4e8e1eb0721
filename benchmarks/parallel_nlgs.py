"""Benchmark: one step on 1 and 2 numba threads (issue 16), stage by stage: the serial step
(solver threads 1 and domains 1: nlgs_2d or nlgs_3d and the serial kernels) against NLGS by
two domains (saxum.solver.nlgs.nlgs_2d_domains or nlgs_3d_domains) on 1 thread (with the serial
kernels) and on 2 (with the parallel detection, assembly and, in 2D, end gaps), in one process.

Cases (dt 1e-3 s, saxum.NLGS, VARIANTS): running-bond walls of 0.25 x 0.065 m bricks, 1800
kg/m^3, mu 0.6, on a fixed ground: 160 x 100 (16 080 bricks) at rest, and 50 x 40 (2025 bricks)
on a base shaken at 0.7 g, 2 Hz (it slides on its base); with --3d, L walls of
saxum.structures.wall3d (0.25 x 0.12 x 0.065 m bricks, the same material): 40 courses of two 12
m legs (3840 bricks) at rest, and 20 courses of two 6 m legs (960 bricks) on a base shaken at
0.7 g, 2 Hz, along (0.6, 0.8, 0) (3D: nlgs_3d_domains, polyhedron_contacts_parallel and the
parallel 3D assembly). Per case and variant, interleaved --repeats times, after `warm` steps of
that simulation (the kernels compiled before on a small one): wall time (time.perf_counter) and
CPU time (time.process_time: all threads; omp's threads spin while they wait, CPU time that is
not work) per step of detection, the warm start (Contacts.warm_start_from), assembly, the
solve, the end gaps and the whole step, medians over the repeats; sweeps per step; whether the
1- and 2-thread runs end with the same positions bit for bit. On a shared machine only ratios
from one run mean anything.

Thread-time accounting (Linux: /proc/self/task/*/schedstat, each thread's time on a CPU and
its time waiting for one): per step, the stepping thread's CPU time, the busiest other
thread's and all of theirs. Under NUMBA_THREADING_LAYER=workqueue the stepping thread runs
the serial parts and sleeps in the parallel regions while numba's threads run them (omp's
threads spin instead, so use workqueue for this), so the stepping thread's time plus the
busiest worker's estimates the step's time on idle cores: a lower bound (it leaves out the
wake-ups and assumes the work of each region shared as the totals are), which a loaded
machine changes far less than the wall time.

    python benchmarks/parallel_nlgs.py                               # all 2D cases
    python benchmarks/parallel_nlgs.py --3d --repeats 2              # the 3D cases
    python benchmarks/parallel_nlgs.py --cases "rest 160x100" --steps 10 --repeats 1
    python benchmarks/parallel_nlgs.py --cases "shaken 50x40" --warm 110 --steps 3
    NUMBA_THREADING_LAYER=workqueue python benchmarks/parallel_nlgs.py
"""

import argparse
import collections
import dataclasses
import os
import statistics
import threading
import time

import numba
import numpy as np

import saxum as sx
from saxum.contacts import Contacts
from saxum.ground import harmonic
from saxum.structures import running_bond_wall, wall3d


def _wall(size, amplitude_g):
    model = running_bond_wall(courses=size[0], bricks=size[1], brick_length=0.25,
                              brick_height=0.065, density=1800.0, friction=0.6)
    if amplitude_g > 0.0:
        load = harmonic(amplitude_g * 9.81, 0.5, 4.0).inertial_load()
        model = dataclasses.replace(model, accelerations=(load,))
    return model


def _wall3d(courses, length, amplitude_g):
    """An L wall of saxum.structures.wall3d, two legs `length` [m] long, on a base shaken
    at amplitude_g (2 Hz) along (0.6, 0.8, 0): across the one leg, along the other."""
    model = wall3d(courses=courses, length=length, return_length=length)
    if amplitude_g > 0.0:
        load = harmonic(amplitude_g * 9.81, 0.5, 4.0,
                        direction=(0.6, 0.8, 0.0)).inertial_load()
        model = dataclasses.replace(model, accelerations=(load,))
    return model


CASES = {"rest 160x100": (lambda: _wall((160, 100), 0.0), lambda: _wall((4, 3), 0.0), 5),
         "shaken 50x40": (lambda: _wall((50, 40), 0.7), lambda: _wall((4, 3), 0.7), 150)}
CASES_3D = {"3D rest L 40x12": (lambda: _wall3d(40, 12.0, 0.0),
                                lambda: _wall3d(4, 1.0, 0.0), 5),
            "3D shaken L 20x6": (lambda: _wall3d(20, 6.0, 0.7),
                                 lambda: _wall3d(4, 1.0, 0.7), 40)}
"""name: (model, small model that compiles the kernels, steps before the timed ones: at 0.7 g
the 2D wall slides from about 0.1 s on; the 3D L wall's leg across the motion rocks and
leans from a few hundredths of a second on)"""
VARIANTS = {"serial": {"threads": 1, "domains": 1}, "1 thread": {"threads": 1, "domains": 2},
            "2 threads": {"threads": 2, "domains": 2}}
"""NLGS's settings: the serial kernels (one thread, one domain), NLGS by two domains (what
the default gave every case here on 2 cores while the default domains were the machine's
cores, at most one per 256 free blocks: the figures in BENCHMARKS.md) on 1 and 2 threads."""
STAGES = ("detection", "warm start", "assembly", "solve", "end gaps", "step")


def _timed(owner, name, label, sums):
    inner = getattr(owner, name)

    def timed(*args, **kwargs):
        w, c = time.perf_counter(), time.process_time()
        try:
            return inner(*args, **kwargs)
        finally:
            sums[label] += np.array([time.perf_counter() - w, time.process_time() - c])

    setattr(owner, name, timed)
    return inner


def _thread_times():
    """{thread id: (ns on a CPU, ns waiting for one)} of this process's threads (Linux; {}
    elsewhere)."""
    times = {}
    try:
        for tid in os.listdir("/proc/self/task"):
            with open(f"/proc/self/task/{tid}/schedstat") as f:
                times[int(tid)] = np.array(f.read().split()[:2], dtype=float)
    except OSError:
        return {}
    return times


def _accounting(before, after, steps):
    """(stepping thread's CPU, busiest other thread's, all other threads', stepping
    thread's wait for a CPU) [s] per step between two _thread_times."""
    main = threading.get_native_id()
    spent = {t: (after[t] - before.get(t, 0.0)) * 1e-9 / steps for t in after}
    mine = spent.pop(main, np.zeros(2))
    others = [x[0] for x in spent.values()]
    return np.array([mine[0], max(others, default=0.0), sum(others), mine[1]])


def _run(model, settings, warm, steps):
    """({stage: (wall s, CPU s) per step, "threads": _accounting}, sweeps per step, final
    positions) of NLGS(**settings)."""
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(**settings))
    state = sim.initial_state()
    for _ in range(warm):
        sim.step(state)
    sums = collections.defaultdict(lambda: np.zeros(2))
    for owner, name, label in ((sim.detector, "detect", "detection"),
                               (sim.problem, "assemble", "assembly"),
                               (sim.solver, "solve", "solve"),
                               (sim.problem, "end_gaps", "end gaps"),
                               (sim, "step", "step")):
        _timed(owner, name, label, sums)
    carry = _timed(Contacts, "warm_start_from", "warm start", sums)
    before = _thread_times()
    try:
        for _ in range(steps):
            sim.step(state)
    finally:
        Contacts.warm_start_from = carry
    threads_spent = _accounting(before, _thread_times(), steps)
    sweeps = float(np.mean(sim.log.iterations[warm:]))
    return ({**{k: sums[k] / steps for k in STAGES}, "threads": threads_spent}, sweeps,
            state.body_q.copy())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--cases", default=None,
                        help="comma-separated names (default: all 2D cases, or with --3d "
                             "all 3D ones)")
    parser.add_argument("--3d", dest="three", action="store_true",
                        help="the 3D cases (CASES_3D)")
    parser.add_argument("--warm", type=int, default=None,
                        help="steps before the timed ones (default: the case's)")
    args = parser.parse_args()
    cases = CASES_3D if args.three else CASES
    print(f"numba threads available: {numba.config.NUMBA_NUM_THREADS}; load average "
          f"{os.getloadavg()[0]:.1f} at the start", flush=True)
    for name in (args.cases or ",".join(cases)).split(","):
        build, small, warm = {**CASES, **CASES_3D}[name]
        warm = warm if args.warm is None else args.warm
        model = build()
        for settings in VARIANTS.values():  # compile (or load) every kernel first
            _run(small(), settings, 1, 1)
        rows = {v: [] for v in VARIANTS}
        q = {}
        for _ in range(args.repeats):
            for label, settings in VARIANTS.items():
                *row, q[label] = _run(model, settings, warm, args.steps)
                rows[label].append(row)
        bricks = int((model.body_kind == sx.BodyKind.FREE).sum())
        same = np.array_equal(q["1 thread"], q["2 threads"])
        print(f"\n{name} ({bricks} blocks, {args.steps} steps after {warm}, median of "
              f"{args.repeats}, load average {os.getloadavg()[0]:.1f} at the end); 1 thread == "
              f"2 threads bit for bit: {same}")
        print("| per step [ms], wall (CPU) | " + " | ".join(STAGES) + " | sweeps |")
        print("|---" * (len(STAGES) + 2) + "|")
        med = {}
        for label, r in rows.items():
            med[label] = {k: [statistics.median(x[0][k][i] for x in r) for i in (0, 1)]
                          for k in STAGES}
            cells = " | ".join(f"{1e3 * w:.2f} ({1e3 * c:.2f})" for w, c in med[label].values())
            print(f"| {label} | {cells} | {r[0][1]:.1f} |")
        for top, bottom in (("serial", "2 threads"), ("1 thread", "2 threads"),
                            ("serial", "1 thread")):
            cells = " | ".join(f"{med[top][k][0] / med[bottom][k][0]:.2f}" for k in STAGES)
            print(f"| speed-up {top} / {bottom} (wall) | {cells} | |")
        print("\n| thread times per step [ms] | stepping thread | busiest other | all others "
              "| stepping + busiest | speed-up over serial (estimate) | stepping thread's "
              "wait for a CPU |\n|---|---|---|---|---|---|---|")
        spent = {label: np.median([x[0]["threads"] for x in r], axis=0)
                 for label, r in rows.items()}
        serial = spent["serial"][0] + spent["serial"][1]
        for label, (mine, busiest, others, wait) in spent.items():
            print(f"| {label} | {1e3 * mine:.2f} | {1e3 * busiest:.2f} | {1e3 * others:.2f} | "
                  f"{1e3 * (mine + busiest):.2f} | {serial / (mine + busiest):.2f} | "
                  f"{1e3 * wait:.2f} |")
        print(flush=True)
    print(f"threading layer: {numba.threading_layer()}")


if __name__ == "__main__":
    main()
