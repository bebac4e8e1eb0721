"""Structure generators: arch geometry, walls with openings, piers, bridges, block files."""

import json
import math
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import saxum as sx
from saxum.geometry2d import normalize_polygon
from saxum.structures import (
    ArchShape,
    Opening,
    add_running_bond_wall,
    add_wall,
    arch,
    arch_bridge,
    arch_ring,
    blocks_model,
    buttressed_wall,
    pier,
    read_blocks,
    semicircular_arch,
    wall,
    write_blocks,
)


def _area(poly):
    x, y = np.asarray(poly).T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _starts(model):
    """Simulation.initial_state() refuses overlapping blocks (OverlapError)."""
    return sx.Simulation(model, dt=1e-3).initial_state()


def _moved(model, duration):
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, duration)
    return float(np.hypot(*(state.body_q[:, :2] - model.body_q0[:, :2]).T).max())


SHAPES = {
    "semicircular": ArchShape.semicircular(span=2.0, thickness=0.2),
    "segmental": ArchShape.segmental(span=4.0, rise=1.0, thickness=0.3),
    "shallow": ArchShape.segmental(span=4.0, rise=0.3, thickness=0.3),
    "pointed": ArchShape.pointed(span=2.0, thickness=0.2, eccentricity=1.0),
    "lancet": ArchShape.pointed(span=2.0, thickness=0.2, eccentricity=6.0),
    "elliptical": ArchShape.elliptical(span=4.0, rise=1.5, thickness=0.3),
    "flat ellipse": ArchShape.elliptical(span=4.0, rise=0.3, thickness=0.4),
    "tall ellipse": ArchShape.elliptical(span=2.0, rise=3.0, thickness=0.2),
    "basket-handle": ArchShape.basket_handle(span=4.0, rise=1.2, thickness=0.3),
    "flat basket": ArchShape.basket_handle(span=4.0, rise=0.2, thickness=0.3),
    "flat": ArchShape.flat(span=1.2, depth=0.3),
}


def _check_ring(cut, n):
    """Convex voussoirs of positive area; neighbours share the very same joint points."""
    assert len(cut.voussoirs) == n
    for k, v in enumerate(cut.voussoirs):
        normalize_polygon(v, name=f"voussoir {k + 1}")  # raises unless strictly convex
        assert _area(v) > 0.0
        if k + 1 < n:
            assert np.array_equal(v[-1], cut.voussoirs[k + 1][0])  # intrados end of the joint
            assert np.array_equal(v[-2], cut.voussoirs[k + 1][1])  # extrados end
    normalize_polygon(cut.outline, name="outline")  # the ring and its opening: convex


@pytest.mark.parametrize("name", SHAPES)
@pytest.mark.parametrize("joints", ["radial", "vertical"])
def test_every_voussoir_is_convex_and_joints_are_shared(name, joints):
    for n in (2, 3, 4, 9, 16):
        _check_ring(arch_ring(SHAPES[name], n, joints), n)


@pytest.mark.parametrize("name", SHAPES)
@pytest.mark.parametrize("joints", ["radial", "vertical"])
def test_symmetric_arches_are_exactly_symmetric(name, joints):
    for n in (5, 8):
        vs = arch_ring(SHAPES[name], n, joints).voussoirs
        for k in range(n):
            mirror = vs[n - 1 - k] * [-1.0, 1.0]
            assert {tuple(p) for p in vs[k]} == {tuple(p) for p in mirror}


@pytest.mark.parametrize("name", ["semicircular", "pointed", "flat ellipse", "flat"])
def test_arch_on_piers_passes_the_overlap_check(name):
    for joints in ("radial", "vertical"):
        model = arch(SHAPES[name], voussoirs=7, joints=joints, pier_courses=2,
                     pier_kind=sx.BodyKind.FREE)
        _starts(model)
        assert model.body_count == 1 + 4 + 7


