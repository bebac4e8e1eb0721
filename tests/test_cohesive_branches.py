"""The bonded COHESIVE joint's single-contact solve (saxum.solver.laws_local, 2D): its answer
satisfies the law of saxum.laws on random contact problems, in whichever branch it lands.

The law, per contact with W [1/kg] its Delassus block, q [m/s] the others' velocity,
U = W R + q, g_theta = g + theta^2 h U_n and s_theta = s + theta^2 h U_t (the start-of-step
velocity is 0 here): open (g_theta > 0), the bond alone, R = -beta h A (k_t s_theta,
k_n g_theta); closed, the contact's compression R_n = -h A k_n g_theta >= 0 (the same k_n
whatever the damage) and its Coulomb friction R_c,t = R_t + beta h A k_t s_theta with
|R_c,t| <= mu R_n, sticking (U_t = 0) inside the cone and opposing the slip on it.
Tolerance 1e-9 of the problem's impulse scale: the solve is closed-form per branch, exact
to round-off. The 400 problems land 207 open, 64 sticking, 129 sliding.
"""

import numpy as np

from saxum.laws import LawKind, Parameter
from saxum.solver.laws_local import law_map_width, law_solve_2d, law_terms
from saxum.solver.local2d import factorize_contact_2d

H, AREA, K_N, K_T, MU = 1e-3, 0.1, 1e9, 5e8, 0.6


def _solve(w, q, gap, slip, damage, theta, f_c=0.0):
    """(R [N s], U [m/s]) of the one-contact problem, through law_terms and law_solve_2d;
    f_c [Pa] > 0: with a compression cap, not crushed yet (its impulse h A f_c)."""
    params = np.zeros((1, len(Parameter)))
    params[0, Parameter.K_N], params[0, Parameter.K_T] = K_N, K_T
    params[0, Parameter.F_T], params[0, Parameter.COHESION] = 1e5, 1e5
    params[0, Parameter.G_I], params[0, Parameter.G_II] = 1.0, 1.0
    params[0, Parameter.F_C], params[0, Parameter.G_FC] = f_c, 1.0
    bias = np.zeros(1)
    law_map = np.zeros((1, law_map_width(2)))
    law_terms(np.zeros(1, np.int32), np.array([gap]), np.array([AREA]), np.array([[slip]]),
              np.array([damage]), np.array([0.5]), np.zeros(1), np.zeros((1, 2)), 1,
              np.zeros((1, 2)),
              np.array([int(LawKind.COHESIVE)], np.int8), params, H, theta, w[None], bias,
              law_map)
    m = law_map[0]
    f = factorize_contact_2d(m[1], m[2], m[4], MU)
    r = np.array(law_solve_2d(m, q[0], q[1] + bias[0], bias[0], *f, MU))
    return r, w @ r + q


def test_the_solve_satisfies_the_law_in_both_branches():
    rng = np.random.default_rng(7)
    branches = {"open": 0, "stick": 0, "slide": 0}
    for _ in range(400):
        a = rng.normal(size=(2, 2)) * 0.1
        w = a @ a.T + 1e-3 * np.eye(2)
        q = rng.normal(size=2) * 1e-3
        gap, slip = rng.normal() * 1e-6, rng.normal() * 1e-6
        damage, theta = rng.uniform(0.0, 0.9), rng.choice([0.5, 1.0])
        beta = 1.0 - damage
        r, u = _solve(w, q, gap, slip, damage, theta)
        g_t = gap + theta**2 * H * u[1]
        s_t = slip + theta**2 * H * u[0]
        scale = 1e-9 * (H * AREA * K_N * 1e-6 + np.abs(r).max())
        if g_t > 1e-15:
            branches["open"] += 1
            assert abs(r[1] + beta * H * AREA * K_N * g_t) < scale
            assert abs(r[0] + beta * H * AREA * K_T * s_t) < scale
            continue
        assert r[1] >= -scale
        assert abs(r[1] + H * AREA * K_N * g_t) < scale
        friction = r[0] + beta * H * AREA * K_T * s_t
        assert abs(friction) <= MU * r[1] + scale
        if abs(friction) < MU * r[1] - scale:
            branches["stick"] += 1
            assert abs(u[0]) < 1e-9 * np.abs(q).max()
        else:
            branches["slide"] += 1
            assert friction * u[0] <= scale * abs(u[0])
    assert min(branches.values()) > 20, branches  # every branch was exercised


def test_the_cap_bounds_the_normal_impulse_and_friction_follows_it():
    """Closed contacts with a cap f_c: R_n = min(h A k_n (-g_theta), h A f_c), and Coulomb's
    law on the capped R_n (sticking: U_t = 0; sliding: against U_t). f_c is drawn so that
    about half the problems reach it."""
    rng = np.random.default_rng(11)
    capped = elastic = 0
    for _ in range(200):
        a = rng.normal(size=(2, 2)) * 0.1
        w = a @ a.T + 1e-3 * np.eye(2)
        q = rng.normal(size=2) * 1e-3
        gap, slip = -abs(rng.normal()) * 1e-5, rng.normal() * 1e-6
        damage, theta = rng.uniform(0.0, 0.9), rng.choice([0.5, 1.0])
        f_c = rng.uniform(0.2, 2.0) * K_N * abs(gap)
        r, u = _solve(w, q, gap, slip, damage, theta, f_c)
        if r[1] <= 0.0:
            continue
        cap = H * AREA * f_c
        scale = 1e-9 * (cap + np.abs(r).max())
        assert r[1] <= cap + scale
        if r[1] < cap - scale:
            elastic += 1
            assert abs(r[1] + H * AREA * K_N * (gap + theta**2 * H * u[1])) < scale
        else:
            capped += 1
        friction = r[0] + (1.0 - damage) * H * AREA * K_T * (slip + theta**2 * H * u[0])
        assert abs(friction) <= MU * r[1] + scale
        if abs(friction) < MU * r[1] - scale:
            assert abs(u[0]) < 1e-9 * np.abs(q).max()
        else:
            assert friction * u[0] <= scale * abs(u[0])
    assert min(capped, elastic) > 20, (capped, elastic)
