"""Narrow phase between convex polygons: reference face, incident face, clipped contact points.

For a pair of blocks, the separating-axis test over the edges of both polygons finds the edge of
largest separation; its polygon becomes the antagonist (it carries the frame: n is that edge's
outward normal, t = (n_y, -n_x)), the other the candidate. The candidate's face most opposed to n
(the incident face) is clipped to the extent of the reference face: the ends of the clipped
segment are the contact points, each kept if its gap n . (p - a) is below the alert distance.
Two faces in contact thus give two points at the ends of their common segment, so that a joint
can open and rotate about either end; a vertex against a face gives one point.

Separations that differ by less than the closed gap (1e-6 alert: round-off of blocks built
touching) count as equal: the first edge of a tie is the reference, and an incident face that
reaches the end of the reference face within it is in contact there. Blocks laid corner to
corner (four bricks of a stack bond meeting at a point) otherwise get a normal and a contact
that round-off switches from step to step, each switch a contact lost and one new, with no
impulse to start from. But an incident face in line with the reference face (within the
closed gap) that meets it at one point only is no contact: the blocks only touch corner to
corner, and no normal is right there (along either face it would hold a block that slides past
the other: a block bridging a joint would not slide at 1.05 times the friction), while the only
motion the corner stops, into the corner diagonally, is stopped by the blocks' other joints.

The choice of faces (rejected pair, reference polygon and edge, incident edge) is kept from the
configuration on which the broad phase last ran, with how far each of its comparisons was from
tipping over. Separations n_e . (p - a_e) change by at most d_o + d_r + |dtheta_r| L when the
bodies' points move by at most d_o, d_r and the reference body turns by dtheta_r (L bounding
|p - a|), and the products of unit normals by at most the sum of the turns; while these bounds
stay below the recorded slack, every comparison comes out as it did and the kept choice is the
one the full test would make, so it is used as is: the same contacts bit for bit, without the
test's cost for blocks that barely move.

Contact areas (per metre of depth, so lengths [m]), for laws written in stresses: the points of a
contact share equally the length, projected on the reference face, of the part of the common
segment whose gap is within the alert distance (the gap is linear along it). Two faces in contact
give each end half the overlap length, and the areas of a joint sum to its overlap length; a
vertex against a face (an incident face at an angle theta to the reference face) stands for
about alert / tan(theta), small beside the faces unless they are nearly flush, which is the
part of the faces close enough to interact; an incident face normal to the reference face
gives one point of zero area.

Points for laws in stresses (ContactLaw.points = n, odd, > 2): two ends alone are a trapezoid
rule, with which a joint of width b has the rotational stiffness k_n b^3 / 4 instead of
k_n b^3 / 12 and reaches the edge stress of a linear distribution at f_t b^2 / 2 instead of
f_t b^2 / 6 (docs/design-deformable-and-joints.md, sec. 4). A face contact of such a law gets
n - 2 more points, evenly spaced between its ends on the common segment (fixed fractions of
it, keyed as slots 2 .. n - 1 of the pair of faces), and the areas of composite Simpson panels
(3-point Gauss-Lobatto: 1/6, 4/6, 1/6 of a panel), exact for the force, the first and the
second moment of a linear stress. Where the joint opens beyond alert at one end, the points
still within alert share the part within alert in proportion to their weights, as the ends
alone do.
"""

import numba as nb
import numpy as np

__all__ = ["polygon_contacts", "polygon_contacts_parallel"]


_NO_CHOICE = 0
_REJECTED = 1
_KEPT = 2
_FLIPPED = 3


@nb.njit(inline="always")
def _max_separation(wv, wn, r0, nr, o0, no, tie):
    """(largest over edges e of polygon r of min over vertices p of o of n_e . (p - a_e) [m],
    to within tie [m]: the first edge that reaches it (an edge takes over only if it
    separates more by tie), how far [m] the comparisons that chose it were from tipping over).

    Two edges separate equally when a vertex meets a vertex (blocks laid corner to corner):
    without the tie, round-off would pick one or the other from step to step, and with it
    the contact's normal. Written without data-dependent branches (selects instead): which
    edge and which vertex win changes from pair to pair, and mispredicted branches cost more
    than the arithmetic.
    """
    best = -np.inf
    margin = np.inf
    best_e = 0
    for e in range(nr):
        ax = wv[r0 + e, 0]
        ay = wv[r0 + e, 1]
        nx = wn[r0 + e, 0]
        ny = wn[r0 + e, 1]
        s = nx * (wv[o0, 0] - ax) + ny * (wv[o0, 1] - ay)
        for k in range(o0 + 1, o0 + no):
            t = nx * (wv[k, 0] - ax) + ny * (wv[k, 1] - ay)
            s = t if t < s else s
        better = s > best + tie
        margin = min(margin, abs(s - (best + tie)))
        best_e = e if better else best_e
        best = s if better else best
    return best, best_e, margin


