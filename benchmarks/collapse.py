"""Benchmark of the collapse analyses: a load-to-collapse bisection on the 15-voussoir arch,
a 1000-brick wall brought to rest, and the pulse collapse curve of the 15-voussoir arch.

    python benchmarks/collapse.py [--json benchmarks/results/collapse.json] [--processes 2,1]

Prints and writes as JSON: for the arch (R = 1 m, t/R = 0.15, mu = 1), the horizontal collapse
load factor found by bisection to 0.5 %, the number of trials, simulated and wall time; for
the wall (40 courses of 25 bricks, 1000 bricks + halves, built touching, at rest under gravity
from a cold start), the simulated time until saxum.collapse judges it at rest, the wall time,
NLGS sweeps per step (mean, max) and the time per step; for the pulse collapse curve of
examples/shake_table_arch.toml (15 voussoirs, R = 1 m, t/R = 0.15, mu = 0.7; one-sine pulses of
10 periods from 0.25 to 6 s, amplitude bisected from [0.5, 25] m/s^2 to 2 %, trials judged 2 s
after the pulse), the wall time with the periods spread over 2 worker processes and with 1,
and the amplitudes found. Kernels are compiled (a warm-up run) before the clock starts.
"""

import argparse
import dataclasses
import json
import os
import platform
import resource
import time
from pathlib import Path

import numpy as np

import saxum as sx
from saxum.collapse import (
    DYNAMIC_FRACTION,
    CollapseCriterion,
    collapse_curve,
    critical_value,
    run_trial,
)
from saxum.scenario import load_scenario
from saxum.structures import running_bond_wall, semicircular_arch


def arch_bisection() -> dict:
    model = semicircular_arch(radius=1.0, thickness=0.15, voussoirs=15, friction=1.0)
    g = float(np.hypot(*model.gravity))

    def make(factor):
        loaded = dataclasses.replace(model, accelerations=((lambda t: (factor * g, 0.0)),))
        return sx.Simulation(loaded, dt=1e-3)

    run_trial(make(0.05), 0.05, CollapseCriterion(duration=0.05))  # compile
    start = time.perf_counter()
    result = critical_value(make, 0.05, 0.5, tolerance=0.005)
    wall = time.perf_counter() - start
    return {"load_factor": result.value, "bracket": [result.stands, result.collapses],
            "trials": len(result.trials),
            "simulated_s": sum(t.time for t in result.trials), "wall_s": wall}


def wall_to_rest(courses: int = 40, bricks: int = 25) -> dict:
    model = running_bond_wall(courses=courses, bricks=bricks)
    run_trial(sx.Simulation(running_bond_wall(courses=2, bricks=2), dt=1e-3))  # compile
    sim = sx.Simulation(model, dt=1e-3)
    start = time.perf_counter()
    trial = run_trial(sim, criterion=CollapseCriterion(duration=2.0))
    wall = time.perf_counter() - start
    it = sim.log.iterations
    return {"bricks": int((model.body_kind == sx.BodyKind.FREE).sum()),
            "contacts": int(sim.log.contacts[-1]), "at_rest": not trial.collapsed,
            "time_to_rest_s": trial.time, "wall_s": wall, "steps": len(sim.log),
            "ms_per_step": 1e3 * wall / len(sim.log), "sweeps_mean": float(it.mean()),
            "sweeps_first": int(it[0]), "sweeps_max_after_first": int(it[1:].max(initial=0)),
            "not_converged": int((~sim.log.converged).sum()),
            "largest_displacement_m": trial.displacement}


SHAKE_TABLE_ARCH = Path(__file__).resolve().parents[1] / "examples" / "shake_table_arch.toml"
PERIODS = (0.25, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0)


def pulse_curve(processes: int) -> dict:
    """The collapse curve of the shaking-table arch over PERIODS on `processes` workers."""
    criterion = CollapseCriterion(duration=2.0, fraction=DYNAMIC_FRACTION)
    # compile (the workers then load the kernels from numba's cache)
    run_trial(load_scenario(SHAKE_TABLE_ARCH).build_simulation(),
              criterion=CollapseCriterion(duration=0.05))
    cpu = _cpu_seconds()
    start = time.perf_counter()
    rows = collapse_curve(SHAKE_TABLE_ARCH, PERIODS, 0.5, 25.0, tolerance=0.02,
                          criterion=criterion, processes=processes)
    wall = time.perf_counter() - start
    cpu = _cpu_seconds() - cpu
    return {"processes": processes, "cpus": os.cpu_count(), "periods_s": list(PERIODS),
            "amplitude_g": [p.amplitude / 9.81 for p in rows],
            "trials": sum(p.trials for p in rows), "wall_s": wall, "cpu_s": cpu,
            "load_average_1min_after": os.getloadavg()[0]}


def _cpu_seconds() -> float:
    """User + system CPU time [s] of this process and of its finished children (the worker
    processes of a collapse curve are counted once the pool has shut down)."""
    own, children = (resource.getrusage(who) for who in (resource.RUSAGE_SELF,
                                                          resource.RUSAGE_CHILDREN))
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", type=Path, default=Path("benchmarks/results/collapse.json"))
    parser.add_argument("--processes", default="2,1",
                        help="worker counts for the pulse collapse curve, comma separated")
    parser.add_argument("--parts", default="arch,wall,pulse",
                        help="which benchmarks to run (arch, wall, pulse), comma separated")
    args = parser.parse_args()
    parts = args.parts.split(",")
    out = {"machine": f"{platform.processor() or platform.machine()}, "
                      f"{platform.platform()}, python {platform.python_version()}"}
    if "arch" in parts:
        a = out["arch_bisection"] = arch_bisection()
        print(f"arch 15 voussoirs t/R 0.15: lambda = {a['load_factor']:.4f} "
              f"({a['bracket'][0]:.4f} .. {a['bracket'][1]:.4f}), {a['trials']} trials, "
              f"{a['simulated_s']:.2f} s simulated in {a['wall_s']:.2f} s")
    if "wall" in parts:
        w = out["wall_to_rest"] = wall_to_rest()
        print(f"wall {w['bricks']} bricks, {w['contacts']} contacts: at rest {w['at_rest']} "
              f"after {w['time_to_rest_s']:.3f} s simulated, {w['wall_s']:.2f} s wall "
              f"({w['steps']} steps, {w['ms_per_step']:.2f} ms/step); sweeps first "
              f"{w['sweeps_first']}, mean {w['sweeps_mean']:.1f}, max after the first "
              f"{w['sweeps_max_after_first']}; not converged {w['not_converged']}")
    if "pulse" in parts:
        out["pulse_curve"] = [pulse_curve(int(n)) for n in args.processes.split(",")]
        for c in out["pulse_curve"]:
            print(f"pulse collapse curve, arch 15 voussoirs, {len(c['periods_s'])} periods: "
                  f"{c['trials']} trials in {c['wall_s']:.1f} s wall on {c['processes']} "
                  f"process(es), {c['cpu_s']:.1f} s CPU ({c['cpu_s'] / c['wall_s']:.2f} cores "
                  f"busy on average; {c['cpus']} CPUs, load average "
                  f"{c['load_average_1min_after']:.1f} after); amplitudes [g] "
                  + ", ".join(f"{a:.3f}" for a in c["amplitude_g"]))
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
