"""Solid geometry of convex polyhedral blocks: hull, faces, edges, volume, centroid, inertia.

A block is given as a point set; its convex hull (Qhull, through scipy.spatial.ConvexHull) is
the block. Qhull returns triangles; coplanar neighbouring triangles are merged into the block's
polygonal faces, whose vertices are listed counter-clockwise seen from outside.

Mass properties by decomposition into tetrahedra (o, a, b, c), o a reference point inside the
block and (a, b, c) a fan triangle of a face (D. Eberly, "Polyhedral mass properties (revisited)",
2002; J. Blow, A. Binstock, "How to find the inertia tensor (or other mass properties) of a 3D
solid body represented by a triangle mesh", 2004; F. Tonon, "Explicit exact formulas for the 3-D
tetrahedron inertia tensor in terms of its vertex coordinates", J. Math. Stat. 1, 2005): with
a, b, c taken relative to o and d = a . (b x c) (six times the signed volume),
    V   = sum d / 6
    C   = sum d (a + b + c) / 24 / V                              (centroid)
    S   = sum d / 120 (a a^T + b b^T + c c^T + (a + b + c)(a + b + c)^T)   (second moments)
    S_G = S - V C C^T,   J_G = tr(S_G) 1 - S_G                   (inertia per unit density)
The principal axes (eigenvectors of J_G, right-handed) are the body frame, so the inertia tensor
there is diag(J_1, J_2, J_3).

A cluster (a non-convex block as the union of convex parts k, LMGC90's clustered contactors)
combines its parts by the parallel-axis theorem (Meriam and Kraige, Engineering Mechanics:
Dynamics, appendix B): V = sum V_k, C = sum V_k C_k / V,
J_G = sum [A_k diag(J_k) A_k^T + V_k (|d_k|^2 1 - d_k d_k^T)], d_k = C_k - C.
"""

from dataclasses import dataclass

import numpy as np

from .errors import InputError

__all__ = ["Polyhedron", "clip_polyhedron", "cluster_properties", "convex_polyhedron",
           "polyhedron_properties",
           "quaternion_from_matrix", "relative_quaternions", "rotation_matrix", "rotation_vectors",
           "world_points"]

_REL_TOL = 1e-9


@dataclass(frozen=True)
class Polyhedron:
    """A convex polyhedron: vertices [m] (n, 3); faces: vertex indices per face, CCW seen
    from outside; normals: outward unit normal per face (f, 3); edges: (vertex, vertex) pairs
    (e, 2) with edge_faces (e, 2): the face on the left of the edge going from its first vertex
    to its second (seen from outside) and the face on its right."""

    vertices: np.ndarray
    faces: tuple[np.ndarray, ...]
    normals: np.ndarray
    edges: np.ndarray
    edge_faces: np.ndarray


@dataclass(frozen=True)
class PolyhedronProperties:
    """Volume [m^3], centroid [m] (3,), principal second moments of volume J_1..J_3 about the
    centroid [m^5] (3,) and the principal axes as the columns of a rotation matrix (3, 3)."""

    volume: float
    centroid: np.ndarray
    moments: np.ndarray
    axes: np.ndarray


