"""Narrow phase of round bodies: discs (2D) and spheres (3D) against each other and against
convex polygons (polyhedra), and capsules (a segment ab with round ends of radius r: the 2D
stadium, the 3D spherocylinder).

A round body of radius r touches a convex body at one point. Against another round body the
normal is the line of centres, n = (c_i - c_j) / |c_i - c_j|, and the gap |c_i - c_j| - r_i - r_j.
Against a polygon (polyhedron) P the disc's centre c is compared with P's closest feature: if c is
outside P, the closest point p of P's boundary lies inside a face (n = the face's outward
normal, gap = n . (c - a_f) - r, a_f a point of the face), inside an edge or at a vertex (n =
(c - p) / |c - p|, gap = |c - p| - r); if c is inside P (a deep interpenetration), the face of
largest separation gives n and the (negative) gap. The polygon is the antagonist and carries
the frame; the round body is the candidate and the point c - r n on its surface is the contact
point. Between two round bodies the first of the pair is the candidate.

A contact's key is key_base + (i n_bodies + j) features + the feature of the polygon (face,
edge, vertex) it touches, so that pairs sorted by (i, j) write keys in increasing order and a
contact keeps its impulse while the round body stays on one face.

A capsule is the set of points within r of its segment ab, whose ends the kernel reads off
its bounding rectangle. The closest points of two convex bodies include a vertex of one of
them (ab's vertices are a and b), so a capsule meets a polygon as its two end circles, each a
disc (keys: end 0's features, then end 1's, 2 x the polygon's 2 n features), and as the
polygon's vertices against ab where their closest point is inside ab (keys 4 n + vertex): a
capsule lying on a face touches it at both end circles, a block's corners under its side at
those corners. Against a disc or a capsule: the ends of the first body's segment against the
second's segment, then the second's ends where their closest point is inside the first's
(keys 0-3; an end against an end is found once). The round body of a contact (the
candidate) is the capsule, or the body whose end touches.

A 3D capsule (the spherocylinder) has its segment along its body frame's z axis and a
bounding box for vertices. Against a polyhedron of m sphere features (faces, edges and
vertices as above) it is its two end spheres (keys: end 0's features, then end 1's, 2 m),
then the polyhedron's edges whose closest points to the segment lie inside both (2 m + edge:
a capsule across a block's top edges rests on them) and its vertices against the segment (2
m + edges + vertex); the closest points of a segment and a convex polyhedron are among
these, and a capsule lying on a face touches it at both ends. Two capsules also meet at the
closest points of their segments where these lie inside both (key 4: capsules crossing),
with curvature radius sqrt(r_i r_j) (exact for cylinders crossing at right angles).

Area (laws in stresses): the part of the round body's surface within the alert distance a of
the face, where the gap grows as g + x^2 / (2 R) at a distance x from the point (R the
radius; two round bodies: R = r_i r_j / (r_i + r_j)): in 2D the chord 2 sqrt(2 R (a - g)) [m],
in 3D the disc pi 2 R (a - g) [m^2]. A round body against an edge or a vertex gets no area (as
an edge against an edge of two polyhedra).
"""

import math

import numba as nb

from .fe_nodes3d import _edge_coordinate
from .polygons import _write as _write_2d
from .polygons import alert_of_pair
from .polyhedra import _write as _write_3d

__all__ = ["round_contacts"]

_ROUND = 1  # saxum.model.Shape.ROUND
_POLYGON = 0  # saxum.model.Shape.POLYGON
_CAPSULE = 2  # saxum.model.Shape.CAPSULE


@nb.njit(cache=True)
def _segment(q, wv, edge_length, vertex_start, shape, round_radius, b):
    """(a_x, a_y, a_z, b_x, b_y, b_z) [m]: the ends of capsule b's segment, z = 0 in 2D (its
    bounding rectangle's first edge runs along it; in 3D it runs along the body frame's z axis,
    half its bounding box's extent less r from the centre), or twice the centre of a disc
    (sphere)."""
    cz = q[b, 2] if wv.shape[1] == 3 else 0.0
    if shape[b] != _CAPSULE:
        return q[b, 0], q[b, 1], cz, q[b, 0], q[b, 1], cz
    v0 = vertex_start[b]
    if wv.shape[1] == 2:
        length = edge_length[v0]
        half = 0.5 * length - round_radius[b]
        tx = (wv[v0 + 1, 0] - wv[v0, 0]) / length
        ty = (wv[v0 + 1, 1] - wv[v0, 1]) / length
        tz = 0.0
    else:  # the body z axis: the third column of the rotation of q's quaternion
        w, x, y, z = q[b, 3], q[b, 4], q[b, 5], q[b, 6]
        tx = 2.0 * (x * z + w * y)
        ty = 2.0 * (y * z - w * x)
        tz = 1.0 - 2.0 * (x * x + y * y)
        half = abs((wv[v0, 0] - q[b, 0]) * tx + (wv[v0, 1] - q[b, 1]) * ty
                   + (wv[v0, 2] - cz) * tz) - round_radius[b]
    return (q[b, 0] - half * tx, q[b, 1] - half * ty, cz - half * tz,
            q[b, 0] + half * tx, q[b, 1] + half * ty, cz + half * tz)


