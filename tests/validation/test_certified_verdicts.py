"""Certified verdicts of saxum.collapse against the limit analysis of the same model.

The 9-voussoir semicircular arch of issue 17 (mean radius 1 m, t = 0.15 m, mu = 0.8): its
horizontal collapse factor is 0.147381 (saxum.limit, equal to its four-hinge mechanism by
virtual work to 1e-12, test_limit_analysis.py; J. Heyman, Int. J. Mech. Sci. 11, 1969).
Loaded from rest just past it (lambda = 0.14761, 0.16 % above), the mechanism starts so
slowly that the force-ratio test alone called the trial at rest after its first 0.05 s
(displacement 3e-6 m); a verdict at rest now needs an equilibrium certificate (a rest
solution of the last step, found by the static programme), so the trial runs on and the
arch collapses (a block moves by 1 % of the smallest block's size). Just below (0.1473,
0.06 % below) it stands, certified. The bisection's bracket then contains the static factor
(the issue's case: bracket 0.1179 .. 0.1769, tolerance 0.2 %).

A block on a plane (b/h = 0.4, mu = 0.6): the bracket contains b/h (statics). The same for
the 15-, 21- and 31-voussoir arches (four-hinge factors 0.150465 and 0.148315 and the
31-voussoir one, test_limit_analysis.py), the 15-voussoir arch extruded 0.5 m deep in two
staggered pieces (3D, the 2D factor within 1e-4; to 0.5 %, which takes fewer 3D trials: what
is checked is that the bracket holds the static value, not its width) and the slender 3D
running-bond wall loaded out of its plane (12 courses of 0.065 m, b = 0.12 m, mu = 0.6:
b/h = 0.1538, test_wall_overturn3d.py; to 0.5 % likewise).

Minimum thickness: the 60-voussoir semicircular arch (R = 1 m, mu = 1, under its weight)
stands by the static programme down to t = 0.107448 m (test_limit_analysis.py; the
continuous arch's 0.107478, Milankovitch 1907, is approached from below as the voussoirs
multiply). The bisection over thickness from 3 % above to 2 % below (asymmetric so that no
trial falls on the limit itself), to 0.2 % (the issue's tolerance, the coarsest at which both
ends of the bracket are dynamic verdicts close to the limit, where the mechanism starts
slowest: it ends 0.03 % above, certified standing, and 0.13 % below, collapsing; 7 trials),
holds the programme's minimum thickness.
"""

import pytest
from limit_analysis import with_load_factor
from test_limit_analysis import _block, _stands

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value, run_trial
from saxum.limit import limit_analysis
from saxum.structures import semicircular_arch, wall3d
from saxum.structures.solid import extruded


def _arch():
    return semicircular_arch(radius=1.0, thickness=0.15, voussoirs=9, friction=0.8)


def test_a_slow_mechanism_is_not_called_at_rest():
    model = _arch()
    exact = limit_analysis(model).factor
    assert exact == pytest.approx(0.147381, abs=1e-6)
    past = run_trial(with_load_factor(model, 0.14761), 0.14761)
    assert past.collapsed and past.certified
    below = run_trial(with_load_factor(model, 0.1473), 0.1473)
    assert not below.collapsed and below.certified


def _arch_of(voussoirs: int):
    return semicircular_arch(radius=1.0, thickness=0.15, voussoirs=voussoirs, friction=0.8)


def _wall():
    return wall3d(courses=12, length=0.5, thickness=0.12, brick_height=0.065, friction=0.6)


Y = (0.0, 1.0, 0.0)


@pytest.mark.parametrize("model, bracket, tolerance, direction", [
    (_arch(), (0.1179, 0.1769), 0.002, None),
    (_block(0.4, 1.0, 0.6), (0.3, 0.5), 0.002, None),
    (_arch_of(15), (0.12, 0.19), 0.002, None),
    (_arch_of(21), (0.12, 0.19), 0.002, None),
    (_arch_of(31), (0.12, 0.19), 0.002, None),
    (extruded(_arch_of(15), 0.5, pieces=2, stagger=True), (0.12, 0.19), 0.005, None),
    (_wall(), (0.12, 0.19), 0.005, Y)],
    ids=["arch 9", "block", "arch 15", "arch 21", "arch 31", "arch 15 extruded 3D",
         "wall 3D out of plane"])
def test_bracket_contains_the_static_factor(model, bracket, tolerance, direction):
    exact = (limit_analysis(model) if direction is None
             else limit_analysis(model, direction=direction)).factor
    result = critical_value(lambda x: with_load_factor(model, x, direction=direction),
                            *bracket, tolerance=tolerance,
                            criterion=CollapseCriterion(duration=1.0))
    assert result.stands <= exact <= result.collapses
    assert all(t.certified for t in result.trials)


def _bisect_static_thickness(voussoirs: int, lo: float, hi: float) -> float:
    """Least thickness [m] at which the static programme finds the arch standing, to 1e-5
    relative (far inside the dynamic bracket's 0.2 %)."""
    while hi - lo > 1e-5 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if _stands(mid, voussoirs, 1.0) else (mid, hi)
    return hi


def test_bracket_over_thickness_contains_the_static_minimum_thickness():
    least = _bisect_static_thickness(60, 0.10, 0.115)
    assert least == pytest.approx(0.107448, rel=1e-4)  # test_limit_analysis.py's value
    result = critical_value(
        lambda t: sx.Simulation(semicircular_arch(radius=1.0, thickness=t, voussoirs=60,
                                                  friction=1.0), dt=1e-3),
        1.03 * least, 0.98 * least, tolerance=0.002, criterion=CollapseCriterion(duration=1.0))
    assert result.collapses <= least <= result.stands
    assert all(t.certified for t in result.trials)
