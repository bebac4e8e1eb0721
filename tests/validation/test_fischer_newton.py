"""Semismooth Newton on the Fischer-Burmeister function and the smoothing Newton method
(saxum.solver.fischer) on 3D local problems u = W r + q with closed-form solutions (FCLIB order
[normal, tangent, tangent]), and the smoothing method on a captured step of the shaken L wall.

One contact with a diagonal W (Coulomb's law, NSCD.md): pressed with a tangential load inside
the cone it sticks, r = -W^-1 q (u = 0); pushed harder than friction holds it slides, r on the
cone's edge against the slip, r_N = -q_N / W_NN, r_T = -mu r_N q_T / |q_T| (W_TT = 1 isotropic:
the slip is along q_T); with q_N > 0 it separates, r = 0; with mu = 0 it is pressed without
friction, r = (-q_N / W_NN, 0, 0). A box of mass 3 kg on four corner points (6 dof, 12 unknowns:
W of rank 6, the normal impulses not unique) pushed down and sideways within the cone comes to
rest: u = 0 and the impulses sum to M (-v_free) (Newton's second law over the step).
A 2D contact (spacedim 2, solved as 3D with a second tangent of W = 1, q = 0) pushed harder
than friction holds slides: r = (-q_N / W_NN, -mu r_N sign(q_T)).
Tolerances: 1e-10 (the solver's natural-map tolerance 1e-12 relative to |q| of order one, and
round-off); the property test's 1e-9 is its tolerance 1e-10 plus round-off on |q| up to 10.
The L wall's step (tests/data/small_l_wall_step14.npz, written by `python
benchmarks/capped_steps.py --small --save-first ...`: step 14 of the 29-brick L wall under 0.7 g,
280 contacts, W = H* M^-1 H*^T of rank 168 of 840, NLGS's iterate after 5000 sweeps at a
natural-map error of 1.6e-5): a solution exists (strict feasibility, docs/method.md), the
smoothing method is asked for the hybrid's tolerance 1e-6.
"""

from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from saxum.solver.fischer import fischer_burmeister, fischer_burmeister_newton, smoothing_newton
from saxum.solver.newton import _block_diagonal, proximal_point
from saxum.solver.residual import natural_map_error

SOLVERS = [fischer_burmeister_newton, smoothing_newton, proximal_point]


def _solve(w, q, mu, solver=fischer_burmeister_newton):
    w = sp.csr_matrix(np.asarray(w, dtype=float))
    q, mu = np.asarray(q, dtype=float), np.asarray(mu, dtype=float)
    result = solver(w, q, mu, None, 1e-12)
    assert result.error <= 1e-12
    return result.r


@pytest.mark.parametrize("solver", SOLVERS)
def test_contact_sticks(solver):
    w = np.diag([2.0, 1.0, 1.0])
    q = np.array([-1.0, 0.1, -0.05])  # |r_T| = 0.11 < 0.5 x r_N = 0.25
    assert _solve(w, q, [0.5], solver) == pytest.approx(-q / np.diag(w), abs=1e-10)


@pytest.mark.parametrize("solver", SOLVERS)
def test_contact_slides(solver):
    q = np.array([-1.0, 3.0, 4.0])
    r = _solve(np.diag([2.0, 1.0, 1.0]), q, [0.5], solver)
    assert r[0] == pytest.approx(0.5, abs=1e-10)
    assert r[1:] == pytest.approx(-0.5 * 0.5 * q[1:] / 5.0, abs=1e-10)


@pytest.mark.parametrize("solver", SOLVERS)
def test_contact_separates(solver):
    r = _solve(np.diag([2.0, 1.0, 1.0]), [0.3, 1.0, -2.0], [0.5], solver)
    assert np.abs(r).max() <= 1e-10


@pytest.mark.parametrize("solver", SOLVERS)
def test_frictionless_contact(solver):
    r = _solve(np.diag([2.0, 1.0, 1.0]), [-1.0, 3.0, 4.0], [0.0], solver)
    assert r == pytest.approx([0.5, 0.0, 0.0], abs=1e-10)


def test_2d_contact_slides():
    w = sp.csr_matrix(np.diag([2.0, 1.0]))
    q, mu = np.array([-1.0, 3.0]), np.array([0.5])
    result = fischer_burmeister_newton(w, q, mu, tolerance=1e-12, spacedim=2)
    assert result.error <= 1e-12
    assert result.r == pytest.approx([0.5, -0.25], abs=1e-10)


