"""Nonlinear Gauss-Seidel (NLGS) over the contacts, in "exchange local-global" form.

Each sweep visits the contacts in order; for contact alpha it computes the local velocity from
the current body velocities, removes its own contribution (u = U - W_aa R_a), solves the
single-contact problem exactly with W_aa, relaxes R_a <- omega R_new + (1 - omega) R_a, and
pushes the change straight into the body velocities, v += M^-1 H_a dR. W is never assembled, so
a sweep costs O(contacts) (M. Jean, CMAME 177, 1999; NSCD.md).

Convergence: LMGC90's "Quad" criterion compares a quadratic mean of the impulse change over a
sweep with the impulses. Here the quadratic form is the Delassus one, dR^T W dR = |H dR|^2_M^-1,
evaluated through the body velocities (which the sweep keeps anyway):
    error = sqrt( sum_b |v_b - v_b^prev|^2_M / sum_b |v_b - v_b^free|^2_M ),   |x|^2_M = x^T M x,
(plus a round-off floor 1e-14 |v|_M in the denominator),
v^prev the velocities before the sweep. It is the W-norm of the sweep's impulse change relative
to the W-norm of the impulse, and unlike a per-contact norm it ignores self-equilibrated impulse
changes (H dR = 0), which are indeterminate for rigid blocks and do not move anything; so a
statically indeterminate wall at rest converges instead of wandering in that null space.
The solve stops when error <= tolerance or after max_iterations sweeps.
"""

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from ..errors import InputError
from .base import ContactSolver, SolverReport
from .local2d import solve_contact_2d
from .local3d import solve_contact_3d
from .problem import ContactProblem

__all__ = ["NLGS"]


@dataclass
class NLGS(ContactSolver):
    """tolerance [-] on the relative change per sweep (see module doc), max_iterations sweeps
    per step, relaxation omega in (0, 1]."""

    tolerance: float = 1e-6
    max_iterations: int = 5000
    relaxation: float = 1.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.tolerance) and self.tolerance > 0.0):
            raise InputError(f"solver.tolerance must be > 0, got {self.tolerance}")
        if self.max_iterations < 1:
            raise InputError(f"solver.max_iterations must be >= 1, got {self.max_iterations}")
        if not (0.0 < self.relaxation <= 1.0):
            raise InputError(f"solver.relaxation must be in (0, 1], got {self.relaxation}")
        self._v_prev = np.empty((0, 0))

    def solve(self, problem: ContactProblem, impulse: np.ndarray, v_free: np.ndarray,
              v: np.ndarray) -> SolverReport:
        c = problem.contacts
        if self._v_prev.shape != v.shape:
            self._v_prev = np.empty_like(v)
        sweep = nlgs_3d if problem.model.dim == 3 else nlgs_2d
        iterations, error = sweep(
            c.candidate, c.antagonist, problem.h_cand, problem.h_ant, problem.delassus,
            problem.bias, problem.friction, problem.active, problem.count,
            problem.model.body_inv_mass, v_free, v, self._v_prev, impulse,
            self.tolerance, self.max_iterations, self.relaxation,
        )
        return SolverReport(iterations=iterations, error=error, converged=error <= self.tolerance)


@nb.njit(cache=True)
def nlgs_2d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass, v_free,
            v, v_prev, impulse, tolerance, max_iterations, relaxation):
    """Run NLGS sweeps; returns (sweeps done, final error). Updates v and impulse in place;
    v_prev is work memory shaped like v. Written out for 2D rigid bodies (3 dof, frame (t, n)):
    the unrolled loads and stores halve the cost of a contact update against loops over dof."""
    nactive = 0
    for a in range(count):
        nactive += active[a]
    if nactive == 0:
        return 0, 0.0
    error = np.inf
    it = 0
    while it < max_iterations:
        it += 1
        v_prev[:] = v
        for k in range(count):
            a = count - 1 - k
            if not active[a]:
                continue
            c = cand[a]
            b = ant[a]
            vc0, vc1, vc2 = v[c, 0], v[c, 1], v[c, 2]
            vb0, vb1, vb2 = v[b, 0], v[b, 1], v[b, 2]
            wtt = delassus[a, 0, 0]
            wtn = delassus[a, 0, 1]
            wnn = delassus[a, 1, 1]
            rt0 = impulse[a, 0]
            rn0 = impulse[a, 1]
            ut = (h_cand[a, 0, 0] * vc0 + h_cand[a, 0, 1] * vc1 + h_cand[a, 0, 2] * vc2
                  + h_ant[a, 0, 0] * vb0 + h_ant[a, 0, 1] * vb1 + h_ant[a, 0, 2] * vb2
                  - wtt * rt0 - wtn * rn0)
            un = (h_cand[a, 1, 0] * vc0 + h_cand[a, 1, 1] * vc1 + h_cand[a, 1, 2] * vc2
                  + h_ant[a, 1, 0] * vb0 + h_ant[a, 1, 1] * vb1 + h_ant[a, 1, 2] * vb2
                  - wtn * rt0 - wnn * rn0)
            rt, rn = solve_contact_2d(wtt, wtn, wnn, ut, un + bias[a], friction[a])
            if relaxation != 1.0:
                rt = relaxation * rt + (1.0 - relaxation) * rt0
                rn = relaxation * rn + (1.0 - relaxation) * rn0
            dt = rt - rt0
            dn = rn - rn0
            if dt != 0.0 or dn != 0.0:
                # v += M^-1 H_a (dt, dn) on the candidate c and the antagonist b
                v[c, 0] = vc0 + inv_mass[c, 0] * (h_cand[a, 0, 0] * dt + h_cand[a, 1, 0] * dn)
                v[c, 1] = vc1 + inv_mass[c, 1] * (h_cand[a, 0, 1] * dt + h_cand[a, 1, 1] * dn)
                v[c, 2] = vc2 + inv_mass[c, 2] * (h_cand[a, 0, 2] * dt + h_cand[a, 1, 2] * dn)
                v[b, 0] = vb0 + inv_mass[b, 0] * (h_ant[a, 0, 0] * dt + h_ant[a, 1, 0] * dn)
                v[b, 1] = vb1 + inv_mass[b, 1] * (h_ant[a, 0, 1] * dt + h_ant[a, 1, 1] * dn)
                v[b, 2] = vb2 + inv_mass[b, 2] * (h_ant[a, 0, 2] * dt + h_ant[a, 1, 2] * dn)
            impulse[a, 0] = rt
            impulse[a, 1] = rn
        error = _relative_change(v, v_prev, v_free, inv_mass)
        if error <= tolerance:
            break
    return it, error


