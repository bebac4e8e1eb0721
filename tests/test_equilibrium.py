"""The second-order cone pieces of the 3D rest solution (saxum.solver.equilibrium): the inverse
Hessian of the barrier problem against a direct inversion, and the step to the cone's boundary
(property tests; the rest solution itself is validated in tests/validation/
test_rest_solution3d.py)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from saxum.solver.equilibrium import _lorentz_exit, _lorentz_hessian_inverse

J = np.diag([-1.0, 1.0, -1.0])  # Q(x) = x^T J x = x_n^2 - x_t^2 - x_s^2


def _inside(tangent, angle, room):
    """A point of the cone |(x_t, x_s)| <= x_n: x_n = |x_T| (1 + room) + 1e-3."""
    return np.array([tangent * math.cos(angle), tangent * (1.0 + room) + 1e-3,
                     tangent * math.sin(angle)])


points = st.builds(_inside, st.floats(0.0, 10.0), st.floats(-math.pi, math.pi),
                   st.floats(1e-3, 10.0))


@given(points, st.just(0.0) | st.floats(0.05, 2.0), st.floats(0.1, 100.0))
def test_inverse_hessian_of_the_barrier_problem(x, mu, scale):
    """P = t B^T B + grad^2 phi, phi = -log Q (Hessian -2 J / Q + 4 J x x^T J / Q^2), t = 1 /
    r0^2, B = diag(1, 1 / mu, 1) (diag(0, 1, 0) for mu = 0): the kernel's P^-1 and gradient
    t B^T B x - 2 J x / Q agree with numpy's to 1e-9 of their size."""
    b = np.diag([1.0, 1.0 / mu, 1.0]) if mu > 0.0 else np.diag([0.0, 1.0, 0.0])
    t = 1.0 / scale**2
    q = x @ J @ x
    p = t * b.T @ b - 2.0 * J / q + 4.0 * np.outer(J @ x, J @ x) / q**2
    inv, grad = np.empty((3, 3)), np.empty(3)
    _lorentz_hessian_inverse(b, x, scale, inv, grad)
    expected = np.linalg.inv(p)
    assert np.abs(inv - expected).max() <= 1e-9 * np.abs(expected).max()
    assert np.array_equal(inv, inv.T)
    gradient = t * b.T @ b @ x - 2.0 * J @ x / q
    assert grad == pytest.approx(gradient, rel=1e-9, abs=1e-9 * np.abs(gradient).max())


@given(points, st.tuples(*[st.floats(-10.0, 10.0)] * 3))
def test_exit_step_reaches_the_cone_boundary_first(x, dx):
    """a = _lorentz_exit(x, dx): x + a dx on the boundary (x_n = |x_T| to 1e-7 of |x| + a |dx|:
    a line through the apex has a double root, which round-off moves by sqrt(1e-16) relative)
    and x + s a dx inside for s < 1 (0.25 to 0.99, to round-off); inf when the half-line stays
    inside."""
    dx = np.array(dx)
    a = _lorentz_exit(x, dx)
    assert a > 0.0

    def room(y):
        return y[1] - math.hypot(y[0], y[2])

    for s in (0.25, 0.5, 0.9, 0.99):
        if math.isfinite(a):
            assert room(x + s * a * dx) > -1e-12 * (np.abs(x).max() + a * np.abs(dx).max())
        else:
            assert room(x + 10.0**(6 * s) * dx) >= 0.0
    if math.isfinite(a):
        end = x + a * dx
        assert abs(room(end)) <= 1e-7 * (np.abs(x).max() + a * np.abs(dx).max())
