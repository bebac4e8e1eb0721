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
the 15- and 21-voussoir arches (four-hinge factors 0.150465 and 0.148315,
test_limit_analysis.py) and the 15-voussoir arch extruded 0.5 m deep in two staggered
pieces (3D, the 2D factor within 1e-4; to 0.5 %, which takes fewer 3D trials: what is
checked is that the bracket holds the static value, not its width).
"""

import pytest
from limit_analysis import with_load_factor
from test_limit_analysis import _block

from saxum.collapse import CollapseCriterion, critical_value, run_trial
from saxum.limit import limit_analysis
from saxum.structures import semicircular_arch
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


@pytest.mark.parametrize("model, bracket, tolerance", [
    (_arch(), (0.1179, 0.1769), 0.002),
    (_block(0.4, 1.0, 0.6), (0.3, 0.5), 0.002),
    (_arch_of(15), (0.12, 0.19), 0.002),
    (_arch_of(21), (0.12, 0.19), 0.002),
    (extruded(_arch_of(15), 0.5, pieces=2, stagger=True), (0.12, 0.19), 0.005)],
    ids=["arch 9", "block", "arch 15", "arch 21", "arch 15 extruded 3D"])
def test_bracket_contains_the_static_factor(model, bracket, tolerance):
    exact = limit_analysis(model).factor
    result = critical_value(lambda x: with_load_factor(model, x), *bracket,
                            tolerance=tolerance, criterion=CollapseCriterion(duration=1.0))
    assert result.stands <= exact <= result.collapses
    assert all(t.certified for t in result.trials)
