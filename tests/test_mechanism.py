"""Joint resultants and the thrust line, on hand-made contacts with known answers; discs are
no hinges."""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.mechanism import (
    joint_opening,
    joint_resultants,
    joint_states,
    mechanism,
    round_pairs,
    thrust_line,
)


def _contacts(pairs, points, rn, rt=None, gap=None):
    k = len(pairs)
    up = np.tile(np.array([[1.0, 0.0], [0.0, 1.0]]), (k, 1, 1))  # t = x, n = y
    rt = np.zeros(k) if rt is None else np.asarray(rt, float)
    return {"candidate": np.array([p[0] for p in pairs]),
            "antagonist": np.array([p[1] for p in pairs]),
            "point": np.asarray(points, float), "frame": up,
            "gap": np.zeros(k) if gap is None else np.asarray(gap, float),
            "force": np.column_stack((rt, np.asarray(rn, float)))}


def test_centre_of_pressure_and_resultant():
    c = _contacts([(2, 1), (1, 2), (3, 1)], [(0.0, 0.0), (1.0, 0.0), (5.0, 1.0)],
                  rn=[1.0, 3.0, 2.0], rt=[0.5, -0.1, 0.0])
    pairs, cop, resultant = joint_resultants(c, gap_tolerance=1e-6)
    assert pairs.tolist() == [[1, 2], [1, 3]]
    assert cop[0] == pytest.approx([0.75, 0.0])  # (1 * 0 + 3 * 1) / 4
    assert resultant[0] == pytest.approx([0.4, 4.0])
    assert cop[1] == pytest.approx([5.0, 1.0]) and resultant[1] == pytest.approx([0.0, 2.0])


def test_open_points_carry_nothing_and_unloaded_joints_have_no_centre():
    c = _contacts([(1, 2), (1, 2), (3, 4)], [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)],
                  rn=[1.0, 3.0, 0.0], gap=[0.0, 1e-3, 0.0])
    _, cop, _ = joint_resultants(c, gap_tolerance=1e-6)
    assert cop[0] == pytest.approx([0.0, 0.0])
    assert np.isnan(cop[1]).all()


def test_thrust_line_is_ordered_about_the_centre():
    # springings a hair below the centre's level must still be the ends of the line
    angles = np.radians([180.0 + 1e-9, 30.0, 90.0, -1e-9])
    pts = np.column_stack((np.cos(angles), np.sin(angles)))
    c = _contacts([(1, 2), (2, 3), (3, 4), (4, 5)], pts, rn=[1.0, 1.0, 1.0, 1.0])
    line = thrust_line(c, 1e-6, centre=(0.0, 0.0))
    assert line == pytest.approx(pts[[0, 2, 1, 3]])


def _tilted_wall(friction, factor, seconds=0.15):
    """A 12-course running-bond wall two bricks long (0.5 x 0.78 m) under a horizontal load
    factor, after `seconds` of motion."""
    import dataclasses

    import saxum as sx
    from saxum.mechanism import mechanism
    from saxum.structures import wall

    model = wall(courses=12, bricks=2, friction=friction)
    loaded = dataclasses.replace(model, accelerations=((lambda t: (factor * 9.81, 0.0)),))
    sim = sx.Simulation(loaded, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, seconds)
    return mechanism(loaded, state, 1e-3)


def test_wall_hinges_and_slides_are_located_by_course_and_position():
    rocking = _tilted_wall(friction=1.0, factor=1.0)
    toe = [j for j in rocking.hinges if j.courses == (1,)]
    assert toe and all(j.along == pytest.approx(0.5, abs=1e-3) for j in toe)  # right end
    assert "hinge between ground and brick c1b2 at (0.5, " in rocking.text()
    assert ": course 1 against ground, 0.5 m along" in rocking.text()
    inner = [j for j in rocking.hinges if j.courses and len(j.courses) == 2]
    for j in inner:  # a bed joint between neighbouring courses, or a head joint
        assert abs(j.courses[0] - j.courses[1]) <= 1
        assert ("head joint in course" if j.courses[0] == j.courses[1]
                else "bed joint between courses") in j.location
    sliding = _tilted_wall(friction=0.3, factor=0.6)
    base = [j for j in sliding.sliding if j.courses == (1,)]
    assert base and "sliding joint between ground and brick c1b" in sliding.text()
    assert all(0.0 <= j.along <= 0.5 for j in base)


