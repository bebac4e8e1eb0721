"""The exact single-contact solve in 2D (Signorini + Coulomb), by enumeration of the cases.

Given the contact's Delassus block W = [[W_tt, W_tn], [W_tn, W_nn]] and the local velocity that
the other impulses leave, u = (u_t, u_n + b_n), find R = (R_t, R_n) with U = u + W R and
    U_n >= 0, R_n >= 0, U_n R_n = 0;  |R_t| <= mu R_n, R_t = -mu R_n sign(U_t) if U_t != 0.
The cases are tried in turn (M. Jean, CMAME 177, 1999, sec. 6; LMGC90's 2D NLGS):
no contact (u_n >= 0: R = 0); stick (U = 0: R = -W^-1 u, accepted if R_n > 0 and
|R_t| <= mu R_n); slide in direction s = +1 or -1 (R_t = -s mu R_n, U_n = 0:
R_n = -u_n / (W_nn - s mu W_tn), accepted if R_n >= 0 and s U_t >= 0).
"""

import numba as nb

__all__ = ["factorize_contact_2d", "solve_contact_2d", "solve_factored_contact_2d"]


@nb.njit(inline="always")
def factorize_contact_2d(wtt, wtn, wnn, mu):
    """The divisions of the solve, done once per contact and step (NLGS visits a contact many
    times with the same W and mu): (W_nn / det, W_tn / det, W_tt / det) [kg], the entries of
    W^-1 (det = W_tt W_nn - W_tn^2), and 1 / (W_nn - s mu W_tn) [kg] for s = +1, -1, or 0 where
    that denominator is not positive (no slide that way)."""
    det = wtt * wnn - wtn * wtn
    plus = wnn - mu * wtn
    minus = wnn + mu * wtn
    return (wnn / det, wtn / det, wtt / det, 1.0 / plus if plus > 0.0 else 0.0,
            1.0 / minus if minus > 0.0 else 0.0)


@nb.njit(inline="always")
def solve_factored_contact_2d(wtt, wtn, wnn, inv_nn, inv_tn, inv_tt, slide_plus, slide_minus,
                              ut, un, mu):
    """Impulse (R_t, R_n) [N s] of one contact, W in [1/kg], u in [m/s], with the factors of
    factorize_contact_2d(wtt, wtn, wnn, mu)."""
    if un >= 0.0:
        return 0.0, 0.0
    rt_stick = inv_tn * un - inv_nn * ut
    rn_stick = inv_tn * ut - inv_tt * un
    if rn_stick > 0.0 and abs(rt_stick) <= mu * rn_stick:
        return rt_stick, rn_stick
    # first try the direction of U_t when R_t = 0 and U_n = 0 (sign of u_t - W_tn u_n / W_nn)
    s = 1.0 if ut * wnn - wtn * un >= 0.0 else -1.0
    for _ in range(2):
        inv = slide_plus if s > 0.0 else slide_minus
        if inv > 0.0:
            rn = -un * inv
            rt = -s * mu * rn
            if s * (ut + wtt * rt + wtn * rn) >= 0.0:
                return rt, rn
        s = -s
    # Reached only through round-off at the stick/slide boundary, where U = 0 and the stick
    # impulse lies on the cone's edge: slide along that edge (keeps the W_tn coupling exact).
    s = -1.0 if rt_stick > 0.0 else 1.0
    inv = slide_plus if s > 0.0 else slide_minus
    if inv > 0.0:
        rn = -un * inv
        return -s * mu * rn, rn
    rn = max(rn_stick, 0.0)
    return min(max(rt_stick, -mu * rn), mu * rn), rn


@nb.njit(inline="always")
def solve_contact_2d(wtt, wtn, wnn, ut, un, mu):
    """Impulse (R_t, R_n) [N s] of one contact; W in [1/kg], u in [m/s]."""
    inv_nn, inv_tn, inv_tt, plus, minus = factorize_contact_2d(wtt, wtn, wnn, mu)
    return solve_factored_contact_2d(wtt, wtn, wnn, inv_nn, inv_tn, inv_tt, plus, minus, ut, un,
                                     mu)
