"""Anderson acceleration of NLGS in 3D (saxum.solver.nlgs.nlgs_3d_anderson) on the shaken 3D L
wall (benchmarks/convergence.py, wall3d-shaken: 72 bricks under 0.7 g along x, dt 1e-3):

- --npz: its onset step 19 (tests/data/l_wall_step19.npz, 770 contacts) from NLGS's capped
  iterate, plain sweeps (nlgs_3d) and accelerated ones to the tolerance, at most --sweeps:
  sweeps, NLGS's criterion, the natural-map error, |r - r0|, CPU time;
- --steps N: the case's first N steps (300: its 0.3 s) with each of --variants back to back in
  this process: "plain" Hybrid(accelerate=False) (every 3D sweep plain: main's before 3D
  acceleration), "default" Hybrid() (the refinement's sweeps accelerated), "windows" Hybrid()
  with every sweep after its first window accelerated too (an experiment: Hybrid has no
  option for it); steps above the tolerance, the onset steps among them, the solvers that
  finished the steps, sweeps per step, CPU time per step (time.thread_time), largest
  displacement.

    python benchmarks/anderson3d.py --npz
    python benchmarks/anderson3d.py --steps 300 --variants plain,default
"""

import argparse
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))
from convergence import CASES, DT  # noqa: E402  (benchmarks/ is not a package)
from test_l_wall_steps import kernel_problem  # noqa: E402

import saxum as sx  # noqa: E402
from saxum.solver.nlgs import _ANDERSON_DEPTH, nlgs_3d, nlgs_3d_anderson  # noqa: E402


def npz_sweeps(name: str, accelerated: bool, tolerance: float, sweeps: int) -> dict:
    """Sweeps on a stored step from NLGS's iterate (kernel_problem)."""
    p = kernel_problem(name)
    v, impulse = p["v"].copy(), p["impulse"].copy()
    args = (p["cand"], p["ant"], p["h_cand"], p["h_ant"], p["delassus"], p["bias"],
            p["friction"], p["active"], p["count"], p["inv_mass"], p["mass"], p["v_free"], v,
            np.empty_like(v), impulse, np.empty((p["count"], 38)))
    start = time.process_time()
    if accelerated:
        history = (np.empty((_ANDERSON_DEPTH + 2,) + v.shape),
                   np.empty((_ANDERSON_DEPTH + 2, p["count"], 3)))
        done, error = nlgs_3d_anderson(*args, *history, tolerance, sweeps, 1.0)
    else:
        done, error = nlgs_3d(*args, None, None, None, 0, tolerance, sweeps, 1.0)
    cpu = time.process_time() - start
    local = p["local"]
    return {"sweeps": int(done), "error": float(error),
            "natural_map": local.natural_map_error(impulse),
            "moved": float(np.linalg.norm(impulse - p["impulse"])
                           / np.linalg.norm(p["impulse"])), "cpu_s": cpu}


class _Windows(sx.Hybrid):
    """Hybrid with every sweep after its first window accelerated (experiment)."""

    def solve(self, problem, impulse, v_free, v):
        self._more._accelerate_all = True
        return super().solve(problem, impulse, v_free, v)

    def _sweep_to(self, *args):
        out = super()._sweep_to(*args)
        self._more._accelerate_all = True
        return out


VARIANTS = {"plain": lambda: sx.Hybrid(accelerate=False), "default": sx.Hybrid,
            "windows": _Windows}


def l_wall(variant: str, steps: int) -> dict:
    model = CASES["wall3d-shaken"][0]()
    sim = sx.Simulation(model, dt=DT, solver=VARIANTS[variant]())
    state = sim.initial_state()
    cpu = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sx.SolverWarning)
        for _ in range(steps):
            start = time.thread_time()
            sim.step(state)
            cpu.append(time.thread_time() - start)
    log = sim.log
    converged = np.asarray(log.converged)
    above = np.flatnonzero(~converged) + 1
    natural = np.asarray(log.natural_map)[~converged]
    free = model.body_kind == sx.BodyKind.FREE
    moved = np.linalg.norm(state.body_q[free, :3] - model.body_q0[free, :3], axis=1)
    return {"variant": variant, "above": above.tolist(),
            "natural_max": float(np.nanmax(natural)) if natural.size else 0.0,
            "finished": np.bincount(np.asarray(log.solver), minlength=5).tolist(),
            "sweeps_mean": float(np.mean(log.iterations)),
            "cpu_ms_mean": 1e3 * statistics.fmean(cpu[1:]),
            "largest_displacement_m": float(moved.max())}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--npz", action="store_true")
    parser.add_argument("--step", default="l_wall_step19.npz")
    parser.add_argument("--sweeps", type=int, default=50_000)
    parser.add_argument("--tolerance", type=float, default=1e-6)
    parser.add_argument("--steps", type=int, default=0)
    parser.add_argument("--variants", default="plain,default")
    args = parser.parse_args()
    if args.npz:
        npz_sweeps(args.step, True, args.tolerance, 1)  # compile both kernels first
        npz_sweeps(args.step, False, args.tolerance, 1)
        for accelerated in (False, True):
            r = npz_sweeps(args.step, accelerated, args.tolerance, args.sweeps)
            print(f"{args.step} {'Anderson' if accelerated else 'plain':8s}: {r['sweeps']} "
                  f"sweeps, error {r['error']:.3g}, natural map {r['natural_map']:.3g}, "
                  f"|r - r0| / |r0| {r['moved']:.3g}, CPU {r['cpu_s']:.2f} s", flush=True)
    if args.steps:
        l_wall("plain", 2)  # compile (or load) the kernels first
        for variant in args.variants.split(","):
            r = l_wall(variant, args.steps)
            names = ("nlgs", "conic", "newton", "smoothing", "proximal")
            print(f"{variant}: {len(r['above'])} of {args.steps} steps above the tolerance "
                  f"{r['above']}, natural-map error up to {r['natural_max']:.2g}; finished by "
                  + ", ".join(f"{n} {k}" for n, k in zip(names, r["finished"], strict=False) if k)
                  + f"; {r['sweeps_mean']:.0f} sweeps a step, {r['cpu_ms_mean']:.0f} ms of CPU a "
                  f"step; largest displacement {r['largest_displacement_m']:.4f} m", flush=True)


if __name__ == "__main__":
    main()
