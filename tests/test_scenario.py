"""Scenario files: every key round-trips, Python and TOML give the same objects, and every kind
of bad input gets a message naming the key, the line and the allowed values."""

import json
import math
import textwrap

import numpy as np
import pytest

import saxum as sx
from saxum.scenario import (
    Arch3dStructure,
    ArchBridgeStructure,
    ArchOnPiers3dStructure,
    ArchStructure,
    BlocksStructure,
    BondedWallStructure,
    Bridge3dStructure,
    ButtressedWallStructure,
    DetectionSpec,
    EnsembleSpec,
    FemaP695Spec,
    FloodSpec,
    GroundMotionSpec,
    LawSpec,
    Loads,
    MaterialSpec,
    MeshStructure,
    OpeningSpec,
    OutputSpec,
    Pier3dStructure,
    PierStructure,
    PointLoad,
    Scenario,
    Settlement,
    ShapedArchStructure,
    SolverSpec,
    Wall3dStructure,
    WallStructure,
    load_scenario,
    parse_scenario,
)

FULL = textwrap.dedent("""\
    title = "every key"

    [structure]
    type = "running_bond_wall"
    courses = 3
    bricks = 4
    brick_length = 0.3
    brick_height = 0.07
    density = 1900.0

    [[laws]]
    groups = ["brick", "brick"]
    friction = 0.7
    kind = "restitution_coulomb"
    restitution = 0.2

    [[laws]]
    groups = ["brick", "ground"]
    friction = 0.5
    kind = "signorini_coulomb"

    [loads]
    gravity = [0.0, -9.8]
    horizontal_acceleration = 0.5
    load_factor_rate = 0.01

    [[loads.point_loads]]
    block = "brick c3b2"
    magnitude = 10.0
    direction = [1.0, 0.0]

    [[loads.settlements]]
    block = "ground"
    magnitude = 0.001
    direction = [0.0, -1.0]
    rotation = 0.001
    time = 0.5
    profile = "smooth"

    [loads.ground_motion]
    pulse = "mavroeidis_papageorgiou"
    amplitude = 0.5
    velocity = 0.3
    period = 0.4
    gamma = 2.5
    nu = 0.2
    direction = [1.0, 0.5]
    scale = 1.5
    start = 0.01
    end = 0.9
    baseline_correction = true

    [loads.flood]
    level = 0.1
    velocity = 0.5
    tailwater = 0.05
    water_density = 1050.0
    drag_coefficient = 0.8

    [solver]
    dt = 5e-4
    theta = 0.6
    tolerance = 1e-7
    max_iterations = 300
    relaxation = 0.9
    rest_after = 20
    kind = "nlgs"
    threads = 1
    domains = 3
    refine = 4.0
    criterion = "quad"
    warm_start = "start.json"

    [detection]
    alert = 0.002
    margin = 0.003
    interpenetration = 1e-6
    refresh_every = 5
    per_pair = true
    initial_overlap = 2e-6

    [output]
    duration = 0.1
    interval = 0.02
    checkpoint_interval = 0.05
    histories = ["brick c1b1", 2]
""")

PYTHON = Scenario(
    title="every key",
    structure=WallStructure(courses=3, bricks=4, brick_length=0.3, brick_height=0.07,
                            density=1900.0),
    laws=[LawSpec(groups=("brick", "brick"), friction=0.7, kind="restitution_coulomb",
                  restitution=0.2),
          LawSpec(groups=("brick", "ground"), friction=0.5, kind="signorini_coulomb")],
    loads=Loads(gravity=(0.0, -9.8), horizontal_acceleration=0.5, load_factor_rate=0.01,
                point_loads=[PointLoad(block="brick c3b2", magnitude=10.0, direction=(1.0, 0.0))],
                settlements=[Settlement(block="ground", magnitude=0.001, direction=(0.0, -1.0),
                                        rotation=0.001, time=0.5, profile="smooth")],
                ground_motion=GroundMotionSpec(
                    pulse="mavroeidis_papageorgiou", amplitude=0.5, velocity=0.3, period=0.4,
                    gamma=2.5, nu=0.2, direction=(1.0, 0.5), scale=1.5, start=0.01, end=0.9,
                    baseline_correction=True),
                flood=FloodSpec(level=0.1, velocity=0.5, tailwater=0.05, water_density=1050.0,
                                drag_coefficient=0.8)),
    solver=SolverSpec(dt=5e-4, theta=0.6, tolerance=1e-7, max_iterations=300, relaxation=0.9,
                      rest_after=20, kind="nlgs", threads=1, domains=3, refine=4.0,
                      criterion="quad", warm_start="start.json"),
    detection=DetectionSpec(alert=0.002, margin=0.003, interpenetration=1e-6, refresh_every=5,
                            per_pair=True, initial_overlap=2e-6),
    output=OutputSpec(duration=0.1, interval=0.02, checkpoint_interval=0.05,
                      histories=["brick c1b1", 2]),
)


