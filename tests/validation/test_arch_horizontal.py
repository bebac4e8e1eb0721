"""Horizontal collapse load factor of a semicircular arch against a rigid-block limit analysis.

Reference: the least admissible four-hinge mechanism by virtual work, computed independently
of saxum in limit_analysis.py (kinematic theorem for rigid blocks with no tension and no
sliding; J. Heyman, Int. J. Mech. Sci. 11, 1969; A. Gago, J. Alvarez & M. Ochsendorf, 2011).
Voussoirs here are computed from the arch's definition: quadrilaterals with straight intrados
and extrados between the ends of radial joints, mean radius R = 1 m, t/R = 0.15, 15 voussoirs
numbered from the left springing, density 2000 kg/m^3.

Test: saxum's bisection (loading from rest to a fixed lambda, mu = 1 so that no joint slides)
finds the collapse load factor within 3 % (the issue's tolerance) and its hinges at the same
joints (intrados or extrados alike) as the least mechanism, one joint of slack allowed.
"""

import math

import pytest
from limit_analysis import saxum_horizontal_collapse
from limit_analysis import semicircular_four_hinge as limit_analysis

from saxum.structures import semicircular_arch

RADIUS, RATIO, VOUSSOIRS = 1.0, 0.15, 15


def test_limit_analysis_orders_arches_by_thickness():
    """A check of the reference itself: a thicker arch needs a larger load factor."""
    lam_thin, _ = limit_analysis(1.0, 0.12, 15)
    lam_thick, _ = limit_analysis(1.0, 0.2, 15)
    assert 0.0 < lam_thin < lam_thick


def test_horizontal_collapse_load_factor_of_the_semicircular_arch():
    lam_ref, hinges_ref = limit_analysis(RADIUS, RATIO * RADIUS, VOUSSOIRS)
    model = semicircular_arch(radius=RADIUS, thickness=RATIO * RADIUS, voussoirs=VOUSSOIRS,
                              friction=1.0)
    lam, mech, found = saxum_horizontal_collapse(
        model, lam_ref, VOUSSOIRS,
        lambda p: "intrados" if math.hypot(*p) < RADIUS else "extrados")
    assert lam == pytest.approx(lam_ref, rel=0.03)
    assert not mech.sliding
    assert len(found) == 4, found
    for (joint, side), (joint_ref, side_ref) in zip(found, hinges_ref, strict=True):
        assert abs(joint - joint_ref) <= 1 and side == side_ref, (found, hinges_ref)
