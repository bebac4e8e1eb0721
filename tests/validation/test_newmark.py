"""Newmark's sliding block (N. M. Newmark, "Effects of earthquakes on dams and embankments",
Geotechnique 15, 1965): a rigid block on a horizontal base with friction mu, the base
accelerated by a rectangular pulse of amplitude A g (A > mu) and duration T, slips relative
to the base by
    u = V^2 / (2 g mu) (1 - mu / A),   V = A g T.
Tolerance 1 % (the issue's). The block is wide and low so that it cannot rock; the pulse is
applied as inertial forces in the frame of the base (saxum.ground) and, as a check of the
equivalence, by driving the base with the integrated ground velocity."""

import numpy as np
import pytest

import saxum as sx
from saxum.ground import rectangular

G = 9.81
MU = 0.2


def _slip(a_factor, duration, driven):
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-5.0, -0.2), (5.0, -0.2), (5.0, 0.0), (-5.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="base", name="base")
    block = b.add_block([(-0.2, 0.0), (0.2, 0.0), (0.2, 0.1), (-0.2, 0.1)], density=2000.0)
    b.set_law("block", "base", sx.ContactLaw(friction=MU))
    b.set_law("block", "block", sx.ContactLaw(friction=MU))
    pulse = rectangular(a_factor * G, duration)
    if driven:
        pulse.apply_as_driven_supports(b, ["base"])
    else:
        pulse.apply_as_inertial_forces(b)
    model = b.finalize()
    sim = sx.Simulation(model, dt=5e-4)
    state = sim.initial_state()
    v = a_factor * G * duration
    stop = duration + v / (MU * G) * 1.2 + 0.1  # the block has stopped by then
    sim.run(state, stop)
    base = model.body("base")
    relative = (state.body_q[block, 0] - model.body_q0[block, 0]) - (
        state.body_q[base, 0] - model.body_q0[base, 0])
    assert abs(state.body_v[block, 0] - state.body_v[base, 0]) < 1e-6  # slip has ended
    return -relative  # the block lags behind the base: slip opposite to the pulse


@pytest.mark.parametrize("a_factor, duration", [(0.5, 0.2), (1.0, 0.1)])
def test_newmark_slip(a_factor, duration):
    v = a_factor * G * duration
    expected = v ** 2 / (2.0 * G * MU) * (1.0 - MU / a_factor)
    assert _slip(a_factor, duration, driven=False) == pytest.approx(expected, rel=0.01)


def test_driven_base_gives_the_same_slip_as_inertial_forces():
    inertial = _slip(0.5, 0.2, driven=False)
    driven = _slip(0.5, 0.2, driven=True)
    assert driven == pytest.approx(inertial, rel=1e-3)
    assert np.isfinite(driven)
