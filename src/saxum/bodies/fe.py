"""Deformable blocks: the finite-element body kind (issue 14; design-deformable-and-joints.md).

A DEFORMABLE block is a mesh of linear triangles (3D: tetrahedra) whose node velocities are
integrated by the same theta-method as the rigid bodies, M~ = M + h theta C + h^2 theta^2 K,
in a co-rotated frame per block; the mechanics (meshing, assembly, frames, free velocity,
stresses, energies) are saxum.fe's (FEBlocks). What is specific to the contact dynamics is
here: the model's side (FEBodies: meshes, candidates, contact areas), the step's stages for
the loop (FEKind), and the contact rows of an FE side:

    U = F sum_p w_p v_p               (rows of H* on the side's nodes: the contact frame F),
    W_aa += F (sum_pq w_p w_q R G_pq R^T) F^T,   v_q += R G_qp R^T (w_p F^T dR)
    (G = M~^-1 in the block's frame, q every node of the block) [M. Jean, CMAME 177 (1999)
    235-257, sec. 5; design-deformable-and-joints.md section 3].
Candidates are boundary nodes (saxum.detection.fe_nodes, .fe_nodes3d), antagonists rigid
blocks' edges (3D: faces) and other deformable blocks' boundary facets. The kernels of the
contact rows are one for both dimensions (d from the arrays' shapes).
"""

from dataclasses import dataclass

import numba as nb
import numpy as np

from ..errors import InputError
from ..fe.blocks import FEBlocks, _add_node_velocity, compliance_block, congruence
from ..fe.material import Elastic
from ..fe.mesh import Mesh, fit_mesh, mesh_polygon
from ..geometry3d import Polyhedron
from ..laws import LawKind
from .fe3d import frame_quaternions, mesh_polyhedra, principal_axes

__all__ = ["FEBodies", "FEKind", "build_fe_bodies", "fe_contact_rows", "fe_end_gaps",
           "fe_restitution", "side_push", "side_velocity", "stored_blocks"]

_RESTITUTION = int(LawKind.RESTITUTION_COULOMB)


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
    edge_start: np.ndarray
    """3D: block f's boundary edges (the sides of its boundary triangles) are
    edge_node[edge_start[f]:edge_start[f+1]]; 2D: zeros (its facets are its edges), int64."""
    edge_node: np.ndarray
    """3D: the two nodes (global numbers) of each boundary edge, shape [n_edges, 2], int64."""
    edge_facet: np.ndarray
    """3D: the two boundary triangles that share each edge, shape [n_edges, 2], int64."""

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
    facet_node = np.concatenate([m.facets + s for m, s in zip(meshes, node_start, strict=False)
                                 ]).astype(np.int64)
    return FEBodies(
        body=np.array(bodies, dtype=np.int32), fe_index=fe_index, meshes=tuple(meshes),
        materials=tuple(materials),
        node_x0=np.ascontiguousarray(np.concatenate([m.nodes for m in meshes])),
        node_side=np.concatenate(sides),
        boundary_start=np.cumsum([0] + [len(m.boundary_nodes) for m in meshes]).astype(np.int64),
        boundary_node=np.concatenate([m.boundary_nodes + s for m, s in
                                      zip(meshes, node_start, strict=False)]).astype(np.int64),
        facet_start=np.cumsum([0] + [len(m.facets) for m in meshes]).astype(np.int64),
        facet_node=facet_node,
        **_boundary_edges(facet_node, [len(m.facets) for m in meshes], dim),
    )


