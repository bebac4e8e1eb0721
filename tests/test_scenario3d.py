"""3D scenarios: every 3D structure type and load key, errors for vectors of the wrong size,
a run to a results file with its picture and ParaView export, and resume bit for bit."""

import math
import os
import signal
import textwrap
from pathlib import Path

import meshio
import numpy as np
import PIL.Image
import pytest

import saxum as sx
from saxum.cli import info_text, main
from saxum.errors import InputError
from saxum.plot import animate, plot_frame, plot_histories
from saxum.results import Results, ResultsWriter
from saxum.runner import resume_run, run_scenario
from saxum.scenario import load_scenario, parse_scenario
from saxum.vtk import export_vtk

LAWS = """
    [[laws]]
    groups = ["{a}", "{a}"]
    friction = 0.6
    [[laws]]
    groups = ["{a}", "{b}"]
    friction = 0.6
"""


def _scenario(structure: str, groups=("brick", "ground"), extra: str = "",
              duration: float = 0.02) -> str:
    return textwrap.dedent(structure) + textwrap.dedent(
        LAWS.format(a=groups[0], b=groups[1])) + textwrap.dedent(extra) + textwrap.dedent(f"""
        [output]
        duration = {duration}
        interval = 0.01
        checkpoint_interval = 0.01
    """)


WALL = """
    title = "L-shaped wall"
    [structure]
    type = "wall_3d"
    courses = 3
    length = 0.75
    return_length = 0.5
    thickness = 0.1
    brick_length = 0.2
    brick_height = 0.06
    density = 1900.0
"""


def test_wall_3d_with_every_3d_load_key():
    text = _scenario(WALL, extra="""
        [loads]
        gravity = [0.0, 0.0, -9.8]
        horizontal_acceleration = 0.5
        horizontal_azimuth = 30.0
        load_factor_rate = 0.1
        [[loads.point_loads]]
        block = "brick c3a2"
        magnitude = 10.0
        direction = [0.0, 3.0, -4.0]
        [[loads.settlements]]
        block = "ground"
        magnitude = 0.002
        direction = [1.0, 0.0, 0.0]
        rotation = [0.0, 0.0, 0.01]
        time = 0.5
    """)
    model = parse_scenario(text).build_model()
    assert model.dim == 3 and model.group_names == ("brick", "ground")
    assert tuple(model.gravity) == (0.0, 0.0, -9.8)
    # ground; courses through the corner along x: 4 + 2 bricks, the others 3 + 3
    assert model.body_count == 1 + (4 + 2) + (3 + 3) + (4 + 2)
    acc, = model.accelerations
    assert acc(2.0) == pytest.approx((0.5 + 0.1 * 9.8 * 2.0) * np.array(
        [math.cos(math.radians(30)), math.sin(math.radians(30)), 0.0]))
    (bodies, force), = model.forces
    assert model.body_name[bodies[0]] == "brick c3a2"
    assert force(0.0) == pytest.approx((0.0, 6.0, -8.0, 0.0, 0.0, 0.0))
    ground = model.body("ground")
    assert model.body_kind[ground] == sx.BodyKind.DRIVEN
    assert model.motions[0](0.1) == pytest.approx((0.004, 0.0, 0.0, 0.0, 0.0, 0.02))
    assert model.motions[0](0.6) == pytest.approx((0.0,) * 6)


@pytest.mark.parametrize(("extra", "message"), [
    ("[loads]\ngravity = [0.0, -9.81]", "loads.gravity has 2 components, the model is 3D"),
    ("[[loads.point_loads]]\nblock = \"brick c1a1\"\nmagnitude = 1.0\ndirection = [1.0, 0.0]",
     r"loads.point_loads\[0\].direction has 2 components"),
    ("[[loads.settlements]]\nblock = \"ground\"\nmagnitude = 0.01\nrotation = 0.1",
     "rotation vector"),
    ("[loads.ground_motion]\npulse = \"one_sine\"\namplitude = 1.0\ndirection = [1.0, 0.0]",
     "ground_motion.direction has 2 components"),
])
def test_3d_vectors_of_the_wrong_size_are_refused(extra, message):
    with pytest.raises(InputError, match=message):
        parse_scenario(_scenario(WALL, extra=extra)).build_model()


