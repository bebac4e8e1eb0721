"""What the first Results.stresses call builds: the full deformable blocks (M, K by
scikit-fem, M~^-1 per block) against their geometry alone (FEBlocks.geometry: frames and
stresses need no more), on the 15 deformable voussoirs of a semicircular arch, back to back
in one process (kernels compiled before the clock starts).

    python benchmarks/fe_stresses.py [--mesh 0.012] [--repeat 3]

Prints wall and CPU seconds of each build (the smallest of `repeat`), their ratio, and the
largest difference of the stresses they give, relative to the largest stress.
"""

import argparse
import time

import numpy as np

from saxum.fe import FEBlocks
from saxum.scenario import parse_scenario

ARCH = """\
[structure]
type = "semicircular_arch"
radius = 1.0
thickness = 0.15
voussoirs = 15

[[laws]]
groups = ["*", "*"]
friction = 0.6

[[materials]]
groups = ["voussoir"]
E = 1.0e10
nu = 0.2
density = 2400.0
mesh_size = {mesh}

[output]
duration = 0.01
"""


def _clock(build, repeat):
    best = (np.inf, np.inf)
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        blocks = build()
        best = min(best, (time.perf_counter() - wall, time.process_time() - cpu))
    return blocks, best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", type=float, default=0.012)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    fe = parse_scenario(ARCH.format(mesh=args.mesh)).build_model().fe
    meshes, materials = list(fe.meshes), list(fe.materials)
    small = FEBlocks.build(meshes[:1], materials[:1], 1e-3, 0.5)  # compile the kernels
    small.stresses(small.x0, *small.frames(small.x0))
    full, (full_wall, full_cpu) = _clock(lambda: FEBlocks.build(meshes, materials, 1e-3, 0.5),
                                         args.repeat)
    cheap, (cheap_wall, cheap_cpu) = _clock(lambda: FEBlocks.geometry(meshes, materials),
                                            args.repeat)
    rng = np.random.default_rng(0)
    x = full.x0 + 1e-6 * rng.standard_normal(full.x0.shape)
    a = full.stresses(x, *full.frames(x))[0]
    b = cheap.stresses(x, *cheap.frames(x))[0]
    print(f"{len(full.cell_node)} cells, {full.n_nodes} nodes, {full.n_blocks} blocks")
    print(f"full build (M, K, M~^-1): wall {full_wall:.3f} s, cpu {full_cpu:.3f} s")
    print(f"geometry only:            wall {cheap_wall:.3f} s, cpu {cheap_cpu:.3f} s")
    print(f"ratio full / geometry: wall {full_wall / cheap_wall:.0f}, "
          f"cpu {full_cpu / cheap_cpu:.0f}")
    print(f"stress difference: {np.abs(a - b).max() / np.abs(a).max():.1e} of the largest")


if __name__ == "__main__":
    main()
