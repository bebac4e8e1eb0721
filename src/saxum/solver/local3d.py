"""The single-contact solve in 3D (Signorini + isotropic Coulomb), by cases like the 2D one.

Frame (t, n, s) as saxum's 3D contacts (index 1 is the normal, 0 and 2 the tangents), so the
same routine serves the 3D time stepper and FCLIB problems (whose order [n, t, s] the caller
permutes). Given the contact's Delassus block W (3 x 3, positive definite; symmetry is not
needed) and the local velocity u that the other impulses leave, find R with U = u + W R and
    U_n >= 0, R_n >= 0, U_n R_n = 0;  |R_T| <= mu R_n;  R_T = -mu R_n U_T / |U_T| if U_T != 0.
The cases are tried in turn (as in 2D: M. Jean, CMAME 177, 1999, sec. 6):
- no contact: u_n >= 0 gives R = 0;
- stick: U = 0, R = -W^-1 u, accepted if R_n > 0 and |R_T| <= mu R_n;
- slide with unit slip direction d = (cos phi, sin phi) in the (t, s) plane: R_T = -mu R_n d
  and U_n = 0 give R_n = -u_n / D(phi), D = W_nn - mu W_nT d, and then
      U_T(phi) = u_T + R_n (W_Tn - mu W_TT d)  must equal  lambda d with lambda >= 0.
  Multiplied by D > 0, the parallelism condition cross(D U_T, d) = 0 is a trigonometric
  polynomial of degree 2 in phi (at most 4 roots), solved to round-off by Newton's method from
  the current slip direction and, if that does not give an admissible root (D > 0,
  lambda >= 0), from every root of the equivalent quartic in z = exp(i phi) (companion matrix
  eigenvalues); among several admissible roots the one nearest the current impulse is kept,
  which keeps an NLGS sweep continuous. Unlike a local Newton on the Alart-Curnier function,
  no step length or line search is involved: a returned slide satisfies the law to round-off.
- fallback (round-off cases only, see the end of solve_contact_3d).
"""

import math

import numba as nb
import numpy as np

from ..linalg3 import solve3

__all__ = ["open_or_stick_3d", "solve_contact_3d"]

_NEWTON = 50  # iteration cap of a Newton solve in phi (converges in a few from a good guess)


@nb.njit(cache=True)
def _slide(w, u, mu, phi):
    """h(phi) = cross(D U_T, d), h'(phi), D(phi) and D lambda = D U_T . d at slip angle phi."""
    c = math.cos(phi)
    s = math.sin(phi)
    un = u[1]
    d_ = w[1, 1] - mu * (w[1, 0] * c + w[1, 2] * s)
    dd = -mu * (-w[1, 0] * s + w[1, 2] * c)
    # P = D U_T = D u_T - u_n (W_Tn - mu W_TT d), and its derivative in phi
    p0 = d_ * u[0] - un * (w[0, 1] - mu * (w[0, 0] * c + w[0, 2] * s))
    p1 = d_ * u[2] - un * (w[2, 1] - mu * (w[2, 0] * c + w[2, 2] * s))
    q0 = dd * u[0] + un * mu * (-w[0, 0] * s + w[0, 2] * c)
    q1 = dd * u[2] + un * mu * (-w[2, 0] * s + w[2, 2] * c)
    h = p0 * s - p1 * c
    dh = q0 * s - q1 * c + p0 * c + p1 * s
    return h, dh, d_, p0 * c + p1 * s


@nb.njit(cache=True)
def _newton(w, u, mu, phi):
    """Root of h by Newton's method from phi (nan if a step is not finite). It stops when a step
    is at the round-off of phi or after _NEWTON steps, so the result may not be a root: that is
    checked afterwards, by _admissible."""
    for _ in range(_NEWTON):
        h, dh, _d, _l = _slide(w, u, mu, phi)
        if h == 0.0:
            return phi
        new = phi - h / dh if dh != 0.0 else math.nan
        if not math.isfinite(new):
            return math.nan
        if abs(new - phi) <= 1e-14 * (1.0 + abs(phi)):
            return new
        phi = new
    return phi


