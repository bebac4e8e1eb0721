"""Cost of the deformable-block kernels (saxum.fe) on 200 bricks, all ratios from one run.

    python benchmarks/fe_kernels.py [--dim 2] [--blocks 200] [--size 0.04]

A wall's worth of 0.4 x 0.2 m bricks (3D: 0.4 x 0.2 x 0.1 m), each meshed structured at
`size` (2D: 66 nodes at 0.04 m). Prints: the assembly (scikit-fem) and the factorization
(prepare: dense Cholesky and inverse of M~ per block; equal blocks share one) times; per step,
the time of the frames, the free velocity and the position update, of one M~^-1 solve of all
blocks (the update after NLGS), of the element stresses, and of rotating every block's
condensed boundary compliance G; per NLGS contact update, the velocity update through M~^-1 of
all nodes of the block against that of its boundary nodes only, each the mean of 100000
updates of one node's impulse called from compiled code. Kernels are compiled before the clock
starts.
"""

import argparse
import time

import numba as nb
import numpy as np

from saxum.fe import Elastic, FEBlocks, mesh_polygon, mesh_polyhedron
from saxum.fe.blocks import apply_boundary_impulse, apply_impulse


def _clock(function, repeat):
    start = time.perf_counter()
    for _ in range(repeat):
        function()
    return (time.perf_counter() - start) / repeat


@nb.njit
def _updates(blocks_arrays, block, nodes, impulse, rotation, v, repeat, boundary_only):
    node_start, boundary_start, boundary_node, inv_start, inv = blocks_arrays
    for _ in range(repeat):
        if boundary_only:
            apply_boundary_impulse(node_start, boundary_start, boundary_node, inv_start, inv,
                                   rotation, block, nodes, impulse, v)
        else:
            apply_impulse(node_start, inv_start, inv, block, nodes, impulse, rotation, v)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dim", type=int, default=2)
    parser.add_argument("--blocks", type=int, default=200)
    parser.add_argument("--size", type=float, default=0.04)
    args = parser.parse_args()
    if args.dim == 2:
        mesh = mesh_polygon([[0, 0], [0.4, 0], [0.4, 0.2], [0, 0.2]], args.size)
    else:
        corners = [[x, y, z] for x in (0, 0.4) for y in (0, 0.2) for z in (0, 0.1)]
        faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4],
                 [1, 5, 7, 3]]
        mesh = mesh_polyhedron(corners, faces, args.size)
    material = Elastic(1e10, 0.2, 2400.0, damping=(0.0, 1e-5))
    FEBlocks.build([mesh], [material], 1e-3, 0.5)  # compile nothing yet; warm scikit-fem
    start = time.perf_counter()
    blocks = FEBlocks.build([mesh] * args.blocks, [material] * args.blocks, 1e-3, 0.5)
    build = time.perf_counter() - start
    prepare = _clock(lambda: blocks.prepare(1e-3, 0.5), 1)

    rng = np.random.default_rng(0)
    x = blocks.x0 + 1e-6 * rng.standard_normal(blocks.x0.shape)
    v = 1e-3 * rng.standard_normal(x.shape)
    force = blocks.weight([0.0, -9.81] if args.dim == 2 else [0.0, 0.0, -9.81])
    _, _, spin, rotation_step = frames = blocks.step_frames(x, v)
    rotation, centroid = frames[:2]

    def step():
        r, c, w, rs = blocks.step_frames(x, v)
        v_next = blocks.free_velocity(x, v, force, r, c, w, rs)
        blocks.update_positions(x.copy(), v, v_next)

    step()
    blocks.stresses(x, rotation, centroid)
    g = blocks.boundary_compliance(rotation_step)
    b = 3
    bnd = blocks.boundary_node[blocks.boundary_start[b]:blocks.boundary_start[b + 1]]
    nodes = bnd[:1].copy()
    impulse = np.ones((1, args.dim)) * 1e-3
    arrays = (blocks.node_start, blocks.boundary_start, blocks.boundary_node, blocks.inv_start,
              blocks.inv)
    _updates(arrays, b, nodes, impulse, rotation_step, v, 1, True)
    _updates(arrays, b, nodes, impulse, rotation_step, v, 1, False)

    per_step = _clock(step, 50)
    solve = _clock(lambda: blocks.apply_nodal_impulses(force, rotation_step, v), 50)
    stresses = _clock(lambda: blocks.stresses(x, rotation, centroid), 50)
    compliance = _clock(lambda: blocks.boundary_compliance(rotation_step), 20)
    repeat = 100000
    all_nodes = _clock(lambda: _updates(arrays, b, nodes, impulse, rotation_step, v, repeat,
                                        False), 1) / repeat
    boundary = _clock(lambda: _updates(arrays, b, nodes, impulse, rotation_step, v, repeat,
                                       True), 1) / repeat
    dofs = args.dim * len(mesh.nodes)
    print(f"{args.blocks} bricks, dim {args.dim}, {len(mesh.nodes)} nodes ({dofs} DOFs, "
          f"{len(mesh.boundary_nodes)} on the boundary) each; M~^-1 {blocks.inv.nbytes / 1e6:.1f} "
          f"MB, G {g.nbytes / 1e6:.1f} MB")
    print(f"build (assembly + prepare) {build:.3f} s, prepare alone {prepare:.3f} s")
    print(f"step (frames + free velocity + positions) {1e3 * per_step:.3f} ms, M~^-1 of all "
          f"blocks (apply_nodal_impulses) {1e3 * solve:.3f} ms, stresses {1e3 * stresses:.3f} "
          f"ms, all G rotated (boundary_compliance) {1e3 * compliance:.3f} ms")
    print(f"contact update of one node's impulse: all nodes of the block {1e9 * all_nodes:.0f} "
          f"ns, boundary nodes only {1e9 * boundary:.0f} ns, ratio {all_nodes / boundary:.2f}")

if __name__ == "__main__":
    main()
