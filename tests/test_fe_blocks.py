"""Kernels over all deformable blocks (saxum.fe.blocks) against dense, independent numpy
computations: co-rotated frames, free velocity, impulses, condensed compliance, energies."""

import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation
from test_fe_mesh import BRICK, BRICK_FACES, TRAPEZOID

from saxum.errors import InputError
from saxum.fe import Elastic, FEBlocks, mesh_polygon, mesh_polyhedron

H, THETA = 2e-3, 0.55


def _blocks(dim):
    """Two blocks of different materials (one damped), shifted apart."""
    return FEBlocks.build(*_meshes(dim), H, THETA)


def _meshes(dim):
    """(meshes, materials) of _blocks."""
    if dim == 2:
        meshes = [mesh_polygon(TRAPEZOID, 0.1), mesh_polygon(np.array(TRAPEZOID) + [1, 0], 0.15)]
        materials = [Elastic(1e8, 0.2, 2000.0, thickness=0.3),
                     Elastic(5e7, 0.3, 1500.0, damping=(0.8, 3e-4))]
    else:
        meshes = [mesh_polyhedron(BRICK, BRICK_FACES, 0.1),
                  mesh_polyhedron(BRICK + [1, 0, 0], BRICK_FACES, 0.07)]
        materials = [Elastic(1e8, 0.2, 2000.0), Elastic(5e7, 0.3, 1500.0, damping=(0.8, 3e-4))]
    return meshes, materials


def _rotation(dim, seed):
    if dim == 2:
        a = 2 * math.pi * seed
        return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    return Rotation.from_rotvec(np.array([0.3, -1.0, 2.0]) * seed * 3).as_matrix()


def _moved(blocks, rotations, shifts, strain=0.0, seed=0):
    """Nodes turned by rotations[b] about c0[b], shifted, plus a small random deformation."""
    rng = np.random.default_rng(seed)
    x = np.empty_like(blocks.x0)
    for b in range(blocks.n_blocks):
        s = slice(blocks.node_start[b], blocks.node_start[b + 1])
        local = blocks.x0[s] - blocks.c0[b]
        local = local + strain * rng.standard_normal(local.shape) * 0.1
        x[s] = blocks.c0[b] + shifts[b] + local @ rotations[b].T
    return x


@settings(max_examples=40)
@given(st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi),
       st.lists(st.floats(-100, 100), min_size=3, max_size=3))
def test_frame_of_a_rigidly_moved_mesh_is_its_rotation(a, b, c, shift):
    """Polar factor of A = Q S (S symmetric positive definite) is Q; a rigid motion carries no
    strain, so internal forces and stresses vanish (to round-off of the ~1e2 m coordinates)."""
    for dim, blocks in ((2, BLOCKS_2D), (3, BLOCKS_3D)):
        if dim == 2:
            rotations = [_rotation(2, a / (2 * math.pi)), _rotation(2, b / (2 * math.pi))]
        else:
            rotations = [Rotation.from_euler("zyx", [a, b, c]).as_matrix(),
                         Rotation.from_euler("xyz", [c, a, b]).as_matrix()]
        shifts = [np.array(shift[:dim]), -np.array(shift[:dim])]
        x = _moved(blocks, rotations, shifts)
        rotation, centroid = blocks.frames(x)
        assert np.abs(rotation - np.array(rotations)).max() < 1e-12
        assert np.abs(centroid - (blocks.c0 + np.array(shifts))).max() < 1e-12
        forces = blocks.internal_forces(x, rotation, centroid)
        stress = blocks.stresses(x, rotation, centroid)[0]
        # reference: the stress of a 1e-12 strain; rigid motions stay below it
        assert np.abs(stress).max() < 1e-12 * 1e8 * 1e2
        assert np.abs(forces).max() < 1e-12 * 1e8 * 1e2


BLOCKS_2D = _blocks(2)
BLOCKS_3D = _blocks(3)


