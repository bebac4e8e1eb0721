"""The discrete contact problem of one step, in the local frames of the contacts.

For each contact alpha: the rows of H*_alpha on the candidate and antagonist velocities, the
Delassus block W_alpha_alpha = H*_c M_c^-1 H_c + H*_a M_a^-1 H_a, the shift b_n of the law
(see saxum.laws), the friction coefficient, and whether the contact is active this step.
With v the end-of-step velocities, U_alpha = H*_alpha v and v = v_free + M^-1 H R (NSCD.md).
"""

import numba as nb
import numpy as np

from .. import rigid2d, rigid3d
from ..contacts import Contacts
from ..laws import LawKind
from ..model import Model

__all__ = ["ContactProblem"]

_RESTITUTION = int(LawKind.RESTITUTION_COULOMB)


class ContactProblem:
    """Work arrays of the local problem (first `count` rows valid), reused from step to step."""

    def __init__(self, model: Model) -> None:
        self.model = model
        self.count = 0
        self._allocate(64)

    def _allocate(self, capacity: int) -> None:
        d, dof = self.model.dim, self.model.dof
        self.capacity = capacity
        self.h_cand = np.zeros((capacity, d, dof))
        """Rows of H* on the candidate's velocity [-, m], shape [capacity, dim, dof]."""
        self.h_ant = np.zeros((capacity, d, dof))
        """Rows of H* on the antagonist's velocity [-, m], shape [capacity, dim, dof]."""
        self.delassus = np.zeros((capacity, d, d))
        """Diagonal Delassus block W_alpha_alpha [1/kg], shape [capacity, dim, dim]."""
        self.bias = np.zeros(capacity)
        """Shift b_n of the normal condition U_n + b_n >= 0 [m/s], shape [capacity]."""
        self.friction = np.zeros(capacity)
        """Coulomb coefficient mu [-], shape [capacity]."""
        self.active = np.zeros(capacity, dtype=np.bool_)
        """Contact enters the solve this step (else R = 0), shape [capacity]."""

    def assemble(
        self, contacts: Contacts, q: np.ndarray, v_begin: np.ndarray, h: float, theta: float,
        closed_gap: float,
    ) -> None:
        """Build the problem of `contacts` detected on configuration q [m, rad]; v_begin is the
        velocity at the start of the step (for restitution), h [s] the step, theta [-].
        closed_gap [m]: velocity-level laws treat a contact as closed (active) when its gap is
        below this round-off tolerance, so that blocks built touching are in contact at once."""
        if contacts.count > self.capacity:
            self._allocate(max(contacts.count, 2 * self.capacity))
        self.count = k = contacts.count
        m = self.model
        self.contacts = contacts
        jacobians = rigid3d.contact_jacobians if m.dim == 3 else rigid2d.contact_jacobians
        jacobians(q, contacts.candidate, contacts.antagonist, contacts.point,
                  contacts.frame, contacts.gap, k, self.h_cand, self.h_ant)
        _assemble(contacts.candidate, contacts.antagonist, contacts.law, contacts.gap, k,
                  self.h_cand, self.h_ant, m.body_inv_mass, v_begin, m.law_kind,
                  m.law_friction, m.law_restitution, h, theta, closed_gap,
                  self.delassus, self.bias, self.friction, self.active)

    def apply_impulses(self, impulse: np.ndarray, v: np.ndarray) -> None:
        """v += M^-1 H R for the current impulses (the warm start); inactive contacts' R = 0."""
        c = self.contacts
        _apply(c.candidate, c.antagonist, self.h_cand, self.h_ant, self.active, self.count,
               self.model.body_inv_mass, impulse, v)

    def statistics(self, impulse: np.ndarray, v: np.ndarray, w: np.ndarray | None, h: float,
                   theta: float):
        """(active contacts with R_n > 0, largest end-of-step interpenetration [m]), the gap at
        the end estimated as g + theta h U_n(v) + h U_n(w), w the projection's pseudo-velocity
        (saxum.solver.projection; None when there was no projection)."""
        c = self.contacts
        return _statistics(c.candidate, c.antagonist, self.h_cand, self.h_ant, c.gap, self.count,
                           impulse, v, w if w is not None else v, 0.0 if w is None else h, h,
                           theta)


@nb.njit(inline="always")
def _local_velocity(h_cand, h_ant, a, r, c, b, v):
    u = 0.0
    for d in range(v.shape[1]):
        u += h_cand[a, r, d] * v[c, d] + h_ant[a, r, d] * v[b, d]
    return u


@nb.njit(cache=True)
def _assemble(cand, ant, law, gap, count, h_cand, h_ant, inv_mass, v_begin, law_kind,
              law_friction, law_restitution, h, theta, closed_gap, delassus, bias, friction,
              active):
    dim = h_cand.shape[1]
    h_theta = h * theta
    for a in range(count):
        c = cand[a]
        b = ant[a]
        for r in range(dim):
            for s in range(dim):
                w = 0.0
                for d in range(inv_mass.shape[1]):
                    w += (h_cand[a, r, d] * inv_mass[c, d] * h_cand[a, s, d]
                          + h_ant[a, r, d] * inv_mass[b, d] * h_ant[a, s, d])
                delassus[a, r, s] = w
        kind = law_kind[law[a]]
        friction[a] = law_friction[law[a]]
        # Gaps within +-closed_gap count as exactly closed: targets that differ by round-off
        # would be incompatible in a statically indeterminate assembly.
        g = gap[a] - min(max(gap[a], -closed_gap), closed_gap)
        if kind == _RESTITUTION:
            active[a] = gap[a] <= closed_gap
            un = _local_velocity(h_cand, h_ant, a, 1, c, b, v_begin)
            bias[a] = law_restitution[law[a]] * min(un, 0.0)
        else:
            # Signorini and gap-based: an open contact may close exactly by the end of the step
            # (g + theta h U_n >= 0), a closed one gets U_n >= 0; the gap-based law's
            # interpenetration is removed afterwards by saxum.solver.projection.
            active[a] = True
            bias[a] = max(g, 0.0) / h_theta


@nb.njit(cache=True)
def _apply(cand, ant, h_cand, h_ant, active, count, inv_mass, impulse, v):
    for a in range(count):
        if not active[a]:
            impulse[a, :] = 0.0
            continue
        c = cand[a]
        b = ant[a]
        for d in range(v.shape[1]):
            fc = 0.0
            fa = 0.0
            for r in range(impulse.shape[1]):
                fc += h_cand[a, r, d] * impulse[a, r]
                fa += h_ant[a, r, d] * impulse[a, r]
            v[c, d] += inv_mass[c, d] * fc
            v[b, d] += inv_mass[b, d] * fa


@nb.njit(cache=True)
def _statistics(cand, ant, h_cand, h_ant, gap, count, impulse, v, w, h_w, h, theta):
    loaded = 0
    worst = 0.0
    for a in range(count):
        if impulse[a, 1] > 0.0:
            loaded += 1
        g_end = gap[a] + theta * h * _local_velocity(h_cand, h_ant, a, 1, cand[a], ant[a], v)
        if h_w != 0.0:
            g_end += h_w * _local_velocity(h_cand, h_ant, a, 1, cand[a], ant[a], w)
        worst = max(worst, -g_end)
    return loaded, worst
