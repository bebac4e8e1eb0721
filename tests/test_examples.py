"""The examples run against the current API and give their documented answers."""

import importlib.util
from pathlib import Path

import pytest

from saxum import BodyKind
from saxum.lmgc90 import import_lmgc90

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_arch_example_stands():
    # t/R = 0.15 is well above the minimum thickness 0.1075 (Heyman 1969): the crown must not
    # move by more than 1e-4 R = 0.2 mm.
    assert _load("arch_standing").main(duration=0.5) < 2e-4


def test_lmgc90_arch_example():
    # LMGC90's arche_plein_ceintre_2D: joints open by pi/100; with its IQS_CLB_g0 law the
    # open joints act as closed and the arch stands (below 1e-6 m: 0.12 um, the drift of
    # NLGS at Quad 1e-4), without it (IQS_CLB) the crown falls freely for the 0.1 s of
    # LMGC90's run (its joints stay open: the fall closes them by a seventh of it),
    # g t^2 / 2 exactly with theta = 0.5 under constant gravity (1e-9: round-off of 100
    # steps)
    example = _load("lmgc90_arch")
    g = -float(example.arch().gravity[1])
    g0, plain = example.main(duration=0.1).values()
    assert abs(g0) < 1e-6
    assert plain == pytest.approx(0.5 * g * 0.1**2, rel=1e-9)


def test_wall_example_stays_at_rest():
    assert _load("wall_at_rest").main(duration=0.2) < 1e-4


def test_demo_writes_picture(tmp_path):
    from saxum.cli import main

    out = tmp_path / "arch.png"
    assert main(["demo", "arch", "--duration", "1.0", "-o", str(out)]) == 0
    assert out.stat().st_size > 10_000


@pytest.mark.parametrize("name, bodies", [("pointed_arch", 1 + 4 + 13), ("bridge", 60)])
def test_example_scenarios_stand_under_their_own_weight(name, bodies):
    """The bundled structures stand: judged at rest (unbalanced force ratio < 1e-4 for
    0.05 s, saxum.collapse) before any block has moved by 1 % of the smallest block's size."""
    from saxum.collapse import run_trial
    from saxum.scenario import load_scenario

    sim = load_scenario(EXAMPLES / f"{name}.toml").build_simulation()
    assert sim.model.body_count == bodies
    trial = run_trial(sim)
    assert not trial.collapsed and trial.displacement < 1e-6


def test_earthquake_examples_run(tmp_path):
    """The shaking-table arch and the two Burnum scenarios, shortened to a few steps."""
    from saxum.cli import main

    for name in ("shake_table_arch", "burnum_harmonic", "burnum_record"):
        out = tmp_path / f"{name}.h5"
        assert main(["run", str(EXAMPLES / f"{name}.toml"), "--quiet", "-o", str(out),
                     "--set", "output.duration=0.04"]) == 0, name
        assert out.stat().st_size > 0


def test_shake_table_arch_collapse_curve_point():
    """One period of the shaking-table example, bracketed close to the answer: a 1 s one-sine
    pulse collapses the arch a little above its static load factor (0.150,
    tests/validation/test_arch_pulse.py) with a four-hinge mechanism, one hinge at a
    springing (+-90 degrees from the crown)."""
    _, rows = _load("shake_table_arch").main(periods=(1.0,), tolerance=0.02, stands=1.6,
                                             collapses=1.8, duration=1.0, processes=1,
                                             static=False, picture=None)
    (period, amplitude, _, angles), = rows
    assert 0.150 <= amplitude <= 0.2
    assert len(angles) == 4 and 90.0 in map(abs, angles)


