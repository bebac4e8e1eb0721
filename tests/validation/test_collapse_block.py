"""A rigid block on the ground under a horizontal load factor lambda (a tilting-table test):
it overturns at lambda = b/h when sliding is prevented and slides at lambda = mu when
mu < b/h (statics of a rigid block: moment of m lambda g about the toe against that of m g,
and Coulomb's law at the base). Tolerance 1 % (the issue's), found by saxum.collapse's
bisection to 0.2 %, each trial loading the block from rest to a fixed lambda.
The mechanism report names the toe hinge for overturning and the sliding base otherwise."""

import pytest

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value
from saxum.mechanism import mechanism

B, H = 0.5, 1.0  # block width and height [m]: b/h = 0.5
G = 9.81


def _block(mu):
    def make(factor):
        b = sx.ModelBuilder(gravity=(0.0, -G))
        b.add_block([(-2.0, -0.2), (2.0, -0.2), (2.0, 0.0), (-2.0, 0.0)],
                    kind=sx.BodyKind.FIXED, group="ground", name="ground")
        b.add_block([(0.0, 0.0), (B, 0.0), (B, H), (0.0, H)], density=2000.0, name="block")
        b.set_law("block", "ground", sx.ContactLaw(friction=mu))
        b.set_law("block", "block", sx.ContactLaw(friction=mu))
        b.add_acceleration(lambda t: (factor * G, 0.0))
        return sx.Simulation(b.finalize(), dt=1e-3)
    return make


@pytest.mark.parametrize("mu, expected, mode", [(1.0, B / H, "overturns"), (0.3, 0.3, "slides")])
def test_block_collapse_load_factor(mu, expected, mode):
    result = critical_value(_block(mu), 0.1, 0.9, tolerance=0.002,
                            criterion=CollapseCriterion(duration=1.0))
    assert result.value == pytest.approx(expected, rel=0.01)
    assert result.stands < result.collapses
    trial = result.collapse()
    mech = mechanism(trial.simulation.model, trial.state, trial.simulation.integrator.dt)
    assert mech.moving == ["block"]
    if mode == "overturns":
        assert [j.hinge_point[0] for j in mech.hinges] == [pytest.approx(B)]  # the toe
        assert not mech.sliding
    else:
        assert [j.bodies for j in mech.sliding] == [("ground", "block")]
        assert not mech.hinges


def test_point_load_that_overturns_the_block():
    """A horizontal force F at the centre of mass overturns the block (mu = 1) at
    F = m g b/h: the same moment balance about the toe, within 1 %."""
    mass = 2000.0 * B * H  # [kg/m]

    def make(force):
        b = sx.ModelBuilder(gravity=(0.0, -G))
        b.add_block([(-2.0, -0.2), (2.0, -0.2), (2.0, 0.0), (-2.0, 0.0)],
                    kind=sx.BodyKind.FIXED, group="ground", name="ground")
        block = b.add_block([(0.0, 0.0), (B, 0.0), (B, H), (0.0, H)], density=2000.0)
        b.set_law("block", "ground", sx.ContactLaw(friction=1.0))
        b.set_law("block", "block", sx.ContactLaw(friction=1.0))
        b.add_force([block], lambda t: (force, 0.0, 0.0))
        return sx.Simulation(b.finalize(), dt=1e-3)

    expected = mass * G * B / H
    result = critical_value(make, 0.2 * expected, 2.0 * expected, tolerance=0.002)
    assert result.value == pytest.approx(expected, rel=0.01)
