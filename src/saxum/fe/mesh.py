"""Meshes of deformable blocks: linear triangles (2D) and tetrahedra (3D).

Convex polygons are meshed by the Delaunay triangulation (Qhull) of points every ~size along
the edges and of an equilateral lattice of spacing `size` inside; rectangles get a structured
grid. Polyhedra: parallelepipeds (bricks) get a structured grid of Kuhn
tetrahedra (6 per hexahedron, conforming); any other convex polyhedron is coned from its
centroid over its faces and then refined uniformly by red refinement (J. Bey, "Tetrahedral grid
refinement", Computing 55 (1995) 355-378: each tetrahedron into 8 through its edge midpoints,
which keeps at most three similarity classes, so the quality of the coarse mesh is kept).
"""

import math
from dataclasses import dataclass
from itertools import combinations, permutations

import numpy as np

from saxum.errors import InputError, plain

__all__ = ["DEFAULT_MAX_NODES", "Mesh", "boundary_facets", "fit_mesh", "mesh_polygon",
           "mesh_polyhedron"]

DEFAULT_MAX_NODES = 1000
"""Largest number of nodes of one block's mesh unless max_nodes says otherwise: M~^-1 is stored
densely per block ((d n)^2 numbers: 1000 nodes in 3D are 72 MB)."""


@dataclass(frozen=True)
class Mesh:
    """A simplex mesh of one block.

    nodes [n, d] float64: reference coordinates [m]; cells [m, d + 1] int64, positively
    oriented (counter-clockwise triangles, tetrahedra with det[x1-x0, x2-x0, x3-x0] > 0);
    facets [f, d] int64: the boundary edges (2D) or triangles (3D), oriented outward (2D: the
    outward normal of edge (a, b) is (b - a) turned by -90 degrees; 3D: (b - a) x (c - a));
    boundary_nodes [b] int64: the nodes on the boundary, sorted.
    """

    nodes: np.ndarray
    cells: np.ndarray
    facets: np.ndarray
    boundary_nodes: np.ndarray

    @property
    def dim(self) -> int:
        return self.nodes.shape[1]

    @classmethod
    def from_cells(cls, nodes, cells, name: str = "block") -> "Mesh":
        """Mesh from node coordinates [n, d] [m] and cells [m, d + 1] (any orientation): cells
        are turned positive, the boundary facets found (faces of exactly one cell). Raises
        InputError for a bad shape, an index out of range, a degenerate cell or an unused node."""
        nodes = np.array(nodes, dtype=np.float64)
        cells = np.array(cells)
        if nodes.ndim != 2 or nodes.shape[1] not in (2, 3) or nodes.shape[0] < nodes.shape[1] + 1:
            raise InputError(f"{name}: mesh nodes must be an array [n, 2] or [n, 3] of at least "
                             f"d + 1 points, got shape {nodes.shape}")
        dim = nodes.shape[1]
        if not np.all(np.isfinite(nodes)):
            raise InputError(f"{name}: mesh nodes contain NaN or infinite coordinates")
        if cells.ndim != 2 or cells.shape[1] != dim + 1 or cells.shape[0] == 0 or \
                not np.issubdtype(cells.dtype, np.integer):
            raise InputError(f"{name}: mesh cells must be an integer array [m, {dim + 1}] "
                             f"(linear {'triangles' if dim == 2 else 'tetrahedra'}), "
                             f"got shape {cells.shape} of {cells.dtype}")
        cells = cells.astype(np.int64)
        if cells.min() < 0 or cells.max() >= len(nodes):
            raise InputError(f"{name}: mesh cells refer to nodes outside 0..{len(nodes) - 1}")
        unused = np.setdiff1d(np.arange(len(nodes)), cells)
        if len(unused):
            raise InputError(f"{name}: mesh nodes {plain(unused[:5])} belong to no cell; "
                             "remove them")
        volume = _signed_volumes(nodes, cells)
        scale = np.ptp(nodes, axis=0).max() ** dim
        bad = np.flatnonzero(np.abs(volume) <= 1e-12 * scale)
        if len(bad):
            raise InputError(f"{name}: mesh cells {plain(bad[:5])} have zero "
                             f"{'area' if dim == 2 else 'volume'}; fix the mesh")
        cells = cells.copy()
        flip = volume < 0
        cells[flip, 0], cells[flip, 1] = cells[flip, 1], cells[flip, 0].copy()
        facets = _boundary_facets(cells, dim)
        return cls(nodes, cells, facets, np.unique(facets))


