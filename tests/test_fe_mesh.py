"""Meshes of deformable blocks: coverage, outward boundary facets, conformity, quality (least
angle over random convex polygons), bad input."""

import math

import hypothesis.strategies as st
import numpy as np
import pytest
from hypothesis import assume, given, settings
from scipy.spatial import ConvexHull

from saxum.errors import InputError
from saxum.fe import Mesh, mesh_polygon, mesh_polyhedron
from saxum.fe.mesh import _signed_volumes

TRAPEZOID = [[0.0, 0.0], [0.6, 0.0], [0.5, 0.3], [0.1, 0.3]]  # a voussoir-like quadrilateral
BRICK = np.array([[x, y, z] for x in (0, 0.4) for y in (0, 0.2) for z in (0, 0.1)])
BRICK_FACES = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4],
               [1, 5, 7, 3]]


def _polygon_area(v):
    v = np.asarray(v)
    return 0.5 * abs(np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]))


def _check_2d(mesh, area, interior_point):
    volume = _signed_volumes(mesh.nodes, mesh.cells)
    assert np.all(volume > 0)
    assert math.isclose(volume.sum(), area, rel_tol=1e-12)
    x = mesh.nodes[mesh.facets]
    d = x[:, 1] - x[:, 0]
    normal = np.stack([d[:, 1], -d[:, 0]], axis=1)
    assert np.all(np.sum(normal * (x.mean(axis=1) - interior_point), axis=1) > 0)
    # a closed boundary: every boundary node starts exactly one facet and ends one
    assert np.array_equal(np.sort(mesh.facets[:, 0]), mesh.boundary_nodes)
    assert np.array_equal(np.sort(mesh.facets[:, 1]), mesh.boundary_nodes)


@pytest.mark.parametrize("vertices", [TRAPEZOID, TRAPEZOID[::-1]])
def test_polygon_mesh_covers_the_block_with_outward_boundary(vertices):
    mesh = mesh_polygon(vertices, 0.05)
    _check_2d(mesh, _polygon_area(vertices), np.mean(vertices, axis=0))
    edges = np.linalg.norm(np.diff(mesh.nodes[mesh.cells[:, [0, 1, 2, 0]]], axis=1), axis=2)
    # lattice spacing size, boundary spacing <= 3/2 size, lattice >= 0.6 size inside: the
    # longest edge spans the band between boundary and lattice, well under 2 size
    assert edges.max() < 2.0 * 0.05


def test_rectangle_gets_a_structured_mesh():
    rect = [[1.0, 2.0], [1.0 + 0.9, 2.0], [1.9, 2.3], [1.0, 2.3]]
    mesh = mesh_polygon(rect, 0.1)
    assert len(mesh.nodes) == 10 * 4 and len(mesh.cells) == 2 * 9 * 3
    _check_2d(mesh, 0.27, np.array([1.45, 2.15]))


def test_box_gets_structured_kuhn_tetrahedra():
    mesh = mesh_polyhedron(BRICK, BRICK_FACES, 0.1)
    assert len(mesh.nodes) == 5 * 3 * 2 and len(mesh.cells) == 6 * 4 * 2 * 1
    _check_3d(mesh, 0.4 * 0.2 * 0.1, 2 * (0.08 + 0.04 + 0.02), BRICK.mean(axis=0))


def _check_3d(mesh, volume, surface, interior_point):
    v = _signed_volumes(mesh.nodes, mesh.cells)
    assert np.all(v > 0)
    assert math.isclose(v.sum(), volume, rel_tol=1e-12)
    x = mesh.nodes[mesh.facets]
    normal = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    assert np.all(np.sum(normal * (x.mean(axis=1) - interior_point), axis=1) > 0)
    # conforming and closed: boundary triangles add up to the surface, their vector areas to 0
    assert math.isclose(0.5 * np.linalg.norm(normal, axis=1).sum(), surface, rel_tol=1e-12)
    assert np.allclose(normal.sum(axis=0), 0.0, atol=1e-12 * surface)


def test_convex_polyhedron_is_coned_and_red_refined():
    octahedron = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1],
                           [0, 0, -1.0]]) * 0.2 + [1.0, 2.0, 3.0]
    faces = ConvexHull(octahedron).simplices
    mesh = mesh_polyhedron(octahedron, faces, 0.05)
    _check_3d(mesh, 4 / 3 * 0.2**3, 8 * math.sqrt(3) / 2 * (0.2 * math.sqrt(2)) ** 2 / 2,
              octahedron.mean(axis=0))
    x = mesh.nodes[mesh.cells]
    longest = max(np.linalg.norm(x[:, i] - x[:, j], axis=1).max()
                  for i in range(4) for j in range(i + 1, 4))
    assert longest <= 0.05


def test_bad_mesh_size_and_node_count_are_refused():
    with pytest.raises(InputError, match=r"voussoir 3: mesh size = 2.0 m is larger than the "
                                         r"block \(its largest dimension is 0.6"):
        mesh_polygon(TRAPEZOID, 2.0, name="voussoir 3")
    with pytest.raises(InputError, match="mesh size = 0.0 m must be positive"):
        mesh_polygon(TRAPEZOID, 0.0)
    with pytest.raises(InputError, match=r"mesh size = 0.002 m gives about \d+ nodes, more "
                                         "than max_nodes = 1000; give a larger mesh size or "
                                         "raise max_nodes"):
        mesh_polygon(TRAPEZOID, 0.002)
    with pytest.raises(InputError, match=r"mesh size = 0.01 m gives 1271 nodes, more than "
                                         r"max_nodes = 500"):
        mesh_polygon([[0, 0], [0.4, 0], [0.4, 0.3], [0, 0.3]], 0.01, max_nodes=500)
    with pytest.raises(InputError, match=r"brick: mesh size = 0.02 m gives 1386 nodes"):
        mesh_polyhedron(BRICK, BRICK_FACES, 0.02, name="brick")
    assert len(mesh_polyhedron(BRICK, BRICK_FACES, 0.02, max_nodes=1386).nodes) == 1386


