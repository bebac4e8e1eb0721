"""Contact detection between convex polyhedra (saxum.detection: broad phase in 3D, narrow phase
of saxum.detection.polyhedra): points, gaps, frames, identities, invariance, overlap errors."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import saxum as sx
from saxum.contacts import Contacts
from saxum.detection import DetectionSettings, detector_for
from saxum.detection.broadphase import bounding_boxes, grid_pairs
from saxum.errors import OverlapError
from saxum.structures.solid import box


def _rotation(axis, angle):
    a = np.asarray(axis, dtype=float)
    a /= np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def _cube(size=1.0):
    h = 0.5 * size
    return box(-h, -h, -h, h, h, h)


def _detect(blocks, alert=0.01):
    b = sx.ModelBuilder(dim=3)
    for k, points in enumerate(blocks):
        b.add_block(points, density=1000.0, name=f"block {k}")
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    model = b.finalize()
    contacts = Contacts(3)
    detector_for(model, DetectionSettings(alert=alert)).detect(model.body_q0, contacts)
    return model, contacts


def _rows(c):
    n = c.count
    return c.point[:n], c.gap[:n], c.frame[:n], c.candidate[:n], c.antagonist[:n], c.key[:n]


def _check_frames(frame):
    for f in frame:
        assert f @ f.T == pytest.approx(np.eye(3), abs=1e-12)
        assert np.cross(f[0], f[1]) @ f[2] == pytest.approx(1.0, abs=1e-12)  # (t, n, s)


def test_offset_bricks_touch_at_the_corners_of_their_overlap():
    model, c = _detect([box(0, 0, 0, 1, 1, 1), box(0.5, 0.25, 1, 1.5, 1.25, 2)])
    point, gap, frame, cand, ant, key = _rows(c)
    assert c.count == 4
    assert sorted(map(tuple, point.round(12))) == [(0.5, 0.25, 1.0), (0.5, 1.0, 1.0),
                                                   (1.0, 0.25, 1.0), (1.0, 1.0, 1.0)]
    # the faces meet at z = 1 m: each side's height is centre + R (vertex - centre), round-off
    # of ~1e-16 m on 1 m; 1e-12 m allowed
    assert np.abs(gap).max() <= 1e-12
    assert np.all(ant == 0) and np.all(cand == 1)  # the first body carries the frame
    assert frame[:, 1] == pytest.approx(np.tile([0.0, 0.0, 1.0], (4, 1)))
    _check_frames(frame)
    assert np.all(np.diff(key) > 0)


def test_squares_at_45_degrees_touch_at_all_eight_corners_of_the_octagon():
    top = _cube() @ _rotation((0, 0, 1), math.pi / 4).T + (0.5, 0.5, 1.5)
    _, c = _detect([box(0, 0, 0, 1, 1, 1), top])
    point, gap, *_ = _rows(c)
    assert c.count == 8
    r = math.sqrt(0.5)
    # the octagon's corners: on the square's sides at 1 - 1/sqrt(2) and 1/sqrt(2)
    for x, y in point[:, :2]:
        on_side = min(abs(x), abs(x - 1), abs(y), abs(y - 1)) < 1e-12
        other = y if min(abs(x), abs(x - 1)) < 1e-12 else x
        assert on_side and min(abs(other - (1 - r)), abs(other - r)) < 1e-12
    assert np.abs(gap).max() < 1e-12


def test_edge_and_vertex_against_a_face():
    base = box(0, 0, 0, 1, 1, 1)
    edge = _cube() @ _rotation((1, 0, 0), math.pi / 4).T
    edge += (0.5, 0.5, 1.0 - edge[:, 2].min())
    _, c = _detect([base, edge])
    point, gap, frame, *_ = _rows(c)
    assert c.count == 2
    assert point == pytest.approx(np.array([[0.0, 0.5, 1.0], [1.0, 0.5, 1.0]]), abs=1e-12)
    corner = _cube() @ _rotation((1, 1, 0), 0.6).T
    corner += (0.5, 0.5, 1.003 - corner[:, 2].min())
    _, c = _detect([base, corner])
    point, gap, frame, *_ = _rows(c)
    assert c.count == 1 and gap[0] == pytest.approx(0.003, abs=1e-12)
    assert frame[0, 1] == pytest.approx([0.0, 0.0, 1.0])


def test_crossed_edges_give_one_edge_edge_contact():
    low = _cube() @ _rotation((1, 0, 0), math.pi / 4).T
    low -= (0.0, 0.0, low[:, 2].max())
    high = _cube() @ _rotation((0, 1, 0), math.pi / 4).T
    high -= (0.0, 0.0, high[:, 2].min() - 0.004)
    _, c = _detect([low, high])
    point, gap, frame, cand, ant, _ = _rows(c)
    assert c.count == 1
    assert gap[0] == pytest.approx(0.004, abs=1e-12)
    assert point[0] == pytest.approx([0.0, 0.0, 0.004], abs=1e-12)
    assert frame[0, 1] == pytest.approx([0.0, 0.0, 1.0], abs=1e-12)
    _check_frames(frame)
    # apart by more than the alert distance: nothing
    _, c = _detect([low, high + (0.0, 0.0, 0.02)])
    assert c.count == 0


def test_blocks_meeting_only_at_corners_are_not_in_contact_under_round_off():
    """Two cubes touching at a single corner, or along an edge with faces in one plane: three
    (two) faces of each separate by 0, which one most is round-off, and no normal is right
    (saxum.detection.polyhedra): no contact, for shifts of 1e-12 m in any direction too (far
    below the closed gap, 1e-8 m here). Overlapping by 0.1 mm along the edge, the faces share
    an area: a contact."""
    for shift in np.array(np.meshgrid(*[(-1e-12, 0.0, 1e-12)] * 3)).reshape(3, -1).T:
        _, c = _detect([box(0, 0, 0, 1, 1, 1), box(1, 1, 1, 2, 2, 2) + shift])
        assert c.count == 0
        _, c = _detect([box(0, 0, 0, 1, 1, 1), box(1, 0, 1, 2, 1, 2) + shift])
        assert c.count == 0
    _, c = _detect([box(0, 0, 0, 1, 1, 1), box(1 - 1e-4, 0, 1, 2, 1, 2)])
    assert c.count == 4 and np.abs(c.gap[:4]).max() < 1e-12
    assert np.allclose(np.abs(c.frame[:4, 1]), [0.0, 0.0, 1.0])


def test_gap_within_alert_and_nothing_beyond():
    _, c = _detect([box(0, 0, 0, 1, 1, 1), box(0, 0, 1.006, 1, 1, 2)])
    assert c.count == 4 and np.allclose(c.gap[:4], 0.006, atol=1e-12)
    _, c = _detect([box(0, 0, 0, 1, 1, 1), box(0, 0, 1.011, 1, 1, 2)])
    assert c.count == 0


angles = st.tuples(st.floats(-math.pi, math.pi), st.floats(0.0, math.pi),
                   st.floats(-math.pi, math.pi))


@settings(max_examples=30)
@given(angles, st.tuples(*[st.floats(-20.0, 20.0)] * 3), st.floats(0.0, 0.8),
       st.floats(0.0, 0.008))
def test_contacts_move_with_a_rigid_motion_of_the_pair(rot, shift, offset, lift):
    """Points, normals and gaps of two stacked blocks follow any rotation R and translation d
    of the pair: p -> R p + d, n -> R n, gap unchanged; same count. (The identities are not
    compared: faces are numbered in the order Qhull finds them, which depends on the input.)"""
    r = _rotation((math.cos(rot[0]) * math.sin(rot[1]), math.sin(rot[0]) * math.sin(rot[1]),
                   math.cos(rot[1])), rot[2])
    blocks = [box(0, 0, 0, 1, 0.6, 0.4), box(offset, 0.1, 0.4 + lift, offset + 1, 0.7,
                                             0.8 + lift)]
    _, ref = _detect(blocks)
    _, moved = _detect([p @ r.T + shift for p in blocks])
    assert moved.count == ref.count == 4
    back = (moved.point[: moved.count] - shift) @ r
    expected = ref.point[: ref.count]
    assert back[np.lexsort(back.round(6).T)] == pytest.approx(
        expected[np.lexsort(expected.round(6).T)], abs=1e-9)
    assert moved.gap[: moved.count] == pytest.approx(np.full(4, lift), abs=1e-9)
    assert moved.frame[: moved.count, 1] @ r == pytest.approx(
        np.tile([0.0, 0.0, 1.0], (4, 1)), abs=1e-9)
    _check_frames(moved.frame[: moved.count])


@settings(max_examples=20)
@given(st.lists(st.tuples(*[st.floats(0.0, 3.0)] * 3, st.floats(0.05, 0.4)), min_size=2,
                max_size=40))
def test_broad_phase_3d_finds_every_overlapping_box_once(specs):
    lo = np.array([s[:3] for s in specs])
    hi = lo + np.array([[s[3]] * 3 for s in specs])
    n = len(specs)
    out = np.empty((4 * n * n, 2), dtype=np.int32)
    count = grid_pairs(lo, hi, np.ones(n, bool), np.zeros(n, bool),
                       float((hi - lo).max()), out)
    found = {tuple(p) for p in out[:count]}
    assert len(found) == count
    brute = {(i, j) for i in range(n) for j in range(i + 1, n)
             if np.all(lo[i] <= hi[j]) and np.all(lo[j] <= hi[i])}
    assert found == brute


def test_bounding_boxes_3d():
    wv = np.array([[0.0, 1.0, 2.0], [1.0, -1.0, 3.0], [5.0, 5.0, 5.0]])
    lo, hi = np.empty((2, 3)), np.empty((2, 3))
    bounding_boxes(wv, np.array([0, 2, 3]), 0.5, lo, hi)
    assert lo[0] == pytest.approx([-0.5, -1.5, 1.5]) and hi[1] == pytest.approx([5.5] * 3)


def test_overlap_at_start_names_the_pair_and_depth():
    b = sx.ModelBuilder(dim=3)
    b.add_block(box(-2, -2, -0.2, 2, 2, 0), kind=sx.BodyKind.FIXED, group="ground",
                name="ground")
    b.add_block(box(0, 0, -0.003, 0.3, 0.2, 0.2), density=2000.0, name="sunk stone")
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    sim = sx.Simulation(b.finalize(), dt=1e-3)
    with pytest.raises(OverlapError, match=r"'sunk stone' and 'ground' overlap by 0\.003 m"):
        sim.initial_state()