def test_arches_keep_their_report():
    """Voussoirs are not coursed blocks: no course, no position along a course."""
    import dataclasses

    import saxum as sx
    from saxum.mechanism import mechanism
    from saxum.structures import semicircular_arch

    model = semicircular_arch(radius=1.0, thickness=0.1, voussoirs=9)
    sim = sx.Simulation(dataclasses.replace(model), dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 0.2)
    mech = mechanism(model, state, 1e-3)
    assert mech.hinges and all(j.courses is None and j.location is None for j in mech.joints)
    assert "along" not in mech.text() and "course" not in mech.text()


def test_mechanism_of_a_results_frame_locates_wall_joints_by_course(tmp_path):
    """frame_mechanism reads a wall's results file as mechanism() reads the model (it once
    failed on blocks named by course: the results' bodies had no vertices)."""
    from saxum.mechanism import frame_mechanism, mechanism
    from saxum.results import Results
    from saxum.runner import run_scenario
    from saxum.scenario import Scenario

    scenario = Scenario.model_validate({
        "structure": {"type": "running_bond_wall", "courses": 12, "bricks": 2},
        "laws": [{"groups": ["*", "*"], "friction": 1.0}],
        "loads": {"horizontal_acceleration": 9.81},
        "output": {"duration": 0.15, "interval": 0.05}})
    run_scenario(scenario, tmp_path / "wall.h5", quiet=True)
    with Results(tmp_path / "wall.h5") as r:
        from_file = frame_mechanism(r, -1)
    sim = scenario.build_simulation()
    state = sim.initial_state()
    sim.run(state, 0.15)
    direct = mechanism(sim.model, state, sim.integrator.dt)
    assert any(j.courses == (1,) for j in from_file.hinges)
    assert from_file.text() == direct.text()


def _contacts_3d(joints):
    """Hand-made 3D contacts: joints of (pair, [(point, gap, normal force), ...]), frame
    t = x, n = z, s = y."""
    rows = [(pair, p, g, rn) for pair, points in joints for p, g, rn in points]
    k = len(rows)
    frame = np.tile(np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]]), (k, 1, 1))
    return {"candidate": np.array([r[0][0] for r in rows]),
            "antagonist": np.array([r[0][1] for r in rows]),
            "point": np.array([r[1] for r in rows], float).reshape(k, 3), "frame": frame,
            "gap": np.array([r[2] for r in rows], float),
            "force": np.column_stack((np.zeros(k), [r[3] for r in rows], np.zeros(k)))}