def test_self_crossing_polygon_is_refused():
    bow_tie = [[0, 0], [1, 1], [1, 0], [0, 1]]
    with pytest.raises(InputError, match="arch: polygon edges 0 and 2 cross"):
        mesh_polygon(bow_tie, 0.2, name="arch")


def test_non_convex_polyhedron_and_bad_cells_are_refused():
    notch = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.1, 0.1, 0.1]])
    faces = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 4, 2], [1, 3, 4], [2, 4, 3]]
    with pytest.raises(InputError, match="not convex"):
        mesh_polyhedron(notch, faces, 0.5)
    nodes = [[0, 0], [1, 0], [0, 1], [2, 2]]
    with pytest.raises(InputError, match=r"mesh nodes \[3\] belong to no cell"):
        Mesh.from_cells(nodes, [[0, 1, 2]])
    with pytest.raises(InputError, match=r"cells \[1\] have zero area"):
        Mesh.from_cells(nodes, [[0, 1, 2], [0, 1, 1], [1, 3, 2]])
    with pytest.raises(InputError, match="outside 0..3"):
        Mesh.from_cells(nodes, [[0, 1, 4], [1, 3, 2]])


def _least_angles(nodes, cells):
    """Least interior angle of each triangle [degrees]."""
    x = nodes[cells]
    angles = []
    for k in range(3):
        u, w = x[:, (k + 1) % 3] - x[:, k], x[:, (k + 2) % 3] - x[:, k]
        cos = np.sum(u * w, axis=1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1))
        angles.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    return np.min(angles, axis=0)


@settings(max_examples=150, deadline=None)
@given(st.lists(st.floats(0.0, 2.0 * math.pi), min_size=3, max_size=9, unique=True),
       st.floats(0.15, 1.0), st.floats(-math.pi, math.pi), st.floats(0.05, 1.0),
       st.floats(0.2, 0.8) | st.none())
def test_random_convex_polygon_mesh_is_conforming_with_angles_bounded(angles, aspect, turn,
                                                                      fraction, collinear):
    """Points on an ellipse (semi-axes 1 m and `aspect` m, turned by `turn`) in angle order are
    a convex polygon; `collinear` puts an extra vertex on edge 0 at that fraction. Size is the
    given fraction of the shortest edge. The least angle is bounded by min(20 degrees, a third
    of the sharpest corner): measured over 2400 random polygons it is >= 0.398 times the
    sharpest corner and >= 23.8 degrees where no corner is below 30 degrees."""
    t = np.sort(angles)
    c, s = math.cos(turn), math.sin(turn)
    v = np.stack([np.cos(t), aspect * np.sin(t)], axis=1) @ np.array([[c, s], [-s, c]])
    edge = np.roll(v, -1, axis=0) - v
    length = np.linalg.norm(edge, axis=1)
    assume(length.min() > 0.02)
    cos = -np.sum(np.roll(edge, 1, axis=0) * edge, axis=1) / (np.roll(length, 1) * length)
    corner = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))).min()
    assume(corner > 1.0)
    if collinear is not None:
        v = np.insert(v, 1, v[0] + collinear * edge[0], axis=0)
        edge = np.roll(v, -1, axis=0) - v
        length = np.linalg.norm(edge, axis=1)
    size = fraction * length.min()
    assume(2.0 / size < 60)
    mesh = mesh_polygon(v, size, max_nodes=10_000)
    _check_2d(mesh, _polygon_area(v), v.mean(axis=0))
    # every vertex is a node; every facet lies on an edge of the polygon, within it
    # (the vertices are copied into the point set; 1e-12 of the block's size is round-off room)
    gap = np.linalg.norm(mesh.nodes[None] - v[:, None], axis=2).min(axis=1)
    assert np.all(gap <= 1e-12 * np.ptp(v, axis=0).max())
    x = mesh.nodes[mesh.facets]
    normal = np.stack([edge[:, 1], -edge[:, 0]], axis=1) / length[:, None]
    offset = x[:, :, None, :] - v[None, None]
    across = np.abs(np.einsum("fpkd,kd->fpk", offset, normal)).max(axis=1)
    along = np.einsum("fpkd,kd->fpk", offset, edge / length[:, None]) / length
    inside = (along.min(axis=1) >= -1e-12) & (along.max(axis=1) <= 1 + 1e-12)
    assert np.all(np.any((across <= 1e-12) & inside, axis=1))
    assert _least_angles(mesh.nodes, mesh.cells).min() >= min(20.0, corner / 3.0)


def test_non_convex_polygon_is_refused():
    chevron = [[0, 0], [0.4, 0.1], [0.8, 0], [0.8, 0.3], [0, 0.3]]
    with pytest.raises(InputError, match=r"voussoir 2: the polygon is not convex \(vertex 1 "
                                         r"of the counter-clockwise outline is a reflex corner"):
        mesh_polygon(chevron, 0.1, name="voussoir 2")