@nb.njit(cache=True)
def _quartic_roots(w, u, mu):
    """Roots z of z^2 h(phi(z)): the Fourier coefficients c_0..c_2 of h come exactly from 5
    samples (degree 2 < 5/2 aliases nothing), c_-k = conj(c_k); eigenvalues of the companion
    matrix of the polynomial with trailing zero coefficients (roots z = 0) dropped."""
    c = np.zeros(5, dtype=np.complex128)
    for j in range(5):
        phi = 2.0 * math.pi * j / 5.0
        h = _slide(w, u, mu, phi)[0]
        for k in range(3):
            c[2 + k] += h * complex(math.cos(k * phi), -math.sin(k * phi)) / 5.0
    c[1] = c[3].conjugate()
    c[0] = c[4].conjugate()
    size = 0.0
    for k in range(5):
        size = max(size, abs(c[k]))
    lead = 4
    while lead > 0 and abs(c[lead]) <= 1e-15 * size:
        lead -= 1
    low = 0
    while low < lead and abs(c[low]) <= 1e-15 * size:
        low += 1
    n = lead - low
    if n == 0:
        return np.zeros(0, dtype=np.complex128)
    companion = np.zeros((n, n), dtype=np.complex128)
    for k in range(n):
        companion[0, k] = -c[lead - 1 - k] / c[lead]
        if k + 1 < n:
            companion[k + 1, k] = 1.0
    return np.linalg.eigvals(companion)


@nb.njit(cache=True)
def _admissible(w, u, mu, phi):
    """R_n of the slide at phi, or -1 where it is not admissible: not a root of h (Newton stops
    on its step size, which far from a root shows as a large h), D <= 0, or lambda < 0 beyond
    round-off (at the stick/slide boundary lambda = 0 comes out as +-1e-16 of the terms)."""
    h, _dh, d_, dl = _slide(w, u, mu, phi)
    scale = d_ * (abs(u[0]) + abs(u[2])) + abs(u[1]) * (
        abs(w[0, 1]) + abs(w[2, 1]) + mu * (abs(w[0, 0]) + abs(w[0, 2]) + abs(w[2, 0])
                                            + abs(w[2, 2])))
    if not (math.isfinite(phi) and d_ > 0.0 and dl >= -1e-13 * scale
            and abs(h) <= 1e-9 * scale):
        return -1.0
    return -u[1] / d_


@nb.njit(cache=True)
def _residual2(w, u, mu, rt, rn, rs):
    """|R - proj_K(R - (U + mu |U_T| e_n))|^2 with U = u + W R (the natural map with De Saxce's
    change of variable; projection formula in saxum.solver.residual, which measures the error of
    whole problems independently of this solver)."""
    ut = u[0] + w[0, 0] * rt + w[0, 1] * rn + w[0, 2] * rs
    un = u[1] + w[1, 0] * rt + w[1, 1] * rn + w[1, 2] * rs
    us = u[2] + w[2, 0] * rt + w[2, 1] * rn + w[2, 2] * rs
    zt = rt - ut
    zn = rn - un - mu * math.hypot(ut, us)
    zs = rs - us
    norm_t = math.hypot(zt, zs)
    if zn >= 0.0 and norm_t <= mu * zn:
        pt, pn, ps = zt, zn, zs
    elif mu * norm_t <= -zn:
        pt, pn, ps = 0.0, 0.0, 0.0
    else:
        pn = (mu * norm_t + zn) / (mu * mu + 1.0)
        pt, ps = mu * pn * zt / norm_t, mu * pn * zs / norm_t
    return (rt - pt) ** 2 + (rn - pn) ** 2 + (rs - ps) ** 2


@nb.njit(cache=True)
def _distance2(mu, rn, phi, r):
    return ((-mu * rn * math.cos(phi) - r[0]) ** 2 + (rn - r[1]) ** 2
            + (-mu * rn * math.sin(phi) - r[2]) ** 2)


@nb.njit(cache=True)
def _set_slide(mu, rn, phi, r):
    r[0] = -mu * rn * math.cos(phi)
    r[1] = rn
    r[2] = -mu * rn * math.sin(phi)


