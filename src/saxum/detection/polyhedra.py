"""Narrow phase between convex polyhedra: separating axes, reference face, clipped contact points.

For a pair of blocks the separating-axis test runs over three families of axes: the face normals
of either block (separation of a face f: min over the other block's vertices p of
n_f . (p - a_f)) and the cross products of pairs of edges, one of each block, that build a face
of the Minkowski difference (their arcs on the Gauss map cross: D. Gregorius, "The separating
axis test between convex polyhedra", GDC 2013). The largest separation is the common plane of
the two blocks; beyond the alert distance there is no contact.

- Face contact (a face separation is the largest, up to `ref_tol` in favour of faces): the face's
  block becomes the antagonist and carries the frame, n the face's outward normal, t the
  direction of its first edge and s = t x n, so that (t, n, s) is right-handed. The candidate's
  face most opposed to n (the incident face) is clipped by the side planes of the reference face
  (Sutherland-Hodgman); of the clipped polygon's points with gap n . (p - a) below the alert
  distance, the extreme points in 16 directions of the reference face's plane (+-t +-s first,
  then +-t and +-s, then the eight in between) are kept, each once, at most MAX_POINTS: four
  for two rectangles side by side, all eight corners of two squares at 45 degrees, three for a
  triangle (every corner whose exterior angle exceeds 22.5 degrees is kept), so that a joint
  can open and rock about any edge of the contact surface; a vertex against a face gives one
  point and an edge against a face two. Taking the points by direction, rather than by how the
  clipping made them, keeps their identity when a corner of one face crosses an edge of the
  other by round-off, as happens all the time in a wall built flush.
- Contact areas, for laws written in stresses: the area, projected on the reference face, of
  the part of the clipped polygon whose gap is within the alert distance is shared among the
  face contact's points as the median dual of their polygon does: about the mean c of the
  points, taken in the polygon's order, each fan triangle (c, P_k, P_k+1) gives half its area
  to either corner, and the shares are scaled to sum to the area (a quarter each for the four
  corners of a rectangle; equal shares where the points span no area). The areas of a joint
  thus sum to its overlap polygon's area. An edge or a vertex against a face (an incident face
  at an angle theta to it) stands for the part of that face within the alert distance: a strip
  (alert - gap) / tan(theta) wide along the edge, a corner of it for a vertex, small beside the
  faces unless they are nearly flush; an edge-edge contact has zero area.
- Points for laws in stresses (ContactLaw.points = 3): the corners alone are a trapezoid-like
  rule, too stiff in rotation (docs/design-deformable-and-joints.md, sec. 4). A face contact
  of such a law with n >= 3 corners also gets the midpoints of the corners' polygon's edges
  (slot SLOTS + the slot of the edge's first corner in polygon order) and its centre, the
  mean of the corners (slot 2 SLOTS), with the weights of a rule that keeps the corners,
  scaled to sum to the area as above. A quadrilateral: tensor Simpson on its bilinear map
  from [-1, 1]^2 times the map's Jacobian (1/36, 4/36, 16/36 of the area for a rectangle),
  exact for polynomials of degree 2 in the face's plane on any convex quadrilateral
  (the integrand times the bilinear Jacobian stays bicubic). A triangle: the rule 3/60,
  8/60, 27/60 of the area at its corners, edge midpoints and centroid, exact to degree 3
  (A.H. Stroud, "Approximate calculation of multiple integrals", 1971, T2:3-1). More corners:
  a fan of triangles about the centre, each with the rule 1/12 per corner, 1/2 at its outer
  edge's midpoint, 1/3 at the centre, exact for linear stresses (force and moments) only.
- Corners only: where the incident face lies in the reference face's plane (within the
  closed gap) and the two meet only along a line or at a point, the blocks touch edge to edge
  or corner to corner (a stone over a head joint and the next stone of the course below, the
  inside corner of an L wall): there is no contact. No normal is right there: along either
  face it would hold a block that slides past the other (a block bridging a joint would not
  slide at 1.05 times the friction), while the only motion the corner stops, into the corner
  diagonally, is stopped by the blocks' other joints; once the faces overlap, however
  little, the contact is there, with its area.
- Edge-edge contact (an edge pair separates more than any face by more than `ref_tol`): one
  point, the closest point of the candidate's edge to the antagonist's, n along the cross
  product of the edges (pointing from the antagonist to the candidate), t along the
  antagonist's edge.

Contact identity (key): pair, which body is the antagonist, reference and incident features
(faces, or edges numbered after the faces) and the slot (the direction that picked the point),
written in increasing key order for pairs sorted by (i, j), as saxum.contacts needs.
"""

import math

import numba as nb
import numpy as np

from .polygons import _same_sizes, alert_of_pair, copy_rows

__all__ = ["MAX_POINTS", "SLOTS", "polyhedron_contacts", "polyhedron_contacts_parallel"]

