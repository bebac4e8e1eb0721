"""The semicircular arch under its weight lumped on the centreline (the "CCR" hypothesis of
G. Cocchetti & E. Rizzi, "Analytical and numerical analysis on the collapse mode of
circular masonry arches", Frattura ed Integrita Strutturale 51, 2020, Table 3): for the
complete semicircular arch the least thickness is t/R = 0.107426, and the thrust line of
that arch, the only one, needs a friction coefficient mu > 0.395832 for its purely
rotational (hinge) mode; for no thickness does an equilibrium exist below mu = 0.309215.

Here each of 240 voussoirs (mean radius R = 1 m, radial joints) carries its weight
rho g t R dphi (the centreline's length times t, as CCR) at the centreline point of its
mid-angle: gravity off, the weight a point load with its moment about the centre of mass.
These are statements about equilibrium alone (a thrust line within the ring whose force
at every joint lies in the Coulomb cone), which is the static programme's feasibility
(saxum.limit.stands): exact for any flow rule, associative or not (the non-associative
scheme of saxum.limit changes only the collapse factor and mechanism of a loaded
structure, not whether an admissible state exists). Bisections: t/R and mu to 1e-6.
Tolerance 1e-4 relative: the weights lumped at 240 points and the joints at 240 angles
differ from the continuous ring by O(n^-2) (measured 4e-5 on t, 1.3e-5 on the 0.3958; 60
voussoirs: 7e-4 on the 0.3092).
"""

import math

import pytest

import saxum as sx
from saxum.limit import stands
from saxum.structures.arch import add_supported_semicircular_arch

VOUSSOIRS = 240
RHO_G = 2000.0 * 9.81


def _ccr_arch(thickness: float, mu: float) -> sx.Model:
    builder = sx.ModelBuilder(gravity=(0.0, 0.0))
    ids = add_supported_semicircular_arch(builder, radius=1.0, thickness=thickness,
                                          voussoirs=VOUSSOIRS)
    builder.set_law("voussoir", "voussoir", sx.ContactLaw(friction=mu))
    builder.set_law("voussoir", "support", sx.ContactLaw(friction=mu))
    centre = builder.finalize().body_q0[ids, :2]
    weight = RHO_G * thickness * math.pi / VOUSSOIRS
    for k, body in enumerate(ids):  # voussoir k + 1 from the left springing
        phi = math.pi * (1.0 - (k + 0.5) / VOUSSOIRS)
        moment = -(math.cos(phi) - centre[k, 0]) * weight  # (p - c) x (0, -w)
        builder.add_force([body], lambda t, m=moment: (0.0, -weight, m))
    return builder.finalize()


def _least(standing, lo: float, hi: float, tolerance: float) -> float:
    """The least x in [lo, hi] at which standing(x) (true at hi), to `tolerance`."""
    while hi - lo > tolerance:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if standing(mid) else (mid, hi)
    return hi


def test_the_least_thickness_and_its_friction_threshold():
    t = _least(lambda x: stands(_ccr_arch(x, 1.0)), 0.10, 0.11, 1e-6)
    assert t == pytest.approx(0.107426, rel=1e-4)
    mu = _least(lambda x: stands(_ccr_arch(t, x)), 0.3, 0.5, 1e-6)
    assert mu == pytest.approx(0.395832, rel=1e-4)


def test_no_thickness_stands_below_the_sliding_threshold():
    # a thick ring: the friction it needs no longer depends on t (60 voussoirs measured the
    # same figure at t/R = 0.3 ... 1.9), the least over all thicknesses
    mu = _least(lambda x: stands(_ccr_arch(0.5, x)), 0.2, 0.4, 1e-6)
    assert mu == pytest.approx(0.309215, rel=1e-4)
