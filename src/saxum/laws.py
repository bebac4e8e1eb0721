"""Contact laws: the unilateral condition in the normal direction and Coulomb friction.

Each law is written, for an active contact alpha, as the complementarity
    U_n + b_n >= 0,   R_n >= 0,   (U_n + b_n) R_n = 0,
with Coulomb's law |R_t| <= mu R_n, R_t = -mu R_n U_t/|U_t| if U_t != 0, where U is the relative
velocity at the end of the step and b_n a shift that depends on the law (NSCD.md; M. Jean,
CMAME 177, 1999; names after LMGC90's families):

- SIGNORINI_COULOMB (IQS_CLB): active for every contact within the alert distance,
  b_n = max(g, 0) / (theta h), g the gap on the predicted configuration: an open contact may
  close exactly by the end of the step, a closed one gets U_n >= 0 (inelastic shock). It never
  pushes blocks apart, so an interpenetration, once made, stays.
- RESTITUTION_COULOMB (RST_CLB): active when g <= 0, b_n = e_n min(U_n^-, 0) (Newton's law,
  U_n^+ >= -e_n U_n^-).
- GAP_SIGNORINI_COULOMB (GAP_SGR_CLB, default): the same velocity problem as SIGNORINI_COULOMB,
  then a projection of the positions onto g >= 0 at the end of the step (pseudo-velocities,
  frictionless; saxum.solver.projection), which removes interpenetration and drift without
  adding a separation velocity. (A gap target b_n = g / (theta h) in the velocity problem, as
  NSCD.md writes the law, makes impacts rebound as if elastic when theta = 1/2.)
"""

import math
from dataclasses import dataclass
from enum import IntEnum

from .errors import InputError

__all__ = ["MAX_LAW_POINTS", "ContactLaw", "LawKind"]

MAX_LAW_POINTS = 15
"""Most points a 2D face-to-face contact may get (`ContactLaw.points`): seven Simpson panels."""


class LawKind(IntEnum):
    """The normal part of a contact law (friction is Coulomb for all)."""

    SIGNORINI_COULOMB = 0
    RESTITUTION_COULOMB = 1
    GAP_SIGNORINI_COULOMB = 2


@dataclass(frozen=True)
class ContactLaw:
    """A contact law: friction coefficient mu [-], kind, restitution e_n [-] (RESTITUTION only).

    points: contact points of a face-to-face contact, for laws written in stresses
    (saxum.detection.polygons, .polyhedra). 2 (default): the ends of the common segment (3D:
    the corners of the contact polygon), each standing for an equal share: a trapezoid rule,
    which is all a dry law needs (it ignores the areas) but which makes a joint's rotational
    stiffness 3 times too high. 2D: an odd number n >= 3 adds points so that the ends and
    the new points form (n - 1) / 2 Simpson panels (3-point Gauss-Lobatto, weights 1/6, 4/6,
    1/6 of a panel): exact for the force and moment of a linear stress and for the
    rotational stiffness. 3D: 3 adds the midpoints of the polygon's edges and a centre, with
    a rule exact for linear stresses (module doc of saxum.detection.polyhedra).
    """

    friction: float
    kind: LawKind = LawKind.GAP_SIGNORINI_COULOMB
    restitution: float = 0.0
    points: int = 2

    def __post_init__(self) -> None:
        if not (math.isfinite(self.friction) and self.friction >= 0.0):
            raise InputError(f"friction must be a finite number >= 0, got {self.friction}")
        if not (math.isfinite(self.restitution) and 0.0 <= self.restitution <= 1.0):
            raise InputError(f"restitution must be in [0, 1], got {self.restitution}")
        if self.restitution != 0.0 and self.kind != LawKind.RESTITUTION_COULOMB:
            raise InputError(
                f"restitution={self.restitution} is only used by LawKind.RESTITUTION_COULOMB, "
                f"not by {self.kind.name}; set kind=LawKind.RESTITUTION_COULOMB or drop it"
            )
        if not (isinstance(self.points, int) and (self.points == 2 or (
                3 <= self.points <= MAX_LAW_POINTS and self.points % 2 == 1))):
            raise InputError(
                f"points={self.points!r}: a face-to-face contact takes 2 points (its ends) or an "
                f"odd number from 3 to {MAX_LAW_POINTS} (Simpson panels); use 3 for a joint in "
                "stresses"
            )
        object.__setattr__(self, "kind", LawKind(self.kind))
