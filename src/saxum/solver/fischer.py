"""Semismooth Newton on the Fischer-Burmeister function of the second-order cone
complementarity problem of 3D Coulomb friction, globalized by a line search on its merit and
regularized by Levenberg-Marquardt for the rank-deficient W.

Formulation (V. Acary, M. Bremond, O. Huber, "On solving contact problems with Coulomb
friction: formulations and numerical comparisons", Advanced Topics in Nonsmooth Dynamics,
Springer 2018, sec. 3.3, "Fischer-Burmeister function"). With u = W r + q in FCLIB order
[normal, tangents] and De Saxce's change of variable u_hat = u + mu |u_T| e_N (see
saxum.solver.residual), the Coulomb law is K* ∋ u_hat ⊥ r ∈ K, K = {|r_T| <= mu r_N}. The
scalings x = (mu r_N, r_T), y = rho (u_hat_N, mu u_T) (rho > 0: 1 / W's largest diagonal entry
of the contact's block, so that x and y have the same size) map r ∈ K and u_hat ∈ K* onto
the self-dual Lorentz cone L = {|z_bar| <= z_0} with x . y = rho mu r . u_hat, so per contact
    x ∈ L, y ∈ L, x . y = 0  <=>  phi(x, y) = x + y - (x∘x + y∘y)^(1/2) = 0
(M. Fukushima, Z.-Q. Luo, P. Tseng, "Smoothing functions for second-order-cone
complementarity problems", SIAM J. Optim. 12, 2002, Prop. 2.1), with the Jordan product
x∘y = (x . y, x_0 y_bar + y_0 x_bar) and the square root by the spectral decomposition
w = lambda_1 c_1 + lambda_2 c_2, lambda_1,2 = w_0 -+ |w_bar|, c_1,2 = (1, -+ w_bar / |w_bar|) / 2
(ibid., eq. 2.2-2.3). Its Jacobian: d phi / dx = I - 2 S L_x, d phi / dy = I - 2 S L_y, L_x the
arrow matrix [[x_0, x_bar^T], [x_bar, x_0 I]] (dw/dx = 2 L_x) and S the Jacobian of the
square root at w (J.-S. Chen, X. Chen, P. Tseng, "Analysis of nonsmooth vector-valued
functions associated with second-order cones", Math. Program. 101, 2004, Prop. 5.2):
    S = [[b, c e^T], [c e, a I + (b - a) e e^T]],  e = w_bar / |w_bar|,
    a = 1 / (sqrt lambda_2 + sqrt lambda_1),  b, c = (f'(lambda_2) +- f'(lambda_1)) / 2,
f'(lambda) = 1 / (2 sqrt lambda), lambda floored at 1e-14 lambda_2 where x∘x + y∘y lies on
the cone's boundary (the limit of the interior's Jacobians there is bounded; the floor picks a
nearby element). A contact with mu = 0 has the scalar Fischer-Burmeister function
r_N + rho u_N - sqrt(r_N^2 + (rho u_N)^2) and phi_T = r_T.

Globalization and regularization. The merit psi = ||phi||^2 / 2 is continuously
differentiable (Fukushima, Luo, Tseng 2002, Prop. 5.2 on phi's square norm), with gradient
g = J^T phi, J = (d phi / dr) + (d phi / du) W. Each iteration solves the Levenberg-Marquardt
system (J^T J + lambda I) d = -g, lambda = m ||phi|| (N. Yamashita, M. Fukushima, "On the
rate of convergence of the Levenberg-Marquardt method", Computing Suppl. 15, 2001: quadratic
convergence under a local error bound, without isolated solutions, which W of rigid blocks
does not have: more contact unknowns than degrees of freedom), and takes the longest step t
in 1, 1/2, ... with psi(r + t d) <= psi(r) + 1e-4 t g . d (Armijo); m is multiplied by 10
when 30 halvings find no such step or the step is shorter than 0.1, and divided by 10 after
a full step. The linear algebra is
sparse: per-contact 3x3 blocks of d phi / dr and d phi / du times W (scipy.sparse), solved by
SuperLU. The iterate of least natural-map error is returned.

Smoothing Newton (smoothing_newton): Newton on the smoothed function phi_eps(x, y) = x + y -
(x∘x + y∘y + 2 eps^2 e)^(1/2) for a decreasing eps, where the merit above has stationary
points that are not solutions (rank-deficient W at the onset of sliding; docs/method.md, "The
shaken 3D L wall", (e)); J is then factored by a sparse LU of J itself, not J^T J.

2D problems (spacedim 2: [normal, tangent]) are solved as 3D ones with a second tangent of
W = 1 (its row and column otherwise zero) and q = 0: there u_T2 = r_T2, which every solution
has zero (sliding, r_T = -c u_T with c > 0 gives r_T2 = -c r_T2; sticking, u_T = 0), so the
3D problem's solutions are the 2D ones with r_T2 = 0, and their natural maps are the same.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .conic import ConicResult
from .newton import _block_diagonal
from .residual import natural_map_error

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = ["fischer_burmeister", "fischer_burmeister_newton", "smoothing_newton"]

_ARMIJO = 1e-4
"""Sufficient decrease of the merit per unit step and unit directional derivative."""
_HALVINGS = 30
"""Step halvings before the Levenberg-Marquardt multiplier is raised."""
_MULTIPLIER = (1e-8, 1e-2, 1e10)
"""Levenberg-Marquardt multiplier m of lambda = m ||phi||: least, first, largest."""
_SHORT = 0.1
"""A step shorter than this raises the multiplier tenfold too: where phi's Jacobian changes
fast (contacts near the cone's apex or edge) the Gauss-Newton direction is taken in steps of
1e-2 to 1e-3 for tens of iterations (the shaken L wall's steps), a shorter, more gradient-like
direction is taken whole."""
_PATIENCE = 10
"""Iterations after which Newton stops where ||phi|| has not halved: it has reached a
stationary point of the merit that is not a solution (siconosdat_Capsules-i101-404 from zero:
3.5e-7 from iteration 30 to 200; the shaken L wall's steps at the onset of motion,
docs/method.md), where more iterations cost ~0.2 s each on 770 contacts for nothing."""
_LEAST = 1e-14
"""Least Levenberg-Marquardt lambda relative to J^T J's largest diagonal entry."""
_START = 1e-2
"""First smoothing eps of smoothing_newton relative to the mean size |(r, y)| / sqrt(contacts)
of the impulses and the scaled velocities y = rho u at its start (the shaken L wall's steps,
docs/method.md: from 1e-3 the path is lost sooner)."""
_SHRINK = 2.0
"""Factor by which smoothing_newton divides eps from one level to the next: on the small
shaken L wall's seven capped steps 2 with _LEVEL 20 reaches 1e-6 on all of them in 61-118
factorizations; 4, or 10 iterations per level, leave some of them above after 150-400."""
_LEVEL = 20
"""Newton iterations at most per level of eps; a level ends where ||phi_eps|| <= _CLOSE eps,
or earlier where the line search finds no step (the next level goes on from its iterate)."""
_CLOSE = 0.1
"""A level's iterate is on the path where ||phi_eps|| <= this times eps."""
_FLOOR = 1e-14
"""Least eigenvalue of x∘x + y∘y relative to the largest, in the Jacobian only: on the cone's
boundary f'(lambda_1) is infinite while S L_x stays bounded (Chen, Chen, Tseng 2004)."""


def _arrow(z: np.ndarray) -> np.ndarray:
    """Arrow matrices L_z = [[z_0, z_bar^T], [z_bar, z_0 I]] of z (contacts, 3)."""
    out = z[:, 0, None, None] * np.eye(3)[None]
    out[:, 0, 1:] = z[:, 1:]
    out[:, 1:, 0] = z[:, 1:]
    return out


def fischer_burmeister(r: np.ndarray, w: sp.csr_matrix, q: np.ndarray, mu: np.ndarray,
                       rho: np.ndarray, smoothing: float = 0.0):
    """(phi, A, B): the Fischer-Burmeister function phi(r) of the module doc (flat, FCLIB
    order, 3D) and the blocks A = d phi / dr, B = d phi / du (contacts, 3, 3) of an element of
    its generalized Jacobian, J = A + B W. smoothing eps > 0 [N s]: the smoothed function
    x + y - (x∘x + y∘y + 2 eps^2 e)^(1/2), e = (1, 0, 0) (Fukushima, Luo, Tseng 2002), smooth
    everywhere, with the same formulas (w_0 raised by 2 eps^2)."""
    rr = r.reshape(-1, 3)
    uu = (w @ r + q).reshape(-1, 3)
    m = rr.shape[0]
    ut = uu[:, 1:]
    norm_ut = np.sqrt(np.einsum("ij,ij->i", ut, ut))
    # x = D r, y = rho E(u) u_hat with D = diag(mu, 1, 1); dy/du = rho [[1, mu t^T], [0, mu I]]
    x = rr.copy()
    x[:, 0] *= mu
    y = np.empty_like(uu)
    y[:, 0] = rho * (uu[:, 0] + mu * norm_ut)
    y[:, 1:] = (rho * mu)[:, None] * ut
    w0 = np.einsum("ij,ij->i", x, x) + np.einsum("ij,ij->i", y, y) + 2.0 * smoothing**2
    wbar = 2.0 * (x[:, 0, None] * x[:, 1:] + y[:, 0, None] * y[:, 1:])
    norm_wbar = np.sqrt(np.einsum("ij,ij->i", wbar, wbar))
    e = np.zeros_like(wbar)
    e[:, 0] = 1.0  # any unit vector where w_bar = 0 (lambda_1 = lambda_2: S = f' I)
    has = norm_wbar > 0.0
    e[has] = wbar[has] / norm_wbar[has, None]
    lam1 = np.maximum(w0 - norm_wbar, 0.0)
    lam2 = w0 + norm_wbar
    s1, s2 = np.sqrt(lam1), np.sqrt(lam2)
    root = np.empty_like(x)
    root[:, 0] = 0.5 * (s1 + s2)
    root[:, 1:] = 0.5 * (s2 - s1)[:, None] * e
    phi = x + y - root
    floor = np.maximum(_FLOOR * lam2, 1e-300)
    d1 = 0.5 / np.sqrt(np.maximum(lam1, floor))
    d2 = 0.5 / np.sqrt(np.maximum(lam2, floor))
    a = 1.0 / np.maximum(s1 + s2, np.sqrt(floor))
    b, c = 0.5 * (d2 + d1), 0.5 * (d2 - d1)
    s = np.zeros((m, 3, 3))
    s[:, 0, 0] = b
    s[:, 0, 1:] = c[:, None] * e
    s[:, 1:, 0] = c[:, None] * e
    s[:, 1:, 1:] = (a[:, None, None] * np.eye(2)[None]
                    + (b - a)[:, None, None] * e[:, :, None] * e[:, None, :])
    eye = np.eye(3)[None]
    dphi_dx = eye - 2.0 * s @ _arrow(x)
    dphi_dy = eye - 2.0 * s @ _arrow(y)
    dx_dr = np.zeros((m, 3, 3))
    dx_dr[:, 0, 0] = mu
    dx_dr[:, 1, 1] = dx_dr[:, 2, 2] = 1.0
    t = np.zeros_like(ut)
    moving = norm_ut > 0.0
    t[moving] = ut[moving] / norm_ut[moving, None]
    dy_du = np.zeros((m, 3, 3))
    dy_du[:, 0, 0] = rho
    dy_du[:, 0, 1:] = (rho * mu)[:, None] * t
    dy_du[:, 1, 1] = dy_du[:, 2, 2] = rho * mu
    a_blocks = dphi_dx @ dx_dr
    b_blocks = dphi_dy @ dy_du
    frictionless = mu == 0.0
    if np.any(frictionless):
        rn, yn = rr[frictionless, 0], rho[frictionless] * uu[frictionless, 0]
        hyp = np.hypot(np.hypot(rn, yn), np.sqrt(2.0) * smoothing)
        safe = np.where(hyp > 0.0, hyp, 1.0)
        # at (0, 0) the element (1 - 1/sqrt 2, 1 - 1/sqrt 2) of the generalized Jacobian
        da = np.where(hyp > 0.0, 1.0 - rn / safe, 1.0 - np.sqrt(0.5))
        db = np.where(hyp > 0.0, 1.0 - yn / safe, 1.0 - np.sqrt(0.5))
        phi[frictionless, 0] = rn + yn - hyp
        phi[frictionless, 1:] = rr[frictionless, 1:]
        a_f = np.zeros((rn.size, 3, 3))
        a_f[:, 0, 0] = da
        a_f[:, 1, 1] = a_f[:, 2, 2] = 1.0
        b_f = np.zeros((rn.size, 3, 3))
        b_f[:, 0, 0] = db * rho[frictionless]
        a_blocks[frictionless] = a_f
        b_blocks[frictionless] = b_f
    return phi.ravel(), a_blocks, b_blocks


def _lifted(w: sp.spmatrix, q: np.ndarray, r: np.ndarray):
    """A 2D problem (FCLIB order) as the 3D one of the module doc: (W, q, r) with a second
    tangent per contact, W = 1 and q = r = 0 there."""
    import scipy.sparse as sp

    m = q.size // 2
    place = (3 * np.arange(m)[:, None] + np.arange(2)[None]).ravel()  # 2D index -> 3D index
    lift = sp.csr_matrix((np.ones(2 * m), (place, np.arange(2 * m))), shape=(3 * m, 2 * m))
    pad = np.zeros(3 * m)
    pad[3 * np.arange(m) + 2] = 1.0
    q3, r3 = lift @ q, lift @ r
    return (lift @ w @ lift.T + sp.diags(pad)).tocsr(), q3, r3, place


def _level(r, w, q, mu, rho, smoothing: float):
    """Newton on the smoothed function phi_eps (at most _LEVEL iterations, Armijo on
    ||phi_eps||^2 / 2; the smoothed Jacobian is factored by a sparse LU of J itself): (r,
    whether ||phi_eps|| <= _CLOSE eps, the iterates after the first, the LU factorizations)."""
    import scipy.sparse.linalg as spla

    phi, a_blocks, b_blocks = fischer_burmeister(r, w, q, mu, rho, smoothing)
    merit = 0.5 * float(phi @ phi)
    iterates = []
    for solves in range(_LEVEL):
        if np.sqrt(2.0 * merit) <= _CLOSE * smoothing:
            return r, True, iterates, solves
        jacobian = (_block_diagonal(a_blocks) + _block_diagonal(b_blocks) @ w).tocsc()
        try:
            direction = spla.splu(jacobian).solve(-phi)
        except RuntimeError:  # "Factor is exactly singular"
            return r, False, iterates, solves + 1
        t = 1.0
        for _ in range(_HALVINGS):
            trial = r + t * direction
            phi_trial, a_trial, b_trial = fischer_burmeister(trial, w, q, mu, rho, smoothing)
            merit_trial = 0.5 * float(phi_trial @ phi_trial)
            if merit_trial <= (1.0 - 2.0 * _ARMIJO * t) * merit:
                break
            t *= 0.5
        else:
            return r, False, iterates, solves + 1
        r, phi, a_blocks, b_blocks, merit = trial, phi_trial, a_trial, b_trial, merit_trial
        iterates.append(r)
    return r, np.sqrt(2.0 * merit) <= _CLOSE * smoothing, iterates, _LEVEL


def smoothing_newton(w: sp.spmatrix, q: np.ndarray, mu: np.ndarray,
                     r0: np.ndarray | None = None, tolerance: float = 1e-8,
                     max_solves: int = 150) -> ConicResult:
    """Smoothing Newton on the 3D problem u = W r + q (FCLIB order) from r0 (zero if None):
    Newton on the smoothed function phi_eps (fischer_burmeister's smoothing) for eps = eps_0,
    eps_0 / 2, ..., each level from the last level's iterate (on the path or not), following
    the path of the smoothed problems' solutions to eps -> 0 (L. Qi, D. Sun, G. Zhou, "A new
    look at smoothing Newton methods for nonlinear complementarity problems and box
    constrained variational inequalities", Math. Program. 87, 2000; for second-order cones
    Fukushima, Luo & Tseng 2002). For eps > 0 phi_eps has no kink and its Jacobian is
    regular where the unsmoothed one is not: where
    Fischer-Burmeister Newton stops at a stationary point of its merit, a contact loaded
    (r_N > 0) with a small opening velocity (u_N > 0) has d phi / d r_N ~ (rho u_N / r_N)^2,
    and the step that unloads it is not seen; eps of the size of r_N makes it seen
    (docs/method.md). Stops where the natural-map error ||F_nat|| / ||q|| is <= tolerance
    (checked at every iterate), after max_solves LU factorizations, or after a level in which
    no step decreases ||phi_eps|| (the path is lost: the shaken L wall's onset steps,
    docs/method.md). Returns the iterate of least natural-map error (ConicResult: iterations, the
    levels; interior_iterations, the LU factorizations)."""
    import scipy.sparse as sp

    w = sp.csr_matrix(w, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    mu = np.asarray(mu, dtype=np.float64)
    if q.size == 0:
        return ConicResult(np.zeros(0), 0, 0, 0.0)
    rho = 1.0 / np.maximum(w.diagonal().reshape(-1, 3).max(axis=1), 1e-300)
    r = np.zeros(q.size) if r0 is None else np.array(r0, dtype=np.float64)
    best, best_r = natural_map_error(w, q, mu, r, 3), r
    y = rho[:, None] * (w @ r + q).reshape(-1, 3)
    smoothing = _START * float(np.sqrt(r @ r + np.sum(y * y)) / np.sqrt(mu.size))
    levels = solves = 0
    moved = True
    while best > tolerance and solves < max_solves and moved:
        r, on_path, iterates, factored = _level(r, w, q, mu, rho, smoothing)
        levels += 1
        solves += factored
        moved = on_path or bool(iterates)
        for iterate in iterates:
            error = natural_map_error(w, q, mu, iterate, 3)
            if error < best:
                best, best_r = error, iterate
        smoothing /= _SHRINK
    return ConicResult(best_r, levels, solves, best)


def fischer_burmeister_newton(w: sp.spmatrix, q: np.ndarray, mu: np.ndarray,
                              r0: np.ndarray | None = None, tolerance: float = 1e-8,
                              max_iterations: int = 100, spacedim: int = 3) -> ConicResult:
    """The method of the module doc on u = W r + q (FCLIB order; spacedim 2 is solved as 3D)
    from r0 (zero if None), until the natural-map error ||F_nat(r)|| / ||q||
    (saxum.solver.residual) is <= tolerance, after max_iterations iterations, when no step
    decreases the merit even with the largest Levenberg-Marquardt multiplier, or when ||phi||
    has not halved in _PATIENCE iterations. Returns the iterate of least natural-map error
    (ConicResult: interior_iterations counts the linear solves)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    w = sp.csr_matrix(w, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    mu = np.asarray(mu, dtype=np.float64)
    if q.size == 0:
        return ConicResult(np.zeros(0), 0, 0, 0.0)
    if spacedim == 2:
        w3, q3, r3, place = _lifted(w, q, np.zeros(q.size) if r0 is None else r0)
        result = fischer_burmeister_newton(w3, q3, mu, r3, tolerance, max_iterations)
        r = result.r[place]
        return ConicResult(r, result.iterations, result.interior_iterations,
                           natural_map_error(w, q, mu, r, 2))
    rho = 1.0 / np.maximum(w.diagonal().reshape(-1, 3).max(axis=1), 1e-300)
    r = np.zeros(q.size) if r0 is None else np.array(r0, dtype=np.float64)
    phi, a_blocks, b_blocks = fischer_burmeister(r, w, q, mu, rho)
    merit = 0.5 * float(phi @ phi)
    best, best_r = natural_map_error(w, q, mu, r, 3), r
    identity = sp.identity(q.size, format="csr")
    multiplier = _MULTIPLIER[1]
    solves = 0
    it = 0
    mark, since = merit, 0  # the merit when ||phi|| last halved, and the iterations since
    while it < max_iterations and best > tolerance and merit > 0.0 and since < _PATIENCE:
        it += 1
        since += 1
        jacobian = (_block_diagonal(a_blocks) + _block_diagonal(b_blocks) @ w).tocsr()
        gradient = jacobian.T @ phi
        normal = (jacobian.T @ jacobian).tocsc()
        # lambda > 0 where phi has vanished to round-off: J^T J is singular (rank-deficient W)
        least = _LEAST * max(float(normal.diagonal().max()), 1e-300)
        step = None
        while step is None and multiplier <= _MULTIPLIER[2]:
            solves += 1
            lam = max(multiplier * np.sqrt(2.0 * merit), least)
            direction = spla.spsolve((normal + lam * identity).tocsc(), -gradient)
            slope = float(gradient @ direction)
            t = 1.0
            usable = np.all(np.isfinite(direction)) and slope < 0.0
            for _ in range(_HALVINGS if usable else 0):
                trial = r + t * direction
                phi_trial, a_trial, b_trial = fischer_burmeister(trial, w, q, mu, rho)
                merit_trial = 0.5 * float(phi_trial @ phi_trial)
                if merit_trial <= merit + _ARMIJO * t * slope:
                    step = t
                    break
                t *= 0.5
            else:
                multiplier *= 10.0
        if step is None:
            break
        if step == 1.0:
            multiplier = max(multiplier / 10.0, _MULTIPLIER[0])
        elif step < _SHORT:
            multiplier *= 10.0
        r, phi, a_blocks, b_blocks, merit = trial, phi_trial, a_trial, b_trial, merit_trial
        error = natural_map_error(w, q, mu, r, 3)
        if error < best:
            best, best_r = error, r
        if merit <= 0.25 * mark:
            mark, since = merit, 0
    return ConicResult(best_r, it, solves, best)
