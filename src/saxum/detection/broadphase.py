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

__all__ = ["bounding_boxes", "grid_pairs", "grid_pairs_parallel", "sort_pairs"]


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
    i0 = np.zeros((n, 3), np.int64)
    i1 = np.zeros((n, 3), np.int64)
    entries = _cells(0, n, lo, hi, large, cell, i0, i1)
    start, e_body, e_cell, mask = _grid(large, i0, i1, entries)
    count = _small_pairs(0, n, lo, hi, mobile, large, i0, i1, start, e_body, e_cell, mask,
                         out)
    return _large_pairs(lo, hi, mobile, large, out, count)


_GRID_BODIES = 2048
"""Bodies per block of grid_pairs_parallel."""


@nb.njit(parallel=True, cache=True)
def grid_pairs_parallel(lo, hi, mobile, large, cell, out, scratch):
    """grid_pairs on numba's threads, the same pairs in the same order: the bodies' cells by
    blocks of _GRID_BODIES bodies in parallel, the grid filled in the bodies' order (one
    thread), each block's pairs into its own share of the rows of scratch (as long as out)
    in parallel, copied in the blocks' order into out, then the large bodies' pairs.
    Returns as grid_pairs: more than len(out) where out or a block's share of scratch is
    short (the caller then enlarges both to twice that and calls again)."""
    n = lo.shape[0]
    blocks = -(-n // _GRID_BODIES)
    i0 = np.zeros((n, 3), np.int64)
    i1 = np.zeros((n, 3), np.int64)
    found = np.zeros(blocks, np.int64)
    for k in nb.prange(blocks):
        found[k] = _cells(k * _GRID_BODIES, min(n, (k + 1) * _GRID_BODIES), lo, hi, large,
                          cell, i0, i1)
    start, e_body, e_cell, mask = _grid(large, i0, i1, found.sum())
    room = scratch.shape[0] // blocks
    for k in nb.prange(blocks):
        found[k] = _small_pairs(k * _GRID_BODIES, min(n, (k + 1) * _GRID_BODIES), lo, hi,
                                mobile, large, i0, i1, start, e_body, e_cell, mask,
                                scratch[k * room:(k + 1) * room])
    if found.max() > room:  # blocks x the most is more than len(scratch) == len(out)
        return blocks * found.max()
    first = np.zeros(blocks + 1, np.int64)
    for k in range(blocks):
        first[k + 1] = first[k] + found[k]
    for k in nb.prange(blocks):
        for p in range(found[k]):
            out[first[k] + p, 0] = scratch[k * room + p, 0]
            out[first[k] + p, 1] = scratch[k * room + p, 1]
    return _large_pairs(lo, hi, mobile, large, out, first[blocks])


@nb.njit(inline="always")
def _cells(b0, b1, lo, hi, large, cell, i0, i1):
    """The first and last cells i0, i1 of the small bodies b0 .. b1 - 1; returns how many
    cells they cover in all."""
    entries = 0
    for b in range(b0, b1):
        if large[b]:
            continue
        for d in range(lo.shape[1]):
            i0[b, d] = _cell(lo[b, d], cell)
            i1[b, d] = _cell(hi[b, d], cell)
        entries += (i1[b, 0] - i0[b, 0] + 1) * (i1[b, 1] - i0[b, 1] + 1) * (i1[b, 2] - i0[b, 2]
                                                                            + 1)
    return entries


@nb.njit(inline="always")
def _grid(large, i0, i1, entries):
    """The hashed grid of the small bodies' cells, in the bodies' order: (start, e_body,
    e_cell, mask), bucket k's entries start[k] .. start[k + 1] - 1."""
    n = large.shape[0]
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
    return start, e_body, e_cell, mask


@nb.njit(inline="always")
def _small_pairs(b0, b1, lo, hi, mobile, large, i0, i1, start, e_body, e_cell, mask, out):
    """The pairs (i, j > i) of the small bodies i = b0 .. b1 - 1 into out (as many as fit);
    returns how many."""
    cap = out.shape[0]
    count = 0
    for i in range(b0, b1):
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
    return count


@nb.njit(inline="always")
def _large_pairs(lo, hi, mobile, large, out, count):
    """The pairs of the large bodies, each against every body (directly), into out from row
    count on (as many as fit); returns count plus how many."""
    cap = out.shape[0]
    n = lo.shape[0]
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
