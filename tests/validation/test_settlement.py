"""Settlement of a support: the critical settlement of a column straddling the edge of a
settling support, and the mechanism of a dry-stone wall with a door when the ground under
the pier beyond the door settles.

1. Column (closed form, statics of a rigid block). A column B x H (0.2 x 1 m) stands across
   the edge x = 0 between a fixed support (left) and one that settles by delta (right), its
   centre e = 0.02 m right of the edge. It turns about the edge of the fixed support, resting
   on its bottom-right corner, at distance c = B/2 + e from the edge, so its tilt is
   theta = asin(delta / c); it overturns about that corner when its centre of mass passes
   above it, tan theta = B / H. Critical settlement:
       delta_c = (B/2 + e) B / sqrt(B^2 + H^2) = 0.023534 m.
   saxum: the settlement as in a scenario (profile "smooth", 4 s, mu = 10 so that nothing
   slides), the settlement collapse criterion of saxum.collapse (a block as fast as after a
   free fall by the displacement threshold during the settlement, or moving on after it),
   bisection to 0.5 %. Tolerance 2 %: with slower settlements the value creeps up by about 1 %
   (the column slips at the edge, whose normal force vanishes at the critical tilt), with
   faster ones it drops (2.5 % low in 2 s: the column arrives at a tilt with some speed).

2. Wall with a door (mechanism). The failure mode reported for dry-jointed panels with an
   opening under the settlement of one support (F. Portioli, L. Cascini, "Large displacement
   analysis of dry-jointed masonry structures subjected to settlements using rigid block
   modelling", Eng. Struct. 148 (2017) 485-496, tests on small-scale panels with an opening;
   also their Eng. Struct. 113 (2016) 347-361): the part of the wall on the moving support
   moves down with it as a macro-block, separated from the rest by a stepped diagonal crack
   that starts at a corner of the opening and runs along the joints through the spandrel.
   Only the papers' abstracts were available here, so their numbers are not compared; what
   is checked is that mechanism, with its geometry derived from the kinematics of dry
   running bond, independently of saxum:
   - the lintel over the door turns about the opening's top corner on the fixed side (the
     edge of the fixed pier): its material point there does not move;
   - a brick moves if and only if it rests, directly or through other bricks, on a moving
     block (the settling ground, the lintel); nothing else can move it, dry joints carry no
     tension. In running bond a brick rests on two bricks of the course below that it
     overlaps by half, so the moving region's boundary in the spandrel is a stepped crack
     that starts at the lintel's end and moves by half a brick per course: inclined at
     tan(alpha) = 2 h_b / l_b (h_b, l_b the brick's height and length) from the horizontal;
   - the pier on the settling ground moves down with it by delta, without turning (mu = 0.6:
     the thrust of the sagging spandrel pushes it aside; this is not checked);
   - the structure accommodates the settlement: judged at rest by the settlement criterion
     (the absolute-displacement one would call it collapsed: the pier moved by delta).
   Checked at two settlements, 10 and 20 mm, applied smoothly over 1 s.
"""

import json
import math
import textwrap

import numpy as np
import pytest

import saxum as sx
from saxum.collapse import CollapseCriterion, run_trial, scenario_critical_value
from saxum.structures import Opening, add_wall

B, H, E = 0.2, 1.0, 0.02


def test_critical_settlement_of_a_column_straddling_the_edge_of_a_settling_support(tmp_path):
    reference = (B / 2 + E) * B / math.hypot(B, H)
    x0, x1 = E - B / 2, E + B / 2
    (tmp_path / "column.json").write_text(json.dumps({"blocks": [
        {"name": "fixed", "kind": "fixed", "group": "ground",
         "vertices": [[-1, -0.1], [0, -0.1], [0, 0], [-1, 0]]},
        {"name": "settling", "kind": "fixed", "group": "ground",
         "vertices": [[0, -0.1], [1, -0.1], [1, 0], [0, 0]]},
        {"name": "column", "density": 2000.0,
         "vertices": [[x0, 0], [x1, 0], [x1, H], [x0, H]]}]}))
    (tmp_path / "column.toml").write_text(textwrap.dedent("""\
        [structure]
        type = "blocks"
        file = "column.json"
        [[laws]]
        groups = ["*", "*"]
        friction = 10.0
        [[loads.settlements]]
        block = "settling"
        magnitude = 0.01
        time = 4.0
        profile = "smooth"
        [solver]
        dt = 2e-3
        [output]
        duration = 5.0
    """))
    result = scenario_critical_value(tmp_path / "column.toml", "loads.settlements[0].magnitude",
                                     0.5 * reference, 1.5 * reference, tolerance=0.005)
    assert result.value == pytest.approx(reference, rel=0.02)
    stood = next(t for t in result.trials if t.value == result.stands)
    tilt = -float(stood.state.body_q[stood.simulation.model.body("column"), 2])
    assert tilt == pytest.approx(math.asin(result.stands / (B / 2 + E)), rel=0.02)