def test_2d_scenario_refuses_the_azimuth():
    text = textwrap.dedent("""
        [structure]
        type = "running_bond_wall"
        courses = 2
        bricks = 2
        [loads]
        horizontal_acceleration = 1.0
        horizontal_azimuth = 10.0
    """) + textwrap.dedent(LAWS.format(a="brick", b="ground")) + "[output]\nduration = 0.1\n"
    with pytest.raises(InputError, match="horizontal_azimuth is for 3D models"):
        parse_scenario(text).build_model()


def test_ground_motion_in_3d_pulse_and_record(tmp_path):
    pulse = _scenario(WALL, extra="""
        [loads.ground_motion]
        pulse = "one_sine"
        amplitude = 2.0
        period = 0.5
        direction = [0.0, 1.0, 0.0]
    """)
    acc, = parse_scenario(pulse).build_model().accelerations
    assert acc(0.125) == pytest.approx((0.0, -2.0, 0.0))
    record = tmp_path / "quake.csv"
    record.write_text("# units: m/s^2\n0.0, 0.0, 0.0\n1.0, 1.0, 0.5\n")
    recorded = _scenario(WALL, extra=f"""
        [loads.ground_motion]
        file = "{record.name}"
        azimuth = 90.0
    """)
    acc, = parse_scenario(recorded, base_dir=tmp_path).build_model().accelerations
    assert acc(0.5) == pytest.approx((0.0, -0.5, -0.25), abs=1e-12)


def test_arch_pier_and_bridge_structures():
    arch = parse_scenario(_scenario("""
        [structure]
        type = "semicircular_arch_3d"
        radius = 1.0
        thickness = 0.15
        voussoirs = 7
        depth = 0.6
        pieces = 2
        stagger = true
        density = 2100.0
    """, groups=("voussoir", "support"))).build_model()
    assert arch.dim == 3 and arch.body_count == 1 + 4 * 2 + 3 * 3
    assert float(arch.body_density.max()) == 2100.0
    pier = parse_scenario(_scenario("""
        [structure]
        type = "pier_3d"
        width = 0.6
        depth = 0.4
        courses = 3
        course_height = 0.3
        density = 2300.0
    """, groups=("pier", "ground"))).build_model()
    assert pier.body_count == 1 + 6
    text = textwrap.dedent("""
        [structure]
        type = "bridge_3d"
        span = 4.0
        rise = 1.0
        thickness = 0.4
        voussoirs = 7
        width = 2.0
        spandrel_thickness = 0.5
        abutment_width = 1.5
        abutment_height = 1.0
        fill = "none"
        course_height = 0.4
        block_length = 1.0
        pieces = 2
        stagger = false
        density = 2000.0
        [output]
        duration = 0.01
    """)
    groups = ["ground", "pier", "voussoir", "spandrel"]
    text += "".join(f'[[laws]]\ngroups = ["{a}", "{b}"]\nfriction = 0.6\n'
                    for i, a in enumerate(groups) for b in groups[i:])
    bridge = parse_scenario(text).build_model()
    assert set(bridge.group_names) == set(groups)
    spandrel = [b for b in range(bridge.body_count)
                if bridge.group_names[bridge.body_group[b]] == "spandrel"]
    widths = {round(float(np.ptp(bridge.vertices(b)[:, 1])), 9) for b in spandrel}
    assert widths == {0.5}  # the walls at both faces, nothing between them