def test_segmental_arch_on_free_piers_stands():
    """The skewbacks of the piers' top blocks fit the springing faces exactly."""
    shape = ArchShape.segmental(span=4.0, rise=1.0, thickness=0.4)
    model = arch(shape, voussoirs=11, pier_kind=sx.BodyKind.FREE, pier_courses=3,
                 pier_height=2.0)
    left = arch_ring(shape, 11).left
    top = model.vertices(model.body("left pier c3"))
    for point in left:  # the intrados and extrados ends of the springing face
        assert np.hypot(*(top - point).T).min() < 1e-12
    assert _moved(model, 0.2) < 1e-5


@pytest.mark.parametrize("span, rise", [(2.0, 1.0), (4.0, 1.0), (4.0, 0.3)])
@pytest.mark.parametrize("n", [3, 10, 25])
def test_circular_ring_area_is_the_analytic_one(span, rise, n):
    """A voussoir between radial joints dphi apart, its faces chords of radii r and r + t, has
    area (r_o^2 - r_i^2) sin(dphi) / 2; n of them tend to the annular sector as n grows."""
    t = 0.25
    shape = ArchShape.segmental(span=span, rise=rise, thickness=t)
    embrace = 4.0 * math.atan(2.0 * rise / span)
    r = (span * span / 4.0 + rise * rise) / (2.0 * rise)
    areas = [_area(v) for v in arch_ring(shape, n).voussoirs]
    ring = 0.5 * ((r + t) ** 2 - r * r)
    assert sum(areas) == pytest.approx(n * ring * math.sin(embrace / n), rel=1e-9)
    assert max(areas) == pytest.approx(min(areas), rel=1e-9)  # equal voussoirs
    dphi = embrace / n
    assert abs(sum(areas) / (ring * embrace) - 1.0) <= dphi * dphi / 6.0


def test_model_mass_is_density_times_ring_area():
    model = arch(ArchShape.semicircular(span=2.0, thickness=0.2), voussoirs=12, density=2000.0)
    voussoirs = [b for b in range(model.body_count) if model.body_name[b].startswith("vou")]
    ring = 0.5 * (1.2**2 - 1.0**2) * 12 * math.sin(math.pi / 12)
    assert model.body_mass[voussoirs].sum() == pytest.approx(2000.0 * ring, rel=1e-9)


@pytest.mark.parametrize("e", [0.0, 0.3, 1.0, 4.0])
def test_pointed_crown_is_at_the_right_height(e):
    span, t = 3.0, 0.3
    shape = ArchShape.pointed(span=span, thickness=t, eccentricity=e)
    crown = span / 2 * math.sqrt(1 + 2 * e)
    extrados = math.sqrt(((1 + e) * span / 2 + t) ** 2 - (e * span / 2) ** 2)
    even = arch_ring(shape, 8).voussoirs
    assert even[3][-1] == pytest.approx([0.0, crown], abs=1e-12)  # the crown joint
    assert even[3][-2] == pytest.approx([0.0, extrados], abs=1e-12)
    keystone = arch_ring(shape, 7).voussoirs[3]
    assert len(keystone) == (4 if e == 0.0 else 5)  # a pointed keystone keeps the point
    if e > 0.0:
        top = keystone[np.argmax(keystone[:, 1])]
        assert top == pytest.approx([0.0, extrados], abs=1e-12)
    assert shape.intrados(np.array([0.5]))[0] == pytest.approx([0.0, crown], abs=1e-12)


