"""Pictures and animations of results (saxum.plot)."""

import matplotlib.animation
import matplotlib.pyplot as plt
import numpy as np
import pytest
from PIL import Image

import saxum as sx
from saxum.errors import InputError
from saxum.plot import (
    animate,
    joint_states,
    plot_frame,
    plot_histories,
    prefixed_unit,
    save_states,
)
from saxum.results import Results, ResultsWriter
from saxum.structures import semicircular_arch

STEPS, EVERY = 300, 30  # 0.3 s of a collapsing arch, a frame every 30 steps: 11 frames


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A thin arch (t/R = 0.09, below the minimum thickness) starting to collapse: hinges
    form, so the frames have loaded, hinged and open contacts."""
    path = tmp_path_factory.mktemp("plot") / "arch.h5"
    model = semicircular_arch(radius=1.0, thickness=0.09, voussoirs=15)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    with ResultsWriter(path, model, dt=1e-3, theta=0.5) as w:
        w.write_frame(state)
        for _ in range(STEPS):
            w.log_step(sim.step(state))
            if state.step % EVERY == 0:
                w.write_frame(state)
        w.set_status(1)
    with Results(path) as r:
        yield model, state, r


def _image(path, fmt: str) -> Image.Image:
    im = Image.open(path)
    assert im.format == fmt
    return im


def test_frame_picture_has_the_size_asked_and_labels(run, tmp_path):
    _, _, r = run
    out = tmp_path / "frame.png"
    fig = plot_frame(r, -1, out, figsize=(6.0, 4.0), dpi=50)
    assert _image(out, "PNG").size == (300, 200)
    ax = fig.axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x [m]", "y [m]")
    assert "t = 0.300 s" in ax.get_title()
    assert fig.axes[1].get_ylabel().startswith("displacement [")  # the colour bar
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(text.endswith("N/m") for text in labels)  # force scale, N/m or kN/m
    assert any(text.startswith("hinge (") and text != "hinge (0)" for text in labels)
    assert plt.get_fignums() == []  # nothing left in pyplot's global state


def test_frame_draws_into_given_axes(run):
    _, _, r = run
    fig = plt.figure()
    try:
        ax = fig.add_subplot()
        assert plot_frame(r, 3, ax=ax, forces=False, colour_by="rotation") is fig
        assert ax.get_legend() is None
        assert fig.axes[1].get_ylabel().startswith("rotation [deg]")
    finally:
        plt.close(fig)


def test_frame_bad_input(run):
    _, _, r = run
    with pytest.raises(InputError, match="out of range"):
        plot_frame(r, r.frame_count)
    with pytest.raises(InputError, match="colour_by"):
        plot_frame(r, colour_by="stress")


def test_histories_picture(run, tmp_path):
    _, _, r = run
    out = tmp_path / "histories.png"
    fig = plot_histories(r, out, body="voussoir 8", figsize=(5.0, 8.0), dpi=40)
    assert _image(out, "PNG").size == (200, 320)
    assert all("[" in ax.get_ylabel() for ax in fig.axes)  # units on every axis
    assert fig.axes[-1].get_xlabel() == "time [s]"
    assert "voussoir 8" in fig.axes[0].get_title()
    # Default: the free block that moved most; an index works as well as a name.
    moved = np.linalg.norm(r.body_q[-1, :, :2] - r.model["body_q0"][:, :2], axis=1)
    assert r.body_name[int(np.argmax(moved))] in plot_histories(r).axes[0].get_title()
    assert "voussoir 2" in plot_histories(r, body="2").axes[0].get_title()
    with pytest.raises(InputError, match="no block"):
        plot_histories(r, body="keystone")


class _QuietRun:
    """The results of `run` with the kinetic energy scaled by 1e-7 (a structure at rest)."""

    def __init__(self, results):
        self._results = results
        self.steps = {**results.steps, "kinetic_energy": 1e-7 * results.steps["kinetic_energy"]}

    def __getattr__(self, name):
        return getattr(self._results, name)


def test_histories_scale_the_kinetic_energy(run):
    """The energy's axis has the unit prefix that keeps its largest value in [1, 1000)."""
    _, _, r = run
    for results in (r, _QuietRun(r)):
        energy = plot_histories(results, body="voussoir 8").axes[-3]
        top = max(line.get_ydata().max() for line in energy.get_lines())
        assert 1.0 <= top < 1000.0, (energy.get_ylabel(), top)
        unit = energy.get_ylabel().removeprefix("kinetic energy [").removesuffix("]")
        per_joule = {"J/m": 1.0, "mJ/m": 1e3, "µJ/m": 1e6, "nJ/m": 1e9}[unit]
        assert top == pytest.approx(results.steps["kinetic_energy"].max() * per_joule)


def test_prefixed_unit():
    assert prefixed_unit(2.5e4, "J") == (1e-3, "kJ")
    assert prefixed_unit(1.0, "J/m") == (1.0, "J/m")
    assert prefixed_unit(3e-5, "J") == (1e6, "µJ")
    assert prefixed_unit(1e-30, "J") == (1e9, "nJ")
    assert prefixed_unit(0.0, "J") == (1.0, "J")


