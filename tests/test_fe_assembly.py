"""Mass and stiffness of deformable blocks (scikit-fem P1): total mass, rigid-body modes,
patch tests (plane stress, plane strain, 3D) and the free-free bar's first axial frequency."""

import math

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse.linalg as spla
from test_fe_mesh import BRICK, BRICK_FACES

from saxum.fe import Elastic, FEBlocks, damping, mass_stiffness, mesh_polygon, mesh_polyhedron

# A rectangle with an extra vertex on its base is not meshed as a rectangle: the Delaunay
# (unstructured) mesh, the harder case for a patch test
L, H = 0.8, 0.3
PENTAGON = [[0, 0], [0.37, 0], [L, 0], [L, H], [0, H]]
RECTANGLE = [[0, 0], [L, 0], [L, H], [0, H]]


def _rigid_modes(nodes):
    """Translations and infinitesimal rotations about the origin, columns [d n, 3 | 6]."""
    n, d = nodes.shape
    modes = []
    for k in range(d):
        t = np.zeros((n, d))
        t[:, k] = 1.0
        modes.append(t.ravel())
    axes = [(0, 1)] if d == 2 else [(0, 1), (1, 2), (2, 0)]
    for a, b in axes:
        r = np.zeros((n, d))
        r[:, a] = -nodes[:, b]
        r[:, b] = nodes[:, a]
        modes.append(r.ravel())
    return np.array(modes).T


@pytest.mark.parametrize("thickness", [0.25, None])
def test_total_mass_is_rho_times_volume_2d(thickness):
    mesh = mesh_polygon(PENTAGON, 0.05)
    M, _ = mass_stiffness(mesh, Elastic(2e10, 0.2, 2400.0, thickness=thickness))
    ex = np.zeros((len(mesh.nodes), 2))
    ex[:, 0] = 1.0
    depth = 1.0 if thickness is None else thickness
    assert math.isclose(ex.ravel() @ M @ ex.ravel(), 2400.0 * L * H * depth, rel_tol=1e-12)


