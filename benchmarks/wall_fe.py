"""A running-bond wall of deformable bricks against the same wall of rigid bricks, in one run
(issue 14, "Performance"): ms per step (wall and CPU), NLGS sweeps per step, the steps that
took the sticking start (saxum.solver.sticking), those that took it up, its CPU time,
contacts, and the setup (meshing, assembly, M~^-1) of the deformable wall.

    python benchmarks/wall_fe.py --courses 20 --bricks 10 --steps 100 [--pulse 2.0]
    python benchmarks/wall_fe.py --dim 3 --courses 4 --bricks 3 --steps 100

--pulse A: a horizontal acceleration A [m/s^2] of the whole model over the measured steps
(a ground motion felt as inertial forces), after the first step at rest.
--detect N: then N detections of the last state (Detector.detect, the node contacts'
narrow phase among them) timed alone: CPU ms per detection.

Bricks 0.4 x 0.2 m (half bricks at the ends of every other course), E = 10 GPa, nu = 0.2,
2000 kg/m^3, Rayleigh beta = 1e-4 s, mesh 0.05 m; the wall stands on a fixed ground under its
weight from rest, dt = 1 ms (the first steps, in which the joints take up the weight, are the
ones measured: the expensive part of a run at rest). --dim 3: the same wall extruded 0.2 m
deep (saxum.structures.solid.add_extruded: bricks 0.4 x 0.2 x 0.2 m), mesh 0.1 m.
"""

import argparse
import time

import numpy as np

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation
from saxum.solver import nlgs
from saxum.structures.solid import add_extruded
from saxum.structures.wall import add_running_bond_wall


def wall(courses: int, bricks: int, deformable: bool, dim: int = 2,
         pulse: float = 0.0) -> sx.Model:
    b = ModelBuilder()
    add_running_bond_wall(b, courses=courses, bricks=bricks, brick_length=0.4,
                          brick_height=0.2, density=2000.0)
    width = 0.4 * bricks
    b.add_block([(-1.0, -0.3), (width + 1.0, -0.3), (width + 1.0, 0.0), (-1.0, 0.0)],
                kind=BodyKind.FIXED, group="ground")
    if dim == 3:
        plane = b
        plane.set_law("brick", "brick", sx.ContactLaw(friction=0.6))
        plane.set_law("brick", "ground", sx.ContactLaw(friction=0.6))
        b = ModelBuilder(dim=3)
        add_extruded(b, plane.finalize(), 0.2)
    if pulse:  # (on the model built last: the 3D one of an extruded wall)
        b.add_acceleration(lambda t: (pulse if t > 1.5e-3 else 0.0,) + (0.0,) * (dim - 1))
    if deformable:
        b.set_material("brick", Elastic(1.0e10, 0.2, 2000.0, damping=(0.0, 1e-4)),
                       0.05 if dim == 2 else 0.1)
    law = sx.ContactLaw(friction=0.6)
    b.set_law("brick", "brick", law)
    b.set_law("brick", "ground", law)
    return b.finalize()


def run(model: sx.Model, steps: int,
        detections: int = 0) -> tuple[float, float, float, float, float, str]:
    """(setup [s], ms per step, sweeps per step, contacts at the end, CPU ms per step, the
    sticking starts: steps that took one and their CPU ms each, and CPU ms per detection of
    the last state over `detections`)."""
    start = time.perf_counter()
    sim = Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.step(state)  # compiles
    setup = time.perf_counter() - start
    sticking = [0, 0.0]
    solve = nlgs.sticking_solution

    def timed(*args):
        begin = time.process_time()
        out = solve(*args)
        sticking[0] += 1
        sticking[1] += time.process_time() - begin
        return out

    nlgs.sticking_solution = timed
    cpu = time.process_time()
    start = time.perf_counter()
    for _ in range(steps):
        sim.step(state)
    elapsed = time.perf_counter() - start
    cpu = time.process_time() - cpu
    nlgs.sticking_solution = solve
    sweeps = float(np.mean(sim.log.iterations[-steps:]))
    starts = (f"sticking start in {sticking[0]} steps, taken in "
              f"{sim.solver.rest_solutions - (sim.solver.rest_attempts - sticking[0])} "
              f"({1e3 * sticking[1] / max(sticking[0], 1):.0f} CPU ms each)")
    if detections:
        probe = state.contacts.copy()
        node_x = state.node_x if model.fe is not None else None
        begin = time.process_time()
        for _ in range(detections):
            sim.detector.detect(state.body_q, probe, node_x)
        starts += f", {1e3 * (time.process_time() - begin) / detections:.2f} CPU ms/detection"
    return (setup, 1e3 * elapsed / steps, sweeps, float(state.contacts.count),
            1e3 * cpu / steps, starts)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--courses", type=int, default=20)
    parser.add_argument("--bricks", type=int, default=10)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--dim", type=int, choices=(2, 3), default=2)
    parser.add_argument("--pulse", type=float, default=0.0)
    parser.add_argument("--detect", type=int, default=0)
    args = parser.parse_args()
    for deformable in (False, True):
        start = time.perf_counter()
        model = wall(args.courses, args.bricks, deformable, args.dim, args.pulse)
        built = time.perf_counter() - start
        setup, ms, sweeps, contacts, cpu, starts = run(model, args.steps, args.detect)
        nodes = model.fe.node_count if model.fe is not None else 0
        print(f"{'deformable' if deformable else 'rigid':>10}: {model.body_count - 1} bricks, "
              f"{nodes} nodes, model {built:.1f} s, simulation setup {setup:.1f} s, "
              f"{ms:.1f} ms/step ({cpu:.1f} CPU), {sweeps:.0f} sweeps/step, "
              f"{contacts:.0f} contacts, {starts}", flush=True)


if __name__ == "__main__":
    main()
