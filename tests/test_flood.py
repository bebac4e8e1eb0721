"""saxum.flood: the pressure integrals against an independent clipped-polygon computation, the
head drop across a wall, level series, the field-load hook of the time loop, scenario keys and
bad input (each message names the parameter or key)."""

import math
import textwrap

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import saxum as sx
from saxum.flood import FloodLoad
from saxum.scenario import FloodSpec, parse_scenario

G = 9.81


def _model(polygons, *, load=None):
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-9.0, -1.0), (9.0, -1.0), (9.0, -0.5), (-9.0, -0.5)],
                kind=sx.BodyKind.FIXED, group="ground", name="ground")
    for poly in polygons:
        b.add_block(poly, density=2400.0)
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    if load is not None:
        b.add_field_load(load)
    return b.finalize()


def _below(poly, level):
    """The part of a convex polygon below y = level (Sutherland-Hodgman, one half-plane)."""
    out = []
    for a, b in zip(poly, np.roll(poly, -1, axis=0), strict=True):
        if a[1] < level:
            out.append(a)
        if (a[1] < level) != (b[1] < level):
            out.append(a + (level - a[1]) / (b[1] - a[1]) * (b - a))
    return np.array(out)


def _area_centroid(poly):
    x, y = poly.T
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    area = 0.5 * cross.sum()
    return area, np.array([((x + x1) * cross).sum(), ((y + y1) * cross).sum()]) / (6 * area)


@given(st.integers(3, 9), st.floats(0.2, 3.0), st.floats(0.2, 3.0), st.floats(-3.2, 3.2),
       st.floats(-0.5, 1.5), st.integers(0, 2**31 - 1))
def test_pressure_integrals_are_buoyancy_of_the_submerged_part(sides, a, b, angle, level,
                                                               seed):
    """Still water: the edge integrals of p = rho_w g (h - y) give rho_w g A_sub upward
    through the centroid of the submerged part, for any convex block at any angle and level
    (the part under water computed here by clipping the polygon)."""
    rng = np.random.default_rng(seed)
    step = 2 * np.pi / sides  # points on an ellipse, in order: a convex polygon
    phi = step * (np.arange(sides) + rng.uniform(0.0, 0.8, sides))
    poly = np.column_stack((a * np.cos(phi), 1.0 + b * np.sin(phi)))
    area = _area_centroid(poly)[0]
    model = _model([poly])
    q = model.body_q0.copy()
    q[1, 2] = angle
    depth = level * b  # from below the block to above it
    load = FloodLoad(level=1.0 + depth)
    fx, fy, torque = load.forces(model, q)[1]
    wet = _below(model.vertices(1, q), 1.0 + depth)
    scale = 1000.0 * G * area
    if len(wet) < 3:
        assert abs(fx) + abs(fy) + abs(torque) <= 1e-9 * scale * max(a, b)
        return
    sub, centre = _area_centroid(wet)
    assert fx == pytest.approx(0.0, abs=1e-9 * scale)
    assert fy == pytest.approx(1000.0 * G * sub, abs=1e-9 * scale)
    lever = centre[0] - q[1, 0]
    assert torque == pytest.approx(lever * 1000.0 * G * sub, abs=1e-9 * scale * max(a, b))


def test_head_drop_across_a_wall_gives_thrust_and_triangular_uplift():
    """Level d upstream, tailwater at the foot: thrust rho g d^2/2 on the upstream face,
    uplift rho g d b/2 at b/3 from the heel (the triangle of gravity-dam practice); both
    follow the wall when it slides."""
    b, h, d = 0.6, 2.0, 1.5
    load = FloodLoad(level=d, tailwater=0.0)
    model = _model([[(0.0, 0.0), (b, 0.0), (b, h), (0.0, h)]], load=load)
    rho_g = 1000.0 * G
    thrust, uplift = rho_g * d * d / 2, rho_g * d * b / 2
    torque = thrust * (h / 2 - d / 3) + uplift * (b / 3 - b / 2)  # about the centre
    expected = [thrust, uplift, torque]
    assert load.forces(model)[1] == pytest.approx(expected, rel=1e-12)
    q = model.body_q0.copy()
    q[1, 0] += 0.37
    assert load.forces(model, q)[1] == pytest.approx(expected, rel=1e-12)


def test_level_series_and_velocity_series_are_linear_in_time():
    load = FloodLoad(level_series=[(0.0, 0.0), (10.0, 2.0)],
                     velocity_series=[(0.0, 0.0), (5.0, 3.0)])
    assert load.heads(-1.0) == (0.0, 0.0)
    # interpolated or held past the ends: a few operations on values of ~1 (round-off ~1e-16),
    # 1e-12 allowed
    assert load.heads(2.5) == pytest.approx((0.5, 0.5), abs=1e-12)
    assert load.heads(20.0) == pytest.approx((2.0, 2.0), abs=1e-12)
    assert load.velocity.at(2.5) == pytest.approx(1.5, abs=1e-12)
    assert load.velocity.at(9.0) == pytest.approx(3.0, abs=1e-12)
    model = _model([[(0.0, 0.0), (1.0, 0.0), (1.0, 3.0), (0.0, 3.0)]])
    f = load.forces(model, t=5.0)[1]
    assert f[1] == pytest.approx(1000.0 * G * 1.0)  # 1 m of water on a 1 m wide block
    assert f[0] == pytest.approx(0.5 * 1000.0 * 1.4 * 9.0 * 1.0)