def _dense(blocks):
    n = blocks.dim * blocks.n_nodes
    M = sp.csr_matrix((blocks.m_data, blocks.m_indices, blocks.m_indptr), shape=(n, n))
    K = sp.csr_matrix((blocks.k_data, blocks.k_indices, blocks.k_indptr), shape=(n, n))
    node_alpha = blocks.alpha[blocks.node_block]
    node_beta = blocks.beta[blocks.node_block]
    dof = lambda a: sp.diags(np.repeat(a, blocks.dim))  # noqa: E731
    return M, K, dof(node_alpha), dof(node_beta)


def _node_rotation(blocks, rotation):
    """The world <- block rotation of every node as one sparse block-diagonal matrix."""
    return sp.block_diag([rotation[b] for b in blocks.node_block], format="csr")


@pytest.mark.parametrize("dim", [2, 3])
def test_free_velocity_solves_the_theta_method_in_the_step_frame(dim):
    """M~_s (v_free - v) = h [F - C v_s - f_int - h theta K_s u'_s] solved with a sparse LU of
    the world M~_s = Q (M + h theta C + h^2 theta^2 K) Q^T, Q the step frames R_s node by
    node, u' = R_s^T v - w x R^T (x - c) (blocks.py): the kernel's dense M~^-1 and its
    rotations agree with it to round-off."""
    blocks = BLOCKS_2D if dim == 2 else BLOCKS_3D
    rng = np.random.default_rng(7)
    x = _moved(blocks, [_rotation(dim, 0.1), _rotation(dim, 0.37)],
               [np.ones(dim), -np.ones(dim)], strain=1e-3, seed=3)
    v = rng.standard_normal(x.shape)
    force = rng.standard_normal(x.shape) * 1e3
    rotation, centroid, spin, rotation_step = blocks.step_frames(x, v)
    v_free = blocks.free_velocity(x, v, force, rotation, centroid, spin, rotation_step)

    M, K, alpha, beta = _dense(blocks)
    q = _node_rotation(blocks, rotation_step)
    r = _node_rotation(blocks, rotation)
    mt = M + H * THETA * (alpha @ M + beta @ K) + (H * THETA) ** 2 * K
    u = (r.T @ (x - centroid[blocks.node_block]).ravel()) - (blocks.x0 - blocks.c0[
        blocks.node_block]).ravel()
    rel = (r.T @ (x - centroid[blocks.node_block]).ravel()).reshape(x.shape)
    w = spin[blocks.node_block]
    if dim == 2:
        turn = w * np.stack([-rel[:, 1], rel[:, 0]], axis=1)
    else:
        wl = np.einsum("nki,nk->ni", rotation[blocks.node_block], w)
        turn = np.cross(wl, rel)
    rate = q.T @ v.ravel() - turn.ravel()
    rhs = H * (q.T @ force.ravel() - alpha @ M @ (q.T @ v.ravel()) - K @ u
               - (beta + H * THETA * sp.identity(len(u))) @ K @ rate)
    expected = v.ravel() + q @ spla.spsolve(mt.tocsc(), rhs)
    assert np.abs(v_free.ravel() - expected).max() < 1e-10 * np.abs(expected - v.ravel()).max()


