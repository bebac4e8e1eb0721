"""Newmark's sliding block in 3D: base motion along an arbitrary horizontal direction.

N. M. Newmark, "Effects of earthquakes on dams and embankments", Geotechnique 15, 1965: a rigid
block on a horizontal base with friction mu, the base accelerated by a rectangular pulse of
amplitude A g (A > mu) and duration T, slips relative to the base by
    u = V^2 / (2 g mu) (1 - mu / A),   V = A g T,
opposite to the pulse; with isotropic friction the slip is along the pulse's direction
whatever that is. The pulse has three components (x, y, z) (saxum.ground with a 3D model),
here horizontal at azimuth 0.9 rad (and, for the second case, made from a one-component
record by GroundMotion.in_3d). Tolerances: slip within 1 % of Newmark (the issue's), at most
1e-6 of it across the pulse's direction; driving the base with the ground velocity gives the
same slip as the inertial forces (0.1 %)."""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.ground import rectangular
from saxum.structures.solid import box

G = 9.81
MU = 0.2
AZIMUTH = 0.9


def _slip(a_factor, duration, driven, from_2d=False):
    b = sx.ModelBuilder(dim=3)
    b.add_block(box(-5, -5, -0.2, 5, 5, 0), kind=sx.BodyKind.FIXED, group="base", name="base")
    block = b.add_block(box(-0.2, -0.2, 0.0, 0.2, 0.2, 0.1), density=2000.0)
    b.set_law("block", "base", sx.ContactLaw(friction=MU))
    b.set_law("block", "block", sx.ContactLaw(friction=MU))
    d = np.array([math.cos(AZIMUTH), math.sin(AZIMUTH), 0.0])
    if from_2d:
        pulse = rectangular(a_factor * G, duration).in_3d(AZIMUTH)
    else:
        pulse = rectangular(a_factor * G, duration, direction=tuple(d))
    assert pulse.components == 3
    if driven:
        pulse.apply_as_driven_supports(b, ["base"])
    else:
        pulse.apply_as_inertial_forces(b)
    model = b.finalize()
    sim = sx.Simulation(model, dt=5e-4)
    state = sim.initial_state()
    v = a_factor * G * duration
    sim.run(state, duration + v / (MU * G) * 1.2 + 0.1)
    base = model.body("base")
    relative = (state.body_q[block, :3] - model.body_q0[block, :3]) - (
        state.body_q[base, :3] - model.body_q0[base, :3])
    assert np.linalg.norm(state.body_v[block, :3] - state.body_v[base, :3]) < 1e-6
    along = -float(relative @ d)
    across = np.linalg.norm(relative + along * d)
    return along, across


@pytest.mark.parametrize(("a_factor", "duration", "from_2d"), [(0.5, 0.2, False),
                                                               (1.0, 0.1, True)])
def test_newmark_slip_in_any_horizontal_direction(a_factor, duration, from_2d):
    v = a_factor * G * duration
    expected = v**2 / (2.0 * G * MU) * (1.0 - MU / a_factor)
    along, across = _slip(a_factor, duration, driven=False, from_2d=from_2d)
    assert along == pytest.approx(expected, rel=0.01)
    assert across < 1e-6 * expected


def test_driven_base_gives_the_same_slip_in_3d():
    inertial, _ = _slip(0.5, 0.2, driven=False)
    driven, _ = _slip(0.5, 0.2, driven=True)
    assert driven == pytest.approx(inertial, rel=1e-3)
