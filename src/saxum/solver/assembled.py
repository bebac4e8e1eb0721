"""A step's contact problem assembled as sparse matrices, in FCLIB's order.

The time stepper never assembles W (NLGS works through the body velocities), but a solver that
factorizes (saxum.solver.conic) and the FCLIB export need it. For the active contacts of a
ContactProblem (or a view with its arrays), per contact a the rows of H* (h_cand, h_ant) in the
order [n, t(, s)], M^-1 = diag(model.body_inv_mass):
    W = H* M^-1 H*^T,   q = H* v_free + b e_n,
and the impulses R give v = v_free + M^-1 H*^T R [m/s, rad/s].
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from .residual import natural_map_error

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = ["AssembledProblem", "assemble_local", "fclib_order"]


def fclib_order(dim: int) -> list[int]:
    """saxum component (t, n[, s]) of each FCLIB component [n, t[, s]]."""
    return [1, 0, 2][:dim]


@dataclass(frozen=True)
class AssembledProblem:
    """active: indices of the active contacts; hstar (active x dim, bodies x dof) CSR;
    inv_mass (bodies x dof, flat) [1/kg, 1/(kg m^2)]; q [m/s] and mu [-] of the local problem
    u = W r + q; w (CSR) [1/kg], formed on first use."""

    active: np.ndarray
    hstar: sp.csr_matrix
    inv_mass: np.ndarray
    q: np.ndarray
    mu: np.ndarray

    @cached_property
    def w(self) -> sp.csr_matrix:
        import scipy.sparse as sp

        w = (self.hstar @ sp.diags(self.inv_mass) @ self.hstar.T).tocsr()
        w.sum_duplicates()
        return w

    def impulses(self, impulse: np.ndarray) -> np.ndarray:
        """The active contacts' impulses [N s] (count, dim) in saxum's frame -> flat r."""
        dim = impulse.shape[1]
        return impulse[self.active][:, fclib_order(dim)].ravel()

    def natural_map_error(self, impulse: np.ndarray) -> float:
        """||F_nat(r)|| / ||q|| (saxum.solver.residual) of the active contacts' impulses [N s]
        (count, dim), u = W r + q recomputed from them; 0 without active contacts."""
        if self.active.size == 0:
            return 0.0
        return natural_map_error(self.w, self.q, self.mu, self.impulses(impulse),
                                 impulse.shape[1])

    def scatter(self, r: np.ndarray, v_free: np.ndarray, impulse: np.ndarray,
                v: np.ndarray) -> None:
        """impulse = r on the active contacts (0 on the others), v = v_free + M^-1 H*^T r."""
        dim = impulse.shape[1]
        impulse[:] = 0.0
        impulse[self.active[:, None], fclib_order(dim)] = r.reshape(-1, dim)
        v[:] = v_free + (self.inv_mass * (self.hstar.T @ r)).reshape(v.shape)


def assemble_local(problem, v_free: np.ndarray) -> AssembledProblem:
    """The module doc's H*, W and q for the active contacts of `problem`; v_free [m/s, rad/s]
    (bodies, dof)."""
    import scipy.sparse as sp  # ~0.25 s: imported by the runs that assemble W

    model = problem.model
    dim, dof = model.dim, model.dof
    contacts = problem.contacts
    active = np.flatnonzero(problem.active[: problem.count])
    order = fclib_order(dim)
    nc = active.size
    rows = np.repeat(np.arange(nc * dim), 2 * dof)
    body = np.stack([contacts.candidate[active], contacts.antagonist[active]], axis=1)
    cols = (body[:, None, :, None] * dof + np.arange(dof)).repeat(dim, axis=1)
    vals = np.stack([problem.h_cand[active][:, order], problem.h_ant[active][:, order]], axis=2)
    hstar = sp.csr_matrix((vals.ravel(), (rows, cols.ravel())),
                          shape=(nc * dim, model.body_count * dof))
    shift = np.zeros((nc, dim))
    shift[:, 0] = problem.bias[active]
    q = hstar @ v_free.ravel() + shift.ravel()
    return AssembledProblem(active, hstar, model.body_inv_mass.ravel(), q,
                            problem.friction[active].copy())
