"""Opening the results file of a run with deformable blocks, and its first read of body_v,
whose rows of the deformable blocks (their nodes' nearest rigid motion,
FEBlocks.rigid_velocities) are filled from the stored nodes.

    python benchmarks/fe_results_open.py [--frames 2000] [--repeat 3] [--file PATH]

Writes (once: an existing --file is reused) a run of the 15 deformable voussoirs of a
semicircular arch (mesh 0.03 m) with a frame every step, then prints the wall and CPU
seconds (the smallest of `repeat`, kernels compiled before the clock starts) of
Results(path) alone and of reading body_v after it.
"""

import argparse
import time
from pathlib import Path

from fe_stresses import ARCH  # benchmarks/ is the script's folder, on the path

from saxum.results import Results
from saxum.runner import run_scenario
from saxum.scenario import parse_scenario

FILE_EVERY_STEP = """
[solver]
dt = 1e-4
"""


def _scenario(frames: int) -> str:
    """fe_stresses.py's arch, mesh 0.03 m, damped, a frame every step (dt = 0.1 ms)."""
    return (ARCH.format(mesh=0.03)
            .replace("density = 2400.0", "density = 2400.0\ndamping = [0.0, 1e-4]")
            .replace("duration = 0.01", f"duration = {frames * 1e-4}\ninterval = 1e-4\n"
                     "checkpoint_interval = 1.0") + FILE_EVERY_STEP)


def _clock() -> tuple[float, float]:
    return time.perf_counter(), time.process_time()


def _since(start: tuple[float, float]) -> tuple[float, float]:
    wall, cpu = _clock()
    return wall - start[0], cpu - start[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--file", default="fe_results_open.h5")
    args = parser.parse_args()
    path = Path(args.file)
    if not path.exists():
        run_scenario(parse_scenario(_scenario(args.frames)), path, quiet=True)
    with Results(path) as r:  # compiles the kernels
        r.body_v.sum()
        frames, nodes = r.frame_count, r.node_x.shape[1]
    opened, first_read = [], []
    for _ in range(args.repeat):
        start = _clock()
        results = Results(path)
        opened.append(_since(start))
        start = _clock()
        results.body_v.sum()
        first_read.append(_since(start))
        results.close()
    print(f"{frames} frames, {nodes} nodes: open {min(w for w, _ in opened):.3f} s wall "
          f"({min(c for _, c in opened):.3f} CPU), first body_v read "
          f"{min(w for w, _ in first_read):.3f} s wall ({min(c for _, c in first_read):.3f} "
          "CPU)")


if __name__ == "__main__":
    main()