def _signed_volumes(nodes, cells):
    """Signed area (2D) or volume (3D) of each cell [m^2 | m^3]."""
    x = nodes[cells]
    edges = x[:, 1:] - x[:, :1]
    return np.linalg.det(edges) / math.factorial(nodes.shape[1])


def _boundary_facets(cells, dim):
    """Faces of exactly one (positive) cell, oriented outward (boundary_facets)."""
    return boundary_facets(cells, dim)[0]


def boundary_facets(cells, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """(facets [f, dim], cell [f]): the faces of exactly one of the positive simplices
    `cells` [m, dim + 1], oriented outward, and the index of that cell. In a positive simplex
    the face opposite vertex k, with the vertex order below, has the outward orientation."""
    if dim == 2:
        local = np.array([[1, 2], [2, 0], [0, 1]])
    else:
        local = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])
    faces = cells[:, local].reshape(-1, dim)
    _, index, counts = np.unique(np.sort(faces, axis=1), axis=0, return_index=True,
                                 return_counts=True)
    outer = np.sort(index[counts == 1])
    return faces[outer], outer // (dim + 1)


def fit_mesh(mesh: Mesh, normals: np.ndarray, offsets: np.ndarray, volume: float,
             max_nodes: int = DEFAULT_MAX_NODES, name: str = "block") -> Mesh:
    """A given mesh of a convex block {x: n_i . x <= c_i} (normals [k, d], offsets c [k] [m]) of
    area (3D volume) `volume` [m^2 | m^3], checked to be one: every node inside the block and
    every boundary node on a face of it (within 1e-9 of the block's size), the cells' areas
    (volumes) adding up to the block's (1e-9), at most max_nodes nodes; else an InputError."""
    dim = len(normals[0])
    if not isinstance(mesh, Mesh) or mesh.dim != dim:
        raise InputError(f"{name}: mesh must be a saxum.fe.Mesh of {dim}D nodes "
                         f"(saxum.fe.Mesh.from_cells(nodes, cells)), got {mesh!r:.60}")
    if len(mesh.nodes) > max_nodes:
        raise InputError(f"{name}: the given mesh has {len(mesh.nodes)} nodes, more than "
                         f"max_nodes = {max_nodes}; give a coarser mesh")
    tol = 1e-9 * _diameter(mesh.nodes)
    height = mesh.nodes @ np.asarray(normals).T - np.asarray(offsets)  # [n, k], <= 0 inside
    outside = np.flatnonzero(height.max(axis=1) > tol)
    if len(outside):
        raise InputError(f"{name}: given mesh nodes {plain(outside[:5])} lie outside the block; "
                         "mesh the block itself")
    off = mesh.boundary_nodes[np.abs(height[mesh.boundary_nodes]).min(axis=1) > tol]
    cells = np.abs(_signed_volumes(mesh.nodes, mesh.cells)).sum()
    if len(off) or abs(cells - volume) > 1e-9 * volume:
        raise InputError(f"{name}: the given mesh does not fill the block (its cells cover "
                         f"{cells:.9g} of {volume:.9g} {'m^2' if dim == 2 else 'm^3'}"
                         + (f"; nodes {plain(off[:5])} are on its boundary but on no face of "
                            "the block" if len(off) else "") + "); mesh the block itself")
    return mesh