def test_named_arches_have_their_span_and_rise():
    for shape, rise in [(ArchShape.segmental(span=4.0, rise=1.1, thickness=0.3), 1.1),
                        (ArchShape.elliptical(span=4.0, rise=0.7, thickness=0.3), 0.7),
                        (ArchShape.basket_handle(span=4.0, rise=1.3, thickness=0.3), 1.3)]:
        points = shape.intrados(np.linspace(0.0, 1.0, 201))
        assert points[0] == pytest.approx([-2.0, 0.0], abs=1e-12)
        assert points[-1] == pytest.approx([2.0, 0.0], abs=1e-12)
        assert points[100] == pytest.approx([0.0, rise], abs=1e-12)
        # constant thickness along the joints, and equal steps of s are equal lengths
        joints = shape.extrados(np.linspace(0.0, 1.0, 201)) - points
        assert np.hypot(*joints.T) == pytest.approx(0.3, rel=1e-12)
        fine = shape.intrados(np.linspace(0.0, 1.0, 20001))
        steps = np.hypot(*np.diff(fine, axis=0).T).reshape(200, 100).sum(axis=1)
        assert steps == pytest.approx(steps.mean(), rel=1e-6)


@settings(max_examples=40, deadline=None)
@given(span=st.floats(0.5, 20.0), ratio=st.floats(0.02, 0.5), thickness=st.floats(0.02, 0.3),
       n=st.integers(2, 40), joints=st.sampled_from(["radial", "vertical"]),
       kind=st.sampled_from(["segmental", "elliptical", "pointed"]))
def test_any_arch_cuts_into_convex_voussoirs(span, ratio, thickness, n, joints, kind):
    rise, t = ratio * span, thickness * span
    shape = {"segmental": lambda: ArchShape.segmental(span=span, rise=rise, thickness=t),
             "elliptical": lambda: ArchShape.elliptical(span=span, rise=rise, thickness=t),
             "pointed": lambda: ArchShape.pointed(span=span, thickness=t,
                                                  eccentricity=8.0 * ratio)}[kind]()
    _check_ring(arch_ring(shape, n, joints), n)


@pytest.mark.parametrize("call, words", [
    (lambda: arch_ring(ArchShape.semicircular(span=2.0, thickness=0.2), 1),
     ["voussoirs=1", "use more voussoirs"]),
    (lambda: ArchShape.segmental(span=2.0, rise=1.5, thickness=0.2), ["rise", "(0, span/2"]),
    (lambda: ArchShape.pointed(span=2.0, thickness=0.2, eccentricity=-1.0), ["eccentricity"]),
    (lambda: ArchShape.basket_handle(span=2.0, rise=1.0, thickness=0.2), ["rise"]),
    (lambda: ArchShape.circular(span=2.0, thickness=0.2, embrace=4.0), ["embrace", "(0, pi]"]),
    (lambda: ArchShape.flat(span=1.0, depth=0.2, skewback=2.0), ["skewback"]),
    (lambda: arch_ring(SHAPES["flat"], 5, "diagonal"), ["joints", "'radial'"]),
    (lambda: arch(SHAPES["segmental"], voussoirs=5, pier_width=0.1), ["pier_width"]),
    (lambda: arch(SHAPES["segmental"], voussoirs=0), ["voussoirs", ">= 1"]),
    (lambda: semicircular_arch(radius=1.0, thickness=2.5, voussoirs=9),
     ["thickness must be less than 2 radius", "thickness=2.5"]),
    (lambda: semicircular_arch(radius=1.0, thickness=0.2, voussoirs=0), ["voussoirs", ">= 1"]),
    (lambda: semicircular_arch(radius=-1.0, thickness=0.2, voussoirs=9), ["radius", "> 0"]),
])
def test_bad_arch_input_names_the_parameter(call, words):
    with pytest.raises(sx.InputError) as info:
        call()
    assert all(w in str(info.value) for w in words), str(info.value)


def _bricks(model):
    names = np.array(model.body_name)
    return [b for b in range(model.body_count) if names[b].startswith("brick")]


@pytest.mark.parametrize("bond, half, count", [("running", True, 3 * 4 + 2 * 5),
                                               ("running", False, 3 * 4 + 2 * 3),
                                               ("stack", True, 5 * 4)])
