"""Bad input for 3D models gets an InputError that names the block, file, key or parameter."""

import meshio
import numpy as np
import pytest

import saxum as sx
from saxum.errors import InputError
from saxum.ground import one_sine
from saxum.structures import (
    ArchShape,
    add_blocks_from_mesh,
    add_extruded,
    bridge3d,
    read_mesh_blocks,
    wall3d,
)
from saxum.structures.solid import box

CUBE = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
TRIANGLES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])


def _write(path, points, triangles):
    meshio.write(path, meshio.Mesh(points, [("triangle", np.asarray(triangles))]))
    return path


def test_the_cube_mesh_is_a_good_block(tmp_path):
    (block,) = read_mesh_blocks(_write(tmp_path / "cube.stl", CUBE, TRIANGLES))
    assert sorted(map(tuple, block)) == sorted(map(tuple, CUBE))


def _grid_of_cubes(path, drop_last: int = 0):
    """A 2 x 2 x 2 stack of unit cubes that touch face to face (so four meet at some edges),
    each face's diagonal chosen at random; the last `drop_last` triangles left out."""
    rng = np.random.default_rng(7)
    points, triangles = [], []
    for k, corner in enumerate(np.ndindex(2, 2, 2)):
        tri = TRIANGLES.copy()
        flip = rng.random(6) < 0.5  # the other diagonal of a square face
        tri.reshape(6, 2, 3)[flip] = tri.reshape(6, 2, 3)[flip][:, :, [1, 2, 0]][:, ::-1]
        points.append(CUBE + corner)
        triangles.append(tri + 8 * k)
    triangles = np.vstack(triangles)
    return _write(path, np.vstack(points), triangles[: len(triangles) - drop_last])


@pytest.mark.parametrize("suffix", ["stl", "obj"])
def test_touching_blocks_of_a_mesh_stay_apart(tmp_path, suffix):
    """Stacked blocks share corners and edges (STL merges them): each is still one block."""
    blocks = read_mesh_blocks(_grid_of_cubes(tmp_path / f"grid.{suffix}"))
    assert len(blocks) == 8
    for block, corner in zip(blocks, np.ndindex(2, 2, 2), strict=True):
        assert sorted(map(tuple, block)) == sorted(map(tuple, CUBE + corner))


def test_open_block_among_touching_ones(tmp_path):
    """A face missing from the top cube: its wedge closes on a neighbour's face, so the error
    may name the neighbour, but the surface is found open."""
    path = _grid_of_cubes(tmp_path / "grid.obj", drop_last=1)
    with pytest.raises(InputError, match=r"grid\.obj: block \d \(near .*\): the surface is "
                                         r"not closed"):
        read_mesh_blocks(path)


def test_open_mesh(tmp_path):
    path = _write(tmp_path / "open.obj", CUBE, TRIANGLES[:-1])
    with pytest.raises(InputError, match=r"open\.obj: block 0 .* is not closed: the edge"):
        read_mesh_blocks(path)


def test_mesh_with_a_face_turned_over(tmp_path):
    tris = TRIANGLES.copy()
    tris[3] = tris[3, ::-1]
    path = _write(tmp_path / "flipped.stl", CUBE, tris)
    with pytest.raises(InputError, match="flipped.stl: block 0 .* not consistently oriented"):
        read_mesh_blocks(path)


def test_non_convex_mesh(tmp_path):
    dented = CUBE.copy()
    dented[7] = (0.6, 0.6, 0.6)  # a corner pushed into the cube
    path = _write(tmp_path / "dented.ply", dented, TRIANGLES)
    with pytest.raises(InputError, match=r"dented\.ply: block 0 .* not convex"):
        read_mesh_blocks(path)


def test_non_convex_mesh_whose_corners_are_all_on_its_hull(tmp_path):
    """A unit cube whose top is folded into a valley along y (ridge at z = 0.6): its two new
    vertices lie on the hull's faces y = 0 and y = 1, so only the volume tells: it encloses
    1 - 0.2 = 0.8 m^3, its hull 1 m^3."""
    points = np.vstack((CUBE, [(0.5, 0.0, 0.6), (0.5, 1.0, 0.6)]))
    polygons = [[0, 2, 6, 4], [0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 8, 1], [2, 3, 9, 7, 6],
                [1, 8, 9, 3], [8, 5, 7, 9]]
    inside = np.array([0.5, 0.5, 0.4])
    triangles = []
    for poly in polygons:
        fan = [[poly[0], poly[k], poly[k + 1]] for k in range(1, len(poly) - 1)]
        a, b, c = points[fan[0]]
        if np.cross(b - a, c - a) @ (points[poly].mean(axis=0) - inside) < 0.0:
            fan = [t[::-1] for t in fan]
        triangles += fan
    path = _write(tmp_path / "valley.vtu", points, triangles)
    with pytest.raises(InputError, match=r"valley\.vtu: block 0 .* not convex: it encloses "
                                         r"0\.8 m\^3, its convex hull 1 m\^3"):
        read_mesh_blocks(path)


