"""The second solver family: De Saxce's fixed point on the friction threshold, each convex
subproblem solved by an interior-point conic solver (Clarabel).

For the local problem u = W r + q (FCLIB order [normal, tangent(s)] per contact, see
saxum.solver.residual) the Coulomb law is the complementarity K* ∋ u + s e_N ⊥ r ∈ K with
s_alpha = mu_alpha |u_T,alpha| (De Saxce's modified velocity). With s frozen it is the
optimality condition of the convex problem
    minimize 1/2 r^T W r + (q + s e_N)^T r   over r in K = prod_alpha {|r_T| <= mu_alpha r_N}
(V. Acary, F. Cadoux, C. Lemarechal, J. Malick, "A formulation of the linear discrete Coulomb
friction problem via convex optimization", ZAMM 91, 2011), whose velocities u are unique even
where W is singular and the impulses are not (a statically indeterminate assembly, contacts on
the cone's edge without slip: the steps where Gauss-Seidel crawls, docs/method.md). The fixed
point iterates s <- mu |u_T(r(s))| until the natural-map error of the Coulomb problem reaches
the tolerance (a contraction for small mu; Acary, Bremond and Huber, "On solving contact
problems with Coulomb friction: formulations and numerical comparisons", 2018, compare it on
FCLIB as the "fixed point on the friction threshold"). The map s -> mu |u_T(r(s))| converges
linearly, at 0.4-0.9 per iteration on the FCLIB problems: Anderson's acceleration (memory
_MEMORY; H. Walker, P. Ni, "Anderson acceleration for fixed-point iterations", SIAM J. Numer.
Anal. 49, 2011) extrapolates s from the last iterates and their residuals g(s) - s, clipped at
s >= 0.

Each subproblem is a sparse conic quadratic program for Clarabel (P. Goulart, Y. Chen,
"Clarabel: an interior-point solver for conic programs with quadratic objectives", 2024):
variables r, constraints D r in a product of cones, D per contact (mu r_N, r_T[, r_S]) in the
second-order cone (3D), (mu r_N - r_T, mu r_N + r_T) >= 0 (2D, a polyhedral cone), r_T = 0 and
r_N >= 0 for mu = 0. W is symmetrized ((W + W^T) / 2: problems from Bullet-based codes are
symmetric only to round-off) and the problem scaled to unit W and q, so that Clarabel's
absolute tolerances mean the same on every problem. The solver is built once and only its
linear term is updated between fixed-point iterations (the KKT structure is kept).
An interior point ends at ~1e-7 of complementarity on degenerate problems: the callers polish
with Gauss-Seidel sweeps from it (saxum.fclib, saxum.solver.hybrid).
"""

import math
from dataclasses import dataclass

import clarabel
import numpy as np
import scipy.sparse as sp

from .residual import natural_map_error

__all__ = ["ConicResult", "delassus_conic"]

_INNER_TOLERANCE = 1e-12
"""Clarabel's gap and feasibility tolerances on the scaled problem (unit W and q)."""
_MEMORY = 5
"""Past iterates of s that Anderson's acceleration combines."""
_STALE = 6
"""Fixed-point iterations in a row without a smaller error after which the iteration stops:
on the friction threshold the map can leave the error where it is (docs/method.md)."""


@dataclass(frozen=True)
class ConicResult:
    """r [FCLIB order] (the iterate of least error), fixed-point iterations, interior-point
    iterations in all, natural-map error ||F_nat(r)|| / ||q|| of the Coulomb problem."""

    r: np.ndarray
    iterations: int
    interior_iterations: int
    error: float


def cone_constraints(mu: np.ndarray, spacedim: int) -> tuple[sp.csc_matrix, list]:
    """(A, cones) with -A r in the cones <=> every r_alpha in its Coulomb cone (module doc);
    rows: the zero cone (tangents of mu = 0), the nonnegative orthant (normals of mu = 0 and
    the 2D cones' two faces), then one second-order cone of 3 rows per 3D contact."""
    d = spacedim
    n = mu.size
    frictionless = np.flatnonzero(mu == 0.0)
    rough = np.flatnonzero(mu > 0.0)
    rows, cols, vals = [], [], []
    k = 0
    # zero cone: r_T = 0 for mu = 0
    tangents = (d * frictionless[:, None] + np.arange(1, d)).ravel()
    rows.append(k + np.arange(tangents.size))
    cols.append(tangents)
    vals.append(-np.ones(tangents.size))
    k += tangents.size
    nonneg = frictionless.size
    rows.append(k + np.arange(frictionless.size))
    cols.append(d * frictionless)
    vals.append(-np.ones(frictionless.size))
    k += frictionless.size
    if d == 2:
        # mu r_N -+ r_T >= 0: two rows per contact, each on r_N and r_T
        face = k + 2 * np.arange(rough.size)
        for sign, offset in ((1.0, 0), (-1.0, 1)):
            rows += [face + offset, face + offset]
            cols += [d * rough, d * rough + 1]
            vals += [-mu[rough], sign * np.ones(rough.size)]
        k += 2 * rough.size
        nonneg += 2 * rough.size
    else:
        block = k + 3 * np.arange(rough.size)
        rows += [block, block + 1, block + 2]
        cols += [d * rough, d * rough + 1, d * rough + 2]
        vals += [-mu[rough], -np.ones(rough.size), -np.ones(rough.size)]
        k += 3 * rough.size
    a = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(k, d * n))
    cones = []
    if tangents.size:
        cones.append(clarabel.ZeroConeT(int(tangents.size)))
    if nonneg:
        cones.append(clarabel.NonnegativeConeT(int(nonneg)))
    if d == 3:
        cones += [clarabel.SecondOrderConeT(3) for _ in range(rough.size)]
    return a, cones


