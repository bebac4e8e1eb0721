"""A third route to a step's solution: semismooth Newton on the Alart-Curnier function, with
a proximal term and a line search.

For the local problem u = W r + q (FCLIB order [normal, tangent(s)] per contact, see
saxum.solver.residual) the Coulomb law holds iff F(r) = 0, with per contact alpha
    F_N = r_N - max(0, r_N - rho_alpha u_N),
    F_T = r_T - proj_D(mu_alpha max(0, r_N)) (r_T - rho_alpha u_T),
proj_D(R) the projection on the disk (2D: the segment) of radius R (P. Alart, A. Curnier, "A
mixed formulation for frictional contact problems prone to Newton like solution methods",
CMAME 92, 1991), rho_alpha = 1 / (largest diagonal entry of W_alpha alpha), so that rho W is of
order one. F is piecewise smooth; each iteration solves
    (J + sigma I) d = -F,   J = dF/dr + dF/du W   (an element of the generalized Jacobian),
with sigma the proximal regularization (W of rigid blocks is singular: more unknowns than
degrees of freedom), and takes the longest step t in 1, 1/2, ... with
||F(r + t d)||^2 <= (1 - 1e-4 t) ||F(r)||^2 (Armijo). sigma is multiplied by 10 when no step
decreases ||F|| and divided by 10 after a full step (V. Acary, M. Bremond, O. Huber, "On
solving contact problems with Coulomb friction: formulations and numerical comparisons",
2018: the globalized and regularized semismooth Newton methods of their comparison). The
linear systems are sparse (scipy's SuperLU on J + sigma I, as sparse as W).

Where this serves: steps at the friction threshold on which Gauss-Seidel crawls (docs/method.md):
from NLGS's iterate there Newton crawls too (the shaken stack's capped step: natural-map error
4.1e-5 -> 2.4e-5), from zero impulses it reaches 2.4e-9 in 1 s (benchmarks/convergence.py,
stack-shaken). The iterate of least natural-map error is returned.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .conic import ConicResult
from .residual import natural_map_error

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = ["alart_curnier", "alart_curnier_newton", "proximal_point"]

_ARMIJO = 1e-4
"""Sufficient decrease of ||F||^2 per unit step."""
_HALVINGS = 20
"""Step halvings before the proximal term is raised."""
_SIGMA = (1e-12, 1e-6, 1e8)
"""Proximal regularization: least, first, largest (relative to rho W, of order one)."""
_PROXIMAL = 1e-3
"""proximal_point's sigma relative to W's largest diagonal entry: on the shaken 3D L wall's
steps above the tolerance each subproblem is then solved to 1e-13 in 5-20 Newton iterations,
and the outer iterations move 1e-3 to 3e-3 of |r| each; with 1e-2 they move ten times less,
with 1e-4 the subproblems take 40 iterations and more (docs/method.md, (f))."""
_INNER = 40
"""Newton iterations at most per proximal subproblem..."""
_INNER_TOLERANCE = 1e-13
"""... and its natural-map error: solved to round-off, as the outer map's fixed point is the
solution only where the subproblems are solved exactly."""


def alart_curnier(r: np.ndarray, w: sp.csr_matrix, q: np.ndarray, mu: np.ndarray,
                  spacedim: int, rho: np.ndarray):
    """(F, A, B): the Alart-Curnier function F(r) of the module doc (flat) and the blocks
    A = dF/dr, B = dF/du (contacts, spacedim, spacedim) of an element of its generalized
    Jacobian, J = A + B W."""
    d = spacedim
    rr = r.reshape(-1, d)
    uu = (w @ r + q).reshape(-1, d)
    m = rr.shape[0]
    f = np.empty_like(rr)
    a = rr[:, 0] - rho * uu[:, 0]
    pressed = a > 0.0
    f[:, 0] = rr[:, 0] - np.where(pressed, a, 0.0)
    z = rr[:, 1:] - rho[:, None] * uu[:, 1:]
    norm_z = np.linalg.norm(z, axis=1)
    radius = mu * np.maximum(rr[:, 0], 0.0)
    inside = norm_z <= radius
    safe = np.where(norm_z > 0.0, norm_z, 1.0)
    scale = np.where(inside, 1.0, radius / safe)
    f[:, 1:] = rr[:, 1:] - scale[:, None] * z
    n = z / safe[:, None]
    eye = np.eye(d - 1)
    # d proj / dz: I inside the disk, (R / |z|) (I - n n^T) outside
    dproj = np.where(inside[:, None, None], eye[None],
                     scale[:, None, None] * (eye[None] - n[:, :, None] * n[:, None, :]))
    a_blocks = np.zeros((m, d, d))
    b_blocks = np.zeros((m, d, d))
    a_blocks[:, 0, 0] = 1.0 - pressed
    b_blocks[:, 0, 0] = rho * pressed
    a_blocks[:, 1:, 1:] = eye[None] - dproj
    b_blocks[:, 1:, 1:] = rho[:, None, None] * dproj
    # d proj / d r_N = n mu outside the disk (where r_N > 0)
    a_blocks[:, 1:, 0] = np.where(inside[:, None], 0.0, -n * (mu * (rr[:, 0] > 0.0))[:, None])
    return f.ravel(), a_blocks, b_blocks


def _block_diagonal(blocks: np.ndarray) -> sp.csr_matrix:
    import scipy.sparse as sp

    m, d, _ = blocks.shape
    base = d * np.arange(m)[:, None, None]
    rows = np.broadcast_to(base + np.arange(d)[None, :, None], blocks.shape)
    cols = np.broadcast_to(base + np.arange(d)[None, None, :], blocks.shape)
    return sp.csr_matrix((blocks.ravel(), (rows.ravel(), cols.ravel())), shape=(m * d, m * d))


def alart_curnier_newton(w: sp.spmatrix, q: np.ndarray, mu: np.ndarray, spacedim: int,
                         r0: np.ndarray | None = None, tolerance: float = 1e-8,
                         max_iterations: int = 100) -> ConicResult:
    """Semismooth Newton of the module doc on u = W r + q from r0 (zero if None), until the
    natural-map error ||F_nat(r)|| / ||q|| (saxum.solver.residual) is <= tolerance, after
    max_iterations iterations, or when no step decreases ||F|| even with the largest proximal
    term (the natural-map error may stay where it is for tens of iterations while ||F|| falls:
    the shaken stack's step, 15 iterations at 0.11 from zero impulses, then 2.4e-9 after 50).
    Returns the iterate of least natural-map error (ConicResult: interior_iterations counts
    the linear solves)."""
    import scipy.sparse as sp  # ~0.3 s with its linalg: imported by the runs that use Newton
    import scipy.sparse.linalg as spla

    w = sp.csr_matrix(w, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    mu = np.asarray(mu, dtype=np.float64)
    if q.size == 0:
        return ConicResult(np.zeros(0), 0, 0, 0.0)
    d = spacedim
    rho = 1.0 / np.maximum(w.diagonal().reshape(-1, d).max(axis=1), 1e-300)
    r = np.zeros(q.size) if r0 is None else np.array(r0, dtype=np.float64)
    f, a_blocks, b_blocks = alart_curnier(r, w, q, mu, d, rho)
    merit = float(f @ f)
    best, best_r = natural_map_error(w, q, mu, r, d), r
    identity = sp.identity(q.size, format="csr")
    sigma = _SIGMA[1]
    solves = 0
    it = 0
    while it < max_iterations and best > tolerance:
        it += 1
        jacobian = _block_diagonal(a_blocks) + _block_diagonal(b_blocks) @ w
        step = None
        while step is None and sigma <= _SIGMA[2]:
            solves += 1
            direction = spla.spsolve((jacobian + sigma * identity).tocsc(), -f)
            t = 1.0
            for _ in range(_HALVINGS if np.all(np.isfinite(direction)) else 0):
                trial = r + t * direction
                f_trial, a_trial, b_trial = alart_curnier(trial, w, q, mu, d, rho)
                if f_trial @ f_trial <= (1.0 - _ARMIJO * t) * merit:
                    step = t
                    break
                t *= 0.5
            else:
                sigma *= 10.0
        if step is None:
            break
        if step == 1.0:
            sigma = max(sigma / 10.0, _SIGMA[0])
        r, f, a_blocks, b_blocks = trial, f_trial, a_trial, b_trial
        merit = float(f @ f)
        error = natural_map_error(w, q, mu, r, d)
        if error < best:
            best, best_r = error, r
    return ConicResult(best_r, it, solves, best)


def proximal_point(w: sp.spmatrix, q: np.ndarray, mu: np.ndarray, r0: np.ndarray | None = None,
                   tolerance: float = 1e-8, max_outer: int = 20) -> ConicResult:
    """The proximal point method on the 3D problem u = W r + q (FCLIB order) from r0 (zero if
    None): outer
    iterations r_k+1 solving the Coulomb problem of u = (W + sigma I) r + (q - sigma r_k),
    sigma = _PROXIMAL times W's largest diagonal entry, each by alart_curnier_newton from r_k
    (W + sigma I is positive definite: Newton converges there in a few iterations where on W
    it stalls), until the natural-map error ||F_nat(r)|| / ||q|| of the original problem is
    <= tolerance or after max_outer outer iterations (R. T. Rockafellar, "Monotone operators
    and the proximal point algorithm", SIAM J. Control Optim. 14, 1976; with an inner
    semismooth Newton, the method Acary, Bremond and Huber 2018 find robust on FCLIB). A fixed
    point of the outer map solves the original problem (u's sigma terms cancel). Returns the
    iterate of least natural-map error (ConicResult: iterations, the outer ones;
    interior_iterations, Newton's in all)."""
    import scipy.sparse as sp

    w = sp.csr_matrix(w, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    mu = np.asarray(mu, dtype=np.float64)
    r = np.zeros(q.size) if r0 is None else np.array(r0, dtype=np.float64)
    best, best_r = natural_map_error(w, q, mu, r, 3), r
    sigma = _PROXIMAL * float(w.diagonal().max()) if q.size else 0.0
    shifted = (w + sigma * sp.identity(q.size, format="csr")).tocsr()
    inner = outer = 0
    while outer < max_outer and best > tolerance:
        outer += 1
        result = alart_curnier_newton(shifted, q - sigma * r, mu, 3, r, _INNER_TOLERANCE,
                                      _INNER)
        inner += result.iterations
        r = result.r
        error = natural_map_error(w, q, mu, r, 3)
        if error < best:
            best, best_r = error, r
    return ConicResult(best_r, outer, inner, best)
