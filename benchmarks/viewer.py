"""Benchmark of `saxum view` (saxum.view): the size of the page of a large 3D run, and the
time to write the page of the bundled 3D bridge flood example.

    python benchmarks/viewer.py [--bridge RESULTS.h5] [--json benchmarks/results/viewer.json]
                                [--keep FOLDER]

1. A 3D running-bond wall of about 1000 bricks (saxum.structures.wall3d: 40 courses,
   6.25 m long, bricks 0.25 x 0.12 x 0.065 m) pushed in its plane by a horizontal acceleration
   of 3 m/s^2, which it resists (friction 0.6: it would slide beyond 5.9 m/s^2) standing, run
   for 200 output frames (one per step, dt = 1e-3 s): every joint is loaded, so its contacts
   are the heaviest part of the page. The page's size does not depend on how far the blocks
   move (14 bytes per block and frame); pushed out of its plane the wall rocks, and a step
   then takes minutes on 2 cores. Reported: blocks, frames, contact points stored and
   packed, the page's size [MB] (target: under 10 MB), the time to write it.
2. examples/flood_bridge3d.toml as bundled (run here first unless --bridge gives its results
   file): the time to write its page, Results opened and page written (target: under 5 s),
   median of 3, in this process after the imports; wall and CPU time (user + sys of this
   process, which a loaded machine changes less).
"""

import argparse
import json
import platform
import statistics
import tempfile
import time
from pathlib import Path

from saxum.cli import main
from saxum.results import Results
from saxum.view import view_data, write_view

ROOT = Path(__file__).resolve().parents[1]

WALL = """\
title = "3D wall of about 1000 bricks, pushed"
[structure]
type = "wall_3d"
courses = 40
length = 6.25
thickness = 0.12
brick_length = 0.25
brick_height = 0.065
[[laws]]
groups = ["*", "*"]
friction = 0.6
[loads]
horizontal_acceleration = 3.0
[solver]
dt = 1e-3
[output]
duration = 0.199
interval = 1e-3
"""


def page_of(results: Path, out: Path) -> dict:
    """Write the page of `results`; its size and what went in."""
    start, cpu = time.perf_counter(), time.process_time()
    with Results(results) as r:
        write_view(r, out)
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
        data, _ = view_data(r)
        stored = int(r.contact_counts.sum())
        blocks, frames = len(r.body_name), r.frame_count
    return {"blocks": blocks, "frames": frames, "contacts_stored": stored,
            "contact_frame_stride": data["overlay"]["stride"],
            "bytes": out.stat().st_size, "MB": round(out.stat().st_size / 2**20, 2),
            "write_s": round(seconds, 2), "write_cpu_s": round(cpu, 2)}


def main_() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bridge", type=Path, help="results of examples/flood_bridge3d.toml")
    parser.add_argument("--keep", type=Path, help="folder to keep the results and pages in")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    result = {"machine": platform.platform(), "python": platform.python_version()}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = args.keep or Path(tmp)
        scenario = tmp / "wall1000.toml"
        scenario.write_text(WALL)
        assert main(["run", str(scenario), "--quiet"]) == 0
        result["wall_1000_blocks_200_frames"] = page_of(scenario.with_suffix(".h5"),
                                                        tmp / "wall.html")
        print("large 3D run:", result["wall_1000_blocks_200_frames"])
        bridge = args.bridge
        if bridge is None:
            bridge = tmp / "bridge3d.h5"
            assert main(["run", str(ROOT / "examples" / "flood_bridge3d.toml"), "-o",
                         str(bridge), "--quiet"]) == 0
        times = [page_of(bridge, tmp / "bridge.html") for _ in range(3)]
        result["flood_bridge3d"] = {**times[0], **{key: statistics.median(t[key] for t in times)
                                                   for key in ("write_s", "write_cpu_s")},
                                    "write_s_all": [t["write_s"] for t in times]}
        print("flood_bridge3d example:", result["flood_bridge3d"])
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main_()
