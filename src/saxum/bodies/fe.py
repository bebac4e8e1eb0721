"""Deformable blocks: the finite-element body kind (issue 14; design-deformable-and-joints.md).

A DEFORMABLE block is a mesh of linear triangles (3D: tetrahedra) whose node velocities are
integrated by the same theta-method as the rigid bodies, M~ = M + h theta C + h^2 theta^2 K,
in a co-rotated frame per block; the mechanics (meshing, assembly, frames, free velocity,
stresses, energies) are saxum.fe's (FEBlocks). What is specific to the contact dynamics is
here: the model's side (FEBodies: meshes, candidates, contact areas), the step's stages for
the loop (FEKind), and the contact rows of an FE side:

    U = F v_node - ...   (rows of H* on the node: the contact frame F),
    W_aa += F R G_pp R^T F^T,   v_q += R G_qp R^T F^T dR   (G = M~^-1 in the frame, q in the
    block), [Jean99, sec. 5; design section 3].
Candidates are boundary nodes (saxum.detection.fe_nodes, .fe_nodes3d), antagonists rigid
blocks' edges (3D: faces) and other deformable blocks' boundary facets. The 2D kernels here
are written out for 2 x 2 blocks; saxum.bodies.fe3d has them for any dimension (used in 3D).
"""

from dataclasses import dataclass

import numba as nb
import numpy as np

from ..errors import InputError
from ..fe.blocks import FEBlocks
from ..fe.material import Elastic
from ..fe.mesh import Mesh, mesh_polygon
from ..geometry3d import Polyhedron
from .fe3d import (
    fe_contact_rows_nd,
    fe_end_gaps_nd,
    frame_quaternions,
    mesh_polyhedra,
    principal_axes,
)

__all__ = ["FEBodies", "FEKind", "build_fe_bodies", "stored_blocks"]


@dataclass(frozen=True)
class FEBodies:
    """The deformable blocks of a model (d = 2 or 3): their meshes and materials, and what
    detection reads; nodes are numbered block after block (saxum.fe.FEBlocks' numbering)."""

    body: np.ndarray
    """Body index of each deformable block, shape [n_fe], int32."""
    fe_index: np.ndarray
    """Deformable block index of each body, -1 for rigid bodies, shape [body_count], int32."""
    meshes: tuple[Mesh, ...]
    materials: tuple[Elastic, ...]
    node_x0: np.ndarray
    """Reference (initial) node positions [m], shape [n_nodes, d]."""
    node_side: np.ndarray
    """The node's tributary boundary in the block's reference axes, zeros inside: 2D half of
    each of the (up to two) boundary edges at the node, as its outward normal times half its
    length [m], shape [n_nodes, 2, 2]; 3D a third of each boundary triangle at the node, as
    its outward normal times a third of its area [m^2], shape [n_nodes, K, 3] (K the most
    triangles at a node, zeros beyond a node's own). A node's contact area on a face of
    normal n is sum max(0, -n . R s), the part of its tributary boundary that faces the
    antagonist."""
    boundary_start: np.ndarray
    """Block f's contact candidates are boundary_node[boundary_start[f]:...[f+1]], int64."""
    boundary_node: np.ndarray
    """Boundary nodes (global numbers), sorted per block, int64."""
    facet_start: np.ndarray
    """Block f's boundary edges are facet_node[facet_start[f]:facet_start[f+1]], int64."""
    facet_node: np.ndarray
    """Boundary facets (global node numbers), the antagonists: 2D edges, counter-clockwise
    (outward normal = the edge turned by -90 degrees), shape [n_facets, 2]; 3D triangles (a,
    b, c) with outward normal along (b - a) x (c - a), shape [n_facets, 3]; int64."""

    @property
    def count(self) -> int:
        return len(self.body)

    @property
    def node_count(self) -> int:
        return len(self.node_x0)


