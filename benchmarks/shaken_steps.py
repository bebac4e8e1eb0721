"""Per-step study of the shaken 512-brick wall of benchmarks/shaken_wall.py (the same model,
base motion and solver defaults): for each step its sweeps, error, outcome, the solver that
finished it, the sweeps of its refinement (saxum.solver.nlgs.Refinement) and whether it was
an onset, the CPU time of the step, and the wall's state after it (the bottom course's mean
displacement against Newmark's sliding block, the spread of the bricks' horizontal
velocities around their mean: the drift between courses that inexact steps leave). Prints
the capped steps, the first of them in context, and the cost by phase of Newmark's block
(stuck / sliding); --json keeps every column.

    python benchmarks/shaken_steps.py                                # 0.7 g, 2 s, NLGS
    python benchmarks/shaken_steps.py --solver hybrid --duration 1
    python benchmarks/shaken_steps.py --set refine=0 --set tolerance=1e-7
"""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests" / "validation"))
from shaken_wall import FREQUENCY, _motion  # noqa: E402  (benchmarks/ is not a package)
from test_shaken_wall import newmark_sine  # noqa: E402
from wall import BRICK_HEIGHT, BRICK_LENGTH, DENSITY, FRICTION, GRAVITY, SMALL  # noqa: E402


def _value(text: str):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def run(amplitude_g: float, duration: float, dt: float, solver_name: str,
        options: dict) -> dict:
    import dataclasses

    import saxum as sx
    from saxum.solver import nlgs
    from saxum.structures import running_bond_wall

    model = running_bond_wall(courses=SMALL[0], bricks=SMALL[1], brick_length=BRICK_LENGTH,
                              brick_height=BRICK_HEIGHT, density=DENSITY, friction=FRICTION)
    if amplitude_g > 0.0:
        model = dataclasses.replace(
            model, accelerations=(_motion(amplitude_g, duration).inertial_load(),))
    warm = sx.Simulation(model, dt=dt)  # compile (or load) the kernels first
    state = warm.initial_state()
    for _ in range(3):
        warm.step(state)
    solver = {"nlgs": sx.NLGS, "hybrid": sx.Hybrid}[solver_name](**options)
    refined = {"sweeps": 0, "onset": False}
    step_of = nlgs.Refinement.step

    def recorded(self, solver, sweeps, iterations, error, converged):
        done, error = step_of(self, solver, sweeps, iterations, error, converged)
        refined["sweeps"] += done
        refined["onset"] |= self.carrying and iterations >= nlgs._ONSET_SWEEPS
        return done, error

    nlgs.Refinement.step = recorded
    sim = sx.Simulation(model, dt=dt, solver=solver)
    state = sim.initial_state()
    free = model.body_kind == sx.BodyKind.FREE
    q0 = state.body_q[free].copy()
    bottom = np.abs(q0[:, 1] - 0.5 * BRICK_HEIGHT) < 1e-9
    steps = round(duration / dt)
    cols = {k: np.zeros(steps) for k in ("cpu", "refined", "onset", "bottom", "newmark",
                                         "spread", "velocity")}
    for k in range(steps):
        refined["sweeps"], refined["onset"] = 0, False
        c0 = time.thread_time()
        sim.step(state)
        cols["cpu"][k] = time.thread_time() - c0
        cols["refined"][k], cols["onset"][k] = refined["sweeps"], refined["onset"]
        dx = state.body_q[free, 0] - q0[:, 0]
        vx = state.body_v[free, 0]
        cols["bottom"][k] = dx[bottom].mean()
        cols["velocity"][k] = vx.mean()
        cols["spread"][k] = np.abs(vx - vx.mean()).max()
        cols["newmark"][k] = (newmark_sine(amplitude_g * GRAVITY, FREQUENCY, FRICTION, GRAVITY,
                                           state.time) if amplitude_g * GRAVITY > FRICTION
                              * GRAVITY else 0.0)
    log = sim.log
    out = {k: v.tolist() for k, v in cols.items()}
    out.update(sweeps=log.iterations.tolist(), error=log.error.tolist(),
               converged=log.converged.tolist(), solver=log.solver.tolist(),
               outcome=log.outcome.tolist(), max_iterations=solver.max_iterations,
               largest_displacement=float(np.abs(state.body_q[free, 0] - q0[:, 0]).max()),
               why=log.why())
    return out