@nb.njit(inline="always")
def _closest_on_segment(px, py, pz, seg):
    """(x, y, z, u) [m, m, m, -]: the point of segment ab, seg = (a, b) [m], closest to p, at
    the fraction u of ab."""
    ax, ay, az, bx, by, bz = seg
    ex = bx - ax
    ey = by - ay
    ez = bz - az
    length2 = ex * ex + ey * ey + ez * ez
    u = 0.0 if length2 == 0.0 else min(1.0, max(0.0, ((px - ax) * ex + (py - ay) * ey
                                                      + (pz - az) * ez) / length2))
    return ax + u * ex, ay + u * ey, az + u * ez, u


@nb.njit(cache=True)
def _closest_of_segments(first, second):
    """(s, u) [-]: the fractions of the segments first = (a, b) and second = (c, d) [m] at
    their closest points (C. Ericson, Real-time collision detection, 2005, sec. 5.1.9:
    minimize over s the distance to the line cd, clamp, then take u on cd and clamp again, s
    following); parallel segments: s = 0."""
    ax, ay, az, bx, by, bz = first
    cx, cy, cz, dx, dy, dz = second
    e1x, e1y, e1z = bx - ax, by - ay, bz - az
    e2x, e2y, e2z = dx - cx, dy - cy, dz - cz
    rx, ry, rz = ax - cx, ay - cy, az - cz
    aa = e1x * e1x + e1y * e1y + e1z * e1z
    ee = e2x * e2x + e2y * e2y + e2z * e2z
    bb = e1x * e2x + e1y * e2y + e1z * e2z
    cc = e1x * rx + e1y * ry + e1z * rz
    ff = e2x * rx + e2y * ry + e2z * rz
    den = aa * ee - bb * bb
    s = min(1.0, max(0.0, (bb * ff - cc * ee) / den)) if den > 0.0 else 0.0
    u = (bb * s + ff) / ee
    if u < 0.0:
        return min(1.0, max(0.0, -cc / aa)), 0.0
    if u > 1.0:
        return min(1.0, max(0.0, (bb - cc) / aa)), 1.0
    return s, u


@nb.njit(inline="always")
def _pair_of_round(q, round_radius, i, j, dim):
    """(n, gap [m], curvature radius R [m]) of two round bodies: n from j to i (a tuple of 3,
    z = 0 in 2D)."""
    dx = q[i, 0] - q[j, 0]
    dy = q[i, 1] - q[j, 1]
    dz = q[i, 2] - q[j, 2] if dim == 3 else 0.0
    d = math.sqrt(dx * dx + dy * dy + dz * dz)
    ri = round_radius[i]
    rj = round_radius[j]
    if d > 0.0:
        n = (dx / d, dy / d, dz / d)
    else:  # concentric: any direction; the gap says how deep
        n = (0.0, 1.0, 0.0) if dim == 2 else (0.0, 0.0, 1.0)
    return n, d - ri - rj, ri * rj / (ri + rj)


