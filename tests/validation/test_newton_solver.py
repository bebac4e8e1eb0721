"""Semismooth Newton on the Alart-Curnier function (saxum.solver.newton) on local problems
u = W r + q with closed-form solutions (FCLIB order [normal, tangent(s)]), and on the step of
the shaken stack at which Gauss-Seidel stalls.

One contact with a diagonal W (Coulomb's law, NSCD.md): pressed with a tangential load inside
the cone it sticks, r = -W^-1 q (u = 0); pushed harder than friction holds it slides, r on the
cone's edge, r_N = -q_N / W_NN, r_T = -mu r_N q_T / |q_T| (the slip along q_T); with q_N > 0 it
separates, r = 0. A block on two contact points that only translate (a redundant problem: W of
rank 2 for 4 unknowns, the impulses not unique): u = 0 and the normal impulses carry the load,
r_N1 + r_N2 = -q_N / W_NN-part. Tolerances: 1e-10 (the solver's natural-map tolerance 1e-12,
relative to |q| of order one, and round-off).
"""

import math
import warnings

import numpy as np
import pytest
import scipy.sparse as sp

import saxum as sx
from saxum.solver.newton import alart_curnier_newton
from saxum.solver.residual import natural_map_error
from saxum.structures import wall


def _solve(w, q, mu, dim):
    w = sp.csr_matrix(np.asarray(w, dtype=float))
    result = alart_curnier_newton(w, np.asarray(q, dtype=float), np.asarray(mu, dtype=float),
                                  dim, tolerance=1e-12)
    assert result.error <= 1e-12
    assert result.error == natural_map_error(w, np.asarray(q, dtype=float),
                                             np.asarray(mu, dtype=float), result.r, dim)
    return result.r


@pytest.mark.parametrize("dim", [2, 3])
def test_contact_sticks(dim):
    w = np.diag([2.0, 1.0, 1.0][:dim])
    q = np.array([-1.0, 0.1, -0.05][:dim])  # |r_T| = 0.1 (0.11) < 0.5 x r_N = 0.25
    r = _solve(w, q, [0.5], dim)
    assert r == pytest.approx(-q / np.diag(w), abs=1e-10)


@pytest.mark.parametrize("dim", [2, 3])
def test_contact_slides(dim):
    w = np.diag([2.0, 1.0, 1.0][:dim])
    q = np.array([-1.0, 3.0, 4.0][:dim])
    mu = 0.5
    r = _solve(w, q, [mu], dim)
    direction = q[1:] / np.linalg.norm(q[1:])
    assert r[0] == pytest.approx(0.5, abs=1e-10)
    assert r[1:] == pytest.approx(-mu * 0.5 * direction, abs=1e-10)


@pytest.mark.parametrize("dim", [2, 3])
def test_contact_separates(dim):
    r = _solve(np.diag([2.0, 1.0, 1.0][:dim]), [0.3, 1.0, -2.0][:dim], [0.5], dim)
    assert np.abs(r).max() <= 1e-10


def test_redundant_contacts_at_rest():
    """A body of mass 2 kg that translates in the plane (2 dof) on two contact points with the
    same frame: H* has the rows (n, t) twice, W = H* M^-1 H*^T = 0.5 [[I, I], [I, I]] (rank 2
    of 4), q = H* v_free with v_free = (0.1, -0.3) m/s (pushed sideways within the cone)."""
    h = np.array([[0.0, 1.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0]])  # rows (n, t) per contact
    w = 0.5 * h @ h.T
    q = h @ np.array([0.1, -0.3])
    r = _solve(w, q, [0.6, 0.6], 2)
    u = w @ r + q
    assert np.abs(u).max() <= 1e-10
    assert r[0] + r[2] == pytest.approx(0.6, abs=1e-10)  # 2 kg x 0.3 m/s
    assert r[1] + r[3] == pytest.approx(-0.2, abs=1e-10)  # 2 kg x -0.1 m/s


def _shaken_stack():
    """The stack-bond wall of 10 courses x 2 bricks of benchmarks/convergence.py
    (stack-shaken) under a horizontal acceleration of 0.7 g."""
    import dataclasses

    model = wall(courses=10, bricks=2, bond="stack")
    g = float(np.hypot(*model.gravity))
    return dataclasses.replace(model, accelerations=((lambda t: (0.7 * g, 0.0)),))


def test_hybrid_solves_the_stalled_step_of_the_shaken_stack():
    """Step 7 of the shaken stack: NLGS alone stops at its cap (error 1.5e-6 > 1e-6), the
    conic fixed point's iterate is no better (natural-map error 4e-5: the friction threshold,
    docs/method.md), semismooth Newton from zero impulses solves it (natural-map error 2e-9)
    and one NLGS sweep confirms it."""
    logs = []
    for solver in (sx.NLGS(), sx.Hybrid()):
        sim = sx.Simulation(_shaken_stack(), dt=1e-3, solver=solver)
        state = sim.initial_state()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sx.SolverWarning)
            for _ in range(7):
                sim.step(state)
        logs.append(sim.log)
    assert not logs[0].converged[6] and math.isfinite(logs[0].error[6])
    assert logs[1].converged.all()
    assert logs[1].solver[6] == sx.solver.SOLVER_NAMES.index("newton")
