"""Rigid limit of deformable voussoirs (issue 14, "Rigid limit"): the horizontal collapse load
factor of the 15-voussoir semicircular arch (centre-line radius 1 m, t = 0.15 m, mu = 1) with
rigid voussoirs and with deformable ones of decreasing Young's modulus E.

Each factor is a bisection on lambda (the same for every case): gravity at once, the
horizontal load lambda g ramped linearly over `--ramp` seconds (a sudden load would excite the
elastic arch), then held for 1 s; a trial collapses when a block's frame has moved by more
than 1 % of the smallest block's size. Deformable voussoirs: nu = 0.2, rho = 2000 kg/m^3,
Rayleigh beta = 1e-4 s, mesh size `--mesh`. Prints lambda and lambda / lambda_limit
(tests/validation/limit_analysis.py, the rigid-block kinematic limit analysis).

    python benchmarks/fe_arch_rigid_limit.py --E 0 1e12 1e10 1e9 --mesh 0.075 --ramp 0.8

(E = 0: rigid voussoirs.) Near the limit the elastic arch rocks on its partly open joints with
almost no damping, and a short ramp excites it: finer meshes (softer hinges) need a longer
ramp before the factor settles (BENCHMARKS.md, "Mesh and ramp").
"""

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation
from saxum.structures.arch import add_semicircular_arch

sys.path.insert(0, str(Path(__file__).parents[1] / "tests" / "validation"))
from limit_analysis import semicircular_four_hinge  # noqa: E402


def arch(young: float, mesh: float) -> sx.Model:
    """The arch on a fixed support; young = 0: rigid voussoirs."""
    b = ModelBuilder()
    add_semicircular_arch(b, radius=1.0, thickness=0.15, voussoirs=15)
    b.add_block([(-1.5, -0.2), (1.5, -0.2), (1.5, 0), (-1.5, 0)], kind=BodyKind.FIXED,
                group="support")
    if young:
        b.set_material("voussoir", Elastic(young, 0.2, 2000.0, damping=(0.0, 1e-4)), mesh)
    law = sx.ContactLaw(friction=1.0)
    b.set_law("voussoir", "voussoir", law)
    b.set_law("voussoir", "support", law)
    return b.finalize()


def collapses(model: sx.Model, factor: float, ramp: float, dt: float = 1e-3) -> bool:
    """Whether the arch collapses under factor g, ramped over `ramp` [s] and held 1 s."""
    loaded = dataclasses.replace(
        model, accelerations=((lambda t: (factor * 9.81 * min(1.0, t / ramp), 0.0)),))
    sim = Simulation(loaded, dt=dt)
    state = sim.initial_state()
    limit = 0.01 * float(model.body_size[model.body_kind != BodyKind.FIXED].min())
    for _ in range(round((ramp + 1.0) / dt)):
        sim.step(state)
        if np.abs(state.body_q[:, :2] - model.body_q0[:, :2]).max() > limit:
            return True
    return False


def critical(model: sx.Model, low: float, high: float, tolerance: float, ramp: float) -> float:
    """Bisection between a factor that stands (low) and one that collapses (high)."""
    if collapses(model, low, ramp) or not collapses(model, high, ramp):
        raise SystemExit(f"the bracket {low:.4f} .. {high:.4f} does not hold the collapse")
    while high - low > tolerance:
        mid = 0.5 * (low + high)
        if collapses(model, mid, ramp):
            high = mid
        else:
            low = mid
    return 0.5 * (low + high)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--E", type=float, nargs="+", default=[0.0, 1e10])
    parser.add_argument("--mesh", type=float, default=0.075)
    parser.add_argument("--ramp", type=float, default=0.8)
    parser.add_argument("--bracket", type=float, nargs=2, default=[0.8, 1.2],
                        help="the bisection's start, as fractions of the limit-analysis factor")
    args = parser.parse_args()
    reference, _ = semicircular_four_hinge(1.0, 0.15, 15)
    print(f"limit analysis (rigid blocks): lambda = {reference:.5f}")
    for young in args.E:
        start = time.perf_counter()
        factor = critical(arch(young, args.mesh), args.bracket[0] * reference,
                          args.bracket[1] * reference, 0.002 * reference, args.ramp)
        kind = "rigid" if not young else f"E = {young:.3g} Pa"
        print(f"{kind:>16}: lambda = {factor:.5f} = {factor / reference:.4f} of the limit "
              f"({time.perf_counter() - start:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