def test_wall_brick_count_and_half_bricks(bond, half, count):
    model = wall(courses=5, bricks=4, bond=bond, half_bricks=half, brick_length=0.3,
                 brick_height=0.1)
    _starts(model)
    bricks = _bricks(model)
    assert len(bricks) == count
    areas = model.body_mass[bricks] / 1800.0
    halves = int(np.isclose(areas, 0.015, rtol=1e-9).sum())
    assert halves == (4 if bond == "running" and half else 0)
    if half:  # ends flush: the wall is a full rectangle
        assert areas.sum() == pytest.approx(5 * 0.1 * 4 * 0.3, rel=1e-12)


def test_running_bond_wall_is_add_wall():
    a, b = sx.ModelBuilder(), sx.ModelBuilder()
    assert add_running_bond_wall(a, courses=4, bricks=3) == add_wall(b, courses=4,
                                                                       bricks=3)["bricks"]


def test_openings_leave_the_right_hole():
    length, height = 12 * 0.25, 20 * 0.065
    door = Opening(x=0.4, y=0.0, width=0.7, height=0.65)  # lintel two courses high
    window = Opening(x=1.7, y=0.39, width=0.8, height=0.3, head="segmental_arch", rise=0.2,
                     voussoirs=7, head_depth=0.12)
    model = wall(courses=20, bricks=12, openings=[door, window], min_piece=0.0)
    _starts(model)
    groups = [model.group_names[g] for g in model.body_group]
    assert groups.count("lintel") == 1 and groups.count("voussoir") == 7
    intrados = arch_ring(ArchShape.segmental(span=0.8, rise=0.2, thickness=0.12), 7).voussoirs
    under = _area([v[0] for v in intrados] + [intrados[-1][-1]])  # void below the chords
    solid = model.body_mass[1:].sum() / 1800.0
    hole = 0.7 * 0.65 + 0.8 * 0.3 + under
    assert solid == pytest.approx(length * height - hole, rel=1e-9)
    # bricks next to the door are cut to its edges, and the lintel bears on both sides
    lintel = model.vertices(groups.index("lintel"))
    # vertices are centre + (vertex - centre): round-off of ~1e-16 m on 1 m, 1e-12 m allowed
    assert lintel[:, 0].min() == pytest.approx(0.4 - 0.125)
    assert lintel[:, 1].min() == pytest.approx(0.65, abs=1e-12)


def test_flat_arch_and_plain_openings():
    openings = [Opening(x=0.25, y=0.26, width=0.5, height=0.26, head="flat_arch",
                        voussoirs=5, head_depth=0.195),
                Opening(x=1.25, y=0.0, width=0.25, height=0.13, head="none")]
    model = wall(courses=12, bricks=8, bond="stack", openings=openings)
    _starts(model)
    assert sum(n.startswith("opening 1 voussoir") for n in model.body_name) == 5


@pytest.mark.parametrize("opening, words", [
    (Opening(x=1.8, y=0.0, width=0.5, height=0.3), ["openings[0]", "outside the wall"]),
    (Opening(x=0.5, y=0.0, width=0.5, height=1.5), ["openings[0]", "add courses"]),
    (Opening(x=0.5, y=0.0, width=0.5, height=0.3, head="arch"), ["openings[0].head"]),
    (Opening(x=0.5, y=0.0, width=-0.5, height=0.3), ["openings[0].width"]),
    (Opening(x=0.0, y=0.0, width=2.5, height=0.3),
     ["openings[0].width = 2.5 m is larger than the wall's width (2 m)", "add bricks"]),
    (Opening(x=0.0, y=0.0, width=0.5, height=0.7),
     ["openings[0].height = 0.7 m is larger than the wall's height (0.65 m)", "add courses"]),
    (Opening(x=0.5, y=0.0, width=0.5, height=0.3, head="segmental_arch", rise=0.4),
     ["openings[0] (segmental_arch): rise must be in (0, span/2"]),
    (Opening(x=0.5, y=0.0, width=0.5, height=0.3, head="flat_arch", voussoirs=0),
     ["openings[0] (flat_arch): voussoirs must be a whole number >= 1"]),
])
def test_bad_openings_are_named(opening, words):
    with pytest.raises(sx.InputError) as info:
        wall(courses=10, bricks=8, openings=[opening])
    assert all(w in str(info.value) for w in words), str(info.value)
    with pytest.raises(sx.InputError, match=r"openings\[0\] and openings\[1\]"):
        wall(courses=10, bricks=8, openings=[Opening(x=0.5, y=0, width=0.5, height=0.3),
                                             Opening(x=0.9, y=0, width=0.5, height=0.3)])