@nb.njit(inline="always")
def _choose_faces(wv, wn, i0, ni, j0, nj, alert, ref_tol, tie):
    """The separating-axis test of polygons i and j: (_REJECTED, _KEPT (i is the reference) or
    _FLIPPED (j is), reference edge, incident edge, slack [m] of the comparisons of
    separations, slack [-] of the comparisons of products of normals) (module doc); tie [m]:
    see _max_separation."""
    s_i, e_i, margin_i = _max_separation(wv, wn, i0, ni, j0, nj, tie)
    if s_i > alert:
        return _REJECTED, 0, 0, s_i - alert, np.inf
    s_j, e_j, margin_j = _max_separation(wv, wn, j0, nj, i0, ni, tie)
    if s_j > alert:
        return _REJECTED, 0, 0, s_j - alert, np.inf
    flip = s_j > s_i + ref_tol
    slack = min(min(alert - s_i, alert - s_j), 0.5 * abs(s_j - (s_i + ref_tol)))
    if flip:
        ref, a0, c0, nc = e_j, j0, i0, ni
        slack = min(slack, 0.5 * margin_j)
    else:
        ref, a0, c0, nc = e_i, i0, j0, nj
        slack = min(slack, 0.5 * margin_i)
    # incident edge: the candidate's edge whose normal is most opposed to the reference's
    nx = wn[a0 + ref, 0]
    ny = wn[a0 + ref, 1]
    inc = 0
    most = np.inf
    second = np.inf
    for e in range(nc):
        d = wn[c0 + e, 0] * nx + wn[c0 + e, 1] * ny
        lower = d < most
        second = most if lower else min(second, d)
        inc = e if lower else inc
        most = d if lower else most
    return _FLIPPED if flip else _KEPT, ref, inc, slack, 0.5 * (second - most)


@nb.njit(inline="always")
def _clipped_end(s_clip, s0, ds, p0x, p0y, p1x, p1y, nx, ny, ax, ay):
    """The point of the incident segment p0-p1 at abscissa s_clip [m] along the reference face
    (p0 at s0, ds = s1 - s0 >= 0; p0 itself when ds = 0) and its gap n . (p - a) [m]."""
    f = (s_clip - s0) / ds if ds > 0.0 else 0.0
    px = p0x + f * (p1x - p0x)
    py = p0y + f * (p1y - p0y)
    return px, py, nx * (px - ax) + ny * (py - ay)


@nb.njit(inline="always")
def _alert_length(length, g0, g1, alert):
    """The part [m] of a segment of projected length `length` [m] whose gap, linear from g0 at
    one end to g1 at the other, is within alert [m], where one end at most is within alert."""
    if length <= 0.0 or min(g0, g1) > alert:
        return 0.0
    return length * (alert - min(g0, g1)) / abs(g1 - g0)


@nb.njit(inline="always")
def alert_of_pair(law_alert, body_alert, law_index, i, j, alert):
    """Alert distance [m] of the pair of bodies (i, j) of law law_index: law_alert[law_index],
    or where that is NaN (DetectionSettings.per_pair) min(body_alert[i], body_alert[j]);
    alert where the pair has no law."""
    if law_index < 0:
        return alert
    a = law_alert[law_index]
    return a if a == a else min(body_alert[i], body_alert[j])


