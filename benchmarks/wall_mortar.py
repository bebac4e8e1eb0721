"""Benchmark: a mortared running-bond wall (cohesive joints, saxum.laws COHESIVE) pushed to
failure, against the same wall with dry joints, in one run.

The wall: --courses x --bricks running bond (25 x 40: 1012 bricks of 0.25 x 0.065 m, 1800
kg/m^3) on a fixed ground, gravity, and a horizontal load m lambda(t) g on every brick with
lambda = --rate t (a tilting table). Dry: Coulomb mu = 0.6 on every joint (the gap law).
Mortared: the same friction plus a bond (k_n = 1e10, k_t = 4e9 Pa/m, f_t = 5 kPa, c = 10 kPa,
G_I = 2, G_II = 10 J/m^2: a weak lime mortar, so that the wall fails within the run). Both
models step with NLGS (its defaults) and Moreau-Jean theta = --theta (1 by default: a bonded
joint is elastic in compression, and under theta = 1/2, which keeps a spring's energy, the
wall settling under gravity rings on its joints for the whole run; saxum.laws, COHESIVE) in
one process, interleaved in chunks of --chunk steps, so that both see the same machine load.

Per model: time per step [ms] (mean over all steps, first step apart; wall and CPU time, user +
sys of the process, which the machine's load changes less), NLGS sweeps per step
(mean, and steps at the cap), the load factor at which a brick first moves by more than a
brick height relative to the ground (failure), and for the mortared wall the share of contacts
fully damaged at the end.

    PYTHONPATH=src python benchmarks/wall_mortar.py                 # 1.5 s at 1 g/s
    PYTHONPATH=src python benchmarks/wall_mortar.py --courses 10 --bricks 10 --duration 0.5
"""

import argparse
import statistics
import time

import numpy as np

import saxum as sx
from saxum.structures.wall import add_grounded_running_bond_wall

GRAVITY = 9.81
MORTAR = dict(kind=sx.LawKind.COHESIVE, k_n=1e10, k_t=4e9, f_t=5e3, cohesion=1e4, g_i=2.0,
              g_ii=10.0)


def wall(courses: int, bricks: int, rate: float, mortar: bool) -> sx.Model:
    b = sx.ModelBuilder(gravity=(0.0, -GRAVITY))
    add_grounded_running_bond_wall(b, courses=courses, bricks=bricks)
    law = sx.ContactLaw(friction=0.6, **(MORTAR if mortar else {}))
    b.set_law("brick", "brick", law)
    b.set_law("brick", "ground", law)
    b.add_acceleration(lambda t: (rate * t * GRAVITY, 0.0))
    return b.finalize()


class Run:
    """One model stepping, with its timings and failure load factor."""

    def __init__(self, name: str, model: sx.Model, dt: float, theta: float,
                 rate: float) -> None:
        self.name = name
        self.rate = rate
        self.sim = sx.Simulation(model, dt=dt, theta=theta)
        self.state = self.sim.initial_state()
        self.q0 = self.state.body_q.copy()
        self.height = 0.065
        self.times: list[float] = []
        self.cpu: list[float] = []
        self.failure = None

    def advance(self, steps: int) -> None:
        for _ in range(steps):
            t0, c0 = time.perf_counter(), time.process_time()
            self.sim.step(self.state)
            self.times.append(time.perf_counter() - t0)
            self.cpu.append(time.process_time() - c0)
            if self.failure is None:
                moved = np.abs(self.state.body_q[:, :2] - self.q0[:, :2]).max()
                if moved > self.height:
                    self.failure = self.rate * self.state.time

    def report(self) -> str:
        log = self.sim.log
        times = self.times[1:]
        c = self.state.contacts
        cracked = (f", {np.mean(c.damage[: c.count] >= 1.0):.0%} of contacts cracked"
                   if self.name == "mortared" else "")
        failure = "none" if self.failure is None else f"{self.failure:.3f}"
        return (f"{self.name:9s} {self.sim.model.body_count - 1} bricks: "
                f"{1e3 * statistics.fmean(times):.2f} ms/step (median "
                f"{1e3 * statistics.median(times):.2f}; CPU "
                f"{1e3 * statistics.fmean(self.cpu[1:]):.2f}), {np.mean(log.iterations):.1f} "
                f"sweeps/step, {int(np.sum(~log.converged))} steps not converged, failure at "
                f"lambda = {failure}{cracked}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--courses", type=int, default=25)
    parser.add_argument("--bricks", type=int, default=40)
    parser.add_argument("--duration", type=float, default=1.5, help="[s]")
    parser.add_argument("--rate", type=float, default=1.0, help="d(lambda)/dt [1/s]")
    parser.add_argument("--dt", type=float, default=1e-3, help="[s]")
    parser.add_argument("--theta", type=float, default=1.0, help="Moreau-Jean theta")
    parser.add_argument("--chunk", type=int, default=50, help="steps per turn")
    args = parser.parse_args()
    runs = [Run(name, wall(args.courses, args.bricks, args.rate, name == "mortared"), args.dt,
                args.theta, args.rate) for name in ("dry", "mortared")]
    steps = round(args.duration / args.dt)
    done = 0
    while done < steps:
        n = min(args.chunk, steps - done)
        for run in runs:
            run.advance(n)
        done += n
    print(f"{steps} steps of {args.dt:g} s, theta = {args.theta:g}, lambda up to "
          f"{args.rate * args.duration:g}, interleaved in chunks of {args.chunk}")
    for run in runs:
        print(run.report())
    dry, mortared = (statistics.fmean(r.times[1:]) for r in runs)
    cpu_dry, cpu_mortared = (statistics.fmean(r.cpu[1:]) for r in runs)
    print(f"time per step, mortared / dry: {mortared / dry:.2f} (CPU time: "
          f"{cpu_mortared / cpu_dry:.2f})")


if __name__ == "__main__":
    main()