def build_fe_bodies(bodies: list[int], shapes: list, materials: list[Elastic],
                    sizes: list[float | None], names: list[str], body_count: int) -> FEBodies:
    """Mesh each block's shape, a polygon (vertices [k, 2] [m]; saxum.fe.mesh_polygon) or a
    polyhedron (saxum.geometry3d.Polyhedron; saxum.bodies.fe3d.mesh_polyhedra), with elements
    of about its size [m] (None: 2D a fifth of its smallest side, 3D half its shortest
    edge)."""
    dim = 3 if shapes and isinstance(shapes[0], Polyhedron) else 2
    for material, name in zip(materials, names, strict=True):
        if not isinstance(material, Elastic):
            raise InputError(f"{name}: material must be a saxum.fe.Elastic, got {material!r}")
        try:
            material.depth(dim)
        except InputError as error:
            raise InputError(f"{name}: {error}") from None
    if dim == 3:
        meshes, sides = mesh_polyhedra(shapes, sizes, names)
    else:
        meshes, sides = _mesh_polygons(shapes, sizes, names)
    node_start = np.cumsum([0] + [len(m.nodes) for m in meshes])
    fe_index = np.full(body_count, -1, dtype=np.int32)
    fe_index[bodies] = np.arange(len(bodies), dtype=np.int32)
    return FEBodies(
        body=np.array(bodies, dtype=np.int32), fe_index=fe_index, meshes=tuple(meshes),
        materials=tuple(materials),
        node_x0=np.ascontiguousarray(np.concatenate([m.nodes for m in meshes])),
        node_side=np.concatenate(sides),
        boundary_start=np.cumsum([0] + [len(m.boundary_nodes) for m in meshes]).astype(np.int64),
        boundary_node=np.concatenate([m.boundary_nodes + s for m, s in
                                      zip(meshes, node_start, strict=False)]).astype(np.int64),
        facet_start=np.cumsum([0] + [len(m.facets) for m in meshes]).astype(np.int64),
        facet_node=np.concatenate([m.facets + s for m, s in
                                   zip(meshes, node_start, strict=False)]).astype(np.int64),
    )


def _mesh_polygons(polygons, sizes, names) -> tuple[list[Mesh], list[np.ndarray]]:
    """Triangle meshes of the polygons and their node sides [n, 2, 2] (FEBodies.node_side)."""
    meshes, sides = [], []
    for poly, size, name in zip(polygons, sizes, names, strict=True):
        if size is None:
            size = 0.2 * float(np.linalg.norm(np.roll(poly, -1, axis=0) - poly, axis=1).min())
        mesh = mesh_polygon(poly, size, name=name)
        meshes.append(mesh)
        edge = mesh.nodes[mesh.facets[:, 1]] - mesh.nodes[mesh.facets[:, 0]]
        half = 0.5 * np.column_stack((edge[:, 1], -edge[:, 0]))  # outward: counter-clockwise
        side = np.zeros((len(mesh.nodes), 2, 2))
        side[mesh.facets[:, 0], 0] = half  # each boundary node starts one edge, ends another
        side[mesh.facets[:, 1], 1] = half
        sides.append(side)
    return meshes, sides


def stored_blocks(model: dict) -> FEBlocks:
    """The deformable blocks' geometry (saxum.fe.FEBlocks.geometry: no M, K or M~^-1) rebuilt
    from a results file's model datasets (fe_node_x0, fe_node_start, fe_cell_node,
    fe_cell_start, fe_material), for frames and stresses of stored node positions."""
    node_start, cell_start = model["fe_node_start"], model["fe_cell_start"]
    meshes = [Mesh.from_cells(model["fe_node_x0"][a:b],
                              model["fe_cell_node"][c:d] - a)
              for a, b, c, d in zip(node_start[:-1], node_start[1:], cell_start[:-1],
                                    cell_start[1:], strict=True)]
    materials = [Elastic(row[0], row[1], row[2], damping=(row[3], row[4]),
                         thickness=row[5] if row[5] > 0.0 else None)
                 for row in model["fe_material"]]
    return FEBlocks.geometry(meshes, materials)


