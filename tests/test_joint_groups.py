"""Laws per kind of joint (saxum.structures.Assembly.joints, [[laws]] joint): generated walls
and arches tell bed, head, radial, ring and support joints apart, so that one key gives each
kind its law; the contacts found in a model built so carry the law of their kind of joint."""

import textwrap

import numpy as np
import pytest

import saxum as sx
from saxum.contacts import Contacts
from saxum.detection import detector_for
from saxum.errors import InputError
from saxum.scenario import parse_scenario
from saxum.structures import add_supported_arch, add_wall
from saxum.structures.arch import ArchShape

# a friction per kind of joint, so that a contact's law tells which kind it was given
FRICTION = {"bed": 0.71, "head": 0.52, "radial": 0.63, "ring": 0.44, "support": 0.85,
            "spandrel": 0.37, "fill": 0.29, "parapet": 0.33}


def _laws(*kinds):
    return "".join(f'\n[[laws]]\njoint = "{k}"\nfriction = {FRICTION[k]}\n' for k in kinds)


def _scenario(structure, *kinds):
    text = textwrap.dedent(structure) + _laws(*kinds) + "\n[output]\nduration = 0.01\n"
    return parse_scenario(text)


def _contacts(model):
    c = Contacts(model.dim)
    detector_for(model).detect(model.body_q0, c)
    n = c.count
    return (c.candidate[:n], c.antagonist[:n], model.law_friction[c.law[:n]], c.frame[:n, 1])


def test_wall_bed_and_head_joints_get_their_laws():
    model = _scenario("""\
        [structure]
        type = "wall"
        courses = 4
        bricks = 3
        [[structure.openings]]
        x = 0.25
        y = 0.065
        width = 0.25
        height = 0.065
        bearing = 0.05
        head_depth = 0.065
        """, "bed", "head", "support").build_model()
    ground = model.body("ground")
    cand, ant, friction, normal = _contacts(model)
    assert len(cand) > 20
    for a, b, mu, n in zip(cand, ant, friction, normal, strict=True):
        names = model.body_name[a], model.body_name[b]
        if ground in (a, b):
            kind = "support"
        elif abs(n[1]) > 0.99 or "opening 1 lintel" in names:
            kind = "bed"  # between courses, or between the lintel and the bricks
        else:
            assert abs(n[0]) > 0.99, names
            kind = "head"
        assert mu == FRICTION[kind], (names, kind)
    groups = set(model.group_names)
    assert {"brick odd", "brick even", "lintel", "ground"} == groups


def test_running_bond_wall_has_the_same_blocks_with_or_without_joint_groups():
    structure = """\
        [structure]
        type = "running_bond_wall"
        courses = 3
        bricks = 2
        """
    jointed = _scenario(structure, "bed", "head", "support").build_model()
    plain = parse_scenario(textwrap.dedent(structure) + textwrap.dedent("""
        [[laws]]
        groups = ["*", "*"]
        friction = 0.6
        [output]
        duration = 0.01
        """)).build_model()
    assert jointed.body_name == plain.body_name
    assert np.array_equal(jointed.vertex_local, plain.vertex_local)
    assert plain.group_names == ("brick", "ground")
    course = {name: int(name.split()[1][1:].split("b")[0]) for name in jointed.body_name
              if name.startswith("brick c")}  # "brick c<course>b<brick>"
    for b, name in enumerate(jointed.body_name):
        if name in course:
            parity = "odd" if course[name] % 2 else "even"
            assert jointed.group_names[jointed.body_group[b]] == f"brick {parity}"
    cand, ant, friction, normal = _contacts(jointed)
    for a, b, mu, n in zip(cand, ant, friction, normal, strict=True):
        kind = ("support" if "ground" in (jointed.body_name[a], jointed.body_name[b])
                else "bed" if abs(n[1]) > 0.99 else "head")
        assert mu == FRICTION[kind]