def test_gif_has_the_frames_and_size_asked(run, tmp_path):
    _, _, r = run
    out = animate(r, tmp_path / "anim" / "arch.gif", fps=10, frames=[0, 4, 8, 10],
                  figsize=(4.0, 2.5), dpi=40)
    im = _image(out, "GIF")
    assert im.size == (160, 100)
    assert im.n_frames == 4


def test_gif_of_all_frames(run, tmp_path):
    _, _, r = run
    out = animate(r, tmp_path / "all.gif", figsize=(3.0, 2.0), dpi=30, forces=False)
    assert _image(out, "GIF").n_frames == r.frame_count == STEPS // EVERY + 1


def test_mp4_without_ffmpeg_asks_for_gif(run, tmp_path, monkeypatch):
    _, _, r = run
    monkeypatch.setattr(matplotlib.animation.writers, "is_available", lambda name: False)
    with pytest.raises(InputError, match=r"\.gif.*ffmpeg"):
        animate(r, tmp_path / "arch.mp4")
    assert not (tmp_path / "arch.mp4").exists()


def test_animation_bad_suffix(run, tmp_path):
    _, _, r = run
    with pytest.raises(InputError, match=".gif"):
        animate(r, tmp_path / "arch.avi")


def test_save_states_for_the_demo(run, tmp_path):
    model, state, _ = run
    out = tmp_path / "states.png"
    save_states(out, [(model, model.body_q0, "initial"), (model, state.body_q, "after")])
    assert _image(out, "PNG").size == (2 * 6 * 120, int(4.5 * 120))


def _contacts(pairs, normal, gap=None):
    """Hand-made contacts: (candidate, antagonist) per contact and the normal force [N/m]."""
    pairs = np.array(pairs, dtype=np.int32)
    normal = np.array(normal, dtype=float)
    return {"candidate": pairs[:, 0], "antagonist": pairs[:, 1],
            "gap": np.zeros(len(normal)) if gap is None else np.array(gap),
            "force": np.column_stack((np.zeros_like(normal), normal))}


def test_joint_states():
    c = _contacts(
        [(1, 2), (1, 2),  # both ends touching and loaded
         (3, 2), (3, 2),  # one end loaded, the other touching and unloaded: still closed
         (4, 3), (3, 4),  # touching, nothing carried (pair given either way round)
         (5, 4), (5, 4),  # loaded end, the other end open by 1 mm: a hinge
         (6, 5),  # a corner on a face, loaded: a hinge
         (7, 6),  # a corner on a face, unloaded
         (8, 7), (8, 7)],  # both ends open
        [500.0, 300.0, 800.0, 0.0, 0.0, 0.0, 995.0, 0.0, 200.0, 0.0, 0.0, 0.0],
        gap=[0.0] * 7 + [1e-3, 0.0, 0.0, 2e-3, 2e-3])
    assert joint_states(c, gap_tolerance=1e-4).tolist() == [
        "closed", "closed", "closed", "closed", "closed", "closed", "hinge", "open", "hinge",
        "closed", "open", "open"]
    # a looser gap tolerance counts the 1 mm opening as touching: that joint is closed
    assert joint_states(c, 1.5e-3).tolist()[6:8] == ["closed", "closed"]
    assert joint_states(_contacts(np.zeros((0, 2)), []), 1e-4).size == 0


def test_model_picture_names_groups_and_frames_the_free_blocks(tmp_path):
    from saxum.plot import plot_model
    from saxum.structures import Opening, wall

    model = wall(courses=8, bricks=6, openings=[Opening(0.5, 0.0, 0.5, 0.26)])
    out = tmp_path / "wall.png"
    ax = plot_model(model, out, title="a wall").axes[0]
    assert _image(out, "PNG").format == "PNG"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["brick", "lintel"]
    lo, hi = ax.get_xlim()
    assert -0.2 < lo < 0.0 and 1.5 < hi < 1.7  # the wall (1.5 m), not its 4.5 m ground
    assert ax.get_title() == "a wall" and plt.get_fignums() == []


class _StillRun(_QuietRun):
    """The results of `run` with every block 3e-17 m from where it started (round-off)."""

    def __init__(self, results):
        self._results = results
        q0 = results.model["body_q0"]
        self.body_q = np.broadcast_to(q0 + [3e-17, 0.0, 0.0], results.body_q.shape).copy()


def test_a_structure_at_rest_has_no_colour_scale_but_its_largest_displacement(run):
    """Displacements of round-off (3e-17 m) get no colour bar (a 0-1 nm scale would suggest
    a motion): the picture says that the structure is at rest and how far a block moved."""
    _, _, r = run
    still = _StillRun(r)
    free = r.model["body_kind"] == sx.BodyKind.FREE
    largest = np.linalg.norm(still.body_q[-1, free, :2] - r.model["body_q0"][free, :2],
                             axis=1).max()
    assert 0.0 < largest < 1e-15
    fig = plot_frame(still, -1)
    try:
        assert len(fig.axes) == 1  # no colour bar
        notes = [t.get_text() for t in fig.axes[0].texts]
        assert f"at rest: largest displacement {largest:.2g} m" in notes
    finally:
        plt.close(fig)