def convex_polyhedron(points, *, name: str = "block") -> Polyhedron:
    """The convex hull of `points` [m] (n, 3) as a Polyhedron.

    Raises InputError naming `name` for NaN/inf coordinates, fewer than 4 points, a flat
    (zero-volume) set, or a point set that is not convex: a point strictly inside the hull
    (points on its surface, e.g. in the middle of an edge, are dropped).
    """
    p = np.array(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 3:
        raise InputError(f"{name}: vertices must be a list of (x, y, z) points, got shape "
                         f"{p.shape}")
    if len(p) < 4:
        raise InputError(f"{name}: a polyhedron needs at least 4 vertices, got {len(p)}")
    if not np.all(np.isfinite(p)):
        raise InputError(f"{name}: vertex coordinates contain NaN or infinity")
    from scipy.spatial import ConvexHull, QhullError  # here: 0.3 s of import a 2D run skips

    scale = float(np.ptp(p, axis=0).max())
    try:
        hull = ConvexHull(p)
    except QhullError:
        raise InputError(f"{name}: flat or degenerate point set (zero volume); a block needs "
                         "points that do not all lie in one plane") from None
    if hull.volume <= _REL_TOL * scale**3:
        raise InputError(f"{name}: flat point set (volume {hull.volume:.3g} m^3); a block needs "
                         "points that do not all lie in one plane")
    # signed distance of every input point to the hull's planes: <= 0 inside
    depth = (p @ hull.equations[:, :3].T + hull.equations[:, 3]).max(axis=1)
    inside = np.flatnonzero(depth < -_REL_TOL * scale)
    if inside.size:
        k = int(inside[0])
        at = tuple(round(float(x), 6) for x in p[k])
        raise InputError(
            f"{name}: the point set is not convex: vertex {k} at {at} lies "
            f"{-depth[k]:.3g} m inside the convex hull of the others; split the block into "
            "convex parts (blocks, or the parts of one block: ModelBuilder.add_cluster)"
        )
    return _merge_faces(p, hull, scale)


def _merge_faces(p: np.ndarray, hull, scale: float) -> Polyhedron:
    """Polygonal faces from Qhull's triangles: neighbours with the same plane are one face."""
    ntri = len(hull.simplices)
    label = np.full(ntri, -1)
    normal = hull.equations[:, :3]
    nface = 0
    for t in range(ntri):
        if label[t] >= 0:
            continue
        label[t] = nface
        stack = [t]
        while stack:
            s = stack.pop()
            for u in hull.neighbors[s]:
                if label[u] < 0 and normal[u] @ normal[t] > 1.0 - 1e-10:
                    offset = abs(normal[t] @ p[hull.simplices[u]].mean(axis=0)
                                 + hull.equations[t, 3])
                    if offset <= _REL_TOL * scale:
                        label[u] = nface
                        stack.append(u)
        nface += 1
    used = np.unique(hull.simplices)
    new_index = np.full(len(p), -1)
    new_index[used] = np.arange(len(used))
    vertices = p[used]
    faces, normals = [], []
    for f in range(nface):
        tris = np.flatnonzero(label == f)
        n = normal[tris].mean(axis=0)
        n /= np.linalg.norm(n)
        idx = np.unique(hull.simplices[tris])
        pts = p[idx]
        centre = pts.mean(axis=0)
        u = pts[0] - centre
        u -= (u @ n) * n
        u /= np.linalg.norm(u)
        w = np.cross(n, u)
        angle = np.arctan2((pts - centre) @ w, (pts - centre) @ u)
        ring = idx[np.argsort(angle, kind="stable")]
        faces.append(_drop_collinear(p, ring, scale))
        normals.append(n)
    faces = [new_index[f] for f in faces]
    keep = np.unique(np.concatenate(faces))
    if len(keep) < len(vertices):  # points dropped as collinear on an edge
        renumber = np.full(len(vertices), -1)
        renumber[keep] = np.arange(len(keep))
        vertices = vertices[keep]
        faces = [renumber[f] for f in faces]
    edges, edge_faces = _edges(faces)
    return Polyhedron(vertices=vertices, faces=tuple(np.asarray(f, dtype=np.int64) for f in faces),
                      normals=np.array(normals), edges=edges, edge_faces=edge_faces)


def _drop_collinear(p: np.ndarray, ring: np.ndarray, scale: float) -> np.ndarray:
    """The face ring without vertices in the middle of a straight side."""
    keep = []
    m = len(ring)
    for k in range(m):
        a, b, c = p[ring[k - 1]], p[ring[k]], p[ring[(k + 1) % m]]
        if np.linalg.norm(np.cross(b - a, c - b)) > _REL_TOL * scale * np.linalg.norm(c - a):
            keep.append(ring[k])
    return np.array(keep)


def _edges(faces: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Each edge once, as (u, v) with u < v, with the faces on its left and right."""
    left: dict[tuple[int, int], int] = {}
    for f, ring in enumerate(faces):
        for k in range(len(ring)):
            left[(int(ring[k]), int(ring[(k + 1) % len(ring)]))] = f
    edges, adjacent = [], []
    for (u, v), f in sorted(left.items()):
        if u < v:
            edges.append((u, v))
            adjacent.append((f, left[(v, u)]))
    return np.array(edges, dtype=np.int64), np.array(adjacent, dtype=np.int64)


def clip_polyhedron(poly: Polyhedron, normal, offset: float) -> Polyhedron | None:
    """The part {x : normal . x <= offset} of a convex polyhedron (the hull of its vertices on
    that side and of its edges' crossings of the plane), or None if that part is empty or
    flat; normal: a unit vector, offset [m]."""
    n = np.asarray(normal, dtype=np.float64)
    side = poly.vertices @ n - offset
    a, b = poly.edges.T
    crossing = (side[a] < 0.0) != (side[b] < 0.0)
    f = side[a[crossing]] / (side[a[crossing]] - side[b[crossing]])
    cut = poly.vertices[a[crossing]] + f[:, None] * (poly.vertices[b[crossing]]
                                                    - poly.vertices[a[crossing]])
    points = np.vstack((poly.vertices[side <= 0.0], cut))
    if len(points) < 4:
        return None
    from scipy.spatial import ConvexHull, QhullError

    scale = float(np.ptp(poly.vertices, axis=0).max())
    try:
        hull = ConvexHull(points)
    except QhullError:
        return None
    if hull.volume <= _REL_TOL * scale**3:
        return None
    return _merge_faces(points, hull, scale)


def polyhedron_properties(poly: Polyhedron) -> PolyhedronProperties:
    """Volume, centroid, principal second moments of volume and principal axes (module doc)."""
    v = poly.vertices
    origin = v.mean(axis=0)  # inside: sums are taken about it to avoid cancellation
    x = v - origin
    volume6 = 0.0
    first = np.zeros(3)
    second = np.zeros((3, 3))
    for ring in poly.faces:
        a = x[ring[0]]
        for k in range(1, len(ring) - 1):
            b, c = x[ring[k]], x[ring[k + 1]]
            d = float(a @ np.cross(b, c))
            s = a + b + c
            volume6 += d
            first += d * s
            second += d * (np.outer(a, a) + np.outer(b, b) + np.outer(c, c) + np.outer(s, s))
    volume = volume6 / 6.0
    centroid = first / (24.0 * volume)
    s_g = second / 120.0 - volume * np.outer(centroid, centroid)
    inertia = np.trace(s_g) * np.eye(3) - s_g
    return _principal(float(volume), centroid + origin, inertia)


def cluster_properties(parts: "list[Polyhedron]") -> PolyhedronProperties:
    """Volume, centroid, principal second moments and axes of the union of convex parts that
    do not overlap (a cluster: module doc, parallel-axis theorem)."""
    if len(parts) == 1:  # the same numbers as for a block
        return polyhedron_properties(parts[0])
    props = [polyhedron_properties(part) for part in parts]
    volume = sum(p.volume for p in props)
    centroid = sum(p.volume * p.centroid for p in props) / volume
    inertia = np.zeros((3, 3))
    for p in props:
        d = p.centroid - centroid
        inertia += (p.axes * p.moments) @ p.axes.T + p.volume * (d @ d * np.eye(3)
                                                                  - np.outer(d, d))
    return _principal(volume, centroid, 0.5 * (inertia + inertia.T))


def _principal(volume: float, centroid: np.ndarray, inertia: np.ndarray
               ) -> PolyhedronProperties:
    """The properties of a body of inertia tensor `inertia` per unit density [m^5] about its
    centroid: principal moments and right-handed principal axes."""
    off = np.abs(inertia - np.diag(np.diag(inertia))).max()
    if off <= 1e-12 * np.trace(inertia):
        # already principal (e.g. an axis-aligned box): keep the world axes as body axes
        moments, axes = np.diag(inertia).copy(), np.eye(3)
    else:
        moments, axes = np.linalg.eigh(inertia)
        if np.linalg.det(axes) < 0.0:
            axes[:, 2] = -axes[:, 2]
    return PolyhedronProperties(volume=volume, centroid=centroid, moments=moments, axes=axes)


def rotation_matrix(q) -> np.ndarray:
    """Rotation matrix (body to world) of the unit quaternion q = (w, x, y, z); q may be an
    array (..., 4), giving (..., 3, 3)."""
    w, x, y, z = np.moveaxis(np.asarray(q, dtype=np.float64), -1, 0)
    return np.moveaxis(np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]), (0, 1), (-2, -1))


def world_points(q: np.ndarray, start: np.ndarray, local: np.ndarray) -> np.ndarray:
    """World coordinates [m] of the body-frame points `local` (k, 3), body b owning the rows
    start[b]:start[b+1], at the 3D coordinates q (..., bodies, 7): shape (..., k, 3)."""
    owner = np.repeat(np.arange(len(start) - 1), np.diff(start))
    rot = rotation_matrix(q[..., owner, 3:])
    return q[..., owner, :3] + np.einsum("...ij,...j->...i", rot, local)


def relative_quaternions(q: np.ndarray, q0: np.ndarray) -> np.ndarray:
    """The unit quaternions (w, x, y, z) q q0^-1 (..., 4) of the rotations (world frame) that
    take the orientations q0 (..., 4) to q (..., 4)."""
    w0, v0 = q0[..., :1], -q0[..., 1:]
    w1, v1 = q[..., :1], q[..., 1:]
    w = w1 * w0 - np.sum(v1 * v0, axis=-1, keepdims=True)
    v = w1 * v0 + w0 * v1 + np.cross(v1, v0)
    return np.concatenate((w, v), axis=-1)


def rotation_vectors(q: np.ndarray, q0: np.ndarray) -> np.ndarray:
    """Rotation vectors [rad] (world frame; direction: axis, length: angle in [0, pi]) that
    take the orientations q0 (..., 4) to q (..., 4)."""
    r = relative_quaternions(q, q0)
    w, v = r[..., :1], r[..., 1:]
    v = np.where(w < 0.0, -v, v)
    norm = np.linalg.norm(v, axis=-1, keepdims=True)
    angle = 2.0 * np.arctan2(norm, np.abs(w))
    return np.divide(angle * v, norm, out=np.zeros_like(v), where=norm > 0.0)


def quaternion_from_matrix(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z), w >= 0, of the rotation matrix r (Shepperd's method:
    the largest of the four squared components is taken from the diagonal, the others from
    the off-diagonal terms, which keeps it accurate for any angle)."""
    t = np.trace(r)
    diag = (t, r[0, 0], r[1, 1], r[2, 2])
    k = int(np.argmax(diag))
    if k == 0:
        w = 0.5 * np.sqrt(1.0 + t)
        q = np.array([w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w),
                      (r[1, 0] - r[0, 1]) / (4 * w)])
    elif k == 1:
        x = 0.5 * np.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = np.array([(r[2, 1] - r[1, 2]) / (4 * x), x, (r[0, 1] + r[1, 0]) / (4 * x),
                      (r[0, 2] + r[2, 0]) / (4 * x)])
    elif k == 2:
        y = 0.5 * np.sqrt(1.0 - r[0, 0] + r[1, 1] - r[2, 2])
        q = np.array([(r[0, 2] - r[2, 0]) / (4 * y), (r[0, 1] + r[1, 0]) / (4 * y), y,
                      (r[1, 2] + r[2, 1]) / (4 * y)])
    else:
        z = 0.5 * np.sqrt(1.0 - r[0, 0] - r[1, 1] + r[2, 2])
        q = np.array([(r[1, 0] - r[0, 1]) / (4 * z), (r[0, 2] + r[2, 0]) / (4 * z),
                      (r[1, 2] + r[2, 1]) / (4 * z), z])
    q /= np.linalg.norm(q)
    return q if q[0] >= 0.0 else -q
