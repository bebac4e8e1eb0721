"""A block on an elastic joint under an eccentric load: the joint's rotational stiffness.

Structure: a block b = 0.5 m wide, h = 0.5 m high (2000 kg/m^3) on a fixed base, the joint an
ELASTIC law (saxum.laws: k_n = 1e8 Pa/m, damping c_n = 3e5 Pa s/m, about half the critical
of the block's bounce, so that it comes to rest), under its weight N and a torque M = N e
(e < b / 6: the whole joint stays compressed); per metre of depth, run for 1 s to rest.

Closed form: a rigid block on a bed of independent springs k_n per unit area (Winkler) turns
by theta = M_tot / (k_n I), I = b^3 / 12 the joint's second moment, and settles by
N / (k_n b) (e.g. J.E. Bowles, "Foundation analysis and design", 5th ed., McGraw-Hill 1996,
sec. 9: rigid footing on an elastic subgrade); M_tot = M + N (h / 2) theta, the weight's lever
arm growing as the block turns (its centre of mass h / 2 above the joint), so
theta = M / (k_n I - N h / 2). The contact points' areas A_i are the rule that integrates the
springs: sum A_i x_i^2 is b^3 / 12 for Simpson's 3 points (ContactLaw.points = 3) and for 5
(two panels), but b^3 / 4 for the two ends alone: the trapezoid's joint is 3 times too stiff,
checked too with its own closed form (I = b^3 / 4).

Tolerance 0.1 %: at rest the theta-method's equilibrium is the static one, so what is left
is the round-off of the solver's tolerance and the geometry of the settled block (rotation
and settlement of order 1e-4 change the lever arms by that fraction): measured (2026-11-25)
at most 2e-4 of theta and 1.5e-4 of the settlement; against the Winkler rotation without
the lever arm's growth, 1.4e-3 (3 points).
"""

import pytest

import saxum as sx
from saxum.laws import LawKind

B, H, DENSITY, K_N = 0.5, 0.5, 2000.0, 1.0e8
WEIGHT = DENSITY * B * H * 9.81


def _settled(points: int, e: float) -> tuple[float, float]:
    """(rotation [rad], settlement [m]) of the block at rest under the torque N e."""
    builder = sx.ModelBuilder()
    builder.add_block([(-1, -0.5), (1, -0.5), (1, 0), (-1, 0)], kind=sx.BodyKind.FIXED,
                      group="base")
    block = builder.add_block([(0, 0), (B, 0), (B, H), (0, H)], density=DENSITY)
    builder.set_law("block", "base", sx.ContactLaw(friction=0.6, kind=LawKind.ELASTIC, k_n=K_N,
                                                   c_n=3e5, points=points))
    builder.set_law("block", "block", sx.ContactLaw(friction=0.6))
    builder.add_force([block], lambda t: (0.0, 0.0, WEIGHT * e))  # counterclockwise
    model = builder.finalize()
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 1.0)
    turn = state.body_q[block, 2] - model.body_q0[block, 2]
    return float(turn), float(model.body_q0[block, 1] - state.body_q[block, 1])


@pytest.mark.parametrize(("points", "second_moment", "e"), [
    (3, B**3 / 12, B / 12), (3, B**3 / 12, B / 7), (5, B**3 / 12, B / 7),
    (2, B**3 / 4, B / 12)])
def test_rotation_and_settlement_of_a_block_on_an_elastic_joint(points, second_moment, e):
    turn, settlement = _settled(points, e)
    assert turn == pytest.approx(WEIGHT * e / (K_N * second_moment - WEIGHT * H / 2),
                                 rel=1e-3)
    assert settlement == pytest.approx(WEIGHT / (K_N * B), rel=1e-3)
