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

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import clarabel
    import scipy.sparse as sp

from .residual import natural_map

__all__ = ["ConicResult", "body_conic", "cone_rows", "delassus_conic"]

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


def cone_rows(mu: np.ndarray, spacedim: int, dual: bool) -> tuple[sp.csc_matrix, list]:
    """(D, cones) with D x in the cones <=> every x_alpha (FCLIB order) in its Coulomb cone K
    (dual False: |x_T| <= mu x_N) or in the dual cone K* (dual True: mu |x_T| <= x_N). Rows:
    the zero cone (x_T = 0 in K for mu = 0), the nonnegative orthant (x_N >= 0 for mu = 0; the
    2D cones' two faces, K: mu x_N -+ x_T, K*: x_N -+ mu x_T), then one second-order cone per
    3D contact (K: (mu x_N, x_T, x_S), K*: (x_N, mu x_T, mu x_S))."""
    import clarabel  # with scipy.sparse, ~0.3 s: imported by the runs that solve a cone
    import scipy.sparse as sp

    d = spacedim
    frictionless = np.flatnonzero(mu == 0.0)
    rough = np.flatnonzero(mu > 0.0)
    m_rough = mu[rough]
    one = np.ones(rough.size)
    normal, tangent = (one, m_rough) if dual else (m_rough, one)
    rows, cols, vals = [], [], []
    k = 0
    tangents = np.empty(0, dtype=np.int64)
    if not dual:  # x_T = 0 for mu = 0 (in K* the tangent velocity is free)
        tangents = (d * frictionless[:, None] + np.arange(1, d)).ravel()
        rows.append(k + np.arange(tangents.size))
        cols.append(tangents)
        vals.append(np.ones(tangents.size))
        k += tangents.size
    rows.append(k + np.arange(frictionless.size))
    cols.append(d * frictionless)
    vals.append(np.ones(frictionless.size))
    k += frictionless.size
    nonneg = frictionless.size
    if d == 2:
        face = k + 2 * np.arange(rough.size)
        for sign, offset in ((-1.0, 0), (1.0, 1)):
            rows += [face + offset, face + offset]
            cols += [d * rough, d * rough + 1]
            vals += [normal, sign * tangent]
        k += 2 * rough.size
        nonneg += 2 * rough.size
    else:
        block = k + 3 * np.arange(rough.size)
        rows += [block, block + 1, block + 2]
        cols += [d * rough, d * rough + 1, d * rough + 2]
        vals += [normal, tangent, tangent]
        k += 3 * rough.size
    matrix = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                           shape=(k, d * mu.size))
    cones = []
    if tangents.size:
        cones.append(clarabel.ZeroConeT(int(tangents.size)))
    if nonneg:
        cones.append(clarabel.NonnegativeConeT(int(nonneg)))
    if d == 3:
        cones += [clarabel.SecondOrderConeT(3) for _ in range(rough.size)]
    return matrix, cones


def _settings() -> clarabel.DefaultSettings:
    import clarabel

    s = clarabel.DefaultSettings()
    s.verbose = False
    s.tol_gap_abs = _INNER_TOLERANCE
    s.tol_gap_rel = _INNER_TOLERANCE
    s.tol_feas = _INNER_TOLERANCE
    s.tol_ktratio = 1e-10
    return s


def _threshold(u: np.ndarray, mu: np.ndarray, spacedim: int) -> np.ndarray:
    """s_alpha = mu_alpha |u_T,alpha| [velocity]."""
    u = u.reshape(-1, spacedim)
    return mu * np.sqrt(np.einsum("ij,ij->i", u[:, 1:], u[:, 1:]))


def _fixed_point(subproblem, velocity, q_norm, mu, spacedim, r0, tolerance, max_iterations):
    """The fixed point of the module doc. subproblem(s) -> (r, interior-point iterations) solves
    the convex problem for the threshold s; velocity(r) -> u, the Coulomb problem's velocity
    of impulses r; q_norm scales the error (||q||, or 1 if q = 0). From s of r0."""
    def error_of(r):
        norm = float(np.linalg.norm(natural_map(r, velocity(r), mu, spacedim)))
        return norm / q_norm

    best_r = r0
    best = error_of(r0)
    s = _threshold(velocity(r0), mu, spacedim)
    interior = 0
    history_s, history_g = [], []
    it = 0
    stale = 0
    while it < max_iterations and best > tolerance and stale < _STALE:
        it += 1
        r, steps = subproblem(s)
        interior += steps
        if not np.all(np.isfinite(r)):
            break
        error = error_of(r)
        stale += 1
        if error < best:
            best, best_r, stale = error, r, 0
        g = _threshold(velocity(r), mu, spacedim)
        if np.linalg.norm(g - s) <= 1e-12 * np.linalg.norm(g):
            break
        s = _anderson(s, g, history_s, history_g)
    return ConicResult(best_r, it, interior, best if math.isfinite(best) else math.inf)


