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

The _g0 variants of these two (`ContactLaw.initial_gap`, LMGC90's IQS_CLB_g0 and
GAP_SGR_CLB_g0) write the condition on g - g0, g0 a contact's gap [m] at the first step of a
run, kept by the contact from step to step (saxum.contacts), so that a joint open at the
start acts as closed: a structure drawn with open joints (LMGC90's arches, joints open by an
angle) stands as if they were closed, with no block moved to close them. As LMGC90's nlgs
(mod_nlgs.f90, mod_nlgs_3D.f90, read for their definitions): for SIGNORINI_COULOMB
g0 = max(g, 0) (an initial interpenetration is not kept) and b_n = max(g - g0, 0) / (theta h);
for GAP_SIGNORINI_COULOMB g0 = g, signed (an initial interpenetration is kept; LMGC90 2D's
definition, its 3D one takes max(g, 0) unless told to manage interpenetrations), and the
projection is onto g >= g0. Contacts that appear after the first step get g0 = 0: the plain
law (LMGC90 keeps g0 only where its solver first met the contact, on its first step).

Joint laws in stresses (per unit of the contact's `area` A [m^2; 2D: m per metre of depth];
parameters in `Parameter`, solved by the same NLGS through saxum.solver.laws_local):

- ELASTIC (after LMGC90's ELASTIC_REPELL_CLB / VISCO_ELASTIC_REPELL_CLB, in stresses and
  theta-weighted: docs/method.md compares them): a normal spring k_n [Pa/m] and
  dashpot c_n [Pa s/m] that only push, sigma_n = max(0, -k_n g - c_n dg/dt), g the gap (its
  negative part the joint's closure), and a tangential spring k_t [Pa/m] in series with a
  Coulomb slider, |tau| <= mu sigma_n (k_t = 0: rigid-plastic Coulomb). No projection: the
  closure is the spring's. A point with no area (edge against edge in 3D) falls back to
  Signorini-Coulomb.
- VISCOUS_COULOMB: the gap law's Signorini condition, and Coulomb friction plus a viscous
  term, |R_t| <= mu R_n + h A eta |U_t| with R_t = -(mu R_n + h A eta |U_t|) U_t / |U_t|
  when U_t != 0 (eta [Pa s/m], U_t [m/s] the sliding velocity at the end of the step): the
  shear stress is mu sigma_n + eta v_t while sliding, at most mu sigma_n while sticking.
  Solved as a dashpot in parallel, |R_t + h A eta U_t| <= mu R_n, the same law (the "viscous
  friction" of the NSCD method, NSCD.md; V. Acary & B. Brogliato, Numerical Methods for
  Nonsmooth Dynamical Systems, Springer 2008, sec. 7: a smooth force in parallel with the
  non-smooth law). The viscous part acts on every active contact of the law, open ones
  within the alert distance too. LMGC90 has no such law (its "viscous law with Coulomb
  threshold" caps the viscous force at mu R_n instead: docs/method.md).
- COHESIVE: a mortar joint, a bond in parallel with a Coulomb contact (the adhesion-friction
  coupling of M. Raous, L. Cangemi & M. Cocu, CMAME 177 (1999) 383-399, and F. Monerie &
  V. Acary, Rev. Eur. Elem. Finis 10 (2001) 489-503). With d in [0, 1] the damage and g the
  gap (g > 0 open), the joint's normal stress (compression > 0) is
      sigma = -k_n g (g <= 0, the contact's),   sigma = -(1 - d) k_n g (g > 0, the bond's),
  so the intact joint (d = 0) is elastic with the same k_n in tension and compression, as
  the interface of P.B. Lourenco & J.G. Rots, "Multisurface interface model for analysis of
  masonry structures", J. Eng. Mech. 123 (1997) 660-668, is until it cracks: its stress
  under a moment is linear (Navier's). The bond's shear stress is tau_b = -(1 - d) k_t s, s
  the tangential jump since bonding, in parallel with Coulomb friction mu sigma on the
  contact's compression, so the intact joint's shear strength under sigma is c + mu sigma
  (Mohr-Coulomb with a tension cut-off f_t), and a fully damaged joint (d = 1) is a Coulomb
  joint, still elastic (k_n) in compression as Lourenco and Rots' interface stays.
  Damage follows the bilinear mixed-mode law of P.P. Camanho &
  C.G. Davila, "Mixed-mode decohesion finite elements for the simulation of delamination in
  composite materials", NASA/TM-2002-211737, with the openings scaled by the onset openings
  delta_n = f_t / k_n, delta_t = c / k_t (so that k_n and k_t may differ):
      lambda = sqrt((<g>+ / delta_n)^2 + (s / delta_t)^2),  kappa = max over time of lambda,
      onset at lambda = 1: (sigma / f_t)^2 + (tau / c)^2 = 1 (their quadratic criterion);
      failure at lambda_f with 1 / lambda_f = cos^2 phi / lambda_I + sin^2 phi / lambda_II,
      cos phi = <g>+ / (delta_n lambda), lambda_I = 2 G_I k_n / f_t^2,
      lambda_II = 2 G_II k_t / c^2 (their linear energy criterion G_n / G_I + G_t / G_II = 1
      for a proportional path: each mode's stress falls linearly to zero at lambda_f);
      d = lambda_f (kappa - 1) / (kappa (lambda_f - 1)) clipped to [0, 1], and d never
      decreases.
  So pure mode I peaks at f_t and dissipates G_I per unit area, pure mode II at c and G_II.
  lambda_I >= 1 and lambda_II >= 1 are needed (else the softening snaps back):
  G_I >= f_t^2 / (2 k_n), G_II >= c^2 / (2 k_t). Joints closed at the start are intact;
  contacts that appear later start fully damaged (a joint does not heal) and, having no
  mortar, are the gap law's rigid Coulomb contacts. No damping: a load applied at once sets
  a bonded assembly vibrating on its joints, which theta = 1/2 (energy-conserving for a
  spring) keeps; so a model with such joints (`undamped_springs`) steps with theta = 1 unless
  told otherwise (saxum.simulation.Simulation), and theta = 1/2 given with them warns.
  Compression cap (optional: f_c > 0 [Pa] with G_fc [J/m^2]): the normal stress of a bonded
  joint (intact or cracked) is bounded, sigma <= sigma_c(w), w >= 0 the joint's plastic
  closure [m] (Contacts.crush, which only grows), with exponential softening
      sigma_c(w) = f_c exp(-f_c w / G_fc),
  so that a joint crushed under growing closure peaks at f_c and dissipates
  int_0^inf sigma_c dw = G_fc per unit area; the closure is elastic plus plastic, the whole
  law (tension and damage included) written on the elastic part g + w. The bound is the cap
  of Lourenco and Rots' interface (their "cap mode"), the ellipse
      sigma^2 + C_ss tau^2 <= sigma_c(w)^2,
  tau the joint's shear stress (C_ss [-] >= 0, optional), in a simpler form: its plastic
  flow is normal to the ellipse (here the closure alone grows: w, no plastic slip, so
  their hardening variable kappa is w), and tau is the shear stress of the step before
  (explicit, like the damage); the shear stays Mohr-Coulomb's on the capped sigma. With
  kappa_p > 0 [m] the cap hardens first, as theirs does, from sigma_i = f_c / 3 (the joint
  yields there) to f_c at the plastic closure kappa_p, along their parabola, then softens
  as above from there:
      sigma_c(w) = f_c / 3 + (2 f_c / 3) sqrt(2 w / kappa_p - w^2 / kappa_p^2)  (w < kappa_p),
      sigma_c(w) = f_c exp(-f_c (w - kappa_p) / G_fc)                          (w >= kappa_p),
  which dissipates f_c kappa_p (1 / 3 + pi / 6) per unit area up to the peak and G_fc after
  it (their softening, parabolic to sigma_m and then exponential to a residual sigma_r, is
  simplified to this exponential, so that G_fc keeps its meaning: the energy after the
  peak). The slope of the softening at its peak, f_c^2 / G_fc, must not exceed k_n (else
  it snaps back): G_fc >= f_c^2 / k_n.
"""

import math
from dataclasses import dataclass, field
from enum import IntEnum

import numpy as np

from .errors import InputError

__all__ = ["INITIAL_GAP_KINDS", "MAX_LAW_POINTS", "NO_CONTACT", "SMOOTH_KINDS", "ContactLaw",
           "LawKind", "NoContact", "Parameter"]

MAX_LAW_POINTS = 15
"""Most points a 2D face-to-face contact may get (`ContactLaw.points`): seven Simpson panels."""


class LawKind(IntEnum):
    """The normal part of a contact law (friction is Coulomb for all), and the joint laws."""

    SIGNORINI_COULOMB = 0
    RESTITUTION_COULOMB = 1
    GAP_SIGNORINI_COULOMB = 2
    ELASTIC = 3
    VISCOUS_COULOMB = 4
    COHESIVE = 5


class Parameter(IntEnum):
    """Columns of Model.law_parameter (0 where a law does not use one)."""

    K_N = 0
    """Normal stiffness k_n [Pa/m]."""
    K_T = 1
    """Tangential stiffness k_t [Pa/m]."""
    C_N = 2
    """Normal damping c_n [Pa s/m] (ELASTIC)."""
    ETA = 3
    """Tangential viscosity eta [Pa s/m] (VISCOUS_COULOMB)."""
    F_T = 4
    """Tensile strength f_t [Pa] (COHESIVE)."""
    COHESION = 5
    """Cohesion c [Pa] (COHESIVE)."""
    G_I = 6
    """Mode I fracture energy G_I [J/m^2] (COHESIVE)."""
    G_II = 7
    """Mode II fracture energy G_II [J/m^2] (COHESIVE)."""
    F_C = 8
    """Compressive strength f_c [Pa] of the cap (COHESIVE; 0: no cap)."""
    G_FC = 9
    """Compressive fracture energy G_fc [J/m^2] of the cap (COHESIVE, with f_c)."""
    C_SS = 10
    """Shear coefficient C_ss [-] of the cap's ellipse (COHESIVE, with f_c; 0: none)."""
    KAPPA_P = 11
    """Plastic closure kappa_p [m] at which the cap's hardening from f_c / 3 reaches f_c
    (COHESIVE, with f_c; 0: no hardening, elastic up to f_c)."""


INITIAL_GAP_KINDS = (LawKind.SIGNORINI_COULOMB, LawKind.GAP_SIGNORINI_COULOMB)
"""Laws with a _g0 variant (ContactLaw.initial_gap)."""

SMOOTH_KINDS = (LawKind.ELASTIC, LawKind.VISCOUS_COULOMB, LawKind.COHESIVE)
"""Laws that the local problem modifies (saxum.solver.laws_local); the others are dry."""

_USED = {
    LawKind.ELASTIC: {"k_n": True, "k_t": False, "c_n": False},
    LawKind.VISCOUS_COULOMB: {"eta": True},
    LawKind.COHESIVE: {"k_n": True, "k_t": True, "f_t": True, "cohesion": True, "g_i": True,
                       "g_ii": True, "f_c": False, "g_fc": False,
                       "c_ss": False, "kappa_p": False},
}
"""Parameters per joint law: name -> required (True) or optional (False, default 0)."""


@dataclass(frozen=True)
class ContactLaw:
    """A contact law: friction coefficient mu [-], kind, restitution e_n [-] (RESTITUTION only),
    and the joint laws' parameters (see `Parameter` and the module doc; SI units):
    k_n, k_t [Pa/m], c_n, eta [Pa s/m], f_t, cohesion, f_c [Pa], g_i, g_ii, g_fc [J/m^2],
    c_ss [-], kappa_p [m].

    points: contact points of a face-to-face contact, for laws written in stresses
    (saxum.detection.polygons, .polyhedra). 2 (default): the ends of the common segment (3D:
    the corners of the contact polygon), each standing for an equal share: a trapezoid rule,
    which is all a dry law needs (it ignores the areas) but which makes a joint's rotational
    stiffness 3 times too high. 2D: an odd number n >= 3 adds points so that the ends and
    the new points form (n - 1) / 2 Simpson panels (3-point Gauss-Lobatto, weights 1/6, 4/6,
    1/6 of a panel): exact for the force and moment of a linear stress and for the
    rotational stiffness. 3D: 3 adds the midpoints of the polygon's edges and a centre, with
    a rule exact for linear stresses (module doc of saxum.detection.polyhedra).

    alert [m]: the alert distance of the contacts of this law (LMGC90's per see-table):
    pairs of blocks closer than this become contacts; None: the detector's
    (DetectionSettings.alert).

    initial_gap (SIGNORINI_COULOMB and GAP_SIGNORINI_COULOMB only): the _g0 variant, the
    condition written on g - g0, g0 each contact's gap at the first step (module doc).

    bond_at [s] (COHESIVE only): when the joints bond. 0 (default): the joints closed at the
    start; t > 0: those closed at time t (after a settling phase, during which the law's
    contacts are Coulomb contacts of the gap law), saxum.simulation.Simulation.step.
    """

    friction: float
    kind: LawKind = LawKind.GAP_SIGNORINI_COULOMB
    restitution: float = 0.0
    k_n: float = 0.0
    k_t: float = 0.0
    c_n: float = 0.0
    eta: float = 0.0
    f_t: float = 0.0
    cohesion: float = 0.0
    g_i: float = 0.0
    g_ii: float = 0.0
    f_c: float = 0.0
    g_fc: float = 0.0
    c_ss: float = 0.0
    kappa_p: float = 0.0
    name: str = field(default="", compare=False)
    """How messages name the law (e.g. "[[laws]] 2 (mortar, mortar)")."""
    points: int = 2
    alert: float | None = None
    bond_at: float = 0.0
    initial_gap: bool = False

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
        if self.alert is not None and not (math.isfinite(self.alert) and self.alert > 0.0):
            raise InputError(f"{self.name or 'a contact law'}: alert must be a finite length "
                             f"> 0 [m], got {self.alert}; leave it out for the detector's")
        object.__setattr__(self, "kind", LawKind(self.kind))
        if not (math.isfinite(self.bond_at) and self.bond_at >= 0.0):
            raise InputError(f"{self.name or 'a contact law'}: bond_at must be a finite time "
                             f">= 0 [s], got {self.bond_at}")
        if self.bond_at > 0.0 and self.kind != LawKind.COHESIVE:
            raise InputError(f"{self.name or 'a contact law'}: bond_at={self.bond_at} is for "
                             f"COHESIVE laws (joints that bond), not {self.kind.name}; drop it")
        if self.initial_gap and self.kind not in INITIAL_GAP_KINDS:
            raise InputError(f"{self.name or 'a contact law'}: initial_gap (a _g0 law) is for "
                             "signorini_coulomb and gap_signorini_coulomb, not "
                             f"{self.kind.name.lower()}; drop it")
        self._check_parameters()

    @property
    def parameters(self) -> np.ndarray:
        """The row of Model.law_parameter, columns `Parameter`."""
        return np.array([getattr(self, p.name.lower()) for p in Parameter], dtype=np.float64)

    def _check_parameters(self) -> None:
        who = self.name or f"the {self.kind.name} law"
        used = _USED.get(self.kind, {})
        for p in Parameter:
            key = p.name.lower()
            value = getattr(self, key)
            if not math.isfinite(value) or value < 0.0:
                raise InputError(f"{who}: {key} must be a finite number >= 0, got {value}")
            if value != 0.0 and key not in used:
                raise InputError(f"{who}: {key} is not a parameter of kind {self.kind.name}; "
                                 f"its parameters are: {', '.join(used) or 'none'}")
            if used.get(key) and value == 0.0:
                raise InputError(f"{who}: kind {self.kind.name} needs {key} > 0")
        if self.kind == LawKind.COHESIVE:
            # linear softening from the strength at the onset opening to zero at
            # 2 G / strength: a shorter tail than the onset opening would snap back
            for g, strength, stiffness in (("g_i", "f_t", "k_n"), ("g_ii", "cohesion", "k_t")):
                least = getattr(self, strength) ** 2 / (2.0 * getattr(self, stiffness))
                if getattr(self, g) < least:
                    raise InputError(
                        f"{who}: {g} = {getattr(self, g):g} J/m^2 is too small for {strength} = "
                        f"{getattr(self, strength):g} Pa and {stiffness} = "
                        f"{getattr(self, stiffness):g} Pa/m: the softening would snap back; "
                        f"use {g} >= {strength}^2 / (2 {stiffness}) = {least:.6g} J/m^2")
            if (self.f_c > 0.0) != (self.g_fc > 0.0):
                given, other = ("f_c", "g_fc") if self.f_c > 0.0 else ("g_fc", "f_c")
                raise InputError(f"{who}: the compression cap needs both f_c [Pa] and g_fc "
                                 f"[J/m^2]; {given} is given, {other} is not (leave both out "
                                 "for a joint that does not crush)")
            if self.c_ss > 0.0 and not self.f_c > 0.0:  # (f_c >= 0 checked above)
                raise InputError(f"{who}: c_ss = {self.c_ss:g} is the shear term of the "
                                 "compression cap, which needs f_c and g_fc; give them or "
                                 "drop c_ss")
            if self.kappa_p > 0.0 and not self.f_c > 0.0:
                raise InputError(f"{who}: kappa_p = {self.kappa_p:g} m is the plastic closure "
                                 "at which the compression cap's hardening peaks, which needs "
                                 "f_c and g_fc; give them or drop kappa_p")
            # exponential softening, slope f_c^2 / G_fc at the peak: steeper than k_n would
            # snap back
            least = self.f_c ** 2 / self.k_n
            if self.f_c > 0.0 and self.g_fc < least:
                raise InputError(
                    f"{who}: g_fc = {self.g_fc:g} J/m^2 is too small for f_c = {self.f_c:g} Pa "
                    f"and k_n = {self.k_n:g} Pa/m: the cap's softening would snap back; use "
                    f"g_fc >= f_c^2 / k_n = {least:.6g} J/m^2")


def undamped_springs(laws) -> list[ContactLaw]:
    """The joint laws with a spring that nothing damps: COHESIVE (its k_n and k_t), and
    ELASTIC without a normal dashpot (c_n = 0) or with a tangential spring (k_t > 0, which has
    none). Under theta = 1/2, which keeps a spring's energy, a load applied at once leaves
    their joints vibrating for the whole run."""
    return [law for law in laws if isinstance(law, ContactLaw) and (
        law.kind == LawKind.COHESIVE
        or (law.kind == LawKind.ELASTIC and (law.c_n <= 0.0 or law.k_t > 0.0)))]


@dataclass(frozen=True)
class NoContact:
    """The "no contact" law: blocks of the two groups pass through each other (LMGC90 leaves
    such a pair out of its see-tables). The detector drops their pairs before the narrow
    phase, so they never make contacts. Use the instance `NO_CONTACT`."""

    def __repr__(self) -> str:
        return "NO_CONTACT"


NO_CONTACT = NoContact()
"""ModelBuilder.set_law(a, b, NO_CONTACT): groups a and b never touch."""