def test_3d_joint_states_and_hinge_lines():
    from saxum.mechanism import hinge_lines, joint_states

    square = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    c = _contacts_3d([
        ((1, 0), list(zip(square, [0, 0, 0, 0], [1, 1, 1, 1], strict=True))),  # closed
        ((2, 0), list(zip(square, [0, 0, 1e-3, 1e-3], [1, 2, 0, 0], strict=True))),  # edge
        ((3, 0), list(zip(square, [0, 0, 0, 1e-3], [1, 1, 1, 0], strict=True))),  # 3 loaded
        ((4, 0), [((0, 0, 0), 0, 1), ((0, 1, 0), 0, 1)]),  # an edge on a face, no point open
        ((5, 0), list(zip(square, [0, 1e-3, 1e-3, 1e-3], [3, 0, 0, 0], strict=True))),  # pivot
        ((6, 0), list(zip(square, [0, 0, 1e-3, 1e-3], [1, 0, 0, 0], strict=True))),
    ])
    labels = joint_states(c, gap_tolerance=1e-4).reshape(-1)
    assert labels[:4].tolist() == ["closed"] * 4
    assert labels[4:8].tolist() == ["hinge", "hinge", "open", "open"]
    assert labels[8:12].tolist() == ["closed", "closed", "closed", "open"]  # not on a line
    assert labels[12:14].tolist() == ["hinge", "hinge"]
    assert labels[14:18].tolist() == ["hinge", "open", "open", "open"]
    # one loaded point of a joint open on one side, touching along the edge y = 0: a hinge
    assert labels[18:22].tolist() == ["hinge", "closed", "open", "open"]
    lines = hinge_lines(c, 1e-4)
    assert lines.shape == (4, 2, 3)  # the edges y = 0 (twice), x = 0, and the pivot
    assert sorted(map(tuple, np.sort(lines, axis=1).reshape(4, 6))) == [
        (0, 0, 0, 0, 0, 0), (0, 0, 0, 0, 1, 0), (0, 0, 0, 1, 0, 0), (0, 0, 0, 1, 0, 0)]


def test_an_edge_on_a_face_hinges_only_once_the_blocks_have_turned():
    """A joint that touches along a line only (blocks whose edges meet where joints line up)
    carries load at rest without turning: a hinge only when the blocks' relative rotation
    moves a point at the smaller block's size by more than the gap tolerance."""
    from saxum.mechanism import joint_states

    c = _contacts_3d([((4, 0), [((0, 0, 0), 0, 1), ((0, 1, 0), 0, 1)])])
    assert joint_states({**c, "opening": np.full(2, 5e-5)}, 1e-4).tolist() == ["closed"] * 2
    assert joint_states({**c, "opening": np.full(2, 2e-4)}, 1e-4).tolist() == ["hinge"] * 2
    c2 = _contacts([(2, 1)], [(0.0, 0.0)], rn=[1.0])  # 2D: a corner on a face
    assert joint_states({**c2, "opening": np.array([0.0])}, 1e-4).tolist() == ["closed"]
    assert joint_states(c2, 1e-4).tolist() == ["hinge"]  # without openings: as turned


def test_joint_opening_is_the_relative_turn_times_the_smaller_size():
    from saxum.mechanism import joint_opening

    q0 = np.array([[0.0, 0.0, 0.3], [1.0, 0.0, -0.2], [2.0, 0.0, 0.0]])
    q = q0 + [[0.0, 0.0, 0.05], [5.0, 1.0, -0.02], [0.0, 0.0, 0.0]]
    opening = joint_opening(q, q0, np.array([2.0, 0.5, 1.0]), np.array([0, 1]), np.array([1, 2]))
    assert opening == pytest.approx([0.07 * 0.5, 0.02 * 0.5])
    # 3D: body 0 turned by 0.3 rad about z, body 1 by 0.1 rad about z then both by 1 rad
    # about x (the common turn cancels): relative 0.2 rad
    def quat(angle, axis):
        return np.r_[np.cos(angle / 2), np.sin(angle / 2) * np.asarray(axis, float)]

    def mul(a, b):
        return np.r_[a[0] * b[0] - a[1:] @ b[1:], a[0] * b[1:] + b[0] * a[1:]
                     + np.cross(a[1:], b[1:])]

    start = quat(0.7, (0, 1, 0))
    common = quat(1.0, (1, 0, 0))
    q0 = np.array([np.r_[0, 0, 0, start], np.r_[1, 0, 0, start]])
    q = np.array([np.r_[0, 0, 0, mul(common, mul(quat(0.3, (0, 0, 1)), start))],
                  np.r_[3, 2, 1, mul(common, mul(quat(0.1, (0, 0, 1)), start))]])
    opening = joint_opening(q, q0, np.array([1.0, 2.0]), np.array([0]), np.array([1]))
    assert opening == pytest.approx([0.2], rel=1e-12)