class _Recorder:
    """A field load that records where and when it is evaluated and pushes every free block
    with 10 N per metre of its abscissa."""

    def __init__(self):
        self.calls = []

    def check(self, model):
        self.checked = model.body_count

    def add(self, model, q, t, out):
        self.calls.append((q[:, 0].copy(), t))
        out[:, 0] += np.where(model.body_kind == sx.BodyKind.FREE, 10.0 * q[:, 0], 0.0)


def test_field_loads_are_explicit_at_the_start_of_the_step():
    b = sx.ModelBuilder(gravity=(0.0, 0.0))
    block = b.add_block([(1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0)], density=100.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    load = _Recorder()
    b.add_field_load(load)
    model = b.finalize()
    assert load.checked == 1
    dt, theta = 0.01, 0.6
    sim = sx.Simulation(model, dt=dt, theta=theta)
    state = sim.initial_state()
    x0 = state.body_q[block, 0]
    sim.step(state)
    sim.step(state)
    (first, t0), (second, t1) = load.calls
    assert t0 == pytest.approx(theta * dt) and t1 == pytest.approx(dt + theta * dt)
    assert first[block] == x0 and second[block] > x0  # q at the start of each step
    mass = 100.0
    v1 = dt * 10.0 * x0 / mass
    assert state.body_v[block, 0] == pytest.approx(v1 + dt * 10.0 * second[block] / mass)
    force = np.zeros((1, 3))
    sim.external_force(0.0, force, state.body_q)
    assert force[0, 0] == pytest.approx(10.0 * state.body_q[block, 0])
    with pytest.raises(sx.InputError, match="add_field_load"):
        sx.ModelBuilder().add_field_load(lambda t: 0)


SCENARIO = textwrap.dedent("""\
    [structure]
    type = "running_bond_wall"
    courses = 4
    bricks = 3
    [[laws]]
    groups = ["brick", "brick"]
    friction = 0.7
    [[laws]]
    groups = ["brick", "ground"]
    friction = 0.7
    [output]
    duration = 0.1
    [loads.flood]
""")


def _error(text, overrides=()):
    with pytest.raises(sx.InputError) as err:
        parse_scenario(text, overrides=overrides).build_model()
    return str(err.value)


def test_scenario_flood_builds_the_load():
    sc = parse_scenario(SCENARIO + "level = 0.2\nvelocity = 1.5\n",
                        overrides=["loads.flood.level=0.15"])
    assert sc.loads.flood == FloodSpec(level=0.15, velocity=1.5)
    model = sc.build_model()
    (load,) = model.field_loads
    assert isinstance(load, FloodLoad) and load.heads(0.0) == (0.15, 0.15)
    assert load.velocity.at(0.0) == 1.5 and load.drag_coefficient == 1.4


@pytest.mark.parametrize("extra, expected", [
    ("level = 0.1\ndrag_coefficient = -0.5\n",
     "line 15: loads.flood.drag_coefficient: Input should be greater than or equal to 0"),
    ("level_series = [[0.0, 0.0], [5.0, 0.2], [4.0, 0.3]]\n",
     "line 14: loads.flood.level_series: times must increase, but entry 2 "
     "(t = 4 s) does not come after entry 1 (t = 5 s)"),
    ("velocity = 1.0\n", "loads.flood.level: give level or level_series, not both or neither"),
    ("level = 0.1\nlevel_series = [[0, 0], [1, 1]]\n", "not both or neither"),
    ("level = 0.1\ndepth = 2\n",
     "line 15: loads.flood.depth: unknown key; allowed keys here: level, level_series"),
    ("level = 0.1\nwater_density = 0\n",
     "loads.flood.water_density: Input should be greater than 0"),
    ("level = -0.3\n", "loads.flood.level: a water level of -0.3 m is below the ground: the "
     "structure stands at 0 m"),
    ("level_series = [[0, -1], [1, 1]]\n", "loads.flood.level_series: a water level of -1 m "
     "is below the ground"),
    ("level = 0.2\ntailwater = -0.1\n", "loads.flood.tailwater: a water level of -0.1 m is "
     "below the ground"),
])
def test_bad_flood_input_names_the_key(extra, expected):
    assert expected in _error(SCENARIO + extra)


def test_bad_flood_parameters_in_python_are_named():
    with pytest.raises(sx.InputError, match="flood.drag_coefficient must be a finite number"):
        FloodLoad(level=1.0, drag_coefficient=-1.0)
    with pytest.raises(sx.InputError, match=r"flood.level_series \(\[time \[s\], m\] pairs\): "
                                            "times must increase, but entry 1"):
        FloodLoad(level_series=[(1.0, 0.0), (1.0, 2.0)])
    with pytest.raises(sx.InputError, match="flood.velocity_series .*NaN"):
        FloodLoad(level=1.0, velocity_series=[(0.0, 0.0), (1.0, math.nan)])
    with pytest.raises(sx.InputError, match="flood.level: a water level of -2 m is below"):
        _model([[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]],
               load=FloodLoad(level=-2.0))


def test_cli_collapse_on_the_flood_level_draws_the_water(tmp_path, capsys):
    """`saxum collapse --vary loads.flood.level` on the bundled bridge section
    (examples/flood_bridge.toml, 3 m/s): the upstream parapet (0.4 x 1 m on the deck at 7 m)
    slides off where mu g (rho_s t h - rho_w t d) = 1/2 rho_w C_d U^2 d (statics, as in
    tests/test_examples.py); the picture shows the water."""
    import shutil
    from pathlib import Path

    from saxum.cli import main

    examples = Path(__file__).resolve().parents[1] / "examples"
    for name in ("flood_bridge.toml", "flood-bridge-section.json"):
        shutil.copy(examples / name, tmp_path / name)
    out = tmp_path / "collapse.h5"
    assert main(["collapse", str(tmp_path / "flood_bridge.toml"), "--vary", "loads.flood.level",
                 "--stands", "7.4", "--collapses", "7.9", "--tolerance", "0.002",
                 "-o", str(out)]) == 0
    text = capsys.readouterr().out
    stands, collapses = (float(v) for v in
                         text.split("stands at ")[1].split(" (")[0].split(", collapses at "))
    mu_g, t, h = 0.6 * G, 0.4, 1.0
    level = 7.0 + mu_g * 2400.0 * t * h / (0.5 * 1000.0 * 1.4 * 3.0**2 + mu_g * 1000.0 * t)
    assert stands < level < collapses and collapses - stands < 0.02
    assert "moving blocks (1, " in text and "upstream parapet" in text
    assert "sliding joint between upstream wall c6 and upstream parapet" in text
    with sx.Results(out) as r:
        from saxum.plot import plot_frame

        ax = plot_frame(r, -1).axes[0]
        assert any(np.allclose(c.get_facecolor()[0][:3], (0x9c / 255, 0xc8 / 255, 0xe8 / 255))
                   for c in ax.collections)  # the water's colour
        assert any("flow → 3 m/s" in t.get_text() for t in ax.texts)
    assert out.with_suffix(".png").stat().st_size > 10_000


SCENARIO_3D = textwrap.dedent("""\
    [structure]
    type = "wall_3d"
    courses = 3
    length = 0.5
    [[laws]]
    groups = ["brick", "brick"]
    friction = 0.7
    [[laws]]
    groups = ["brick", "ground"]
    friction = 0.7
    [output]
    duration = 0.01
    [loads.flood]
    level = 0.1
""")


def test_scenario_flood_in_3d_flows_at_its_azimuth():
    """The wall (x from 0 to 0.5 m, 0.12 m thick along y) under 0.1 m of water flowing at
    2 m/s along +y (azimuth 90): buoyancy of the wet volume and drag on the wet upstream
    face, 1/2 rho_w C_d U^2 0.5 x 0.1 m, on the bottom course."""
    sc = parse_scenario(SCENARIO_3D + "velocity = 2.0\nazimuth = 90\n")
    model = sc.build_model()
    (load,) = model.field_loads
    assert load.along(model) == pytest.approx([0.0, 1.0, 0.0], abs=1e-15)
    f = load.forces(model)
    assert f.shape == (model.body_count, 6)
    assert f[:, 1].sum() == pytest.approx(0.5 * 1000.0 * 1.4 * 4.0 * 0.5 * 0.1, rel=1e-12)
    wet = 0.5 * 0.12 * 0.065 + 0.5 * 0.12 * (0.1 - 0.065)  # two courses under 0.1 m
    assert f[:, 2].sum() == pytest.approx(1000.0 * G * wet, rel=1e-12)
    assert np.abs(f[:, 0]).max() < 1e-12 * f[:, 1].sum()  # (cos 90 degrees: 6e-17)


def test_flood_azimuth_is_for_3d_models():
    assert "loads.flood.azimuth is for 3D models" in _error(SCENARIO + "level = 0.1\n"
                                                            "azimuth = 30\n")
    with pytest.raises(sx.InputError, match="flood.azimuth must be a finite number"):
        FloodLoad(level=1.0, azimuth=math.inf)


def test_3d_flood_runs_and_its_picture_shows_the_water(tmp_path):
    from saxum.plot import plot_frame
    from saxum.runner import run_scenario

    sc = parse_scenario(SCENARIO_3D + "velocity = 2.0\nazimuth = 90\n")
    run_scenario(sc, tmp_path / "r.h5", quiet=True)
    with sx.Results(tmp_path / "r.h5") as r:
        assert r.status == "finished"
        ax = plot_frame(r, -1).axes[0]
        water = [c for c in ax.collections
                 if np.allclose(np.asarray(c.get_facecolor())[:1, :3],
                                (0x9c / 255, 0xc8 / 255, 0xe8 / 255))]
        assert water
        assert any("flow 2 m/s towards 90°" in t.get_text() for t in ax.texts)