def report(r: dict, dt: float) -> None:
    sweeps = np.array(r["sweeps"])
    cpu = np.array(r["cpu"]) * 1e3
    capped = np.flatnonzero(~np.array(r["converged"], dtype=bool))
    slide = np.abs(np.diff(np.r_[0.0, r["newmark"]])) > 0.0
    print(f"steps {len(sweeps)}, sweeps per step {sweeps.mean():.1f}, refinement's "
          f"{np.mean(r['refined']):.1f}, onsets {int(np.sum(r['onset']))}, CPU ms/step "
          f"{cpu[1:].mean():.2f} (median {np.median(cpu[1:]):.2f}), not converged "
          f"{len(capped)}, finished by {np.bincount(r['solver'], minlength=4).tolist()}")
    for name, mask in (("Newmark's block sliding", slide), ("stuck", ~slide)):
        print(f"  {name}: {int(mask.sum())} steps, {sweeps[mask].sum()} sweeps, CPU "
              f"{cpu[mask].sum() / 1e3:.1f} s, not converged "
              f"{int(np.isin(capped, np.flatnonzero(mask)).sum())}")
    print(f"  bottom course - Newmark at the end {1e3 * (r['bottom'][-1] - r['newmark'][-1]):+.4f}"
          f" mm, largest |dx| {1e3 * r['largest_displacement']:.4f} mm, largest velocity spread"
          f" {max(r['spread']):.2e} m/s")
    print(f"  not converged at steps: {capped.tolist()}")
    print(f"  {r['why']}")
    print(f"{'step':>5} {'t':>6} {'sweeps':>6} {'refined':>7} {'onset':>5} {'error':>8} "
          f"{'solver':>6} {'cpu ms':>7} {'bottom-NM mm':>12} {'spread m/s':>10} {'slide':>5}")
    first = capped[0] if len(capped) else int(np.argmax(sweeps))
    shown = set(range(max(first - 15, 0), min(first + 10, len(sweeps))))
    shown |= set(capped.tolist())
    shown |= set(np.flatnonzero(np.array(r["onset"]) > 0).tolist())
    for k in sorted(shown):
        print(f"{k:>5} {(k + 1) * dt:>6.3f} {sweeps[k]:>6} {int(r['refined'][k]):>7} "
              f"{int(r['onset'][k]):>5} {r['error'][k]:>8.1e} {r['solver'][k]:>6} "
              f"{cpu[k]:>7.1f} {1e3 * (r['bottom'][k] - r['newmark'][k]):>+12.5f} "
              f"{r['spread'][k]:>10.2e} {int(slide[k]):>5}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--amplitude", type=float, default=0.7, help="A / g (default 0.7)")
    parser.add_argument("--duration", type=float, default=2.0, help="[s] (default 2)")
    parser.add_argument("--dt", type=float, default=1e-3, help="[s] (default 1e-3)")
    parser.add_argument("--solver", choices=("nlgs", "hybrid"), default="nlgs")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="a solver option (saxum.NLGS, saxum.Hybrid), repeatable")
    parser.add_argument("--json", type=Path, default=None, help="write every column here")
    args = parser.parse_args(argv)
    options = {k: _value(v) for k, v in (s.split("=", 1) for s in args.set)}
    r = run(args.amplitude, args.duration, args.dt, args.solver, options)
    report(r, args.dt)
    if args.json:
        args.json.write_text(json.dumps(r))
    return 0


if __name__ == "__main__":
    sys.exit(main())