def test_every_key_is_read_and_equals_the_python_objects():
    sc = parse_scenario(FULL)
    assert sc == PYTHON
    # and every value differs from its default, so none was silently dropped
    for part in ("structure", "loads", "solver", "detection", "output"):
        spec = getattr(sc, part)
        default = type(spec).model_validate(
            {k: v for k, v in spec.model_dump().items()
             if type(spec).model_fields[k].is_required() or k == "type"})
        for key, field in type(spec).model_fields.items():
            if key == "horizontal_azimuth":
                continue  # 3D only (tests/test_scenario3d.py)
            if key != "type" and not field.is_required():
                assert getattr(spec, key) != getattr(default, key), f"{part}.{key}"


def test_json_round_trip_keeps_every_key():
    sc = parse_scenario(FULL)
    assert Scenario.model_validate_json(sc.model_dump_json()) == sc


def test_scenario_builds_the_model_and_simulation_it_describes():
    sc = parse_scenario(FULL)
    sim = sc.build_simulation()
    m = sim.model
    assert m.body_count == 1 + 3 * 4 + 1  # ground + bricks (the middle course has 5 pieces)
    assert np.allclose(m.gravity, (0.0, -9.8))
    law = m.laws[m.group_law[m.group_names.index("brick"), m.group_names.index("brick")]]
    assert law == sx.ContactLaw(0.7, sx.LawKind.RESTITUTION_COULOMB, 0.2)
    assert sim.integrator.dt == 5e-4 and sim.integrator.theta == 0.6
    assert (sim.solver.tolerance, sim.solver.max_iterations, sim.solver.relaxation,
            sim.solver.rest_after, sim.solver.threads, sim.solver.domains,
            sim.solver.criterion, sim.solver.refine) == (1e-7, 300, 0.9, 20, 1, 3, "quad", 4.0)
    assert (sim.detector.alert, sim.detector.margin, sim.detector.interpenetration,
            sim.detector.refresh_every) == (0.002, 0.003, 1e-6, 5)
    assert sim.detector.initial_overlap == pytest.approx(2e-6, rel=1e-15)
    ramp, ground = m.accelerations
    assert ramp(2.0) == pytest.approx((0.5 + 0.01 * 9.8 * 2.0, 0.0))
    motion = sc.loads.ground_motion.motion()  # the pulse, trimmed, scaled, corrected
    assert motion.time[0] == 0.0 and motion.time[-1] == pytest.approx(0.89)
    assert motion.velocity()[-1] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert ground(0.2) == pytest.approx(tuple(-a for a in motion.acceleration_at(0.2)))


def test_override_sets_nested_keys():
    sc = parse_scenario(FULL, overrides=["solver.dt=1e-4", "structure.courses=5",
                                         'title="changed"'])
    assert sc.solver.dt == 1e-4 and sc.structure.courses == 5 and sc.title == "changed"


def test_override_with_nothing_removes_a_key():
    """`--set KEY=` / `--unset KEY`: the key's default applies (none for a table)."""
    sc = parse_scenario(FULL, overrides=["loads.ground_motion=", "solver.dt="])
    assert sc.loads.ground_motion is None and sc.solver.dt == 1e-3
    assert "the scenario has no 'loads.flood' to remove" in _error(
        ARCH, overrides=["loads.flood="])
    assert "--unset 'solver.dtt'" in _error(FULL, overrides=["solver.dtt="])


