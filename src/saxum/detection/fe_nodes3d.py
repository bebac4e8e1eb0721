"""Narrow phase of deformable blocks in 3D, saxum.detection.fe_nodes' rules with faces for
edges: a point is a boundary node of a deformable block or a vertex of a rigid polyhedron, a
face is a rigid polyhedron's face or a boundary triangle of a deformable block.

    deformable - rigid:       the block's boundary nodes against the polyhedron's faces, and
                              the polyhedron's vertices against the block's triangles;
    deformable - deformable:  the boundary nodes of the block of lower index against the
                              other's triangles.

A point's face is chosen as in 2D (saxum.detection.fe_nodes, module doc): among the faces
within the alert distance of the largest signed distance to the faces' planes, outside =
max_f n_f . (x - a_f), into which x projects, the one most opposed to the point's outward
direction (fe_nodes.prefer), so that a node at the end of a pressed joint stays on the bed
face; a point with outside within `alert` becomes a contact on that face: frame (t, n, s)
with n the face's outward normal, t along its first edge and s = t x n
(saxum.detection.polyhedra's frame), point = x, gap the face's n . (x - a). A point that
projects into no such face is left to the faces' edges and corners (a rigid corner against a
deformable block is a contact of its own, and so is a rigid edge crossing a boundary edge of
a deformable block: below). A node's contact on a deformable block is keyed by the flat side
its triangle lies on (fe_nodes.flat_sides).
Sides: a node is side_node with weight 1; a triangle is its three nodes with the barycentric
coordinates of the projection of x.

Edges (deformable - rigid): where a rigid edge P(s) = a + s (b - a) crosses a side Q(t) = p +
t (q - p) of a boundary triangle, away from their ends (where the corner's or the node's own
contact holds), the contact is at the closest points: n = (b - a) x (q - p) made unit and
turned out of the rigid block, g = n . (Q - P), t along the rigid edge, candidate the two
nodes (weights 1 - t, t), point Q. It is a contact of the two edges when n is strictly
inside the rigid edge's normal cone (between its faces' normals: on a face's normal, the
edge lies on that face, whose own contacts hold) and -n within the deformable edge's (of its
two triangles' normals; for two coplanar triangles, their normal within _FLAT: a rigid edge
lying across a face of the block crosses the mesh's edges there), and g is no deeper than
the deformable edge is long. This is what holds a rigid block that rocks on its edge on a
deformable one, or a rigid beam laid across a deformable block's edge: neither has a node or
a corner on the other's faces where they touch. Not detected: an edge of a deformable block
crossing one of another deformable block.

Area: a node stands for the part of its tributary boundary (a third of each adjacent boundary
triangle) that faces the face, sum max(0, -n . R s) over its triangles' shares s (outward
normal times a third of the area, saxum.bodies.fe.FEBodies.node_side, turned by the block's
frame R); a rigid vertex for nothing (0), as in 2D.
"""

import math

import numba as nb
import numpy as np

from .fe_nodes import candidate_node, facet_side, key_layout, pair_sides, prefer, rigid_side, unit
from .polyhedra import _write as _polyhedron_row

__all__ = ["node_contacts_3d"]


_FLAT = 1e-6
"""|m x n|^2 below which the normal m of a deformable block's triangle is n (1e-3 rad): the
cone of an edge between coplanar triangles, loose enough for their strain (~1e-4 rad)."""
_STRICT = 1e-6
"""(n1 x n) . (n x n2) above which n is strictly inside the normal cone of a rigid edge
between faces of normals n1, n2 (about 1e-3 rad from either)."""
_END = 1e-6
"""Closest points within this fraction of an edge's length of its ends are left to the
corner's or the node's own contact."""