def test_flood_bridge_parapet_goes_at_the_statics_values():
    """The first two cases of the flood example (docs/flood.md): the upstream parapet
    (t x h = 0.4 x 1.0 m, rho_s = 2400 kg/m^3 on the deck, mu = 0.6, C_d = 1.4) fails where
    the statics of a rigid block under drag 1/2 rho_w C_d U^2 (wet height) and buoyancy put
    it: sliding at mu g (rho_s t h - rho_w t d) = 1/2 rho_w C_d U^2 d under a 3 m/s flow,
    overturning about its toe at 1/2 rho_w C_d U^2 h^2/2 = g (rho_s - rho_w) t h t/2 with
    the water 1 m over the deck (sliding and the other mode need more); within 1 %."""
    import math

    from saxum.structures.blockfile import read_blocks

    fb = _load("flood_bridge")
    stored = read_blocks(EXAMPLES / "flood-bridge-section.json")
    model = fb.section()
    assert [s.name for s in stored] == list(model.body_name)
    for k, spec in enumerate(stored):
        assert spec.vertices == pytest.approx(model.vertices(k), abs=1e-12)

    g, rho_w, rho_s, mu, cd = 9.81, 1000.0, fb.STONE, 0.6, 1.4
    t, h = fb.PARAPET
    drag = 0.5 * rho_w * cd * 3.0**2  # [Pa] at 3 m/s
    slide = mu * g * rho_s * t * h / (drag + mu * g * rho_w * t)
    overturn = (-g * rho_w * t * t / 2 + math.sqrt((g * rho_w * t * t / 2) ** 2
                + 2 * drag * g * rho_s * t * t * h)) / drag  # drag d^2/2 = g (.. - ..) t/2
    level = fb.DECK + min(slide, overturn)
    u_overturn = math.sqrt(g * (rho_s - rho_w) * t * t / (0.5 * rho_w * cd * h))
    u_slide = math.sqrt(mu * g * (rho_s - rho_w) * t / (0.5 * rho_w * cd))
    assert slide < overturn and u_overturn < u_slide
    found = fb.main(tolerance=0.004, cases=tuple(fb.CASES)[:2])
    (by_level, mech_level), (by_velocity, mech_velocity) = found.values()
    assert by_level.value == pytest.approx(level, rel=0.01)
    assert by_velocity.value == pytest.approx(min(u_overturn, u_slide), rel=0.01)
    assert mech_level.moving == mech_velocity.moving == ["upstream parapet"]
    assert [j.bodies for j in mech_level.sliding] == [("upstream wall c6", "upstream parapet")]
    assert [j.hinge_point for j in mech_velocity.hinges] == [pytest.approx((0.4 + 1.2, 7.0))]


def test_flood_bridge_blocked_by_debris_slides_at_the_statics_level():
    """The fourth case of the flood example: arches blocked, the head falling linearly across
    the section from the upstream level h to a tailwater at the springing (4 m). On the
    section's outline (joints inside cancel) the water gives a thrust, the uplift on its base
    and the weight of the water on the cutwaters and deck; the section slides on the river
    bed (mu = 0.6) where thrust = mu (weight + water on top - uplift): h = 10.18 m by
    quadrature here (overturning about the downstream toe would need 14.3 m); within 1 %."""
    from scipy.integrate import quad
    from scipy.optimize import brentq

    fb = _load("flood_bridge")
    g, rho_w, mu, tail = 9.81, 1000.0, 0.6, fb.PIER_HEIGHT
    x_up, x_down = fb.UPSTREAM_CUTWATER, fb.UPSTREAM_CUTWATER + fb.WIDTH
    length = x_down + fb.DOWNSTREAM_CUTWATER
    weight = g * (fb.STONE * length * fb.PIER_HEIGHT
                  + fb.STONE * 2 * fb.WALL * fb.SPANDREL_HEIGHT
                  + fb.FILL * (fb.WIDTH - 2 * fb.WALL) * fb.SPANDREL_HEIGHT)

    def unbalanced(h):
        def p(x, y):
            return rho_w * g * max(h + (tail - h) * x / length - y, 0.0)

        def along_y(x, y0, y1):
            return quad(lambda y: p(x, y), y0, y1)[0]

        def along_x(y, x0, x1):
            return quad(lambda x: p(x, y), x0, x1)[0]

        thrust = (along_y(0.0, 0.0, 4.0) + along_y(x_up, 4.0, fb.DECK)
                  - along_y(x_down, 4.0, fb.DECK) - along_y(length, 0.0, 4.0))
        on_top = (along_x(4.0, 0.0, x_up) + along_x(4.0, x_down, length)
                  + along_x(fb.DECK, x_up, x_down))
        return thrust - mu * (weight + on_top - along_x(0.0, 0.0, length))

    expected = brentq(unbalanced, 5.0, 20.0)
    name = "arches blocked by debris, tailwater at the springing"
    ((result, mech),) = fb.main(tolerance=0.004, cases=(name,)).values()
    assert result.value == pytest.approx(expected, rel=0.01)
    assert len(mech.moving) == 73  # every free block: the whole section slides
    assert {j.bodies[0] for j in mech.sliding} == {"river bed"}