def test_cli_unset_is_an_override_in_order():
    import saxum.cli as cli

    args = cli._parser().parse_args(["run", "s.toml", "--set", "solver.dt=1e-4", "--unset",
                                     "loads.ground_motion"])
    assert args.set == ["solver.dt=1e-4", "loads.ground_motion="]


def test_blocks_file_relative_to_the_scenario(tmp_path):
    (tmp_path / "blocks.json").write_text(json.dumps({"blocks": [
        {"vertices": [[-1, -0.1], [1, -0.1], [1, 0], [-1, 0]], "kind": "fixed",
         "group": "ground", "name": "ground"},
        {"vertices": [[0, 0], [0, 0.5], [0.2, 0.5], [0.2, 0]], "density": 2500.0}]}))
    (tmp_path / "s.toml").write_text(textwrap.dedent("""\
        [structure]
        type = "blocks"
        file = "blocks.json"
        [[laws]]
        groups = ["block", "ground"]
        friction = 0.6
        [[laws]]
        groups = ["block", "block"]
        friction = 0.6
        [output]
        duration = 0.01
    """))
    sc = load_scenario(tmp_path / "s.toml")
    assert isinstance(sc.structure, BlocksStructure)
    m = sc.build_model()
    assert m.body_name == ("ground", "block 2")  # unnamed blocks: "block K", K from 1
    assert m.body_mass[1] == pytest.approx(0.1 * 2500.0)


def _error(text, **kw):
    with pytest.raises(sx.InputError) as info:
        parse_scenario(text, **kw)
    return str(info.value)


ARCH = textwrap.dedent("""\
    [structure]
    type = "semicircular_arch"
    radius = 1.0
    thickness = 0.15
    voussoirs = 9

    [[laws]]
    groups = ["voussoir", "voussoir"]
    friction = 0.6

    [[laws]]
    groups = ["voussoir", "support"]
    friction = 0.6

    [output]
    duration = 0.1
""")


@pytest.mark.parametrize("edit, expected", [
    (("radius = 1.0", "radius = 1.0\ncolour = 3"),
     ["line 4: structure.colour: unknown key",
      "allowed keys here: type, radius, thickness, voussoirs, density"]),
    (("voussoirs = 9", 'voussoirs = "nine"'),
     ["line 5: structure.voussoirs", "valid integer", "'nine'"]),
    (("voussoirs = 9", "voussoirs = 0"),
     ["line 5: structure.voussoirs", "greater than or equal to 1"]),
    (('friction = 0.6\n\n[[laws]]\ngroups = ["voussoir", "support"]',
      'friction = 0.6\n\n[[laws]]\ngroups = ["voussoir", "support"]\nkind = "sticky"'),
     ["laws[1].kind", "'gap_signorini_coulomb', 'elastic', 'viscous', 'cohesive' or 'none'",
      "line 13"]),
    (("friction = 0.6", "friction = -0.2"),
     ["line 9: laws[0].friction: Input should be greater than or equal to 0"]),
    (("duration = 0.1", "interval = 0.1"), ["output.duration: missing (required)"]),
    (('type = "semicircular_arch"', 'type = "dome"'),
     ["structure", "'semicircular_arch', 'running_bond_wall', 'blocks'"]),
    (("[output]", "[solver]\ndt = -1e-3\n[output]"),
     ["solver.dt: Input should be greater than 0", "(got -0.001)"]),
    (("[output]", "[solver]\ntheta = 0.3\n[output]"), ["solver.theta", "0.5"]),
])
def test_bad_scenarios_name_key_line_and_allowed_values(edit, expected):
    old, new = edit
    assert old in ARCH
    message = _error(ARCH.replace(old, new, 1))
    for part in expected:
        assert part in message, (part, message)


def test_syntax_error_names_the_line():
    message = _error(ARCH.replace("radius = 1.0", "radius = = 1.0"), source="s.toml")
    assert "s.toml: not valid TOML" in message and "line 3" in message


