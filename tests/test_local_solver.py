"""Property tests of the exact single-contact solver saxum.solver.local2d.solve_contact_2d.

For a contact with Delassus block W = [[W_tt, W_tn], [W_tn, W_nn]] (symmetric positive definite)
and local velocity u that the other impulses leave, the returned impulse R = (R_t, R_n) must give
U = u + W R satisfying the Signorini-Coulomb law (M. Jean, CMAME 177, 1999; NSCD.md):
    U_n >= 0, R_n >= 0, U_n R_n = 0;  |R_t| <= mu R_n;  R_t = -mu R_n sign(U_t) if U_t != 0.
Tolerances are relative to the scale of the problem, s = |u| + |W| |R| (velocities) and |R|
(impulses): 1e-9 (round-off of a 2x2 solve is ~1e-15).
"""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from saxum.solver.local2d import solve_contact_2d

REL = 1e-9


def _violations(w, u, mu, r):
    """List of the conditions of the law that (u, W, R) violates."""
    w = np.asarray(w, dtype=float)
    u = np.asarray(u, dtype=float)
    r = np.asarray(r, dtype=float)
    big_u = u + w @ r
    scale_v = np.abs(u).max() + np.abs(w).max() * np.abs(r).max()
    tol_v = REL * scale_v
    tol_r = REL * np.abs(r).max()
    out = []
    if not np.all(np.isfinite(r)):
        return ["R not finite"]
    if big_u[1] < -tol_v:
        out.append(f"U_n = {big_u[1]:.3g} < 0")
    if r[1] < 0.0:
        out.append(f"R_n = {r[1]:.3g} < 0")
    if abs(big_u[1] * r[1]) > tol_v * max(abs(r[1]), tol_r):
        out.append(f"U_n R_n = {big_u[1] * r[1]:.3g} != 0")
    if abs(r[0]) > mu * r[1] * (1.0 + REL) + tol_r * 1e-3:
        out.append(f"|R_t| = {abs(r[0]):.3g} > mu R_n = {mu * r[1]:.3g}")
    if abs(big_u[0]) > tol_v and abs(r[0] + mu * r[1] * math.copysign(1.0, big_u[0])) > tol_r:
        out.append(f"U_t = {big_u[0]:.3g} but R_t = {r[0]:.3g} != -mu R_n sign(U_t)")
    return out


def _solve(w, u, mu):
    return np.array(solve_contact_2d(float(w[0, 0]), float(w[0, 1]), float(w[1, 1]),
                                     float(u[0]), float(u[1]), float(mu)))


# W = L L^T with L lower triangular, positive diagonal: every SPD 2x2 matrix, scaled over 1e-3..1e3
spd = st.tuples(
    st.floats(0.05, 3.0), st.floats(-3.0, 3.0), st.floats(0.05, 3.0), st.floats(-3.0, 3.0)
).map(lambda p: 10.0 ** p[3] * np.array([[p[0] ** 2, p[0] * p[1]],
                                          [p[0] * p[1], p[1] ** 2 + p[2] ** 2]]))
# Subnormal velocities are left out: an impulse of ~1e-324 / W underflows to zero.
component = st.floats(-10.0, 10.0, allow_subnormal=False)
velocity = st.tuples(component, component).map(np.array)
friction = st.floats(0.0, 1.5)


@settings(max_examples=2000, deadline=None)
@given(w=spd, u=velocity, mu=friction)
def test_random_contact_satisfies_signorini_coulomb(w, u, mu):
    r = _solve(w, u, mu)
    assert _violations(w, u, mu, r) == []


# --- hand cases -------------------------------------------------------------------------------

W_DIAG = np.array([[2.0, 0.0], [0.0, 1.0]])
W_COUPLED = np.array([[1.0, 0.5], [0.5, 2.0]])


@pytest.mark.parametrize("u", [(0.0, 0.0), (3.0, 0.0), (-1.0, 2.0), (5.0, 1e-12)])
def test_separating_or_grazing_contact_has_no_impulse(u):
    r = _solve(W_COUPLED, np.array(u), 0.8)
    assert r[0] == 0.0 and r[1] == 0.0


def test_frictionless_normal_impact():
    # u_n = -2 m/s, W_nn = 1/kg: R_n = 2 N s stops the contact; mu = 0: no tangential impulse
    r = _solve(W_DIAG, np.array([3.0, -2.0]), 0.0)
    assert r == pytest.approx([0.0, 2.0], abs=1e-15)


def test_sticking_contact_stops_both_components():
    # u = (0.5, -2): stick gives R = -W^-1 u = (-0.25, 2), |R_t| = 0.25 <= 0.5 * 2
    r = _solve(W_DIAG, np.array([0.5, -2.0]), 0.5)
    assert r == pytest.approx([-0.25, 2.0], rel=1e-14)
    assert W_DIAG @ r + [0.5, -2.0] == pytest.approx([0.0, 0.0], abs=1e-14)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_sliding_contact_is_on_the_cone_edge(sign):
    # u = (±3, -2), mu = 0.5: stick would need |R_t| = 1.5 > 0.5 * 2; slides with R_n = 2,
    # R_t = -sign 1, U = (±3 - sign 2, 0) = (±1, 0)
    u = np.array([3.0 * sign, -2.0])
    r = _solve(W_DIAG, u, 0.5)
    assert r == pytest.approx([-sign * 1.0, 2.0], rel=1e-14)
    assert u + W_DIAG @ r == pytest.approx([sign * 1.0, 0.0], abs=1e-14)


def test_sliding_with_coupled_delassus():
    # W_tn != 0: sliding in +t (s = 1) needs R_n = -u_n / (W_nn - mu W_tn) = 1 / (2 - 0.25)
    u = np.array([4.0, -1.0])
    mu = 0.5
    r = _solve(W_COUPLED, u, mu)
    rn = 1.0 / (2.0 - mu * 0.5)
    assert r == pytest.approx([-mu * rn, rn], rel=1e-14)
    big_u = u + W_COUPLED @ r
    assert big_u[1] == pytest.approx(0.0, abs=1e-14)
    assert big_u[0] > 0.0


# --- stick/slide boundary ---------------------------------------------------------------------


def test_stick_slide_boundary_case_found_by_search():
    """A contact exactly at the stick/slide boundary (U = 0, R_t = -mu R_n). Here round-off
    makes the stick test and both slide tests fail, and the fallback branch of
    solve_contact_2d (slide along the edge of the cone nearest the stick impulse) is reached;
    its result must still obey the law to round-off. Exact solution: R = (0.59 * 0.51, 0.51),
    U = 0."""
    w = np.array([[1.31, 0.51], [0.51, 0.99]])
    u = np.array([-0.654279, -0.658359])
    mu = 0.59
    r = _solve(w, u, mu)
    assert _violations(w, u, mu, r) == []
    assert r == pytest.approx([0.59 * 0.51, 0.51], rel=1e-9)


@settings(max_examples=1000, deadline=None)
@given(w=spd, mu=st.floats(0.05, 1.5), rn=st.floats(0.01, 10.0), s=st.sampled_from([1.0, -1.0]))
def test_stick_slide_boundary_satisfies_the_law(w, mu, rn, s):
    """u built so that R = (-s mu R_n, R_n) with U = 0 solves the law: exactly on the boundary
    between sticking and sliding, where round-off decides the case."""
    r_exact = np.array([-s * mu * rn, rn])
    u = -(w @ r_exact)
    assume(u[1] < 0.0)
    r = _solve(w, u, mu)
    assert _violations(w, u, mu, r) == []