def test_arch_rings_radial_and_support_joints_get_their_laws():
    model = _scenario("""\
        [structure]
        type = "arch"
        shape = "semicircular"
        span = 2.0
        thickness = 0.3
        voussoirs = 9
        rings = 2
        ring_stagger = true
        """, "radial", "ring", "support", "bed").build_model()
    ring = {b: (1 if name.startswith("ring 1") else 0)
            for b, name in enumerate(model.body_name) if "voussoir" in name}
    cand, ant, friction, _ = _contacts(model)
    kinds = set()
    for a, b, mu in zip(cand, ant, friction, strict=True):
        if a in ring and b in ring:
            kind = "radial" if ring[a] == ring[b] else "ring"
        else:
            kind = "support"
        kinds.add(kind)
        assert mu == FRICTION[kind], (model.body_name[a], model.body_name[b])
    assert kinds == {"radial", "ring", "support"}


def test_semicircular_arch_names_its_joints():
    model = _scenario("""\
        [structure]
        type = "semicircular_arch"
        radius = 1.0
        thickness = 0.15
        voussoirs = 7
        """, "radial", "support").build_model()
    support = model.body("support")
    cand, ant, friction, _ = _contacts(model)
    for a, b, mu in zip(cand, ant, friction, strict=True):
        assert mu == FRICTION["support" if support in (a, b) else "radial"]


def test_generators_record_their_joints():
    builder = sx.ModelBuilder()
    asm = add_wall(builder, courses=2, bricks=2, ground=True, joint_groups=True)
    assert asm.joints == {"head": [("brick odd", "brick odd"), ("brick even", "brick even")],
                          "bed": [("brick odd", "brick even")],
                          "support": [("ground", "brick odd"), ("ground", "brick even")]}
    builder = sx.ModelBuilder()
    asm = add_supported_arch(builder, ArchShape.semicircular(span=2.0, thickness=0.3),
                             voussoirs=5, rings=3)
    assert sorted(asm.joints["ring"]) == [("voussoir ring 1", "voussoir ring 2"),
                                          ("voussoir ring 1", "voussoir ring 3"),
                                          ("voussoir ring 2", "voussoir ring 3")]
    assert len(asm.joints["radial"]) == 3
    assert asm.joints["bed"] == [("pier", "pier")]


def test_without_joint_groups_a_wall_keeps_one_brick_group():
    builder = sx.ModelBuilder()
    asm = add_wall(builder, courses=2, bricks=2, ground=True)
    assert asm.groups == ["ground", "brick"] and asm.joints == {}


@pytest.mark.parametrize(("text", "match"), [
    ('[structure]\ntype = "running_bond_wall"\ncourses = 2\nbricks = 2\n' + _laws("ring"),
     'joint = "ring": the structure has no such joints'),
    ('[structure]\ntype = "running_bond_wall"\ncourses = 2\nbricks = 2\n'
     + _laws("bed", "head", "support")
     + '\n[[laws]]\ngroups = ["brick odd", "brick even"]\nfriction = 0.3\n',
     r'also "bed" joints'),
])
def test_bad_joint_laws_are_refused(text, match):
    scenario = parse_scenario(text + "\n[output]\nduration = 0.01\n")
    with pytest.raises(InputError, match=match):
        scenario.build_model()


def test_blocks_from_a_file_do_not_name_their_joints(tmp_path):
    from saxum.structures import pier, write_blocks

    write_blocks(tmp_path / "pier.json", pier(width=0.5, height=1.0))
    scenario = parse_scenario(f'[structure]\ntype = "blocks"\nfile = "{tmp_path / "pier.json"}"'
                              + _laws("bed") + "\n[output]\nduration = 0.01\n")
    with pytest.raises(InputError, match='structure type "blocks" does not name its joints'):
        scenario.build_model()


def test_a_law_takes_groups_or_a_joint():
    for both in ('groups = ["brick", "brick"]\njoint = "bed"', ""):
        with pytest.raises(InputError, match="either groups"):
            parse_scenario('[structure]\ntype = "running_bond_wall"\ncourses = 2\nbricks = 2\n'
                           f"[[laws]]\n{both}\nfriction = 0.6\n[output]\nduration = 0.01\n")