def _check_size(name, size, diameter):
    try:
        size = float(size)
    except (TypeError, ValueError):
        raise InputError(f"{name}: mesh size = {plain(size)} is not a number; give it in m") \
            from None
    if not math.isfinite(size) or size <= 0.0:
        raise InputError(f"{name}: mesh size = {plain(size)} m must be positive")
    if size > diameter:
        raise InputError(f"{name}: mesh size = {plain(size)} m is larger than the block (its "
                         f"largest dimension is {diameter:.6g} m); give a size below that")
    return size


def _check_count(name, count, max_nodes, size, about=""):
    if count > max_nodes:
        raise InputError(f"{name}: mesh size = {plain(size)} m gives {about}{count} nodes, "
                         f"more than max_nodes = {max_nodes}; give a larger mesh size or "
                         "raise max_nodes")


def _vertices(name, vertices, dim):
    vertices = np.asarray(vertices, dtype=np.float64)
    if vertices.ndim != 2 or vertices.shape[1] != dim or len(vertices) < dim + 1:
        raise InputError(f"{name}: vertices must be an array [k, {dim}] with k >= {dim + 1}, "
                         f"got shape {vertices.shape}")
    if not np.all(np.isfinite(vertices)):
        raise InputError(f"{name}: vertices contain NaN or infinite coordinates")
    return vertices


def _diameter(vertices):
    return float(np.max(np.linalg.norm(vertices[:, None] - vertices[None], axis=-1)))