@nb.njit(cache=True)
def _relative_change(v, v_prev, v_free, inv_mass):
    """sqrt(|v - v_prev|^2_M / (|v - v_free|^2_M + (1e-14 |v|_M)^2)), 0 when nothing changed.
    The second term of the denominator is the round-off floor: a change below ~1e-14 of the
    velocities themselves cannot be resolved in double precision, so a contact with a tiny
    impulse on a fast body must not keep the solver sweeping."""
    num = 0.0
    den = 0.0
    size = 0.0
    for b in range(v.shape[0]):
        for d in range(v.shape[1]):
            if inv_mass[b, d] > 0.0:
                num += (v[b, d] - v_prev[b, d]) ** 2 / inv_mass[b, d]
                den += (v[b, d] - v_free[b, d]) ** 2 / inv_mass[b, d]
                size += v[b, d] ** 2 / inv_mass[b, d]
    if num == 0.0:
        return 0.0
    den += 1e-28 * size
    if den == 0.0:
        return np.inf
    return math.sqrt(num / den)


@nb.njit(cache=True)
def nlgs_3d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass, v_free,
            v, v_prev, impulse, tolerance, max_iterations, relaxation):
    """nlgs_2d for 3D rigid bodies (6 dof, frame (t, n, s)): the single-contact problem on the
    Coulomb cone is solved exactly by saxum.solver.local3d.solve_contact_3d."""
    nactive = 0
    for a in range(count):
        nactive += active[a]
    if nactive == 0:
        return 0, 0.0
    u = np.empty(3)
    r = np.empty(3)
    r0 = np.empty(3)
    error = np.inf
    it = 0
    while it < max_iterations:
        it += 1
        v_prev[:] = v
        for k in range(count):
            a = count - 1 - k
            if not active[a]:
                continue
            c = cand[a]
            b = ant[a]
            w = delassus[a]
            for i in range(3):
                r0[i] = impulse[a, i]
            for i in range(3):
                ui = 0.0
                for d in range(6):
                    ui += h_cand[a, i, d] * v[c, d] + h_ant[a, i, d] * v[b, d]
                u[i] = ui - (w[i, 0] * r0[0] + w[i, 1] * r0[1] + w[i, 2] * r0[2])
                r[i] = r0[i]
            u[1] += bias[a]
            solve_contact_3d(w, u, friction[a], r)
            if relaxation != 1.0:
                for i in range(3):
                    r[i] = relaxation * r[i] + (1.0 - relaxation) * r0[i]
            d0 = r[0] - r0[0]
            d1 = r[1] - r0[1]
            d2 = r[2] - r0[2]
            if d0 != 0.0 or d1 != 0.0 or d2 != 0.0:
                # v += M^-1 H_a dR on the candidate c and the antagonist b
                for d in range(6):
                    v[c, d] += inv_mass[c, d] * (h_cand[a, 0, d] * d0 + h_cand[a, 1, d] * d1
                                                 + h_cand[a, 2, d] * d2)
                    v[b, d] += inv_mass[b, d] * (h_ant[a, 0, d] * d0 + h_ant[a, 1, d] * d1
                                                 + h_ant[a, 2, d] * d2)
            impulse[a, 0] = r[0]
            impulse[a, 1] = r[1]
            impulse[a, 2] = r[2]
        error = _relative_change(v, v_prev, v_free, inv_mass)
        if error <= tolerance:
            break
    return it, error