@nb.njit(cache=True)
def polygon_contacts(
    pairs, npairs, wv, wn, edge_length, vertex_start, body_group, group_law, law_points,
    slots, alert, law_alert, body_alert, ref_tol, max_vertices, q, radius, motion, turn, record,
    faces, slack,
    candidate, antagonist, key, law, point, frame, gap, area,
):
    """Contacts of the first npairs pairs of polygons with world vertices wv [m] and outward
    unit normals wn of the edges that start at them.

    alert: the detector's alert distance [m] (its closed gap is 1e-6 alert); law_alert [m]:
    the alert distance per law (ContactLaw.alert, or alert), which a pair of that law uses, or
    NaN: min(body_alert[i], body_alert[j]) [m] for the pair (i, j) (DetectionSettings.per_pair);
    ref_tol: a face of the first body of a pair stays the reference
    unless the second body's best face separates more by ref_tol [m] (a bias that keeps contact
    identities stable across steps). law_points: points of a face-to-face contact per law
    (Model.law_points), or None where every law has 2 (numba then compiles the kernel
    without the code of more points, in two thirds of the time); slots >= max(law_points):
    keys per pair of faces. Output arrays need room for slots * npairs contacts.
    Returns (the number of contacts written, in increasing key order for pairs sorted by
    (i, j), the number of pairs that used their kept choice of faces).

    The kept choice of faces (module doc): q [m, rad] the configuration, radius [m] the bodies'
    radii about their centroids, motion [m] and turn [rad] bounds of each body's displacement
    and rotation since the reference configuration; record: q is that configuration, so the
    full test runs on every pair and fills faces (int32 [npairs, 3]: choice, reference edge,
    incident edge) and slack (float [npairs, 2]); otherwise a pair whose bounds stay within its
    slack uses its row of faces (choice _NO_CHOICE: run the full test).

    area [m^2/m, a length]: the share of the contact face each point stands for (module doc).
    """
    nbody = vertex_start.shape[0] - 1
    tie = 1e-6 * alert  # the detector's closed_gap: separations closer than this are equal
    count = 0
    reused = 0
    for p in range(npairs):
        i = pairs[p, 0]
        j = pairs[p, 1]
        law_index = group_law[body_group[i], body_group[j]]
        pair_alert = alert_of_pair(law_alert, body_alert, law_index, i, j, alert)
        i0 = vertex_start[i]
        ni = vertex_start[i + 1] - i0
        j0 = vertex_start[j]
        nj = vertex_start[j + 1] - j0
        kept = False
        if not record and faces[p, 0] != _NO_CHOICE:
            far = (abs(q[i, 0] - q[j, 0]) + abs(q[i, 1] - q[j, 1])) + (radius[i] + radius[j])
            # round-off of the separations as computed, with a wide margin
            eps = 1e-14 * (far + abs(q[i, 0]) + abs(q[i, 1]) + abs(q[j, 0]) + abs(q[j, 1]))
            moved = motion[i] + motion[j] + max(turn[i], turn[j]) * far + eps
            kept = moved < slack[p, 0] and turn[i] + turn[j] + 1e-14 < slack[p, 1]
        if kept:
            choice, ref, inc = faces[p, 0], faces[p, 1], faces[p, 2]
            reused += 1
        else:
            choice, ref, inc, slack_length, slack_turn = _choose_faces(wv, wn, i0, ni, j0, nj,
                                                                       pair_alert, ref_tol,
                                                                       tie)
            if record:
                faces[p, 0] = choice
                faces[p, 1] = ref
                faces[p, 2] = inc
                slack[p, 0] = slack_length
                slack[p, 1] = slack_turn
        if choice == _REJECTED:
            continue
        flip = choice == _FLIPPED
        if flip:
            ant, a0 = j, j0
            cand, c0, nc = i, i0, ni
        else:
            ant, a0 = i, i0
            cand, c0, nc = j, j0, nj
        ax = wv[a0 + ref, 0]
        ay = wv[a0 + ref, 1]
        nx = wn[a0 + ref, 0]
        ny = wn[a0 + ref, 1]
        tx = -ny
        ty = nx
        length = edge_length[a0 + ref]
        k0 = c0 + inc
        k1 = c0 + (inc + 1 if inc + 1 < nc else 0)
        p0x = wv[k0, 0]
        p0y = wv[k0, 1]
        p1x = wv[k1, 0]
        p1y = wv[k1, 1]
        s0 = tx * (p0x - ax) + ty * (p0y - ay)
        s1 = tx * (p1x - ax) + ty * (p1y - ay)
        if s0 > s1:
            p0x, p1x = p1x, p0x
            p0y, p1y = p1y, p0y
            s0, s1 = s1, s0
        if s1 < -tie or s0 > length + tie:
            continue
        if (abs(nx * (p1x - p0x) + ny * (p1y - p0y)) <= tie
                and min(s1, length) - max(s0, 0.0) <= tie):
            continue  # faces in line, meeting at one point: corner to corner (module doc)
        ds = s1 - s0
        base = (((i * nbody + j) * 2 + flip) * max_vertices + ref) * max_vertices + inc
        first = count
        for slot in range(2):
            if slot == 0:
                s_clip = max(s0, 0.0)
            else:
                s_clip = min(s1, length)
                if ds <= 0.0:
                    break
            px, py, g = _clipped_end(s_clip, s0, ds, p0x, p0y, p1x, p1y, nx, ny, ax, ay)
            if g > pair_alert:
                continue
            _write(candidate, antagonist, key, law, point, frame, gap, count, cand, ant,
                   base * slots + slot, law_index, px, py, nx, ny, g)
            count += 1
        s_lo = max(s0, 0.0)
        s_hi = min(s1, length)
        if law_points is not None:  # None: no law has more points, and no code for them
            points = law_points[law_index] if law_index >= 0 else 2
            if points > 2 and ds > 0.0 and s_hi - s_lo > tie:
                # the inner points of the Simpson panels, slots 2 .. points - 1 (module doc)
                for slot in range(2, points):
                    s_clip = s_lo + (s_hi - s_lo) * (slot - 1) / (points - 1)
                    px, py, g = _clipped_end(s_clip, s0, ds, p0x, p0y, p1x, p1y, nx, ny, ax,
                                             ay)
                    if g <= pair_alert:
                        _write(candidate, antagonist, key, law, point, frame, gap, count,
                               cand, ant, base * slots + slot, law_index, px, py, nx, ny, g)
                        count += 1
                _simpson_areas(key, area, first, count, base, slots, points, s_lo, s_hi, s0,
                               ds, p0x, p0y, p1x, p1y, nx, ny, ax, ay, pair_alert)
                continue
        if count - first == 2:  # flush faces, the common case: half each
            area[first] = area[first + 1] = 0.5 * max(s_hi - s_lo, 0.0)
        elif count > first:  # one end beyond alert (or ds = 0): the other stands for the rest
            g0 = _clipped_end(s_lo, s0, ds, p0x, p0y, p1x, p1y, nx, ny, ax, ay)[2]
            g1 = _clipped_end(s_hi, s0, ds, p0x, p0y, p1x, p1y, nx, ny, ax, ay)[2]
            area[first] = _alert_length(s_hi - s_lo if ds > 0.0 else 0.0, g0, g1, pair_alert)
    return count, reused


