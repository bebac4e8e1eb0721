"""theta's default (saxum.simulation.Simulation): 1/2, or 1 for a model whose joint springs
nothing damps (saxum.laws.undamped_springs), said in the run's log; theta = 1/2 given with
such laws warns, naming them (UndampedJointWarning); the scenario's solver.theta follows."""

import logging
import math
import warnings

import pytest

import saxum as sx
from saxum.scenario import parse_scenario

MORTAR = dict(kind=sx.LawKind.COHESIVE, k_n=1e10, k_t=4e9, f_t=5e3, cohesion=1e4, g_i=2.0,
              g_ii=10.0)


def _pair(law: sx.ContactLaw) -> sx.Model:
    b = sx.ModelBuilder(gravity=(0.0, -9.81))
    b.add_block([(-1.0, -0.2), (1.0, -0.2), (1.0, 0.0), (-1.0, 0.0)],
                kind=sx.BodyKind.FIXED, group="ground")
    b.add_block([(0.0, 0.0), (0.5, 0.0), (0.5, 0.5), (0.0, 0.5)], density=2000.0)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    return b.finalize()


@pytest.mark.parametrize(("law", "theta"), [
    (sx.ContactLaw(friction=0.6), 0.5),
    (sx.ContactLaw(friction=0.6, kind=sx.LawKind.VISCOUS_COULOMB, eta=1e3), 0.5),
    (sx.ContactLaw(friction=0.6, kind=sx.LawKind.ELASTIC, k_n=1e8, c_n=1e5), 0.5),
    (sx.ContactLaw(friction=0.6, kind=sx.LawKind.ELASTIC, k_n=1e8), 1.0),
    (sx.ContactLaw(friction=0.6, kind=sx.LawKind.ELASTIC, k_n=1e8, c_n=1e5, k_t=1e8), 1.0),
    (sx.ContactLaw(friction=0.6, **MORTAR), 1.0),
])
def test_default_theta_is_one_for_undamped_joint_springs(law, theta, caplog):
    with caplog.at_level(logging.INFO, logger="saxum"), warnings.catch_warnings():
        warnings.simplefilter("error", sx.UndampedJointWarning)
        sim = sx.Simulation(_pair(law), dt=1e-4)
    # one of two stored constants, not a computed value: 1e-12 only guards the rule
    assert math.isclose(sim.integrator.theta, theta, abs_tol=1e-12)
    said = [r.getMessage() for r in caplog.records if "theta = 1 (not given)" in r.getMessage()]
    assert len(said) == int(theta > 0.75)  # the note only where the rule chose theta = 1
    if said:
        assert law.kind.name in said[0]


def test_theta_one_half_given_with_undamped_joint_springs_warns_with_the_law_and_the_cure():
    law = sx.ContactLaw(friction=0.6, name="[[laws]] 0 (brick, ground)", **MORTAR)
    with pytest.warns(sx.UndampedJointWarning) as caught:
        sim = sx.Simulation(_pair(law), dt=1e-4, theta=0.5)
    message = str(caught[0].message)
    assert "[[laws]] 0 (brick, ground)" in message
    assert "theta = 1" in message and "keeps a spring's energy" in message
    assert math.isclose(sim.integrator.theta, 0.5, abs_tol=1e-12)  # as given
    with warnings.catch_warnings():
        warnings.simplefilter("error", sx.UndampedJointWarning)
        sx.Simulation(_pair(law), dt=1e-4, theta=0.6)  # damps, if slowly: no warning
        sx.Simulation(_pair(sx.ContactLaw(friction=0.6)), dt=1e-4, theta=0.5)  # dry


SCENARIO = """
[structure]
type = "wall"
courses = 2
bricks = 2

[[laws]]
groups = ["*", "*"]
kind = "cohesive"
friction = 0.6
k_n = 1e10
k_t = 4e9
f_t = 5e3
cohesion = 1e4
g_i = 2.0
g_ii = 10.0

[output]
duration = 0.01
"""


def test_scenario_theta_left_out_follows_the_rule_and_given_is_kept():
    with warnings.catch_warnings():
        warnings.simplefilter("error", sx.UndampedJointWarning)
        default = parse_scenario(SCENARIO).build_simulation()
    assert math.isclose(default.integrator.theta, 1.0, abs_tol=1e-12)  # the rule's constant
    given = parse_scenario(SCENARIO.replace("[output]", "[solver]\ntheta = 0.7\n[output]"))
    assert math.isclose(given.build_simulation().integrator.theta, 0.7, abs_tol=1e-12)
