"""saxum on LMGC90's POLYF vault (RIGID_3D/POLYF/Vault; tests/data/lmgc90/vault3d, written
by examples/lmgc90_vault.py): the import, and the run through the scenario path with the
example's command.py settings (dt 1e-3 s, theta 0.5, NLGS 'QM/16' 1.666e-4, at most 1000
sweeps), over the example's 10 steps and over 0.3 s, at rest.

    python benchmarks/lmgc90_vault.py

Prints the import's time, then per run: time per step and CPU time per step (the process's,
which a loaded machine changes less), NLGS sweeps per step (mean, max), rest solutions found
/ attempted, contacts at the end and the deepest drop of a free stone. Kernels are compiled
by a short run first. JSON: benchmarks/results/lmgc90_vault.json.
"""

import json
import tempfile
import time
from pathlib import Path

import numpy as np

from saxum.lmgc90 import import_lmgc90
from saxum.model import BodyKind
from saxum.scenario import load_scenario

VAULT = Path(__file__).resolve().parents[1] / "tests" / "data" / "lmgc90" / "vault3d"
SOLVER = ["solver.theta=0.5", 'solver.criterion="qm/16"', "solver.tolerance=1.666e-4",
          "solver.max_iterations=1000"]


def run(scenario: Path, steps: int) -> dict:
    sim = load_scenario(scenario, SOLVER).build_simulation()
    state = sim.initial_state()
    start, cpu = time.perf_counter(), time.process_time()
    sim.run(state, steps * 1e-3)  # the scenario's dt
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    m = sim.model
    free = m.body_kind == BodyKind.FREE
    sweeps = np.asarray(sim.log.iterations)
    return {"steps": len(sweeps), "ms_per_step": 1e3 * wall / len(sweeps),
            "cpu_ms_per_step": 1e3 * cpu / len(sweeps),
            "sweeps_mean": float(sweeps.mean()), "sweeps_max": int(sweeps.max()),
            "rest_solutions": sim.solver.rest_solutions,
            "rest_attempts": sim.solver.rest_attempts, "contacts": int(state.contacts.count),
            "deepest_drop_m": float((m.body_q0[free, 2] - state.body_q[free, 2]).max())}


def main() -> None:
    start, cpu = time.perf_counter(), time.process_time()
    imported = import_lmgc90(VAULT)
    imported.model()
    took = {"import_s": time.perf_counter() - start, "import_cpu_s": time.process_time() - cpu}
    print(f"import + model: {took['import_s']:.2f} s ({took['import_cpu_s']:.2f} s CPU), "
          f"{len(imported.blocks)} stones")
    with tempfile.TemporaryDirectory() as folder:
        scenario = Path(folder) / "vault.toml"
        imported.write_scenario(scenario, duration=0.3, overlap_tolerance=1e-3)
        run(scenario, 3)  # compile
        rows = {steps: run(scenario, steps) for steps in (10, 300)}
    for steps, r in rows.items():
        print(f"{steps:4d} steps: {r['ms_per_step']:.2f} ms/step, {r['cpu_ms_per_step']:.2f} "
              "CPU; "
              f"sweeps {r['sweeps_mean']:.1f} mean, {r['sweeps_max']} max; rest "
              f"{r['rest_solutions']}/{r['rest_attempts']}; {r['contacts']} contacts; deepest "
              f"drop {r['deepest_drop_m']:.2g} m")
    out = Path("benchmarks/results/lmgc90_vault.json")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({**took, "runs": rows}, indent=1))


if __name__ == "__main__":
    main()
