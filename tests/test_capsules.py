"""Capsules (2D stadiums, saxum.ModelBuilder.add_capsule): mass properties, bad input, the
contacts with polygons, discs and capsules, drawing, and the places that refuse them."""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.geometry2d import polygon_properties
from saxum.mechanism import round_pairs
from saxum.model import drawn_outlines


def _finalize(builder, friction=0.5):
    law = sx.ContactLaw(friction=friction)
    for group in builder.groups:
        builder.set_law("block", group, law)
    return builder.finalize()


def _stadium(length, radius, sides=20000):
    """A polygon inscribed in the stadium, its ends halves of a regular polygon."""
    turn = np.linspace(-0.5 * np.pi, 0.5 * np.pi, sides // 2 + 1)
    arc = radius * np.column_stack((np.cos(turn), np.sin(turn)))
    return np.concatenate((arc + (0.5 * length, 0.0), -arc - (0.5 * length, 0.0)))


def test_capsule_mass_properties_match_a_fine_polygon():
    # independent check of the parallel-axis formula: the polygon inscribed in the stadium
    # with 10000 sides per end converges as 1/sides^2 (relative error ~1e-7 here), 1e-6
    length, radius = 0.4, 0.05
    area, polar = sx.capsule_properties(length, radius)
    props = polygon_properties(_stadium(length, radius))
    assert area == pytest.approx(props.area, rel=1e-6)
    assert polar == pytest.approx(props.polar_moment, rel=1e-6)
    b = sx.ModelBuilder()
    c = b.add_capsule((1.0, 2.0), length, radius, angle=0.7, density=2000.0)
    m = _finalize(b)
    assert m.body_mass[c] == pytest.approx(2000.0 * area, rel=1e-14)
    assert m.body_inertia[c] == pytest.approx(2000.0 * polar, rel=1e-14)
    assert m.body_q0[c] == pytest.approx([1.0, 2.0, 0.0], abs=1e-14)
    assert m.body_shape[c] == sx.Shape.CAPSULE and m.has_round
    assert m.body_size[c] == pytest.approx(math.sqrt(area), rel=1e-14)


@pytest.mark.parametrize(("length", "radius", "what"), [
    (0.0, 0.1, "length"), (-1.0, 0.1, "length"), (math.nan, 0.1, "length"),
    (0.3, 0.0, "radius"), (0.3, -0.1, "radius"), (0.3, math.inf, "radius")])
def test_bad_capsule_sizes_are_named(length, radius, what):
    with pytest.raises(sx.InputError, match=rf"rod: the capsule's {what} must be a finite "
                       r"length > 0 \[m\]"):
        sx.ModelBuilder().add_capsule((0.0, 0.0), length, radius, density=2000.0, name="rod")


def test_capsule_orientation_of_the_other_dimension_is_refused():
    with pytest.raises(sx.InputError, match="rod: angle is for 2D capsules"):
        sx.ModelBuilder(dim=3).add_capsule((0.0, 0.0, 0.0), 0.3, 0.1, angle=0.5,
                                           density=2000.0, name="rod")
    with pytest.raises(sx.InputError, match="rod: axis is for 3D capsules"):
        sx.ModelBuilder().add_capsule((0.0, 0.0), 0.3, 0.1, axis=(1.0, 0.0, 0.0),
                                      density=2000.0, name="rod")
    with pytest.raises(sx.InputError, match="rod: the centre must be 3 finite coordinates"):
        sx.ModelBuilder(dim=3).add_capsule((0.0, 0.0), 0.3, 0.1, density=2000.0, name="rod")


def _contacts(model):
    detector = sx.Simulation(model, dt=1e-3, detection=sx.DetectionSettings(alert=0.02)
                             ).detector
    c = detector.contacts_at(model.body_q0)
    assert np.all(np.diff(c.key[: c.count]) > 0)  # the warm start's merge needs this
    return c


def test_capsule_on_a_corner_and_against_a_disc_and_a_capsule():
    # distances by Pythagoras; the capsule `rod` is 0.4 long, ends of radius 0.05, along x
    b = sx.ModelBuilder()
    b.add_block([(-0.05, -0.2), (0.05, -0.2), (0.05, 0.0), (-0.05, 0.0)],
                kind=sx.BodyKind.FIXED, group="ground", name="post")
    rod = b.add_capsule((0.02, 0.055), 0.4, 0.05, density=2000.0, name="rod")
    disc = b.add_disc((0.3, 0.055 + 0.008), 0.05, density=2000.0, name="disc")
    # a capsule across the rod, its lower end 0.004 above the rod's side
    cross = b.add_capsule((-0.1, 0.055 + 0.1 + 0.15 + 0.004), 0.3, 0.05, angle=0.5 * math.pi,
                          density=2000.0, name="cross")
    model = _finalize(b)
    c = _contacts(model)
    found = {}
    for k in range(c.count):
        found.setdefault((int(c.candidate[k]), int(c.antagonist[k])), []).append(k)
    # the post's two top corners under the rod's flat side: gap 0.005, normal up
    on_post = found[(rod, 0)]
    assert sorted(c.point[on_post, 0]) == pytest.approx([-0.05, 0.05], abs=1e-12)
    assert c.gap[on_post] == pytest.approx([0.005, 0.005], abs=1e-12)
    assert c.frame[on_post, 1].ravel() == pytest.approx([0.0, 1.0] * 2, abs=1e-12)
    assert c.area[on_post] == pytest.approx([0.0, 0.0])  # vertices: no face
    # the disc against the rod's right end circle (centre x = 0.22): sqrt(0.08^2 + 0.008^2)
    (k,) = found[(rod, disc)]
    assert c.gap[k] == pytest.approx(math.hypot(0.08, 0.008) - 0.1, abs=1e-12)
    # the crossing capsule's lower end on the rod's side, straight above: gap 0.004
    (k,) = found[(cross, rod)]
    assert c.gap[k] == pytest.approx(0.004, abs=1e-12)
    assert c.frame[k, 1] == pytest.approx([0.0, 1.0], abs=1e-12)
    assert c.point[k] == pytest.approx([-0.1, 0.055 + 0.05 + 0.004], abs=1e-12)


def test_capsules_lying_side_by_side_touch_at_two_points():
    b = sx.ModelBuilder()
    low = b.add_capsule((0.0, 0.0), 0.4, 0.05, kind=sx.BodyKind.FIXED, group="ground")
    high = b.add_capsule((0.1, 0.103), 0.4, 0.05, density=2000.0)
    c = _contacts(_finalize(b))
    assert c.count == 2
    assert sorted(c.point[: c.count, 0]) == pytest.approx([-0.1, 0.2], abs=1e-12)
    assert c.gap[: c.count] == pytest.approx([0.003, 0.003], abs=1e-12)
    assert {int(x) for x in c.candidate[: c.count]} | {int(x) for x in c.antagonist[: 2]} == {
        low, high}


def test_capsule_is_drawn_as_its_stadium_and_its_contacts_are_no_hinges():
    b = sx.ModelBuilder()
    b.add_plane((0.0, 0.0), (0.0, 1.0), 1.0, name="plane")
    rod = b.add_capsule((0.0, 0.05), 0.4, 0.05, angle=0.3, density=2000.0)
    m = _finalize(b)
    start, local = drawn_outlines(m.body_vertex_start, m.vertex_local, m.body_round_radius,
                                  shape=m.body_shape)
    ring = local[start[rod]:start[rod + 1]]
    # every drawn point lies on the stadium: at r from the segment
    t = np.array([math.cos(0.3), math.sin(0.3)])
    u = np.clip(ring @ t, -0.2, 0.2)
    assert np.hypot(*(ring - u[:, None] * t).T) == pytest.approx(0.05, abs=1e-12)
    assert polygon_properties(ring).area > 0.0  # counter-clockwise
    assert round_pairs(m.body_shape, np.array([rod]), np.array([0])).all()


def test_capsules_that_meet_capsules_are_refused_by_lmgc90_export_and_csv(tmp_path):
    b = sx.ModelBuilder()
    b.add_capsule((0.0, 0.0), 0.4, 0.05, density=2000.0, name="rod")
    m = _finalize(b)
    with pytest.raises(sx.InputError, match="LMGC90 has no JONCx-JONCx contact"):
        sx.export_lmgc90(m, tmp_path / "out")
    from saxum.structures.blockfile import write_blocks
    with pytest.raises(sx.InputError, match="block 'rod' is a capsule; CSV"):
        write_blocks(tmp_path / "b.csv", m)


def _pile(dim):
    """Capsules and a disc (3D: capsules, a sphere and a slab) falling on a plane."""
    b = sx.ModelBuilder(dim=dim)
    if dim == 2:
        b.add_plane((0.0, 0.0), (0.0, 1.0), 1.0, name="plane")
        b.add_capsule((0.0, 0.2), 0.3, 0.05, angle=0.4, density=2000.0)
        b.add_capsule((0.05, 0.4), 0.3, 0.05, angle=-0.3, density=2000.0)
        b.add_disc((-0.1, 0.55), 0.05, density=2000.0)
        return _finalize(b)
    b.add_plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0), name="plane")
    b.add_capsule((0.0, 0.0, 0.1), 0.3, 0.05, axis=(1.0, 0.2, 0.1), density=2000.0)
    b.add_capsule((0.05, 0.0, 0.25), 0.3, 0.05, axis=(0.1, 1.0, -0.2), density=2000.0)
    b.add_sphere((-0.1, 0.05, 0.4), 0.05, density=2000.0)
    b.add_block([(x, y, z) for x in (-0.15, 0.15) for y in (-0.1, 0.1) for z in (0.5, 0.55)],
                density=2000.0)
    return _finalize(b)


@pytest.mark.parametrize("dim", [2, 3])
def test_capsule_run_is_deterministic(dim):
    m = _pile(dim)
    runs = []
    for _ in range(2):
        sim = sx.Simulation(m, dt=1e-3)
        state = sim.initial_state()
        sim.run(state, 0.2)
        runs.append(state.body_q.copy())
    assert np.array_equal(runs[0], runs[1])
    gaps = sim.detector.contacts_at(runs[0]).gap
    # the gap-based law projects a contact once deeper than `interpenetration` at the start
    # of a step, so that step's drift on curved surfaces, |U_t|^2 h^2 / (2 R), can overshoot
    # it: ~4e-7 m per step for the 3D capsules crossing here (1.68e-6 m at 0.2 s against
    # 1.61e-6), less than a second `interpenetration`
    limit = sim.detector.interpenetration * (2.0 if dim == 3 else 1.0)
    assert gaps.min() > -limit