L_B, H_B = 0.25, 0.065  # brick [m]: tan(alpha) = 2 h_b / l_b = 0.52
DOOR_X, DOOR_W, DOOR_H = 0.75, 0.5, 4 * H_B  # [m]
SETTLE_TIME = 1.0  # [s]


def _wall(settlement):
    builder = sx.ModelBuilder()
    asm = add_wall(builder, courses=10, bricks=8, brick_length=L_B, brick_height=H_B,
                   openings=[Opening(DOOR_X, 0.0, DOOR_W, DOOR_H)], ground=True,
                   ground_splits=[DOOR_X + DOOR_W])
    for a in asm.groups:
        for b in asm.groups:
            builder.set_law(a, b, sx.ContactLaw(friction=0.6))
    rate = 0.5 * math.pi * settlement / SETTLE_TIME

    def smooth(t):
        return (0.0, -rate * math.sin(math.pi * t / SETTLE_TIME), 0.0) if t < SETTLE_TIME \
            else (0.0, 0.0, 0.0)

    builder.drive("ground 2", smooth)
    return asm, sx.Simulation(builder.finalize(), dt=1e-3)


def _moving_region(asm):
    """Bricks that rest, directly or through others, on the settling ground or the lintel."""
    bricks = asm["bricks"]
    box = {b: (*asm.outlines[b].min(axis=0), *asm.outlines[b].max(axis=0)) for b in bricks}
    box.update({b: (*asm.outlines[b].min(axis=0), *asm.outlines[b].max(axis=0))
                for b in asm["lintels"]})
    moving = set(asm["lintels"]) | {b for b in bricks if box[b][1] < 1e-9
                                    and box[b][0] >= DOOR_X + DOOR_W - 1e-9}
    grown = True
    while grown:
        grown = False
        for b in set(bricks) - moving:
            if any(abs(box[a][3] - box[b][1]) < 1e-9
                   and min(box[a][2], box[b][2]) - max(box[a][0], box[b][0]) > 1e-9
                   for a in moving):
                moving.add(b)
                grown = True
    return moving, box


@pytest.mark.parametrize("settlement", [0.01, 0.02])
def test_wall_with_a_door_under_settlement_forms_the_expected_mechanism(settlement):
    asm, sim = _wall(settlement)
    model = sim.model
    trial = run_trial(sim, settlement, CollapseCriterion(after_motion=True,
                                                         not_before=SETTLE_TIME))
    assert not trial.collapsed  # the settlement is accommodated
    u = trial.state.body_q - model.body_q0
    moved = np.hypot(u[:, 0], u[:, 1])
    assert moved.max() > 0.5 * settlement  # so the absolute criterion would say collapsed

    # the lintel turns (clockwise) about the fixed pier's corner, the door's top-left corner
    lintel = asm["lintels"][0]
    corner = np.array([DOOR_X, DOOR_H])
    turn = u[lintel, 2]
    arm = corner - model.body_q0[lintel, :2]
    rotated = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    assert np.hypot(*(trial.state.body_q[lintel, :2] + rotated @ arm - corner)) < 1e-3 * (
        settlement)
    assert turn < -0.1 * settlement / DOOR_W

    # moving region = the bricks resting on moving blocks; the rest does not move
    moving, box = _moving_region(asm)
    bricks = asm["bricks"]
    assert all(moved[b] > 0.02 * settlement for b in moving), "a brick of the region stayed"
    assert all(moved[b] < 0.005 * settlement for b in set(bricks) - moving), "one moved"
    # the crack in the spandrel: from the lintel's end, half a brick per course
    top = DOOR_H + 2 * H_B  # top of the lintel
    courses = sorted({round(box[b][1] / H_B) for b in bricks if box[b][1] >= top - 1e-9})
    crack = [min(box[b][0] for b in bricks if b in moving and round(box[b][1] / H_B) == c)
             for c in courses]
    lintel_end = DOOR_X - 0.5 * L_B  # the lintel bears half a brick on the fixed pier
    # it starts at the head joint of the first course above the lintel left of its end
    above = [box[b][0] for b in bricks if abs(box[b][1] - top) < 1e-9
             and box[b][0] < lintel_end < box[b][2]]
    assert len(courses) == 4 and crack[0] == pytest.approx(above[0])
    assert np.diff(crack) == pytest.approx([-0.5 * L_B] * 3)
    assert math.atan2(H_B, -np.mean(np.diff(crack))) == pytest.approx(math.atan(2 * H_B / L_B))

    # the pier on the settling ground moves down with it without turning
    pier = [b for b in bricks if box[b][0] >= DOOR_X + DOOR_W - 1e-9 and box[b][3] <= top + 1e-9]
    assert len(pier) > 10
    assert u[pier, 1] == pytest.approx(-settlement, rel=0.01)
    assert np.abs(u[pier, 2]).max() < 1e-3