def test_pier_and_buttressed_wall():
    model = pier(width=0.5, height=2.0, courses=4)
    _starts(model)
    assert model.body_count == 5 and model.body_mass[1:].sum() == pytest.approx(2000.0 * 1.0)
    model = buttressed_wall(height=3.0, thickness=0.5, courses=10, buttress_width=1.0,
                            buttress_height=2.4, setbacks=2, block_length=0.5)
    _starts(model)
    # wall 0.5 x 3, buttress 1.0 wide for 4 courses, then 0.5 wide for 4 (courses of 0.3 m)
    area = 0.5 * 3.0 + 1.0 * 1.2 + 0.5 * 1.2
    assert model.body_mass[1:].sum() == pytest.approx(2000.0 * area, rel=1e-12)
    assert _moved(model, 0.1) < 1e-5
    with pytest.raises(sx.InputError, match="buttress_height must be a whole number"):
        buttressed_wall(height=3.0, thickness=0.5, courses=10, buttress_width=1.0,
                        buttress_height=1.0)


BRIDGE = {"spans": 2, "voussoirs": 9, "pier_width": 1.0, "pier_height": 1.5,
          "abutment_width": 1.5, "course_height": 0.4, "block_length": 0.8}


@pytest.mark.parametrize("fill", ["surcharge", "blocks"])
def test_bridge_stands_under_its_own_weight(fill):
    shape = ArchShape.segmental(span=4.0, rise=1.2, thickness=0.4)
    model = arch_bridge(shape, fill=fill, fill_depth=0.5, **BRIDGE)
    groups = set(model.group_names)
    assert {"ground", "pier", "voussoir", "spandrel"} <= groups
    assert ("fill" in groups) == (fill == "blocks")
    if fill == "surcharge":
        # the fill weighs at least its 0.5 m layer over the whole bridge, 12 m long
        load = sum(force(0.0)[1] for _, force in model.forces)
        layer = -1800.0 * 9.81 * 0.5 * 12.0
        assert layer * 1.05 < load <= layer
    assert _moved(model, 0.2) < 1e-5


def _arch_model():
    return arch(ArchShape.pointed(span=2.0, thickness=0.25, eccentricity=0.5), voussoirs=7,
                pier_kind=sx.BodyKind.FREE)


@pytest.mark.parametrize("suffix", [".json", ".csv"])
def test_block_files_round_trip(tmp_path, suffix):
    model = _arch_model()
    path = tmp_path / f"arch{suffix}"
    write_blocks(path, model)
    again = blocks_model(path)
    assert again.body_name == model.body_name
    assert np.array_equal(again.body_kind, model.body_kind)
    assert again.group_names == model.group_names
    assert np.array_equal(again.body_density, model.body_density)
    for b in range(model.body_count):
        assert np.allclose(again.vertices(b), model.vertices(b), rtol=0, atol=1e-12)
    _starts(again)