@nb.njit(inline="always")
def _nearest_face(x, y, z, mx, my, mz, f0, f1, wv, wn, fvs, fv, tie, window):
    """(outside [m], g [m], face) of point (x, y, z) against the faces f0..f1 of a rigid
    polyhedron (world vertices wv, outward unit normals wn, face rings fvs/fv counter-clockwise
    seen from outside), fe_nodes._nearest_edge in 3D: outside the largest signed distance, g
    and the face those of the face chosen (fe_nodes.prefer, by the node's outward direction
    (mx, my, mz)) among the faces within `window` of outside into which the point projects
    (within tie). Face -1: none."""
    mx, my, mz = unit(mx, my, mz)
    outside = -1e300
    for f in range(f0, f1):
        a = fv[fvs[f]]
        outside = max(outside, wn[f, 0] * (x - wv[a, 0]) + wn[f, 1] * (y - wv[a, 1])
                      + wn[f, 2] * (z - wv[a, 2]))
    best = -1
    g = -1e300
    facing = 1e300
    for f in range(f0, f1):
        a = fv[fvs[f]]
        nx, ny, nz = wn[f, 0], wn[f, 1], wn[f, 2]
        d = nx * (x - wv[a, 0]) + ny * (y - wv[a, 1]) + nz * (z - wv[a, 2])
        if d < outside - window:
            continue
        dot = nx * mx + ny * my + nz * mz
        if not prefer(dot, d, facing, g, tie) or not _in_face(x, y, z, nx, ny, nz, fvs[f],
                                                              fvs[f + 1], wv, fv, tie):
            continue
        g = d
        best = f
        facing = dot
    return outside, g, best


@nb.njit(inline="always")
def _in_face(x, y, z, nx, ny, nz, ring0, ring1, wv, fv, tie):
    """Whether (x, y, z) projects into the face of normal n and vertex ring fv[ring0:ring1]
    (counter-clockwise seen from outside), within tie [m] of its edges."""
    for k in range(ring0, ring1):
        a = fv[k]
        b = fv[k + 1] if k + 1 < ring1 else fv[ring0]
        ex = wv[b, 0] - wv[a, 0]
        ey = wv[b, 1] - wv[a, 1]
        ez = wv[b, 2] - wv[a, 2]
        # n x e points into a counter-clockwise face: its distance from the edge's line
        ix = ny * ez - nz * ey
        iy = nz * ex - nx * ez
        iz = nx * ey - ny * ex
        inside = ix * (x - wv[a, 0]) + iy * (y - wv[a, 1]) + iz * (z - wv[a, 2])
        if inside < -tie * math.sqrt(ex * ex + ey * ey + ez * ez):
            return False
    return True


@nb.njit(inline="always")
def _triangle(node_x, facet_node, f):
    """(unit outward normal, twice the area [m^2]) of boundary triangle f on node_x."""
    a = facet_node[f, 0]
    b = facet_node[f, 1]
    c = facet_node[f, 2]
    ux = node_x[b, 0] - node_x[a, 0]
    uy = node_x[b, 1] - node_x[a, 1]
    uz = node_x[b, 2] - node_x[a, 2]
    vx = node_x[c, 0] - node_x[a, 0]
    vy = node_x[c, 1] - node_x[a, 1]
    vz = node_x[c, 2] - node_x[a, 2]
    nx = uy * vz - uz * vy
    ny = uz * vx - ux * vz
    nz = ux * vy - uy * vx
    twice = math.sqrt(nx * nx + ny * ny + nz * nz)
    return nx / twice, ny / twice, nz / twice, twice


@nb.njit(inline="always")
def _edge_coordinate(node_x, p, q, x, y, z, nx, ny, nz, twice):
    """Barycentric coordinate [-] of (x, y, z) projected on a triangle of normal n and twice
    the area `twice`, for the vertex opposite edge (p, q) (p to q counter-clockwise), and
    the point's distance from that edge's line [m] (positive inside)."""
    ex = node_x[q, 0] - node_x[p, 0]
    ey = node_x[q, 1] - node_x[p, 1]
    ez = node_x[q, 2] - node_x[p, 2]
    rx = x - node_x[p, 0]
    ry = y - node_x[p, 1]
    rz = z - node_x[p, 2]
    s = nx * (ey * rz - ez * ry) + ny * (ez * rx - ex * rz) + nz * (ex * ry - ey * rx)
    return s / twice, s / math.sqrt(ex * ex + ey * ey + ez * ez)