class FEKind:
    """The deformable body kind of one simulation (time step h [s], theta [-]): the blocks'
    mechanics (saxum.fe.FEBlocks, M~^-1 for this h and theta), their frames, and the node
    velocities of the step. body_q0: the model's initial body rows (3D: their principal
    axes, which the blocks' body rows keep turning)."""

    def __init__(self, fe: FEBodies, h: float, theta: float,
                 body_q0: np.ndarray | None = None) -> None:
        import scipy.sparse as sp  # ~0.3 s: imported by the runs that have FE blocks

        self.model = fe
        self.blocks = FEBlocks.build(list(fe.meshes), list(fe.materials), h, theta)
        b = self.blocks
        ht = h * theta
        dof_block = np.repeat(b.node_block, b.dim)
        self.iteration_matrix = (
            sp.diags(1.0 + ht * b.alpha[dof_block])
            @ sp.csr_matrix((b.m_data, b.m_indices, b.m_indptr))
            + sp.diags(ht * b.beta[dof_block] + ht * ht)
            @ sp.csr_matrix((b.k_data, b.k_indices, b.k_indptr))).tocsr()
        """M~ = (1 + h theta alpha) M + (h theta beta + h^2 theta^2) K of all blocks, block
        axes [kg], sparse: saxum.solver.sticking's equations."""
        self.rotation = self.blocks.frames(fe.node_x0)[0]
        """The frame of M~^-1 in the step, per block [n_fe, d, d] (FEBlocks.step_frames'
        rotation_step: the start frame turned on by the block's spin)."""
        n, d = fe.node_x0.shape
        self.dim = d
        self.axes0 = None if d == 2 else principal_axes(body_q0[fe.body])
        """3D: the principal axes of each block's body row at the start [n_fe, 3, 3] (the
        body frame that the co-rotated frame turns: saxum.bodies.fe3d.frame_quaternions)."""
        self._rows = fe_contact_rows if d == 2 else fe_contact_rows_nd
        self._end_gaps = fe_end_gaps if d == 2 else fe_end_gaps_nd
        self.v_free = np.zeros((n, d))
        """Free node velocities of the step [m/s]."""
        self.v = np.zeros((n, d))
        """Node velocities during and after the contact solve [m/s]."""
        self.v_begin = np.zeros((n, d))
        """Node velocities at the start of the step [m/s] (for the joint laws)."""
        self.x_pred = np.zeros((n, d))
        """Node positions of the predicted configuration (for detection) [m]."""

    def free_velocity(self, node_x: np.ndarray, node_v: np.ndarray,
                      acceleration: np.ndarray) -> None:
        """v_free of all nodes under a uniform acceleration [m/s^2] (gravity and the model's
        accelerations, theta-weighted), from positions node_x [m] and velocities node_v [m/s]
        at the start of the step, in the step's frames (FEBlocks.step_frames); v = v_free."""
        b = self.blocks
        rotation, centroid, spin, self.rotation = b.step_frames(node_x, node_v)
        self.v_free[:] = b.free_velocity(node_x, node_v, b.weight(acceleration), rotation,
                                         centroid, spin, self.rotation)
        self.v[:] = self.v_free
        self.v_begin[:] = node_v

    def predict(self, node_x: np.ndarray, node_v: np.ndarray) -> None:
        """x_pred = x + (1 - theta) h v (the configuration detection sees)."""
        self.x_pred[:] = self.blocks.predict_positions(node_x, node_v)

    def update(self, node_x: np.ndarray, node_v: np.ndarray, body_q: np.ndarray) -> None:
        """End of step: x += h [(1 - theta) v_i + theta v_i+1], v = v_i+1; the blocks' body
        rows get their new frames (centre of mass, angle; 3D quaternion)."""
        self.blocks.update_positions(node_x, node_v, self.v)
        node_v[:] = self.v
        rotation, centroid = self.blocks.frames(node_x)
        body = self.model.body
        if self.dim == 3:
            body_q[body, :3] = centroid
            body_q[body, 3:] = frame_quaternions(rotation, self.axes0)
            return
        body_q[body, :2] = centroid
        body_q[body, 2] = np.arctan2(rotation[:, 1, 0], rotation[:, 0, 0])

    def kinetic_energy(self, node_v: np.ndarray) -> float:
        """1/2 sum v^T M v over the blocks [J; 2D per m of depth]."""
        return float(self.blocks.kinetic_energy(node_v).sum())

    def strain_energy(self, node_x: np.ndarray) -> float:
        """1/2 sum u^T K u over the blocks, u co-rotated [J; 2D per m of depth]."""
        return float(self.blocks.strain_energy(node_x, *self.blocks.frames(node_x)).sum())

    def assemble_contacts(self, problem, v: np.ndarray) -> None:
        """The FE sides of problem's contacts (candidate = node, side_kind 1): rows of H* = the
        frame, Delassus block += F G_pp F^T, and the warm start v_node += M~^-1 H R."""
        c = problem.contacts
        b = self.blocks
        self._rows(c.side_kind, c.side_node, c.side_weight, c.frame, c.impulse, problem.count,
                   problem.active, b.node_block, b.node_start, b.inv_start, b.inv,
                   self.rotation, problem.h_cand, problem.h_ant, problem.delassus, self.v)

    def local_velocities(self, problem, v: np.ndarray, out: np.ndarray, begin: bool) -> None:
        """ContactProblem.local_velocities for problems with FE sides (2D): U [m/s] from the
        bodies' v and the nodes' velocities, those at the start of the step with begin, else
        the solve's."""
        c = problem.contacts
        fe_local_velocities(c.candidate, c.antagonist, problem.h_cand, problem.h_ant,
                            c.side_kind, c.side_node, c.side_weight, problem.count, v,
                            self.v_begin if begin else self.v, out)

    def end_gaps(self, problem, impulse: np.ndarray, v: np.ndarray, w: np.ndarray | None,
                 h: float, theta: float) -> tuple[int, float]:
        """ContactProblem.end_gaps for problems with FE sides (no projection: w is None)."""
        c = problem.contacts
        return self._end_gaps(c.side_kind, c.side_node, c.side_weight, c.candidate,
                              c.antagonist, problem.h_cand, problem.h_ant, c.gap, problem.count,
                              impulse, v, self.v, h, theta, problem.gap_end)


