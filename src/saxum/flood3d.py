"""Floods on 3D blocks: the compiled kernels behind saxum.flood.FloodLoad for convex polyhedra.

The water is that of saxum.flood (module doc there): piezometric head H(s) [m] along "up" u
(-gravity), a function of the horizontal coordinate s = e . x [m] along the unit vector e of
the flow's azimuth: `level` upstream (s <= s_a), the tailwater downstream (s >= s_b), linear in
between, s_a and s_b the extreme free-block vertices along e. The pressure at x is
p = rho_w g max(H(s) - u . x, 0) on every face of every free block (joints wet).

Pressure. A face is a convex polygon; cut by the vertical planes s = s_a and s = s_b, each
piece has a head linear in x, so its wet part {H(s) - u . x >= 0} is the piece clipped by a
plane, and p is linear over it. Over a fan triangle (x_0, x_1, x_2) of area A with vertex
pressures p_k, with P = p_0 + p_1 + p_2 (linear shape functions: int phi_i phi_j dA =
A (1 + delta_ij) / 12):
    int p dA = A P / 3,        int p (x - G) dA = A / 12 sum_k (P + p_k) (x_k - G),
and the face gives F = -n int p dA, M = -(int p (x - G) dA) x n. Exact up to round-off; by the
divergence theorem a block under still water gets rho_w g V_sub up through the centroid of
its submerged part.

Drag. The flow of velocity U pushes with p_d = 1/2 rho_w C_d U |U| [Pa] on the area the
structure presents to it: the wet parts ("panels") of the faces that face upstream
(n . f < 0, f = sign(U) e the flow direction), projected along f onto the plane (w, u),
w = u x f, where no other panel lies in front of them (a face of any body: fixed ones and
upstream blocks shield those behind them). Panels of non-penetrating blocks do not cross, so
over the overlap of two projections one panel is in front of the other everywhere; a panel
in front is cut out of the one behind exactly (convex polygon difference: the part outside
each of its edges in turn). What remains of a free block's panel gets p_d times its projected
area along f, at its centroid (mapped back onto the panel, which is affine in (w, u)). Parts
of a panel narrower than 1e-6 of the panels' extent (their area below that width times their
half perimeter), such as the slivers left between flush faces that settled by round-off, are
dropped (at most p_d times that width per unit length of edge). Candidate shielders come from
a uniform grid of the projection plane (cells about the panels' mean size), so the cost is
about linear in the number of panels. The total on a structure is 1/2 rho_w C_d A U^2 with A
the wet area of its outline seen from upstream (AASHTO LRFD 3.7.3.1, docs/flood.md).

All forces [N] and moments [N m] are in the world frame, about each body's centre of mass.
"""

import math

import numba as nb
import numpy as np

from .bodies.rigid3d import _rotate, _rotation
from .detection.polyhedra import _clip

__all__ = ["DRAG_OVERFLOW", "drag_forces_3d", "extent_3d", "hydrostatic_forces_3d"]

_PIECES = 128  # exposed pieces of one panel, at most
DRAG_OVERFLOW = 1
"""drag_forces_3d's status when a panel's exposed part needed more pieces than it holds."""


@nb.njit(cache=True)
def extent_3d(q, kind, vertex_start, vertex_local, e):
    """(smallest, largest) of e . x [m] over the free blocks' vertices x at coordinates q."""
    lo = np.inf
    hi = -np.inf
    for b in range(q.shape[0]):
        if kind[b] != 0:
            continue
        r = _rotation(q, b)
        for k in range(vertex_start[b], vertex_start[b + 1]):
            x, y, z = _rotate(r, vertex_local[k, 0], vertex_local[k, 1], vertex_local[k, 2])
            v = (q[b, 0] + x) * e[0] + (q[b, 1] + y) * e[1] + (q[b, 2] + z) * e[2]
            lo = min(lo, v)
            hi = max(hi, v)
    return lo, hi


@nb.njit(inline="always")
def _most_points(face_vertex_start):
    """The largest number of vertices of a face."""
    most = 3
    for f in range(face_vertex_start.shape[0] - 1):
        most = max(most, face_vertex_start[f + 1] - face_vertex_start[f])
    return most