POINT_LOAD = """\
title = "arch under a point load"
[structure]
type = "semicircular_arch"
radius = 1.0
thickness = 0.15
voussoirs = 9
[[laws]]
groups = ["*", "*"]
friction = 0.6
[[loads.point_loads]]
block = "voussoir 3"
magnitude = 2000.0
direction = [1.0, -1.0]
[solver]
dt = 1e-3
[output]
duration = 0.01
interval = 0.01
"""


def test_legend_names_the_thrust_line_and_the_point_loads(tmp_path):
    """The point load is drawn as an arrow onto its block's centre of mass, along the force,
    and the legend names it with its size, and the thrust line."""
    from saxum.cli import main

    scenario = tmp_path / "loaded.toml"
    scenario.write_text(POINT_LOAD)
    assert main(["run", str(scenario), "--quiet"]) == 0
    with Results(scenario.with_suffix(".h5")) as r:
        ax = plot_frame(r, -1, thrust_line=True).axes[0]
        centre = r.body_q[-1, r.body_name.index("voussoir 3"), :2]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "thrust line" in labels and "point load 2 kN/m" in labels
    (arrow,) = [a for a in ax.texts if hasattr(a, "arrow_patch")]
    assert arrow.xy == pytest.approx(tuple(centre))
    along = np.subtract(arrow.xy, arrow.xyann)
    assert along / np.linalg.norm(along) == pytest.approx(np.array([1.0, -1.0]) / np.sqrt(2))


FLOODED = """\
[structure]
type = "blocks"
file = "block.json"
[[laws]]
groups = ["*", "*"]
friction = 0.6
[loads.flood]
level = 0.5
velocity = 0.0
[solver]
dt = 1e-3
[output]
duration = 0.01
interval = 0.01
"""


def test_water_is_drawn_from_the_ground_up(tmp_path):
    """The water fills the space between the ground's top (y = 0 here) and its level, not the
    ground and the space below it."""
    from saxum.cli import main

    (tmp_path / "block.json").write_text(
        '{"blocks": [{"vertices": [[-2, -0.5], [2, -0.5], [2, 0], [-2, 0]], "kind": "fixed",'
        ' "name": "ground"},'
        ' {"vertices": [[0, 0], [0.4, 0], [0.4, 0.2], [0, 0.2]], "density": 2400}]}')
    scenario = tmp_path / "flooded.toml"
    scenario.write_text(FLOODED)
    assert main(["run", str(scenario), "--quiet"]) == 0
    with Results(scenario.with_suffix(".h5")) as r:
        ax = plot_frame(r, -1).axes[0]
    water = [c for c in ax.collections if len(c.get_facecolor())
             and np.allclose(c.get_facecolor()[0][:3], (0x9c / 255, 0xc8 / 255, 0xe8 / 255))]
    (y,) = [np.concatenate([p.vertices[:, 1] for p in c.get_paths()]) for c in water]
    assert y.min() == pytest.approx(0.0, abs=1e-12) and y.max() == pytest.approx(0.5)


WALL3D = """\
title = "3D wall under a point load"
[structure]
type = "wall_3d"
courses = 2
length = 0.6
thickness = 0.1
brick_length = 0.2
brick_height = 0.06
[[laws]]
groups = ["*", "*"]
friction = 0.6
[[loads.point_loads]]
block = "brick c2a1"
magnitude = 50.0
direction = [0.0, 0.0, -1.0]
[solver]
dt = 1e-3
[output]
duration = 0.01
interval = 0.01
"""


def test_3d_picture_force_scale_point_load_and_rest(tmp_path):
    """A 3D frame's legend gives the scale of the contact dots (the full-scale force and half
    of it, with their units) and names the point load; a wall at rest gets no colour bar
    but its largest displacement."""
    from saxum.cli import main

    scenario = tmp_path / "wall3d.toml"
    scenario.write_text(WALL3D)
    assert main(["run", str(scenario), "--quiet"]) == 0
    with Results(scenario.with_suffix(".h5")) as r:
        fig = plot_frame(r, -1)
        largest = np.linalg.norm(r.body_q[-1, :, :3] - r.model["body_q0"][:, :3], axis=1).max()
        full = r.contacts(1)["force"][:, 1].max()
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    scale = [float(text.split()[-2]) for text in labels[:2]]  # the dots' scale comes first
    assert len(scale) == 2 and scale[1] == pytest.approx(scale[0] / 2)
    assert full <= scale[0] < 5 * full  # the next 1, 2 or 5 times a power of ten
    assert "point load 50 N" in labels
    assert len(fig.axes) == 1  # no colour bar: at rest
    assert f"at rest: largest displacement {largest:.2g} m" in [t.get_text() for t in fig.texts]