@nb.njit(cache=True)
def _disc_polygon(c_x, c_y, wv, wn, edge_length, v0, nv):
    """(n_x, n_y, distance [m] from the disc's centre c to the polygon along n, feature): the
    polygon's closest feature to c (module doc); feature: edge e, or nv + vertex k."""
    best_s = -math.inf
    best_e = 0
    for e in range(nv):
        s = wn[v0 + e, 0] * (c_x - wv[v0 + e, 0]) + wn[v0 + e, 1] * (c_y - wv[v0 + e, 1])
        if s > best_s:
            best_s = s
            best_e = e
    if best_s <= 0.0:  # the centre is inside: the face of largest separation
        return wn[v0 + best_e, 0], wn[v0 + best_e, 1], best_s, best_e
    dist = math.inf
    nx = ny = 0.0
    feature = 0
    for e in range(nv):
        ax = wv[v0 + e, 0]
        ay = wv[v0 + e, 1]
        # along the edge: t = (-n_y, n_x) turns from v_e towards v_e+1 (CCW polygon)
        u = -wn[v0 + e, 1] * (c_x - ax) + wn[v0 + e, 0] * (c_y - ay)
        s = wn[v0 + e, 0] * (c_x - ax) + wn[v0 + e, 1] * (c_y - ay)
        if 0.0 < u < edge_length[v0 + e] and s > 0.0:
            if s < dist:
                dist, nx, ny, feature = s, wn[v0 + e, 0], wn[v0 + e, 1], e
        elif u <= 0.0:  # the vertex v_e (each vertex is the start of one edge)
            d = math.hypot(c_x - ax, c_y - ay)
            if d < dist:
                dist, nx, ny, feature = d, (c_x - ax) / d, (c_y - ay) / d, nv + e
    return nx, ny, dist, feature


@nb.njit(inline="always")
def _inside_face(wv, wn, fvs, fv, f, px, py, pz):
    """Whether the point p [m] of face f's plane lies inside the face (CCW from outside)."""
    ring0 = fvs[f]
    m = fvs[f + 1] - ring0
    for k in range(m):
        a = fv[ring0 + k]
        b = fv[ring0 + (k + 1 if k + 1 < m else 0)]
        if _edge_coordinate(wv, a, b, px, py, pz, wn[f, 0], wn[f, 1], wn[f, 2], 1.0)[0] < 0.0:
            return False
    return True


@nb.njit(cache=True)
def _sphere_polyhedron(cx, cy, cz, wv, wn, vertex_start, face_start, fvs, fv, edge_start,
                       edge_vertex, b, max_faces, max_edges):
    """(n, distance [m] from the sphere's centre c to polyhedron b along n, feature): its
    closest feature (module doc); feature: face f, max_faces + edge e, or max_faces +
    max_edges + vertex k (all local to b)."""
    f0 = face_start[b]
    best_s = -math.inf
    best_f = f0
    for f in range(f0, face_start[b + 1]):
        a = fv[fvs[f]]
        s = wn[f, 0] * (cx - wv[a, 0]) + wn[f, 1] * (cy - wv[a, 1]) + wn[f, 2] * (cz - wv[a, 2])
        if s > best_s:
            best_s = s
            best_f = f
    if best_s <= 0.0:  # the centre is inside: the face of largest separation
        return (wn[best_f, 0], wn[best_f, 1], wn[best_f, 2]), best_s, best_f - f0
    # the closest point lies inside a face (then P lies beyond that face's plane, which is
    # the least distance), inside an edge or at a vertex
    for f in range(f0, face_start[b + 1]):
        a = fv[fvs[f]]
        s = wn[f, 0] * (cx - wv[a, 0]) + wn[f, 1] * (cy - wv[a, 1]) + wn[f, 2] * (cz - wv[a, 2])
        if s > 0.0 and _inside_face(wv, wn, fvs, fv, f, cx - s * wn[f, 0], cy - s * wn[f, 1],
                                    cz - s * wn[f, 2]):
            return (wn[f, 0], wn[f, 1], wn[f, 2]), s, f - f0
    dist = math.inf
    px = py = pz = 0.0
    feature = 0
    for e in range(edge_start[b], edge_start[b + 1]):
        a = edge_vertex[e, 0]
        ex = wv[edge_vertex[e, 1], 0] - wv[a, 0]
        ey = wv[edge_vertex[e, 1], 1] - wv[a, 1]
        ez = wv[edge_vertex[e, 1], 2] - wv[a, 2]
        u = (ex * (cx - wv[a, 0]) + ey * (cy - wv[a, 1]) + ez * (cz - wv[a, 2])) / (
            ex * ex + ey * ey + ez * ez)
        if 0.0 < u < 1.0:
            x = wv[a, 0] + u * ex
            y = wv[a, 1] + u * ey
            z = wv[a, 2] + u * ez
            d = math.sqrt((cx - x) ** 2 + (cy - y) ** 2 + (cz - z) ** 2)
            if d < dist:
                dist, px, py, pz, feature = d, x, y, z, max_faces + e - edge_start[b]
    for k in range(vertex_start[b], vertex_start[b + 1]):
        d = math.sqrt((cx - wv[k, 0]) ** 2 + (cy - wv[k, 1]) ** 2 + (cz - wv[k, 2]) ** 2)
        if d < dist:
            dist, px, py, pz = d, wv[k, 0], wv[k, 1], wv[k, 2]
            feature = max_faces + max_edges + k - vertex_start[b]
    return ((cx - px) / dist, (cy - py) / dist, (cz - pz) / dist), dist, feature


