"""The single-contact solves of the viscous friction law and of the damped elastic law
(saxum.solver.laws_local) against the closed-form solutions of the laws' definitions.

VISCOUS_COULOMB, as issue 15 states it: |R_t| <= mu R_n + c |U_t|, with R_t against U_t and
on the bound when U_t != 0 (Coulomb plus a viscous term), c = h A eta [kg] the viscous
impulse per unit of sliding velocity (h [s] the step, A [m^2] the contact's area, eta
[Pa s/m]), U the contact's velocity at the end of the step, Signorini on U_n + b_n; the
viscous term acts on every active contact of the law, open ones too (R_n = 0 allows
c |U_t|: saxum.laws).
ELASTIC with theta = 1 against LMGC90's VISCO_ELASTIC_REPELL_CLB (mod_nlgs.f90 and
mod_nlgs_3D.f90, read for its definition; docs/method.md cites the lines): Signorini-Coulomb
on W_nn + 1 / (k H^2 + eta_n H) and the shift k g / (k H + eta_n), LMGC90's per-contact
stiffness k = k_n A [N/m] and viscosity eta_n = c_n A [N s/m], g the gap at the start.
Per contact, U = W R + q (W [1/kg] the Delassus block, q [m/s] the others' velocity).

The reference solutions are written here from those definitions, case by case (open, stick,
slide each way), not with saxum's solver. Tolerance 1e-9 of the problem's largest impulse:
both are closed forms per case, equal up to round-off (the 3D slide is Newton's on a slip
angle, converged to round-off).
"""

import numpy as np
import pytest

from saxum.laws import LawKind, Parameter
from saxum.solver.laws_local import law_map_width, law_solve_2d, law_solve_3d, law_terms
from saxum.solver.local2d import factorize_contact_2d

H, AREA, MU = 1e-3, 0.1, 0.6


def _terms(kind, w, gap, bias, theta=1.0, eta=0.0, k_n=0.0, c_n=0.0):
    """law_map row and b_n of one contact of `kind` (saxum.solver.laws_local.law_terms);
    bias: the gap law's b_n [m/s] (VISCOUS_COULOMB's normal part)."""
    dim = w.shape[0]
    params = np.zeros((1, len(Parameter)))
    params[0, Parameter.ETA], params[0, Parameter.K_N] = eta, k_n
    params[0, Parameter.C_N] = c_n
    b = np.array([bias])
    law_map = np.zeros((1, law_map_width(dim)))
    law_terms(np.zeros(1, np.int32), np.array([gap]), np.array([AREA]),
              np.zeros((1, dim - 1)), np.zeros(1), np.zeros(1), np.zeros(1),
              np.zeros((1, dim)), 1, np.zeros((1, dim)), np.array([int(kind)], np.int8),
              params, H, theta, w[None], b, law_map)
    return law_map[0], b[0]


def _saxum_2d(kind, w, q, gap=0.0, bias=0.0, **law):
    m, b = _terms(kind, w, gap, bias, **law)
    f = factorize_contact_2d(m[1], m[2], m[4], MU)
    return np.array(law_solve_2d(m, q[0], q[1] + b, b, *f, MU))


def _reference_2d(w, q, c):
    """The solutions R [N s] of the 2D law with V = W R + q: open, R_n = 0 and
    R_t = -c U_t, if that leaves V_n >= 0 (c = 0: if q_n >= 0; LMGC90's and saxum's
    local solvers take this case first); else closed, V_n = 0 and R_n >= 0, with
    R_t = -s mu R_n - c U_t and s U_t > 0 (slide, s = +-1) or U_t = 0 and |R_t| <= mu R_n
    (stick)."""
    rt = -c * q[0] / (1.0 + c * w[0, 0])  # open: U_t = q_t + W_tt R_t
    if q[1] + w[1, 0] * rt >= 0.0:
        return [np.array([rt, 0.0])]
    found = []
    r = np.linalg.solve(w, -q)  # stick: U = 0
    if r[1] >= 0.0 and abs(r[0]) <= MU * r[1]:
        found.append(r)
    for s in (1.0, -1.0):
        # unknowns (U_t, R_n): U_t = W_tt R_t + W_tn R_n + q_t, 0 = W_nt R_t + W_nn R_n + q_n
        a = np.array([[1.0 + w[0, 0] * c, s * MU * w[0, 0] - w[0, 1]],
                      [-w[1, 0] * c, w[1, 1] - s * MU * w[1, 0]]])
        ut, rn = np.linalg.solve(a, [q[0], -q[1]])
        if rn >= 0.0 and s * ut > 0.0:
            found.append(np.array([-s * MU * rn - c * ut, rn]))
    return found


def _problems(rng, count):
    """Random 2D problems: W with a normal-tangential coupling below a fifth of the diagonal
    (Coulomb's 2D problem then has one solution), q over all cases."""
    for _ in range(count):
        wt, wn = rng.uniform(0.5e-2, 2e-2, 2)
        wtn = rng.uniform(-0.2, 0.2) * np.sqrt(wt * wn)
        yield np.array([[wt, wtn], [wtn, wn]]), rng.normal(size=2) * 1e-3


