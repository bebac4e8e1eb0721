"""saxum view (saxum.view): the packing of frames into the page (round trip within the
quantization's stated bound), the page's data against the results file, bad input (a file
that is not a results file, a killed run, a run too large), and in headless Chromium (skipped
where none is installed): the 2D and 3D pages render, one mesh per block, the slider moves
the blocks to the stored positions, no console error."""

import base64
import json
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from browser import chromium, screenshot, selftest
from PIL import Image
from test_plot import WALL3D

import saxum as sx
from saxum.cli import main
from saxum.errors import InputError
from saxum.results import Results, ResultsWriter
from saxum.structures import semicircular_arch
from saxum.view import (
    _Packer,
    dequantize,
    quantize,
    quantize_quaternions,
    view_data,
    view_html,
    write_view,
)

STEP = 1.0 / 65535  # one 16-bit level, as a fraction of the range packed


def test_quantize_round_trip_within_half_a_level():
    """Positions come back within (hi - lo) / 65535 / 2 on each axis (module doc), the
    ends exactly at the ends of the range."""
    rng = np.random.default_rng(7)
    values = rng.uniform(-3.0, 5.0, size=(200, 40, 3)) * np.array([1.0, 1e-3, 1e-7])
    lo, hi = values.min(axis=(0, 1)), values.max(axis=(0, 1))
    back = dequantize(quantize(values, lo, hi), lo, hi)
    # half a level, and 1e-12 relative for the round-off of the arithmetic itself
    bound = 0.5 * STEP * (hi - lo) * (1 + 1e-12)
    assert np.all(np.abs(back - values) <= bound)
    assert np.abs(back - values).max(axis=(0, 1)) == pytest.approx(0.5 * STEP * (hi - lo),
                                                                   rel=0.01)  # tight bound
    flat = quantize(np.full(4, 2.5), np.float64(2.5), np.float64(2.5))  # no range: all at lo
    # lo + 0 x (hi - lo): 1e-15 relative allows the arithmetic's round-off on another CPU
    assert np.allclose(dequantize(flat, 2.5, 2.5), 2.5, rtol=1e-15, atol=0.0)