def _settings() -> "clarabel.DefaultSettings":
    s = clarabel.DefaultSettings()
    s.verbose = False
    s.tol_gap_abs = _INNER_TOLERANCE
    s.tol_gap_rel = _INNER_TOLERANCE
    s.tol_feas = _INNER_TOLERANCE
    s.tol_ktratio = 1e-10
    return s


def threshold(w: sp.spmatrix, q: np.ndarray, mu: np.ndarray, r: np.ndarray,
              spacedim: int) -> np.ndarray:
    """s_alpha = mu_alpha |u_T,alpha| [velocity] with u = W r + q."""
    u = (w @ r + q).reshape(-1, spacedim)
    return mu * np.sqrt(np.einsum("ij,ij->i", u[:, 1:], u[:, 1:]))


def delassus_conic(w: sp.spmatrix, q: np.ndarray, mu: np.ndarray, spacedim: int,
                   r0: np.ndarray | None = None, tolerance: float = 1e-8,
                   max_iterations: int = 50) -> ConicResult:
    """The fixed point of the module doc from s = mu |u_T(r0)| (s = 0 if r0 is None), until
    the natural-map error (with W as given) is <= tolerance, after max_iterations
    fixed-point iterations, when s no longer changes (to 1e-12 of its size), or after _STALE
    iterations in a row without a smaller error."""
    w = sp.csr_matrix(w, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    m = q.size
    if m == 0:
        return ConicResult(np.zeros(0), 0, 0, 0.0)
    sym = (0.5 * (w + w.T)).tocsc()
    w_scale = float(np.abs(sym.diagonal()).max()) or 1.0
    q_scale = float(np.abs(q).max()) or 1.0
    impulse_scale = q_scale / w_scale
    p = sp.triu(sym / w_scale, format="csc")
    a, cones = cone_constraints(mu, spacedim)
    b = np.zeros(a.shape[0])
    if r0 is None:
        s = np.zeros(mu.size)
        best_r, best = np.zeros(m), natural_map_error(w, q, mu, np.zeros(m), spacedim)
    else:
        best_r = np.array(r0, dtype=np.float64)
        best = natural_map_error(w, q, mu, best_r, spacedim)
        s = threshold(sym, q, mu, best_r, spacedim)
    solver = None
    interior = 0
    history_s, history_g = [], []
    it = 0
    stale = 0
    while it < max_iterations and best > tolerance and stale < _STALE:
        it += 1
        c = q.copy()
        c[::spacedim] += s
        c /= q_scale
        if solver is None:
            solver = clarabel.DefaultSolver(p, c, a, b, cones, _settings())
        else:
            solver.update(q=c)
        sol = solver.solve()
        interior += sol.iterations
        r = impulse_scale * np.asarray(sol.x)
        if not np.all(np.isfinite(r)):
            break
        error = natural_map_error(w, q, mu, r, spacedim)
        stale += 1
        if error < best:
            best, best_r, stale = error, r, 0
        g = threshold(sym, q, mu, r, spacedim)
        if np.linalg.norm(g - s) <= 1e-12 * np.linalg.norm(g):
            break
        s = _anderson(s, g, history_s, history_g)
    return ConicResult(best_r, it, interior, best if math.isfinite(best) else math.inf)


def _anderson(s: np.ndarray, g: np.ndarray, history_s: list, history_g: list) -> np.ndarray:
    """The next s from the iterate s, its image g = g(s) and the last _MEMORY pairs (updated
    here): s' = g - dG gamma, gamma the least-squares fit of the residual f = g - s by the
    differences dF of past residuals (Walker and Ni 2011, type II), clipped at 0."""
    history_s.append(s)
    history_g.append(g)
    if len(history_s) > _MEMORY + 1:
        history_s.pop(0)
        history_g.pop(0)
    if len(history_s) < 2:
        return g
    f = np.array([gg - ss for ss, gg in zip(history_s, history_g, strict=True)])
    d_f = np.diff(f, axis=0).T
    d_g = np.diff(np.array(history_g), axis=0).T
    gamma, *_ = np.linalg.lstsq(d_f, f[-1], rcond=1e-12)
    return np.maximum(g - d_g @ gamma, 0.0)