@nb.njit(inline="always")
def _compliance(inverse, base, n2, q, p, c, s):
    """World 2 x 2 block R G[q, p] R^T of M~^-1 (frame G), nodes q, p local to the block."""
    r0 = base + 2 * q * n2 + 2 * p
    r1 = r0 + n2
    g00 = inverse[r0]
    g01 = inverse[r0 + 1]
    g10 = inverse[r1]
    g11 = inverse[r1 + 1]
    # R G
    a00 = c * g00 - s * g10
    a01 = c * g01 - s * g11
    a10 = s * g00 + c * g10
    a11 = s * g01 + c * g11
    # (R G) R^T
    return (a00 * c - a01 * s, a00 * s + a01 * c, a10 * c - a11 * s, a10 * s + a11 * c)


@nb.njit(inline="always")
def push_node_impulse(inverse, inv_start, node_start, block, p, c, s, fx, fy, v):
    """v_q += R G[q, p] R^T (fx, fy) for every node q of the block of node p: the change of
    the block's velocities from an impulse (fx, fy) [N s] on node p (global numbers)."""
    n0 = node_start[block]
    n2 = 2 * (node_start[block + 1] - n0)
    base = inv_start[block]
    lx = c * fx + s * fy
    ly = -s * fx + c * fy
    pl = p - n0
    for q in range(n2 // 2):
        r0 = base + 2 * q * n2 + 2 * pl
        r1 = r0 + n2
        gx = inverse[r0] * lx + inverse[r0 + 1] * ly
        gy = inverse[r1] * lx + inverse[r1 + 1] * ly
        v[n0 + q, 0] += c * gx - s * gy
        v[n0 + q, 1] += s * gx + c * gy


@nb.njit(inline="always")
def side_velocity(rows, a, kind, nodes, weights, body, v, node_v):
    """(U_t, U_n) [m/s] of one side of contact a: rows . v_body for a rigid side (kind 0), sum
    w_i rows . v_node_i for an FE side (rows [t; n] on the node, signed by side)."""
    u0 = 0.0
    u1 = 0.0
    if kind == 1:
        for i in range(nodes.shape[0]):
            w = weights[i]
            if w != 0.0:
                p = nodes[i]
                u0 += w * (rows[a, 0, 0] * node_v[p, 0] + rows[a, 0, 1] * node_v[p, 1])
                u1 += w * (rows[a, 1, 0] * node_v[p, 0] + rows[a, 1, 1] * node_v[p, 1])
    else:
        for d in range(v.shape[1]):
            u0 += rows[a, 0, d] * v[body, d]
            u1 += rows[a, 1, d] * v[body, d]
    return u0, u1


@nb.njit(cache=True)
def fe_local_velocities(cand, ant, h_cand, h_ant, side_kind, side_node, side_weight, count, v,
                        node_v, out):
    """out[a] = (U_t, U_n) [m/s] of contacts with rigid or FE sides (side_velocity)."""
    for a in range(count):
        uc0, uc1 = side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0],
                                 cand[a], v, node_v)
        ua0, ua1 = side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1],
                                 ant[a], v, node_v)
        out[a, 0] = uc0 + ua0
        out[a, 1] = uc1 + ua1