MAX_POINTS = 8
"""Contact points of one face-to-face contact, at most."""

# directions of the reference face's plane that pick the kept points, as (t, s) components:
# diagonals first (unique corners of rectangles aligned with the face), then axes, then between
_C = math.cos(math.pi / 8)
_S = math.sin(math.pi / 8)
_DIRECTIONS = np.array([[1.0, 1.0], [1.0, -1.0], [-1.0, -1.0], [-1.0, 1.0],
                        [1.0, 0.0], [0.0, -1.0], [-1.0, 0.0], [0.0, 1.0],
                        [_C, _S], [_S, -_C], [-_C, -_S], [-_S, _C],
                        [_C, -_S], [-_S, -_C], [-_C, _S], [_S, _C]])
SLOTS = len(_DIRECTIONS)
"""Directions that pick contact points, and so the slots of a face contact's keys."""


@nb.njit(inline="always")
def _face_separation(wv, wn, face_start, fvs, fv, vertex_start, body, other, alert, tie):
    """Largest over the faces f of `body` of min over the vertices p of `other` of
    n_f . (p - a_f) [m], to within tie [m]: the first face that reaches it (a face takes over
    only if it separates more by tie), and that face; stops early once a face separates by
    more than alert. Several faces separate equally where blocks meet corner to corner (at
    the inside corner of an L wall): without the tie round-off would pick one or another
    from step to step, and with it the contact's normal and identity."""
    best = -np.inf
    best_f = face_start[body]
    p0 = vertex_start[other]
    p1 = vertex_start[other + 1]
    for f in range(face_start[body], face_start[body + 1]):
        a = fv[fvs[f]]
        nx = wn[f, 0]
        ny = wn[f, 1]
        nz = wn[f, 2]
        off = nx * wv[a, 0] + ny * wv[a, 1] + nz * wv[a, 2]
        s = np.inf
        for k in range(p0, p1):
            s = min(s, nx * wv[k, 0] + ny * wv[k, 1] + nz * wv[k, 2] - off)
        if s > best + tie:
            best = s
            best_f = f
            if s > alert:
                break
    return best, best_f


@nb.njit(inline="always")
def _cross(ax, ay, az, bx, by, bz):
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@nb.njit(inline="always")
def _edge_separation(wv, wn, edge_start, edge_vertex, edge_face, q, i, j, alert, tie):
    """Largest separation along the cross products of edge pairs (one of i, one of j) that
    build a face of the Minkowski difference of i and -j, to within tie [m] (the first pair
    that reaches it, as _face_separation); returns (separation, edge of i, edge of j, axis
    x, y, z) with the axis pointing from i to j. -inf when no pair qualifies."""
    best = -np.inf
    best_a = -1
    best_b = -1
    bx_ = by_ = bz_ = 0.0
    for ea in range(edge_start[i], edge_start[i + 1]):
        na = edge_face[ea, 0]
        nb_ = edge_face[ea, 1]
        ax, ay, az = wn[na, 0], wn[na, 1], wn[na, 2]
        bx, by, bz = wn[nb_, 0], wn[nb_, 1], wn[nb_, 2]
        bax, bay, baz = _cross(bx, by, bz, ax, ay, az)
        pa0 = edge_vertex[ea, 0]
        pa1 = edge_vertex[ea, 1]
        dax = wv[pa1, 0] - wv[pa0, 0]
        day = wv[pa1, 1] - wv[pa0, 1]
        daz = wv[pa1, 2] - wv[pa0, 2]
        for eb in range(edge_start[j], edge_start[j + 1]):
            # the Gauss map of -j: normals negated
            nc = edge_face[eb, 0]
            nd = edge_face[eb, 1]
            cx, cy, cz = -wn[nc, 0], -wn[nc, 1], -wn[nc, 2]
            dx, dy, dz = -wn[nd, 0], -wn[nd, 1], -wn[nd, 2]
            cba = cx * bax + cy * bay + cz * baz
            dba = dx * bax + dy * bay + dz * baz
            if cba * dba >= 0.0:
                continue
            dcx, dcy, dcz = _cross(dx, dy, dz, cx, cy, cz)
            adc = ax * dcx + ay * dcy + az * dcz
            bdc = bx * dcx + by * dcy + bz * dcz
            if adc * bdc >= 0.0 or cba * bdc <= 0.0:
                continue
            pb0 = edge_vertex[eb, 0]
            pb1 = edge_vertex[eb, 1]
            ux, uy, uz = _cross(dax, day, daz, wv[pb1, 0] - wv[pb0, 0], wv[pb1, 1] - wv[pb0, 1],
                                wv[pb1, 2] - wv[pb0, 2])
            norm = math.sqrt(ux * ux + uy * uy + uz * uz)
            len_a = math.sqrt(dax * dax + day * day + daz * daz)
            if norm <= 1e-9 * len_a * len_a:
                continue  # parallel edges: covered by the face axes
            ux /= norm
            uy /= norm
            uz /= norm
            # orient from i to j: away from i's centre of mass
            if (ux * (wv[pa0, 0] - q[i, 0]) + uy * (wv[pa0, 1] - q[i, 1])
                    + uz * (wv[pa0, 2] - q[i, 2])) < 0.0:
                ux, uy, uz = -ux, -uy, -uz
            s = (ux * (wv[pb0, 0] - wv[pa0, 0]) + uy * (wv[pb0, 1] - wv[pa0, 1])
                 + uz * (wv[pb0, 2] - wv[pa0, 2]))
            if s > best + tie:
                best = s
                best_a = ea
                best_b = eb
                bx_, by_, bz_ = ux, uy, uz
                if s > alert:
                    return best, best_a, best_b, bx_, by_, bz_
    return best, best_a, best_b, bx_, by_, bz_