@pytest.mark.parametrize("suffix", [".json", ".csv"])
def test_3d_block_files_round_trip(tmp_path, suffix):
    """3D blocks ([x, y, z] vertices, a z column in CSV): written and read back as the same
    polyhedra, built into a 3D model (blocks_model), also by a scenario of type "blocks"."""
    from saxum.scenario import parse_scenario
    from saxum.structures import pier3d

    model = pier3d(width=0.4, depth=0.3, courses=2, course_height=0.25)
    path = tmp_path / f"pier{suffix}"
    write_blocks(path, model)
    again = blocks_model(path)
    assert again.dim == 3 and again.body_name == model.body_name
    assert again.group_names == model.group_names
    assert np.array_equal(again.body_kind, model.body_kind)
    assert again.body_mass == pytest.approx(model.body_mass, rel=1e-12)
    for b in range(model.body_count):
        assert np.allclose(np.sort(again.vertices(b), axis=0), np.sort(model.vertices(b), axis=0),
                           rtol=0, atol=1e-12)
    scenario = parse_scenario(f"""
        [structure]
        type = "blocks"
        file = "{path}"
        [[laws]]
        groups = ["*", "*"]
        friction = 0.6
        [output]
        duration = 0.01
    """.replace("\n        ", "\n"))
    assert scenario.structure.dim == 3 and scenario.build_model().dim == 3


@pytest.mark.parametrize("name, text, words", [
    ("a.json", '{"blocks": [{"vertices": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "density": 1},'
               ' {"vertices": [[0,0],[1,0],[0,1]], "density": 1}]}',
     ["blocks[1]", "vertices of 2 coordinates, but the blocks above have 3"]),
    ("b.csv", "block,x,y,z,density\nA,0,0,0,1\nA,1,0,0,\nA,0,1,0,\nA,1,1,0,\n",
     ["block 'A' (lines 2-5)", "flat"]),
    ("c.csv", "block,x,y,z\nA,0,0,0\nA,1,0,0\nA,0,1,\nA,0,0,1\n", ["line 4", "z [m]"]),
])
def test_bad_3d_block_files_name_the_block_or_line(tmp_path, name, text, words):
    with pytest.raises(sx.InputError) as info:
        read_blocks(_write(tmp_path / name, text), density=1000.0)
    assert all(w in str(info.value) for w in words), str(info.value)


def test_3d_block_file_needs_a_3d_builder(tmp_path):
    from saxum.structures import add_blocks_from_file

    path = _write(tmp_path / "t.json", '{"blocks": [{"vertices": '
                                       '[[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "density": 1}]}')
    with pytest.raises(sx.InputError, match="holds 3D blocks and the model is 2D: build it "
                                            r"with ModelBuilder\(dim=3\)"):
        add_blocks_from_file(sx.ModelBuilder(), path)


def _write(path, text):
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("name, text, words", [
    ("a.csv", "block,x,y,density\nA,0,0,2000\nA,1,0,\nA,1,1,\nA,0.5,0.4,\nA,0,1,\n",
     ["block 'A' (lines 2-6)", "not strictly convex"]),
    ("b.csv", "block,x,y\nA,0,0\nA,1,zero\nA,0,1\n", ["line 3", "y [m]"]),
    ("c.csv", "block,x,y,density\nA,0,0,1\nA,1,0,\nA,0,1,\nB,2,0,1\nB,3,0,\nB,2,1,\nA,5,5,\n",
     ["line 8", "block 'A' appears again"]),
    ("d.csv", "block,x,y,density\nA,0,0,1\nA,1,0,2\nA,0,1,\n", ["line 3", "density"]),
    ("e.csv", "name,x,y\nA,0,0\n", ["line 1", "block, x, y"]),
    ("f.csv", "block,x,y\nA,0,0\nA,1,0\nA,0,1\n", ["block 'A'", "no density"]),
    ("g.json", '{"blocks": [{"vertices": [[0,0],[1,0],[0,1]], "density": 1},'
               ' {"vertices": [[0,0],[1,0],[0,1]], "kind": "rolling", "name": "B"}]}',
     ["blocks[1] ('B')", "kind must be one of"]),
    ("h.json", '{"blocks": [{"vertices": [[0,0],[1,0]], "density": 1}]}',
     ["blocks[0]", "at least 3 vertices"]),
    ("i.json", '{"blocks": [{"vertexes": []}]}', ["blocks[0]", '"vertices"']),
    ("j.json", '{"blocks": [{"vertices": [[0,0],[1,0],[0,1]], "densty": 1}]}',
     ["blocks[0]", "unknown key 'densty'"]),
    ("k.txt", "", ["unknown block file format 'txt'"]),
])
def test_bad_block_files_name_the_block_or_line(tmp_path, name, text, words):
    with pytest.raises(sx.InputError) as info:
        read_blocks(_write(tmp_path / name, text))
    assert all(w in str(info.value) for w in words), str(info.value)