def mesh_polygon(vertices, size: float, max_nodes: int = DEFAULT_MAX_NODES,
                 name: str = "block") -> Mesh:
    """Triangle mesh of a convex polygon (vertices [k, 2] [m], either orientation; collinear
    vertices allowed) with elements of about `size` [m]: boundary points every ~size along each
    edge, interior points on an equilateral lattice of spacing `size` at least 0.6 size inside,
    and the Delaunay triangulation of all of them (Qhull through scipy.spatial.Delaunay), whose
    union is their convex hull, the polygon. Least angle >= min(20 degrees, sharpest corner / 3)
    for a size below the shortest edge (property-tested); a size above it leaves the triangles
    at a short edge sharper (down to 11 degrees measured for 1-3 times the shortest edge).
    A rectangle gets a structured grid of ceil(side / size)
    cells per side, each square split into two triangles along alternating diagonals.
    InputError if the polygon crosses itself (a repeated vertex counts) or is not convex, the
    size is larger than the block or the mesh would have more than max_nodes nodes."""
    vertices = _vertices(name, vertices, 2)
    size = _check_size(name, size, _diameter(vertices))
    crossing = _crossing_edges(vertices)
    if crossing is not None:
        raise InputError(f"{name}: polygon edges {crossing[0]} and {crossing[1]} cross; give the "
                         "vertices of a simple polygon in order around it")
    x, y = vertices[:, 0], vertices[:, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    if abs(area) <= 1e-12 * _diameter(vertices) ** 2:
        raise InputError(f"{name}: the polygon has zero area")
    if area < 0:
        vertices = vertices[::-1]
    rectangle = _rectangle(vertices)
    if rectangle is not None:
        return _structured(name, *rectangle, size, max_nodes)
    reflex = _reflex_vertex(vertices)
    if reflex is not None:
        raise InputError(f"{name}: the polygon is not convex (vertex {reflex} of the "
                         "counter-clockwise outline is a reflex corner); split it into convex "
                         "blocks")
    edge = np.roll(vertices, -1, axis=0) - vertices
    perimeter = float(np.linalg.norm(edge, axis=1).sum())
    # the lattice has one node per sqrt(3)/2 size^2 of area, the boundary one per size of length
    estimate = int(abs(area) / (math.sqrt(3.0) / 2.0 * size * size) + perimeter / size)
    if estimate > 10 * max_nodes:
        _check_count(name, estimate, max_nodes, size, about="about ")
    nodes = np.concatenate([_edge_points(vertices, size), _lattice_points(vertices, size)])
    _check_count(name, len(nodes), max_nodes, size)
    from scipy.spatial import Delaunay  # ~0.5 s: imported by the runs that mesh

    cells = Delaunay(nodes).simplices
    # Qhull returns flat triangles on three collinear boundary points (a vertical facet of the
    # points lifted onto the paraboloid; in about half the meshes of random polygons) besides
    # the proper ones on their two edges: they cover nothing and are dropped
    flat = np.abs(_signed_volumes(nodes, cells)) <= 1e-12 * _diameter(vertices) ** 2
    return Mesh.from_cells(nodes, cells[~flat], name)


def _reflex_vertex(vertices):
    """Index of a reflex corner of a counter-clockwise polygon (turn to the right beyond
    round-off), or None; collinear vertices (no turn) are allowed."""
    edge = np.roll(vertices, -1, axis=0) - vertices
    length = np.linalg.norm(edge, axis=1)
    following = np.roll(edge, -1, axis=0)
    turn = (edge[:, 0] * following[:, 1] - edge[:, 1] * following[:, 0]) / \
        (length * np.roll(length, -1))
    bad = np.flatnonzero(turn < -1e-9)
    return None if len(bad) == 0 else int((bad[0] + 1) % len(vertices))


def _edge_points(vertices, size):
    """The vertices and n - 1 evenly spaced points inside each edge [m], n = length / size
    rounded to the nearest integer (at least 1): spacings between 2/3 and 3/2 size, which keeps
    the boundary triangles of an edge just longer than `size` from being halved."""
    points = []
    for a, b in zip(vertices, np.roll(vertices, -1, axis=0), strict=True):
        n = max(1, math.floor(float(np.linalg.norm(b - a)) / size + 0.5))
        points.append(a + np.arange(n)[:, None] / n * (b - a))
    return np.concatenate(points)


def _lattice_points(vertices, size):
    """Nodes of an equilateral triangular lattice of spacing `size` [m], with rows parallel to
    the longest edge of the counter-clockwise convex polygon, that lie at least 0.6 size inside
    every edge (the distance to a convex polygon's boundary is the least distance to its edge
    lines). 0.6 rather than 0.5: the least angle over 2400 random convex polygons rose from 21
    to 24 degrees (corners >= 30 degrees), for a few percent fewer nodes."""
    edge = np.roll(vertices, -1, axis=0) - vertices
    length = np.linalg.norm(edge, axis=1)
    tangent = edge / length[:, None]
    inward = np.stack([-tangent[:, 1], tangent[:, 0]], axis=1)
    k = int(np.argmax(length))
    local = (vertices - vertices[k]) @ np.stack([tangent[k], inward[k]], axis=1)
    row = math.sqrt(3.0) / 2.0 * size
    j = np.arange(1, int(local[:, 1].max() / row) + 1)
    i = np.arange(math.floor(local[:, 0].min() / size) - 1,
                  math.ceil(local[:, 0].max() / size) + 1)
    u = (i[None, :] + 0.5 * (j[:, None] % 2)) * size
    w = np.broadcast_to(j[:, None] * row, u.shape)
    points = vertices[k] + u.reshape(-1, 1) * tangent[k] + w.reshape(-1, 1) * inward[k]
    depth = np.min(np.einsum("pkd,kd->pk", points[:, None] - vertices[None], inward), axis=1)
    return points[depth >= 0.6 * size]


def _crossing_edges(vertices):
    """(i, j) of two non-adjacent edges that intersect (edge k from vertex k to k + 1), or None."""
    k = len(vertices)
    a = vertices
    b = np.roll(vertices, -1, axis=0)

    def side(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    for i in range(k):
        for j in range(i + 2, k):
            if i == 0 and j == k - 1:
                continue  # adjacent through vertex 0
            if side(a[i], b[i], a[j]) * side(a[i], b[i], b[j]) <= 0 and \
                    side(a[j], b[j], a[i]) * side(a[j], b[j], b[i]) <= 0:
                return i, j
    return None


def _rectangle(vertices):
    """(origin, side a, side b) if the polygon is a rectangle (4 vertices, right angles)."""
    if len(vertices) != 4:
        return None
    a = vertices[1] - vertices[0]
    b = vertices[3] - vertices[0]
    scale = np.linalg.norm(a) * np.linalg.norm(b)
    if abs(a @ b) > 1e-9 * scale or np.linalg.norm(vertices[2] - vertices[0] - a - b) > \
            1e-9 * math.sqrt(scale):
        return None
    return vertices[0], a, b


def _structured(name, origin, a, b, size, max_nodes):
    na = max(1, math.ceil(np.linalg.norm(a) / size - 1e-9))
    nb = max(1, math.ceil(np.linalg.norm(b) / size - 1e-9))
    _check_count(name, (na + 1) * (nb + 1), max_nodes, size)
    i, j = np.meshgrid(np.arange(na + 1), np.arange(nb + 1), indexing="ij")
    nodes = origin + (i.reshape(-1, 1) / na) * a + (j.reshape(-1, 1) / nb) * b
    node = (i * (nb + 1) + j)
    n00, n10 = node[:-1, :-1].ravel(), node[1:, :-1].ravel()
    n01, n11 = node[:-1, 1:].ravel(), node[1:, 1:].ravel()
    # alternating diagonals (a union-jack pattern) keep the mesh symmetric under reflections
    even = ((i[:-1, :-1] + j[:-1, :-1]) % 2 == 0).ravel()
    first = np.where(even[:, None], np.stack([n00, n10, n11], 1), np.stack([n00, n10, n01], 1))
    second = np.where(even[:, None], np.stack([n00, n11, n01], 1), np.stack([n10, n11, n01], 1))
    return Mesh.from_cells(nodes, np.concatenate([first, second]), name)


def mesh_polyhedron(vertices, faces, size: float, max_nodes: int = DEFAULT_MAX_NODES,
                    name: str = "block") -> Mesh:
    """Tetrahedral mesh of a convex polyhedron (vertices [k, 3] [m], faces: lists of vertex
    indices, any orientation) with elements of about `size` [m]. A parallelepiped gets a
    structured grid of ceil(edge / size) hexahedra per edge, each split into 6 Kuhn
    tetrahedra; any other convex polyhedron is coned from its centroid (faces fanned from
    their centres) and red-refined until no edge is longer than about `size` (longest coarse
    edge / 2^levels <= size). InputError if the polyhedron is not convex, the size is larger
    than the block or the mesh would have more than max_nodes nodes."""
    vertices = _vertices(name, vertices, 3)
    size = _check_size(name, size, _diameter(vertices))
    try:
        faces = [np.asarray(f, dtype=np.int64) for f in faces]
    except (TypeError, ValueError):
        raise InputError(f"{name}: faces must be lists of vertex indices") from None
    if len(faces) < 4 or any(f.ndim != 1 or len(f) < 3 or f.min() < 0 or f.max() >= len(vertices)
                             for f in faces):
        raise InputError(f"{name}: faces must be at least 4 lists of >= 3 vertex indices in "
                         f"0..{len(vertices) - 1}")
    centroid = vertices.mean(axis=0)
    diameter = _diameter(vertices)
    for f, face in enumerate(faces):
        normal = np.cross(vertices[face[1]] - vertices[face[0]],
                          vertices[face[2]] - vertices[face[0]])
        normal /= np.linalg.norm(normal) or 1.0
        side = (vertices - vertices[face[0]]) @ normal
        if not (np.all(side <= 1e-9 * diameter) or np.all(side >= -1e-9 * diameter)):
            raise InputError(f"{name}: the polyhedron is not convex (vertices lie on both "
                             f"sides of face {f}); split it into convex blocks")
    box = _parallelepiped(vertices)
    if box is not None:
        return _kuhn(name, *box, size, max_nodes)
    nodes = [vertices, [centroid]]
    cells = []
    g = len(vertices)
    count = g + 1
    for face in faces:
        if len(face) == 3:
            cells.append([g, *face])
            continue
        nodes.append([vertices[face].mean(axis=0)])
        for k in range(len(face)):
            cells.append([g, count, face[k], face[(k + 1) % len(face)]])
        count += 1
    nodes = np.concatenate(nodes)
    cells = np.array(cells, dtype=np.int64)
    x = nodes[cells]
    longest = max(np.linalg.norm(x[:, i] - x[:, j], axis=1).max()
                  for i in range(4) for j in range(i + 1, 4))
    for _ in range(max(0, math.ceil(math.log2(longest / size) - 1e-9))):
        nodes, cells = _red_refine(nodes, cells)
        _check_count(name, len(nodes), max_nodes, size)
    return Mesh.from_cells(nodes, cells, name)


def _parallelepiped(vertices):
    """(origin, edges a, b, c) if the 8 vertices are the corners o + {0,1}a + {0,1}b + {0,1}c."""
    if len(vertices) != 8:
        return None
    o = vertices[0]
    scale = np.linalg.norm(vertices - o, axis=1).max()
    for trio in combinations(range(1, 8), 3):
        a, b, c = vertices[list(trio)] - o
        if abs(np.linalg.det(np.stack([a, b, c]))) <= 1e-9 * scale ** 3:
            continue
        corners = np.array([o + i * a + j * b + k * c for i in (0, 1) for j in (0, 1)
                            for k in (0, 1)])
        gap = np.linalg.norm(corners[:, None] - vertices[None], axis=-1).min(axis=1)
        if np.all(gap <= 1e-9 * scale):
            return o, a, b, c
    return None


def _kuhn(name, origin, a, b, c, size, max_nodes):
    n = [max(1, math.ceil(np.linalg.norm(e) / size - 1e-9)) for e in (a, b, c)]
    _check_count(name, (n[0] + 1) * (n[1] + 1) * (n[2] + 1), max_nodes, size)
    i, j, k = (g.reshape(-1, 1) for g in np.meshgrid(*(np.arange(m + 1) for m in n),
                                                     indexing="ij"))
    nodes = origin + i / n[0] * a + j / n[1] * b + k / n[2] * c
    index = np.arange(len(nodes)).reshape(n[0] + 1, n[1] + 1, n[2] + 1)
    corner = index[:-1, :-1, :-1].ravel()
    step = np.array([(n[1] + 1) * (n[2] + 1), n[2] + 1, 1])
    cells = []
    # Kuhn: the 6 tetrahedra along the cube's main diagonal, one per order of the 3 axes; the
    # same split in every cube makes the faces of neighbours match
    for order in permutations(range(3)):
        path = np.cumsum([0, *step[list(order)]])
        cells.append(corner[:, None] + path[None, :])
    return Mesh.from_cells(nodes, np.concatenate(cells), name)


def _red_refine(nodes, cells):
    """One level of Bey's red refinement: each tetrahedron into 8 through its edge midpoints
    (interior octahedron cut along the diagonal between the midpoints of edges 02 and 13)."""
    pairs = np.array([(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)])
    edges = np.sort(cells[:, pairs].reshape(-1, 2), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = len(nodes) + inverse.reshape(-1, 6)
    nodes = np.concatenate([nodes, 0.5 * (nodes[unique[:, 0]] + nodes[unique[:, 1]])])
    v0, v1, v2, v3 = cells.T
    m01, m02, m03, m12, m13, m23 = mid.T
    children = [(v0, m01, m02, m03), (m01, v1, m12, m13), (m02, m12, v2, m23),
                (m03, m13, m23, v3), (m01, m02, m03, m13), (m01, m02, m12, m13),
                (m02, m03, m13, m23), (m02, m12, m13, m23)]
    return nodes, np.concatenate([np.stack(t, axis=1) for t in children])