@nb.njit(inline="always")
def open_or_stick_3d(w00, w01, w02, w10, w11, w12, w20, w21, w22, ut, un, us, mu):
    """The two first cases of solve_contact_3d on scalars (callers that solve many contacts
    inline it and call solve_contact_3d only for the others): (0, 0, 0, 0) when u_n >= 0 (no
    contact), (1, R_t, R_n, R_s) for a stick, R = -W^-1 u inside the cone (W by cofactors),
    (-1, stick R) otherwise (a slide, or mu = 0)."""
    if un >= 0.0:
        return 0, 0.0, 0.0, 0.0
    st, sn, ss = solve3(w00, w01, w02, w10, w11, w12, w20, w21, w22, ut, un, us)
    st, sn, ss = -st, -sn, -ss
    if mu > 0.0 and sn > 0.0 and math.hypot(st, ss) <= mu * sn:
        return 1, st, sn, ss
    return -1, st, sn, ss


@nb.njit(cache=True)
def solve_contact_3d(w, u, mu, r):
    """Impulse R [N s] of one contact, frame (t, n, s): W [1/kg] (3, 3), u [m/s] (3,).
    r (3,): on entry the current impulse (picks among several slides), on return the solution.
    Returns the case: 0 no contact, 1 stick, 2 slide, 3 fallback (see below)."""
    un = u[1]
    case, st, sn, ss = open_or_stick_3d(w[0, 0], w[0, 1], w[0, 2], w[1, 0], w[1, 1], w[1, 2],
                                        w[2, 0], w[2, 1], w[2, 2], u[0], un, u[2], mu)
    if case >= 0:
        r[0] = st
        r[1] = sn
        r[2] = ss
        return case
    if mu == 0.0:
        r[0] = 0.0
        r[1] = -un / w[1, 1]
        r[2] = 0.0
        return 2
    # slide: Newton from the current slip direction, else from the stick impulse's one
    if r[1] > 0.0 and (r[0] != 0.0 or r[2] != 0.0):
        phi0 = math.atan2(-r[2], -r[0])
    else:
        phi0 = math.atan2(-ss, -st)
    phi = _newton(w, u, mu, phi0)
    rn = _admissible(w, u, mu, phi)
    if rn >= 0.0:
        _set_slide(mu, rn, phi, r)
        return 2
    # all roots: h(phi) = sum_{k=-2..2} c_k z^k, z = exp(i phi), so z^2 h is a quartic in z
    # whose roots on the unit circle are the slip angles; each is polished by Newton in phi.
    best = math.inf
    best_rn = -1.0
    best_phi = 0.0
    for z in _quartic_roots(w, u, mu):
        if abs(abs(z) - 1.0) > 1e-3:
            continue
        root = _newton(w, u, mu, math.atan2(z.imag, z.real))
        rn = _admissible(w, u, mu, root)
        if rn >= 0.0:
            dist = _distance2(mu, rn, root, r)
            if dist < best:
                best, best_rn, best_phi = dist, rn, root
    if best_rn >= 0.0:
        _set_slide(mu, best_rn, best_phi, r)
        return 2
    # Reached through round-off only: for u_n ~ -0, where the slide's R_n = -u_n / D needs a
    # D below round-off, or where the boundary tolerance of _admissible does not suffice. Keep
    # the best of three candidates by the local natural-map residual: no impulse, the stick
    # impulse shrunk onto the cone, the slide along the stick impulse's direction.
    rn = max(sn, 0.0)
    shrink = min(1.0, mu * rn / max(math.hypot(st, ss), 1e-300))
    best_t, best_n, best_s = 0.0, 0.0, 0.0
    best = _residual2(w, u, mu, 0.0, 0.0, 0.0)
    res = _residual2(w, u, mu, st * shrink, rn, ss * shrink)
    if res < best:
        best, best_t, best_n, best_s = res, st * shrink, rn, ss * shrink
    phi = math.atan2(-ss, -st)
    d_ = _slide(w, u, mu, phi)[2]
    if d_ > 0.0:
        rn = -un / d_
        t, s = -mu * rn * math.cos(phi), -mu * rn * math.sin(phi)
        if _residual2(w, u, mu, t, rn, s) < best:
            best_t, best_n, best_s = t, rn, s
    r[0] = best_t
    r[1] = best_n
    r[2] = best_s
    return 3