@nb.njit(cache=True)
def polyhedron_contacts(
    pairs, npairs, q, wv, wn, vertex_start, face_start, fvs, fv, edge_start, edge_vertex,
    edge_face, body_group, group_law, law_points, slots, alert, law_alert, body_alert, ref_tol,
    max_faces, max_edges, max_face_vertices, candidate, antagonist, key, law, point, frame, gap,
    area,
):
    """Contacts of the first npairs pairs of polyhedra (module doc), world vertices wv [m] and
    outward unit face normals wn; q the configuration (centres of mass [m]).

    alert: the detector's alert distance [m] (its closed gap is 1e-6 alert); law_alert [m]: the
    alert distance per law (ContactLaw.alert, or alert), which a pair of that law uses, or NaN:
    min(body_alert[i], body_alert[j]) [m] for the pair (i, j) (DetectionSettings.per_pair).
    ref_tol [m]: a face of the first body of a pair stays the
    reference unless the second body's best face separates more by ref_tol, and faces are
    preferred to edge pairs unless these separate more by ref_tol (biases that keep contact
    identities stable across steps). law_points: points of a face contact per law
    (Model.law_points: 2, or 3 for the rule exact for linear stresses); slots: keys per pair
    of features, SLOTS, or 2 SLOTS + 1 if a law has 3 points. Output arrays need room for
    MAX_POINTS * npairs contacts, 2 MAX_POINTS + 1 per pair if a law has 3 points.
    Returns the number of contacts written, in increasing key order for pairs sorted by (i, j).
    area [m^2]: the share of the contact polygon each point stands for (module doc).
    """
    nbody = vertex_start.shape[0] - 1
    tie = 1e-6 * alert  # the detector's closed_gap: separations closer than this are equal
    features = max_faces + max_edges
    size = 2 * max_face_vertices + 2
    px = np.empty((2, size))
    py = np.empty((2, size))
    pz = np.empty((2, size))
    dist = np.empty(size)
    pu = np.empty(size)
    pw = np.empty(size)
    picked = np.empty(MAX_POINTS, dtype=np.int64)
    order = np.empty(MAX_POINTS, dtype=np.int64)
    weight = np.empty(2 * MAX_POINTS + 1)
    count = 0
    for p in range(npairs):
        i = pairs[p, 0]
        j = pairs[p, 1]
        law_index = group_law[body_group[i], body_group[j]]
        pair_alert = alert_of_pair(law_alert, body_alert, law_index, i, j, alert)
        s_i, f_i = _face_separation(wv, wn, face_start, fvs, fv, vertex_start, i, j,
                                    pair_alert, tie)
        if s_i > pair_alert:
            continue
        s_j, f_j = _face_separation(wv, wn, face_start, fvs, fv, vertex_start, j, i,
                                    pair_alert, tie)
        if s_j > pair_alert:
            continue
        s_e, e_i, e_j, ux, uy, uz = _edge_separation(wv, wn, edge_start, edge_vertex, edge_face,
                                                     q, i, j, pair_alert, tie)
        if s_e > pair_alert:
            continue
        pair_key = (i * nbody + j) * 2
        if s_e > max(s_i, s_j) + ref_tol:
            # edge-edge: i is the antagonist, the point on j's edge
            a0 = edge_vertex[e_i, 0]
            a1 = edge_vertex[e_i, 1]
            b0 = edge_vertex[e_j, 0]
            b1 = edge_vertex[e_j, 1]
            cx, cy, cz, ox, oy, oz = _closest_points(wv, a0, a1, b0, b1)
            tx = wv[a1, 0] - wv[a0, 0]
            ty = wv[a1, 1] - wv[a0, 1]
            tz = wv[a1, 2] - wv[a0, 2]
            norm = math.sqrt(tx * tx + ty * ty + tz * tz)
            ref = max_faces + e_i - edge_start[i]
            inc = max_faces + e_j - edge_start[j]
            _write(candidate, antagonist, key, law, point, frame, gap, count, j, i,
                   ((pair_key * features + ref) * features + inc) * slots, law_index,
                   cx, cy, cz, tx / norm, ty / norm, tz / norm, ux, uy, uz,
                   ux * (cx - ox) + uy * (cy - oy) + uz * (cz - oz))
            area[count] = 0.0
            count += 1
            continue
        flip = s_j > s_i + ref_tol
        if flip:
            ant, cand, ref_face = j, i, f_j
        else:
            ant, cand, ref_face = i, j, f_i
        nx = wn[ref_face, 0]
        ny = wn[ref_face, 1]
        nz = wn[ref_face, 2]
        # incident face: the candidate's face most opposed to n
        inc_face = face_start[cand]
        most = np.inf
        for f in range(face_start[cand], face_start[cand + 1]):
            d = wn[f, 0] * nx + wn[f, 1] * ny + wn[f, 2] * nz
            if d < most:
                most = d
                inc_face = f
        m = 0
        for k in range(fvs[inc_face], fvs[inc_face + 1]):
            px[0, m] = wv[fv[k], 0]
            py[0, m] = wv[fv[k], 1]
            pz[0, m] = wv[fv[k], 2]
            m += 1
        r0 = fvs[ref_face]
        nr = fvs[ref_face + 1] - r0
        a = fv[r0]
        ax = wv[a, 0]
        ay = wv[a, 1]
        az = wv[a, 2]
        tx = wv[fv[r0 + 1], 0] - ax
        ty = wv[fv[r0 + 1], 1] - ay
        tz = wv[fv[r0 + 1], 2] - az
        norm = math.sqrt(tx * tx + ty * ty + tz * tz)
        tx /= norm
        ty /= norm
        tz /= norm
        src = 0
        for k in range(nr):
            # side plane of the reference edge k: outward normal (edge x n), through its start
            e0 = fv[r0 + k]
            e1 = fv[r0 + (k + 1) % nr]
            ex = wv[e1, 0] - wv[e0, 0]
            ey = wv[e1, 1] - wv[e0, 1]
            ez = wv[e1, 2] - wv[e0, 2]
            sx, sy, sz = _cross(ex, ey, ez, nx, ny, nz)
            length = math.sqrt(sx * sx + sy * sy + sz * sz)
            sx /= length
            sy /= length
            sz /= length
            off = sx * wv[e0, 0] + sy * wv[e0, 1] + sz * wv[e0, 2]
            m = _clip(px, py, pz, dist, src, m, sx, sy, sz, off, 1e-9 * length)
            src = 1 - src
            if m == 0:
                break
        if m == 0:
            continue
        for k in range(m):
            dist[k] = nx * (px[src, k] - ax) + ny * (py[src, k] - ay) + nz * (pz[src, k] - az)
        sx, sy, sz = _cross(tx, ty, tz, nx, ny, nz)  # s = t x n, as _write's frame
        face_area = _alert_area(px, py, pz, dist, src, m, ax, ay, az, tx, ty, tz, sx, sy, sz,
                                pair_alert)
        # keep the points within the alert distance
        kept = 0
        for k in range(m):
            g = dist[k]
            if g <= pair_alert:
                px[src, kept] = px[src, k]
                py[src, kept] = py[src, k]
                pz[src, kept] = pz[src, k]
                dist[kept] = g
                kept += 1
        if kept == 0 or _corner_only(wv, fvs, fv, inc_face, nx, ny, nz, ax, ay, az, px, py,
                                     pz, src, kept, tie):
            continue
        for k in range(kept):  # coordinates in the face's plane, for the picks and the areas
            pu[k] = tx * px[src, k] + ty * py[src, k] + tz * pz[src, k]
            pw[k] = sx * px[src, k] + sy * py[src, k] + sz * pz[src, k]
        base = ((pair_key + flip) * features + ref_face - face_start[ant]) * features + (
            inc_face - face_start[cand])
        first = count
        for slot in range(SLOTS):
            if count - first == MAX_POINTS:
                break
            dt = _DIRECTIONS[slot, 0]
            ds = _DIRECTIONS[slot, 1]
            best = -np.inf
            pick = 0
            for k in range(kept):
                h = dt * pu[k] + ds * pw[k]
                if h > best:
                    best = h
                    pick = k
            # Each point once, and past the diagonals only a point that extends the support
            # appreciably in this direction: along a side that is straight up to round-off,
            # the extreme point is noise (anywhere on the side), not a corner.
            reach = -np.inf
            fresh = True
            for c in range(first, count):
                if (abs(point[c, 0] - px[src, pick]) + abs(point[c, 1] - py[src, pick])
                        + abs(point[c, 2] - pz[src, pick])) <= 1e-3 * alert:
                    fresh = False
                    break
                reach = max(reach, dt * pu[picked[c - first]] + ds * pw[picked[c - first]])
            if slot >= 4 and best <= reach + 1e-3 * alert * math.hypot(dt, ds):
                fresh = False
            if fresh:
                _write(candidate, antagonist, key, law, point, frame, gap, count, cand, ant,
                       base * slots + slot, law_index, px[src, pick], py[src, pick],
                       pz[src, pick], tx, ty, tz, nx, ny, nz, dist[pick])
                picked[count - first] = pick
                count += 1
        n = count - first
        if n >= 3 and law_index >= 0 and law_points[law_index] >= 3 and _linear_rule(
                picked, order, n, pu, pw, weight) > 0.0:
            count = _write_rule_points(face_area, picked, order, n, weight, px, py, pz, dist,
                                       src, candidate, antagonist, key, law, point, frame, gap,
                                       area, first, base * slots, cand, ant, law_index, tx, ty,
                                       tz, nx, ny, nz)
        else:
            _share_area(face_area, picked, order, n, pu, pw, area, first)
    return count


