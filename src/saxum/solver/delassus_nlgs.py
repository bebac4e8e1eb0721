"""Nonlinear Gauss-Seidel over an assembled Delassus operator: the FCLIB local problem.

Find r, u in R^m (m = spacedim x contacts, FCLIB order [normal, tangent(s)] per contact) with
u = W r + q and each contact on its Coulomb cone (saxum.solver.residual). W is a CSR matrix
whose rows a*d .. a*d+d-1 belong to contact a. A sweep visits the contacts (last first, the
order of the time stepper's NLGS, so that an exported saxum step re-solved from the same start
goes through the same iterates); for contact a it computes
    u_a = q_a + sum_b W_ab r_b   (the current rows of W times r),
removes its own contribution with the symmetric part S_aa = (W_aa + W_aa^T) / 2 of the
diagonal block, u_free = u_a - S_aa r_a, solves the single-contact problem with (S_aa, u_free)
exactly (saxum.solver.local2d / local3d, in saxum's frame (t, n[, s])) and relaxes
r_a <- omega r_new + (1 - omega) r_a. Using S_aa on both sides keeps the fixed point exact
(U = u_free + S_aa r_a = u_a) when W is symmetric only to round-off, as in problems from
Bullet-based codes, while the single-contact solvers can assume a symmetric block.

The sweeps stop when the relative change of the impulses over a sweep,
    ||r - r_prev|| / ||r||   (0 when r = 0 and nothing changed),
drops to `tolerance`, or after `max_iterations` sweeps. That test is the solver's own; the
error it reports is the natural-map residual of saxum.solver.residual, computed afterwards
from r alone.
"""

import math
from dataclasses import dataclass

import numba as nb
import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from .local2d import solve_contact_2d
from .local3d import solve_contact_3d
from .residual import natural_map_error

__all__ = ["DelassusNLGS", "DelassusReport"]


@dataclass(frozen=True)
class DelassusReport:
    """Result of a solve: r and u = W r + q [FCLIB order], sweeps, final relative change
    (the stopping test), natural-map error ||F_nat(r)|| / ||q||, converged (change <=
    tolerance)."""

    r: np.ndarray
    u: np.ndarray
    iterations: int
    change: float
    error: float
    converged: bool


@dataclass
class DelassusNLGS:
    """tolerance [-] on the relative change of r per sweep, max_iterations sweeps,
    relaxation omega in (0, 1]."""

    tolerance: float = 1e-12
    max_iterations: int = 100_000
    relaxation: float = 1.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.tolerance) and self.tolerance > 0.0):
            raise InputError(f"tolerance must be > 0, got {self.tolerance}")
        if self.max_iterations < 1:
            raise InputError(f"max_iterations must be >= 1, got {self.max_iterations}")
        if not (0.0 < self.relaxation <= 1.0):
            raise InputError(f"relaxation must be in (0, 1], got {self.relaxation}")

    def solve(self, w: sp.spmatrix, q: np.ndarray, mu: np.ndarray, spacedim: int,
              r: np.ndarray | None = None) -> DelassusReport:
        """Solve u = W r + q, r on the cones of mu, starting from r (zero if None)."""
        if spacedim not in (2, 3):
            raise InputError(f"spacedim must be 2 or 3, got {spacedim}")
        w = sp.csr_matrix(w, dtype=np.float64, copy=True)  # sum_duplicates works in place
        w.sum_duplicates()
        q = np.ascontiguousarray(q, dtype=np.float64)
        mu = np.ascontiguousarray(mu, dtype=np.float64)
        m = q.size
        if w.shape != (m, m) or m != spacedim * mu.size:
            raise InputError(f"W {w.shape}, q ({m}) and mu ({mu.size}) do not match for "
                             f"spacedim {spacedim}")
        r = np.zeros(m) if r is None else np.array(r, dtype=np.float64)
        if r.shape != (m,):
            raise InputError(f"the starting r has {r.size} components, the problem {m}")
        # one signature for the compiled kernels, whatever scipy's index dtype
        indptr = w.indptr.astype(np.int64)
        indices = w.indices.astype(np.int64)
        data = np.ascontiguousarray(w.data)
        blocks = diagonal_blocks(indptr, indices, data, spacedim, mu.size)
        bad = np.flatnonzero(~(blocks[:, 1, 1] > 0.0))
        if bad.size:
            raise InputError(f"contact {bad[0]}: the diagonal block of W has W_nn = "
                             f"{blocks[bad[0], 1, 1]:g}, it must be positive")
        iterations, change = nlgs_delassus(indptr, indices, data, q, mu, blocks, r, np.empty(m),
                                           self.tolerance, self.max_iterations,
                                           self.relaxation)
        return DelassusReport(r=r, u=w @ r + q, iterations=iterations, change=change,
                              error=natural_map_error(w, q, mu, r, spacedim),
                              converged=change <= self.tolerance)


@nb.njit(inline="always")
def _fclib_index(i):
    """Component of saxum's frame (t, n, s) -> its place in FCLIB's [n, t, s]."""
    return 1 if i == 0 else (0 if i == 1 else i)


@nb.njit(cache=True)
def diagonal_blocks(indptr, indices, data, dim, count):
    """S_aa = (W_aa + W_aa^T) / 2 per contact, in saxum's frame, shape (count, dim, dim)."""
    blocks = np.zeros((count, dim, dim))
    for a in range(count):
        for i in range(dim):
            row = a * dim + _fclib_index(i)
            for k in range(indptr[row], indptr[row + 1]):
                col = indices[k] - a * dim
                if 0 <= col < dim:
                    j = _fclib_index(col)
                    blocks[a, i, j] += 0.5 * data[k]
                    blocks[a, j, i] += 0.5 * data[k]
    return blocks


@nb.njit(cache=True)
def nlgs_delassus(indptr, indices, data, q, mu, blocks, r, r_prev, tolerance, max_iterations,
                  relaxation):
    """NLGS sweeps (module doc); r [FCLIB order] is the start and the result, r_prev work
    memory of the same size. Returns (sweeps done, final relative change)."""
    count, dim = blocks.shape[0], blocks.shape[1]
    u_loc = np.zeros(3)
    r_loc = np.zeros(3)
    r_old = np.zeros(3)
    change = math.inf
    it = 0
    while it < max_iterations:
        it += 1
        r_prev[:] = r
        for k in range(count):
            a = count - 1 - k
            s = blocks[a]
            for i in range(dim):
                row = a * dim + _fclib_index(i)
                ui = q[row]
                for p in range(indptr[row], indptr[row + 1]):
                    ui += data[p] * r[indices[p]]
                u_loc[i] = ui
                r_old[i] = r[row]
            for i in range(dim):
                for j in range(dim):
                    u_loc[i] -= s[i, j] * r_old[j]
            if dim == 2:
                rt, rn = solve_contact_2d(s[0, 0], s[0, 1], s[1, 1], u_loc[0], u_loc[1], mu[a])
                r_loc[0] = rt
                r_loc[1] = rn
            else:
                r_loc[:] = r_old
                solve_contact_3d(s, u_loc, mu[a], r_loc)
            for i in range(dim):
                r[a * dim + _fclib_index(i)] = (relaxation * r_loc[i]
                                                + (1.0 - relaxation) * r_old[i])
        num = 0.0
        den = 0.0
        for i in range(r.size):
            num += (r[i] - r_prev[i]) ** 2
            den += r[i] ** 2
        change = 0.0 if num == 0.0 else (math.sqrt(num / den) if den > 0.0 else math.inf)
        if change <= tolerance:
            break
    return it, change