def test_missing_files_are_named(tmp_path):
    with pytest.raises(sx.InputError, match="no scenario file"):
        load_scenario(tmp_path / "absent.toml")
    sc = parse_scenario(ARCH.replace(
        'type = "semicircular_arch"\nradius = 1.0\nthickness = 0.15\nvoussoirs = 9',
        'type = "blocks"\nfile = "nowhere.json"'), base_dir=tmp_path)
    with pytest.raises(sx.InputError, match="no blocks file at .*nowhere.json"):
        sc.build_model()


def test_bad_block_in_a_blocks_file_is_named(tmp_path):
    path = tmp_path / "b.json"
    path.write_text(json.dumps({"blocks": [{"vertices": [[0, 0], [1, 0], [1, 1]], "density": 1e3},
                                           {"vertices": [[0, 0], [1, 0]]}]}))
    sc = Scenario(structure=BlocksStructure(file=path),
                  laws=[LawSpec(groups=("block", "block"), friction=0.5)],
                  output=OutputSpec(duration=0.1))
    with pytest.raises(sx.InputError, match=r"blocks\[1\]: .*at least 3 vertices"):
        sc.build_model()


def test_bad_override_is_named():
    assert "expected KEY=VALUE" in _error(ARCH, overrides=["solver.dt"])
    assert "--set solver.dt" in _error(ARCH, overrides=["solver.dt=0"])
    assert "loads.point_loads has 0 entries, so no [0] (counted from 0)" in _error(
        ARCH, overrides=["loads.point_loads[0].magnitude=5"])
    assert "laws has 2 entries, so no [2]" in _error(ARCH, overrides=["laws[2].friction=1"])
    assert "output.duration is not a table with keys, so it has no 'x'" in _error(
        ARCH, overrides=["output.duration.x=1"])


def test_a_scenario_given_as_results_file_is_named(tmp_path):
    from saxum.results import Results

    (tmp_path / "arch.toml").write_text(ARCH)
    with pytest.raises(sx.InputError, match=r"arch.toml is not a readable HDF5 file: .* it "
                                            r"looks like a scenario: run it first \(saxum run"):
        Results(tmp_path / "arch.toml")


def test_a_results_file_given_as_scenario_is_named(tmp_path):
    binary = tmp_path / "run.h5"
    binary.write_bytes(b"\x89HDF\r\n\x1a\n\x00\x00")
    with pytest.raises(sx.InputError, match="run.h5 is not a scenario .* saxum info"):
        load_scenario(binary)


def test_python_and_toml_arch_are_the_same_scenario():
    py = Scenario(structure=ArchStructure(radius=1.0, thickness=0.15, voussoirs=9),
                  laws=[LawSpec(groups=("voussoir", "voussoir"), friction=0.6),
                        LawSpec(groups=("voussoir", "support"), friction=0.6)],
                  output=OutputSpec(duration=0.1))
    assert parse_scenario(ARCH) == py


def test_docs_describe_every_key():
    """docs/scenario.md has a table row for every key of every part of a scenario."""
    from pathlib import Path

    doc = (Path(__file__).parents[1] / "docs" / "scenario.md").read_text()
    for model in (Scenario, ArchStructure, WallStructure, BlocksStructure, ShapedArchStructure,
                  BondedWallStructure, OpeningSpec, PierStructure, ButtressedWallStructure,
                  ArchBridgeStructure, Arch3dStructure, ArchOnPiers3dStructure,
                  Wall3dStructure, Pier3dStructure,
                  Bridge3dStructure, MeshStructure, LawSpec, MaterialSpec, Loads, PointLoad,
                  Settlement,
                  GroundMotionSpec, FemaP695Spec, FloodSpec, SolverSpec, DetectionSpec,
                  OutputSpec, EnsembleSpec):
        for key in model.model_fields:
            if key != "type":
                assert f"| `{key}` |" in doc, f"{model.__name__}.{key} is not documented"
    for tag in ("semicircular_arch", "running_bond_wall", "blocks", "arch", "wall", "pier",
                "buttressed_wall", "arch_bridge", "semicircular_arch_3d", "arch_3d", "wall_3d",
                "pier_3d", "bridge_3d", "mesh"):
        assert f'`type = "{tag}"`' in doc


