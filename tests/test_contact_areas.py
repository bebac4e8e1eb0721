"""Contact areas (saxum.contacts.Contacts.area): the share of the contact face that each point
of a contact stands for, as detection computes it (saxum.detection.polygons, .polyhedra).

Tolerances: the blocks have coordinates and sizes of order 1 m, and each area comes from a few
differences of world coordinates (round-off about 1e-16 m each, more after a rotation of the
whole configuration) multiplied by lengths of order 1 m: 1e-12 [m or m^2] leaves a margin of
a thousand over that round-off and is still 1e-10 of the alert distance, far below any
physical meaning.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import saxum as sx
from saxum.contacts import Contacts
from saxum.detection import DetectionSettings, detector_for
from saxum.structures.solid import box

TOL = 1e-12
ALERT = 0.01


def _turn2(points, angle, centre=(0.0, 0.0)):
    c, s = math.cos(angle), math.sin(angle)
    return [(centre[0] + c * (x - centre[0]) - s * (y - centre[1]),
             centre[1] + s * (x - centre[0]) + c * (y - centre[1])) for x, y in points]


def _box2(x0, y0, w, h, angle=0.0):
    return _turn2([(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)], angle)


def _rotation(axis, angle):
    a = np.asarray(axis, dtype=float)
    a /= np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def _detect(blocks, dim):
    b = sx.ModelBuilder(dim=dim)
    for k, points in enumerate(blocks):
        b.add_block(points, density=1000.0, name=f"block {k}")
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    model = b.finalize()
    contacts = Contacts(dim)
    detector_for(model, DetectionSettings(alert=ALERT)).detect(model.body_q0, contacts)
    return contacts.area[: contacts.count], contacts


# -- 2D: lengths per metre of depth ---------------------------------------------------------


def test_block_on_block_each_end_stands_for_half_the_joint():
    area, _ = _detect([_box2(0, 0, 1.0, 0.5), _box2(0, 0.5, 1.0, 0.5)], 2)
    assert area == pytest.approx([0.5, 0.5], abs=TOL)


def test_partial_overlap_shares_the_common_segment():
    # the upper block overhangs by 0.3 m: common segment 0.7 m
    area, _ = _detect([_box2(0, 0, 1.0, 0.5), _box2(0.3, 0.5, 1.0, 0.5)], 2)
    assert area == pytest.approx([0.35, 0.35], abs=TOL)


@pytest.mark.parametrize("angle", [0.3, -1.1, 2.5])
def test_rotated_pair_keeps_its_overlap_length(angle):
    # both blocks turned as a whole: the joint is the same 0.6 m long
    blocks = [_turn2(_box2(0, 0, 1.0, 0.5), angle), _turn2(_box2(0.4, 0.5, 0.8, 0.3), angle)]
    area, _ = _detect(blocks, 2)
    assert area.sum() == pytest.approx(0.6, abs=TOL)
    assert area == pytest.approx([0.3, 0.3], abs=TOL)


def test_vertex_on_face_stands_for_the_part_within_the_alert_distance():
    # a square turned by 30 degrees whose lowest corner is 2 mm above the ground's face: of its
    # incident edge (at 30 degrees to the face) the part within alert projects on the face
    # as (alert - gap) / tan(30 deg)
    theta, lift = math.radians(30.0), 0.002
    square = [(x + 0.5, y + lift) for x, y in _turn2(_box2(0, 0, 0.2, 0.2), theta)]
    area, c = _detect([_box2(0, -0.5, 1.0, 0.5), square], 2)
    assert c.count == 1
    assert area[0] == pytest.approx((ALERT - lift) / math.tan(theta), abs=TOL)


def test_tilted_face_open_beyond_the_alert_distance_at_one_end():
    # the upper block's face rises by 3 alert over its 1 m: one end is in contact, and it
    # stands for the third of the joint whose gap is within alert
    rise = 3.0 * ALERT
    theta = math.atan(rise)
    upper = _turn2(_box2(0, 0, 1.0, 0.5), theta)
    area, c = _detect([_box2(-0.2, -0.5, 1.4, 0.5), upper], 2)
    assert c.count == 1
    assert area[0] == pytest.approx(ALERT / rise, abs=TOL)


@settings(max_examples=40, deadline=None)
@given(w0=st.floats(0.2, 2.0), w1=st.floats(0.2, 2.0), offset=st.floats(-0.9, 0.9),
       angle=st.floats(-math.pi, math.pi), lift=st.floats(0.0, 0.5 * ALERT))
def test_property_areas_are_nonnegative_and_sum_to_the_overlap_length(w0, w1, offset, angle,
                                                                       lift):
    x1 = offset * w0
    overlap = min(w0, x1 + w1) - max(0.0, x1)
    blocks = [_turn2(_box2(0, 0, w0, 0.4), angle),
              _turn2(_box2(x1, 0.4 + lift, w1, 0.3), angle)]
    area, c = _detect(blocks, 2)
    assert np.all(area >= 0.0)
    if overlap > 1e-3:  # beyond the corner-to-corner tie (module doc of polygons)
        assert c.count == 2
        assert area.sum() == pytest.approx(overlap, abs=TOL)


@settings(max_examples=40, deadline=None)
@given(tilt=st.floats(-0.2, 0.2), lift=st.floats(0.0, 0.9 * ALERT), x1=st.floats(-0.5, 0.5))
def test_property_tilted_blocks_have_areas_within_the_overlap(tilt, lift, x1):
    upper = [(x, y + lift) for x, y in _turn2(_box2(x1, 0.4, 0.8, 0.3), tilt, (x1, 0.4))]
    area, _ = _detect([_box2(0, 0, 1.0, 0.4), upper], 2)
    assert np.all(area >= 0.0)
    assert area.sum() <= 1.0 + TOL


# -- 3D: areas ------------------------------------------------------------------------------


def test_offset_bricks_share_their_overlap_rectangle():
    area, c = _detect([box(0, 0, 0, 1, 1, 1), box(0.5, 0.25, 1, 1.5, 1.25, 2)], 3)
    assert c.count == 4
    assert area == pytest.approx([0.5 * 0.75 / 4] * 4, abs=TOL)


def test_squares_at_45_degrees_share_their_octagon():
    # two unit squares, one turned by 45 degrees about their common axis: the overlap is the
    # regular octagon of inradius 1/2, area 2 (sqrt 2 - 1); its 8 corners share it equally
    turn = _rotation((0, 0, 1), math.pi / 4)
    lower = box(-0.5, -0.5, -1, 0.5, 0.5, 0)
    upper = box(-0.5, -0.5, 0, 0.5, 0.5, 1) @ turn.T
    area, c = _detect([lower, upper], 3)
    assert c.count == 8
    assert area.sum() == pytest.approx(2.0 * (math.sqrt(2.0) - 1.0), abs=TOL)
    assert area == pytest.approx([area.sum() / 8] * 8, abs=TOL)


def test_edge_on_face_stands_for_a_strip_within_the_alert_distance():
    # a cube turned by 30 degrees about x, its lowest edge 2 mm above the ground: of the
    # incident face the strip within alert is (alert - gap) / tan(30 deg) wide and 1 m long
    theta, lift = math.radians(30.0), 0.002
    cube = box(-0.5, -0.5, -0.5, 0.5, 0.5, 0.5) @ _rotation((1, 0, 0), theta).T
    cube[:, 2] += lift - cube[:, 2].min()
    area, c = _detect([box(-2, -2, -1, 2, 2, 0), cube], 3)
    assert c.count == 2
    assert area.sum() == pytest.approx((ALERT - lift) / math.tan(theta), abs=TOL)
    assert area == pytest.approx([area.sum() / 2] * 2, abs=TOL)


def test_edge_against_edge_has_no_area():
    # two cubes crossed edge to edge (the upper one's lowest edge across the lower one's top
    # edge), 1 mm apart
    lower = box(-0.5, -0.5, -0.5, 0.5, 0.5, 0.5) @ _rotation((1, 0, 0), math.pi / 4).T
    upper = box(-0.5, -0.5, -0.5, 0.5, 0.5, 0.5) @ _rotation((0, 1, 0), math.pi / 4).T
    upper[:, 2] += lower[:, 2].max() - upper[:, 2].min() + 0.001
    area, c = _detect([lower, upper], 3)
    assert c.count == 1
    assert area[0] == pytest.approx(0.0, abs=TOL)


@settings(max_examples=30, deadline=None)
@given(size=st.tuples(st.floats(0.3, 2.0), st.floats(0.3, 2.0)),
       shift=st.tuples(st.floats(-0.8, 0.8), st.floats(-0.8, 0.8)),
       axis=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(0.1, 1)),
       angle=st.floats(-math.pi, math.pi), lift=st.floats(0.0, 0.5 * ALERT))
def test_property_3d_areas_are_nonnegative_and_sum_to_the_overlap_area(size, shift, axis,
                                                                        angle, lift):
    lx, ly = size
    x1, y1 = shift[0] * lx, shift[1] * ly
    overlap = ((min(1.0, x1 + lx) - max(0.0, x1)) * (min(1.0, y1 + ly) - max(0.0, y1)))
    turn = _rotation(axis, angle)
    lower = box(0, 0, -0.5, 1, 1, 0) @ turn.T
    upper = box(x1, y1, lift, x1 + lx, y1 + ly, lift + 0.4) @ turn.T
    area, c = _detect([lower, upper], 3)
    assert np.all(area >= 0.0)
    if min(min(1.0, x1 + lx) - max(0.0, x1), min(1.0, y1 + ly) - max(0.0, y1)) > 1e-3:
        assert c.count == 4
        assert area.sum() == pytest.approx(overlap, abs=TOL)


# -- the field travels with the contacts ----------------------------------------------------


def test_area_is_kept_by_copy_and_reserve():
    _, c = _detect([box(0, 0, 0, 1, 1, 1), box(0.5, 0.25, 1, 1.5, 1.25, 2)], 3)
    expected = c.area[: c.count].copy()
    assert np.array_equal(c.copy().area[: c.count], expected)
    c.reserve(10 * c.capacity)
    assert np.array_equal(c.area[: c.count], expected)


def test_results_frames_and_checkpoints_store_the_areas(tmp_path):
    from saxum.results import Results, ResultsWriter
    from saxum.structures import wall

    model = wall(courses=3, bricks=2, friction=0.6)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    with ResultsWriter(tmp_path / "w.h5", model, dt=1e-3, theta=0.5) as w:
        sim.run(state, 0.01)
        w.write_frame(state)
        w.write_checkpoint(state, sim.detector)
    expected = state.contacts.area[: state.contacts.count]
    assert expected.sum() > 0.0
    with Results(tmp_path / "w.h5") as r:
        assert np.array_equal(r.contacts(-1)["area"], expected)
        assert r.units["area"] == "m^2/m"
        restored = sim.restore(r.checkpoint(-1)).contacts
    assert np.array_equal(restored.area[: restored.count], expected)


def test_results_written_before_areas_are_read_and_resumed_without_them(tmp_path):
    import h5py

    from saxum.mechanism import frame_mechanism
    from saxum.results import Results, ResultsWriter
    from saxum.structures import wall

    model = wall(courses=3, bricks=2, friction=0.6)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    path = tmp_path / "old.h5"
    with ResultsWriter(path, model, dt=1e-3, theta=0.5) as w:
        sim.run(state, 0.005)
        w.write_frame(state)
        w.write_checkpoint(state, sim.detector)
    with h5py.File(path, "a") as f:  # the layout of files from before Contacts.area
        del f["frames/contacts/area"], f["checkpoints/contacts/area"]
        for group in ("frames", "steps", "histories", "checkpoints"):  # nor row checksums
            if f"{group}/checksum" in f:
                del f[f"{group}/checksum"]
    with Results(path) as r:
        assert "area" not in r.contacts(-1) and "area" not in r.checkpoint(-1)["contacts"]
        count = r.contacts(-1)["gap"].size
        frame_mechanism(r, -1)  # builds its Contacts from the fields the file has
    writer, _ = ResultsWriter.resume(path)
    with writer:
        writer.write_frame(state)
    with Results(path) as r:
        assert r.frame_count == 2 and r.contacts(-1)["gap"].size == count
