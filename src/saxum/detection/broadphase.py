"""Broad phase: pairs of bodies whose padded bounding boxes overlap, on a uniform hashed grid.

Cost O(N) in the number of bodies: each small body is entered in the (at most 4 in 2D, 8 in 3D)
cells its box covers; a pair is reported only from the cell that holds the lower corner of the
two boxes' intersection, so it is reported once. The same kernel serves 2D and 3D boxes (in 2D
every box lies in the layer of cells iz = 0). Bodies much larger than the cell (grounds, long
supports) are tested against all bodies directly, which costs O(N) per large body.
"""

import math

import numba as nb
import numpy as np

__all__ = ["bounding_boxes", "grid_pairs", "sort_pairs"]


@nb.njit(cache=True)
def bounding_boxes(wv, vertex_start, pad, lo, hi):
    """Axis-aligned boxes of each body's world vertices wv, enlarged by pad [m] on every side."""
    for b in range(vertex_start.shape[0] - 1):
        for d in range(wv.shape[1]):
            mn = np.inf
            mx = -np.inf
            for k in range(vertex_start[b], vertex_start[b + 1]):
                x = wv[k, d]
                mn = min(mn, x)
                mx = max(mx, x)
            lo[b, d] = mn - pad
            hi[b, d] = mx + pad


@nb.njit(inline="always")
def _overlap(lo, hi, i, j):
    for d in range(lo.shape[1]):
        if lo[i, d] > hi[j, d] or lo[j, d] > hi[i, d]:
            return False
    return True


@nb.njit(inline="always")
def _bucket(ix, iy, iz, mask):
    return ((ix * 73856093) ^ (iy * 19349663) ^ (iz * 83492791)) & mask


@nb.njit(inline="always")
def _cell(x, cell):
    return math.floor(x / cell)


@nb.njit(cache=True)
def grid_pairs(lo, hi, mobile, large, cell, out):
    """Write the pairs (i < j) of overlapping boxes with at least one mobile body into out[:, 0:2].

    lo, hi: boxes [m], shape [n, dim] (dim 2 or 3); mobile, large: bool [n]; cell: grid spacing
    [m], not smaller than any small body's box. Returns the number of pairs found, which may
    exceed len(out): the caller then enlarges out and calls again.
    """
    n = lo.shape[0]
    cap = out.shape[0]
    i0 = np.zeros((n, 3), np.int64)
    i1 = np.zeros((n, 3), np.int64)
    entries = 0
    for b in range(n):
        if large[b]:
            continue
        for d in range(lo.shape[1]):
            i0[b, d] = _cell(lo[b, d], cell)
            i1[b, d] = _cell(hi[b, d], cell)
        entries += (i1[b, 0] - i0[b, 0] + 1) * (i1[b, 1] - i0[b, 1] + 1) * (i1[b, 2] - i0[b, 2]
                                                                            + 1)
    size = 1
    while size < 2 * entries:
        size *= 2
    mask = size - 1
    start = np.zeros(size + 1, np.int64)
    for b in range(n):
        if not large[b]:
            for ix in range(i0[b, 0], i1[b, 0] + 1):
                for iy in range(i0[b, 1], i1[b, 1] + 1):
                    for iz in range(i0[b, 2], i1[b, 2] + 1):
                        start[_bucket(ix, iy, iz, mask) + 1] += 1
    for k in range(size):
        start[k + 1] += start[k]
    fill = start[:-1].copy()
    e_body = np.empty(entries, np.int64)
    e_cell = np.empty((entries, 3), np.int64)
    for b in range(n):
        if not large[b]:
            for ix in range(i0[b, 0], i1[b, 0] + 1):
                for iy in range(i0[b, 1], i1[b, 1] + 1):
                    for iz in range(i0[b, 2], i1[b, 2] + 1):
                        k = fill[_bucket(ix, iy, iz, mask)]
                        e_body[k] = b
                        e_cell[k, 0] = ix
                        e_cell[k, 1] = iy
                        e_cell[k, 2] = iz
                        fill[_bucket(ix, iy, iz, mask)] += 1

    count = 0
    for i in range(n):
        if large[i]:
            continue
        for ix in range(i0[i, 0], i1[i, 0] + 1):
            for iy in range(i0[i, 1], i1[i, 1] + 1):
                for iz in range(i0[i, 2], i1[i, 2] + 1):
                    bk = _bucket(ix, iy, iz, mask)
                    for k in range(start[bk], start[bk + 1]):
                        j = e_body[k]
                        if (j <= i or e_cell[k, 0] != ix or e_cell[k, 1] != iy
                                or e_cell[k, 2] != iz):
                            continue
                        if not (mobile[i] or mobile[j]) or not _overlap(lo, hi, i, j):
                            continue
                        # the cell of the intersection's lower corner: floor(max(a, b) / cell)
                        # is max(floor(a / cell), floor(b / cell)), both already known
                        if (max(i0[i, 0], i0[j, 0]) == ix and max(i0[i, 1], i0[j, 1]) == iy
                                and max(i0[i, 2], i0[j, 2]) == iz):
                            if count < cap:
                                out[count, 0] = i
                                out[count, 1] = j
                            count += 1
    for i in range(n):
        if not large[i]:
            continue
        for j in range(n):
            if j == i or (large[j] and j < i):
                continue
            if (mobile[i] or mobile[j]) and _overlap(lo, hi, i, j):
                if count < cap:
                    out[count, 0] = min(i, j)
                    out[count, 1] = max(i, j)
                count += 1
    return count


@nb.njit(cache=True)
def sort_pairs(pairs, count, n):
    """Sort the first `count` pairs by (i, j), so that contact order does not depend on the grid.
    Pairs are distinct and i < n: a counting sort on i, then each i's j in place by Shell sort
    (gaps 1, 4, 13, ... of Knuth, TAOCP vol. 3, 5.2.1): an insertion sort for a body's few j,
    O(k^1.5) for a large body's k. (np.sort would do, but compiling it, and the slice
    assignment's error message, costs seconds of a first run.)"""
    start = np.zeros(n + 1, np.int64)
    for k in range(count):
        start[pairs[k, 0] + 1] += 1
    for i in range(n):
        start[i + 1] += start[i]
    fill = start[:-1].copy()
    second = np.empty(count, np.int32)
    for k in range(count):
        i = pairs[k, 0]
        second[fill[i]] = pairs[k, 1]
        fill[i] += 1
    for i in range(n):
        lo = start[i]
        hi = start[i + 1]
        gap = 1
        while gap < (hi - lo) // 3:
            gap = 3 * gap + 1
        while gap > 0:
            for k in range(lo + gap, hi):
                j = second[k]
                m = k - gap
                while m >= lo and second[m] > j:
                    second[m + gap] = second[m]
                    m -= gap
                second[m + gap] = j
            gap //= 3
        for k in range(lo, hi):
            pairs[k, 0] = i
            pairs[k, 1] = second[k]
