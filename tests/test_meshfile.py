"""Blocks from volume meshes (saxum.structures.read_mesh_blocks): cells grouped by their block
tag, or by connectivity; a group must fill its convex hull."""

import meshio
import numpy as np
import pytest

from saxum.errors import InputError
from saxum.geometry3d import convex_polyhedron, polyhedron_properties
from saxum.structures import read_mesh_blocks


def _cubes(origins):
    """Unit cubes at `origins` as hexahedra (VTK node order) on shared nodes: a conforming
    mesh of stones in contact."""
    points: dict[tuple, int] = {}
    cells = []
    for ox, oy, oz in origins:
        corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                   (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
        cells.append([points.setdefault((ox + x, oy + y, oz + z), len(points))
                      for x, y, z in corners])
    return np.array(list(points), float), np.array(cells)


def _volumes(blocks):
    return sorted(round(polyhedron_properties(convex_polyhedron(b)).volume, 12) for b in blocks)


def test_tagged_cells_make_one_block_per_tag(tmp_path):
    points, cells = _cubes([(0, 0, 0), (1, 0, 0), (0, 0, 1)])
    for key in ("block", "gmsh:geometrical"):
        path = tmp_path / f"{key.replace(':', '_')}.vtu"
        meshio.write(path, meshio.Mesh(points, [("hexahedron", cells)],
                                       cell_data={key: [np.array([7, 3, 7])]}))
        blocks = read_mesh_blocks(path)
        assert _volumes(blocks) == [1.0, 2.0]  # the two tagged 7 (a 1 x 1 x 2 stone), cube 3


def test_untagged_stones_in_contact_are_one_group_which_must_be_convex(tmp_path):
    points, cells = _cubes([(0, 0, 0), (1, 0, 0)])
    path = tmp_path / "bar.vtu"
    meshio.write(path, meshio.Mesh(points, [("hexahedron", cells)]))
    assert _volumes(read_mesh_blocks(path)) == [2.0]  # convex: one block, by connectivity
    points, cells = _cubes([(0, 0, 0), (1, 0, 0), (0, 0, 1)])  # an L: not one convex block
    meshio.write(path, meshio.Mesh(points, [("hexahedron", cells)]))
    with pytest.raises(InputError, match=r"bar\.vtu: block 0 .* 3 volume cells fill 3 m\^3, "
                                         r"their convex hull 3\.5 m\^3: not one convex block; "
                                         r"tag each block's cells"):
        read_mesh_blocks(path)


def test_a_cube_of_tetrahedra_is_one_block(tmp_path):
    points, cells = _cubes([(0, 0, 0)])
    c = cells[0]
    # six tetrahedra around the diagonal 0-6 (Kuhn's triangulation of the cube)
    tets = np.array([[c[0], c[1], c[2], c[6]], [c[0], c[2], c[3], c[6]],
                     [c[0], c[3], c[7], c[6]], [c[0], c[7], c[4], c[6]],
                     [c[0], c[4], c[5], c[6]], [c[0], c[5], c[1], c[6]]])
    path = tmp_path / "cube.vtu"
    meshio.write(path, meshio.Mesh(points, [("tetra", tets)]))
    assert _volumes(read_mesh_blocks(path)) == [1.0]
