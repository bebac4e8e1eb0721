"""All deformable blocks of a model as structure-of-arrays, and the compiled kernels of the
time step over them: co-rotated frames, internal forces, the theta-method's free velocity,
impulses through M~^-1, the condensed compliance of the boundary nodes, the position update,
element stresses and energies.

Co-rotational, small-strain formulation (C.A. Felippa & B. Haugen, "A unified formulation of
small-strain corotational finite elements: I. Theory", CMAME 194 (2005) 2285-2335): each block
carries a frame (rotation R, centroid c) fitted to its nodes; the strain is that of the local
displacement u = R^T (x - c) - (X0 - c0), so a rigid motion, however large, creates none. With
K, C, M~ of the reference mesh,

    f_int = R K u,   M~ = M + h theta C + h^2 theta^2 K,   C = alpha M + beta K,
    M~_world^-1 = R M~^-1 R^T (R applied node by node; M is rotation invariant),

and the theta-method of M. Jean (CMAME 177 (1999) 235-257, sec. 3),

    v_free = v + R_s M~^-1 h [R_s^T F - alpha M R_s^T v - K (u + (beta + h theta) u')],
    u' = R_s^T v - w x R^T (x - c)   (the co-rotated strain rate; K (w x (X0 - c0)) = 0),
    x_next = x + h [(1 - theta) v + theta v_next],

with R, c the frame fitted at the start of the step, w the block's spin (mass-weighted best
fit of the velocities, w = I^-1 sum m_i r_i x v_i) and R_s = exp(theta h [w]) R the frame
turned on to the step's theta point. Freezing the frame at R (R_s = R, u' = R^T v) leaves out
the turning of the internal force with the block, an O(h |f_int|) error per step: a block
spinning in free flight then gains energy at first order in h (a 1 m square, E = 10 MPa,
pi rad/s: 4 %, 2 %, 1 % over half a turn at h = 4, 2, 1 ms); with R_s and u' the error falls
to 2e-6, 3e-7, 4e-8 (tests/validation/test_fe_rigid_rotation.py). f_int = R K u is the
gradient of the strain energy only up to relative terms of the order of the strain (the frame
depends on the nodes; FH05 remove them with a projector, not done here), which leaves an energy
error of the order of the strain squared that does not fall with h. Contact impulses of the
step go through the same R_s: v_next = v_free + R_s M~^-1 R_s^T (H r).

The frame's rotation is the polar factor of A = sum_i m_i (x_i - c)(X0_i - c0)^T (m_i the
nodal masses, the row sums of the consistent M, so c is the centre of mass): the rotation that
best fits the reference onto the current nodes in the mass-weighted least-squares sense; a
rigid motion x = c + Q (X0 - c0) gives A = Q S with S symmetric positive definite, so R = Q
exactly. Within a step the scheme stays the linear theta-method of NSCD.md: one solve with the
constant M~ of the block's axes.

Why M~^-1 is stored dense, per block: a block has some 50-300 DOFs and M~^-1 of a connected
mesh is a full matrix anyway; NLGS needs the velocity response of the block's contact nodes to
an impulse on one node, a column of M~^-1, which the explicit inverse gives at the cost of
reading it (O(n)), where a sparse Cholesky factor would need a forward and back solve (O(nnz
of the factor)) per contact update. M and K stay sparse (CSR), the one global block-diagonal
matrix of all blocks. Units: SI throughout; in 2D, masses, forces and energies are those of the
block's depth (thickness in plane stress, per metre in plane strain).
"""

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from saxum.errors import InputError, plain
from saxum.fe.material import Elastic
from saxum.fe.mesh import Mesh

__all__ = [
    "FEBlocks",
    "apply_boundary_impulse",
    "apply_impulse",
    "apply_nodal_impulses",
    "boundary_compliance",
    "compliance_block",
    "congruence",
    "element_stresses",
    "frames",
    "free_velocity",
    "internal_forces",
    "kinetic_energy",
    "local_displacement",
    "predict_positions",
    "spins",
    "step_rotations",
    "strain_energy",
    "update_positions",
]