def test_block_file_defaults(tmp_path):
    path = _write(tmp_path / "b.json", json.dumps({"blocks": [
        {"vertices": [[0, 0], [1000, 0], [1000, 500], [0, 500]], "group": "stone"},
        {"vertices": [[0, 500], [500, 500], [500, 800], [0, 800]]},
        {"vertices": [[-2000, -100], [3000, -100], [3000, 0], [-2000, 0]], "kind": "FIXED"}]}))
    specs = read_blocks(path, density={"stone": 2500.0, "brick": 1800.0}, group="brick",
                        scale=1e-3)
    assert [(s.group, s.kind, s.density) for s in specs] == [
        ("stone", sx.BodyKind.FREE, 2500.0), ("brick", sx.BodyKind.FREE, 1800.0),
        ("brick", sx.BodyKind.FIXED, 0.0)]
    assert _area(specs[0].vertices) == pytest.approx(0.5)


def test_dxf_closed_polylines_become_blocks(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_lwpolyline([(-2, -0.2), (3, -0.2), (3, 0), (-2, 0)], close=True,
                       dxfattribs={"layer": "Fixed"})
    msp.add_lwpolyline([(0, 0), (0.4, 0), (0.4, 0.3), (0, 0.3)], close=True,
                       dxfattribs={"layer": "STONE"})
    # closed by repeating the first point rather than by the flag, as some CAD programs do
    msp.add_polyline2d([(0, 0.3), (0.4, 0.3), (0.2, 0.6), (0, 0.3)],
                       dxfattribs={"layer": "STONE"})
    msp.add_lwpolyline([(1, 1), (2, 1), (2, 2)], dxfattribs={"layer": "NOTES"})
    msp.add_text("north elevation", dxfattribs={"layer": "Notes"})
    path = tmp_path / "elevation.dxf"
    doc.saveas(path)
    specs = read_blocks(path, density=2400.0, ignore_layers=["notes"])
    assert [(s.group, s.kind) for s in specs] == [("Fixed", sx.BodyKind.FIXED),
                                                 ("STONE", sx.BodyKind.FREE),
                                                 ("STONE", sx.BodyKind.FREE)]
    model = blocks_model(path, density=2400.0, ignore_layers=["NOTES"])
    assert _moved(model, 0.05) < 1e-6
    # an open polyline or another entity outside the ignored layers is named, not dropped
    with pytest.raises(sx.InputError, match=r"LWPOLYLINE handle \w+ on layer 'NOTES': an open "
                                            r"polyline \(3 points\); a block must be closed"):
        read_blocks(path, density=2400.0)
    msp.add_line((0, 0), (1, 1), dxfattribs={"layer": "STONE"})
    doc.saveas(path)
    with pytest.raises(sx.InputError, match=r"LINE handle \w+ on layer 'STONE': not a block "
                                            r".*ignore_layers"):
        read_blocks(path, density=2400.0, ignore_layers=["NOTES"])

    msp.add_lwpolyline([(5, 0, 0, 0, 0.5), (6, 0), (6, 1)], format="xyseb", close=True)
    doc.saveas(path)
    with pytest.raises(sx.InputError, match=r"LWPOLYLINE handle \w+ on layer '0'.*bulges"):
        read_blocks(path, density=2400.0, ignore_layers=["NOTES", "STONE"])


def test_dxf_without_ezdxf_says_how_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "ezdxf", None)  # import ezdxf raises ImportError
    with pytest.raises(sx.InputError, match="pip install ezdxf"):
        read_blocks(_write(tmp_path / "x.dxf", ""))


