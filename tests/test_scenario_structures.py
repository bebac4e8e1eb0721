"""Scenario files for the structure generators (arch of any shape, wall with openings, pier,
buttressed wall, arch bridge, blocks from CSV/DXF files) and laws with "*": every key is read,
equals the Python objects, round-trips through JSON, builds the very model the generator
builds; bad input names the key."""

import math
import textwrap

import numpy as np
import pytest

import saxum as sx
from saxum import structures
from saxum.scenario import (
    ArchBridgeStructure,
    BlocksStructure,
    BondedWallStructure,
    ButtressedWallStructure,
    LawSpec,
    OpeningSpec,
    OutputSpec,
    PierStructure,
    Scenario,
    ShapedArchStructure,
    parse_scenario,
)

LAWS = textwrap.dedent("""\

    [[laws]]
    groups = ["*", "*"]
    friction = 0.6

    [output]
    duration = 0.1
""")

ARCH = textwrap.dedent("""\
    [structure]
    type = "arch"
    shape = "pointed"
    span = 2.0
    thickness = 0.25
    eccentricity = 0.5
    voussoirs = 12
    joints = "vertical"
    density = 2100.0
    piers = "free"
    pier_width = 0.6
    pier_height = 1.2
    pier_courses = 3
""") + LAWS

WALL = textwrap.dedent("""\
    [structure]
    type = "wall"
    courses = 8
    bricks = 8
    brick_length = 0.3
    brick_height = 0.1
    half_bricks = false
    min_piece = 0.2
    density = 1900.0
    ground_splits = [1.0]

    [[structure.openings]]
    x = 0.3
    width = 0.3
    height = 0.4
    head_depth = 0.15
    bearing = 0.1

    [[structure.openings]]
    x = 1.0
    y = 0.2
    width = 0.4
    height = 0.3
    head = "segmental_arch"
    head_depth = 0.12
    rise = 0.1
    voussoirs = 5

    [[structure.openings]]
    x = 1.8
    y = 0.2
    width = 0.3
    height = 0.3
    head = "flat_arch"
    head_depth = 0.15
    skewback = 0.3
""") + LAWS

PIER = textwrap.dedent("""\
    [structure]
    type = "pier"
    width = 0.5
    height = 2.0
    courses = 4
    density = 2300.0
""") + LAWS

BUTTRESSED = textwrap.dedent("""\
    [structure]
    type = "buttressed_wall"
    height = 3.0
    thickness = 0.6
    courses = 6
    buttress_width = 1.2
    buttress_height = 2.0
    setbacks = 2
    block_length = 0.4
    density = 2100.0
""") + LAWS

BRIDGE = textwrap.dedent("""\
    [structure]
    type = "arch_bridge"
    shape = "segmental"
    span = 4.0
    rise = 1.2
    thickness = 0.35
    voussoirs = 9
    joints = "vertical"
    spans = 2
    pier_width = 1.2
    pier_height = 2.0
    abutment_width = 1.5
    pier_courses = 2
    piers = "fixed"
    spandrel_height = 1.8
    fill = "blocks"
    fill_depth = 0.6
    course_height = 0.3
    block_length = 0.6
    min_piece = 0.2
    density = 2300.0
    fill_density = 1700.0
""") + LAWS