@nb.njit(inline="always")
def side_push(rows, a, kind, nodes, weights, body, dt, dn, inv_mass, v, node_block,
              node_start, inv_start, inverse, rotation, node_v):
    """v += M^-1 H_side (dt, dn) on one side: the body's diagonal M^-1 for a rigid side, R M~^-1
    R^T of the nodes' block for an FE side (each node w_i of the impulse)."""
    if kind == 1:
        fx = rows[a, 0, 0] * dt + rows[a, 1, 0] * dn
        fy = rows[a, 0, 1] * dt + rows[a, 1, 1] * dn
        for i in range(nodes.shape[0]):
            w = weights[i]
            if w != 0.0:
                p = nodes[i]
                f = node_block[p]
                push_node_impulse(inverse, inv_start, node_start, f, p, rotation[f, 0, 0],
                                  rotation[f, 1, 0], w * fx, w * fy, node_v)
    else:
        for d in range(v.shape[1]):
            v[body, d] += inv_mass[body, d] * (rows[a, 0, d] * dt + rows[a, 1, d] * dn)


@nb.njit(cache=True)
def fe_contact_rows(side_kind, side_node, side_weight, frame, impulse, count, active,
                    node_block, node_start, inv_start, inverse, rotation, h_cand, h_ant,
                    delassus, node_v):
    """For the FE sides of the contacts (side_kind 1): rows of H* = +-[F, 0] on the nodes
    (candidate +, antagonist -), W += F (sum_pq w_p w_q R G[p, q] R^T) F^T, and the warm start
    node_v += M~^-1 H R on their nodes (inactive contacts: R = 0, set by assembly)."""
    for a in range(count):
        for side in range(2):
            if side_kind[a, side] != 1:
                continue
            rows = h_cand if side == 0 else h_ant
            sign = 1.0 if side == 0 else -1.0
            for r in range(2):
                rows[a, r, 0] = sign * frame[a, r, 0]
                rows[a, r, 1] = sign * frame[a, r, 1]
                rows[a, r, 2] = 0.0
            f = node_block[side_node[a, side, 0]]
            c = rotation[f, 0, 0]
            s = rotation[f, 1, 0]
            n0 = node_start[f]
            n2 = 2 * (node_start[f + 1] - n0)
            g00 = g01 = g10 = g11 = 0.0
            for i in range(side_node.shape[2]):
                wi = side_weight[a, side, i]
                if wi == 0.0:
                    continue
                for j in range(side_node.shape[2]):
                    wj = side_weight[a, side, j]
                    if wj == 0.0:
                        continue
                    h00, h01, h10, h11 = _compliance(inverse, inv_start[f], n2,
                                                     side_node[a, side, i] - n0,
                                                     side_node[a, side, j] - n0, c, s)
                    g00 += wi * wj * h00
                    g01 += wi * wj * h01
                    g10 += wi * wj * h10
                    g11 += wi * wj * h11
            for r in range(2):
                gx = g00 * frame[a, r, 0] + g01 * frame[a, r, 1]
                gy = g10 * frame[a, r, 0] + g11 * frame[a, r, 1]
                for q in range(2):
                    delassus[a, q, r] += frame[a, q, 0] * gx + frame[a, q, 1] * gy
            if not active[a]:
                continue
            fx = rows[a, 0, 0] * impulse[a, 0] + rows[a, 1, 0] * impulse[a, 1]
            fy = rows[a, 0, 1] * impulse[a, 0] + rows[a, 1, 1] * impulse[a, 1]
            for i in range(side_node.shape[2]):
                w = side_weight[a, side, i]
                if w != 0.0:
                    push_node_impulse(inverse, inv_start, node_start, f,
                                      side_node[a, side, i], c, s, w * fx, w * fy, node_v)


@nb.njit(cache=True)
def fe_end_gaps(side_kind, side_node, side_weight, cand, ant, h_cand, h_ant, gap, count,
                impulse, v, node_v, h, theta, gap_end):
    """gap_end = g + theta h U_n with each side's velocity by its kind; returns (contacts with
    R_n > 0, largest interpenetration [m])."""
    loaded = 0
    worst = 0.0
    for a in range(count):
        un = (side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0],
                            cand[a], v, node_v)[1]
              + side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1],
                              ant[a], v, node_v)[1])
        g = gap[a] + theta * h * un
        gap_end[a] = g
        loaded += impulse[a, 1] > 0.0
        worst = max(worst, -g)
    return loaded, worst
