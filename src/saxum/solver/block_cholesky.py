"""Sparse Cholesky factorization L L^T = P A P^T of a symmetric positive definite matrix A made
of d x d blocks, one block row and column per body (d: a rigid body's dof, 3 in 2D, 6 in
3D), whose analysis (the order P and the pattern of L) is kept for the next matrix with the
same pattern.

The rest solution's Newton matrices (saxum.solver.equilibrium) change their values from one
Newton iteration, and one step, to the next, and keep their pattern as long as the closed
contacts stay the same (an assembly at rest: every step of a shaken wall's phases at rest).
SuperLU (scipy) orders, analyses and factorizes each of them anew, as a general LU of scalars.
Here:
- analysis, once per pattern: a fill-reducing order of the bodies (SuperLU's multiple minimum
  degree on the graph of the bodies, whose matrix has one entry per block), then the pattern of
  L column by column: a column's rows are its own rows of A below the diagonal and the rows of
  its children in the elimination tree, whose parent is a column's first row below the diagonal
  (J. W. H. Liu, "The role of elimination trees in sparse factorization", SIAM J. Matrix Anal.
  Appl. 11 (1990) 134-172);
- numeric factorization, column by column (left-looking): column k is updated by each earlier
  column j with a block in row k, L_ik -= L_ij L_kj^T, found through linked lists of the
  columns by their next row (A. George and J. W. H. Liu, "Computer Solution of Large Sparse
  Positive Definite Systems", Prentice-Hall 1981), then divided by the Cholesky
  factor of its diagonal block; dense d x d blocks throughout.
"""

import math

import numba as nb
import numpy as np

__all__ = ["BlockCholesky", "analyse"]

_KEPT = 4
"""Analyses kept, the latest first (a few patterns that an assembly at rest goes back to)."""


class Analysis:
    """A pattern's order (new[b]: the position of body b in P A P^T) and L's pattern (block
    column k: rows lrow[lptr[k]:lptr[k + 1]], sorted, the diagonal first); amap: the block of L
    that each block of A's pattern fills (-1 above the diagonal of P A P^T)."""

    __slots__ = ("new", "lptr", "lrow", "amap")

    def __init__(self, new, lptr, lrow, amap) -> None:
        self.new, self.lptr, self.lrow, self.amap = new, lptr, lrow, amap


_analyses: list[tuple[np.ndarray, np.ndarray, Analysis]] = []


def analyse(bptr: np.ndarray, blocks: np.ndarray) -> Analysis:
    """The analysis of a symmetric block pattern (block CSC: column c's block rows
    blocks[bptr[c]:bptr[c + 1]], the diagonal among them), the kept one for a pattern among
    the last _KEPT analysed (kept for the process: the result is the same bit for bit with or
    without it)."""
    for kept_ptr, kept_blocks, analysis in _analyses:
        if np.array_equal(kept_ptr, bptr) and np.array_equal(kept_blocks, blocks):
            return analysis
    new = _order(bptr, blocks)
    lptr, lrow, amap = _symbolic(bptr, blocks, new)
    analysis = Analysis(new, lptr, lrow[: lptr[-1]], amap)
    _analyses.insert(0, (bptr.copy(), blocks.copy(), analysis))
    del _analyses[_KEPT:]
    return analysis