def _cubes(path):
    """Two unit cubes side by side, 1 mm apart, as a triangle mesh."""
    cube = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    tri = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                    [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    meshio.write(path, meshio.Mesh(np.vstack((cube, cube + (1.001, 0, 0))),
                                   [("triangle", np.vstack((tri, tri + 8)))]))


@pytest.mark.parametrize("suffix", ["stl", "obj", "vtu"])
def test_mesh_structure(tmp_path, suffix):
    _cubes(tmp_path / f"stones.{suffix}")
    text = _scenario(f"""
        [structure]
        type = "mesh"
        file = "stones.{suffix}"
        density = 2500.0
        group = "stone"
        ground = true
    """, groups=("stone", "ground"))
    model = parse_scenario(text, base_dir=tmp_path).build_model()
    assert model.body_count == 3 and model.body_name[:2] == ("stones 0", "stones 1")
    assert model.body_mass[:2] == pytest.approx([2500.0, 2500.0])
    assert model.vertices(2)[:, 2].max() == pytest.approx(0.0)  # the ground under them


def test_3d_run_results_picture_paraview_and_resume(tmp_path, monkeypatch):
    text = _scenario(WALL, extra="""
        [loads]
        horizontal_acceleration = 3.0
        horizontal_azimuth = 60.0
    """, duration=0.06)
    one_go = tmp_path / "one.h5"
    run_scenario(parse_scenario(text), one_go, quiet=True)
    with Results(one_go) as r:
        assert r.dim == 3 and r.body_q.shape[1:] == (19, 7) and r.body_v.shape[2] == 6
        assert r.units["force"] == "N"
        assert r.vertices(5, -1).shape == (8, 3)
        ds = r.to_xarray()
        assert ds["body_q"].sel(coordinate="qw").shape == (7, 19)
        picture = tmp_path / "wall.png"
        plot_frame(r, -1, picture, dpi=40)
        assert picture.stat().st_size > 0
        plot_histories(r, tmp_path / "histories.png", dpi=40)
        assert main(["plot", str(one_go), "--thrust-line"]) == 2  # a 2D picture's option
        gif = animate(r, tmp_path / "wall.gif", frames=[0, 3, 6], figsize=(3.0, 3.0), dpi=30)
        with PIL.Image.open(gif) as image:
            assert image.n_frames == 3 and image.size == (90, 90)
        pvd = export_vtk(r, tmp_path / "vtk")
        blocks = meshio.read(pvd.parent / "one" / "blocks_000006.vtu")
        faces = sum(len(c.data) for c in blocks.cells)
        assert faces == 6 * 19
        index = np.concatenate(blocks.cell_data["body_index"])
        assert np.bincount(index).tolist() == [6] * 19
        # each face cell lies on its block at frame 6 and turns outward
        for cells, owners in zip(blocks.cells, blocks.cell_data["body_index"], strict=True):
            for face, b in zip(cells.data, owners, strict=True):
                p = blocks.points[face]
                normal = np.cross(p[1] - p[0], p[2] - p[1])
                assert normal @ (p.mean(axis=0) - r.body_q[6, b, :3]) > 0.0
        contacts = meshio.read(pvd.parent / "one" / "contacts_000006.vtu")
        c = r.contacts(6)
        assert contacts.point_data["normal_force"] == pytest.approx(c["force"][:, 1])
        assert contacts.point_data["normal"] == pytest.approx(c["frame"][:, 1])

    # interrupted after step 25 (the runner's own Ctrl-C handling), then resumed
    stopped = tmp_path / "stopped.h5"
    original = ResultsWriter.log_step

    def log_step(self, report):
        original(self, report)
        if report.step == 25:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(ResultsWriter, "log_step", log_step)
    assert run_scenario(parse_scenario(text), stopped, quiet=True).status == "interrupted"
    monkeypatch.setattr(ResultsWriter, "log_step", original)
    assert resume_run(stopped, quiet=True).status == "finished"
    with Results(one_go) as a, Results(stopped) as b:
        assert np.array_equal(a.body_q, b.body_q) and np.array_equal(a.body_v, b.body_v)
        for name in a.steps:
            # natural_map and rate are nan where a step converged: nan == nan here
            assert np.array_equal(a.steps[name], b.steps[name],
                                  equal_nan=a.steps[name].dtype.kind == "f"), name


PIER = """
    title = "pier"
    [structure]
    type = "pier_3d"
    width = 0.3
    depth = 0.3
    courses = 2
    course_height = 0.5
"""


def test_info_of_a_3d_collapse_under_a_growing_harmonic_motion(tmp_path):
    """saxum info reports the amplitude at collapse with |g| of a 3-component gravity (it
    once failed on 3D results)."""
    path = tmp_path / "pier.toml"
    path.write_text(_scenario(PIER, groups=("pier", "ground"), extra="""
        [loads.ground_motion]
        pulse = "harmonic"
        amplitude = 12.0
        period = 1.0
        cycles = 2
        ramp = 2.0
        [solver]
        dt = 2e-3
    """, duration=1.6))
    assert main(["run", str(path), "-q"]) == 0
    with Results(tmp_path / "pier.h5") as r:
        text = info_text(r)
    assert "collapse at t = " in text and "mechanism at collapse" in text
    assert "moving blocks (" in text and "hinge between ground and pier c1b" in text
    picture = tmp_path / "collapse.png"
    assert main(["plot", str(tmp_path / "pier.h5"), "--collapse", "-o", str(picture)]) == 0
    assert picture.stat().st_size > 10_000
    g = 9.81  # the amplitude grows as 12 t / 2 m/s^2: 0.6 g at t = 1 s
    began = float(text.split("motion began, t = ")[1].split(" s")[0])
    assert f"{6.0 * began:.4g} m/s^2 ({6.0 * began / g:.3g} g) when the collapsing" in text



def test_collapse_of_a_3d_pier_reports_its_hinge_lines(tmp_path, capsys):
    """`saxum collapse` on a 3D pier 0.3 x 0.3 x 1 m under a horizontal load along y
    (azimuth 90): it overturns as one block at lambda = b/h = 0.3 (statics of a rigid block),
    turning about the far edge of its base, y = 0.3 m, which the report gives as hinge lines
    and the picture draws."""
    path = tmp_path / "pier.toml"
    path.write_text(_scenario(PIER, groups=("pier", "ground"), extra="""
        [loads]
        horizontal_azimuth = 90.0
    """))
    out = tmp_path / "collapse.h5"
    assert main(["collapse", str(path), "--vary", "loads.horizontal_acceleration",
                 "--stands", "2.0", "--collapses", "4.0", "--tolerance", "0.03",
                 "-o", str(out)]) == 0
    text = capsys.readouterr().out
    factor = float(text.split("lambda = a/g: ")[1].split()[0])
    assert factor == pytest.approx(0.3, rel=0.03)
    hinges = [line for line in text.splitlines() if line.startswith("hinge between ground")]
    assert len(hinges) == 2 and all(", 0.3, 0)-(" in h and h.endswith(", 0.3, 0) m: course 1 "
                                                                      "against ground")
                                    for h in hinges)
    with Results(out) as r:
        ax = plot_frame(r, -1).axes[0]
    assert any(line.get_linewidth() == 3.0 for line in ax.lines)  # the hinge lines
    assert out.with_suffix(".png").stat().st_size > 10_000


def test_bridge_3d_parapets_need_both_sizes():
    """The flood example's bridge has its parapets, the fill its own density and the road at
    abutment_height + spandrel_height; one parapet size without the other is refused."""
    path = Path(__file__).parents[1] / "examples" / "flood_bridge3d.toml"
    model = load_scenario(path).build_model()
    group = np.array([model.group_names[g] for g in model.body_group])
    parapets = np.vstack([model.vertices(b) for b in np.flatnonzero(group == "parapet")])
    assert (parapets[:, 2].min(), parapets[:, 2].max()) == pytest.approx((7.0, 8.0))
    assert set(model.body_density[group == "fill"]) == {2000.0}
    text = "\n".join(line for line in path.read_text().splitlines()
                     if not line.startswith("parapet_height"))
    with pytest.raises(InputError, match="parapets need both parapet_thickness and "
                                         "parapet_height"):
        parse_scenario(text, base_dir=path.parent)