def delassus_conic(w: sp.spmatrix, q: np.ndarray, mu: np.ndarray, spacedim: int,
                   r0: np.ndarray | None = None, tolerance: float = 1e-8,
                   max_iterations: int = 50) -> ConicResult:
    """The fixed point of the module doc on u = W r + q (FCLIB's local problem) from
    s = mu |u_T(r0)| (r0 = 0 if None), until the natural-map error (with W as given) is <=
    tolerance, after max_iterations fixed-point iterations, when s no longer changes (to
    1e-12 of its size), or after _STALE iterations in a row without a smaller error."""
    import clarabel  # with scipy.sparse, ~0.3 s: imported by the runs that solve a cone
    import scipy.sparse as sp

    w = sp.csr_matrix(w, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    m = q.size
    if m == 0:
        return ConicResult(np.zeros(0), 0, 0, 0.0)
    sym = (0.5 * (w + w.T)).tocsc()
    w_scale = float(np.abs(sym.diagonal()).max()) or 1.0
    q_scale = float(np.abs(q).max()) or 1.0
    p = sp.triu(sym / w_scale, format="csc")
    d, cones = cone_rows(mu, spacedim, dual=False)
    a = -d
    b = np.zeros(a.shape[0])
    solver = []

    def subproblem(s):
        c = q.copy()
        c[::spacedim] += s
        c /= q_scale
        if not solver:
            solver.append(clarabel.DefaultSolver(p, c, a, b, cones, _settings()))
        else:
            solver[0].update(q=c)
        sol = solver[0].solve()
        return (q_scale / w_scale) * np.asarray(sol.x), sol.iterations

    r0 = np.zeros(m) if r0 is None else np.array(r0, dtype=np.float64)
    return _fixed_point(subproblem, lambda r: w @ r + q, float(np.linalg.norm(q)) or 1.0, mu,
                        spacedim, r0, tolerance, max_iterations)


def body_conic(hstar: sp.csr_matrix, mass: np.ndarray, v_free: np.ndarray, u_shift: np.ndarray,
               mu: np.ndarray, spacedim: int, r0: np.ndarray, tolerance: float = 1e-8,
               max_iterations: int = 50) -> ConicResult:
    """The fixed point in body space, the time stepper's form: with the free degrees of
    freedom's velocities v [m/s, rad/s], masses M = diag(mass) [kg, kg m^2] (> 0), H* the
    rows of the active contacts on them (FCLIB order) and u = H* v + u_shift (u_shift: the
    supports' velocities and the laws' shifts),
        minimize 1/2 (v - v_free)^T M (v - v_free)   subject to   u + s e_N in K*,
    whose multipliers are the impulses R (M (v - v_free) = H*^T R): strictly convex in v, so
    v is unique for each s, and W = H* M^-1 H*^T is never formed (the KKT matrix is as sparse
    as H*). Stops as delassus_conic; the error is the natural-map error with
    ||q|| = ||H* v_free + u_shift||."""
    m = u_shift.size
    if m == 0:
        return ConicResult(np.zeros(0), 0, 0, 0.0)
    import clarabel  # with scipy.sparse, ~0.3 s: imported by the runs that solve a cone
    import scipy.sparse as sp

    hstar = sp.csr_matrix(hstar)
    inv_mass = 1.0 / mass
    q = hstar @ v_free + u_shift
    mass_scale = float(mass.max())
    v_scale = float(max(np.abs(v_free).max(), np.abs(q).max())) or 1.0
    d, cones = cone_rows(mu, spacedim, dual=True)
    a = (-(d @ hstar)).tocsc()
    p = sp.diags(mass / mass_scale, format="csc")
    c = -(mass * v_free) / (mass_scale * v_scale)
    solver = []

    def subproblem(s):
        shifted = u_shift.copy()
        shifted[::spacedim] += s
        b = (d @ shifted) / v_scale
        if not solver:
            solver.append(clarabel.DefaultSolver(p, c, a, b, cones, _settings()))
        else:
            solver[0].update(b=b)
        sol = solver[0].solve()
        return (mass_scale * v_scale) * (d.T @ np.asarray(sol.z)), sol.iterations

    def velocity(r):
        return q + hstar @ (inv_mass * (hstar.T @ r))

    return _fixed_point(subproblem, velocity, float(np.linalg.norm(q)) or 1.0, mu, spacedim,
                        np.array(r0, dtype=np.float64), tolerance, max_iterations)


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
