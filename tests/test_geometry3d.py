"""Solid geometry of convex polyhedra (saxum.geometry3d): hull, faces, mass properties.

References: box and canonical tetrahedron in closed form; the tetrahedron of F. Tonon,
"Explicit exact formulas for the 3-D tetrahedron inertia tensor in terms of its vertex
coordinates", J. Math. Stat. 1(1), 2005, 8-11 (published inertia integrals, density 1).
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

import saxum as sx
from saxum.errors import InputError
from saxum.geometry3d import (
    convex_polyhedron,
    polyhedron_properties,
    quaternion_from_matrix,
    rotation_matrix,
)


def _box(a, b, c, origin=(0.0, 0.0, 0.0)):
    return np.array([(x, y, z) for x in (0.0, a) for y in (0.0, b) for z in (0.0, c)]) + origin


def _tensor(props):
    """Inertia tensor per unit density about the centroid, world axes [m^5]."""
    return props.axes @ np.diag(props.moments) @ props.axes.T


def test_box_faces_edges_and_orientation():
    poly = convex_polyhedron(_box(0.4, 0.3, 0.2))
    assert len(poly.vertices) == 8
    assert [len(f) for f in poly.faces] == [4] * 6
    assert len(poly.edges) == 12
    for ring, n in zip(poly.faces, poly.normals, strict=True):
        p = poly.vertices[ring]
        # counter-clockwise seen from outside, normal outward (away from the centre)
        assert np.cross(p[1] - p[0], p[2] - p[1]) @ n > 0.0
        assert (p.mean(axis=0) - poly.vertices.mean(axis=0)) @ n > 0.0
    for (u, v), (left, right) in zip(poly.edges, poly.edge_faces, strict=True):
        ring_l, ring_r = list(poly.faces[left]), list(poly.faces[right])
        k = ring_l.index(u)
        assert ring_l[(k + 1) % 4] == v  # u -> v runs along the left face
        k = ring_r.index(v)
        assert ring_r[(k + 1) % 4] == u  # and back along the right one


def test_box_mass_properties_closed_form():
    a, b, c = 0.4, 0.3, 0.2
    props = polyhedron_properties(convex_polyhedron(_box(a, b, c, (1.0, -2.0, 3.0))))
    v = a * b * c
    assert props.volume == pytest.approx(v, rel=1e-13)
    assert props.centroid == pytest.approx([1.0 + a / 2, -2.0 + b / 2, 3.0 + c / 2], rel=1e-13)
    # J = V/12 (b^2 + c^2, a^2 + c^2, a^2 + b^2), axis-aligned: body axes = world axes
    assert props.moments == pytest.approx(v / 12 * np.array([b * b + c * c, a * a + c * c,
                                                             a * a + b * b]), rel=1e-12)
    assert np.array_equal(props.axes, np.eye(3))


def test_canonical_tetrahedron_closed_form():
    """(0,0,0), (1,0,0), (0,1,0), (0,0,1): V = 1/6, centroid (1/4,1/4,1/4), covariance about
    the origin (2 on the diagonal, 1 off it)/120, so about the centroid the inertia tensor is
    1/80 on the diagonal and 1/480 off it: principal moments 1/96, 1/96, 1/60."""
    props = polyhedron_properties(convex_polyhedron(np.vstack(([0.0, 0, 0], np.eye(3)))))
    assert props.volume == pytest.approx(1 / 6, rel=1e-14)
    assert props.centroid == pytest.approx([0.25] * 3, rel=1e-14)
    assert np.sort(props.moments) == pytest.approx([1 / 96, 1 / 96, 1 / 60], rel=1e-12)
    tensor = _tensor(props)
    assert np.diag(tensor) == pytest.approx([1 / 80] * 3, rel=1e-12)
    assert tensor[0, 1] == pytest.approx(1 / 480, rel=1e-11)
    # the largest moment is about the symmetry axis (1, 1, 1)
    axis = props.axes[:, int(np.argmax(props.moments))]
    assert abs(axis @ np.ones(3)) / math.sqrt(3) == pytest.approx(1.0, abs=1e-12)


def test_tonon_tetrahedron():
    """Tonon (2005), example: a = int (y^2 + z^2) dV = 43520.33257, b = 194711.28938,
    c = 191168.76173, a' = int yz = 4417.66150, b' = int xz = -46343.16662,
    c' = int xy = 11996.20119 about the centroid (the vertices are given to 5 decimals, so
    1e-7 relative)."""
    p = [(8.33220, -11.86875, 0.93355), (0.75523, 5.00000, 16.37072),
         (52.61236, 5.00000, -5.38580), (2.00000, 5.00000, 3.00000)]
    j = _tensor(polyhedron_properties(convex_polyhedron(p)))
    assert [j[0, 0], j[1, 1], j[2, 2]] == pytest.approx([43520.33257, 194711.28938,
                                                         191168.76173], rel=1e-7)
    assert [-j[1, 2], -j[0, 2], -j[0, 1]] == pytest.approx([4417.66150, -46343.16662,
                                                           11996.20119], rel=1e-7)


def test_hull_drops_points_on_the_surface_and_merges_coplanar_triangles():
    pts = np.vstack((_box(1.0, 1.0, 1.0), [(0.5, 0.5, 1.0), (0.5, 0.0, 0.0), (0.2, 0.7, 0.0)]))
    poly = convex_polyhedron(pts)
    assert len(poly.vertices) == 8 and len(poly.faces) == 6


@pytest.mark.parametrize(("points", "message"), [
    (_box(1, 1, 1)[:3], "at least 4"),
    ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0.5, 0.5, 0)], "flat"),
    ([(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)], "flat"),
    ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, math.nan)], "NaN"),
    ([(0, 0), (1, 0), (0, 1)], "(x, y, z)"),
    (np.vstack((_box(1, 1, 1), [(0.5, 0.5, 0.5)])), "not convex: vertex 8"),
])
def test_bad_point_sets_are_refused_by_name(points, message):
    with pytest.raises(InputError, match="stone 7") as err:
        convex_polyhedron(points, name="stone 7")
    assert message in str(err.value)


def test_quaternion_round_trip():
    rng = np.random.default_rng(1)
    for _ in range(50):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        q = q if q[0] >= 0 else -q
        r = rotation_matrix(q)
        assert r @ r.T == pytest.approx(np.eye(3), abs=1e-14)
        assert quaternion_from_matrix(r) == pytest.approx(q, abs=1e-13)


def _random_rotation(angles):
    a, b, c = angles
    rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rx = np.array([[1, 0, 0], [0, math.cos(c), -math.sin(c)], [0, math.sin(c), math.cos(c)]])
    return rz @ ry @ rx


points = st.lists(st.tuples(*[st.floats(-1.0, 1.0)] * 3), min_size=12, max_size=30).map(
    lambda p: np.vstack((np.array(p) * [1.0, 0.6, 0.4], _box(0.3, 0.3, 0.3, (-0.1, -0.1, -0.1)))))
angles = st.tuples(*[st.floats(-math.pi, math.pi)] * 3)
shift = st.tuples(*[st.floats(-50.0, 50.0)] * 3)


@settings(max_examples=40)
@given(points, angles, shift)
def test_mass_properties_are_invariant_under_rigid_motions(pts, rot, move):
    """Volume and principal moments do not change under a rotation R and a translation d,
    the centroid moves to R c + d and the inertia tensor becomes R J R^T."""
    pts = pts[ConvexHull(pts).vertices]  # random points: interior ones would be refused
    hull = convex_polyhedron(pts)
    r = _random_rotation(rot)
    base = polyhedron_properties(hull)
    moved = polyhedron_properties(convex_polyhedron(pts @ r.T + move))
    assert moved.volume == pytest.approx(base.volume, rel=1e-10)
    assert moved.centroid == pytest.approx(r @ base.centroid + move, abs=1e-9)
    assert np.sort(moved.moments) == pytest.approx(np.sort(base.moments), rel=1e-8)
    assert _tensor(moved) == pytest.approx(r @ _tensor(base) @ r.T,
                                           abs=1e-8 * base.moments.max())


@settings(max_examples=40)
@given(st.floats(0.1, 2.0), st.floats(0.1, 2.0), st.floats(0.1, 2.0), st.floats(0.1, 0.9),
       angles, shift)
def test_parallel_axis_theorem_over_two_halves(a, b, c, split, rot, move):
    """A box cut in two boxes across its length: volumes add, the centroid is their volume
    average and J_G = sum_k [J_k + V_k (|d_k|^2 1 - d_k d_k^T)], d_k = c_k - c (Steiner)."""
    r = _random_rotation(rot)
    whole = polyhedron_properties(convex_polyhedron(_box(a, b, c) @ r.T + move))
    parts = [polyhedron_properties(convex_polyhedron(_box(split * a, b, c) @ r.T + move)),
             polyhedron_properties(convex_polyhedron(
                 (_box((1 - split) * a, b, c) + [split * a, 0, 0]) @ r.T + move))]
    assert sum(p.volume for p in parts) == pytest.approx(whole.volume, rel=1e-12)
    centre = sum(p.volume * p.centroid for p in parts) / whole.volume
    assert centre == pytest.approx(whole.centroid, abs=1e-10 * (1 + np.abs(move).max()))
    steiner = sum(_tensor(p) + p.volume * ((p.centroid - centre) @ (p.centroid - centre)
                                           * np.eye(3) - np.outer(p.centroid - centre,
                                                                  p.centroid - centre))
                  for p in parts)
    assert steiner == pytest.approx(_tensor(whole), abs=1e-9 * whole.moments.max())


def test_model_3d_arrays():
    b = sx.ModelBuilder(dim=3)
    pts = _box(0.4, 0.3, 0.2) @ _random_rotation((0.3, -0.2, 1.1)).T + (1.0, 2.0, 3.0)
    stone = b.add_block(pts, density=2000.0, name="stone")
    b.add_block(_box(4, 4, 0.2, (-2, -2, -0.2)), kind=sx.BodyKind.FIXED, group="ground")
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    m = b.finalize()
    assert (m.dim, m.dof) == (3, 6)
    assert m.body_q0.shape == (2, 7) and m.body_inv_mass.shape == (2, 6)
    assert m.body_mass[stone] == pytest.approx(2000.0 * 0.024, rel=1e-12)
    assert m.body_inv_mass[stone, :3] == pytest.approx(1.0 / m.body_mass[stone], rel=1e-14)
    assert m.body_inv_mass[stone, 3:] == pytest.approx(1.0 / m.body_inertia[stone], rel=1e-14)
    assert np.all(m.body_inv_mass[1] == 0.0)
    assert m.body_q0[stone, :3] == pytest.approx(pts.mean(axis=0), abs=1e-12)
    # the world vertices at q0 are the points given (in some order)
    world = m.vertices(stone)
    assert np.abs(np.sort(world, axis=0) - np.sort(pts, axis=0)).max() < 1e-12
    assert len(m.body_face_start) == 3 and m.body_face_start[-1] == 12
    assert np.linalg.norm(m.face_normal_local, axis=1) == pytest.approx(np.ones(12), abs=1e-14)
    assert m.body_size[stone] == pytest.approx(0.024 ** (1 / 3), rel=1e-12)
    assert tuple(m.gravity) == (0.0, 0.0, -9.81)


def test_builder_3d_bad_parameters():
    with pytest.raises(InputError, match="dim must be 2 or 3"):
        sx.ModelBuilder(dim=4)
    with pytest.raises(InputError, match=r"gravity must be 3 finite numbers \(gx, gy, gz\)"):
        sx.ModelBuilder(dim=3, gravity=(0.0, -9.81))
    b = sx.ModelBuilder(dim=3)
    with pytest.raises(InputError, match="brick 3: density"):
        b.add_block(_box(1, 1, 1), density=-1.0, name="brick 3")
    with pytest.raises(InputError, match="brick 4: flat"):
        b.add_block(_box(1, 1, 0), density=1.0, name="brick 4")


def test_clip_polyhedron_keeps_the_part_below_a_plane():
    from saxum.geometry3d import clip_polyhedron

    cube = convex_polyhedron([(x, y, z) for x in (0, 1) for y in (0, 2) for z in (0, 1)])
    part = polyhedron_properties(clip_polyhedron(cube, (0.0, 0.0, 1.0), 0.3))
    assert part.volume == pytest.approx(0.6) and part.centroid == pytest.approx([0.5, 1, 0.15])
    # a slanted plane through the diagonal x + z = 1 halves the cube
    half = clip_polyhedron(cube, np.array([1.0, 0.0, 1.0]) / np.sqrt(2), 1 / np.sqrt(2))
    assert polyhedron_properties(half).volume == pytest.approx(1.0)
    assert clip_polyhedron(cube, (0.0, 0.0, 1.0), -0.1) is None  # all above
    assert clip_polyhedron(cube, (0.0, 0.0, 1.0), 0.0) is None  # a face only: flat
    whole = clip_polyhedron(cube, (0.0, 0.0, 1.0), 5.0)
    assert polyhedron_properties(whole).volume == pytest.approx(2.0)