@pytest.mark.parametrize("dim", [2, 3])
def test_impulses_and_condensed_compliance_agree_with_m_tilde(dim):
    """apply_nodal_impulses, apply_impulse (one block, a few nodes), the update of the
    boundary nodes only, the boundary compliance G = Q B M~^-1 B^T Q^T and one of its node
    blocks against a sparse solve with M~."""
    blocks = BLOCKS_2D if dim == 2 else BLOCKS_3D
    rng = np.random.default_rng(11)
    rotation_step = np.array([_rotation(dim, 0.2), _rotation(dim, -0.45)])
    M, K, alpha, beta = _dense(blocks)
    mt = (M + H * THETA * (alpha @ M + beta @ K) + (H * THETA) ** 2 * K).tocsc()
    q = _node_rotation(blocks, rotation_step)
    world = lambda p: q @ spla.spsolve(mt, q.T @ p.ravel())  # noqa: E731

    impulse = rng.standard_normal(blocks.x0.shape)
    v0 = rng.standard_normal(blocks.x0.shape)
    v = v0.copy()
    blocks.apply_nodal_impulses(impulse, rotation_step, v)
    expected = world(impulse)
    assert np.abs((v - v0).ravel() - expected).max() < 1e-10 * np.abs(expected).max()

    b = 1
    nodes = blocks.boundary_node[blocks.boundary_start[b]:blocks.boundary_start[b + 1]][[0, 3, 5]]
    impulses = rng.standard_normal((3, dim))
    v = v0.copy()
    blocks.apply_impulse(b, nodes, impulses, rotation_step, v)
    p = np.zeros_like(v0)
    p[nodes] = impulses
    expected = world(p)
    assert np.abs((v - v0).ravel() - expected).max() < 1e-10 * np.abs(expected).max()

    v = v0.copy()
    blocks.apply_boundary_impulse(b, nodes, impulses, rotation_step, v)
    bnd = blocks.boundary_node[blocks.boundary_start[b]:blocks.boundary_start[b + 1]]
    expected = expected.reshape(v.shape)
    assert np.abs(v[bnd] - v0[bnd] - expected[bnd]).max() < 1e-10 * np.abs(expected).max()
    interior = np.setdiff1d(np.arange(blocks.n_nodes), bnd)
    assert np.array_equal(v[interior], v0[interior])

    g = blocks.boundary_compliance(rotation_step)
    for b in range(blocks.n_blocks):
        bnd = blocks.boundary_node[blocks.boundary_start[b]:blocks.boundary_start[b + 1]]
        dofs = (dim * bnd[:, None] + np.arange(dim)).ravel()
        columns = np.zeros((dim * blocks.n_nodes, len(dofs)))
        columns[dofs, np.arange(len(dofs))] = 1.0
        full = q @ spla.spsolve(mt, q.T @ columns)
        expected = np.asarray(full)[dofs]
        got = g[blocks.compliance_start[b]:blocks.compliance_start[b + 1]].reshape(len(dofs), -1)
        assert np.abs(got - expected).max() < 1e-10 * np.abs(expected).max()
        pair = blocks.compliance_block(b, bnd[2], bnd[-1], rotation_step)
        assert np.abs(pair - expected[dim * 2:dim * 3, -dim:]).max() < \
            1e-10 * np.abs(expected).max()


def test_spin_and_step_rotation_of_a_rigid_spin():
    """Velocities of a rigid rotation w x (x - c) give spin w back; the step frame is R turned
    by theta h w (2D: angles add; 3D: exp of the rotation vector)."""
    for dim, blocks in ((2, BLOCKS_2D), (3, BLOCKS_3D)):
        rotations = [_rotation(dim, 0.3), _rotation(dim, 0.8)]
        x = _moved(blocks, rotations, [np.zeros(dim), np.ones(dim)])
        rotation, centroid = blocks.frames(x)
        w = np.array([[0.7], [-2.0]]) if dim == 2 else np.array([[0.7, -0.2, 0.4],
                                                                [0.0, 3.0, -1.0]])
        r = x - centroid[blocks.node_block]
        wn = w[blocks.node_block]
        v = (wn * np.stack([-r[:, 1], r[:, 0]], 1) if dim == 2 else np.cross(wn, r)) + 5.0
        _, _, spin, rotation_step = blocks.step_frames(x, v)
        assert np.abs(spin - w).max() < 1e-12
        for b in range(2):
            turn = (_rotation(2, THETA * H * w[b, 0] / (2 * math.pi)) if dim == 2 else
                    Rotation.from_rotvec(THETA * H * w[b]).as_matrix())
            assert np.abs(rotation_step[b] - turn @ rotation[b]).max() < 1e-14