def _order(bptr: np.ndarray, blocks: np.ndarray) -> np.ndarray:
    """new[b]: SuperLU's multiple minimum degree order of the bodies (on A + A^T of a matrix
    with the blocks' pattern, diagonally dominant so that it factorizes without pivoting; its
    values play no part in the order)."""
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu

    n = len(bptr) - 1
    column = np.repeat(np.arange(n), np.diff(bptr))
    values = np.where(blocks == column, np.diff(bptr)[column].astype(float), -1.0)
    lu = splu(csc_matrix((values, blocks, bptr), shape=(n, n)), permc_spec="MMD_AT_PLUS_A",
              diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    return lu.perm_c.astype(np.int64)


class BlockCholesky:
    """The factor L of P A P^T (analysis: the pattern's Analysis; values: L's blocks,
    (blocks, d, d))."""

    __slots__ = ("analysis", "values")

    def __init__(self, analysis: Analysis, values: np.ndarray) -> None:
        self.analysis, self.values = analysis, values

    @classmethod
    def factorize(cls, analysis: Analysis, bptr: np.ndarray, data: np.ndarray,
                  indptr: np.ndarray, size: int) -> "BlockCholesky | None":
        """The factor of A given by its scalar CSC data and indptr (block (r, c) of A's pattern
        at data[indptr[size c] + size (its place in column c) + dc * per + dr], per: column
        c's scalar rows; saxum.solver.equilibrium._pattern), None where a pivot is not
        positive (A not positive definite to round-off). size: 3 or 6 (2D and 3D rigid
        bodies: _numeric compiles its loops for these two)."""
        if size not in (3, 6):
            raise ValueError(f"block size {size}: 3 or 6 (a rigid body's dof)")
        a = analysis
        values = np.empty((len(a.lrow), size, size))
        if not _numeric(a.lptr, a.lrow, a.amap, bptr, data, indptr, values):
            return None
        return cls(analysis, values)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """A^-1 rhs for rhs (bodies x d, or flat in that order)."""
        a = self.analysis
        size = self.values.shape[1]
        out = np.empty((len(a.new), size))
        _solve(a.lptr, a.lrow, a.new, self.values, rhs.reshape(-1, size), out)
        return out.reshape(rhs.shape)


@nb.njit(cache=True)
def _symbolic(bptr, blocks, new):
    """(lptr, lrow, amap) of Analysis for the pattern (bptr, blocks) in the order new, lrow
    with room to spare after lptr[-1]. Loops rather than numpy's fancy indexing, slices and
    sort, which took seconds more to compile."""
    n = new.shape[0]
    old = np.empty(n, dtype=np.int64)  # the body in each place of P A P^T
    for body in range(n):
        old[new[body]] = body
    # L's columns in order: the diagonal, then A's rows and the children's rows, sorted
    child = np.empty(n, dtype=np.int64)  # first child of each column (-1: none)
    sibling = np.empty(n, dtype=np.int64)  # next child of the same parent
    mark = np.empty(n, dtype=np.int64)
    for k in range(n):
        child[k] = sibling[k] = mark[k] = -1
    lptr = np.zeros(n + 1, dtype=np.int64)
    lrow = np.empty(bptr[n] + n, dtype=np.int64)
    for k in range(n):
        at = lptr[k]
        if at + n - k > lrow.shape[0]:  # room for the longest column k can have
            grown = np.empty(max(2 * lrow.shape[0], at + n - k), dtype=np.int64)
            for t in range(at):
                grown[t] = lrow[t]
            lrow = grown
        lrow[at] = k
        mark[k] = k
        at += 1
        body = old[k]
        for t in range(bptr[body], bptr[body + 1]):  # A's rows below the diagonal
            i = new[blocks[t]]
            if i > k and mark[i] != k:
                mark[i] = k
                lrow[at] = i
                at += 1
        c = child[k]
        while c >= 0:
            for t in range(lptr[c] + 1, lptr[c + 1]):
                i = lrow[t]
                if mark[i] != k:
                    mark[i] = k
                    lrow[at] = i
                    at += 1
            c = sibling[c]
        for t in range(lptr[k] + 2, at):  # insertion sort: short columns, no sort to compile
            i = lrow[t]
            u = t
            while lrow[u - 1] > i:
                lrow[u] = lrow[u - 1]
                u -= 1
            lrow[u] = i
        lptr[k + 1] = at
        if at > lptr[k] + 1:  # the parent: the first row below the diagonal
            parent = lrow[lptr[k] + 1]
            sibling[k] = child[parent]
            child[parent] = k
    amap = np.empty(bptr[n], dtype=np.int64)
    for j in range(n):
        for t in range(lptr[j], lptr[j + 1]):
            mark[lrow[t]] = t  # where each row is in column j
        body = old[j]
        for t in range(bptr[body], bptr[body + 1]):
            amap[t] = mark[new[blocks[t]]] if new[blocks[t]] >= j else -1
    return lptr, lrow, amap


@nb.njit(cache=True)
def _numeric(lptr, lrow, amap, bptr, data, indptr, values):
    """L's blocks (values, (blocks, d, d)) of A (BlockCholesky.factorize); False at a pivot
    that is not positive."""
    n = lptr.shape[0] - 1
    size = values.shape[1]
    for p in range(values.shape[0]):
        for r in range(size):
            for e in range(size):
                values[p, r, e] = 0.0
    for c in range(n):
        base = indptr[size * c]
        per = indptr[size * c + 1] - base
        for t in range(bptr[c], bptr[c + 1]):
            p = amap[t]
            if p < 0:
                continue
            at = base + size * (t - bptr[c])
            for dc in range(size):
                for dr in range(size):
                    values[p, dr, dc] = data[at + dc * per + dr]
    # the block size a constant of the compiled loops (2D and 3D rigid bodies): half the time
    if size == 3:
        return _left_looking(lptr, lrow, values, 3)
    return _left_looking(lptr, lrow, values, 6)


@nb.njit(inline="always")
def _left_looking(lptr, lrow, values, size):
    """L's blocks in place of P A P^T's lower blocks (values); False at a pivot that is not
    positive."""
    n = lptr.shape[0] - 1
    head = np.empty(n, dtype=np.int64)  # the columns whose next row is k, linked by nxt
    nxt = np.empty(n, dtype=np.int64)
    for k in range(n):
        head[k] = nxt[k] = -1
    cursor = np.zeros(n, dtype=np.int64)  # each column's block in the row being factorized
    pos = np.zeros(n, dtype=np.int64)  # where each row is in the column being factorized
    for k in range(n):
        for t in range(lptr[k], lptr[k + 1]):
            pos[lrow[t]] = t
        j = head[k]
        while j >= 0:
            following = nxt[j]
            p0 = cursor[j]  # L_kj
            for p in range(p0, lptr[j + 1]):
                target = pos[lrow[p]]
                for r in range(size):
                    for s in range(size):
                        acc = 0.0
                        for e in range(size):
                            acc += values[p, r, e] * values[p0, s, e]
                        values[target, r, s] -= acc
            p0 += 1
            cursor[j] = p0
            if p0 < lptr[j + 1]:
                row = lrow[p0]
                nxt[j] = head[row]
                head[row] = j
            j = following
        d = lptr[k]
        for e in range(size):  # the diagonal block's Cholesky factor, lower
            pivot = values[d, e, e]
            for f in range(e):
                pivot -= values[d, e, f] * values[d, e, f]
            if not pivot > 0.0:
                return False
            pivot = math.sqrt(pivot)
            values[d, e, e] = pivot
            for r in range(e + 1, size):
                acc = values[d, r, e]
                for f in range(e):
                    acc -= values[d, r, f] * values[d, e, f]
                values[d, r, e] = acc / pivot
                values[d, e, r] = 0.0
        for p in range(d + 1, lptr[k + 1]):  # L_ik = A_ik L_kk^-T
            for r in range(size):
                for e in range(size):
                    acc = values[p, r, e]
                    for f in range(e):
                        acc -= values[p, r, f] * values[d, e, f]
                    values[p, r, e] = acc / values[d, e, e]
        if lptr[k + 1] > d + 1:
            cursor[k] = d + 1
            row = lrow[d + 1]
            nxt[k] = head[row]
            head[row] = k
    return True


@nb.njit(cache=True)
def _solve(lptr, lrow, new, values, rhs, out):
    """out = A^-1 rhs (bodies x d, in the bodies' own order): L y = P rhs, L^T z = y."""
    n = lptr.shape[0] - 1
    size = values.shape[1]
    y = np.empty((n, size))
    for b in range(n):
        for e in range(size):
            y[new[b], e] = rhs[b, e]
    for k in range(n):
        d = lptr[k]
        for e in range(size):
            acc = y[k, e]
            for f in range(e):
                acc -= values[d, e, f] * y[k, f]
            y[k, e] = acc / values[d, e, e]
        for p in range(d + 1, lptr[k + 1]):
            i = lrow[p]
            for r in range(size):
                acc = 0.0
                for e in range(size):
                    acc += values[p, r, e] * y[k, e]
                y[i, r] -= acc
    for k in range(n - 1, -1, -1):
        d = lptr[k]
        for p in range(d + 1, lptr[k + 1]):
            i = lrow[p]
            for e in range(size):
                acc = 0.0
                for r in range(size):
                    acc += values[p, r, e] * y[i, r]
                y[k, e] -= acc
        for e in range(size - 1, -1, -1):
            acc = y[k, e]
            for f in range(e + 1, size):
                acc -= values[d, f, e] * y[k, f]
            y[k, e] = acc / values[d, e, e]
    for b in range(n):
        for e in range(size):
            out[b, e] = y[new[b], e]