def test_bridge3d_parapets_on_the_walls_with_broken_joints_and_a_lighter_fill():
    """Parapets t x h on both spandrel walls, flush with the faces, over the walls' whole
    length; no parapet joint over a head joint of the course below (blocks 1.5 m long on a
    top course of 1.5 m blocks, not shifted: all but one would be); the fill of its own
    density; the bridge stands under its own weight."""
    from saxum.structures import bridge3d

    shape = ArchShape.segmental(span=4.0, rise=2.0, thickness=0.5)
    model = bridge3d(shape, voussoirs=5, width=4.0, spandrel_thickness=0.6, abutment_width=1.5,
                     pier_height=2.0, spandrel_height=3.0, parapet=(0.4, 1.0),
                     parapet_length=1.5, course_height=1.0, block_length=1.5, density=2400.0,
                     fill_density=1800.0)
    group = np.array([model.group_names[g] for g in model.body_group])
    assert set(model.body_density[group == "fill"]) == {1800.0}
    assert set(model.body_density[(group != "fill") & (group != "ground")]) == {2400.0}
    walls = np.vstack([model.vertices(b) for b in np.flatnonzero(group == "spandrel")])
    deck = walls[:, 2].max()
    below = np.vstack([model.vertices(b) for b in np.flatnonzero(group != "parapet")])
    under = below[np.isclose(below[:, 2], deck), 0]
    parapets = [model.vertices(b) for b in np.flatnonzero(group == "parapet")]
    assert len(parapets) % 2 == 0
    for y0, y1 in ((0.0, 0.4), (3.6, 4.0)):
        row = sorted((p for p in parapets if np.isclose(p[:, 1].min(), y0)),
                     key=lambda p: p[:, 0].min())
        assert len(row) == len(parapets) // 2
        for p in row:
            assert p[:, 1].max() == pytest.approx(y1, abs=1e-12)
            assert (p[:, 2].min(), p[:, 2].max()) == pytest.approx((deck, deck + 1.0))
        edges = [p[:, 0].min() for p in row] + [row[-1][:, 0].max()]
        assert edges == pytest.approx([0.0, 1.875, 3.375, 4.875, 6.375, 7.0])
        assert (edges[0], edges[-1]) == pytest.approx((walls[:, 0].min(), walls[:, 0].max()))
        for a, p in zip(edges[1:-1], row[:-1], strict=True):
            assert p[:, 0].max() == pytest.approx(a, abs=1e-12)  # the blocks touch
            assert np.abs(under - a).min() > 1e-6  # not on a joint below (0.375 m off)
    _starts(model)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 0.1)
    assert np.abs(state.body_q[:, :3] - model.body_q0[:, :3]).max() < 1e-5


def test_every_arch_numbers_its_voussoirs_from_the_left_springing():
    """One convention for names that mechanism reports and docs use: "voussoir 1" is at the
    left springing, the numbers grow to the right (semicircular_arch numbered them from the
    right before)."""
    for model in (semicircular_arch(radius=1.0, thickness=0.15, voussoirs=9),
                  arch(ArchShape.semicircular(span=2.0, thickness=0.15), voussoirs=9)):
        x = [float(model.body_q0[model.body(f"voussoir {k}"), 0]) for k in range(1, 10)]
        assert x == sorted(x) and x[0] < 0.0 < x[-1]