def test_flood_bridge3d_has_the_2d_sections_cross_section_and_stands():
    """The 3D flood example's bridge (docs/flood.md, "In 3D: the whole bridge") has the 2D
    section's walls, parapets, materials and road height, so that its parapet statics are
    the 2D ones (tests/validation/test_flood_bridge3d.py checks the 3D parapet against them);
    under its scenario's flood (2 m of water at 3 m/s) it stands."""
    from saxum.collapse import run_trial

    fb, fb3 = _load("flood_bridge"), _load("flood_bridge3d")
    structure = fb3.load_scenario(fb3.SCENARIO).structure
    assert (structure.width, structure.spandrel_thickness) == (fb.WIDTH, fb.WALL)
    assert (structure.parapet_thickness, structure.parapet_height) == fb.PARAPET
    assert (structure.density, structure.fill_density) == (fb.STONE, fb.FILL)
    # sums of heights of a few metres: one rounding each (~1e-15 m), 1e-12 m allowed
    deck = structure.abutment_height + structure.spandrel_height
    assert deck == pytest.approx(fb3.DECK, abs=1e-12) and fb.DECK == pytest.approx(fb3.DECK,
                                                                                  abs=1e-12)
    sim = fb3.scenario([]).build_simulation()
    assert sim.model.body_count == 59
    trial = run_trial(sim, criterion=fb3.CRITERION)
    assert not trial.collapsed and trial.displacement < 1e-6


@pytest.mark.parametrize("name, keyword, written", [
    ("flood_bridge", "picture", "flood-bridge.png"),
    ("flood_bridge3d", "pictures", None),
    ("shake_table_arch", "picture", "shake_table_arch-curve.png"),
])
def test_example_scripts_write_into_the_working_directory_unless_asked(
        name, keyword, written, tmp_path, monkeypatch):
    """Run as scripts, the examples write their pictures (and flood_bridge its blocks) to the
    current directory, or to --out: never over the repository's tracked files."""
    module = _load(name)
    calls = []
    monkeypatch.setattr(module, "main", lambda **options: calls.append(options))
    monkeypatch.chdir(tmp_path)
    module.cli([])
    module.cli(["--out", "pictures"])
    here, asked = (Path(c[keyword]).resolve() for c in calls)
    expected = [tmp_path, tmp_path / "pictures"]
    if written is not None:
        expected = [folder / written for folder in expected]
    assert [here, asked] == expected
    if name == "flood_bridge":
        assert (tmp_path / "flood-bridge-section.json").is_file()
        assert (tmp_path / "pictures" / "flood-bridge-section.json").is_file()


def test_lmgc90_vault_example_reads_stones_and_writes_polyf(tmp_path):
    # two cubes 0.1 m across in abeille2.dat's layout (a stone: its faces, a face: its
    # points {x, y, z}), one with its centre below the springing height (fixed), one above
    example = _load("lmgc90_vault")

    def stone(z0):
        corners = [(x, y, z0 + z) for x in (0.0, 0.1) for y in (0.0, 0.1) for z in (0.0, 0.1)]
        faces = [[c for c in corners if c[axis] == side] for axis in range(3)
                 for side in sorted({c[axis] for c in corners})]
        return _braces(_braces(_braces(repr(x) for x in c) for c in f) for f in faces)

    source = tmp_path / "stones.dat"
    source.write_text(stone(0.5) + "\n" + stone(0.9) + "\n", encoding="utf-8")
    stones = example.read_stones(source)
    assert [len(s) for s in stones] == [8, 8]
    imported = import_lmgc90(example.main(source, tmp_path / "DATBOX"))
    kinds = [blk.kind for blk in imported.blocks]
    assert kinds == [BodyKind.FIXED, BodyKind.FREE]
    assert "POLYF" in (tmp_path / "DATBOX" / "BODIES.DAT").read_text()


def _braces(items) -> str:
    return "{" + ", ".join(items) + "}"
