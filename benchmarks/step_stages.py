"""Benchmark: where a step's time goes, the 512-brick wall of benchmarks/shaken_wall.py at rest
and on its shaking base (NLGS, dt 1e-3 s).

Each stage of Simulation.step (detection, assembly, the solver and, inside it, NLGS's sweeps,
the load following's start and the rest solution, the loads of the step...) is wrapped with a
timer of the stepping thread's CPU time (time.thread_time, which a loaded machine changes less
than wall time), summed over the steps after the first and divided by their number. The
wrappers add a few microseconds per call: compare stages and cases within one run, and the
totals with shaken_wall.py's. Run it with another source tree first on PYTHONPATH to compare.

    python benchmarks/step_stages.py                      # A = 0 and 0.3 g, 2000 steps
    python benchmarks/step_stages.py --amplitudes 0,0.3 --steps 1000 --repeats 3
"""

import argparse
import collections
import dataclasses
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from shaken_wall import _motion  # noqa: E402  (benchmarks/ is not a package)
from wall import BRICK_HEIGHT, BRICK_LENGTH, DENSITY, FRICTION, SMALL  # noqa: E402

import saxum as sx  # noqa: E402
import saxum.solver.nlgs as nlgs  # noqa: E402
from saxum.structures import running_bond_wall  # noqa: E402


def _timed(owner, name: str, label: str, sums: collections.Counter) -> None:
    """Wrap owner.name so that its calls add their CPU time [s] to sums[label]."""
    inner = getattr(owner, name)

    def timed(*args, **kwargs):
        start = time.thread_time()
        try:
            return inner(*args, **kwargs)
        finally:
            sums[label] += time.thread_time() - start

    setattr(owner, name, timed)


def stages(amplitude_g: float, steps: int, dt: float = 1e-3) -> dict:
    """CPU time per step [s] of each stage, and in all, after the first step."""
    model = running_bond_wall(courses=SMALL[0], bricks=SMALL[1], brick_length=BRICK_LENGTH,
                              brick_height=BRICK_HEIGHT, density=DENSITY, friction=FRICTION)
    if amplitude_g > 0.0:
        load = _motion(amplitude_g, steps * dt).inertial_load()
        model = dataclasses.replace(model, accelerations=(load,))
    sums = collections.Counter()
    sim = sx.Simulation(model, dt=dt, solver=sx.NLGS())
    for owner, name, label in (
            (nlgs, "nlgs_2d", "solve: NLGS sweeps (packing included)"),
            (nlgs, "rest_solution", "solve: rest solution"),
            (sim.detector, "detect", "detection"),
            (sim.problem, "assemble", "assembly and warm start"),
            (sim.problem, "end_gaps", "end-of-step gaps"),
            (sim, "_step_force", "loads of the step"),
            (sim.projection, "project", "position projection"),
            (sim.solver, "solve", "solve (all)")):
        _timed(owner, name, label, sums)
    following = getattr(sim.solver, "_following", None)
    if following is not None:
        _timed(following, "start", "solve: load following's start", sums)
        _timed(following, "record", "solve: load following's record", sums)
    state = sim.initial_state()
    sim.step(state)  # the cold start (and any compilation) apart
    sums.clear()
    start = time.thread_time()
    for _ in range(steps - 1):
        sim.step(state)
    per_step = {label: total / (steps - 1) for label, total in sums.items()}
    per_step["step (all)"] = (time.thread_time() - start) / (steps - 1)
    per_step["sweeps per step"] = float(sim.log.iterations[1:].mean())
    per_step["rest solutions"] = sim.solver.rest_solutions
    return per_step


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--amplitudes", default="0,0.3", help="A / g, comma-separated")
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=1,
                        help="cases run in turn this many times; the least per stage is kept")
    args = parser.parse_args(argv)
    amplitudes = [float(a) for a in args.amplitudes.split(",")]
    stages(amplitudes[0], 10)  # compile (or load) the kernels
    best = {}
    for _ in range(args.repeats):
        for a in amplitudes:
            for label, value in stages(a, args.steps).items():
                best[(a, label)] = min(best.get((a, label), value), value)
    labels = sorted({label for _, label in best}, key=lambda x: (x.startswith("step"), x))
    print(f"saxum {sx.__file__}; CPU per step [us], least of {args.repeats} run(s)")
    print(f"{'stage':40s}" + "".join(f"{f'A = {a:g} g':>12s}" for a in amplitudes))
    for label in labels:
        values = [best.get((a, label)) for a in amplitudes]
        scale = 1.0 if label in ("sweeps per step", "rest solutions") else 1e6
        print(f"{label:40s}" + "".join(f"{'-' if v is None else f'{v * scale:.1f}':>12s}"
                                       for v in values))
    return 0


if __name__ == "__main__":
    sys.exit(main())