def test_quaternions_round_trip_within_half_a_step():
    rng = np.random.default_rng(3)
    q = rng.normal(size=(500, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    back = quantize_quaternions(q) / 32767.0
    assert np.all(np.abs(back - q) <= 0.5 / 32767 + 1e-15)  # + the division's round-off


def test_packer_index_reads_every_array_back():
    pack = _Packer()
    arrays = {"a": np.arange(5, dtype=np.uint16), "b": np.linspace(0, 1, 7),
              "c": np.arange(6, dtype=np.int32).reshape(2, 3), "d": np.ones(3, np.float32)}
    for name, a in arrays.items():
        pack.add(name, a)
    raw = base64.b64decode(pack.base64())
    for name, a in arrays.items():
        kind, offset, count, shape = pack.index[name]
        assert offset % 8 == 0  # a Float64Array view needs it
        back = np.frombuffer(raw, dtype=a.dtype, count=count, offset=offset).reshape(shape)
        assert np.array_equal(back, a)


@pytest.fixture(scope="module")
def arch(tmp_path_factory):
    """A thin arch (t/R = 0.09) starting to collapse: 0.2 s, a frame every 20 steps."""
    path = tmp_path_factory.mktemp("view") / "arch.h5"
    model = semicircular_arch(radius=1.0, thickness=0.09, voussoirs=9)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    with ResultsWriter(path, model, dt=1e-3, theta=0.5) as w:
        w.write_frame(state)
        for _ in range(200):
            w.log_step(sim.step(state))
            if state.step % 20 == 0:
                w.write_frame(state)
        w.set_status(1)
    return path


@pytest.fixture(scope="module")
def wall3d(tmp_path_factory):
    scenario = tmp_path_factory.mktemp("view3d") / "wall3d.toml"
    scenario.write_text(WALL3D)  # 3 courses pushed over by 6 m/s^2 for 0.06 s, 7 frames
    assert main(["run", str(scenario), "--quiet", "--set", "structure.courses=3",
                 "--set", "loads.horizontal_acceleration=6.0", "--unset", "loads.point_loads",
                 "--set", "output.duration=0.06"]) == 0
    return scenario.with_suffix(".h5")


def _positions(data: dict, pack: _Packer) -> np.ndarray:
    """The bodies' positions [frames, bodies, 3] decoded from the page's arrays as the viewer
    does (p0 + dequantized u)."""
    raw = base64.b64decode(pack.base64())

    def read(name, dtype):
        _, offset, count, shape = pack.index[name]
        return np.frombuffer(raw, dtype=dtype, count=count, offset=offset).reshape(shape)

    lo, hi = np.array(data["u_lo"]), np.array(data["u_hi"])
    return read("p0", np.float64) + dequantize(read("u", np.uint16), lo, hi)


@pytest.mark.parametrize("which", ["arch", "wall3d"])
def test_page_data_gives_the_stored_positions(which, request):
    """Decoded as the viewer decodes them, the positions are the stored ones within half a
    16-bit level of the displacements' range; every frame and body is there."""
    path = request.getfixturevalue(which)
    with Results(path) as r:
        data, pack = view_data(r)
        stored = r.body_q[..., : r.dim]
        frames, bodies = r.frame_count, len(r.body_name)
    back = _positions(data, pack)[..., : stored.shape[-1]]
    assert back.shape == (frames, bodies, stored.shape[-1])
    bound = 0.5 * STEP * (np.array(data["u_hi"]) - np.array(data["u_lo"]))[: stored.shape[-1]]
    assert np.all(np.abs(back - stored) <= bound * (1 + 1e-9) + 1e-12)
    assert data["time"] == pytest.approx(r.time.tolist(), rel=1e-15)  # JSON keeps float64
    assert len(data["overlay"]["frames"]) == frames  # contacts on every frame: small run
    assert data["colours"] == {}  # rigid blocks, no cohesive law: no damage, no stress


def test_every_and_block_subset(wall3d):
    with Results(wall3d) as r:
        data, _ = view_data(r, every=4)
        assert data["frames"] == [0, 4, r.frame_count - 1]  # and always the last
        data, _ = view_data(r, blocks="brick c3*")
        names = data["body"]["name"]
        kinds = np.array(data["body"]["kind"])
        # the top course and the supports (the ground), nothing else
        assert all(n.startswith("brick c3") for n, k in zip(names, kinds, strict=True)
                   if k == 0)
        assert (kinds != 0).any() and len(names) < len(r.body_name)
        with pytest.raises(InputError, match="matches no block name or group"):
            view_data(r, blocks="nothing*")


def test_a_run_too_large_says_what_to_do(arch):
    with Results(arch) as r, pytest.raises(InputError) as err:
        view_html(r, max_bytes=1000)
    assert "--every" in str(err.value) and "--blocks" in str(err.value)


def test_not_a_results_file_exits_2(tmp_path, capsys):
    bogus = tmp_path / "notes.h5"
    bogus.write_text("not HDF5")
    assert main(["view", str(bogus), "--no-open"]) == 2
    assert "is not a readable HDF5 file" in capsys.readouterr().err
    import h5py

    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = 1
    assert main(["view", str(tmp_path / "other.h5"), "--no-open"]) == 2
    assert "is not a saxum results file" in capsys.readouterr().err


_KILLED = textwrap.dedent("""\
    import os, sys
    import saxum as sx
    from saxum.structures import semicircular_arch
    from saxum.results import ResultsWriter
    model = semicircular_arch(radius=1.0, thickness=0.15, voussoirs=5)
    state = sx.Simulation(model, dt=1e-3).initial_state()
    w = ResultsWriter(sys.argv[1], model, dt=1e-3, theta=0.5)
    for k in range(3):
        state.time, state.step = 0.01 * k, 10 * k
        w.write_frame(state)
    w.flush_steps()
    os._exit(0)  # dies without closing the file, as a killed run
""")


def test_a_killed_run_is_viewed_and_said_so(tmp_path, capsys):
    out = tmp_path / "killed.h5"
    subprocess.run([sys.executable, "-c", _KILLED, str(out)], check=True, timeout=300)
    page = tmp_path / "killed.html"
    assert main(["view", str(out), "-o", str(page), "--no-open"]) == 0
    err = capsys.readouterr().err
    assert "did not finish (interrupted" in err and "3 frame(s)" in err
    data = json.loads(re.search(r'id="saxum-data">(.*?)</script>', page.read_text(),
                                re.S).group(1))
    assert data["status"] == "interrupted" and len(data["time"]) == 3
    if chromium() is not None:  # the page says so too
        report = selftest(page)
        assert report["errors"] == [] and report["blockMeshes"] == 6
        assert "This run did not finish (interrupted (resume with saxum resume" in (
            report["notes"][0])


def test_jupyter_view_is_an_iframe_of_the_page_and_pages_are_deterministic(arch):
    with Results(arch) as r:
        view = r.view()
        assert view_html(r) == view.html  # the same page twice, bit for bit
    html = view._repr_html_()
    assert html.startswith("<iframe srcdoc=") and "&lt;script" in html
    assert view.html.count("<script") == 4  # data, binary, three.js, viewer


needs_chromium = pytest.mark.skipif(chromium() is None,
                                    reason="no Chromium on PATH (chromium, chromium-browser, "
                                           "google-chrome): the viewer's browser test needs "
                                           "one (Debian: apt-get install chromium)")


@needs_chromium
@pytest.mark.parametrize("which", ["arch", "wall3d"])
def test_page_renders_in_chromium(which, request, tmp_path):
    """The page draws (a screenshot with many colours, not one background), one mesh per
    block, the slider moves the blocks to the last frame's stored positions (within the
    packing's bound and float32), and nothing is written to the console as an error."""
    path = request.getfixturevalue(which)
    with Results(path) as r:
        page = write_view(r, tmp_path / "view.html")
        last = r.body_q[-1]
        dim, bodies = r.dim, len(r.body_name)
        data, _ = view_data(r)
    report = selftest(page)
    assert report["errors"] == []
    assert report["blockMeshes"] == report["blocks"] == bodies
    assert report["frame"] == report["frames"] - 1
    free = np.array(data["body"]["kind"]) == 0
    assert report["movedBlocks"] >= free.sum()  # every free block moved: a collapse
    shown = np.array(report["last"])[:, :3]
    bound = 0.5 * STEP * (np.array(data["u_hi"]) - np.array(data["u_lo"]))
    # three.js holds positions in float64 (JS numbers): the packing's bound is all
    assert np.all(np.abs(shown[:, :dim] - last[:, :dim]) <= bound[:dim] * (1 + 1e-9) + 1e-12)
    png = screenshot(page, tmp_path / "view.png")
    pixels = np.asarray(Image.open(png).convert("RGB"))
    scene = pixels[60:-60, 300:-330].reshape(-1, 3)  # between the panels
    colours = np.unique(scene // 8, axis=0)  # shades, not anti-aliasing noise
    assert pixels.shape[:2] == (800, 1200)
    assert len(colours) > 20 and scene.std() > 10.0  # blocks drawn, not a blank page


def test_view_opens_the_page_in_the_default_browser(arch, tmp_path, monkeypatch, capsys):
    opened = []
    monkeypatch.setattr("webbrowser.open", lambda uri: opened.append(uri) or True)
    page = tmp_path / "a.html"
    assert main(["view", str(arch), "-o", str(page)]) == 0
    assert opened == [page.resolve().as_uri()]
    assert "opened in the default browser" in capsys.readouterr().out