@nb.njit(cache=True)
def _write_round(candidate, antagonist, key, law, point, frame, gap, area, c, cand, ant, k,
                 law_index, px, py, pz, nx, ny, nz, g, curvature, pair_alert, dim):
    """Row c of the contact arrays: point p [m] on the round candidate, normal n, gap g [m],
    and the area within alert of a surface of curvature radius `curvature` [m] (module doc).
    In 3D the frame's t is the world axis least along n made normal to n (a fixed choice:
    the same n gives the same frame from step to step)."""
    if dim == 2:
        _write_2d(candidate, antagonist, key, law, point, frame, gap, c, cand, ant, k,
                  law_index, px, py, nx, ny, g)
        area[c] = 2.0 * math.sqrt(2.0 * curvature * (pair_alert - g))
        return
    if abs(nx) <= abs(ny) and abs(nx) <= abs(nz):
        tx, ty, tz = 1.0 - nx * nx, -nx * ny, -nx * nz
    elif abs(ny) <= abs(nz):
        tx, ty, tz = -ny * nx, 1.0 - ny * ny, -ny * nz
    else:
        tx, ty, tz = -nz * nx, -nz * ny, 1.0 - nz * nz
    norm = math.sqrt(tx * tx + ty * ty + tz * tz)
    _write_3d(candidate, antagonist, key, law, point, frame, gap, c, cand, ant, k, law_index,
              px, py, pz, tx / norm, ty / norm, tz / norm, nx, ny, nz, g)
    area[c] = math.pi * 2.0 * curvature * (pair_alert - g)


@nb.njit(cache=True)
def _write_circle(candidate, antagonist, key, law, point, frame, gap, area, c, cand, ant, k,
                  law_index, cx, cy, cz, sx, sy, sz, r, r_other, pair_alert, curvature, dim):
    """Write the contact of the circle (sphere) of radius r [m] centred at c (on body cand)
    with the point s [m] of body ant, which is round of radius r_other [m] about s; returns
    the next row. Normal from s to c; concentric: along y (3D: z)."""
    dx = cx - sx
    dy = cy - sy
    dz = cz - sz
    d = math.hypot(dx, dy) if dim == 2 else math.sqrt(dx * dx + dy * dy + dz * dz)
    g = d - r - r_other
    if g > pair_alert:
        return c
    if d > 0.0:
        nx, ny, nz = dx / d, dy / d, dz / d
    else:
        nx, ny, nz = (0.0, 1.0, 0.0) if dim == 2 else (0.0, 0.0, 1.0)
    _write_round(candidate, antagonist, key, law, point, frame, gap, area, c, cand, ant, k,
                 law_index, cx - r * nx, cy - r * ny, cz - r * nz, nx, ny, nz, g, curvature,
                 pair_alert, dim)
    return c + 1


