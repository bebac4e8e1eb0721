"""Deformable blocks in 3D: what the FE body kind (saxum.bodies.fe) needs beyond its 2D
kernels. The mechanics (tetrahedra, co-rotated frames, M~^-1) are saxum.fe's, the same in
both dimensions; here are the meshes of polyhedra with their nodes' tributary boundary, and
the contact rows of an FE side written for any dimension d (used for d = 3; the 2D ones in
saxum.bodies.fe are written out for 2 x 2 blocks):

    U = F sum_p w_p v_p               (rows of H* on the side's nodes: the contact frame F),
    W_aa += F (sum_pq w_p w_q R G_pq R^T) F^T,   v_q += R G_qp R^T (w_p F^T dR)
    (G = M~^-1 in the block's frame, q every node of the block) [M. Jean, CMAME 177 (1999)
    235-257, sec. 5; design-deformable-and-joints.md section 3].
"""

import numba as nb
import numpy as np

from ..fe.blocks import _add_node_velocity, compliance_block
from ..fe.mesh import Mesh, mesh_polyhedron
from ..geometry3d import Polyhedron, rotation_matrix

__all__ = ["fe_contact_rows_nd", "fe_end_gaps_nd", "frame_quaternions", "mesh_polyhedra",
           "principal_axes", "side_push_nd", "side_velocity_nd"]


def mesh_polyhedra(polyhedra: list[Polyhedron], sizes: list[float | None],
                   names: list[str]) -> tuple[list[Mesh], list[np.ndarray]]:
    """Tetrahedral meshes of the polyhedra (saxum.fe.mesh_polyhedron) with elements of about
    their size [m] (None: half the block's shortest edge, at least two elements through it),
    and each mesh's node sides [n, K, 3]: a third of the area vector (outward normal times
    area [m^2]) of each boundary triangle at the node, in K slots (zeros beyond its count), so
    that a node's contact area on a face of normal n is sum max(0, -n . R s)."""
    meshes, sides = [], []
    for poly, size, name in zip(polyhedra, sizes, names, strict=True):
        if size is None:
            ends = poly.vertices[poly.edges]
            size = 0.5 * float(np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1).min())
        mesh = mesh_polyhedron(poly.vertices, poly.faces, size, name=name)
        meshes.append(mesh)
        a, b, c = (mesh.nodes[mesh.facets[:, k]] for k in range(3))
        share = np.repeat(np.cross(b - a, c - a) / 6.0, 3, axis=0)  # (area / 3) n per corner
        node = mesh.facets.ravel()
        order = np.argsort(node, kind="stable")
        first = np.searchsorted(node[order], node[order])
        slot = np.empty_like(node)
        slot[order] = np.arange(len(node)) - first
        side = np.zeros((len(mesh.nodes), slot.max() + 1, 3))
        side[node, slot] = share
        sides.append(side)
    widest = max(s.shape[1] for s in sides)
    return meshes, [np.pad(s, ((0, 0), (0, widest - s.shape[1]), (0, 0))) for s in sides]


def frame_quaternions(rotation: np.ndarray, axes0: np.ndarray) -> np.ndarray:
    """Unit quaternions (w, x, y, z), w >= 0, of the blocks' body frames R R0 [nb, 4]: the
    co-rotated frame R [nb, 3, 3] turning the principal axes R0 [nb, 3, 3] of the reference
    block (the body row's frame, saxum.model)."""
    from scipy.spatial.transform import Rotation  # scipy.spatial: ~0.5 s, not at import

    xyzw = Rotation.from_matrix(rotation @ axes0).as_quat()
    q = np.concatenate((xyzw[:, 3:], xyzw[:, :3]), axis=1)
    return np.where(q[:, :1] < 0.0, -q, q)


def principal_axes(body_q0: np.ndarray) -> np.ndarray:
    """Rotation matrices [n, 3, 3] of the body rows' quaternions body_q0 [n, 7]."""
    return np.array([rotation_matrix(q[3:]) for q in body_q0]).reshape(-1, 3, 3)


@nb.njit(inline="always")
def side_velocity_nd(rows, a, kind, nodes, weights, body, v, node_v, u):
    """u += the side's part of U = H* v [m/s] for contact a: rows . v_body for a rigid side
    (kind 0), sum w_i rows[:, :d] . v_node_i for an FE side (rows signed by side)."""
    d = u.shape[0]
    if kind == 1:
        for i in range(nodes.shape[0]):
            w = weights[i]
            if w != 0.0:
                p = nodes[i]
                for r in range(d):
                    s = 0.0
                    for k in range(d):
                        s += rows[a, r, k] * node_v[p, k]
                    u[r] += w * s
    else:
        for r in range(d):
            s = 0.0
            for k in range(v.shape[1]):
                s += rows[a, r, k] * v[body, k]
            u[r] += s