def _box_on_four_points():
    """H (12 x 6: rows (n, t1, t2) = (z, x, y) per corner, columns (v, omega)) and M^-1 of a
    box 0.4 x 0.2 x 0.1 m of 3 kg on its four base corners (p = (+-0.2, +-0.1, -0.05) from
    its centre): the velocity of the corner is v + omega x p."""
    mass, size = 3.0, np.array([0.4, 0.2, 0.1])
    inertia = mass / 12.0 * np.array([size[1] ** 2 + size[2] ** 2, size[0] ** 2 + size[2] ** 2,
                                      size[0] ** 2 + size[1] ** 2])
    rows = []
    for sx_ in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            p = np.array([sx_ * 0.2, sy * 0.1, -0.05])
            for axis in (2, 0, 1):
                e = np.eye(3)[axis]
                rows.append(np.concatenate([e, np.cross(p, e)]))  # e . (omega x p)
    return np.array(rows), np.diag(np.concatenate([np.full(3, 1.0 / mass), 1.0 / inertia]))


@pytest.mark.parametrize("solver", SOLVERS)
def test_redundant_box_comes_to_rest(solver):
    h, m_inv = _box_on_four_points()
    v_free = np.array([0.05, -0.02, -0.3, 0.0, 0.0, 0.0])  # |v_T| 0.054 < 0.6 x 0.3
    w, q = h @ m_inv @ h.T, h @ v_free
    assert np.linalg.matrix_rank(w) == 6
    r = _solve(w, q, np.full(4, 0.6), solver)
    assert np.abs(w @ r + q).max() <= 1e-10
    total = h.T @ r  # impulse and moment of the contacts on the box
    assert total[:3] == pytest.approx(-3.0 * v_free[:3], abs=1e-10)
    assert np.abs(total[3:]).max() <= 1e-10


@pytest.mark.parametrize("solver", SOLVERS)
def test_redundant_box_slides(solver):
    """The box of _box_on_four_points thrown along the ground faster than friction stops it
    in one step (|v_T| = 0.539 > mu |v_N| = 0.18 m/s): the ground's impulse is the closed form
    of a sliding block (vertical 3 kg x 0.3 m/s, friction mu times that against v_T), the box
    ends translating at v_T (1 - 0.18 / 0.539), whatever the split over the four redundant
    corners (W of rank 6 of 12). Tolerance 1e-9: the solvers stop at a natural-map error of
    1e-12 of ||q|| ~ 1."""
    h, m_inv = _box_on_four_points()
    v_free = np.array([0.5, 0.2, -0.3, 0.0, 0.0, 0.0])
    r = _solve(h @ m_inv @ h.T, h @ v_free, np.full(4, 0.6), solver)
    v_t = v_free[:2]
    slip = np.linalg.norm(v_t)
    total = h.T @ r
    assert total[2] == pytest.approx(0.9, abs=1e-9)
    assert total[:2] == pytest.approx(-0.6 * 0.9 * v_t / slip, abs=1e-9)
    v = v_free + m_inv @ total
    assert v == pytest.approx(np.concatenate([v_t * (1.0 - 0.18 / slip), np.zeros(4)]),
                              abs=1e-9)


@pytest.mark.parametrize("smoothing", [0.0, 0.3])
def test_jacobian_against_finite_differences(smoothing):
    """The generalized Jacobian J = A + B W equals phi's derivative where phi is smooth (a
    random point is such a point with probability one; the smoothed function everywhere).
    Central differences of step 1e-7 on phi of order one: error ~1e-14 / 1e-7 + 1e-14 (third
    derivative) -> 1e-6."""
    rng = np.random.default_rng(3)
    b = rng.normal(size=(12, 6))
    w = sp.csr_matrix(b @ b.T)
    q, r, mu = rng.normal(size=12), rng.normal(size=12), np.array([0.5, 0.3, 0.8, 0.0])
    rho = 1.0 / w.diagonal().reshape(-1, 3).max(axis=1)
    _, a_blocks, b_blocks = fischer_burmeister(r, w, q, mu, rho, smoothing)
    jacobian = (_block_diagonal(a_blocks) + _block_diagonal(b_blocks) @ w).toarray()
    step = 1e-7
    numeric = np.column_stack([
        (fischer_burmeister(r + step * e, w, q, mu, rho, smoothing)[0]
         - fischer_burmeister(r - step * e, w, q, mu, rho, smoothing)[0]) / (2.0 * step)
        for e in np.eye(12)])
    assert np.abs(jacobian - numeric).max() <= 1e-6