@nb.njit(cache=True)
def _capsule_pair(q, wv, wn, edge_length, vertex_start, face_start, fvs, fv, edge_start,
                  edge_vertex, shape, round_radius, i, j, pair_alert, max_faces, max_edges, k0,
                  law_index, c, candidate, antagonist, key, law, point, frame, gap, area):
    """Write the contacts of a pair with a capsule (module doc) from row c on, keys k0 +
    feature in increasing order; returns the next row."""
    dim = wv.shape[1]
    cap, other = (i, j) if shape[i] == _CAPSULE else (j, i)
    r = round_radius[cap]
    seg = _segment(q, wv, edge_length, vertex_start, shape, round_radius, cap)
    v0 = vertex_start[other]
    nv = vertex_start[other + 1] - v0
    if shape[other] == _POLYGON and dim == 2:
        # the two end circles as discs (features 0 .. 4 nv), then the polygon's vertices
        # against the segment between them (4 nv + vertex)
        for end in range(2):
            ex, ey = (seg[0], seg[1]) if end == 0 else (seg[3], seg[4])
            nx, ny, dist, feature = _disc_polygon(ex, ey, wv, wn, edge_length, v0, nv)
            g = dist - r
            if g <= pair_alert:
                _write_round(candidate, antagonist, key, law, point, frame, gap, area, c, cap,
                             other, k0 + 2 * nv * end + feature, law_index, ex - r * nx,
                             ey - r * ny, 0.0, nx, ny, 0.0, g, r if feature < nv else 0.0,
                             pair_alert, dim)
                c += 1
        for v in range(nv):
            sx, sy, sz, u = _closest_on_segment(wv[v0 + v, 0], wv[v0 + v, 1], 0.0, seg)
            if 0.0 < u < 1.0:
                c = _write_circle(candidate, antagonist, key, law, point, frame, gap, area, c,
                                  cap, other, k0 + 4 * nv + v, law_index, sx, sy, sz,
                                  wv[v0 + v, 0], wv[v0 + v, 1], 0.0, r, 0.0, pair_alert, 0.0,
                                  dim)
        return c
    if shape[other] == _POLYGON:
        # the two end spheres (features 0 .. 2 m, m = the sphere's features of this
        # polyhedron), then its edges where they pass the segment between its ends (2 m +
        # edge) and its vertices against it (2 m + edges + vertex)
        m = max_faces + max_edges + nv
        e0 = edge_start[other]
        ne = edge_start[other + 1] - e0
        for end in range(2):
            ex, ey, ez = seg[3 * end], seg[3 * end + 1], seg[3 * end + 2]
            n, dist, feature = _sphere_polyhedron(ex, ey, ez, wv, wn, vertex_start, face_start,
                                                  fvs, fv, edge_start, edge_vertex, other,
                                                  max_faces, max_edges)
            g = dist - r
            if g <= pair_alert:
                _write_round(candidate, antagonist, key, law, point, frame, gap, area, c, cap,
                             other, k0 + m * end + feature, law_index, ex - r * n[0],
                             ey - r * n[1], ez - r * n[2], n[0], n[1], n[2], g,
                             r if feature < max_faces else 0.0, pair_alert, dim)
                c += 1
        for e in range(ne):
            a = edge_vertex[e0 + e, 0]
            b = edge_vertex[e0 + e, 1]
            s, u = _closest_of_segments((wv[a, 0], wv[a, 1], wv[a, 2], wv[b, 0], wv[b, 1],
                                         wv[b, 2]), seg)
            if 0.0 < s < 1.0 and 0.0 < u < 1.0:
                c = _write_circle(candidate, antagonist, key, law, point, frame, gap, area, c,
                                  cap, other, k0 + 2 * m + e, law_index,
                                  seg[0] + u * (seg[3] - seg[0]), seg[1] + u * (seg[4] - seg[1]),
                                  seg[2] + u * (seg[5] - seg[2]),
                                  wv[a, 0] + s * (wv[b, 0] - wv[a, 0]),
                                  wv[a, 1] + s * (wv[b, 1] - wv[a, 1]),
                                  wv[a, 2] + s * (wv[b, 2] - wv[a, 2]), r, 0.0, pair_alert,
                                  0.0, dim)
        for v in range(nv):
            sx, sy, sz, u = _closest_on_segment(wv[v0 + v, 0], wv[v0 + v, 1], wv[v0 + v, 2],
                                                seg)
            if 0.0 < u < 1.0:
                c = _write_circle(candidate, antagonist, key, law, point, frame, gap, area, c,
                                  cap, other, k0 + 2 * m + ne + v, law_index, sx, sy, sz,
                                  wv[v0 + v, 0], wv[v0 + v, 1], wv[v0 + v, 2], r, 0.0,
                                  pair_alert, 0.0, dim)
        return c
    # a disc (sphere) or capsule: the ends of the first body's segment against the other's
    # segment, then the other's ends against the first's segment where it is closest inside
    # it (the end-to-end pairs are the first loop's); in 3D, then the closest points of two
    # segments that pass each other inside both (key 4)
    first, second = (i, j)
    a = _segment(q, wv, edge_length, vertex_start, shape, round_radius, first)
    b = _segment(q, wv, edge_length, vertex_start, shape, round_radius, second)
    for end in range(4):
        body, ant, own, seg = (first, second, a, b) if end < 2 else (second, first, b, a)
        ex, ey, ez = (own[0], own[1], own[2]) if end % 2 == 0 else (own[3], own[4], own[5])
        if end % 2 == 1 and shape[body] != _CAPSULE:
            continue  # a disc has one centre
        sx, sy, sz, u = _closest_on_segment(ex, ey, ez, seg)
        if end >= 2 and not (0.0 < u < 1.0):
            continue
        r = round_radius[body]
        r_ant = round_radius[ant]
        # an end on the other's straight side curves as itself, on its end as both together
        curvature = r if 0.0 < u < 1.0 else r * r_ant / (r + r_ant)
        c = _write_circle(candidate, antagonist, key, law, point, frame, gap, area, c, body,
                          ant, k0 + end, law_index, ex, ey, ez, sx, sy, sz, r, r_ant,
                          pair_alert, curvature, dim)
    if dim == 3 and shape[first] == _CAPSULE and shape[second] == _CAPSULE:
        s, u = _closest_of_segments(a, b)
        if 0.0 < s < 1.0 and 0.0 < u < 1.0:
            ri = round_radius[first]
            rj = round_radius[second]
            # two cylinders crossing at right angles: g grows as x^2 / (2 r_j) + y^2 / (2 r_i),
            # the ellipse of area pi 2 sqrt(r_i r_j) (a - g)
            c = _write_circle(candidate, antagonist, key, law, point, frame, gap, area, c,
                              first, second, k0 + 4, law_index, a[0] + s * (a[3] - a[0]),
                              a[1] + s * (a[4] - a[1]), a[2] + s * (a[5] - a[2]),
                              b[0] + u * (b[3] - b[0]), b[1] + u * (b[4] - b[1]),
                              b[2] + u * (b[5] - b[2]), ri, rj, pair_alert, math.sqrt(ri * rj),
                              dim)
    return c