def test_an_edge_on_a_face_at_rest_is_no_hinge():
    """A block on the ground whose top edge touches the sloping face of a fixed block: the
    edge-on-face contact carries load at rest (the rest solution loads every closed contact,
    as between a voussoir's edge and a spandrel stone), but nothing turns: no hinge is
    reported, and nothing moves (without the joints' openings it would count as one)."""
    import saxum as sx
    from saxum.mechanism import joint_states, mechanism

    b = sx.ModelBuilder(dim=3)
    b.add_block([(x, y, z) for x in (-1.0, 3.0) for y in (0.0, 0.4) for z in (-0.5, 0.0)],
                kind=sx.BodyKind.FIXED, group="ground")
    b.add_block([(x, y, z) for x, z in ((1.0, 1.5), (2.5, 0.0), (2.5, 1.5)) for y in (0.0, 0.4)],
                kind=sx.BodyKind.FIXED, group="ground")
    b.add_block([(x, y, z) for x in (0.0, 1.5) for y in (0.0, 0.4) for z in (0.0, 1.0)],
                density=2400.0)
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = b.finalize()
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 0.02)
    report = mechanism(model, state, sim.integrator.dt)
    assert len(report.joints) == 2
    assert not any(j.hinge for j in report.joints)
    assert report.moving == []
    c = state.contacts
    k = c.count
    edge = c.antagonist[:k] == 1
    assert edge.sum() == 2 and np.all(c.impulse[:k][edge, 1] > 0.0)  # loaded, along a line
    plain = {"candidate": c.candidate[:k], "antagonist": c.antagonist[:k],
             "point": c.point[:k], "frame": c.frame[:k], "gap": c.gap[:k],
             "force": c.impulse[:k]}
    assert (joint_states(plain, 1e-6)[edge] == "hinge").all()


def test_round_bodies_roll_stick_and_are_no_hinges():
    """A disc rolling down a 0.3 rad incline (mu = 0.5 > tan(0.3) / 3: it rolls without
    slipping, tests/validation/test_rolling.py) turns about its one contact point, which the
    face-joint rule would call a hinge; a disc resting on the flat ground sticks."""
    slope = 0.3
    normal = np.array([math.sin(slope), math.cos(slope)])
    b = sx.ModelBuilder()
    b.add_plane((0.0, 0.0), normal, 3.0, group="plane", name="incline")
    b.add_plane((0.0, -2.0), (0.0, 1.0), 3.0, group="plane", name="floor")
    b.add_disc(0.1 * normal, 0.1, density=2000.0, name="rolling")
    b.add_disc((0.0, -1.9), 0.1, density=2000.0, name="resting")
    law = sx.ContactLaw(friction=0.5)
    b.set_law("block", "plane", law)
    b.set_law("block", "block", law)
    model = b.finalize()
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    for _ in range(100):
        sim.step(state)
    mech = mechanism(model, state, 1e-3)
    joints = {j.bodies: j for j in mech.joints}
    rolls = next(j for names, j in joints.items() if "rolling" in names)
    rests = next(j for names, j in joints.items() if "resting" in names)
    assert not mech.hinges
    assert rolls.rolling and not rolls.sliding
    assert not rests.rolling and not rests.sliding and not rests.hinge
    assert "rolling contacts (discs, spheres): " in mech.text()
    # without the round flag the rolling disc's point is labelled a hinge
    c = state.contacts
    k = c.count
    contacts = {"candidate": c.candidate[:k], "antagonist": c.antagonist[:k],
                "gap": c.gap[:k], "force": c.impulse[:k] / 1e-3, "point": c.point[:k],
                "opening": joint_opening(state.body_q, model.body_q0, model.body_size,
                                         c.candidate[:k], c.antagonist[:k])}
    assert "hinge" in joint_states(contacts, 1e-6)
    contacts["round"] = round_pairs(model.body_shape, c.candidate[:k], c.antagonist[:k])
    assert set(joint_states(contacts, 1e-6)) == {"closed"}