@nb.njit(inline="always")
def _push_node(inverse, inv_start, node_start, rotation, block, p, f, node_v, pl, dv):
    """node_v[q] += R G[q, p] R^T f for every node q of `block` [m/s]: the response of the
    block to an impulse f [N s] (world axes, [d]) on its node p (global number); pl, dv: work
    memory [d]."""
    d = f.shape[0]
    first = node_start[block]
    n = d * (node_start[block + 1] - first)
    for k in range(d):
        s = 0.0
        for m in range(d):
            s += rotation[block, m, k] * f[m]
        pl[k] = s
    row = inv_start[block] + d * (p - first)
    for q in range(first, node_start[block + 1]):
        _add_node_velocity(inverse, row + d * (q - first) * n, n, pl, rotation, block, dv,
                           node_v, q)


@nb.njit(inline="always")
def _push_side_nodes(rows, a, nodes, weights, dr, node_block, node_start, inv_start, inverse,
                     rotation, node_v, f, pl, dv):
    """node_v += R M~^-1 R^T H_side dR on an FE side of contact a (node i gets w_i of the
    impulse rows^T dR [N s]); f, pl, dv: work memory [d]."""
    d = dr.shape[0]
    for i in range(nodes.shape[0]):
        w = weights[i]
        if w != 0.0:
            for k in range(d):
                s = 0.0
                for r in range(d):
                    s += rows[a, r, k] * dr[r]
                f[k] = w * s
            p = nodes[i]
            _push_node(inverse, inv_start, node_start, rotation, node_block[p], p, f, node_v,
                       pl, dv)


@nb.njit(inline="always")
def side_push_nd(rows, a, kind, nodes, weights, body, dr, inv_mass, v, node_block, node_start,
                 inv_start, inverse, rotation, node_v, f, pl, dv):
    """v += M^-1 H_side dR on one side of contact a, dR [d] [N s]: the body's diagonal M^-1
    for a rigid side (kind 0), R M~^-1 R^T of the nodes' block for an FE side; f, pl, dv:
    work memory [d]."""
    if kind == 1:
        _push_side_nodes(rows, a, nodes, weights, dr, node_block, node_start, inv_start,
                         inverse, rotation, node_v, f, pl, dv)
    else:
        for k in range(v.shape[1]):
            s = 0.0
            for r in range(dr.shape[0]):
                s += rows[a, r, k] * dr[r]
            v[body, k] += inv_mass[body, k] * s


@nb.njit(cache=True)
def fe_contact_rows_nd(side_kind, side_node, side_weight, frame, impulse, count, active,
                       node_block, node_start, inv_start, inverse, rotation, h_cand, h_ant,
                       delassus, node_v):
    """saxum.bodies.fe.fe_contact_rows in any dimension d: for the FE sides (side_kind 1),
    rows of H* = +-[F, 0] on the nodes (candidate +, antagonist -), W += F (sum_pq w_p w_q R
    G[p, q] R^T) F^T, and the warm start node_v += M~^-1 H R for active contacts."""
    d = frame.shape[1]
    g = np.empty((d, d))
    block = np.empty((d, d))
    f = np.empty(d)
    pl = np.empty(d)
    dv = np.empty(d)
    for a in range(count):
        for side in range(2):
            if side_kind[a, side] != 1:
                continue
            rows = h_cand if side == 0 else h_ant
            sign = 1.0 if side == 0 else -1.0
            for r in range(d):
                for k in range(rows.shape[2]):
                    rows[a, r, k] = sign * frame[a, r, k] if k < d else 0.0
            b = node_block[side_node[a, side, 0]]
            g[:] = 0.0
            for i in range(side_node.shape[2]):
                wi = side_weight[a, side, i]
                if wi == 0.0:
                    continue
                for j in range(side_node.shape[2]):
                    wj = side_weight[a, side, j]
                    if wj == 0.0:
                        continue
                    compliance_block(node_start, inv_start, inverse, rotation, b,
                                     side_node[a, side, i], side_node[a, side, j], block)
                    for k in range(d):
                        for m in range(d):
                            g[k, m] += wi * wj * block[k, m]
            for r in range(d):
                for c in range(d):
                    s = 0.0
                    for k in range(d):
                        for m in range(d):
                            s += frame[a, r, k] * g[k, m] * frame[a, c, m]
                    delassus[a, r, c] += s
            if active[a]:
                _push_side_nodes(rows, a, side_node[a, side], side_weight[a, side],
                                 impulse[a], node_block, node_start, inv_start, inverse,
                                 rotation, node_v, f, pl, dv)


@nb.njit(cache=True)
def fe_end_gaps_nd(side_kind, side_node, side_weight, cand, ant, h_cand, h_ant, gap, count,
                   impulse, v, node_v, h, theta, gap_end):
    """saxum.bodies.fe.fe_end_gaps in any dimension: gap_end = g + theta h U_n; returns
    (contacts with R_n > 0, largest interpenetration [m])."""
    u = np.empty(h_cand.shape[1])
    loaded = 0
    worst = 0.0
    for a in range(count):
        u[:] = 0.0
        side_velocity_nd(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0],
                         cand[a], v, node_v, u)
        side_velocity_nd(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1],
                         ant[a], v, node_v, u)
        g = gap[a] + theta * h * u[1]
        gap_end[a] = g
        loaded += impulse[a, 1] > 0.0
        worst = max(worst, -g)
    return loaded, worst
