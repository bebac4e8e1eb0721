"""Benchmark of saxum ensemble: the 15-voussoir arch of examples/shake_table_arch.toml through
N FEMA P695 far-field components x M scale factors (multiple stripes), on a local Dask
cluster of 1 and of 2 worker processes, back to back.

    python benchmarks/ensemble.py [--records 4] [--scales 0.5,1,1.5] [--end 5]
                                  [--workers 1,2] [--json benchmarks/results/ensemble.json]

Each record is cut to its first `--end` seconds (loads.ground_motion.end) and each run lasts
that plus 1 s. Prints and writes as JSON, per worker count: the wall time of the ensemble
(from the cluster's start to the last row written), runs per second, the CPU time (user +
sys) of the client and of the worker processes, and the collapses found; and the speed-up
from the first worker count to the others. The kernels are compiled before (a warm-up run
in this process, which fills numba's cache for the workers).
"""

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

import psutil

from saxum import ensemble as ens
from saxum.records import fema_p695_records
from saxum.scenario import load_scenario

ARCH = Path(__file__).resolve().parents[1] / "examples" / "shake_table_arch.toml"


def _cpu(process: psutil.Process) -> float:
    """User + sys CPU time [s] of a process and of its living descendants."""
    total = 0.0
    for p in [process, *process.children(recursive=True)]:
        try:
            t = p.cpu_times()
            total += t.user + t.system
        except psutil.NoSuchProcess:
            pass
    return total


def measure(scenario, records, workers: int, folder: Path) -> dict:
    me = psutil.Process()
    cpu0 = _cpu(me)
    start = time.perf_counter()
    client = ens.connect(workers=workers)
    try:
        summary = ens.run_ensemble(scenario, folder / f"arch-{workers}.h5", records=records,
                                   client=client, quiet=True, overwrite=True)
        wall = time.perf_counter() - start
        cpu = _cpu(me) - cpu0  # (before the workers end: their time is counted while alive)
    finally:
        cluster = client.cluster
        client.close()
        cluster.close()
    runs = ens.read_ensemble(summary.path).runs
    return {"workers": workers, "runs": summary.runs, "failed": summary.failed,
            "wall_s": round(wall, 2), "runs_per_s": round(summary.runs / wall, 3),
            "cpu_s": round(cpu, 2), "collapses": int((runs["collapsed"] == 1).sum())}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--records", type=int, default=4)
    parser.add_argument("--scales", default="0.5,1,1.5")
    parser.add_argument("--end", type=float, default=5.0)
    parser.add_argument("--workers", default="1,2")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    scenario = load_scenario(ARCH, [f"loads.ground_motion.end={args.end!r}",
                                    'ensemble.records="far-field"',
                                    f'ensemble.scales="{args.scales}"', "ensemble.after=1.0"])
    infos = fema_p695_records("far-field")[: args.records]
    every = ens.ensemble_records("far-field")
    records = [r for r in every if r.source in {f"{i.set} {i.id}{i.component}"
                                                for i in infos}]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        # warm-up: compile the kernels here (numba's cache, which the workers load)
        warm = scenario.model_copy(update={"ensemble": scenario.ensemble.model_copy(
            update={"scales": [min(scenario.ensemble.scales)]})})
        ens.run_ensemble(warm, folder / "warm.h5", records=records[:1], workers=1,
                         processes=False, quiet=True)
        rows = [measure(scenario, records, int(w), folder) for w in args.workers.split(",")]
    base = rows[0]["wall_s"]
    for row in rows:
        row["speed_up"] = round(base / row["wall_s"], 2)
        print(f"{row['workers']} worker(s): {row['runs']} runs ({row['collapses']} collapsed, "
              f"{row['failed']} failed) in {row['wall_s']} s wall, {row['runs_per_s']} runs/s, "
              f"CPU {row['cpu_s']} s; speed-up {row['speed_up']}x")
    out = {"records": args.records, "scales": args.scales, "end_s": args.end,
           "machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
           "load_average": os.getloadavg(), "rows": rows}
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