@dataclass
class FEBlocks:
    """Every deformable block of a model (nb blocks, N nodes, Mc cells in all; d = dim).

    Ragged per-block ranges are `*_start [nb + 1]` offsets into flat arrays, with global node
    indices (0..N-1) everywhere:
    node_start; x0 [N, d] reference coordinates [m]; node_block [N]; node_mass [N] nodal masses
    [kg] (row sums of M, in closed form: geometry()); c0 [nb, d] reference centres of mass [m];
    cell_start, cell_node [Mc, d + 1], cell_block [Mc], cell_grad [Mc, d + 1, d] gradients of the
    shape functions on the reference cell [1/m], cell_lame [Mc, 2] (lambda, mu) [Pa] (plane
    stress: effective lambda), cell_volume [Mc] [m^2 in 2D, m^3 in 3D];
    boundary_start, boundary_node [B] (contact candidates), node_boundary [N] (slot of a node in
    boundary_node, -1 inside), boundary_area [B] tributary boundary of each candidate in the
    reference configuration (2D: half of each adjacent boundary edge, a length [m]; 3D: a third
    of each adjacent boundary triangle [m^2]); facet_start, facet_node [F, d] outward boundary
    edges/triangles (antagonists);
    M, K: block-diagonal CSR over all N d dofs (dof d * node + component) as (indptr, indices,
    data) triples m_* and k_*, [kg] and [N/m] (None from geometry()); alpha [nb] [1/s],
    beta [nb] [s]; material [nb, 6] rows of Elastic.row();
    h [s], theta [-] and, for them, inv_start [nb + 1] and inv (flat): M~^-1 of block b,
    row-major (d n_b)^2 [1/kg], local frame; compliance_start [nb + 1]: offsets of the
    (d B_b)^2 condensed compliance G = B M~^-1 B^T of each block's boundary nodes.
    """

    dim: int
    node_start: np.ndarray
    x0: np.ndarray
    node_block: np.ndarray
    node_mass: np.ndarray
    c0: np.ndarray
    cell_start: np.ndarray
    cell_node: np.ndarray
    cell_block: np.ndarray
    cell_grad: np.ndarray
    cell_lame: np.ndarray
    cell_volume: np.ndarray
    boundary_start: np.ndarray
    boundary_node: np.ndarray
    node_boundary: np.ndarray
    boundary_area: np.ndarray
    facet_start: np.ndarray
    facet_node: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray
    material: np.ndarray
    m_indptr: np.ndarray | None = None
    m_indices: np.ndarray | None = None
    m_data: np.ndarray | None = None
    k_indptr: np.ndarray | None = None
    k_indices: np.ndarray | None = None
    k_data: np.ndarray | None = None
    h: float = math.nan
    theta: float = math.nan
    inv_start: np.ndarray | None = None
    inv: np.ndarray | None = None
    compliance_start: np.ndarray | None = None

    @property
    def n_blocks(self) -> int:
        return len(self.node_start) - 1

    @property
    def n_nodes(self) -> int:
        return len(self.x0)

    @classmethod
    def build(cls, meshes: list[Mesh], materials: list[Elastic], h: float,
              theta: float) -> "FEBlocks":
        """Assemble M and K of each block (scikit-fem) and prepare M~^-1 for the step h [s] and
        theta [-]."""
        import scipy.sparse as sp  # with scikit-fem, ~0.3 s: not for runs without FE blocks

        from saxum.fe.assembly import mass_stiffness

        blocks = cls.geometry(meshes, materials)
        masses, stiffnesses = zip(*(mass_stiffness(m, mat)
                                    for m, mat in zip(meshes, materials, strict=True)),
                                  strict=True)
        M = sp.block_diag(masses, format="csr")
        K = sp.block_diag(stiffnesses, format="csr")
        M.sort_indices()
        K.sort_indices()
        blocks.m_indptr, blocks.m_indices, blocks.m_data = (
            M.indptr.astype(np.int64), M.indices.astype(np.int64), M.data)
        blocks.k_indptr, blocks.k_indices, blocks.k_data = (
            K.indptr.astype(np.int64), K.indices.astype(np.int64), K.data)
        blocks.prepare(h, theta)
        return blocks

    @classmethod
    def geometry(cls, meshes: list[Mesh], materials: list[Elastic]) -> "FEBlocks":
        """The blocks without M, K and M~^-1: what frames and stresses need (build() adds the
        rest). Nodal masses are the row sums of the consistent P1 mass matrix in closed form,
        rho t V_e / (d + 1) from each cell e at the node (t the depth in 2D, 1 m in 3D: the
        element matrix rho t V_e (1 + delta_ij) / ((d + 1)(d + 2)) sums to that per row)."""
        if len(meshes) != len(materials) or not meshes:
            raise InputError(f"FE blocks: {len(meshes)} meshes and {len(materials)} materials; "
                             "give one material per mesh, at least one block")
        dim = meshes[0].dim
        if any(m.dim != dim for m in meshes):
            raise InputError("FE blocks: meshes of different dimensions in one model")
        sizes = np.array([len(m.nodes) for m in meshes])
        node_start = np.concatenate([[0], np.cumsum(sizes)])
        cell_start = np.concatenate([[0], np.cumsum([len(m.cells) for m in meshes])])
        boundary_start = np.concatenate([[0], np.cumsum([len(m.boundary_nodes)
                                                         for m in meshes])])
        facet_start = np.concatenate([[0], np.cumsum([len(m.facets) for m in meshes])])
        x0 = np.concatenate([m.nodes for m in meshes])
        cell_node = np.concatenate([m.cells + s for m, s in zip(meshes, node_start, strict=False)])
        boundary_node = np.concatenate([m.boundary_nodes + s
                                        for m, s in zip(meshes, node_start, strict=False)])
        facet_node = np.concatenate([m.facets + s
                                     for m, s in zip(meshes, node_start, strict=False)])
        node_block = np.repeat(np.arange(len(meshes)), sizes)
        cell_block = np.repeat(np.arange(len(meshes)), np.diff(cell_start))
        node_boundary = np.full(len(x0), -1, dtype=np.int64)
        node_boundary[boundary_node] = np.arange(len(boundary_node))
        xf = x0[facet_node]
        if dim == 2:
            facet_size = np.linalg.norm(xf[:, 1] - xf[:, 0], axis=1)
        else:
            facet_size = 0.5 * np.linalg.norm(np.cross(xf[:, 1] - xf[:, 0], xf[:, 2] - xf[:, 0]),
                                              axis=1)
        boundary_area = np.zeros(len(boundary_node))
        np.add.at(boundary_area, node_boundary[facet_node], facet_size[:, None] / dim)
        xc = x0[cell_node]
        edges = np.swapaxes(xc[:, 1:] - xc[:, :1], 1, 2)  # [Mc, d, d]: columns x_k - x_0
        inverse = np.linalg.inv(edges)  # rows: gradients of the barycentric coordinates 1..d
        grad = np.concatenate([-inverse.sum(axis=1, keepdims=True), inverse], axis=1)
        lame = np.array([mat.lame(dim) for mat in materials])[cell_block]
        volume = np.abs(np.linalg.det(edges)) / math.factorial(dim)
        density = np.array([mat.density * mat.depth(dim) for mat in materials])
        node_mass = np.zeros(len(x0))
        np.add.at(node_mass, cell_node, (density[cell_block] * volume / (dim + 1))[:, None])
        return cls(
            dim=dim, node_start=node_start.astype(np.int64), x0=x0, node_block=node_block,
            node_mass=node_mass, c0=_centres(x0, node_start, node_mass),
            cell_start=cell_start.astype(np.int64),
            cell_node=cell_node.astype(np.int64), cell_block=cell_block, cell_grad=grad,
            cell_lame=lame, cell_volume=volume,
            boundary_start=boundary_start.astype(np.int64),
            boundary_node=boundary_node.astype(np.int64), node_boundary=node_boundary,
            boundary_area=boundary_area,
            facet_start=facet_start.astype(np.int64), facet_node=facet_node.astype(np.int64),
            alpha=np.array([mat.damping[0] for mat in materials]),
            beta=np.array([mat.damping[1] for mat in materials]),
            material=np.array([mat.row() for mat in materials]))

    def prepare(self, h: float, theta: float) -> None:
        """Factor M~ = (1 + h theta alpha) M + (h theta beta + h^2 theta^2) K of every block
        (dense Cholesky, scipy) and store its inverse, for the step h [s] and theta [-]."""
        if not (math.isfinite(h) and h > 0.0):
            raise InputError(f"FE blocks: time step h = {plain(h)} s must be positive")
        if not 0.5 <= theta <= 1.0:
            raise InputError(f"FE blocks: theta = {plain(theta)} must lie in [0.5, 1]")
        d = self.dim
        dofs = d * np.diff(self.node_start)
        self.inv_start = np.concatenate([[0], np.cumsum(dofs * dofs)]).astype(np.int64)
        boundary = d * np.diff(self.boundary_start)
        self.compliance_start = np.concatenate([[0], np.cumsum(boundary * boundary)]).astype(
            np.int64)
        self.inv = np.empty(self.inv_start[-1])
        ht = h * theta
        # Equal blocks share one factorization: a wall's bricks are translated copies whose M~
        # differ only by round-off, so M~ is compared to 12 digits of its largest entry (the
        # inverse itself is only that accurate, cond(M~) ~ 1e3)
        done = {}
        for b in range(self.n_blocks):
            a, e = d * self.node_start[b], d * self.node_start[b + 1]
            m = self._block_matrix(self.m_indptr, self.m_indices, self.m_data, a, e)
            k = self._block_matrix(self.k_indptr, self.k_indices, self.k_data, a, e)
            mt = (1.0 + ht * self.alpha[b]) * m + (ht * self.beta[b] + ht * ht) * k
            key = (e - a, (np.round(mt / np.abs(mt).max(), 12) + 0.0).tobytes())
            if key not in done:
                import scipy.linalg

                inv = scipy.linalg.cho_solve(scipy.linalg.cho_factor(mt), np.eye(e - a))
                done[key] = (0.5 * (inv + inv.T)).ravel()
            self.inv[self.inv_start[b]:self.inv_start[b + 1]] = done[key]
        self.h = float(h)
        self.theta = float(theta)

    @staticmethod
    def _block_matrix(indptr, indices, data, a, e):
        """Dense diagonal block [a:e, a:e] of the block-diagonal CSR matrix."""
        import scipy.sparse as sp

        rows = sp.csr_matrix((data[indptr[a]:indptr[e]], indices[indptr[a]:indptr[e]] - a,
                              indptr[a:e + 1] - indptr[a]), shape=(e - a, e - a))
        return rows.toarray()

    # Python entry points over all blocks (the kernels below do the work)

    def frames(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(rotation [nb, d, d], centroid [nb, d] [m]) of the nodes x [N, d] [m]."""
        rotation = np.empty((self.n_blocks, self.dim, self.dim))
        centroid = np.empty((self.n_blocks, self.dim))
        frames(self.node_start, self.x0, self.c0, self.node_mass, x, rotation, centroid)
        return rotation, centroid

    def internal_forces(self, x, rotation, centroid) -> np.ndarray:
        """f_int = R K u [N], world axes, [N, d]."""
        f = np.empty_like(x)
        internal_forces(self.node_start, self.x0, self.c0, self.k_indptr, self.k_indices,
                        self.k_data, x, rotation, centroid, f)
        return f

    def step_frames(self, x: np.ndarray, v: np.ndarray):
        """The frames of a step from positions x [m] and velocities v [m/s], [N, d]:
        (rotation [nb, d, d], centroid [nb, d] [m], spin [nb, 1 | 3] [rad/s], rotation_step
        [nb, d, d]). rotation and centroid give strains and stresses; rotation_step is the
        frame of M~^-1 in this step (free_velocity, apply_impulse, boundary_compliance)."""
        rotation, centroid = self.frames(x)
        spin = np.empty((self.n_blocks, 1 if self.dim == 2 else 3))
        spins(self.node_start, self.node_mass, x, v, centroid, spin)
        rotation_step = np.empty_like(rotation)
        step_rotations(rotation, spin, self.h, self.theta, rotation_step)
        return rotation, centroid, spin, rotation_step

    def rigid_velocities(self, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The rigid motion nearest (mass-weighted) to node velocities v [m/s] at positions x
        [m], [N, d] or a stack of frames [F, N, d]: (velocity of each block's centre of mass
        [nb, d] [m/s], spin [nb, 1 | 3] [rad/s], spins()), with a leading [F] for a stack."""
        x = np.ascontiguousarray(x, dtype=np.float64)
        v = np.ascontiguousarray(v, dtype=np.float64)
        frames_ = x.reshape((-1,) + x.shape[-2:])
        velocity = np.empty((len(frames_), self.n_blocks, self.dim))
        spin = np.empty((len(frames_), self.n_blocks, 1 if self.dim == 2 else 3))
        rigid_motions(self.node_start, self.node_mass, frames_, v.reshape(frames_.shape),
                      velocity, spin)
        return velocity.reshape(x.shape[:-2] + velocity.shape[1:]), spin.reshape(
            x.shape[:-2] + spin.shape[1:])

    def free_velocity(self, x, v, force, rotation, centroid, spin, rotation_step) -> np.ndarray:
        """v_free [m/s] [N, d] from positions x [m], velocities v [m/s], nodal forces `force`
        [N] [N, d] (world axes) and the step's frames (step_frames), for the h, theta of
        prepare()."""
        v_free = np.empty_like(v)
        free_velocity(self.node_start, self.x0, self.c0, self.m_indptr, self.m_indices,
                      self.m_data, self.k_indptr, self.k_indices, self.k_data, self.alpha,
                      self.beta, self.inv_start, self.inv, self.h, self.theta, x, v, force,
                      rotation, centroid, spin, rotation_step, v_free)
        return v_free

    def apply_nodal_impulses(self, impulse, rotation, v) -> None:
        """v += R_s M~^-1 R_s^T impulse for all blocks, impulse [N, d] [N s] world axes, in
        place; rotation = R_s, the rotation_step of step_frames."""
        apply_nodal_impulses(self.node_start, self.inv_start, self.inv, impulse, rotation, v)

    def apply_impulse(self, block, nodes, impulses, rotation, v) -> None:
        """v[every node of block] += R_s M~^-1 R_s^T P with P = impulses [k, d] [N s] (world
        axes) at `nodes` [k] (global node indices of that block), in place; rotation = R_s."""
        apply_impulse(self.node_start, self.inv_start, self.inv, block,
                      np.asarray(nodes, dtype=np.int64), impulses, rotation, v)

    def apply_boundary_impulse(self, block, nodes, impulses, rotation, v) -> None:
        """v[boundary nodes of block] += R_s B M~^-1 R_s^T P, P = impulses [k, d] [N s] at
        `nodes` [k] (global indices) of that block, in place (interior nodes untouched);
        rotation = R_s."""
        apply_boundary_impulse(self.node_start, self.boundary_start, self.boundary_node,
                               self.inv_start, self.inv, rotation, block,
                               np.asarray(nodes, dtype=np.int64), impulses, v)

    def compliance_block(self, block, i, j, rotation) -> np.ndarray:
        """R_s W_ij R_s^T [1/kg] [d, d] between global nodes i and j of `block`."""
        out = np.empty((self.dim, self.dim))
        compliance_block(self.node_start, self.inv_start, self.inv, rotation, block, i, j, out)
        return out

    def boundary_compliance(self, rotation) -> np.ndarray:
        """G_world = R_s (B M~^-1 B^T) R_s^T of every block's boundary nodes [1/kg], flat with
        offsets compliance_start, block b row-major (d B_b)^2 in the order of boundary_node;
        rotation = R_s."""
        out = np.empty(self.compliance_start[-1])
        boundary_compliance(self.node_start, self.boundary_start, self.boundary_node,
                            self.inv_start, self.inv, self.compliance_start, rotation, out)
        return out

    def predict_positions(self, x, v) -> np.ndarray:
        """x + (1 - theta) h v [m]: the configuration contacts are detected on."""
        out = x.copy()
        predict_positions(out, v, self.h, self.theta)
        return out

    def update_positions(self, x, v, v_next) -> None:
        """x += h [(1 - theta) v + theta v_next] [m], in place."""
        update_positions(x, v, v_next, self.h, self.theta)

    def stresses(self, x, rotation, centroid):
        """Element stresses, world axes [Pa]: (stress [Mc, 3 | 6] (2D: sxx, syy, sxy; 3D: sxx,
        syy, szz, syz, sxz, sxy), principal [Mc, d] ascending (2D: in-plane), compression
        [Mc] = max(0, -smallest principal), tension [Mc] = max(0, largest principal))."""
        mc = len(self.cell_node)
        stress = np.empty((mc, 3 if self.dim == 2 else 6))
        principal = np.empty((mc, self.dim))
        element_stresses(self.x0, self.c0, self.cell_node, self.cell_block, self.cell_grad,
                         self.cell_lame, x, rotation, centroid, stress, principal)
        return (stress, principal, np.maximum(0.0, -principal[:, 0]),
                np.maximum(0.0, principal[:, -1]))

    def kinetic_energy(self, v) -> np.ndarray:
        """1/2 v^T M v [J] per block [nb]."""
        out = np.empty(self.n_blocks)
        kinetic_energy(self.node_start, self.m_indptr, self.m_indices, self.m_data, v, out)
        return out

    def strain_energy(self, x, rotation, centroid) -> np.ndarray:
        """1/2 u^T K u [J] per block [nb], u the co-rotated local displacement."""
        out = np.empty(self.n_blocks)
        strain_energy(self.node_start, self.x0, self.c0, self.k_indptr, self.k_indices,
                      self.k_data, x, rotation, centroid, out)
        return out

    def weight(self, gravity) -> np.ndarray:
        """Nodal forces of the self-weight [N] [N, d]: M times the uniform field g [m/s^2]
        is the nodal mass times g (consistent and lumped agree for a uniform field)."""
        return self.node_mass[:, None] * np.asarray(gravity, dtype=np.float64)[None, :]


def _centres(x0: np.ndarray, node_start: np.ndarray, node_mass: np.ndarray) -> np.ndarray:
    """Centre of mass of each block's reference nodes [m], [nb, d]."""
    return np.array([np.average(x0[a:b], axis=0, weights=node_mass[a:b])
                     for a, b in zip(node_start[:-1], node_start[1:], strict=True)])


# ---- compiled kernels (all blocks in one call; no Python loop over blocks or nodes) ----


@nb.njit(cache=True)
def centroids(node_start, node_mass, x, centroid):
    """centroid[b] = sum m_i x_i / sum m_i [m] over block b's nodes."""
    d = x.shape[1]
    for b in range(len(node_start) - 1):
        total = 0.0
        for k in range(d):
            centroid[b, k] = 0.0
        for i in range(node_start[b], node_start[b + 1]):
            total += node_mass[i]
            for k in range(d):
                centroid[b, k] += node_mass[i] * x[i, k]
        for k in range(d):
            centroid[b, k] /= total


@nb.njit(cache=True)
def rigid_motions(node_start, node_mass, x, v, velocity, spin):
    """For each of the F frames of x, v [F, N, d] ([m], [m/s]): velocity[f, b] = sum m_i v_i /
    sum m_i [m/s] and spin[f, b] [rad/s] (spins()) of block b, the rigid motion nearest
    (mass-weighted) to its nodal velocities."""
    nb_ = len(node_start) - 1
    d = x.shape[2]
    centroid = np.empty((nb_, d))
    for f in range(x.shape[0]):
        centroids(node_start, node_mass, x[f], centroid)
        spins(node_start, node_mass, x[f], v[f], centroid, spin[f])
        for b in range(nb_):
            total = 0.0
            for k in range(d):
                velocity[f, b, k] = 0.0
            for i in range(node_start[b], node_start[b + 1]):
                total += node_mass[i]
                for k in range(d):
                    velocity[f, b, k] += node_mass[i] * v[f, i, k]
            for k in range(d):
                velocity[f, b, k] /= total


@nb.njit(cache=True)
def frames(node_start, x0, c0, node_mass, x, rotation, centroid):
    """centroid[b] = sum m_i x_i / sum m_i [m]; rotation[b] = polar factor of A = sum m_i (x_i -
    c)(X0_i - c0)^T (2D: the angle atan2(A10 - A01, A00 + A11); 3D: U diag(1, 1, det) V^T
    from the SVD A = U S V^T), the best mass-weighted rigid fit of the reference."""
    d = x.shape[1]
    centroids(node_start, node_mass, x, centroid)
    for b in range(len(node_start) - 1):
        a = np.zeros((d, d))
        for i in range(node_start[b], node_start[b + 1]):
            for k in range(d):
                dx = node_mass[i] * (x[i, k] - centroid[b, k])
                for m in range(d):
                    a[k, m] += dx * (x0[i, m] - c0[b, m])
        if d == 2:
            angle = math.atan2(a[1, 0] - a[0, 1], a[0, 0] + a[1, 1])
            c = math.cos(angle)
            s = math.sin(angle)
            rotation[b, 0, 0] = c
            rotation[b, 0, 1] = -s
            rotation[b, 1, 0] = s
            rotation[b, 1, 1] = c
        else:
            u, _, vt = np.linalg.svd(a)
            r = u @ vt
            if np.linalg.det(r) < 0.0:
                for k in range(3):
                    u[k, 2] = -u[k, 2]
                r = u @ vt
            rotation[b] = r


@nb.njit(cache=True)
def spins(node_start, node_mass, x, v, centroid, spin):
    """spin[b] = I^-1 sum m_i r_i x v_i [rad/s], r_i = x_i - c, I = sum m_i (|r_i|^2 1 - r_i
    r_i^T): the angular velocity of the rigid motion nearest (mass-weighted) to the nodal
    velocities; spin [nb, 1] (2D: about z) or [nb, 3]."""
    d = x.shape[1]
    for b in range(len(node_start) - 1):
        if d == 2:
            num = 0.0
            den = 0.0
            for i in range(node_start[b], node_start[b + 1]):
                rx = x[i, 0] - centroid[b, 0]
                ry = x[i, 1] - centroid[b, 1]
                num += node_mass[i] * (rx * v[i, 1] - ry * v[i, 0])
                den += node_mass[i] * (rx * rx + ry * ry)
            spin[b, 0] = num / den
        else:
            inertia = np.zeros((3, 3))
            momentum = np.zeros(3)
            r = np.empty(3)
            for i in range(node_start[b], node_start[b + 1]):
                for k in range(3):
                    r[k] = x[i, k] - centroid[b, k]
                rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
                for k in range(3):
                    inertia[k, k] += node_mass[i] * rr
                    for m in range(3):
                        inertia[k, m] -= node_mass[i] * r[k] * r[m]
                momentum[0] += node_mass[i] * (r[1] * v[i, 2] - r[2] * v[i, 1])
                momentum[1] += node_mass[i] * (r[2] * v[i, 0] - r[0] * v[i, 2])
                momentum[2] += node_mass[i] * (r[0] * v[i, 1] - r[1] * v[i, 0])
            spin[b] = np.linalg.solve(inertia, momentum)


@nb.njit(cache=True)
def step_rotations(rotation, spin, h, theta, rotation_step):
    """rotation_step[b] = exp(theta h [w_b]) rotation[b]: the frame turned on by the spin to the
    step's theta point (Rodrigues' formula in 3D)."""
    d = rotation.shape[1]
    for b in range(rotation.shape[0]):
        if d == 2:
            a = theta * h * spin[b, 0]
            c = math.cos(a)
            s = math.sin(a)
            for m in range(2):
                rotation_step[b, 0, m] = c * rotation[b, 0, m] - s * rotation[b, 1, m]
                rotation_step[b, 1, m] = s * rotation[b, 0, m] + c * rotation[b, 1, m]
        else:
            wx = theta * h * spin[b, 0]
            wy = theta * h * spin[b, 1]
            wz = theta * h * spin[b, 2]
            a = math.sqrt(wx * wx + wy * wy + wz * wz)
            # sin(a)/a and (1 - cos(a))/a^2 by their series near 0
            if a < 1e-4:
                s1 = 1.0 - a * a / 6.0
                s2 = 0.5 - a * a / 24.0
            else:
                s1 = math.sin(a) / a
                s2 = (1.0 - math.cos(a)) / (a * a)
            w = np.array([[0.0, -wz, wy], [wz, 0.0, -wx], [-wy, wx, 0.0]])
            turn = np.eye(3) + s1 * w + s2 * (w @ w)
            rotation_step[b] = turn @ rotation[b]


@nb.njit(cache=True)
def local_displacement(node_start, x0, c0, x, rotation, centroid, u):
    """u_i = R^T (x_i - c) - (X0_i - c0) [m], the co-rotated displacement, u [N, d]."""
    d = x.shape[1]
    for b in range(len(node_start) - 1):
        for i in range(node_start[b], node_start[b + 1]):
            for k in range(d):
                s = 0.0
                for m in range(d):
                    s += rotation[b, m, k] * (x[i, m] - centroid[b, m])
                u[i, k] = s - (x0[i, k] - c0[b, k])


@nb.njit(cache=True)
def _to_local(node_start, rotation, w, out):
    """out_i = R_b^T w_i node by node (world to block axes)."""
    d = w.shape[1]
    for b in range(len(node_start) - 1):
        for i in range(node_start[b], node_start[b + 1]):
            for k in range(d):
                s = 0.0
                for m in range(d):
                    s += rotation[b, m, k] * w[i, m]
                out[i, k] = s


@nb.njit(cache=True)
def _csr_matvec(indptr, indices, data, y, out):
    """out = A y for a CSR matrix over the flat dofs (y, out [N, d] viewed as [N d])."""
    flat = y.reshape(-1)
    res = out.reshape(-1)
    for r in range(len(indptr) - 1):
        s = 0.0
        for p in range(indptr[r], indptr[r + 1]):
            s += data[p] * flat[indices[p]]
        res[r] = s


@nb.njit(cache=True)
def _rotate_add(node_start, rotation, local, out):
    """out_i += R_b local_i node by node (block to world axes)."""
    d = local.shape[1]
    for b in range(len(node_start) - 1):
        for i in range(node_start[b], node_start[b + 1]):
            for k in range(d):
                s = 0.0
                for m in range(d):
                    s += rotation[b, k, m] * local[i, m]
                out[i, k] += s


@nb.njit(cache=True)
def internal_forces(node_start, x0, c0, k_indptr, k_indices, k_data, x, rotation, centroid, f):
    """f = R K u [N], u the co-rotated displacement; f [N, d] world axes (overwritten)."""
    u = np.empty_like(x)
    local_displacement(node_start, x0, c0, x, rotation, centroid, u)
    ku = np.empty_like(x)
    _csr_matvec(k_indptr, k_indices, k_data, u, ku)
    f[:] = 0.0
    _rotate_add(node_start, rotation, ku, f)


@nb.njit(cache=True)
def _dense_solve(node_start, inv_start, inv, rhs, out):
    """out[block b] = M~_b^-1 rhs[block b] for every block (local axes, overwritten); np.dot
    (BLAS dgemv) is some 5 times faster here than a compiled loop."""
    d = rhs.shape[1]
    flat = rhs.reshape(-1)
    res = out.reshape(-1)
    for b in range(len(node_start) - 1):
        a = d * node_start[b]
        n = d * node_start[b + 1] - a
        res[a:a + n] = np.dot(inv[inv_start[b]:inv_start[b + 1]].reshape(n, n), flat[a:a + n])


@nb.njit(cache=True)
def free_velocity(node_start, x0, c0, m_indptr, m_indices, m_data, k_indptr, k_indices, k_data,
                  alpha, beta, inv_start, inv, h, theta, x, v, force, rotation, centroid, spin,
                  rotation_step, v_free):
    """v_free = v + R_s M~^-1 h [R_s^T F - alpha M R_s^T v - K (u + (beta + h theta) u')],
    u' = R_s^T v - w x R^T (x - c) (module docstring), [m/s] [N, d]; force F [N] [N, d] world
    axes; rotation R and centroid c from frames(), spin w from spins(), rotation_step R_s from
    step_rotations()."""
    d = x.shape[1]
    u = np.empty_like(x)
    local_displacement(node_start, x0, c0, x, rotation, centroid, u)
    vl = np.empty_like(v)
    _to_local(node_start, rotation_step, v, vl)
    rhs = np.empty_like(v)
    _to_local(node_start, rotation_step, force, rhs)
    # u += (beta + h theta) u', with w x R^T (x - c) = w x (u + X0 - c0) and K (w x (X0 - c0))
    # = 0: only w x u is needed (2D: w e_z x u; 3D: w in block axes R^T w = R_s^T w)
    for b in range(len(node_start) - 1):
        g = beta[b] + h * theta
        if d == 2:
            w = spin[b, 0]
            for i in range(node_start[b], node_start[b + 1]):
                ux = u[i, 0]
                uy = u[i, 1]
                u[i, 0] = ux + g * (vl[i, 0] + w * uy)
                u[i, 1] = uy + g * (vl[i, 1] - w * ux)
        else:
            wl = rotation[b].T @ spin[b]
            for i in range(node_start[b], node_start[b + 1]):
                cx = wl[1] * u[i, 2] - wl[2] * u[i, 1]
                cy = wl[2] * u[i, 0] - wl[0] * u[i, 2]
                cz = wl[0] * u[i, 1] - wl[1] * u[i, 0]
                u[i, 0] += g * (vl[i, 0] - cx)
                u[i, 1] += g * (vl[i, 1] - cy)
                u[i, 2] += g * (vl[i, 2] - cz)
    ku = np.empty_like(v)
    _csr_matvec(k_indptr, k_indices, k_data, u, ku)
    mv = np.empty_like(v)
    _csr_matvec(m_indptr, m_indices, m_data, vl, mv)
    for b in range(len(node_start) - 1):
        for i in range(node_start[b], node_start[b + 1]):
            for k in range(d):
                rhs[i, k] = h * (rhs[i, k] - alpha[b] * mv[i, k] - ku[i, k])
    dv = np.empty_like(v)
    _dense_solve(node_start, inv_start, inv, rhs, dv)
    v_free[:] = v
    _rotate_add(node_start, rotation_step, dv, v_free)


@nb.njit(cache=True)
def apply_nodal_impulses(node_start, inv_start, inv, impulse, rotation, v):
    """v += R M~^-1 R^T impulse for every block [m/s]; impulse [N, d] [N s] world axes."""
    local = np.empty_like(impulse)
    _to_local(node_start, rotation, impulse, local)
    dv = np.empty_like(impulse)
    _dense_solve(node_start, inv_start, inv, local, dv)
    _rotate_add(node_start, rotation, dv, v)


@nb.njit(inline="always")
def _impulse_in_block_frame(rotation, block, impulses, j, pl):
    """pl = R_s^T P_j [N s]: impulse j (world axes) in the block's step frame."""
    d = pl.shape[0]
    for k in range(d):
        s = 0.0
        for m in range(d):
            s += rotation[block, m, k] * impulses[j, m]
        pl[k] = s


@nb.njit(inline="always")
def _add_node_velocity(inv, row, n, pl, rotation, block, dv, v, i):
    """v[i] += R_s W pl [m/s], W the d x d block of M~^-1 whose first entry is inv[row] (row
    stride n); dv is work memory [d]."""
    d = pl.shape[0]
    for k in range(d):
        s = 0.0
        for m in range(d):
            s += inv[row + k * n + m] * pl[m]
        dv[k] = s
    for k in range(d):
        s = 0.0
        for m in range(d):
            s += rotation[block, k, m] * dv[m]
        v[i, k] += s


@nb.njit(cache=True)
def apply_impulse(node_start, inv_start, inv, block, nodes, impulses, rotation, v):
    """v[i] += R M~^-1 R^T P for every node i of `block` [m/s], P = impulses [k, d] [N s]
    (world axes) at the global node indices nodes [k] of that block: the columns of M~^-1 of
    those nodes only, O(d n_b k d)."""
    d = v.shape[1]
    first = node_start[block]
    n = d * (node_start[block + 1] - first)
    base = inv_start[block]
    pl = np.empty(d)
    dv = np.empty(d)
    for j in range(len(nodes)):
        _impulse_in_block_frame(rotation, block, impulses, j, pl)
        col = d * (nodes[j] - first)
        for i in range(first, node_start[block + 1]):
            _add_node_velocity(inv, base + d * (i - first) * n + col, n, pl, rotation, block, dv,
                               v, i)


@nb.njit(cache=True)
def compliance_block(node_start, inv_start, inv, rotation, block, i, j, out):
    """out = R_s W_ij R_s^T [1/kg], [d, d]: the block of the world M~^-1 between nodes i and j
    (global indices) of `block`, what a Delassus block W_aa = sum F w w out F^T needs."""
    d = out.shape[0]
    first = node_start[block]
    n = d * (node_start[block + 1] - first)
    row = inv_start[block] + d * (i - first) * n + d * (j - first)
    for k in range(d):
        for m in range(d):
            s = 0.0
            for a in range(d):
                for c in range(d):
                    s += rotation[block, k, a] * inv[row + a * n + c] * rotation[block, m, c]
            out[k, m] = s


@nb.njit(cache=True)
def apply_boundary_impulse(node_start, boundary_start, boundary_node, inv_start, inv, rotation,
                           block, nodes, impulses, v):
    """v[q] += R_s W_qp R_s^T P_p for every boundary node q of `block` [m/s], P = impulses
    [k, d] [N s] (world axes) at nodes p = nodes [k] (global indices), W the blocks of M~^-1
    (the condensed compliance B M~^-1 B^T read in place): the velocity update of an NLGS
    contact update, O(d^2 B_b k); interior nodes are not touched."""
    d = v.shape[1]
    first = node_start[block]
    n = d * (node_start[block + 1] - first)
    base = inv_start[block]
    pl = np.empty(d)
    dv = np.empty(d)
    for j in range(len(nodes)):
        _impulse_in_block_frame(rotation, block, impulses, j, pl)
        col = d * (nodes[j] - first)
        for q in range(boundary_start[block], boundary_start[block + 1]):
            i = boundary_node[q]
            _add_node_velocity(inv, base + d * (i - first) * n + col, n, pl, rotation, block, dv,
                               v, i)


@nb.njit(cache=True)
def boundary_compliance(node_start, boundary_start, boundary_node, inv_start, inv,
                        compliance_start, rotation, out):
    """out[block b] = R (B M~^-1 B^T) R^T [1/kg], (d B_b)^2 row-major over the block's
    boundary nodes in boundary_node order: G[p, q] = R W_pq R^T, W_pq the d x d block of M~^-1
    between boundary nodes p and q (the Delassus contribution of the block)."""
    d = rotation.shape[1]
    w = np.empty((d, d))
    t = np.empty((d, d))
    for b in range(len(node_start) - 1):
        first = node_start[b]
        n = d * (node_start[b + 1] - first)
        nbnd = boundary_start[b + 1] - boundary_start[b]
        size = d * nbnd
        for p in range(nbnd):
            rp = d * (boundary_node[boundary_start[b] + p] - first)
            for q in range(nbnd):
                cq = d * (boundary_node[boundary_start[b] + q] - first)
                for a in range(d):
                    for c in range(d):
                        w[a, c] = inv[inv_start[b] + (rp + a) * n + cq + c]
                for k in range(d):
                    for c in range(d):
                        s = 0.0
                        for a in range(d):
                            s += rotation[b, k, a] * w[a, c]
                        t[k, c] = s
                row = compliance_start[b] + d * p * size + d * q
                for k in range(d):
                    for m in range(d):
                        s = 0.0
                        for c in range(d):
                            s += t[k, c] * rotation[b, m, c]
                        out[row + k * size + m] = s


@nb.njit(cache=True)
def predict_positions(x, v, h, theta):
    """x += (1 - theta) h v [m], in place."""
    for i in range(x.shape[0]):
        for k in range(x.shape[1]):
            x[i, k] += (1.0 - theta) * h * v[i, k]


@nb.njit(cache=True)
def update_positions(x, v, v_next, h, theta):
    """x += h [(1 - theta) v + theta v_next] [m], in place."""
    for i in range(x.shape[0]):
        for k in range(x.shape[1]):
            x[i, k] += h * ((1.0 - theta) * v[i, k] + theta * v_next[i, k])


@nb.njit(inline="always")
def congruence(r, b, s, out):
    """out = r[b] s r[b]^T [d, d]: a tensor s turned by the rotation (or frame) r[b]."""
    d = s.shape[0]
    for k in range(d):
        for m in range(d):
            t = 0.0
            for a in range(d):
                for c in range(d):
                    t += r[b, k, a] * s[a, c] * r[b, m, c]
            out[k, m] = t


@nb.njit(cache=True)
def element_stresses(x0, c0, cell_node, cell_block, cell_grad, cell_lame, x, rotation,
                     centroid, stress, principal):
    """Stress of each linear cell [Pa] from the co-rotated displacement: eps = sym(sum_a u_a
    grad N_a), sigma_l = lambda tr(eps) I + 2 mu eps, sigma = R sigma_l R^T; stress [Mc, 3 | 6]
    (2D: xx, yy, xy; 3D: xx, yy, zz, yz, xz, xy), principal [Mc, d] ascending (eigenvalues of
    the in-plane tensor in 2D)."""
    d = x.shape[1]
    eps = np.empty((d, d))
    sl = np.empty((d, d))
    sw = np.empty((d, d))
    ul = np.empty(d)
    for e in range(cell_node.shape[0]):
        b = cell_block[e]
        eps[:] = 0.0
        for a in range(d + 1):
            i = cell_node[e, a]
            for k in range(d):
                s = 0.0
                for m in range(d):
                    s += rotation[b, m, k] * (x[i, m] - centroid[b, m])
                ul[k] = s - (x0[i, k] - c0[b, k])
            for k in range(d):
                for m in range(d):
                    eps[k, m] += 0.5 * (ul[k] * cell_grad[e, a, m] + ul[m] * cell_grad[e, a, k])
        trace = 0.0
        for k in range(d):
            trace += eps[k, k]
        for k in range(d):
            for m in range(d):
                sl[k, m] = 2.0 * cell_lame[e, 1] * eps[k, m]
            sl[k, k] += cell_lame[e, 0] * trace
        congruence(rotation, b, sl, sw)
        if d == 2:
            stress[e, 0] = sw[0, 0]
            stress[e, 1] = sw[1, 1]
            stress[e, 2] = sw[0, 1]
            # principal stresses are invariants: from the local tensor, in closed form
            mean = 0.5 * (sl[0, 0] + sl[1, 1])
            radius = math.hypot(0.5 * (sl[0, 0] - sl[1, 1]), sl[0, 1])
            principal[e, 0] = mean - radius
            principal[e, 1] = mean + radius
        else:
            stress[e, 0] = sw[0, 0]
            stress[e, 1] = sw[1, 1]
            stress[e, 2] = sw[2, 2]
            stress[e, 3] = sw[1, 2]
            stress[e, 4] = sw[0, 2]
            stress[e, 5] = sw[0, 1]
            principal[e] = np.linalg.eigvalsh(sl)


@nb.njit(cache=True)
def kinetic_energy(node_start, m_indptr, m_indices, m_data, v, out):
    """out[b] = 1/2 v^T M v [J] of each block."""
    d = v.shape[1]
    mv = np.empty_like(v)
    _csr_matvec(m_indptr, m_indices, m_data, v, mv)
    for b in range(len(node_start) - 1):
        s = 0.0
        for i in range(node_start[b], node_start[b + 1]):
            for k in range(d):
                s += v[i, k] * mv[i, k]
        out[b] = 0.5 * s


@nb.njit(cache=True)
def strain_energy(node_start, x0, c0, k_indptr, k_indices, k_data, x, rotation, centroid, out):
    """out[b] = 1/2 u^T K u [J] of each block, u the co-rotated displacement."""
    d = x.shape[1]
    u = np.empty_like(x)
    local_displacement(node_start, x0, c0, x, rotation, centroid, u)
    ku = np.empty_like(x)
    _csr_matvec(k_indptr, k_indices, k_data, u, ku)
    for b in range(len(node_start) - 1):
        s = 0.0
        for i in range(node_start[b], node_start[b + 1]):
            for k in range(d):
                s += u[i, k] * ku[i, k]
        out[b] = 0.5 * s
