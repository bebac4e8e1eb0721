"""The gap-based law: inelastic impacts that do not rebound, and interpenetration removed by a
position projection that leaves the velocities alone.

Closed forms (NSCD.md; J.J. Moreau 1988; V. Acary, CMAME 256, 2013, projected Moreau-Jean):
- a rigid block dropped flat on a rigid ground under the inelastic law (Newton e_n = 0) stops:
  after the impact its vertical velocity is 0 (we allow 1e-6 of the impact velocity, solver
  tolerance) and it never leaves the ground again;
- a block placed interpenetrating the ground by p = 1 mm and released at rest is projected back
  within one step to an interpenetration below the tolerance the projection works to
  (DetectionSettings.interpenetration), and its velocity after that step is the free-fall
  velocity stopped by the ground, i.e. 0 (|v| < 1e-9 m/s): the correction is made on positions,
  not by a separation velocity.
"""

import numpy as np
import pytest

import saxum as sx

G = 9.81
DT = 1e-3


def _block_on_ground(y0, kind):
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-2.0, -0.2), (2.0, -0.2), (2.0, 0.0), (-2.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground")
    b.add_block([(-0.1, y0), (0.1, y0), (0.1, y0 + 0.2), (-0.1, y0 + 0.2)], density=2000.0,
                group="block")
    b.set_law("ground", "block", sx.ContactLaw(friction=0.5, kind=kind))
    b.set_law("block", "block", sx.ContactLaw(friction=0.5, kind=kind))
    return b.finalize()


@pytest.mark.parametrize("kind", [sx.LawKind.GAP_SIGNORINI_COULOMB, sx.LawKind.SIGNORINI_COULOMB])
def test_dropped_block_stops_without_rebound(kind):
    drop = 0.0125  # [m]: impact velocity sqrt(2 g drop) = 0.495 m/s
    model = _block_on_ground(drop, kind)
    sim = sx.Simulation(model, dt=DT, detection=sx.DetectionSettings(alert=0.02))
    state = sim.initial_state()
    vy = []
    for _ in range(300):
        sim.step(state)
        vy.append(state.body_v[1, 1])
    vy = np.array(vy)
    impact = np.sqrt(2.0 * G * drop)
    assert vy.min() == pytest.approx(-impact, rel=0.02)  # it did fall and hit the ground
    after = vy[np.argmin(vy) + 1:]
    assert np.abs(after).max() < 1e-6 * impact


def test_interpenetration_is_projected_out_without_a_separation_velocity():
    p = 1e-3
    model = _block_on_ground(-p, sx.LawKind.GAP_SIGNORINI_COULOMB)
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state(check_overlaps=False)
    report = sim.step(state)
    assert report.projection_iterations > 0
    assert report.max_interpenetration <= sim.detector.interpenetration
    assert state.body_q[1, 1] - 0.1 == pytest.approx(0.0, abs=sim.detector.interpenetration)
    assert np.abs(state.body_v[1]).max() < 1e-9
    for _ in range(100):
        report = sim.step(state)
        assert report.max_interpenetration <= sim.detector.interpenetration
    assert np.abs(state.body_v[1]).max() < 1e-9


def test_signorini_law_leaves_an_interpenetration_in_place():
    """The velocity-level law has no position correction: U_n >= 0 only (NSCD.md)."""
    p = 1e-3
    model = _block_on_ground(-p, sx.LawKind.SIGNORINI_COULOMB)
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state(check_overlaps=False)
    sim.run(state, 0.05)
    assert state.body_q[1, 1] - 0.1 == pytest.approx(-p, rel=1e-6)
    assert sim.log.projection_iterations.max() == 0