SEG = structures.ArchShape.segmental(span=4.0, rise=1.2, thickness=0.35)
CASES = {
    "arch": (ARCH, ShapedArchStructure(
        shape="pointed", span=2.0, thickness=0.25, eccentricity=0.5, voussoirs=12,
        joints="vertical", density=2100.0, piers="free", pier_width=0.6, pier_height=1.2,
        pier_courses=3),
        lambda: structures.arch(structures.ArchShape.pointed(span=2.0, thickness=0.25,
                                                             eccentricity=0.5),
                                voussoirs=12, joints="vertical", density=2100.0,
                                pier_width=0.6, pier_height=1.2, pier_courses=3,
                                pier_kind=sx.BodyKind.FREE)),
    "wall": (WALL, BondedWallStructure(
        courses=8, bricks=8, brick_length=0.3, brick_height=0.1,
        half_bricks=False, min_piece=0.2, density=1900.0, ground_splits=[1.0], openings=[
            OpeningSpec(x=0.3, width=0.3, height=0.4, head_depth=0.15, bearing=0.1),
            OpeningSpec(x=1.0, y=0.2, width=0.4, height=0.3, head="segmental_arch",
                        head_depth=0.12, rise=0.1, voussoirs=5),
            OpeningSpec(x=1.8, y=0.2, width=0.3, height=0.3, head="flat_arch",
                        head_depth=0.15, skewback=0.3)]),
        lambda: structures.wall(
            courses=8, bricks=8, brick_length=0.3, brick_height=0.1,
            half_bricks=False, min_piece=0.2, density=1900.0, ground_splits=[1.0], openings=[
                structures.Opening(0.3, 0.0, 0.3, 0.4, head="lintel", head_depth=0.15,
                                   bearing=0.1),
                structures.Opening(1.0, 0.2, 0.4, 0.3, head="segmental_arch",
                                   head_depth=0.12, rise=0.1, voussoirs=5),
                structures.Opening(1.8, 0.2, 0.3, 0.3, head="flat_arch", head_depth=0.15,
                                   skewback=0.3)])),
    "stack bond": ('[structure]\ntype = "wall"\ncourses = 3\nbricks = 4\nbond = "stack"\n'
                   + LAWS, BondedWallStructure(courses=3, bricks=4, bond="stack"),
                   lambda: structures.wall(courses=3, bricks=4, bond="stack")),
    "pier": (PIER, PierStructure(width=0.5, height=2.0, courses=4, density=2300.0),
             lambda: structures.pier(width=0.5, height=2.0, courses=4, density=2300.0)),
    "buttressed_wall": (BUTTRESSED, ButtressedWallStructure(
        height=3.0, thickness=0.6, courses=6, buttress_width=1.2, buttress_height=2.0,
        setbacks=2, block_length=0.4, density=2100.0),
        lambda: structures.buttressed_wall(
            height=3.0, thickness=0.6, courses=6, buttress_width=1.2, buttress_height=2.0,
            setbacks=2, block_length=0.4, density=2100.0)),
    "arch_bridge": (BRIDGE, ArchBridgeStructure(
        shape="segmental", span=4.0, rise=1.2, thickness=0.35, voussoirs=9,
        joints="vertical", spans=2, pier_width=1.2, pier_height=2.0, abutment_width=1.5,
        pier_courses=2, piers="fixed", spandrel_height=1.8, fill="blocks", fill_depth=0.6,
        course_height=0.3, block_length=0.6, min_piece=0.2, density=2300.0,
        fill_density=1700.0),
        lambda: structures.arch_bridge(
            SEG, spans=2, voussoirs=9, joints="vertical", pier_width=1.2, pier_height=2.0,
            abutment_width=1.5, pier_courses=2, pier_kind=sx.BodyKind.FIXED,
            spandrel_height=1.8, fill="blocks", fill_depth=0.6, course_height=0.3,
            block_length=0.6, min_piece=0.2, density=2300.0, fill_density=1700.0)),
}