def test_point_loads_and_settlements():
    text = ARCH + textwrap.dedent("""\
        [[loads.point_loads]]
        block = "voussoir 5"
        magnitude = 1000.0
        direction = [3.0, -4.0]
        [[loads.settlements]]
        block = "support"
        magnitude = 0.02
        rotation = 0.01
        time = 0.5
    """)
    sc = parse_scenario(text, overrides=["loads.point_loads[0].magnitude=2000"])
    assert sc.loads.point_loads[0] == PointLoad(block="voussoir 5", magnitude=2000.0,
                                                direction=(3.0, -4.0))
    m = sc.build_model()
    (bodies, force), = m.forces
    assert [m.body_name[b] for b in bodies] == ["voussoir 5"]
    assert force(0.3) == pytest.approx((1200.0, -1600.0, 0.0))
    support = m.body("support")
    assert m.body_kind[support] == sx.BodyKind.DRIVEN
    motion = m.motions[m.body_motion[support]]
    assert motion(0.1) == pytest.approx((0.0, -0.04, 0.02)) and motion(0.6) == (0.0, 0.0, 0.0)
    smooth = parse_scenario(text, overrides=["loads.settlements[0].profile=smooth"]).build_model()
    motion = smooth.motions[smooth.body_motion[support]]
    # (pi/2) sin(pi t / T) times the mean rate: zero at both ends, pi/2 times it mid-way
    assert motion(0.0) == pytest.approx((0.0, 0.0, 0.0))
    assert motion(0.25) == pytest.approx((0.0, -0.04 * math.pi / 2, 0.02 * math.pi / 2))
    assert motion(0.5) == (0.0, 0.0, 0.0)


def test_bad_loads_are_named():
    bad_block = ARCH + '[[loads.point_loads]]\nblock = "keystone"\nmagnitude = 1.0\n'
    with pytest.raises(sx.InputError, match="no block named 'keystone'"):
        parse_scenario(bad_block).build_model()
    unknown = ARCH + '[[loads.point_loads]]\nblock = "voussoir 1"\nmagnitude = 1.0\nsize = 2\n'
    message = _error(unknown)
    assert "loads.point_loads[0].size: unknown key; allowed keys here: block, magnitude" in message
    assert "line 20" in message
    assert "--set 'laws[5].friction=1': laws has 2 entries, so no [5]" in _error(
        ARCH, overrides=["laws[5].friction=1"])


def test_ground_motion_driving_the_supports(tmp_path):
    (tmp_path / "rec.csv").write_text("# units: g\n0 0\n0.01 0.1\n0.02 0\n")
    text = ARCH + textwrap.dedent("""\
        [loads.ground_motion]
        file = "rec.csv"
        units = "m/s^2"
        apply = "driven"
        supports = ["support"]
    """)
    sc = parse_scenario(text, base_dir=tmp_path)
    assert sc.loads.ground_motion == GroundMotionSpec(
        file=tmp_path / "rec.csv", units="m/s^2", apply="driven", supports=["support"])
    m = sc.build_model()
    support = m.body("support")
    assert m.body_kind[support] == sx.BodyKind.DRIVEN
    motion = m.motions[m.body_motion[support]]
    assert motion(0.01)[0] == pytest.approx(0.5 * 0.01 * 0.1)  # m/s^2 units given
    assert "give one of file (a record), fema_p695 or pulse" in _error(
        ARCH + '[loads.ground_motion]\npulse = "ricker"\nfile = "x.csv"\n')
    assert "needs the names of the supports" in _error(
        ARCH + '[loads.ground_motion]\npulse = "ricker"\napply = "driven"\n')


def test_harmonic_ground_motion_in_a_scenario():
    text = ARCH + textwrap.dedent("""\
        [loads.ground_motion]
        pulse = "harmonic"
        amplitude = 3.0
        period = 0.5
        cycles = 4
        ramp = 2.0
    """)
    motion = parse_scenario(text).loads.ground_motion.motion()
    assert motion.duration == pytest.approx(2.0)
    assert motion.acceleration_at(1.625)[0] == pytest.approx(3.0 * 1.625 / 2.0, rel=1e-3)
    assert "ramp: Input should be greater than or equal to 0" in _error(
        text.replace("ramp = 2.0", "ramp = -1.0"))