@nb.njit(inline="always")
def _nearest_facet(x, y, z, mx, my, mz, f0, f1, node_x, facet_node, tie, window, weight):
    """(outside [m], g [m], facet) of point (x, y, z) against the boundary triangles f0..f1
    of a deformable block (saxum.detection.fe_nodes._nearest_facet in 3D): outside the
    largest signed distance over all triangles, g and the facet those of the triangle chosen
    (fe_nodes.prefer, by the point's own outward direction (mx, my, mz)) among the triangles
    within `window` of outside into which the point projects (within tie); weight [3] gets
    the barycentric coordinates of the projection on it (clamped to the triangle). Facet -1:
    none."""
    mx, my, mz = unit(mx, my, mz)
    outside = -1e300
    for f in range(f0, f1):
        nx, ny, nz = _triangle(node_x, facet_node, f)[:3]
        a = facet_node[f, 0]
        outside = max(outside, nx * (x - node_x[a, 0]) + ny * (y - node_x[a, 1])
                      + nz * (z - node_x[a, 2]))
    best = -1
    g = -1e300
    facing = 1e300
    for f in range(f0, f1):
        nx, ny, nz, twice = _triangle(node_x, facet_node, f)
        a = facet_node[f, 0]
        b = facet_node[f, 1]
        c = facet_node[f, 2]
        d = nx * (x - node_x[a, 0]) + ny * (y - node_x[a, 1]) + nz * (z - node_x[a, 2])
        if d < outside - window:
            continue
        dot = nx * mx + ny * my + nz * mz
        if not prefer(dot, d, facing, g, tie):
            continue
        la, da = _edge_coordinate(node_x, b, c, x, y, z, nx, ny, nz, twice)
        lb, db = _edge_coordinate(node_x, c, a, x, y, z, nx, ny, nz, twice)
        lc, dc = _edge_coordinate(node_x, a, b, x, y, z, nx, ny, nz, twice)
        if da < -tie or db < -tie or dc < -tie:
            continue
        g = d
        best = f
        facing = dot
        la = max(la, 0.0)
        lb = max(lb, 0.0)
        lc = max(lc, 0.0)
        total = la + lb + lc
        weight[0] = la / total
        weight[1] = lb / total
        weight[2] = lc / total
    return outside, g, best