def test_unreadable_and_missing_mesh_files(tmp_path):
    junk = tmp_path / "junk.stl"
    junk.write_bytes(b"\x00\x01 this is not a mesh")
    with pytest.raises(InputError, match="junk.stl: not a mesh file meshio can read"):
        read_mesh_blocks(junk)
    with pytest.raises(InputError, match="no mesh file at"):
        read_mesh_blocks(tmp_path / "missing.obj")


def test_mesh_needs_a_3d_builder(tmp_path):
    path = _write(tmp_path / "cube.stl", CUBE, TRIANGLES)
    with pytest.raises(InputError, match="ModelBuilder\\(dim=3\\)"):
        add_blocks_from_mesh(sx.ModelBuilder(), path, density=2000.0)


@pytest.mark.parametrize(("points", "message"), [
    (np.vstack((CUBE, [(0.5, 0.5, 0.5)])),
     r"pillar 3: the point set is not convex: vertex 8 at \(0\.5, 0\.5, 0\.5\) lies"),
    (CUBE * (1, 1, 0), "pillar 3: flat"),
    (CUBE[:3], "pillar 3: a polyhedron needs at least 4 vertices"),
    ([(0, 0), (1, 0), (0, 1), (1, 1)], r"pillar 3: vertices must be a list of \(x, y, z\)"),
])
def test_bad_blocks_name_the_block(points, message):
    with pytest.raises(InputError, match=message):
        sx.ModelBuilder(dim=3).add_block(points, density=2000.0, name="pillar 3")


def test_driven_3d_block_needs_a_motion_and_forces_need_bodies():
    b = sx.ModelBuilder(dim=3)
    with pytest.raises(InputError, match="table: a DRIVEN block needs motion"):
        b.add_block(CUBE, kind=sx.BodyKind.DRIVEN, name="table")
    with pytest.raises(InputError, match="add_force: no body with index 3"):
        b.add_force([3], lambda t: (0.0,) * 6)


def test_ground_motion_components_must_match_the_model():
    b = sx.ModelBuilder(dim=3)
    with pytest.raises(InputError, match=r"has 2 components, the model is 3D.*in_3d"):
        one_sine(1.0, 0.5).apply_as_inertial_forces(b)
    with pytest.raises(InputError, match="has 3 components, the model is 2D"):
        one_sine(1.0, 0.5, direction=(1.0, 0.0, 0.0)).apply_as_driven_supports(
            sx.ModelBuilder(), ["ground"])


def test_generator_parameters():
    with pytest.raises(InputError, match="must exceed the thickness"):
        wall3d(courses=2, length=1.0, return_length=0.1, thickness=0.12)
    with pytest.raises(InputError, match="courses must be"):
        wall3d(courses=0, length=1.0)
    with pytest.raises(InputError, match="leaves no room between the two spandrel walls"):
        bridge3d(ArchShape.segmental(span=4.0, rise=1.0, thickness=0.4), voussoirs=5,
                 width=1.0, spandrel_thickness=0.5, abutment_width=1.0, pier_height=1.0)
    plane = sx.structures.semicircular_arch(radius=1.0, thickness=0.15, voussoirs=5)
    with pytest.raises(InputError, match=r"spans\['voussoir'\]: \(0, 2\) is not within"):
        add_extruded(sx.ModelBuilder(dim=3), plane, 1.0, spans={"voussoir": [(0.0, 2.0, "v")]})
    with pytest.raises(InputError, match="needs a ModelBuilder\\(dim=3\\)"):
        add_extruded(sx.ModelBuilder(), plane, 1.0)


def test_overlapping_blocks_at_the_start_are_named():
    b = sx.ModelBuilder(dim=3)
    b.add_block(box(0, 0, 0, 1, 1, 1), density=2000.0, name="left stone")
    b.add_block(box(0.99, 0, 0, 2, 1, 1), density=2000.0, name="right stone")
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    with pytest.raises(sx.OverlapError,
                       match=r"'right stone' and 'left stone' overlap by 0\.01 m"):
        sx.Simulation(b.finalize(), dt=1e-3).initial_state()


def test_too_large_a_time_step_in_3d():
    model = wall3d(courses=1, length=0.5)
    with pytest.raises(InputError, match="dt = 0.1 s is too large"):
        sx.Simulation(model, dt=0.1)


def test_bridge3d_parapet_and_fill_parameters():
    shape = ArchShape.segmental(span=4.0, rise=1.0, thickness=0.4)
    common = {"voussoirs": 5, "width": 3.0, "spandrel_thickness": 0.5, "abutment_width": 1.0,
              "pier_height": 1.0}
    with pytest.raises(InputError, match="parapet thickness 0.6 m exceeds the spandrel walls"):
        bridge3d(shape, parapet=(0.6, 1.0), **common)
    with pytest.raises(InputError, match=r"parapet must be \(thickness, height\)"):
        bridge3d(shape, parapet=(0.4,), **common)
    with pytest.raises(InputError, match="parapet_height must be a finite length > 0"):
        bridge3d(shape, parapet=(0.4, -1.0), **common)
    with pytest.raises(InputError, match=r"densities\['fill'\] must be a density > 0"):
        bridge3d(shape, fill_density=-5.0, **common)
