"""Unit and property tests of contact detection: broad phase, narrow phase, contact identity."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import saxum as sx
from saxum.bodies.rigid2d import world_geometry
from saxum.contacts import Contacts
from saxum.detection import DetectionSettings, Detector
from saxum.detection.broadphase import bounding_boxes, grid_pairs, sort_pairs
from saxum.structures import running_bond_wall


def _box(x0, y0, w, h):
    return [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]


def _model(blocks, fixed=()):
    b = sx.ModelBuilder()
    for k, verts in enumerate(blocks):
        kind = sx.BodyKind.FIXED if k in fixed else sx.BodyKind.FREE
        b.add_block(verts, density=1000.0, kind=kind)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    return b.finalize()


def _detect(model, q=None, alert=0.01):
    det = Detector(model, DetectionSettings(alert=alert))
    contacts = Contacts()
    det.detect(model.body_q0 if q is None else q, contacts)
    return contacts


def test_face_to_face_gives_two_points_at_the_ends_of_the_common_segment():
    # upper block overhangs: the common segment of the two faces is x in [0.5, 1.0]
    model = _model([_box(0, 0, 1.0, 0.5), _box(0.5, 0.5, 1.0, 0.5)], fixed=(0,))
    c = _detect(model)
    assert c.count == 2
    xs = sorted(c.point[: c.count, 0])
    assert xs == pytest.approx([0.5, 1.0], abs=1e-12)
    assert np.allclose(c.gap[: c.count], 0.0, atol=1e-12)
    # frame on the antagonist: n is the antagonist's outward face normal towards the candidate
    for a in range(c.count):
        n = c.frame[a, 1]
        t = c.frame[a, 0]
        assert t[0] * n[1] - t[1] * n[0] == pytest.approx(1.0)  # (t, n) right-handed
        centre_c = model.body_q0[c.candidate[a], :2]
        centre_a = model.body_q0[c.antagonist[a], :2]
        assert np.dot(centre_c - centre_a, n) > 0.0


def test_vertex_against_face_gives_one_point_with_its_gap():
    # a square rotated by 45 degrees whose lowest vertex is 2 mm above a ground face
    s = 0.2 / math.sqrt(2.0)
    diamond = [(0.5, 0.002), (0.5 + s, 0.002 + s), (0.5, 0.002 + 2 * s), (0.5 - s, 0.002 + s)]
    model = _model([_box(0, -0.5, 1.0, 0.5), diamond], fixed=(0,))
    c = _detect(model, alert=0.01)
    assert c.count == 1
    assert c.point[0] == pytest.approx([0.5, 0.002], abs=1e-12)
    assert c.gap[0] == pytest.approx(0.002, abs=1e-12)
    assert _detect(model, alert=0.001).count == 0  # beyond the alert distance


def test_keys_are_increasing_and_stable_under_small_motion():
    model = running_bond_wall(courses=4, bricks=5)
    first = _detect(model, alert=0.002)
    keys = first.key[: first.count]
    assert np.all(np.diff(keys) > 0)
    q = model.body_q0.copy()
    q[1:, 0] += 1e-5 * np.sin(np.arange(model.body_count - 1))
    q[1:, 2] += 1e-6 * np.cos(np.arange(model.body_count - 1))
    moved = _detect(model, q, alert=0.002)
    assert moved.count == first.count
    first.impulse[: first.count] = np.arange(2 * first.count).reshape(-1, 2)
    assert moved.warm_start_from(first) == first.count
    assert np.array_equal(moved.impulse[: moved.count], first.impulse[: first.count])


@given(seed=st.integers(0, 2**32 - 1))
def test_corners_where_four_blocks_meet_keep_their_contacts_under_round_off(seed):
    """Stack bond: four bricks meet at a corner, where the diagonal pairs touch vertex to
    vertex and two faces of each separate equally. Within the closed gap the first face is
    the reference (saxum.detection.polygons), so that round-off of the positions (here
    perturbations of 1e-15 m and 1e-15 rad) does not turn the contacts' normals nor drop the
    contacts at the ends of faces: the same keys and frames as unperturbed."""
    model = sx.structures.wall(courses=3, bricks=2, bond="stack")
    first = _detect(model, alert=0.002)
    rng = np.random.default_rng(seed)
    q = model.body_q0 + 1e-15 * rng.uniform(-1.0, 1.0, model.body_q0.shape)
    moved = _detect(model, q, alert=0.002)
    assert moved.count == first.count
    assert np.array_equal(moved.key[: moved.count], first.key[: first.count])
    assert np.allclose(moved.frame[: moved.count], first.frame[: first.count], atol=1e-12)


def _brute_pairs(lo, hi, mobile):
    n = len(lo)
    out = set()
    for i in range(n):
        for j in range(i + 1, n):
            if (mobile[i] or mobile[j]) and np.all(lo[i] <= hi[j]) and np.all(lo[j] <= hi[i]):
                out.add((i, j))
    return out


@settings(max_examples=40, deadline=None)
@given(
    centres=st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3)), min_size=2, max_size=40),
    size=st.floats(0.05, 1.0),
    big=st.booleans(),
)
def test_grid_broad_phase_finds_exactly_the_overlapping_boxes(centres, size, big):
    c = np.array(centres)
    lo = c - 0.5 * size
    hi = c + 0.5 * size
    if big:  # one long body (a ground) that the grid treats apart
        lo[0] = (-5.0, -0.2)
        hi[0] = (5.0, 0.0)
    extent = (hi - lo).max(axis=1)
    large = extent > 4.0 * np.median(extent)
    cell = float(extent[~large].max())
    mobile = np.ones(len(c), dtype=bool)
    mobile[0] = not big
    out = np.empty((len(c) ** 2, 2), dtype=np.int32)
    count = grid_pairs(lo, hi, mobile, large, cell, out)
    sort_pairs(out, count, len(c))
    found = [tuple(p) for p in out[:count]]
    assert len(found) == len(set(found))  # each pair once
    assert set(found) == _brute_pairs(lo, hi, mobile)
    assert found == sorted(found)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.integers(1, 300), min_size=1, max_size=6), st.randoms(use_true_random=False))
def test_sort_pairs_orders_few_and_many_partners(partners, rnd):
    """Pairs (i, j) in random order, some bodies i with hundreds of partners j (a ground): the
    Shell sort of each i's j must give the lexicographic order."""
    pairs = [(i, i + 1 + j) for i, k in enumerate(partners) for j in rnd.sample(range(400), k)]
    rnd.shuffle(pairs)
    out = np.array(pairs, dtype=np.int32)
    sort_pairs(out, len(pairs), len(partners))
    assert [tuple(p) for p in out] == sorted(pairs)


