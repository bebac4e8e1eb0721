"""Discs and spheres: mass properties, detection against polygons, polyhedra and each other,
bad input, the granular fill, and what a polygon-only model keeps."""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.structures import add_granular_box, add_granular_fill


def _two_groups(builder, friction=0.5):
    law = sx.ContactLaw(friction=friction)
    for pair in (("block", "ground"), ("block", "block")):
        builder.set_law(*pair, law)
    return builder.finalize()


def test_disc_and_sphere_mass_properties():
    # closed forms: disc m = rho pi r^2, J = m r^2 / 2; sphere m = rho 4/3 pi r^3, J = 2/5 m r^2
    b = sx.ModelBuilder()
    d = b.add_disc((1.0, 2.0), 0.3, density=2000.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    m2 = b.finalize()
    mass = 2000.0 * math.pi * 0.09
    assert m2.body_mass[d] == pytest.approx(mass, rel=1e-14)
    assert m2.body_inertia[d] == pytest.approx(0.5 * mass * 0.09, rel=1e-14)
    assert m2.body_q0[d] == pytest.approx([1.0, 2.0, 0.0], abs=1e-15)
    assert m2.body_shape[d] == sx.Shape.ROUND
    assert m2.body_round_radius[d] == pytest.approx(0.3, rel=1e-15)  # stored as given
    b3 = sx.ModelBuilder(dim=3)
    s = b3.add_sphere((1.0, 2.0, 3.0), 0.3, density=2000.0)
    b3.set_law("block", "block", sx.ContactLaw(friction=0.5))
    m3 = b3.finalize()
    mass = 2000.0 * 4.0 / 3.0 * math.pi * 0.027
    assert m3.body_mass[s] == pytest.approx(mass, rel=1e-14)
    assert m3.body_inertia[s] == pytest.approx([0.4 * mass * 0.09] * 3, rel=1e-14)
    assert m3.body_q0[s] == pytest.approx([1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0], abs=1e-15)


def test_polygon_only_model_has_no_round_bodies():
    b = sx.ModelBuilder()
    b.add_block([(0, 0), (1, 0), (1, 1), (0, 1)], density=2000.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    m = b.finalize()
    assert not m.has_round and not m.body_shape.any()


@pytest.mark.parametrize("radius", [0.0, -0.1, math.nan, math.inf])
def test_bad_radius_is_named(radius):
    b = sx.ModelBuilder()
    with pytest.raises(sx.InputError, match=r"pebble: the radius must be a finite length > 0"):
        b.add_disc((0.0, 0.0), radius, density=2000.0, name="pebble")


def test_disc_in_3d_and_sphere_in_2d_are_refused():
    with pytest.raises(sx.InputError, match="add_disc is for 2D models.*use add_sphere"):
        sx.ModelBuilder(dim=3).add_disc((0.0, 0.0), 0.1, density=2000.0)
    with pytest.raises(sx.InputError, match="add_sphere is for 3D models.*use add_disc"):
        sx.ModelBuilder().add_sphere((0.0, 0.0, 0.0), 0.1, density=2000.0)
    with pytest.raises(sx.InputError, match="centre must be 2 finite coordinates"):
        sx.ModelBuilder().add_disc((0.0, math.nan), 0.1, density=2000.0)


def test_overlapping_discs_at_start_are_named():
    b = sx.ModelBuilder()
    b.add_block([(-1, -0.1), (1, -0.1), (1, 0), (-1, 0)], kind=sx.BodyKind.FIXED,
                group="ground", name="ground")
    b.add_disc((0.0, 0.1), 0.1, density=2000.0, name="left")
    b.add_disc((0.15, 0.1), 0.1, density=2000.0, name="right")
    model = _two_groups(b)
    with pytest.raises(sx.OverlapError, match=r"'left' and 'right' overlap by 0.05 m"):
        sx.Simulation(model, dt=1e-3).initial_state()


def test_deformable_disc_is_refused():
    b = sx.ModelBuilder()
    b.add_disc((0.0, 0.1), 0.1, density=2000.0, name="pebble")
    with pytest.raises(sx.InputError, match="'pebble', which cannot be deformable"):
        b.set_material("block", sx.Elastic(E=1e9, nu=0.2, density=2000.0))


def test_disc_against_polygon_face_vertex_and_disc():
    # a unit square at the origin; distances by Pythagoras
    b = sx.ModelBuilder()
    b.add_block([(0, 0), (1, 0), (1, 1), (0, 1)], kind=sx.BodyKind.FIXED, group="ground",
                name="square")
    face = b.add_disc((0.5, 1.105), 0.1, density=2000.0, name="face")
    corner = b.add_disc((1.0 + 0.11 / math.sqrt(2), 1.0 + 0.11 / math.sqrt(2)), 0.1,
                        density=2000.0, name="corner")
    pair = b.add_disc((0.5, 1.31), 0.1, density=2000.0, name="on top")
    model = _two_groups(b)
    detector = sx.Simulation(model, dt=1e-3, detection=sx.DetectionSettings(alert=0.02)
                             ).detector
    c = detector.contacts_at(model.body_q0)
    found = {(int(c.candidate[k]), int(c.antagonist[k])): k for k in range(c.count)}
    k = found[(face, 0)]
    assert c.gap[k] == pytest.approx(0.005, abs=1e-12)
    assert c.frame[k, 1] == pytest.approx([0.0, 1.0], abs=1e-15)
    assert c.point[k] == pytest.approx([0.5, 1.005], abs=1e-12)
    k = found[(corner, 0)]
    assert c.gap[k] == pytest.approx(0.01, abs=1e-12)
    assert c.frame[k, 1] == pytest.approx([1 / math.sqrt(2)] * 2, abs=1e-12)
    assert c.area[k] == pytest.approx(0.0, abs=1e-15)  # a vertex: no face within alert
    k = found[(face, pair)]
    assert c.gap[k] == pytest.approx(0.005, abs=1e-12)
    assert c.frame[k, 1] == pytest.approx([0.0, -1.0], abs=1e-15)
    assert np.all(np.diff(c.key[: c.count]) > 0)  # the warm start's merge needs this


def test_sphere_against_polyhedron_face_edge_vertex_and_sphere():
    b = sx.ModelBuilder(dim=3)
    cube = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    b.add_block(cube, kind=sx.BodyKind.FIXED, group="ground", name="cube")
    r, g = 0.1, 0.005
    face = b.add_sphere((0.5, 0.5, 1 + r + g), r, density=2000.0)
    edge = b.add_sphere((0.5, 1 + (r + g) / math.sqrt(2), 1 + (r + g) / math.sqrt(2)), r,
                        density=2000.0)
    vertex = b.add_sphere(np.array([1.0, 1.0, 1.0]) + (r + g) / math.sqrt(3), r,
                          density=2000.0)
    top = b.add_sphere((0.5, 0.5, 1 + 3 * r + 2 * g), r, density=2000.0)
    model = _two_groups(b)
    detector = sx.Simulation(model, dt=1e-3, detection=sx.DetectionSettings(alert=0.02)
                             ).detector
    c = detector.contacts_at(model.body_q0)
    found = {(int(c.candidate[k]), int(c.antagonist[k])): k for k in range(c.count)}
    normals = {face: [0, 0, 1], edge: [0, 1 / math.sqrt(2), 1 / math.sqrt(2)],
               vertex: [1 / math.sqrt(3)] * 3}
    for body, normal in normals.items():
        k = found[(body, 0)]
        assert c.gap[k] == pytest.approx(g, abs=1e-12)
        assert c.frame[k, 1] == pytest.approx(normal, abs=1e-12)
        assert np.linalg.det(c.frame[k]) == pytest.approx(1.0, abs=1e-12)  # right-handed
    k = found[(face, top)]
    assert c.gap[k] == pytest.approx(g, abs=1e-12)
    assert c.frame[k, 1] == pytest.approx([0, 0, -1], abs=1e-15)


def _fill(seed):
    """A box of 30 discs with their laws: (builder, assembly)."""
    b = sx.ModelBuilder()
    asm = add_granular_box(b, 0.3, 0.4, radius=(0.015, 0.025), count=30, seed=seed)
    law = sx.ContactLaw(friction=0.5)
    b.set_law("grain", "grain", law)
    b.set_law("grain", "container", law)
    return b, asm


def test_granular_fill_is_seeded_and_without_overlaps():
    b, asm = _fill(seed=4)
    model = b.finalize()
    assert len(asm["grains"]) == 30
    r = model.body_round_radius[asm["grains"]]
    assert r.min() >= 0.015 and r.max() <= 0.025
    sx.Simulation(model, dt=1e-3).detector.check_overlaps(model.body_q0, tolerance=0.0)
    again, _ = _fill(seed=4)
    other, _ = _fill(seed=5)
    q = [np.array([blk.vertices.mean(axis=0) for blk in x._blocks]) for x in (b, again, other)]
    assert np.array_equal(q[0], q[1]) and not np.array_equal(q[0], q[2])


def test_granular_fill_that_cannot_fit_says_so():
    with pytest.raises(sx.InputError, match="placed .* of 500 grains"):
        add_granular_fill(sx.ModelBuilder(), (0, 0), (0.2, 0.2), radius=(0.02, 0.02),
                          count=500, attempts=5)


def test_granular_scenario_runs_and_plots(tmp_path):
    text = """
[structure]
type = "granular_box"
width = 0.2
height = 0.2
radius_min = 0.02
radius_max = 0.03
count = 6
seed = 2

[[laws]]
groups = ["*", "*"]
friction = 0.5

[output]
duration = 0.02
"""
    path = tmp_path / "fill.toml"
    path.write_text(text)
    sx.run_scenario(sx.load_scenario(path), tmp_path / "fill.h5", quiet=True)
    with sx.Results(tmp_path / "fill.h5") as res:
        assert np.count_nonzero(res.model["body_round_radius"]) == 6
        from saxum.plot import plot_frame
        plot_frame(res, path=tmp_path / "fill.png")
    assert (tmp_path / "fill.png").stat().st_size > 0


def test_round_pairs_survive_a_checkpoint_bit_for_bit():
    b, _ = _fill(seed=1)
    model = b.finalize()
    whole = sx.Simulation(model, dt=1e-3)
    state = whole.initial_state()
    whole.run(state, 0.1)
    whole.run(state, 0.05)
    first = sx.Simulation(model, dt=1e-3)
    half = first.initial_state()
    first.run(half, 0.1)
    second = sx.Simulation(model, dt=1e-3)
    second.detector.restore(first.detector.checkpoint())
    second.solver.restore(first.solver.checkpoint())  # (the refinement, the loads followed)
    half = half.copy()
    second.run(half, 0.05)
    assert np.array_equal(state.body_q, half.body_q)


@pytest.mark.parametrize("dim", [2, 3])
def test_discs_and_spheres_round_trip_through_a_json_block_file(tmp_path, dim):
    from saxum.structures import add_blocks_from_file, write_blocks
    b = sx.ModelBuilder(dim=dim)
    corners = [(0, 0), (1, 0), (1, 0.1), (0, 0.1)] if dim == 2 else [
        (x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 0.1)]
    b.add_block(corners, kind=sx.BodyKind.FIXED, group="ground", name="ground")
    add = b.add_disc if dim == 2 else b.add_sphere
    add((0.5,) * (dim - 1) + (0.3,), 0.2, density=2500.0, name="pebble")
    model = _two_groups(b)
    write_blocks(tmp_path / "blocks.json", model)
    again = sx.ModelBuilder(dim=dim)
    add_blocks_from_file(again, tmp_path / "blocks.json")
    read = _two_groups(again)
    assert read.body_round_radius.tolist() == [0.0, 0.2]
    assert np.array_equal(read.body_q0, model.body_q0)
    assert np.array_equal(read.body_mass, model.body_mass)
    with pytest.raises(sx.InputError, match="'pebble' is a disc .* write JSON"):
        write_blocks(tmp_path / "blocks.csv", model)


def test_json_disc_without_a_positive_radius_is_named(tmp_path):
    from saxum.structures import read_blocks
    path = tmp_path / "bad.json"
    path.write_text('{"blocks": [{"centre": [0, 0], "radius": -1, "density": 2000}]}')
    with pytest.raises(sx.InputError, match=r"blocks\[0\]: a disc \(sphere\) needs a radius > 0"):
        read_blocks(path)


@pytest.mark.parametrize("dim", [2, 3])
def test_plane_face_passes_through_its_point_with_its_normal(dim):
    b = sx.ModelBuilder(dim=dim)
    normal = np.array([0.3, 1.0] if dim == 2 else [0.3, -0.2, 1.0])
    point = np.array([0.5, -0.2] if dim == 2 else [0.5, 0.1, -0.2])
    b.add_plane(point, normal, 2.0 if dim == 2 else (2.0, 1.5), name="ground")
    n = normal / np.linalg.norm(normal)
    add = b.add_disc if dim == 2 else b.add_sphere
    ball = add(point + 0.105 * n, 0.1, density=2000.0)
    model = _two_groups(b)
    c = sx.Simulation(model, dt=1e-3, detection=sx.DetectionSettings(alert=0.02)
                      ).detector.contacts_at(model.body_q0)
    assert c.count == 1 and c.candidate[0] == ball
    assert c.gap[0] == pytest.approx(0.005, abs=1e-12)
    assert c.frame[0, 1] == pytest.approx(n, abs=1e-12)


def test_bad_plane_is_named():
    b = sx.ModelBuilder()
    with pytest.raises(sx.InputError, match="floor: a plane needs a point and a non-zero"):
        b.add_plane((0, 0), (0, 0), 1.0, name="floor")
    with pytest.raises(sx.InputError, match="floor: half_size must be 1 length"):
        b.add_plane((0, 0), (0, 1), -1.0, name="floor")
    with pytest.raises(sx.InputError, match="floor: a plane is a support"):
        b.add_plane((0, 0), (0, 1), 1.0, name="floor", kind=sx.BodyKind.FREE)


def test_flood_refuses_discs():
    b = sx.ModelBuilder()
    b.add_plane((0, 0), (0, 1), 2.0, name="ground")
    b.add_disc((0.0, 0.1), 0.1, density=2000.0)
    b.add_field_load(sx.FloodLoad(level=1.0))
    law = sx.ContactLaw(friction=0.5)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    with pytest.raises(sx.InputError, match="discs .* which a flood does not load yet"):
        b.finalize()


def test_spheres_are_drawn_as_closed_outward_polyhedra_inscribed_in_them():
    from saxum.model import drawn_polyhedra
    b = sx.ModelBuilder(dim=3)
    b.add_plane((0, 0, 0), (0, 0, 1), (1.0, 1.0), name="ground")
    b.add_sphere((0.0, 0.0, 0.2), 0.2, density=2000.0)
    model = _two_groups(b)
    g = drawn_polyhedra({k: getattr(model, k) for k in (
        "body_vertex_start", "vertex_local", "body_face_start", "face_vertex_start",
        "face_vertex", "body_round_radius")})
    assert np.array_equal(g["vertex_local"][:8], model.vertex_local[:8])  # the plane as is
    sphere = g["vertex_local"][g["body_vertex_start"][1]:]
    assert np.linalg.norm(sphere, axis=1) == pytest.approx(0.2, rel=1e-15)
    # divergence theorem: faces outward and closed give a positive volume, less than the
    # sphere's (inscribed)
    volume = 0.0
    fvs, fv = g["face_vertex_start"], g["face_vertex"]
    for f in range(g["body_face_start"][1], g["body_face_start"][2]):
        ring = g["vertex_local"][fv[fvs[f]:fvs[f + 1]]]
        for k in range(1, len(ring) - 1):
            volume += np.dot(ring[0], np.cross(ring[k], ring[k + 1])) / 6.0
    assert 0.9 * 4 / 3 * math.pi * 0.008 < volume < 4 / 3 * math.pi * 0.008


def test_discs_with_deformable_blocks_are_refused():
    b = sx.ModelBuilder()
    b.add_plane((0, 0), (0, 1), 2.0, name="ground")
    b.add_block([(0, 0), (0.2, 0), (0.2, 0.2), (0, 0.2)], name="soft",
                material=sx.Elastic(E=1e9, nu=0.2, density=2000.0))
    b.add_disc((0.5, 0.1), 0.1, density=2000.0)
    model = _two_groups(b)
    with pytest.raises(sx.InputError, match="discs .spheres. and deformable blocks in one model"):
        sx.Simulation(model, dt=1e-3)