PAIR_BLOCK = 2048
"""Pairs per block of polygon_contacts_parallel."""


@nb.njit(parallel=True, cache=True)
def polygon_contacts_parallel(
    pairs, npairs, wv, wn, edge_length, vertex_start, body_group, group_law, law_points,
    slots, alert, law_alert, body_alert, ref_tol, max_vertices, q, radius, motion, turn, record,
    faces, slack, start, in_place,
    candidate, antagonist, key, law, point, frame, gap, area,
    s_candidate, s_antagonist, s_key, s_law, s_point, s_frame, s_gap, s_area,
):
    """polygon_contacts on numba's threads, the same contacts in the same order bit for bit:
    blocks of PAIR_BLOCK pairs in parallel. start (int64, one more than the blocks): where
    each block's contacts began in the last call; in_place: try writing each block's
    contacts straight into the output arrays from there, which holds where every block
    finds as many contacts as then (bodies at rest); otherwise, or
    where one does not (its rows may have run into the next block's: all are written again),
    each block's contacts go into its own rows of the scratch arrays s_* (room for slots *
    npairs contacts: slots * its first pair on), then copied in the blocks' order into the
    output arrays (room as polygon_contacts'). Returns (contacts, pairs that kept their
    faces, whether every block found as many contacts as in start), with start updated."""
    blocks = -(-npairs // PAIR_BLOCK)
    found = np.zeros(blocks, dtype=np.int64)
    reused = np.zeros(blocks, dtype=np.int64)
    if in_place:
        for k in nb.prange(blocks):
            lo = k * PAIR_BLOCK
            hi = min(npairs, lo + PAIR_BLOCK)
            r = start[k]
            found[k], reused[k] = polygon_contacts(
                pairs[lo:hi], hi - lo, wv, wn, edge_length, vertex_start, body_group,
                group_law, law_points, slots, alert, law_alert, body_alert, ref_tol,
                max_vertices, q, radius, motion, turn, record, faces[lo:hi], slack[lo:hi],
                candidate[r:], antagonist[r:], key[r:], law[r:], point[r:], frame[r:], gap[r:],
                area[r:])
        if _same_sizes(found, start):
            return start[blocks], reused.sum(), True
    for k in nb.prange(blocks):
        lo = k * PAIR_BLOCK
        hi = min(npairs, lo + PAIR_BLOCK)
        r = slots * lo
        found[k], reused[k] = polygon_contacts(
            pairs[lo:hi], hi - lo, wv, wn, edge_length, vertex_start, body_group, group_law,
            law_points, slots, alert, law_alert, body_alert, ref_tol, max_vertices, q, radius,
            motion, turn, record, faces[lo:hi], slack[lo:hi], s_candidate[r:],
            s_antagonist[r:], s_key[r:], s_law[r:], s_point[r:], s_frame[r:], s_gap[r:],
            s_area[r:])
    same = _same_sizes(found, start)
    start[0] = 0
    for k in range(blocks):
        start[k + 1] = start[k] + found[k]
    for k in nb.prange(blocks):
        copy_rows(slots * k * PAIR_BLOCK, start[k], found[k],
                  s_candidate, s_antagonist, s_key, s_law, s_point, s_frame, s_gap, s_area,
                  candidate, antagonist, key, law, point, frame, gap, area)
    return start[blocks], reused.sum(), same


@nb.njit(cache=True)
def _same_sizes(found, start):
    """Whether block k found start[k + 1] - start[k] contacts, for every k."""
    for k in range(found.shape[0]):
        if found[k] != start[k + 1] - start[k]:
            return False
    return True


@nb.njit(cache=True)
def copy_rows(src, dst, n, s_candidate, s_antagonist, s_key, s_law, s_point, s_frame, s_gap,
              s_area, candidate, antagonist, key, law, point, frame, gap, area):
    """Rows src .. src + n - 1 of the s_* arrays into rows dst .. dst + n - 1 of the others
    (2D or 3D: the parallel narrow phases, polygon_contacts_parallel and
    saxum.detection.polyhedra.polyhedron_contacts_parallel)."""
    dim = point.shape[1]
    for i in range(n):
        a = src + i
        c = dst + i
        candidate[c] = s_candidate[a]
        antagonist[c] = s_antagonist[a]
        key[c] = s_key[a]
        law[c] = s_law[a]
        for r in range(dim):
            point[c, r] = s_point[a, r]
            for d in range(dim):
                frame[c, r, d] = s_frame[a, r, d]
        gap[c] = s_gap[a]
        area[c] = s_area[a]


@nb.njit(inline="always")
def _write(candidate, antagonist, key, law, point, frame, gap, c, cand, ant, k, law_index, px,
           py, nx, ny, g):
    """Row c of the contact arrays: frame rows t = (n_y, -n_x), n."""
    candidate[c] = cand
    antagonist[c] = ant
    key[c] = k
    law[c] = law_index
    point[c, 0] = px
    point[c, 1] = py
    frame[c, 0, 0] = ny
    frame[c, 0, 1] = -nx
    frame[c, 1, 0] = nx
    frame[c, 1, 1] = ny
    gap[c] = g


@nb.njit(inline="always")
def _simpson_areas(key, area, first, count, base, slots, points, s_lo, s_hi, s0, ds, p0x, p0y,
                   p1x, p1y, nx, ny, ax, ay, alert):
    """Areas [m] of the contacts first:count of a face contact with `points` points, slot 0
    at s_lo, slot 1 at s_hi and slot k >= 2 at s_lo + (s_hi - s_lo) (k - 1) / (points - 1)
    along the reference face: the composite Simpson weights L / (3 (points - 1)) (1, 4, 2, 4,
    ..., 4, 1), L = s_hi - s_lo, when all points are within alert; otherwise the kept points
    (those near one end: the gap is linear) share the part within alert in proportion to
    their weights, as the two ends do (module doc)."""
    panel = (s_hi - s_lo) / (3.0 * (points - 1))
    total = 0.0
    for c in range(first, count):
        slot = key[c] - base * slots
        k = 0 if slot == 0 else points - 1 if slot == 1 else slot - 1  # place in the rule
        area[c] = panel * (1.0 if k == 0 or k == points - 1 else 4.0 if k % 2 == 1 else 2.0)
        total += area[c]
    if count - first < points and total > 0.0:
        g0 = _clipped_end(s_lo, s0, ds, p0x, p0y, p1x, p1y, nx, ny, ax, ay)[2]
        g1 = _clipped_end(s_hi, s0, ds, p0x, p0y, p1x, p1y, nx, ny, ax, ay)[2]
        within = _alert_length(s_hi - s_lo, g0, g1, alert)
        for c in range(first, count):
            area[c] *= within / total