def test_total_mass_is_rho_times_volume_3d():
    mesh = mesh_polyhedron(BRICK, BRICK_FACES, 0.05)
    M, _ = mass_stiffness(mesh, Elastic(2e10, 0.2, 2400.0))
    ez = np.zeros((len(mesh.nodes), 3))
    ez[:, 2] = 1.0
    assert math.isclose(ez.ravel() @ M @ ez.ravel(), 2400.0 * 0.4 * 0.2 * 0.1, rel_tol=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_rigid_body_modes_have_zero_energy(dim):
    if dim == 2:
        mesh = mesh_polygon(PENTAGON, 0.05)
    else:
        mesh = mesh_polyhedron(BRICK, BRICK_FACES, 0.05)
    E = 3e10
    _, K = mass_stiffness(mesh, Elastic(E, 0.2, 2400.0))
    modes = _rigid_modes(mesh.nodes)
    # relative to the energy of a unit strain on the same nodes; round-off is ~1e-16 of it
    strain = mesh.nodes.ravel()  # u = X, a uniform dilation
    reference = strain @ K @ strain
    energy = np.einsum("ik,ij,jk->k", modes, K.toarray(), modes)
    assert np.all(np.abs(energy) < 1e-12 * reference)
    # and a strain mode is not in the kernel
    assert reference > 0.1 * E * (L * H if dim == 2 else 0.008)


def test_rayleigh_damping():
    mesh = mesh_polygon(PENTAGON, 0.1)
    mat = Elastic(2e10, 0.2, 2400.0, damping=(0.3, 2e-4))
    M, K = mass_stiffness(mesh, mat)
    C = damping(M, K, mat)
    assert abs(C - 0.3 * M - 2e-4 * K).max() <= 1e-14 * abs(C).max()


def _solve_uniaxial(mesh, material, sigma):
    """K u = f for a uniaxial traction sigma [Pa] on the face x = max, u_x = 0 on x = 0 and
    the remaining rigid motions held at corner nodes."""
    nodes = mesh.nodes
    n, d = nodes.shape
    _, K = mass_stiffness(mesh, material)
    f = np.zeros((n, d))
    depth = material.depth(d)
    right = nodes[:, 0].max()
    for facet in mesh.facets:
        if np.all(np.abs(nodes[facet, 0] - right) < 1e-12):
            x = nodes[facet]
            size = (np.linalg.norm(x[1] - x[0]) * depth if d == 2 else
                    0.5 * np.linalg.norm(np.cross(x[1] - x[0], x[2] - x[0])))
            f[facet, 0] += sigma * size / d  # consistent load of a constant traction on P1
    fixed = np.zeros((n, d), dtype=bool)
    fixed[np.abs(nodes[:, 0]) < 1e-12, 0] = True
    origin = np.flatnonzero(np.linalg.norm(nodes, axis=1) < 1e-12)[0]
    fixed[origin, 1:] = True
    if d == 3:
        top = np.flatnonzero(np.linalg.norm(nodes - [0, nodes[:, 1].max(), 0], axis=1) < 1e-12)
        fixed[top[0], 2] = True
    free = ~fixed.ravel()
    u = np.zeros(n * d)
    u[free] = spla.spsolve(K[free][:, free].tocsc(), f.ravel()[free])
    return u.reshape(n, d)


@pytest.mark.parametrize("vertices", [PENTAGON, RECTANGLE])
@pytest.mark.parametrize("thickness", [0.2, None])
def test_patch_test_uniaxial_stress_2d(vertices, thickness):
    """P1 elements represent linear displacements exactly, so the uniaxial solution is
    reproduced at every node to round-off (K's condition number ~ (L / size)^2 ~ 1e3 times
    machine epsilon: tolerance 1e-9 of the largest displacement). Plane stress: eps_xx =
    sigma / E, eps_yy = -nu sigma / E; plane strain: eps_xx = (1 - nu^2) sigma / E, eps_yy =
    -nu (1 + nu) sigma / E (Timoshenko & Goodier, Theory of Elasticity, sec. 8 and 16)."""
    E, nu, sigma = 2e10, 0.25, 1.0e6
    material = Elastic(E, nu, 2400.0, thickness=thickness)
    mesh = mesh_polygon(vertices, 0.07)
    u = _solve_uniaxial(mesh, material, sigma)
    if thickness is not None:
        exx, eyy = sigma / E, -nu * sigma / E
    else:
        exx, eyy = (1 - nu * nu) * sigma / E, -nu * (1 + nu) * sigma / E
    exact = mesh.nodes * [exx, eyy]
    assert np.abs(u - exact).max() < 1e-9 * np.abs(exact).max()
    # the element stresses of the block turned by 40 degrees: q sigma q^T. The co-rotated frame
    # (polar factor) of a strained unstructured mesh is q only up to O(strain), and the
    # small-strain stress in it is exact only to first order in the strain [FH05]: tolerance
    # |eps_xx| sigma on the components (measured ~1e-8 sigma); the principal stresses are
    # invariants and exact to round-off
    blocks = FEBlocks.build([mesh], [material], 1e-3, 0.5)
    a = math.radians(40.0)
    q = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    x = (blocks.x0 + u) @ q.T + [5.0, -2.0]
    rotation, centroid = blocks.frames(x)
    assert np.abs(rotation[0] - q).max() < abs(exx)
    stress, principal, compression, tension = blocks.stresses(x, rotation, centroid)
    expected = q @ np.diag([sigma, 0.0]) @ q.T
    error = np.abs(stress - [expected[0, 0], expected[1, 1], expected[0, 1]]).max()
    assert error < abs(exx) * sigma
    assert np.abs(principal - [0.0, sigma]).max() < 1e-9 * sigma
    assert np.abs(tension - sigma).max() < 1e-9 * sigma and compression.max() < 1e-9 * sigma


def test_patch_test_uniaxial_stress_3d():
    """As in 2D: eps_xx = sigma / E, eps_yy = eps_zz = -nu sigma / E to round-off; the turned
    block's stress components to O(strain) (see the 2D test)."""
    E, nu, sigma = 2e10, 0.25, -1.0e6
    material = Elastic(E, nu, 2400.0)
    mesh = mesh_polyhedron(BRICK, BRICK_FACES, 0.05)
    u = _solve_uniaxial(mesh, material, sigma)
    exact = mesh.nodes * [sigma / E, -nu * sigma / E, -nu * sigma / E]
    assert np.abs(u - exact).max() < 1e-9 * np.abs(exact).max()
    blocks = FEBlocks.build([mesh], [material], 1e-3, 0.5)
    a = math.radians(70.0)
    q = np.array([[1.0, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    q = q @ np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    x = (blocks.x0 + u) @ q.T
    rotation, centroid = blocks.frames(x)
    assert np.abs(rotation[0] - q).max() < abs(sigma / E)
    stress, principal, compression, tension = blocks.stresses(x, rotation, centroid)
    s = q @ np.diag([sigma, 0.0, 0.0]) @ q.T
    voigt = [s[0, 0], s[1, 1], s[2, 2], s[1, 2], s[0, 2], s[0, 1]]
    assert np.abs(stress - voigt).max() < abs(sigma / E * sigma)  # as in 2D
    # the Kuhn mesh's uneven nodal masses turn the frame by ~1e-6 (O(strain)): its second
    # order E delta^2 ~ 2e-8 sigma reaches the principal stresses too
    assert np.abs(principal - [sigma, 0.0, 0.0]).max() < abs(sigma / E * sigma)
    assert np.abs(compression + sigma).max() < abs(sigma / E * sigma)
    assert tension.max() < abs(sigma / E * sigma)


def _axial_frequency(size, length=1.0):
    """First axial eigenfrequency [Hz] of a free-free bar (plane stress, nu = 0) from M, K,
    picked as the mode closest to u_x = cos(pi x / L)."""
    mesh = mesh_polygon([[0, 0], [length, 0], [length, 0.2], [0, 0.2]], size)
    M, K = mass_stiffness(mesh, Elastic(1e9, 0.0, 2000.0, thickness=0.1))
    w2, modes = scipy.linalg.eigh(K.toarray(), M.toarray())
    shape = np.zeros_like(mesh.nodes)
    shape[:, 0] = np.cos(math.pi * mesh.nodes[:, 0] / length)
    shape = shape.ravel()
    overlap = np.abs(modes.T @ (M @ shape)) / math.sqrt(shape @ M @ shape)
    k = np.argmax(overlap)
    assert overlap[k] > 0.999
    return math.sqrt(w2[k]) / (2 * math.pi)


def test_free_free_bar_first_axial_frequency():
    """f = c / (2 L), c = sqrt(E / rho) (Timoshenko, Vibration Problems in Engineering, sec.
    on longitudinal vibration of prismatic bars); with nu = 0 in plane stress the 2D bar has
    this 1D mode exactly. Linear elements with consistent mass overestimate a mode of wave
    number k on elements of length l by (k l)^2 / 24 + O((k l)^4) (T.J.R. Hughes, The Finite
    Element Method, 1987, sec. 9.2, dispersion of the consistent mass): the error must lie in
    (0, (k l)^2 / 24] and fall by about 4 when the mesh is halved (second order)."""
    c = math.sqrt(1e9 / 2000.0)
    exact = c / 2.0
    errors = []
    for size in (0.05, 0.025):
        error = _axial_frequency(size) / exact - 1.0
        bound = (math.pi * size) ** 2 / 24.0
        assert 0.0 < error <= bound
        errors.append(error)
    assert 3.5 < errors[0] / errors[1] < 4.5