def _boundary_edges(facet_node: np.ndarray, facets: list[int], dim: int) -> dict:
    """FEBodies' edge_start, edge_node, edge_facet of the boundary triangles facet_node
    (`facets` per block, in block order): each side of a triangle once, with the two
    triangles of the closed surface that share it (none in 2D)."""
    if dim == 2:
        return {"edge_start": np.zeros(len(facets) + 1, dtype=np.int64),
                "edge_node": np.zeros((0, 2), dtype=np.int64),
                "edge_facet": np.zeros((0, 2), dtype=np.int64)}
    sides = np.concatenate([facet_node[:, [0, 1]], facet_node[:, [1, 2]],
                            facet_node[:, [2, 0]]])
    owner = np.tile(np.arange(len(facet_node)), 3)
    order = np.lexsort((sides.max(axis=1), sides.min(axis=1)))
    # on a closed surface each edge is the side of exactly two triangles, adjacent in order
    first, second = order[0::2], order[1::2]
    edge_node = sides[first]
    edge_facet = np.column_stack((owner[first], owner[second]))
    block = np.searchsorted(np.cumsum(facets), edge_facet[:, 0], side="right")
    keep = np.argsort(block, kind="stable")
    return {"edge_start": np.concatenate([[0], np.cumsum(np.bincount(block, minlength=len(
                facets)))]).astype(np.int64),
            "edge_node": np.ascontiguousarray(edge_node[keep]),
            "edge_facet": np.ascontiguousarray(edge_facet[keep])}


def _mesh_polygons(polygons, sizes, names) -> tuple[list[Mesh], list[np.ndarray]]:
    """Triangle meshes of the polygons and their node sides [n, 2, 2] (FEBodies.node_side)."""
    meshes, sides = [], []
    for poly, size, name in zip(polygons, sizes, names, strict=True):
        if isinstance(size, Mesh):
            mesh = _fit_polygon(size, poly, name)
        else:
            if size is None:
                size = 0.2 * float(np.linalg.norm(np.roll(poly, -1, axis=0) - poly,
                                                  axis=1).min())
            mesh = mesh_polygon(poly, size, name=name)
        meshes.append(mesh)
        edge = mesh.nodes[mesh.facets[:, 1]] - mesh.nodes[mesh.facets[:, 0]]
        half = 0.5 * np.column_stack((edge[:, 1], -edge[:, 0]))  # outward: counter-clockwise
        side = np.zeros((len(mesh.nodes), 2, 2))
        side[mesh.facets[:, 0], 0] = half  # each boundary node starts one edge, ends another
        side[mesh.facets[:, 1], 1] = half
        sides.append(side)
    return meshes, sides


