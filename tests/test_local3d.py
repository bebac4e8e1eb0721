"""Property tests of the 3D single-contact solver saxum.solver.local3d.solve_contact_3d.

Frame (t, n, s). For a contact with Delassus block W (3 x 3, symmetric positive definite) and
local velocity u, the returned impulse R must give U = u + W R satisfying
    U_n >= 0, R_n >= 0, U_n R_n = 0;  |R_T| <= mu R_n;  R_T = -mu R_n U_T / |U_T| if U_T != 0,
to a tolerance relative to the scale of the problem (as tests/test_local_solver.py in 2D).
"""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from saxum.solver.local3d import solve_contact_3d

REL = 1e-9


def _violations(w, u, mu, r):
    """List of the conditions of the law that (u, W, R) violates."""
    if not np.all(np.isfinite(r)):
        return ["R not finite"]
    big_u = u + w @ r
    scale_v = np.abs(u).max() + np.abs(w).max() * np.abs(r).max()
    if scale_v == 0.0:
        return []
    tol_v = REL * scale_v
    # Impulses below REL |u| / |W| are round-off: with u_n ~ -1e-16 |u| a slide may need
    # R_n = -u_n / D with D at round-off (mu |W_nT| > W_nn), which no double can resolve.
    tol_r = REL * max(np.abs(r).max(), np.abs(u).max() / np.abs(w).max())
    ut, rt = big_u[[0, 2]], r[[0, 2]]
    out = []
    if big_u[1] < -tol_v:
        out.append(f"U_n = {big_u[1]:.3g} < 0")
    if r[1] < 0.0:
        out.append(f"R_n = {r[1]:.3g} < 0")
    if abs(big_u[1] * r[1]) > tol_v * max(abs(r[1]), tol_r):
        out.append(f"U_n R_n = {big_u[1] * r[1]:.3g} != 0")
    # math.hypot: squares of impulses ~1e-158 would underflow in np.linalg.norm
    if math.hypot(*rt) > mu * r[1] * (1.0 + REL) + tol_r * 1e-3:
        out.append(f"|R_T| = {math.hypot(*rt):.3g} > mu R_n = {mu * r[1]:.3g}")
    # direction: R_T |U_T| = -mu R_n U_T, with U_T / scale_v ~ 1 (no underflow); round-off in U
    # turns the direction of a small U_T by ~1e-16 scale_v / |U_T|, hence the product form
    ut_rel = ut / scale_v
    norm_ut = math.hypot(*ut_rel)
    if norm_ut > REL and np.abs(rt * norm_ut + mu * r[1] * ut_rel).max() > 10 * tol_r:
        out.append(f"U_T = {ut} but R_T = {rt} != -mu R_n U_T/|U_T|")
    return out


def _solve(w, u, mu, r0=(0.0, 0.0, 0.0)):
    r = np.array(r0, dtype=float)
    case = solve_contact_3d(np.asarray(w, dtype=float), np.asarray(u, dtype=float), float(mu), r)
    return r, case


# W = L L^T with L lower triangular, positive diagonal: every SPD 3x3 matrix, scaled 1e-3..1e3
def _spd(p):
    low = np.array([[p[0], 0.0, 0.0], [p[1], p[2], 0.0], [p[3], p[4], p[5]]])
    return 10.0 ** p[6] * low @ low.T


pos = st.floats(0.05, 3.0)
off = st.floats(-3.0, 3.0)
spd = st.tuples(pos, off, pos, off, off, pos, st.floats(-3.0, 3.0)).map(_spd)
component = st.floats(-10.0, 10.0, allow_subnormal=False)
velocity = st.tuples(component, component, component).map(np.array)
friction = st.floats(0.0, 1.5)


@settings(max_examples=2000, deadline=None)
@given(w=spd, u=velocity, mu=friction, r0=velocity)
def test_random_contact_satisfies_signorini_coulomb(w, u, mu, r0):
    r, _case = _solve(w, u, mu, r0)
    assert _violations(w, u, mu, r) == []


@settings(max_examples=1000, deadline=None)
@given(w=spd, mu=st.floats(0.05, 1.5), rn=st.floats(0.01, 10.0),
       phi=st.floats(-math.pi, math.pi), lam=st.floats(0.0, 10.0))
def test_constructed_slide_is_found(w, mu, rn, phi, lam):
    """u built so that R = R_n (-mu cos phi, 1, -mu sin phi), U = (lam cos phi, 0, lam sin phi)
    solves the law (lam = 0: exactly on the stick/slide boundary, where round-off decides)."""
    d = np.array([math.cos(phi), math.sin(phi)])
    r_exact = rn * np.array([-mu * d[0], 1.0, -mu * d[1]])
    u = np.array([lam * d[0], 0.0, lam * d[1]]) - w @ r_exact
    assume(u[1] < 0.0)
    r, _case = _solve(w, u, mu)
    assert _violations(w, u, mu, r) == []


# --- hand cases -------------------------------------------------------------------------------

W_ISO = np.diag([2.0, 1.0, 2.0])


@pytest.mark.parametrize("u", [(0.0, 0.0, 0.0), (3.0, 0.0, -1.0), (-1.0, 2.0, 4.0)])
def test_separating_or_grazing_contact_has_no_impulse(u):
    r, case = _solve(W_ISO, u, 0.8, (1.0, 1.0, 1.0))
    assert case == 0 and np.all(r == 0.0)


def test_frictionless_normal_impact():
    r, _case = _solve(W_ISO, (3.0, -2.0, 1.0), 0.0)
    assert r == pytest.approx([0.0, 2.0, 0.0], abs=1e-15)


def test_sticking_contact_stops_the_contact():
    # stick: R = -W^-1 u = (-0.25, 2, 0.1), |R_T| = 0.27 <= 0.5 * 2
    r, case = _solve(W_ISO, (0.5, -2.0, -0.2), 0.5)
    assert case == 1
    assert r == pytest.approx([-0.25, 2.0, 0.1], rel=1e-14)


def test_sliding_contact_opposes_the_slip():
    # isotropic W: R_n = 2, R_T = -mu R_n u_T/|u_T| = -(0.6, 0.8), U_T = u_T + 2 R_T = (1.8, 2.4)
    u = np.array([3.0, -2.0, 4.0])
    r, case = _solve(W_ISO, u, 0.5)
    assert case == 2
    assert r == pytest.approx([-0.6, 2.0, -0.8], rel=1e-14)
    assert u + W_ISO @ r == pytest.approx([1.8, 0.0, 2.4], abs=1e-14)