@nb.njit(inline="always")
def _block_rotation(q, axes0, body, f, r):
    """r = R_q R0^T [3, 3]: the turn of deformable block f (body `body`) from its reference,
    R_q its body row's rotation (quaternion q[body, 3:]) and R0 = axes0[f] its reference."""
    w, x, y, z = q[body, 3], q[body, 4], q[body, 5], q[body, 6]
    rq = np.array([[1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
                   [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
                   [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)]])
    r[:] = rq @ axes0[f].T


@nb.njit(inline="always")
def _node_side_sum(node_side, p, r, nx, ny, nz):
    """(part of node p's tributary boundary facing the normal n [m^2], its outward direction
    sum R s [m^2] as three numbers) (module doc)."""
    a = 0.0
    mx = my = mz = 0.0
    for k in range(node_side.shape[1]):
        s0 = node_side[p, k, 0]
        s1 = node_side[p, k, 1]
        s2 = node_side[p, k, 2]
        sx = r[0, 0] * s0 + r[0, 1] * s1 + r[0, 2] * s2
        sy = r[1, 0] * s0 + r[1, 1] * s1 + r[1, 2] * s2
        sz = r[2, 0] * s0 + r[2, 1] * s1 + r[2, 2] * s2
        a += max(0.0, -(nx * sx + ny * sy + nz * sz))
        mx += sx
        my += sy
        mz += sz
    return a, mx, my, mz


@nb.njit(inline="always")
def _write(count, cand, ant, key_value, law_index, x, y, z, tx, ty, tz, nx, ny, nz, g,
           area_value, candidate, antagonist, key, law, point, frame, gap, area):
    """Row count of the contact arrays (saxum.detection.polyhedra's row: t along the face's
    first edge, made unit; s = t x n) and its area [m^2]."""
    norm = math.sqrt(tx * tx + ty * ty + tz * tz)
    _polyhedron_row(candidate, antagonist, key, law, point, frame, gap, count, cand, ant,
                    key_value, law_index, x, y, z, tx / norm, ty / norm, tz / norm, nx, ny, nz,
                    g)
    area[count] = area_value


@nb.njit(cache=True)
def _edge_contacts(count, fb, ob, f, law_index, pair_alert, wv, wn, body_edge_start,
                   edge_vertex, edge_face, node_x, facet_node, fe_edge_start, fe_edge_node,
                   fe_edge_facet, edge_base, candidate, antagonist, key, law, point, frame,
                   gap, area, side_kind, side_node, side_weight):
    """Append the contacts of rigid body ob's edges crossing deformable block f's boundary
    edges (module doc) from row `count` on; returns the new count, or -1 when the arrays are
    full. Keys edge_base + e E + k, e the rigid edge, k the block's edge (E of them in all)."""
    edges = fe_edge_node.shape[0]
    for e in range(body_edge_start[ob], body_edge_start[ob + 1]):
        a = edge_vertex[e, 0]
        b = edge_vertex[e, 1]
        n1 = wn[edge_face[e, 0]]
        n2 = wn[edge_face[e, 1]]
        d1 = wv[b] - wv[a]
        aa = d1 @ d1
        for k in range(fe_edge_start[f], fe_edge_start[f + 1]):
            p = fe_edge_node[k, 0]
            q = fe_edge_node[k, 1]
            d2 = node_x[q] - node_x[p]
            r = wv[a] - node_x[p]
            bb = d1 @ d2
            ee = d2 @ d2
            denom = aa * ee - bb * bb
            if denom <= 1e-12 * aa * ee:
                continue  # parallel: the ends' contacts hold
            c = d1 @ r
            ff = d2 @ r
            s = (bb * ff - c * ee) / denom
            t = (aa * ff - bb * c) / denom
            if s <= _END or s >= 1.0 - _END or t <= _END or t >= 1.0 - _END:
                continue
            n = np.cross(d1, d2) / math.sqrt(denom)
            if n @ (n1 + n2) < 0.0:
                n = -n
            g = n @ (node_x[p] + t * d2 - wv[a] - s * d1)
            if g > pair_alert or g < -math.sqrt(ee):
                continue
            if np.cross(n1, n) @ np.cross(n, n2) <= _STRICT:
                continue
            m1 = _triangle(node_x, facet_node, fe_edge_facet[k, 0])
            m2 = _triangle(node_x, facet_node, fe_edge_facet[k, 1])
            u1 = np.array([m1[0], m1[1], m1[2]])
            u2 = np.array([m2[0], m2[1], m2[2]])
            if n @ (u1 + u2) >= 0.0 or np.cross(u1, n) @ np.cross(n, u2) < -_FLAT:
                continue
            if count >= candidate.shape[0]:
                return -1
            x = node_x[p] + t * d2
            side_kind[count, 0] = 1
            side_node[count, 0, 0] = p
            side_node[count, 0, 1] = q
            side_node[count, 0, 2] = p
            side_weight[count, 0, 0] = 1.0 - t
            side_weight[count, 0, 1] = t
            side_weight[count, 0, 2] = 0.0
            rigid_side(count, 1, side_kind, side_node, side_weight)
            _write(count, fb, ob, edge_base + e * edges + k, law_index, x[0], x[1], x[2],
                   d1[0], d1[1], d1[2], n[0], n[1], n[2], g, 0.0, candidate, antagonist, key,
                   law, point, frame, gap, area)
            count += 1
    return count


@nb.njit(cache=True)
def node_contacts_3d(pairs, pair_count, fe_index, q, axes0, node_x, boundary_start,
                     boundary_node, node_side, facet_start, facet_node, flat_side, wv, wn,
                     face_start, fvs,
                     fv, body_vertex_start, body_edge_start, edge_vertex, edge_face,
                     fe_edge_start, fe_edge_node, fe_edge_facet, body_group, group_law, alert,
                     law_alert, body_alert, key_base, count,
                     candidate, antagonist, key, law, point, frame, gap, area, side_kind,
                     side_node, side_weight):
    """Append the contacts of the pairs (body i, body j) with a deformable block (module doc)
    from row `count` on; returns the new count. axes0 [n_fe, 3, 3]: the principal axes of the
    blocks' body rows at the start (saxum.bodies.fe3d.principal_axes). Keys above key_base,
    distinct per (point, face): node p against face or facet e, key_base + p E + e' with e' =
    e for a rigid face and F_r + flat_side[e] for a facet (F_r rigid faces, E = F_r +
    facets; flat_sides: a node that strains or slips onto the next triangle of the same flat
    side keeps its contact, with its warm start and a joint law's damage); a rigid
    vertex k against facet e, key_base + N E + k F + e (N nodes, F facets). The arrays must
    have room for every boundary node and vertex of every pair; a rigid edge e against
    boundary edge k (_edge_contacts), key_base + (N + V) E + e E_k + k (V vertices, E_k
    boundary edges). Returns -1 when the arrays are full. alert [m]: the detector's;
    law_alert, body_alert [m]: per law and body (Detector), which a pair uses
    (alert_of_pair)."""
    faces = wn.shape[0]
    facets = facet_node.shape[0]
    tie, features, vertex_base = key_layout(alert, faces, node_x.shape[0], facets, key_base)
    edge_base = vertex_base + wv.shape[0] * facets
    r = np.empty((3, 3))
    weight = np.empty(3)
    for pr in range(pair_count):
        fb, ob, f, o, law_index, pair_alert = pair_sides(pairs, pr, fe_index, body_group,
                                                         group_law, law_alert, body_alert, alert)
        if law_index < 0:
            continue
        _block_rotation(q, axes0, fb, f, r)
        rigid = o < 0
        for m in range(boundary_start[f], boundary_start[f + 1]):
            p = boundary_node[m]
            x = node_x[p, 0]
            y = node_x[p, 1]
            z = node_x[p, 2]
            mx, my, mz = _node_side_sum(node_side, p, r, 0.0, 0.0, 0.0)[1:]
            if rigid:
                outside, g, e = _nearest_face(x, y, z, mx, my, mz, face_start[ob],
                                              face_start[ob + 1], wv, wn, fvs, fv, tie,
                                              pair_alert)
                if e < 0 or outside > pair_alert:
                    continue
                nx, ny, nz = wn[e, 0], wn[e, 1], wn[e, 2]
                a0 = fv[fvs[e]]
                a1 = fv[fvs[e] + 1]
                tx = wv[a1, 0] - wv[a0, 0]
                ty = wv[a1, 1] - wv[a0, 1]
                tz = wv[a1, 2] - wv[a0, 2]
                rigid_side(count, 1, side_kind, side_node, side_weight)
                face_key = e
            else:
                outside, g, e = _nearest_facet(x, y, z, mx, my, mz, facet_start[o],
                                               facet_start[o + 1], node_x, facet_node, tie,
                                               pair_alert, weight)
                if e < 0 or outside > pair_alert:
                    continue
                nx, ny, nz = _triangle(node_x, facet_node, e)[:3]
                tx = node_x[facet_node[e, 1], 0] - node_x[facet_node[e, 0], 0]
                ty = node_x[facet_node[e, 1], 1] - node_x[facet_node[e, 0], 1]
                tz = node_x[facet_node[e, 1], 2] - node_x[facet_node[e, 0], 2]
                facet_side(count, facet_node, e, weight, side_kind, side_node, side_weight)
                face_key = faces + flat_side[e]
            candidate_node(count, p, side_kind, side_node, side_weight)
            _write(count, fb, ob, key_base + p * features + face_key, law_index, x, y, z, tx,
                   ty, tz, nx, ny, nz, g, _node_side_sum(node_side, p, r, nx, ny, nz)[0],
                   candidate, antagonist, key, law, point, frame, gap, area)
            count += 1
        if not rigid:
            continue
        # the rigid polyhedron's corners against the deformable block's triangles (the 2D
        # loop in fe_nodes has the same steps with an edge's two shape functions for the
        # triangle's barycentric weights: the searches differ, the row writing is shared)
        for k in range(body_vertex_start[ob], body_vertex_start[ob + 1]):
            x = wv[k, 0]
            y = wv[k, 1]
            z = wv[k, 2]
            # the corner's outward direction: from the polyhedron's centre of mass
            outside, g, e = _nearest_facet(x, y, z, x - q[ob, 0], y - q[ob, 1], z - q[ob, 2],
                                           facet_start[f], facet_start[f + 1], node_x,
                                           facet_node, tie, pair_alert, weight)
            if e < 0 or outside > pair_alert:
                continue
            if weight[0] == 1.0 or weight[1] == 1.0 or weight[2] == 1.0:
                continue  # on a node: the node's own contact on the polyhedron's face holds it
            nx, ny, nz = _triangle(node_x, facet_node, e)[:3]
            rigid_side(count, 0, side_kind, side_node, side_weight)
            facet_side(count, facet_node, e, weight, side_kind, side_node, side_weight)
            _write(count, ob, fb, vertex_base + k * facets + e, law_index, x, y, z,
                   node_x[facet_node[e, 1], 0] - node_x[facet_node[e, 0], 0],
                   node_x[facet_node[e, 1], 1] - node_x[facet_node[e, 0], 1],
                   node_x[facet_node[e, 1], 2] - node_x[facet_node[e, 0], 2], nx, ny, nz, g,
                   0.0, candidate, antagonist, key, law, point, frame, gap, area)
            count += 1
        count = _edge_contacts(count, fb, ob, f, law_index, pair_alert, wv, wn, body_edge_start,
                               edge_vertex, edge_face, node_x, facet_node, fe_edge_start,
                               fe_edge_node, fe_edge_facet, edge_base, candidate, antagonist,
                               key, law, point, frame, gap, area, side_kind, side_node,
                               side_weight)
        if count < 0:
            return -1
    return count