def _fit_polygon(mesh: Mesh, polygon: np.ndarray, name: str) -> Mesh:
    """A given mesh of the convex polygon [k, 2] [m] (saxum.fe.mesh.fit_mesh)."""
    edge = np.roll(polygon, -1, axis=0) - polygon
    area = 0.5 * float(np.sum(polygon[:, 0] * edge[:, 1] - polygon[:, 1] * edge[:, 0]))
    normals = np.sign(area) * np.column_stack((edge[:, 1], -edge[:, 0]))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    return fit_mesh(mesh, normals, np.einsum("kd,kd->k", normals, polygon), abs(area),
                    name=name)


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
        self.v_free = np.zeros((n, d))
        """Free node velocities of the step [m/s]."""
        self.v = np.zeros((n, d))
        """Node velocities during and after the contact solve [m/s]."""
        self.v_begin = np.zeros((n, d))
        """Node velocities at the start of the step [m/s] (free_velocity's: the state's, which
        restitution and the joint laws read before the step's end updates them)."""
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
        fe_contact_rows(c.side_kind, c.side_node, c.side_weight, c.frame, c.impulse, problem.count,
                   problem.active, b.node_block, b.node_start, b.inv_start, b.inv,
                   self.rotation, problem.h_cand, problem.h_ant, problem.delassus, self.v)
        m = problem.model
        if (m.law_kind == _RESTITUTION).any():
            fe_restitution(c.side_kind, c.side_node, c.side_weight, c.candidate, c.antagonist,
                           c.law, problem.h_cand, problem.h_ant, problem.count, m.law_kind,
                           m.law_restitution, problem.v_begin, self.v_begin, problem.bias)

    def local_velocities(self, problem, v: np.ndarray, out: np.ndarray, begin: bool) -> None:
        """ContactProblem.local_velocities for problems with FE sides: U [m/s] from the
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
        return fe_end_gaps(c.side_kind, c.side_node, c.side_weight, c.candidate,
                              c.antagonist, problem.h_cand, problem.h_ant, c.gap, problem.count,
                              impulse, v, self.v, h, theta, problem.gap_end)


@nb.njit(inline="always")
def side_velocity(rows, a, kind, nodes, weights, body, v, node_v, u):
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


@nb.njit(cache=True)
def fe_local_velocities(cand, ant, h_cand, h_ant, side_kind, side_node, side_weight, count, v,
                        node_v, out):
    """out[a] = U [m/s] (local axes) of contacts with rigid or FE sides (side_velocity)."""
    for a in range(count):
        u = out[a]
        u[:] = 0.0
        side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0], cand[a], v,
                      node_v, u)
        side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1], ant[a], v,
                      node_v, u)


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
def side_push(rows, a, kind, nodes, weights, body, dr, inv_mass, v, node_block, node_start,
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
def fe_contact_rows(side_kind, side_node, side_weight, frame, impulse, count, active,
                       node_block, node_start, inv_start, inverse, rotation, h_cand, h_ant,
                       delassus, node_v):
    """For the FE sides of the contacts (side_kind 1), d = 2 or 3: rows of H* = +-[F, 0] on
    the nodes (candidate +, antagonist -), W += F (sum_pq w_p w_q R G[p, q] R^T) F^T, and the
    warm start node_v += M~^-1 H R on their nodes for active contacts (inactive: R = 0, set by
    assembly)."""
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
            congruence(frame, a, g, block)
            for r in range(d):
                for c in range(d):
                    delassus[a, r, c] += block[r, c]
            if active[a]:
                _push_side_nodes(rows, a, side_node[a, side], side_weight[a, side],
                                 impulse[a], node_block, node_start, inv_start, inverse,
                                 rotation, node_v, f, pl, dv)


@nb.njit(cache=True)
def fe_restitution(side_kind, side_node, side_weight, cand, ant, law, h_cand, h_ant, count,
                   law_kind, law_restitution, v_begin, node_v_begin, bias):
    """Newton's impact law on the contacts with an FE side under a restitution law: b_n = e_n
    min(U_n-, 0), U_n- = H* v at the start of the step with each side by its kind (the rigid
    assembly read an FE side's velocity from its body row, which holds only its frame), so
    that U_n+ = -e_n U_n- node by node (saxum.solver.problem._law)."""
    u = np.empty(h_cand.shape[1])
    for a in range(count):
        if law_kind[law[a]] != _RESTITUTION or (side_kind[a, 0] != 1 and side_kind[a, 1] != 1):
            continue
        u[:] = 0.0
        side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0], cand[a],
                      v_begin, node_v_begin, u)
        side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1], ant[a],
                      v_begin, node_v_begin, u)
        bias[a] = law_restitution[law[a]] * min(u[1], 0.0)


@nb.njit(cache=True)
def fe_end_gaps(side_kind, side_node, side_weight, cand, ant, h_cand, h_ant, gap, count,
                   impulse, v, node_v, h, theta, gap_end):
    """gap_end = g + theta h U_n with each side's velocity by its kind; returns (contacts
    with R_n > 0, largest interpenetration [m])."""
    u = np.empty(h_cand.shape[1])
    loaded = 0
    worst = 0.0
    for a in range(count):
        u[:] = 0.0
        side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0],
                         cand[a], v, node_v, u)
        side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1],
                         ant[a], v, node_v, u)
        g = gap[a] + theta * h * u[1]
        gap_end[a] = g
        loaded += impulse[a, 1] > 0.0
        worst = max(worst, -g)
    return loaded, worst