PAIR_BLOCK_3D = 512
"""Pairs per block of polyhedron_contacts_parallel (a pair of polyhedra costs several times
a pair of polygons)."""


@nb.njit(parallel=True, cache=True)
def polyhedron_contacts_parallel(
    pairs, npairs, q, wv, wn, vertex_start, face_start, fvs, fv, edge_start, edge_vertex,
    edge_face, body_group, group_law, law_points, slots, alert, law_alert, body_alert, ref_tol,
    max_faces, max_edges, max_face_vertices, room, start, in_place, candidate, antagonist, key,
    law, point, frame, gap, area, s_candidate, s_antagonist, s_key, s_law, s_point, s_frame,
    s_gap, s_area,
):
    """polyhedron_contacts on numba's threads, the same contacts in the same order bit for bit,
    as saxum.detection.polygons.polygon_contacts_parallel: blocks of PAIR_BLOCK_3D pairs in
    parallel; start (int64, one more than the blocks): where each block's contacts began in
    the last call; in_place: try writing each block's contacts straight into the output
    arrays from there (it holds where every block finds as many contacts as then: bodies at
    rest); otherwise, or where one does not, each block's contacts go into its own rows of
    the scratch arrays s_* (room per pair, polyhedron_contacts' MAX_POINTS or
    2 MAX_POINTS + 1: room * its first pair on), then copied in the blocks' order. Returns
    (contacts, whether every block found as many contacts as in start), start updated."""
    blocks = -(-npairs // PAIR_BLOCK_3D)
    found = np.zeros(blocks, dtype=np.int64)
    if in_place:
        for k in nb.prange(blocks):
            lo = k * PAIR_BLOCK_3D
            hi = min(npairs, lo + PAIR_BLOCK_3D)
            r = start[k]
            found[k] = polyhedron_contacts(
                pairs[lo:hi], hi - lo, q, wv, wn, vertex_start, face_start, fvs, fv,
                edge_start, edge_vertex, edge_face, body_group, group_law, law_points, slots,
                alert, law_alert, body_alert, ref_tol, max_faces, max_edges,
                max_face_vertices, candidate[r:], antagonist[r:], key[r:], law[r:],
                point[r:], frame[r:], gap[r:], area[r:])
        if _same_sizes(found, start):
            return start[blocks], True
    for k in nb.prange(blocks):
        lo = k * PAIR_BLOCK_3D
        hi = min(npairs, lo + PAIR_BLOCK_3D)
        r = room * lo
        found[k] = polyhedron_contacts(
            pairs[lo:hi], hi - lo, q, wv, wn, vertex_start, face_start, fvs, fv, edge_start,
            edge_vertex, edge_face, body_group, group_law, law_points, slots, alert, law_alert,
            body_alert, ref_tol, max_faces, max_edges, max_face_vertices, s_candidate[r:],
            s_antagonist[r:], s_key[r:], s_law[r:], s_point[r:], s_frame[r:], s_gap[r:],
            s_area[r:])
    same = _same_sizes(found, start)
    start[0] = 0
    for k in range(blocks):
        start[k + 1] = start[k] + found[k]
    for k in nb.prange(blocks):
        copy_rows(room * k * PAIR_BLOCK_3D, start[k], found[k], s_candidate, s_antagonist,
                  s_key, s_law, s_point, s_frame, s_gap, s_area, candidate, antagonist, key,
                  law, point, frame, gap, area)
    return start[blocks], same


@nb.njit(inline="always")
def _polygon_order(picked, order, n):
    """order[k]: the contact point (0 .. n-1) that comes k-th in the clipped polygon, whose
    vertex picked[r] contact point r is."""
    for r in range(n):
        # insertion sort of at most MAX_POINTS rows by their place in the polygon
        k = r
        while k > 0 and picked[order[k - 1]] > picked[r]:
            order[k] = order[k - 1]
            k -= 1
        order[k] = r


# Quadrilaterals: (xi, eta) of the corners, in polygon order, and of the midpoints of the
# edges from each corner to the next, in the bilinear map from [-1, 1]^2.
_QUAD_CORNER = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
_QUAD_MIDPOINT = np.array([[0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]])


@nb.njit(inline="always")
def _quad_jacobian(u, w, xi, eta):
    """Jacobian [m^2] of the bilinear map of [-1, 1]^2 onto the quadrilateral with corners
    (u[k], w[k]) [m], k = 0..3 in polygon order, at (xi, eta)."""
    du_xi = 0.25 * ((u[1] - u[0]) * (1.0 - eta) + (u[2] - u[3]) * (1.0 + eta))
    dw_xi = 0.25 * ((w[1] - w[0]) * (1.0 - eta) + (w[2] - w[3]) * (1.0 + eta))
    du_eta = 0.25 * ((u[3] - u[0]) * (1.0 - xi) + (u[2] - u[1]) * (1.0 + xi))
    dw_eta = 0.25 * ((w[3] - w[0]) * (1.0 - xi) + (w[2] - w[1]) * (1.0 + xi))
    return du_xi * dw_eta - dw_xi * du_eta


@nb.njit(inline="always")
def _linear_rule(picked, order, n, pu, pw, weight):
    """Weights [m^2] of a rule over the polygon of the n >= 3 contact points (point r: vertex
    picked[r], coordinates pu, pw [m]) that keeps the corners (module doc): weight[r] at
    corner r, weight[n + r] at the midpoint of the edge from corner r to the next in the
    polygon, weight[2 n] at the centre (the mean of the corners). Fills order
    (_polygon_order); returns the polygon's area [m^2] (0: degenerate, no rule)."""
    _polygon_order(picked, order, n)
    for r in range(2 * n + 1):
        weight[r] = 0.0
    cu = cw = 0.0
    for r in range(n):
        cu += pu[picked[r]] / n
        cw += pw[picked[r]] / n
    if n == 4:
        u = np.empty(4)
        w = np.empty(4)
        for k in range(4):
            u[k] = pu[picked[order[k]]]
            w[k] = pw[picked[order[k]]]
        sign = 1.0 if _quad_jacobian(u, w, 0.0, 0.0) >= 0.0 else -1.0
        for k in range(4):
            weight[order[k]] = sign / 9.0 * _quad_jacobian(u, w, _QUAD_CORNER[k, 0],
                                                          _QUAD_CORNER[k, 1])
            weight[4 + order[k]] = sign * 4.0 / 9.0 * _quad_jacobian(
                u, w, _QUAD_MIDPOINT[k, 0], _QUAD_MIDPOINT[k, 1])
        weight[8] = sign * 16.0 / 9.0 * _quad_jacobian(u, w, 0.0, 0.0)
    else:
        for k in range(n):
            r = order[k]
            r1 = order[(k + 1) % n]
            a = picked[r]
            b = picked[r1]
            fan = 0.5 * abs((pu[a] - cu) * (pw[b] - cw) - (pw[a] - cw) * (pu[b] - cu))
            if n == 3:  # one triangle, whose centroid is the centre: 3/60, 8/60, 27/60
                weight[r] += 3.0 * fan / 20.0
                weight[n + r] += 8.0 * fan / 20.0
                weight[2 * n] += 9.0 * fan / 20.0
            else:  # a fan of triangles about the centre: 1/12 per corner, 1/2, 1/3
                weight[r] += fan / 12.0
                weight[r1] += fan / 12.0
                weight[n + r] += fan / 2.0
                weight[2 * n] += fan / 3.0
    total = 0.0
    for r in range(2 * n + 1):
        total += weight[r]
    return total


@nb.njit(inline="always")
def _write_rule_points(face_area, picked, order, n, weight, px, py, pz, dist, src, candidate,
                       antagonist, key, law, point, frame, gap, area, first, key0, cand, ant,
                       law_index, tx, ty, tz, nx, ny, nz):
    """Write the edge midpoints and the centre of the rule `weight` (_linear_rule) after the
    n corners first:first + n of a face contact, with keys key0 + SLOTS + the slot of the
    edge's first corner and key0 + 2 SLOTS (in increasing order: the corners were written
    in increasing slot order), and the areas: the weights scaled to sum to face_area [m^2].
    Returns the new contact count."""
    total = 0.0
    for r in range(2 * n + 1):
        total += weight[r]
    scale = face_area / total
    for r in range(n):
        area[first + r] = scale * weight[r]
    count = first + n
    position = np.empty(MAX_POINTS, dtype=np.int64)
    for k in range(n):
        position[order[k]] = k
    cx = cy = cz = cg = 0.0
    for r in range(n):
        a = picked[r]
        b = picked[order[(position[r] + 1) % n]]
        _write(candidate, antagonist, key, law, point, frame, gap, count, cand, ant,
               key[first + r] + SLOTS, law_index, 0.5 * (px[src, a] + px[src, b]),
               0.5 * (py[src, a] + py[src, b]), 0.5 * (pz[src, a] + pz[src, b]), tx, ty, tz,
               nx, ny, nz, 0.5 * (dist[a] + dist[b]))
        area[count] = scale * weight[n + r]
        count += 1
        cx += px[src, a] / n
        cy += py[src, a] / n
        cz += pz[src, a] / n
        cg += dist[a] / n
    _write(candidate, antagonist, key, law, point, frame, gap, count, cand, ant,
           key0 + 2 * SLOTS, law_index, cx, cy, cz, tx, ty, tz, nx, ny, nz, cg)
    area[count] = scale * weight[2 * n]
    return count + 1


@nb.njit(inline="always")
def _alert_area(px, py, pz, gap, src, m, ax, ay, az, tx, ty, tz, sx, sy, sz, alert):
    """Area [m^2], projected on the reference face's plane (axes t, s through a), of the part
    of the convex polygon px/py/pz[src, :m] whose gap (gap[:m] [m]) is within alert [m]: the
    shoelace formula over the polygon clipped by that half-space, its vertices taken
    in turn (each kept vertex, then the crossing of the edge that leaves it, if any)."""
    twice = 0.0
    u_first = w_first = u_prev = w_prev = 0.0
    emitted = 0
    for k in range(m):
        k1 = (k + 1) % m
        g0 = gap[k]
        g1 = gap[k1]
        for crossing in range(2):
            if crossing == 0 and g0 > alert:
                continue
            if crossing == 1 and (g0 <= alert) == (g1 <= alert):
                continue
            f = (alert - g0) / (g1 - g0) if crossing == 1 else 0.0
            x = px[src, k] + f * (px[src, k1] - px[src, k]) - ax
            y = py[src, k] + f * (py[src, k1] - py[src, k]) - ay
            z = pz[src, k] + f * (pz[src, k1] - pz[src, k]) - az
            u = tx * x + ty * y + tz * z
            w = sx * x + sy * y + sz * z
            if emitted == 0:
                u_first = u
                w_first = w
            else:
                twice += u_prev * w - w_prev * u
            u_prev = u
            w_prev = w
            emitted += 1
    if emitted < 3:
        return 0.0
    return 0.5 * abs(twice + u_prev * w_first - w_prev * u_first)


@nb.njit(inline="always")
def _share_area(face_area, picked, order, n, pu, pw, area, first):
    """area[first + r] = face_area [m^2] times the weight of contact point r, the vertex
    picked[r] of a convex polygon with coordinates pu, pw [m] in the reference face's plane:
    the picked points in the polygon's order about their mean c, each gets half of the two fan
    triangles (c, P_r-1, P_r) and (c, P_r, P_r+1) beside it (the median dual cell of a
    polygon's vertex); equal shares when they span no area. order: work array of n ints."""
    _polygon_order(picked, order, n)
    cu = cw = 0.0
    for r in range(n):
        cu += pu[picked[r]]
        cw += pw[picked[r]]
        area[first + r] = 0.0
    cu /= n
    cw /= n
    total = 0.0
    for r in range(n):
        a = picked[order[r]]
        b = picked[order[(r + 1) % n]]
        triangle = 0.5 * abs((pu[a] - cu) * (pw[b] - cw) - (pw[a] - cw) * (pu[b] - cu))
        area[first + order[r]] += 0.5 * triangle
        area[first + order[(r + 1) % n]] += 0.5 * triangle
        total += triangle
    for r in range(first, first + n):
        area[r] = face_area * area[r] / total if total > 0.0 else face_area / n


@nb.njit(inline="always")
def _clip(px, py, pz, dist, src, m, sx, sy, sz, off, tol):
    """Sutherland-Hodgman: clip the polygon px[src, :m] by the half-space s . p <= off (points
    within tol outside count as inside, so that flush faces are not cut by round-off) into
    row 1 - src; returns the new point count."""
    dst = 1 - src
    for k in range(m):
        dist[k] = sx * px[src, k] + sy * py[src, k] + sz * pz[src, k] - off
    out = 0
    for k in range(m):
        k1 = (k + 1) % m
        d0 = dist[k]
        d1 = dist[k1]
        if d0 <= tol:
            px[dst, out] = px[src, k]
            py[dst, out] = py[src, k]
            pz[dst, out] = pz[src, k]
            out += 1
        if (d0 <= tol) != (d1 <= tol):
            # the crossing of the plane, clamped to the side: with both ends within tol of
            # the plane (one inside, one just outside) the line would cross it anywhere
            f = min(max(d0 / (d0 - d1), 0.0), 1.0)
            px[dst, out] = px[src, k] + f * (px[src, k1] - px[src, k])
            py[dst, out] = py[src, k] + f * (py[src, k1] - py[src, k])
            pz[dst, out] = pz[src, k] + f * (pz[src, k1] - pz[src, k])
            out += 1
    return out


@nb.njit(inline="always")
def _corner_only(wv, fvs, fv, inc_face, nx, ny, nz, ax, ay, az, px, py, pz, src, kept, tie):
    """Whether the incident face lies in the reference face's plane (its vertices' gaps within
    tie [m] of one another) and meets the reference face only along a line or at a point (the
    kept points px/py/pz[src, :kept] within tie of the line through the two farthest apart):
    blocks that only meet at their corners, edge to edge or corner to corner (module doc)."""
    lo = np.inf
    hi = -np.inf
    for k in range(fvs[inc_face], fvs[inc_face + 1]):
        g = nx * (wv[fv[k], 0] - ax) + ny * (wv[fv[k], 1] - ay) + nz * (wv[fv[k], 2] - az)
        lo = min(lo, g)
        hi = max(hi, g)
    if hi - lo > tie:
        return False
    far = 0.0
    a = 0
    b = 0
    for i in range(kept):
        for j in range(i + 1, kept):
            d = ((px[src, i] - px[src, j]) ** 2 + (py[src, i] - py[src, j]) ** 2
                 + (pz[src, i] - pz[src, j]) ** 2)
            if d > far:
                far = d
                a = i
                b = j
    if far <= tie * tie:
        return True
    length = math.sqrt(far)
    ux = (px[src, b] - px[src, a]) / length
    uy = (py[src, b] - py[src, a]) / length
    uz = (pz[src, b] - pz[src, a]) / length
    for k in range(kept):
        rx = px[src, k] - px[src, a]
        ry = py[src, k] - py[src, a]
        rz = pz[src, k] - pz[src, a]
        along = rx * ux + ry * uy + rz * uz
        if rx * rx + ry * ry + rz * rz - along * along > tie * tie:
            return False
    return True


@nb.njit(inline="always")
def _closest_points(wv, a0, a1, b0, b1):
    """Closest points of the segments a0-a1 and b0-b1 (C. Ericson, "Real-time collision
    detection", 2005, sec. 5.1.9): the one on the second, then the one on the first."""
    d1x = wv[a1, 0] - wv[a0, 0]
    d1y = wv[a1, 1] - wv[a0, 1]
    d1z = wv[a1, 2] - wv[a0, 2]
    d2x = wv[b1, 0] - wv[b0, 0]
    d2y = wv[b1, 1] - wv[b0, 1]
    d2z = wv[b1, 2] - wv[b0, 2]
    rx = wv[a0, 0] - wv[b0, 0]
    ry = wv[a0, 1] - wv[b0, 1]
    rz = wv[a0, 2] - wv[b0, 2]
    aa = d1x * d1x + d1y * d1y + d1z * d1z
    ee = d2x * d2x + d2y * d2y + d2z * d2z
    ff = d2x * rx + d2y * ry + d2z * rz
    cc = d1x * rx + d1y * ry + d1z * rz
    bb = d1x * d2x + d1y * d2y + d1z * d2z
    den = aa * ee - bb * bb  # > 0: the edges are not parallel
    s = min(max((bb * ff - cc * ee) / den, 0.0), 1.0)
    t = min(max((bb * s + ff) / ee, 0.0), 1.0)
    s = min(max((bb * t - cc) / aa, 0.0), 1.0)
    return (wv[b0, 0] + t * d2x, wv[b0, 1] + t * d2y, wv[b0, 2] + t * d2z,
            wv[a0, 0] + s * d1x, wv[a0, 1] + s * d1y, wv[a0, 2] + s * d1z)


@nb.njit(inline="always")
def _write(candidate, antagonist, key, law, point, frame, gap, c, cand, ant, k, law_index,
           x, y, z, tx, ty, tz, nx, ny, nz, g):
    """Row c of the contact arrays: frame rows t, n, s = t x n."""
    candidate[c] = cand
    antagonist[c] = ant
    key[c] = k
    law[c] = law_index
    point[c, 0] = x
    point[c, 1] = y
    point[c, 2] = z
    frame[c, 0, 0] = tx
    frame[c, 0, 1] = ty
    frame[c, 0, 2] = tz
    frame[c, 1, 0] = nx
    frame[c, 1, 1] = ny
    frame[c, 1, 2] = nz
    frame[c, 2, 0] = ty * nz - tz * ny
    frame[c, 2, 1] = tz * nx - tx * nz
    frame[c, 2, 2] = tx * ny - ty * nx
    gap[c] = g