def test_positions_energies_and_weight():
    blocks = BLOCKS_2D
    x = blocks.x0.copy()
    v = np.tile([0.3, -0.4], (blocks.n_nodes, 1))
    v_next = np.tile([0.1, 0.2], (blocks.n_nodes, 1))
    predicted = blocks.predict_positions(x, v)
    assert np.allclose(predicted - x, (1 - THETA) * H * v, rtol=0, atol=1e-15)
    blocks.update_positions(x, v, v_next)
    assert np.allclose(x - blocks.x0, H * ((1 - THETA) * v + THETA * v_next), rtol=0,
                       atol=1e-15)
    # a translation: 1/2 m |v|^2 per block, m = rho A t
    area = 0.5 * (0.6 + 0.4) * 0.3
    masses = np.array([2000.0 * area * 0.3, 1500.0 * area * 1.0])
    assert np.allclose(blocks.kinetic_energy(v), 0.5 * masses * 0.25, rtol=1e-12, atol=0)
    weight = blocks.weight([0.0, -9.81])
    assert np.allclose([weight[s:e, 1].sum() for s, e in
                        zip(blocks.node_start[:-1], blocks.node_start[1:], strict=True)],
                       -9.81 * masses, rtol=1e-12, atol=0)
    # a uniform strain eps_xx = e: 1/2 (lambda* + 2 mu) e^2 V (plane stress, block 0)
    e = 1e-4
    x = blocks.x0 + e * (blocks.x0 - blocks.c0[blocks.node_block]) * [1.0, 0.0]
    energy = blocks.strain_energy(x, *blocks.frames(x))
    lam, mu = Elastic(1e8, 0.2, 2000.0, thickness=0.3).lame(2)
    assert math.isclose(energy[0], 0.5 * (lam + 2 * mu) * e * e * area * 0.3, rel_tol=1e-9)


def test_boundary_areas_add_up_to_the_perimeter_and_the_surface():
    for blocks, sizes in ((BLOCKS_2D, [0.6 + 0.4 + 2 * math.hypot(0.1, 0.3)] * 2),
                          (BLOCKS_3D, [2 * (0.08 + 0.04 + 0.02)] * 2)):
        sums = [blocks.boundary_area[a:e].sum() for a, e in
                zip(blocks.boundary_start[:-1], blocks.boundary_start[1:], strict=True)]
        assert np.allclose(sums, sizes, rtol=1e-12, atol=0)
        assert np.all(blocks.boundary_area > 0)


def test_bad_step_and_block_lists_are_refused():
    mesh = mesh_polygon(TRAPEZOID, 0.2)
    material = Elastic(1e8, 0.2, 2000.0)
    with pytest.raises(InputError, match=r"time step h = 0.0 s must be positive"):
        FEBlocks.build([mesh], [material], 0.0, 0.5)
    with pytest.raises(InputError, match=r"theta = 0.4 must lie in \[0.5, 1\]"):
        FEBlocks.build([mesh], [material], 1e-3, 0.4)
    with pytest.raises(InputError, match="2 meshes and 1 materials"):
        FEBlocks.build([mesh, mesh], [material], 1e-3, 0.5)


@pytest.mark.parametrize("dim", [2, 3])
def test_geometry_alone_gives_the_masses_and_stresses_of_the_full_build(dim):
    """FEBlocks.geometry (what Results.stresses builds: no M, K, M~^-1) has the nodal masses
    of the assembled consistent M (its row sums, from scikit-fem's quadrature, against the
    closed form rho t V_e / (d + 1) per cell: equal to round-off, 1e-12 relative) and gives
    the full build's frames and stresses of a turned, strained configuration (1e-12 of the
    largest stress: round-off only)."""
    full = BLOCKS_2D if dim == 2 else BLOCKS_3D
    cheap = FEBlocks.geometry(*_meshes(dim))
    assert cheap.m_data is None and cheap.k_data is None and cheap.inv is None
    m = sp.csr_matrix((full.m_data, full.m_indices, full.m_indptr))
    row_sums = np.asarray(m.sum(axis=1)).ravel()[::dim]
    assert np.abs(cheap.node_mass - row_sums).max() < 1e-12 * row_sums.max()
    x = _moved(full, [_rotation(dim, 0.3), _rotation(dim, 0.7)],
               [np.full(dim, 0.5), np.full(dim, -2.0)], strain=1e-3, seed=4)
    expected = full.stresses(x, *full.frames(x))
    got = cheap.stresses(x, *cheap.frames(x))
    scale = np.abs(expected[0]).max()
    for a, b in zip(got, expected, strict=True):
        assert np.abs(a - b).max() <= 1e-12 * scale
