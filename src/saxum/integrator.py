"""Moreau-Jean theta-method (NSCD.md; M. Jean, CMAME 177, 1999), step [t_i, t_i+1] of length h:

    v_free = v_i + h M^-1 [(1 - theta) F(t_i) + theta F(t_i+1)]
    q_pred = q_i + (1 - theta) h v_i                       (configuration for detection)
    v_i+1  = v_free + M^-1 H R                             (R from the contact solver)
    q_i+1  = q_i + h [(1 - theta) v_i + theta v_i+1]

theta in [0.5, 1]; 0.5 (the default, as LMGC90 users take it) is exact for a free body under
constant forces.
"""

import math
from dataclasses import dataclass

import numba as nb

from .errors import InputError

__all__ = ["MoreauJean", "diagonal_free_velocity"]


@dataclass(frozen=True)
class MoreauJean:
    """Time step h [s] and theta [-] of the Moreau-Jean scheme."""

    dt: float
    theta: float = 0.5

    def __post_init__(self) -> None:
        if not (math.isfinite(self.dt) and self.dt > 0.0):
            raise InputError(f"time step dt must be a finite number > 0 [s], got {self.dt}")
        if not (0.5 <= self.theta <= 1.0):
            raise InputError(f"theta must be in [0.5, 1], got {self.theta}")


@nb.njit(cache=True)
def diagonal_free_velocity(v, inv_mass, force, h, out):
    """out = v + h M^-1 force, M^-1 diagonal per dof (rigid bodies: saxum.bodies); force
    [N, N m] already theta-weighted."""
    for b in range(v.shape[0]):
        for d in range(v.shape[1]):
            out[b, d] = v[b, d] + h * inv_mass[b, d] * force[b, d]