@nb.njit(inline="always")
def _face_points(r, f, face_vertex_start, face_vertex, vertex_local, face):
    """face[:m] = the vertices of face f turned by the rotation r (rows of _rotation), i.e.
    relative to its body's centre of mass in world axes [m]; returns m."""
    m = face_vertex_start[f + 1] - face_vertex_start[f]
    for j in range(m):
        v = face_vertex[face_vertex_start[f] + j]
        face[j, 0], face[j, 1], face[j, 2] = _rotate(r, vertex_local[v, 0], vertex_local[v, 1],
                                                     vertex_local[v, 2])
    return m


@nb.njit(inline="always")
def _piece_range(face, m, e, so, h_up, h_down, s_a, s_b):
    """The first and last pieces (0: s <= s_a, 1: between, 2: s >= s_b) that the face
    polygon face[:m] (points relative to a point at s = so) reaches; a face within a plane
    s = s_a or s = s_b (where the heads of both sides agree) counts in one piece only."""
    if h_down == h_up:
        return 0, 0
    lo = np.inf
    hi = -np.inf
    for j in range(m):
        s = so + e[0] * face[j, 0] + e[1] * face[j, 1] + e[2] * face[j, 2]
        lo = min(lo, s)
        hi = max(hi, s)
    first = 0 if lo < s_a else (1 if lo < s_b else 2)
    last = 2 if hi > s_b else (1 if hi > s_a else 0)
    return first, max(first, last)


@nb.njit(inline="always")
def _wet_piece(i, cut, face, m, px, py, pz, dist, ox, oy, oz, e, up, h_up, h_down, s_a, s_b):
    """Piece i (0: s <= s_a, 1: between, 2: s >= s_b) of the face polygon face[:m] (world
    points relative to o = (ox, oy, oz)), cut from the rest of the face if `cut`, clipped to
    its wet part, into row src of px, py, pz; returns (src, point count, c, k): on the piece
    the head is linear, H - u . x = c + (k e - u) . p at the point p relative to o."""
    for j in range(m):
        px[0, j] = face[j, 0]
        py[0, j] = face[j, 1]
        pz[0, j] = face[j, 2]
    so = e[0] * ox + e[1] * oy + e[2] * oz  # s and height of the origin o
    zo = up[0] * ox + up[1] * oy + up[2] * oz
    src = 0
    k = 0.0
    h = h_up  # the head at s = 0, H = h + k s
    if i == 1:
        k = (h_down - h_up) / (s_b - s_a)
        h = h_up - k * s_a
    elif i == 2:
        h = h_down
    if cut and i > 0:
        m = _clip(px, py, pz, dist, src, m, -e[0], -e[1], -e[2], so - (s_a if i == 1 else s_b),
                  0.0)
        src = 1 - src
    if cut and i < 2 and m >= 3:
        m = _clip(px, py, pz, dist, src, m, e[0], e[1], e[2], (s_a if i == 0 else s_b) - so,
                  0.0)
        src = 1 - src
    if m >= 3:  # wet: (u - k e) . x <= h
        m = _clip(px, py, pz, dist, src, m, up[0] - k * e[0], up[1] - k * e[1],
                  up[2] - k * e[2], h - zo + k * so, 0.0)
        src = 1 - src
    return src, m, h + k * so - zo, k


