"""Blocks that meet corner to corner (2D) or edge to edge (3D) where joints line up.

A block resting on one block and touching the next one only at a corner (a head joint over a
head joint: stack bond, a parapet stone over a joint of the course below) must slide over it
as if the corner were not there: under a horizontal load factor lambda on a bed joint of
friction mu, Coulomb's law (closed form) gives rest for lambda < mu and the sliding
acceleration a = g (lambda - mu) for lambda > mu. The same for a block that meets a fixed
one edge to edge in plan (diagonal neighbours, as at the inside corner of an L wall), in each
horizontal direction. No contact normal is right at a corner (both faces separate by zero):
along the head joint it held the block in place whatever lambda (found on a 3D bridge's
parapet). Tolerances as the incline test of issue 2: 1 % on the acceleration, rest checked
at 0.98 mu (displacement below 1e-6 m).
"""

import pytest

import saxum as sx

G = 9.81
MU = 0.6
DURATION = 0.3


def _rect(x0, x1, y0, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def _box(x0, x1, z0, z1):
    return [(x, y, z) for x in (x0, x1) for y in (0.0, 0.4) for z in (z0, z1)]


def _slide(dim: int, lam: float) -> float:
    """Displacement [m] along the load of a 1.5 x 1 m block on the middle of three fixed
    blocks 1.5 m long, its bottom corners (edges) on theirs, after DURATION under lambda."""
    b = sx.ModelBuilder(dim=dim, gravity=(lam * G, -G) if dim == 2 else (lam * G, 0.0, -G))
    shape = _rect if dim == 2 else _box
    for x0 in (-1.5, 0.0, 1.5):
        b.add_block(shape(x0, x0 + 1.5, -0.5, 0.0), kind=sx.BodyKind.FIXED, group="course")
    b.add_block(shape(0.0, 1.5, 0.0, 1.0), density=2400.0)
    for other in ("course", "block"):
        b.set_law("block", other, sx.ContactLaw(friction=MU))
    sim = sx.Simulation(b.finalize(), dt=1e-3)
    state = sim.initial_state()
    x0 = float(state.body_q[3, 0])
    sim.run(state, DURATION)
    return float(state.body_q[3, 0]) - x0


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_block_slides_over_a_corner_at_coulomb(dim, sign):
    lam = sign * 1.05 * MU
    expected = 0.5 * G * (abs(lam) - MU) * DURATION**2
    assert sign * _slide(dim, lam) == pytest.approx(expected, rel=0.01)
    assert abs(_slide(dim, sign * 0.98 * MU)) < 1e-6


def _slide_in_plan(lam: float, direction: tuple[float, float]) -> float:
    """Displacement [m] along `direction` of a 1 m cube on a fixed ground under lambda along
    it, beside a fixed cube that touches it along one vertical edge only (diagonal in plan)."""
    dx, dy = direction
    b = sx.ModelBuilder(dim=3, gravity=(lam * G * dx, lam * G * dy, -G))
    b.add_block([(x, y, z) for x in (-3, 3) for y in (-3, 3) for z in (-0.5, 0.0)],
                kind=sx.BodyKind.FIXED, group="course")
    b.add_block([(x, y, z) for x in (1, 2) for y in (-1, 0) for z in (0, 1)],
                kind=sx.BodyKind.FIXED, group="course")
    b.add_block([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], density=2000.0)
    for other in ("course", "block"):
        b.set_law("block", other, sx.ContactLaw(friction=MU))
    sim = sx.Simulation(b.finalize(), dt=1e-3)
    state = sim.initial_state()
    start = state.body_q[2, :2].copy()
    sim.run(state, DURATION)
    return float((state.body_q[2, :2] - start) @ direction)


@pytest.mark.parametrize("direction", [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)])
def test_block_slides_past_a_corner_in_plan_at_coulomb(direction):
    expected = 0.5 * G * (1.05 * MU - MU) * DURATION**2
    assert _slide_in_plan(1.05 * MU, direction) == pytest.approx(expected, rel=0.01)
    assert abs(_slide_in_plan(0.98 * MU, direction)) < 1e-6