def test_broad_phase_reports_overflow_instead_of_writing_past_the_end():
    model = running_bond_wall(courses=3, bricks=4)
    wv = np.empty_like(model.vertex_local)
    world_geometry(model.body_q0, model.body_vertex_start, model.vertex_local,
                   model.edge_normal_local, wv, np.empty_like(wv))
    lo = np.empty((model.body_count, 2))
    hi = np.empty((model.body_count, 2))
    bounding_boxes(wv, model.body_vertex_start, 0.001, lo, hi)
    mobile = model.body_kind == sx.BodyKind.FREE
    large = np.zeros(model.body_count, dtype=bool)
    large[0] = True
    small = np.empty((2, 2), dtype=np.int32)
    needed = grid_pairs(lo, hi, mobile, large, 0.3, small)
    assert needed > 2
    big = np.empty((needed, 2), dtype=np.int32)
    assert grid_pairs(lo, hi, mobile, large, 0.3, big) == needed


def test_broad_phase_refreshes_when_a_body_moves_more_than_half_the_margin():
    model = _model([_box(0, 0, 1, 1), _box(3, 0, 1, 1)])
    det = Detector(model, DetectionSettings(alert=0.01, margin=0.1, refresh_every=1000))
    contacts = Contacts()
    det.detect(model.body_q0, contacts)
    assert det.refresh_count == 1 and contacts.count == 0
    q = model.body_q0.copy()
    q[1, 0] -= 0.04  # within margin / 2: no refresh needed
    det.detect(q, contacts)
    assert det.refresh_count == 1
    q[1, 0] = model.body_q0[1, 0] - 1.995  # now touching: must be found
    det.detect(q, contacts)
    assert det.refresh_count == 2
    assert contacts.count == 2


@pytest.mark.parametrize("case", ["collapsing arch", "wall at rest"])
def test_kept_choice_of_faces_gives_the_contacts_of_the_full_test(case):
    """Between broad phases the narrow phase keeps each pair's choice of faces while the
    motion since stays within what could change it (saxum.detection.polygons): at every
    step its contacts must be those of the full separating-axis test on the same pairs."""
    if case == "collapsing arch":  # voussoirs turning and sliding: choices change and expire
        model = sx.structures.semicircular_arch(radius=1.0, thickness=0.09, voussoirs=15)
        steps = 400
    else:
        model = running_bond_wall(courses=4, bricks=3)
        steps = 40
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    det = sim.detector
    twin = Detector(model)
    kept = []

    def detect_and_compare(q, contacts):
        saved = det.checkpoint()
        Detector.detect(det, q, contacts)
        kept.append(det.kept_faces)
        twin.restore(saved)  # the same pairs, no kept choice: the full test on every pair
        full = Contacts()
        twin.detect(q, full)
        assert twin.kept_faces == 0
        assert full.count == contacts.count
        for name in ("candidate", "antagonist", "key", "law"):  # the same contacts, exactly
            assert np.array_equal(getattr(full, name)[: full.count],
                                  getattr(contacts, name)[: contacts.count])
        # and the same geometry to round-off (two code paths): points and gaps are a few
        # operations on coordinates of a few metres (~1e-15 m), frames unit vectors: 1e-12
        for name in ("point", "frame", "gap"):
            assert np.allclose(getattr(full, name)[: full.count],
                               getattr(contacts, name)[: contacts.count], rtol=0, atol=1e-12)

    det.detect = detect_and_compare
    sim.run(state, steps * sim.integrator.dt)
    assert det.refresh_count > 1
    if case == "collapsing arch":  # kept for some pairs, not for all
        assert np.ptp(state.body_q[1:, 2]) > 0.1
        assert 0 < sum(kept) < 0.5 * det.pair_count * steps
    else:  # kept for nearly every pair between broad phases
        assert sum(kept) > 0.8 * det.pair_count * steps