def test_python_generators_take_a_law_per_joint():
    from saxum.structures import arch, wall

    bed, head = sx.ContactLaw(friction=FRICTION["bed"]), sx.ContactLaw(friction=FRICTION["head"])
    model = wall(courses=3, bricks=2, joint_groups=True, friction=FRICTION["support"],
                 joint_laws={"bed": bed, "head": head})
    cand, ant, friction, normal = _contacts(model)
    ground = model.body("ground")
    for a, b, mu, n in zip(cand, ant, friction, normal, strict=True):
        kind = "support" if ground in (a, b) else "bed" if abs(n[1]) > 0.99 else "head"
        assert mu == FRICTION[kind]
    model = arch(ArchShape.semicircular(span=2.0, thickness=0.3), voussoirs=5, rings=2,
                 joint_laws={"ring": sx.ContactLaw(friction=FRICTION["ring"])})
    assert FRICTION["ring"] in model.law_friction
    with pytest.raises(InputError, match="joint_groups=True"):
        wall(courses=2, bricks=2, joint_laws={"bed": bed})


def test_mortared_wall_example_bonds_its_joints_by_kind():
    from pathlib import Path

    from saxum.mechanism import bond_states
    from saxum.scenario import load_scenario

    example = Path(__file__).resolve().parents[1] / "examples" / "mortared_wall.toml"
    sim = load_scenario(example).build_simulation()
    model = sim.model
    state = sim.initial_state()
    sim.run(state, 0.02)
    c = state.contacts
    n = c.count
    bonds = bond_states(c.law[:n], c.damage[:n], c.history[:n], model.law_kind)
    # at lambda = 0.01 every bond holds (contacts made since the start have none): none has
    # cracked, most are intact; the bonded wall is elastic (its joints are compliant in
    # compression too), and its bricks settle on their bed joints by some micrometres under
    # their weight, unevenly beside the window, which shears a few head joints of this weak
    # mortar past its onset slip c / k_t = 0.5 um (32 of 489 points, measured 2026-11-28)
    assert set(bonds.tolist()) <= {"intact", "damaged", ""}
    assert (bonds == "intact").sum() > 0.85 * n
    ground = model.body("ground")
    f_t = model.law_parameter[c.law[:n], sx.laws.Parameter.F_T]
    bonded = bonds != ""  # not the corners that came to touch (by group, bed law)
    for a, b, strength, normal in zip(c.candidate[:n][bonded], c.antagonist[:n][bonded],
                                      f_t[bonded], c.frame[:n, 1][bonded], strict=True):
        head = ground not in (a, b) and abs(normal[0]) > 0.99 and "lintel" not in (
            model.body_name[a] + model.body_name[b])
        assert strength == (1e3 if head else 2e3)
    assert set(c.law[:n].tolist()) == {0, 1}  # the same law for bed and support joints


# --- the other generators: piers, buttressed walls, bridges, 3D ------------------------------

PIER = '[structure]\ntype = "pier"\nwidth = 0.5\nheight = 1.5\ncourses = 3\n'
BUTTRESSED = ('[structure]\ntype = "buttressed_wall"\nheight = 1.0\nthickness = 0.5\ncourses = 2\n'
              "buttress_width = 0.5\nbuttress_height = 0.5\nblock_length = 0.5\n")
ARCH3D = ('[structure]\ntype = "semicircular_arch_3d"\nradius = 1.0\nthickness = 0.2\n'
          "voussoirs = 5\ndepth = 0.5\n")
WALL3D = '[structure]\ntype = "wall_3d"\ncourses = 2\nlength = 0.5\n'
PIER3D = ('[structure]\ntype = "pier_3d"\nwidth = 0.4\ndepth = 0.4\ncourses = 2\n'
          "course_height = 0.3\n")