@nb.njit(cache=True)
def round_contacts(pairs, npairs, q, wv, wn, edge_length, vertex_start, face_start, fvs, fv,
                   edge_start, edge_vertex, shape, round_radius, body_group, group_law, alert,
                   law_alert, body_alert, max_faces, max_edges, key_base, features, first,
                   candidate, antagonist, key, law, point, frame, gap, area):
    """Contacts of the first npairs pairs (sorted by (i, j)), each with a disc or sphere or
    capsule (module doc), written from row `first` on; returns the new count.

    wv [m], wn: world vertices and outward normals, of the edges starting at them (2D) or of
    the faces (3D); q: configuration; edge_length [m] (2D), and in 3D the face and edge arrays
    and their largest counts per body (saxum.model.Model); shape, round_radius [m]: Model's;
    alert, law_alert, body_alert [m]: as polygon_contacts; features: keys per pair."""
    dim = wv.shape[1]
    nbody = q.shape[0]
    c = first
    for p in range(npairs):
        i = pairs[p, 0]
        j = pairs[p, 1]
        law_index = group_law[body_group[i], body_group[j]]
        pair_alert = alert_of_pair(law_alert, body_alert, law_index, i, j, alert)
        if shape[i] == _CAPSULE or shape[j] == _CAPSULE:
            c = _capsule_pair(q, wv, wn, edge_length, vertex_start, face_start, fvs, fv,
                              edge_start, edge_vertex, shape, round_radius, i, j, pair_alert,
                              max_faces, max_edges, key_base + (i * nbody + j) * features,
                              law_index, c, candidate, antagonist, key, law, point, frame, gap,
                              area)
            continue
        cand, ant = (i, j) if shape[i] == _ROUND else (j, i)
        r = round_radius[cand]
        feature = 0
        if shape[ant] == _ROUND:
            n, g, curvature = _pair_of_round(q, round_radius, cand, ant, dim)
        elif dim == 2:
            v0 = vertex_start[ant]
            nx, ny, dist, feature = _disc_polygon(q[cand, 0], q[cand, 1], wv, wn, edge_length,
                                                  v0, vertex_start[ant + 1] - v0)
            n, g = (nx, ny, 0.0), dist - r
            curvature = r if feature < vertex_start[ant + 1] - v0 else 0.0
        else:
            n, dist, feature = _sphere_polyhedron(q[cand, 0], q[cand, 1], q[cand, 2], wv, wn,
                                                  vertex_start, face_start, fvs, fv,
                                                  edge_start, edge_vertex, ant, max_faces,
                                                  max_edges)
            g = dist - r
            curvature = r if feature < max_faces else 0.0
        if g > pair_alert:
            continue
        nx, ny, nz = n
        cz = q[cand, 2] if dim == 3 else 0.0
        _write_round(candidate, antagonist, key, law, point, frame, gap, area, c, cand, ant,
                     key_base + (i * nbody + j) * features + feature, law_index,
                     q[cand, 0] - r * nx, q[cand, 1] - r * ny, cz - r * nz, nx, ny, nz, g,
                     curvature, pair_alert, dim)
        c += 1
    return c
