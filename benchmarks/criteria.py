"""NLGS's convergence criteria side by side (issue 18): saxum's "delassus" and LMGC90's
"quad", "maxm", "qm/16" (saxum.solver.NLGS(criterion=...), docs/criteria.md) at several
tolerances, on structures at rest from the cold start: the drift they leave (the largest
displacement of a block [m], which is zero in the exact solution of a structure at rest),
the sweeps per step and the time per step.

    python benchmarks/criteria.py                           # arch and wall512, 1 s each
    python benchmarks/criteria.py --cases arch --duration 2 --tolerances 1e-4,1.666e-4

Cases (dt = 1e-3 s, theta = 0.5, NLGS alone with its default rest_after):
- arch: semicircular arch of 15 voussoirs, R = 1 m, t/R = 0.15, density 2000 kg/m^3,
  mu = 0.6, on fixed supports (benchmarks/convergence.py's);
- wall512: running-bond wall of 25 x 20 bricks 0.25 x 0.065 m, 1800 kg/m^3, mu = 0.6, at rest.
Kernels are compiled (a short warm-up run of each criterion) before the clock starts; all
rows come from one process, so their times compare. JSON: benchmarks/results/criteria.json.
"""

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import saxum as sx
from saxum.solver.nlgs import CRITERIA
from saxum.structures import running_bond_wall, semicircular_arch

DT = 1e-3
CASES = {
    "arch": lambda: semicircular_arch(radius=1.0, thickness=0.15, voussoirs=15,
                                      density=2000.0, friction=0.6),
    "wall512": lambda: running_bond_wall(courses=25, bricks=20),
}


def run(case: str, criterion: str, tolerance: float, duration: float) -> dict:
    """One run of `case` with NLGS(criterion, tolerance): drift, sweeps and time per step."""
    model = CASES[case]()
    solver = sx.NLGS(tolerance=tolerance, criterion=criterion)
    sim = sx.Simulation(model, dt=DT, solver=solver)
    state = sim.initial_state()
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sx.SolverWarning)
        sim.run(state, duration)
    wall = time.perf_counter() - start
    log = sim.log
    sweeps = np.asarray(log.iterations)
    free = model.body_kind == sx.BodyKind.FREE
    moved = np.linalg.norm(state.body_q[free, :model.dim] - model.body_q0[free, :model.dim],
                           axis=1)
    return {"case": case, "criterion": criterion, "tolerance": tolerance,
            "steps": len(sweeps), "drift_max_m": float(moved.max()),
            "sweeps_mean": float(sweeps.mean()), "sweeps_first": int(sweeps[0]),
            "not_converged": int(np.count_nonzero(~np.asarray(log.converged))),
            "rest_attempts": solver.rest_attempts, "rest_solutions": solver.rest_solutions,
            "ms_per_step": 1e3 * wall / len(sweeps)}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cases", default="arch,wall512")
    p.add_argument("--criteria", default=",".join(CRITERIA))
    p.add_argument("--tolerances", default="1e-6,1e-4,1.666e-4")
    p.add_argument("--duration", type=float, default=1.0)
    p.add_argument("--json", default="benchmarks/results/criteria.json")
    args = p.parse_args()
    criteria = args.criteria.split(",")
    for criterion in criteria:  # compile before the clock (the rest solution's too)
        for tolerance in (1e-6, 1e-4):
            run("arch", criterion, tolerance, 0.005)
    rows = []
    print(f"{'case':8} {'criterion':9} {'tol':>9} {'drift [m]':>10} {'sweeps':>8} "
          f"{'first':>6} {'not conv':>8} {'rest':>7} {'ms/step':>8}")
    for case in args.cases.split(","):
        for tolerance in (float(t) for t in args.tolerances.split(",")):
            for criterion in criteria:
                r = run(case, criterion, tolerance, args.duration)
                rows.append(r)
                print(f"{case:8} {criterion:9} {tolerance:9.4g} {r['drift_max_m']:10.3g} "
                      f"{r['sweeps_mean']:8.1f} {r['sweeps_first']:6d} {r['not_converged']:8d} "
                      f"{r['rest_solutions']:3d}/{r['rest_attempts']:<3d} "
                      f"{r['ms_per_step']:8.3f}", flush=True)
    out = Path(args.json)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"rows": rows, "duration_s": args.duration}, indent=1))


if __name__ == "__main__":
    main()