@pytest.mark.parametrize(("structure", "points"), [
    # 3 blocks on the ground: 2 bed joints and 1 support joint, 2 points each (2D)
    (PIER, {"bed": 4, "support": 2}),
    # course 1 two blocks (wall and buttress), course 2 one block on the wall's: 1 head, 1
    # bed and 2 support joints, 2 points each
    (BUTTRESSED, {"bed": 2, "head": 2, "support": 4}),
    # 5 voussoirs, 4 joints between them and 2 on the support, 4 corners each (3D)
    (ARCH3D, {"radial": 16, "support": 8}),
    # 0.5 m of 0.25 m bricks: course 1 two bricks (1 head joint), course 2 shifted by half a
    # brick three (2 head joints), 4 overlaps between them, 2 bricks on the ground; 4 corners
    (WALL3D, {"bed": 16, "head": 12, "support": 8}),
    # two blocks per course (1 head joint each), crossed: 4 quarter overlaps, 2 on the ground
    (PIER3D, {"bed": 16, "head": 8, "support": 8}),
])
def test_piers_buttressed_walls_and_3d_structures_name_their_joints(structure, points):
    model = _scenario(structure, *points).build_model()
    friction = _contacts(model)[2]
    found = {kind: int(np.count_nonzero(friction == FRICTION[kind])) for kind in points}
    assert found == points and sum(found.values()) == friction.size


def _bridge_kind(a: str, b: str) -> str:
    """The kind of joint between groups a and b as docs/structures.md gives it for bridges."""
    pair = {a, b}
    if "ground" in pair or ({"voussoir", "pier"} == pair):
        return "support"
    for kind in ("parapet", "fill", "spandrel"):
        if kind in pair:
            return kind
    return {"voussoir": "radial", "pier": "bed"}[a]


@pytest.mark.parametrize("structure", [
    '[structure]\ntype = "arch_bridge"\nshape = "segmental"\nspan = 4.0\nrise = 1.0\n'
    "thickness = 0.4\nvoussoirs = 5\nspans = 2\npier_width = 1.0\npier_height = 1.0\n"
    'abutment_width = 1.0\nfill = "blocks"\nfill_depth = 0.5\npier_courses = 2\n',
    '[structure]\ntype = "bridge_3d"\nspan = 4.0\nrise = 2.0\nthickness = 0.5\nvoussoirs = 5\n'
    "width = 4.0\nspandrel_thickness = 0.6\nabutment_width = 1.5\nabutment_height = 2.0\n"
    "parapet_thickness = 0.4\nparapet_height = 1.0\nparapet_length = 2.5\ncourse_height = 1.0\n"
    "block_length = 2.0\n",
])
def test_bridges_name_their_joints(structure):
    kinds = ("bed", "radial", "support", "spandrel", "fill", "parapet")
    if "arch_bridge" in structure:
        kinds = kinds[:-1]
    model = _scenario(structure, *kinds).build_model()
    cand, ant, friction, _ = _contacts(model)
    group = [model.group_names[g] for g in model.body_group]
    found = set()
    for a, b, mu in zip(cand, ant, friction, strict=True):
        kind = _bridge_kind(group[a], group[b])
        assert mu == FRICTION[kind], (model.body_name[a], model.body_name[b])
        found.add(kind)
    # the 2D bridge has piers of two courses; the 3D one a single abutment block per side
    # (no bed joint)
    assert found == set(kinds) - ({"bed"} if "bridge_3d" in structure else set())


@pytest.mark.parametrize("structure", [BUTTRESSED, WALL3D, PIER3D])
def test_joint_groups_leave_the_blocks_as_they_were(structure):
    """The structures that split their courses into odd and even groups for laws per joint
    have the same blocks without (the dry model as before) and with them."""
    dry = parse_scenario(structure + '[[laws]]\ngroups = ["*", "*"]\nfriction = 0.6\n'
                         "[output]\nduration = 0.01\n").build_model()
    jointed = _scenario(structure, "bed", "head", "support").build_model()
    assert "ground" in dry.group_names and len(dry.group_names) == 2
    assert len(jointed.group_names) == 3
    assert dry.body_name == jointed.body_name
    assert np.array_equal(dry.body_q0, jointed.body_q0)
    assert np.array_equal(dry.vertex_local, jointed.vertex_local)