@nb.njit(cache=True)
def hydrostatic_forces_3d(q, kind, radius, vertex_start, vertex_local, face_start,
                          face_vertex_start, face_vertex, face_normal_local, rho_g, up, e,
                          h_up, h_down, s_a, s_b, out):
    """out[b] += (force [N], moment about the centre of mass [N m]) of the water pressure
    p = rho_g max(H(s) - u . x, 0) [Pa] on the faces of every free body b (module doc);
    rho_g = rho_w g [N/m^3]; up, e: unit vectors; heads h_up, h_down [m] and s_a, s_b [m] as
    in the module doc; radius [m]: each body's largest distance from its centre of mass to a
    vertex."""
    cap = _most_points(face_vertex_start) + 4
    face = np.empty((cap, 3))
    px = np.empty((2, cap))
    py = np.empty((2, cap))
    pz = np.empty((2, cap))
    dist = np.empty(cap)
    top = max(h_up, h_down)
    for b in range(q.shape[0]):
        if kind[b] != 0:
            continue
        gx = q[b, 0]
        gy = q[b, 1]
        gz = q[b, 2]
        if gx * up[0] + gy * up[1] + gz * up[2] - radius[b] >= top:
            continue  # above the water
        r = _rotation(q, b)
        fx = fy = fz = mx = my = mz = 0.0
        for f in range(face_start[b], face_start[b + 1]):
            m = _face_points(r, f, face_vertex_start, face_vertex, vertex_local, face)
            nx, ny, nz = _rotate(r, face_normal_local[f, 0], face_normal_local[f, 1],
                                 face_normal_local[f, 2])
            ip = 0.0  # int p dA and int p (x - G) dA over the face
            ix = iy = iz = 0.0
            so = e[0] * gx + e[1] * gy + e[2] * gz
            first, last = _piece_range(face, m, e, so, h_up, h_down, s_a, s_b)
            for i in range(first, last + 1):
                src, n, c, k = _wet_piece(i, first != last, face, m, px, py, pz, dist, gx, gy,
                                          gz, e, up, h_up, h_down, s_a, s_b)
                if n < 3:
                    continue
                ax = e[0] * k - up[0]  # H - u . x = c + a . p on the piece
                ay = e[1] * k - up[1]
                az = e[2] * k - up[2]
                x0 = px[src, 0]
                y0 = py[src, 0]
                z0 = pz[src, 0]
                p0 = rho_g * max(c + ax * x0 + ay * y0 + az * z0, 0.0)
                for j in range(1, n - 1):
                    x1 = px[src, j]
                    y1 = py[src, j]
                    z1 = pz[src, j]
                    x2 = px[src, j + 1]
                    y2 = py[src, j + 1]
                    z2 = pz[src, j + 1]
                    p1 = rho_g * max(c + ax * x1 + ay * y1 + az * z1, 0.0)
                    p2 = rho_g * max(c + ax * x2 + ay * y2 + az * z2, 0.0)
                    # area A = n . (x1 - x0) x (x2 - x0) / 2 (CCW seen from outside)
                    ux = x1 - x0
                    uy = y1 - y0
                    uz = z1 - z0
                    vx = x2 - x0
                    vy = y2 - y0
                    vz = z2 - z0
                    area = 0.5 * (nx * (uy * vz - uz * vy) + ny * (uz * vx - ux * vz)
                                  + nz * (ux * vy - uy * vx))
                    total = p0 + p1 + p2
                    ip += area * total / 3.0
                    w = area / 12.0
                    ix += w * ((total + p0) * x0 + (total + p1) * x1 + (total + p2) * x2)
                    iy += w * ((total + p0) * y0 + (total + p1) * y1 + (total + p2) * y2)
                    iz += w * ((total + p0) * z0 + (total + p1) * z1 + (total + p2) * z2)
            fx -= nx * ip
            fy -= ny * ip
            fz -= nz * ip
            mx -= iy * nz - iz * ny
            my -= iz * nx - ix * nz
            mz -= ix * ny - iy * nx
        out[b, 0] += fx
        out[b, 1] += fy
        out[b, 2] += fz
        out[b, 3] += mx
        out[b, 4] += my
        out[b, 5] += mz


@nb.njit(inline="always")
def _area_centroid(pw, pz, pd, src, m):
    """Area [m^2] (positive for a counter-clockwise ring in (w, z)) and centroid (w, z, d)
    of the polygon in row src of pw, pz, pd (d: the depth, affine over the polygon)."""
    area = 0.0
    cw = cz = cd = 0.0
    for j in range(1, m - 1):
        a = 0.5 * ((pw[src, j] - pw[src, 0]) * (pz[src, j + 1] - pz[src, 0])
                   - (pz[src, j] - pz[src, 0]) * (pw[src, j + 1] - pw[src, 0]))
        area += a
        cw += a * (pw[src, 0] + pw[src, j] + pw[src, j + 1])
        cz += a * (pz[src, 0] + pz[src, j] + pz[src, j + 1])
        cd += a * (pd[src, 0] + pd[src, j] + pd[src, j + 1])
    if area == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    return area, cw / (3.0 * area), cz / (3.0 * area), cd / (3.0 * area)