def _assert_same_model(a, b):
    assert a.body_name == b.body_name
    assert np.array_equal(a.body_kind, b.body_kind)
    assert a.group_names == b.group_names
    assert np.allclose(a.body_mass, b.body_mass, rtol=1e-12)
    assert np.allclose(a.body_q0, b.body_q0, rtol=1e-12, atol=1e-12)
    for k in range(a.body_count):
        assert np.allclose(a.vertices(k), b.vertices(k), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("tag", CASES)
def test_every_key_round_trips_and_builds_the_generators_model(tag):
    text, python, generator = CASES[tag]
    sc = parse_scenario(text)
    assert sc.structure == python
    assert Scenario.model_validate_json(sc.model_dump_json()) == sc
    # every key given differs from its default, so none can have been silently dropped
    given = python.model_fields_set - {"type"}
    for key in given:
        field = type(python).model_fields[key]
        if not field.is_required():
            assert getattr(python, key) != field.get_default(), key
    _assert_same_model(sc.build_model(), generator())


def test_openings_every_key_differs_from_its_default():
    for spec in parse_scenario(WALL).structure.openings:
        for key in spec.model_fields_set:
            field = OpeningSpec.model_fields[key]
            if not field.is_required():
                assert getattr(spec, key) != field.get_default(), key


@pytest.mark.parametrize("keys, direct", [
    ("shape = \"semicircular\"", structures.ArchShape.semicircular(span=2.0, thickness=0.2)),
    ("shape = \"circular\"\nembrace = 2.0",
     structures.ArchShape.circular(span=2.0, thickness=0.2, embrace=2.0)),
    ("shape = \"segmental\"\nrise = 0.5",
     structures.ArchShape.segmental(span=2.0, rise=0.5, thickness=0.2)),
    ("shape = \"pointed\"\neccentricity = 1.0",
     structures.ArchShape.pointed(span=2.0, thickness=0.2, eccentricity=1.0)),
    ("shape = \"elliptical\"\nrise = 1.4",
     structures.ArchShape.elliptical(span=2.0, rise=1.4, thickness=0.2)),
    ("shape = \"basket_handle\"\nrise = 0.6",
     structures.ArchShape.basket_handle(span=2.0, rise=0.6, thickness=0.2)),
    ("shape = \"flat\"", structures.ArchShape.flat(span=2.0, depth=0.2)),
    ("shape = \"flat\"\nskewback = 0.4",
     structures.ArchShape.flat(span=2.0, depth=0.2, skewback=0.4)),
])
def test_each_shape_is_the_archshape_it_names(keys, direct):
    text = f'[structure]\ntype = "arch"\n{keys}\nspan = 2.0\nthickness = 0.2\nvoussoirs = 9\n'
    shape = parse_scenario(text + LAWS).structure.arch_shape()
    s = np.linspace(0.0, 1.0, 41)
    assert np.array_equal(shape.intrados(s), direct.intrados(s))
    assert np.array_equal(shape.extrados(s), direct.extrados(s))


def test_bridge_surcharge_uses_the_scenarios_gravity():
    text = BRIDGE.replace('fill = "blocks"', 'fill = "surcharge"').replace(
        "[output]", "[loads]\ngravity = [0.0, -9.0]\n\n[output]")
    model = parse_scenario(text).build_model()
    reference = structures.arch_bridge(
        SEG, spans=2, voussoirs=9, joints="vertical", pier_width=1.2, pier_height=2.0,
        abutment_width=1.5, pier_courses=2, pier_kind=sx.BodyKind.FIXED, spandrel_height=1.8,
        fill="surcharge", fill_depth=0.6, course_height=0.3, block_length=0.6, min_piece=0.2,
        density=2300.0, fill_density=1700.0, gravity=(0.0, -9.0))
    _assert_same_model(model, reference)
    assert len(model.forces) == len(reference.forces) > 0
    total = sum(f(0.0)[1] * len(b) for b, f in model.forces)
    assert total == pytest.approx(sum(f(0.0)[1] * len(b) for b, f in reference.forces))
    assert total < 0.0


def _error(text, **kw):
    with pytest.raises(sx.InputError) as info:
        sc = parse_scenario(text, **kw)
        sc.build_model()
    return str(info.value)


@pytest.mark.parametrize("text, old, new, expected", [
    (ARCH, "eccentricity = 0.5", "",
     ["line 1: structure:", 'shape = "pointed" needs eccentricity']),
    (ARCH, "eccentricity = 0.5", "eccentricity = 0.5\nrise = 1.0",
     ["structure:", 'rise is not used by shape = "pointed"', "segmental"]),
    (ARCH, 'shape = "pointed"\nspan = 2.0\nthickness = 0.25\neccentricity = 0.5',
     'shape = "segmental"\nspan = 2.0\nthickness = 0.25\nrise = 1.5',
     ["structure:", "rise must be in (0, span/2 = 1]"]),
    (ARCH, 'shape = "pointed"', 'shape = "gothic"', ["line 3: structure.shape", "'pointed'"]),
    (ARCH, "voussoirs = 12", "voussoirs = 0",
     ["line 7: structure.voussoirs", "greater than or equal to 1"]),
    (ARCH, 'joints = "vertical"', 'joints = "diagonal"',
     ["line 8: structure.joints", "'radial' or 'vertical'"]),
    (ARCH, "pier_width = 0.6", "pier_width = 0.1",
     ["structure:", "pier_width", "wider"]),
    (ARCH, "pier_courses = 3", "pier_courses = 3\nabutments = 2",
     ["line 14: structure.abutments: unknown key", "allowed keys here: shape, span, thickness"]),
    (WALL, "x = 1.8", "x = 2.2", ["structure: openings[2]", "outside the wall"]),
    (WALL, "width = 0.3\nheight = 0.4", "width = 3.0\nheight = 0.4",
     ["structure: openings[0].width = 3 m is larger than the wall's width (2.4 m)"]),
    (WALL, "bearing = 0.1", "bearing = 0.1\ncolour = 1",
     ["line 18: structure.openings[0].colour: unknown key",
      "allowed keys here: x, y, width, height, head"]),
    (WALL, "rise = 0.1", "rise = 0.1\nbearing = 0.1",
     ["line 19: structure.openings[1]", 'bearing is not used with head = "segmental_arch"']),
    (WALL, "x = 1.0", "x = 0.4", ["openings[0] and openings[1]", "overlap"]),
    (WALL, "ground_splits = [1.0]", "ground_splits = [1.0, 0.5]",
     ["structure: ground_splits must increase strictly"]),
    (WALL, "bricks = 8", 'bricks = 8\nbond = "english"',
     ["structure.bond", "'running' or 'stack'"]),
    (BUTTRESSED, "buttress_height = 2.0", "buttress_height = 2.2",
     ["structure: buttress_height must be a whole number of courses"]),
    (BRIDGE, 'fill = "blocks"', 'fill = "gravel"', ["structure.fill", "'surcharge'"]),
    (BRIDGE, "spandrel_height = 1.8", "spandrel_height = 0.1", ["structure: spandrel_height"]),
    (PIER, "width = 0.5", "width = -0.5", ["line 3: structure.width", "greater than 0"]),
])
def test_bad_structures_name_the_key(text, old, new, expected):
    assert old in text
    message = _error(text.replace(old, new, 1))
    for part in expected:
        assert part in message, (part, message)


def test_laws_with_a_star():
    text = PIER.replace(LAWS, textwrap.dedent("""\

        [[laws]]
        groups = ["*", "*"]
        friction = 0.5

        [[laws]]
        groups = ["pier", "*"]
        friction = 0.7

        [[laws]]
        groups = ["ground", "pier"]
        friction = 0.9

        [output]
        duration = 0.1
    """))
    m = parse_scenario(text).build_model()

    def mu(a, b):
        return m.laws[m.group_law[m.group_names.index(a), m.group_names.index(b)]].friction

    assert (mu("pier", "ground"), mu("pier", "pier"), mu("ground", "ground")) == (
        0.9, 0.7, 0.5)
    ambiguous = PIER.replace(LAWS, textwrap.dedent("""\
        [[laws]]
        groups = ["pier", "*"]
        friction = 0.7
        [[laws]]
        groups = ["ground", "*"]
        friction = 0.4
        [output]
        duration = 0.1
    """))
    message = _error(ambiguous)
    assert "groups 'ground' and 'pier' match both" in message
    assert 'give a law for ["ground", "pier"]' in message
    unknown = PIER.replace('groups = ["*", "*"]', 'groups = ["brick", "*"]')
    assert "laws[0].groups names group 'brick', which no block has" in _error(unknown)


def test_blocks_from_csv_and_dxf_files(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    (tmp_path / "b.csv").write_text("block,x,y,kind,group\nbase,-1,-0.1,fixed,ground\n"
                                    "base,1,-0.1,,\nbase,1,0,,\nbase,-1,0,,\n"
                                    "stone,0,0,,\nstone,200,0,,\nstone,200,500,,\n")
    csv_text = ('[structure]\ntype = "blocks"\nfile = "b.csv"\nscale = 0.001\n'
                'density = {block = 2500.0}\n' + LAWS)
    sc = parse_scenario(csv_text, base_dir=tmp_path)
    assert sc.structure == BlocksStructure(file=tmp_path / "b.csv", scale=0.001,
                                           density={"block": 2500.0})
    m = sc.build_model()
    assert m.body_name == ("base", "stone")
    assert m.body_mass[1] == pytest.approx(0.5 * 0.2 * 0.5 * 2500.0)
    doc = ezdxf.new()
    doc.layers.add("SUPPORT")
    msp = doc.modelspace()
    msp.add_lwpolyline([(-1, -0.1), (1, -0.1), (1, 0), (-1, 0)], close=True,
                       dxfattribs={"layer": "SUPPORT"})
    msp.add_lwpolyline([(0, 0), (0.2, 0), (0.2, 0.5), (0, 0.5)], close=True,
                       dxfattribs={"layer": "STONE"})
    msp.add_text("elevation", dxfattribs={"layer": "NOTES"})
    doc.saveas(tmp_path / "e.dxf")
    dxf_text = ('[structure]\ntype = "blocks"\nfile = "e.dxf"\nformat = "dxf"\n'
                'fixed_layers = ["support"]\ngroup = "unused"\ndensity = 2000.0\n'
                'ignore_layers = ["notes"]\n' + LAWS)
    m = parse_scenario(dxf_text, base_dir=tmp_path).build_model()
    assert [m.group_names[g] for g in m.body_group] == ["SUPPORT", "STONE"]
    assert m.body_kind[0] == sx.BodyKind.FIXED and m.body_mass[1] == pytest.approx(200.0)
    with pytest.raises(sx.InputError, match="TEXT handle .* on layer 'NOTES': not a block"):
        parse_scenario(dxf_text.replace('ignore_layers = ["notes"]\n', ""),
                       base_dir=tmp_path).build_model()


def test_python_scenario_with_a_generated_structure_runs():
    sc = Scenario(structure=ShapedArchStructure(shape="segmental", span=2.0, rise=0.5,
                                                thickness=0.2, voussoirs=7),
                  laws=[LawSpec(groups=("*", "*"), friction=0.6)],
                  output=OutputSpec(duration=0.05))
    sim = sc.build_simulation()
    state = sim.initial_state()
    sim.run(state, 0.05)
    assert float(np.abs(state.body_q - sim.model.body_q0).max()) < 1e-5
    assert math.isfinite(float(state.body_v.sum()))