def test_smoothed_function_of_one_frictionless_contact():
    """mu = 0: phi_N = r_N + rho u_N - sqrt(r_N^2 + (rho u_N)^2 + 2 eps^2) (the smoothed scalar
    Fischer-Burmeister function), phi_T = r_T; r = (3, 1, 2), u = W r + q = (4, ., .), rho =
    1: 3 + 4 - sqrt(9 + 16 + 2 x 1.5^2) = 7 - sqrt(29.5). Round-off only: 1e-14."""
    w = sp.identity(3, format="csr")
    r, q = np.array([3.0, 1.0, 2.0]), np.array([1.0, 0.0, 0.0])
    phi, _, _ = fischer_burmeister(r, w, q, np.array([0.0]), np.array([1.0]), 1.5)
    assert phi == pytest.approx([7.0 - np.sqrt(29.5), 1.0, 2.0], abs=1e-14)


def test_smoothing_newton_solves_a_capped_step_of_the_shaken_l_wall():
    """Where Fischer-Burmeister Newton stops at a stationary point of its merit (10
    iterations: 9.6e-6 measured; it does not halve ||phi||), the smoothing method reaches the
    hybrid's tolerance 1e-6 from NLGS's iterate, and reports the natural-map error of what it
    returns."""
    data = np.load(Path(__file__).resolve().parents[1] / "data" / "small_l_wall_step14.npz")
    h = sp.csr_matrix((data["h_data"], data["h_indices"], data["h_indptr"]),
                      shape=tuple(data["h_shape"]))
    w = (h @ sp.diags(data["inv_mass"]) @ h.T).tocsr()
    q, mu, r0 = data["q"], data["mu"], data["r"]
    assert natural_map_error(w, q, mu, r0, 3) > 1e-5
    assert fischer_burmeister_newton(w, q, mu, r0, 1e-8, 10).error > 1e-6
    result = smoothing_newton(w, q, mu, r0, 1e-6, 400)
    assert result.error <= 1e-6
    assert result.error == pytest.approx(natural_map_error(w, q, mu, result.r, 3), rel=1e-12,
                                         abs=0.0)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), contacts=st.integers(1, 6), dofs=st.integers(2, 12),
       friction=st.floats(0.1, 1.0), smoothing=st.booleans())
def test_returned_solution_satisfies_its_reported_criterion(seed, contacts, dofs, friction,
                                                            smoothing):
    """W = H M^-1 H^T of random rank min(dofs, 3 contacts): the error returned is the
    natural-map error of the impulses returned, and where it says converged the impulses lie
    in the cones, the modified velocities u_hat in the dual cones and r . u_hat = 0."""
    rng = np.random.default_rng(seed)
    h = rng.normal(size=(3 * contacts, dofs))
    w = sp.csr_matrix(h @ h.T)
    q = rng.normal(size=3 * contacts)
    mu = np.full(contacts, friction)
    if smoothing:
        result = smoothing_newton(w, q, mu, None, 1e-10, 150)
    else:
        result = fischer_burmeister_newton(w, q, mu, tolerance=1e-10, max_iterations=50)
    assert result.error == pytest.approx(natural_map_error(w, q, mu, result.r, 3),
                                         rel=1e-12, abs=0.0)
    if result.error <= 1e-10:
        r = result.r.reshape(-1, 3)
        u = (w @ result.r + q).reshape(-1, 3)
        size = 1e-9 * max(1.0, float(np.linalg.norm(q)))
        assert np.all(friction * r[:, 0] - np.linalg.norm(r[:, 1:], axis=1) >= -size)
        u_hat_n = u[:, 0] + friction * np.linalg.norm(u[:, 1:], axis=1)
        assert np.all(u_hat_n - friction * np.linalg.norm(u[:, 1:], axis=1) >= -size)
        u_hat = u.copy()
        u_hat[:, 0] = u_hat_n
        assert abs(float(np.einsum("ij,ij->", r, u_hat))) <= size * (1.0 + np.abs(r).sum())