@nb.njit(inline="always")
def _sliver(pw, pz, pd, src, m, width):
    """True if the polygon in row src is empty or narrower than `width` [m]: its area is
    below width times its half perimeter."""
    if m < 3:
        return True
    area = _area_centroid(pw, pz, pd, src, m)[0]
    half = 0.0
    for j in range(m):
        j1 = (j + 1) % m
        half += math.hypot(pw[src, j1] - pw[src, j], pz[src, j1] - pz[src, j])
    return area <= width * 0.5 * half


@nb.njit(cache=True)
def drag_forces_3d(q, kind, radius, vertex_start, vertex_local, face_start, face_vertex_start,
                   face_vertex, face_normal_local, pressure, flow, up, e, h_up, h_down, s_a,
                   s_b, out):
    """out[b] += the drag on every free body b (module doc): p_d = `pressure` [Pa] on the
    exposed projected area of its wet upstream faces, along the unit vector `flow` (horizontal,
    sign(U) e), with the moment about the centre of mass [N m]; up, e, heads and s_a, s_b as
    in hydrostatic_forces_3d. Returns 0, or DRAG_OVERFLOW if a panel's exposed part had more
    pieces than the kernel holds (its drag is then incomplete)."""
    wx = up[1] * flow[2] - up[2] * flow[1]  # w = u x f
    wy = up[2] * flow[0] - up[0] * flow[2]
    wz = up[0] * flow[1] - up[1] * flow[0]
    nfaces = face_vertex_start.shape[0] - 1
    cap = _most_points(face_vertex_start) + 4
    vcap = cap + 60  # points of an exposed piece: its panel's, and one per clipping line
    face = np.empty((cap, 3))
    px = np.empty((2, cap))
    py = np.empty((2, cap))
    pz = np.empty((2, cap))
    dist = np.empty(vcap)
    # 1. panels: wet parts of upstream faces, as (w, z, d) rings counter-clockwise in (w, z)
    most = 3 * nfaces
    start = np.zeros(most + 1, dtype=np.int64)
    ring = np.empty((3 * face_vertex.shape[0] + 12 * nfaces, 3))
    body = np.empty(most, dtype=np.int64)
    box = np.empty((most, 6))  # w, z, d ranges
    plane = np.empty((most, 3))  # d = plane[0] + plane[1] w + plane[2] z
    count = 0
    top = max(h_up, h_down)
    for b in range(q.shape[0]):
        gx = q[b, 0]
        gy = q[b, 1]
        gz = q[b, 2]
        if gx * up[0] + gy * up[1] + gz * up[2] - radius[b] >= top:
            continue
        r = _rotation(q, b)
        for f in range(face_start[b], face_start[b + 1]):
            nx, ny, nz = _rotate(r, face_normal_local[f, 0], face_normal_local[f, 1],
                                 face_normal_local[f, 2])
            nf = nx * flow[0] + ny * flow[1] + nz * flow[2]
            if nf >= 0.0:
                continue  # not facing upstream
            m = _face_points(r, f, face_vertex_start, face_vertex, vertex_local, face)
            so = e[0] * gx + e[1] * gy + e[2] * gz
            first, last = _piece_range(face, m, e, so, h_up, h_down, s_a, s_b)
            for i in range(first, last + 1):
                src, n, _, _ = _wet_piece(i, first != last, face, m, px, py, pz, dist, gx, gy,
                                          gz, e, up, h_up, h_down, s_a, s_b)
                if n < 3:
                    continue
                s0 = start[count]
                lo_w = lo_z = lo_d = np.inf
                hi_w = hi_z = hi_d = -np.inf
                for j in range(n):
                    jj = n - 1 - j  # seen from upstream the face turns clockwise: reverse it
                    x = gx + px[src, jj]
                    y = gy + py[src, jj]
                    z = gz + pz[src, jj]
                    cw = wx * x + wy * y + wz * z
                    cz = up[0] * x + up[1] * y + up[2] * z
                    cd = flow[0] * x + flow[1] * y + flow[2] * z
                    ring[s0 + j, 0] = cw
                    ring[s0 + j, 1] = cz
                    ring[s0 + j, 2] = cd
                    lo_w = min(lo_w, cw)
                    hi_w = max(hi_w, cw)
                    lo_z = min(lo_z, cz)
                    hi_z = max(hi_z, cz)
                    lo_d = min(lo_d, cd)
                    hi_d = max(hi_d, cd)
                if hi_w <= lo_w or hi_z <= lo_z:
                    continue  # edge-on: no area
                # the panel's plane n . x = n . x_0 as d(w, z)
                c0 = (nx * (gx + px[src, 0]) + ny * (gy + py[src, 0])
                      + nz * (gz + pz[src, 0]))
                plane[count, 0] = c0 / nf
                plane[count, 1] = -(nx * wx + ny * wy + nz * wz) / nf
                plane[count, 2] = -(nx * up[0] + ny * up[1] + nz * up[2]) / nf
                box[count, 0] = lo_w
                box[count, 1] = hi_w
                box[count, 2] = lo_z
                box[count, 3] = hi_z
                box[count, 4] = lo_d
                box[count, 5] = hi_d
                body[count] = b
                start[count + 1] = s0 + n
                count += 1
    if count == 0:
        return 0
    # 2. a uniform grid of the projection plane, panels listed by the cells their boxes cover
    lo_w = box[:count, 0].min()
    lo_z = box[:count, 2].min()
    span_w = box[:count, 1].max() - lo_w
    span_z = box[:count, 3].max() - lo_z
    mean = 0.0
    for p in range(count):
        mean += max(box[p, 1] - box[p, 0], box[p, 3] - box[p, 2])
    cell = max(mean / count, math.sqrt(span_w * span_z / (4.0 * count)), 1e-12)
    width = 1e-6 * max(span_w, span_z)  # slivers narrower than this are dropped
    ncw = int(span_w / cell) + 1
    ncz = int(span_z / cell) + 1
    cell_start = np.zeros(ncw * ncz + 1, dtype=np.int64)
    for p in range(count):
        for i in range(int((box[p, 0] - lo_w) / cell), int((box[p, 1] - lo_w) / cell) + 1):
            for j in range(int((box[p, 2] - lo_z) / cell), int((box[p, 3] - lo_z) / cell) + 1):
                cell_start[min(i, ncw - 1) * ncz + min(j, ncz - 1) + 1] += 1
    for c in range(ncw * ncz):
        cell_start[c + 1] += cell_start[c]
    fill = cell_start[:-1].copy()
    cell_panel = np.empty(cell_start[-1], dtype=np.int64)
    for p in range(count):
        for i in range(int((box[p, 0] - lo_w) / cell), int((box[p, 1] - lo_w) / cell) + 1):
            for j in range(int((box[p, 2] - lo_z) / cell), int((box[p, 3] - lo_z) / cell) + 1):
                c = min(i, ncw - 1) * ncz + min(j, ncz - 1)
                cell_panel[fill[c]] = p
                fill[c] += 1
    # 3. each free block's panel less the panels in front of it
    ww = np.empty((2, vcap))
    wz_ = np.empty((2, vcap))
    wd = np.empty((2, vcap))
    # exposed pieces (w, z, d rings and point counts), two sets: before and after a shielder
    sw = np.empty((2, _PIECES, vcap))
    sz = np.empty((2, _PIECES, vcap))
    sd = np.empty((2, _PIECES, vcap))
    sn = np.empty((2, _PIECES), dtype=np.int64)
    seen = np.full(count, -1, dtype=np.int64)
    status = 0
    for p in range(count):
        b = body[p]
        if kind[b] != 0:
            continue
        m = start[p + 1] - start[p]
        for j in range(m):
            sw[0, 0, j] = ring[start[p] + j, 0]
            sz[0, 0, j] = ring[start[p] + j, 1]
            sd[0, 0, j] = ring[start[p] + j, 2]
        sn[0, 0] = m
        pieces = 1
        cur = 0
        i0 = int((box[p, 0] - lo_w) / cell)
        i1 = min(int((box[p, 1] - lo_w) / cell), ncw - 1)
        j0 = int((box[p, 2] - lo_z) / cell)
        j1 = min(int((box[p, 3] - lo_z) / cell), ncz - 1)
        for c in range((i1 - i0 + 1) * (j1 - j0 + 1)):
            if pieces == 0:
                break
            cc = (i0 + c // (j1 - j0 + 1)) * ncz + j0 + c % (j1 - j0 + 1)
            for t in range(cell_start[cc], cell_start[cc + 1]):
                s = cell_panel[t]
                if s == p or seen[s] == p or body[s] == b:
                    continue
                seen[s] = p
                if (box[s, 4] >= box[p, 5] or box[s, 0] >= box[p, 1] - width
                        or box[s, 1] <= box[p, 0] + width or box[s, 2] >= box[p, 3] - width
                        or box[s, 3] <= box[p, 2] + width):
                    continue  # wholly behind, or beside
                # their overlap, and which is in front there
                for j in range(m):
                    ww[0, j] = ring[start[p] + j, 0]
                    wz_[0, j] = ring[start[p] + j, 1]
                    wd[0, j] = ring[start[p] + j, 2]
                n = m
                src = 0
                ns = start[s + 1] - start[s]
                for k in range(ns):
                    if n < 3:
                        break
                    ox, oz, off = _edge(ring, start[s], ns, k)
                    n = _clip(ww, wz_, wd, dist, src, n, ox, oz, 0.0, off, 0.0)
                    src = 1 - src
                if _sliver(ww, wz_, wd, src, n, width):
                    continue
                _, cw, cz, cd = _area_centroid(ww, wz_, wd, src, n)
                if plane[s, 0] + plane[s, 1] * cw + plane[s, 2] * cz >= cd:
                    continue  # s is behind p
                # p's pieces less s: the part outside each edge of s in turn
                kept = 0
                for g in range(pieces):
                    n = sn[cur, g]
                    for j in range(n):
                        ww[0, j] = sw[cur, g, j]
                        wz_[0, j] = sz[cur, g, j]
                        wd[0, j] = sd[cur, g, j]
                    src = 0
                    for k in range(ns):
                        if n < 3:
                            break
                        if n + 2 >= vcap:
                            status = DRAG_OVERFLOW
                            break
                        ox, oz, off = _edge(ring, start[s], ns, k)
                        out_n = _clip(ww, wz_, wd, dist, src, n, -ox, -oz, 0.0, -off, 0.0)
                        if not _sliver(ww, wz_, wd, 1 - src, out_n, width):
                            if kept == _PIECES:
                                status = DRAG_OVERFLOW
                            else:
                                for j in range(out_n):
                                    sw[1 - cur, kept, j] = ww[1 - src, j]
                                    sz[1 - cur, kept, j] = wz_[1 - src, j]
                                    sd[1 - cur, kept, j] = wd[1 - src, j]
                                sn[1 - cur, kept] = out_n
                                kept += 1
                        n = _clip(ww, wz_, wd, dist, src, n, ox, oz, 0.0, off, 0.0)
                        src = 1 - src
                pieces = kept
                cur = 1 - cur
                if pieces == 0:
                    break
        # 4. p_d on what is left, at its centroid on the panel
        for g in range(pieces):
            n = sn[cur, g]
            for j in range(n):
                ww[0, j] = sw[cur, g, j]
                wz_[0, j] = sz[cur, g, j]
                wd[0, j] = sd[cur, g, j]
            area, cw, cz, cd = _area_centroid(ww, wz_, wd, 0, n)
            if area <= 0.0:
                continue
            rx = cw * wx + cz * up[0] + cd * flow[0] - q[b, 0]
            ry = cw * wy + cz * up[1] + cd * flow[1] - q[b, 1]
            rz = cw * wz + cz * up[2] + cd * flow[2] - q[b, 2]
            f0 = pressure * area * flow[0]
            f1 = pressure * area * flow[1]
            f2 = pressure * area * flow[2]
            out[b, 0] += f0
            out[b, 1] += f1
            out[b, 2] += f2
            out[b, 3] += ry * f2 - rz * f1
            out[b, 4] += rz * f0 - rx * f2
            out[b, 5] += rx * f1 - ry * f0
    return status


@nb.njit(inline="always")
def _edge(ring, s0, m, k):
    """Outward normal (dz, -dw) of edge k of the counter-clockwise ring ring[s0:s0 + m] in
    (w, z) and the offset of its line: inside is ox w + oz z <= off."""
    a = s0 + k
    a1 = s0 + (k + 1) % m
    ox = ring[a1, 1] - ring[a, 1]
    oz = ring[a, 0] - ring[a1, 0]
    return ox, oz, ox * ring[a, 0] + oz * ring[a, 1]
