"""Semismooth Newton on the Fischer-Burmeister function (saxum.solver.fischer) on 3D local
problems u = W r + q with closed-form solutions (FCLIB order [normal, tangent, tangent]).

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
"""

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from saxum.solver.fischer import fischer_burmeister, fischer_burmeister_newton
from saxum.solver.newton import _block_diagonal
from saxum.solver.residual import natural_map_error


def _solve(w, q, mu, r0=None):
    w = sp.csr_matrix(np.asarray(w, dtype=float))
    q, mu = np.asarray(q, dtype=float), np.asarray(mu, dtype=float)
    result = fischer_burmeister_newton(w, q, mu, r0, tolerance=1e-12)
    assert result.error <= 1e-12
    return result.r


def test_contact_sticks():
    w = np.diag([2.0, 1.0, 1.0])
    q = np.array([-1.0, 0.1, -0.05])  # |r_T| = 0.11 < 0.5 x r_N = 0.25
    assert _solve(w, q, [0.5]) == pytest.approx(-q / np.diag(w), abs=1e-10)


def test_contact_slides():
    q = np.array([-1.0, 3.0, 4.0])
    r = _solve(np.diag([2.0, 1.0, 1.0]), q, [0.5])
    assert r[0] == pytest.approx(0.5, abs=1e-10)
    assert r[1:] == pytest.approx(-0.5 * 0.5 * q[1:] / 5.0, abs=1e-10)


def test_contact_separates():
    r = _solve(np.diag([2.0, 1.0, 1.0]), [0.3, 1.0, -2.0], [0.5])
    assert np.abs(r).max() <= 1e-10


def test_frictionless_contact():
    r = _solve(np.diag([2.0, 1.0, 1.0]), [-1.0, 3.0, 4.0], [0.0])
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


def test_redundant_box_comes_to_rest():
    h, m_inv = _box_on_four_points()
    v_free = np.array([0.05, -0.02, -0.3, 0.0, 0.0, 0.0])  # |v_T| 0.054 < 0.6 x 0.3
    w, q = h @ m_inv @ h.T, h @ v_free
    assert np.linalg.matrix_rank(w) == 6
    r = _solve(w, q, np.full(4, 0.6))
    assert np.abs(w @ r + q).max() <= 1e-10
    total = h.T @ r  # impulse and moment of the contacts on the box
    assert total[:3] == pytest.approx(-3.0 * v_free[:3], abs=1e-10)
    assert np.abs(total[3:]).max() <= 1e-10


def test_jacobian_against_finite_differences():
    """The generalized Jacobian J = A + B W equals phi's derivative where phi is smooth (a
    random point is such a point with probability one). Central differences of step 1e-7 on
    phi of order one: error ~1e-14 / 1e-7 + 1e-14 (third derivative) -> 1e-6."""
    rng = np.random.default_rng(3)
    b = rng.normal(size=(12, 6))
    w = sp.csr_matrix(b @ b.T)
    q, r, mu = rng.normal(size=12), rng.normal(size=12), np.array([0.5, 0.3, 0.8, 0.0])
    rho = 1.0 / w.diagonal().reshape(-1, 3).max(axis=1)
    _, a_blocks, b_blocks = fischer_burmeister(r, w, q, mu, rho)
    jacobian = (_block_diagonal(a_blocks) + _block_diagonal(b_blocks) @ w).toarray()
    step = 1e-7
    numeric = np.column_stack([
        (fischer_burmeister(r + step * e, w, q, mu, rho)[0]
         - fischer_burmeister(r - step * e, w, q, mu, rho)[0]) / (2.0 * step)
        for e in np.eye(12)])
    assert np.abs(jacobian - numeric).max() <= 1e-6


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), contacts=st.integers(1, 6), dofs=st.integers(2, 12),
       friction=st.floats(0.1, 1.0))
def test_returned_solution_satisfies_its_reported_criterion(seed, contacts, dofs, friction):
    """W = H M^-1 H^T of random rank min(dofs, 3 contacts): the error returned is the
    natural-map error of the impulses returned, and where it says converged the impulses lie
    in the cones, the modified velocities u_hat in the dual cones and r . u_hat = 0."""
    rng = np.random.default_rng(seed)
    h = rng.normal(size=(3 * contacts, dofs))
    w = sp.csr_matrix(h @ h.T)
    q = rng.normal(size=3 * contacts)
    mu = np.full(contacts, friction)
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