def test_viscous_friction_2d_solves_the_law_in_every_case():
    rng = np.random.default_rng(3)
    cases = {"open": 0, "stick": 0, "slide": 0}
    for w, q in _problems(rng, 300):
        eta = 10.0 ** rng.uniform(4.0, 6.0)  # c W_tt from 0.05 to 20
        c = H * AREA * eta
        bias = rng.uniform(-2e-4, 2e-4)  # the gap law's b_n
        r = _saxum_2d(LawKind.VISCOUS_COULOMB, w, q, bias=bias, eta=eta)
        ut = (w @ r + q)[0]
        (ref,) = _reference_2d(w, q + [0.0, bias], c)
        assert np.abs(r - ref).max() <= 1e-9 * max(np.abs(ref).max(), 1e-12)
        if ref[1] <= 0.0:
            cases["open"] += 1
        elif abs(ut) < 1e-12:
            cases["stick"] += 1
        else:
            cases["slide"] += 1
            assert abs(r[0]) == pytest.approx(MU * r[1] + c * abs(ut), rel=1e-9)
    assert min(cases.values()) > 30, cases  # every case was exercised


def test_viscous_friction_3d_slides_against_the_velocity_with_the_closed_form():
    """3D, W = diag(w_t, w_n, w_t) in the contact frame (t, n, s): with V = q + (0, b_n, 0),
    open if V_n >= 0, R_T = -c V_T / (1 + w_t c); else R_n = -V_n / w_n, sticking if
    |V_T| <= w_t mu R_n (R_T = -V_T / w_t), and sliding with
    U_T = V_T (1 - w_t mu R_n / |V_T|) / (1 + w_t c), R_T = -(mu R_n + c |U_T|) U_T / |U_T|
    otherwise (T: the two tangential components)."""
    rng = np.random.default_rng(5)
    cases = {"open": 0, "stick": 0, "slide": 0}
    wp, rr = np.empty((3, 3)), np.empty(3)
    for _ in range(300):
        wt, wn = rng.uniform(0.5e-2, 2e-2, 2)
        w = np.diag([wt, wn, wt])
        q = rng.normal(size=3) * 1e-3
        eta = 10.0 ** rng.uniform(4.0, 6.0)
        c, bias = H * AREA * eta, rng.uniform(-2e-4, 2e-4)
        v = q + [0.0, bias, 0.0]
        vt = v[[0, 2]]
        ref = np.zeros(3)
        if v[1] < 0.0:
            ref[1] = -v[1] / wn
            if np.hypot(*vt) <= wt * MU * ref[1]:
                ref[[0, 2]] = -vt / wt
                cases["stick"] += 1
            else:
                u_t = vt * (1.0 - wt * MU * ref[1] / np.hypot(*vt)) / (1.0 + wt * c)
                ref[[0, 2]] = -(MU * ref[1] + c * np.hypot(*u_t)) * u_t / np.hypot(*u_t)
                cases["slide"] += 1
        else:
            ref[[0, 2]] = -c * vt / (1.0 + wt * c)
            cases["open"] += 1
        m, b = _terms(LawKind.VISCOUS_COULOMB, w, 0.0, bias, eta=eta)
        u = q + [0.0, b, 0.0]
        rr[:] = 0.0
        law_solve_3d(m, u, b, MU, wp, rr)
        assert np.abs(rr - ref).max() <= 1e-9 * max(np.abs(ref).max(), 1e-12)
    assert min(cases.values()) > 20, cases  # every case was exercised


def test_damped_elastic_law_is_lmgc90s_visco_elastic_repell_at_theta_1():
    """saxum's ELASTIC (k_n [Pa/m], c_n [Pa s/m], k_t = 0) at theta = 1 on a contact closed at
    the start (g <= 0: where LMGC90 activates VISCO_ELASTIC_REPELL_CLB) gives LMGC90's
    impulse: Signorini-Coulomb on W with W_nn + 1 / (k H^2 + eta_n H) and the shift
    k g / (k H + eta_n) on q_n, k = k_n A, eta_n = c_n A."""
    rng = np.random.default_rng(9)
    cases = {"open": 0, "stick": 0, "slide": 0}
    for w, q in _problems(rng, 300):
        k_n, c_n = 10.0 ** rng.uniform(6.0, 9.0), 10.0 ** rng.uniform(3.0, 6.0)
        gap = -rng.uniform(0.0, 1e-5)
        k, eta_n = k_n * AREA, c_n * AREA
        ww = w + [[0.0, 0.0], [0.0, 1.0 / (k * H * H + eta_n * H)]]
        (ref,) = _reference_2d(ww, q + [0.0, k * gap / (k * H + eta_n)], 0.0)
        r = _saxum_2d(LawKind.ELASTIC, w, q, gap=gap, k_n=k_n, c_n=c_n)
        assert np.abs(r - ref).max() <= 1e-9 * max(np.abs(ref).max(), 1e-12)
        # the reference's open case sets R = 0 (not computed), so R_n > 0 tells it apart
        cases["open" if not ref[1] > 0.0 else "stick" if abs(ref[0]) < MU * ref[1] * (1 - 1e-9)
              else "slide"] += 1
    assert min(cases.values()) > 30, cases

