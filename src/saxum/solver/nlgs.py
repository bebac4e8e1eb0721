"""Nonlinear Gauss-Seidel (NLGS) over the contacts, in "exchange local-global" form.

Each sweep visits the contacts in order; for contact alpha it computes the local velocity from
the current body velocities, removes its own contribution (u = U - W_aa R_a), solves the
single-contact problem exactly with W_aa, relaxes R_a <- omega R_new + (1 - omega) R_a, and
pushes the change straight into the body velocities, v += M^-1 H_a dR. W is never assembled, so
a sweep costs O(contacts) (M. Jean, CMAME 177, 1999; NSCD.md).

Convergence ("Quad", LMGC90): after each sweep,
    error = sqrt( sum_a |dR_a|^2 / m ) / ( sum_a |R_a| / m ),
the quadratic mean of the impulse change over the sweep relative to the mean impulse, m the
number of active contacts; the solve stops when error <= tolerance or after max_iterations sweeps.
"""

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from ..errors import InputError
from .base import ContactSolver, SolverReport
from .local2d import solve_contact_2d
from .problem import ContactProblem

__all__ = ["NLGS"]


@dataclass
class NLGS(ContactSolver):
    """tolerance [-] on the Quad error, max_iterations sweeps per step, relaxation omega in (0, 1]."""

    tolerance: float = 1e-4
    max_iterations: int = 1000
    relaxation: float = 1.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.tolerance) and self.tolerance > 0.0):
            raise InputError(f"solver.tolerance must be > 0, got {self.tolerance}")
        if self.max_iterations < 1:
            raise InputError(f"solver.max_iterations must be >= 1, got {self.max_iterations}")
        if not (0.0 < self.relaxation <= 1.0):
            raise InputError(f"solver.relaxation must be in (0, 1], got {self.relaxation}")

    def solve(self, problem: ContactProblem, impulse: np.ndarray, v: np.ndarray) -> SolverReport:
        c = problem.contacts
        iterations, error = nlgs_2d(
            c.candidate, c.antagonist, problem.h_cand, problem.h_ant, problem.delassus,
            problem.bias, problem.friction, problem.active, problem.count,
            problem.model.body_inv_mass, v, impulse,
            self.tolerance, self.max_iterations, self.relaxation,
        )
        return SolverReport(iterations=iterations, error=error, converged=error <= self.tolerance)


@nb.njit(cache=True)
def nlgs_2d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass, v,
            impulse, tolerance, max_iterations, relaxation):
    """Run NLGS sweeps; returns (sweeps done, final Quad error). Updates v and impulse in place."""
    ndof = v.shape[1]
    nactive = 0
    for a in range(count):
        nactive += active[a]
    if nactive == 0:
        return 0, 0.0
    error = np.inf
    it = 0
    while it < max_iterations:
        it += 1
        sum_dr2 = 0.0
        sum_r = 0.0
        for a in range(count):
            if not active[a]:
                continue
            c = cand[a]
            b = ant[a]
            ut = 0.0
            un = 0.0
            for d in range(ndof):
                ut += h_cand[a, 0, d] * v[c, d] + h_ant[a, 0, d] * v[b, d]
                un += h_cand[a, 1, d] * v[c, d] + h_ant[a, 1, d] * v[b, d]
            wtt = delassus[a, 0, 0]
            wtn = delassus[a, 0, 1]
            wnn = delassus[a, 1, 1]
            rt0 = impulse[a, 0]
            rn0 = impulse[a, 1]
            ut -= wtt * rt0 + wtn * rn0
            un -= wtn * rt0 + wnn * rn0
            rt, rn = solve_contact_2d(wtt, wtn, wnn, ut, un + bias[a], friction[a])
            if relaxation != 1.0:
                rt = relaxation * rt + (1.0 - relaxation) * rt0
                rn = relaxation * rn + (1.0 - relaxation) * rn0
            dt = rt - rt0
            dn = rn - rn0
            if dt != 0.0 or dn != 0.0:
                _push(h_cand, h_ant, a, c, b, inv_mass, v, dt, dn)
            impulse[a, 0] = rt
            impulse[a, 1] = rn
            sum_dr2 += dt * dt + dn * dn
            sum_r += math.sqrt(rt * rt + rn * rn)
        if sum_dr2 == 0.0:
            error = 0.0
        elif sum_r > 0.0:
            error = math.sqrt(sum_dr2 * nactive) / sum_r
        else:
            error = np.inf
        if error <= tolerance:
            break
    return it, error


@nb.njit(inline="always")
def _push(h_cand, h_ant, a, c, b, inv_mass, v, dt, dn):
    """v += M^-1 H_a (dt, dn) on the candidate c and the antagonist b."""
    for d in range(v.shape[1]):
        v[c, d] += inv_mass[c, d] * (h_cand[a, 0, d] * dt + h_cand[a, 1, d] * dn)
        v[b, d] += inv_mass[b, d] * (h_ant[a, 0, d] * dt + h_ant[a, 1, d] * dn)
