"""Outputs of dynamic runs and collapse searches: time histories of chosen blocks at every step
(with the ground acceleration), the time of collapse and the mechanism then (saxum info,
saxum plot --collapse, saxum collapse under a pulse), and the collapse curve's mechanism per
period with its picture and table. The structure is a 0.2 x 1 m block on a fixed ground
(overturns about a corner: one hinge between ground and block)."""

import csv
import re
import textwrap

import numpy as np
import pytest

from saxum.cli import main
from saxum.collapse import DYNAMIC_FRACTION, find_collapse
from saxum.ground import one_sine
from saxum.results import Results

BLOCK = textwrap.dedent("""\
    [structure]
    type = "blocks"
    file = "block.json"
    [[laws]]
    groups = ["block", "ground"]
    friction = 1.0
    [[laws]]
    groups = ["block", "block"]
    friction = 1.0
    [loads.ground_motion]
    pulse = "one_sine"
    amplitude = 6.0
    period = 0.5
    [solver]
    dt = 1e-3
    [output]
    duration = 1.5
    interval = 0.05
    histories = ["pier", 0]
""")


@pytest.fixture()
def block(tmp_path):
    (tmp_path / "block.json").write_text(
        '{"blocks": [{"vertices": [[-2, -0.2], [2, -0.2], [2, 0], [-2, 0]], "kind": "fixed",'
        ' "group": "ground", "name": "ground"},'
        ' {"vertices": [[0, 0], [0.2, 0], [0.2, 1], [0, 1]], "density": 2000, "name": "pier"}]}')
    path = tmp_path / "block.toml"
    path.write_text(BLOCK)
    return path


def test_run_under_a_pulse_histories_time_of_collapse_and_mechanism(block, capsys):
    results = block.with_suffix(".h5")
    assert main(["run", str(block), "--quiet"]) == 0
    with Results(results) as r:
        h = r.histories
        assert h["name"] == ["pier", "ground"] and h["step"].tolist() == list(range(1, 1501))
        pulse = one_sine(6.0, 0.5)
        expected = [pulse.acceleration_at(t)[0] for t in h["time"]]
        assert h["ground_acceleration"][:, 0] == pytest.approx(expected)
        event = find_collapse(r)
        # the frames' verdict agrees with the block's history at every step: the collapse
        # frame is the first frame after the last step at which the block was within limit
        moved = np.hypot(*(h["body_q"][:, 0, :2] - r.model["body_q0"][1, :2]).T)
        assert event.limit == pytest.approx(DYNAMIC_FRACTION * np.sqrt(0.2))
        last_within = h["time"][np.flatnonzero(moved <= event.limit)[-1]]
        assert last_within < event.time <= last_within + 0.05 + 1e-9
        assert event.block == "pier"
    assert main(["info", str(results)]) == 0
    out = capsys.readouterr().out
    assert f"collapse at t = {event.time:.4g} s" in out
    assert "hinge between ground and pier" in out and "moving blocks (1" in out
    assert main(["plot", str(results), "--collapse"]) == 0
    assert results.with_suffix(".collapse.png").stat().st_size > 10_000
    assert main(["plot", str(results), "--histories"]) == 0
    assert results.with_suffix(".histories.png").stat().st_size > 10_000


def test_a_block_that_stands_has_no_collapse(block, capsys):
    results = block.with_name("small.h5")
    assert main(["run", str(block), "--quiet", "-o", str(results), "--set",
                 "loads.ground_motion.amplitude=1.0", "--set", "output.duration=0.6"]) == 0
    assert main(["info", str(results)]) == 0
    assert "collapse: none" in capsys.readouterr().out
    assert main(["plot", str(results), "--collapse"]) == 2
    assert "no collapse" in capsys.readouterr().err
    assert main(["run", str(block), "--quiet", "--set", 'output.histories=["nothing"]']) == 2
    assert "output.histories: no block 'nothing'" in capsys.readouterr().err


def test_collapse_search_under_a_pulse_reports_time_and_mechanism(block, capsys):
    assert main(["collapse", str(block), "--vary", "loads.ground_motion.amplitude",
                 "--stands", "1", "--collapses", "6", "--tolerance", "0.2",
                 "--duration", "1.0"]) == 0
    out = capsys.readouterr().out
    assert "time of collapse: t = " in out and "the ground motion ends at 0.5 s" in out
    assert "hinge between ground and pier" in out
    assert block.with_name("block-collapse.png").stat().st_size > 10_000


def test_collapse_curve_mechanism_per_period_picture_and_table(block, capsys):
    assert main(["collapse-curve", str(block), "--periods", "0.5,1.0", "--stands", "1",
                 "--collapses", "6", "--tolerance", "0.2", "--duration", "1.0",
                 "--processes", "1"]) == 0
    out = capsys.readouterr().out
    assert out.count("hinge between ground and pier") == 2
    assert block.with_name("block-curve.png").stat().st_size > 10_000
    with open(block.with_name("block-curve.csv")) as f:
        rows = list(csv.DictReader(f))
    assert [float(r["period_s"]) for r in rows] == [0.5, 1.0]
    for r in rows:
        assert float(r["stands_m_s2"]) < float(r["collapses_m_s2"])
        assert r["hinges"] == "ground | pier" and r["moving_blocks"] == "pier"
        assert float(r["collapse_time_s"]) > 0.0
    # a longer pulse overturns the block with a smaller amplitude (Housner 1963)
    assert float(rows[1]["amplitude_g"]) < float(rows[0]["amplitude_g"])
    assert "NLGS" not in capsys.readouterr().err  # converged at every step of every trial
    # an NLGS that cannot converge in 2 sweeps is reported, period by period (NLGS alone: the
    # default hybrid's conic step finishes such steps)
    assert main(["collapse-curve", str(block), "--periods", "0.5", "--stands", "1",
                 "--collapses", "6", "--tolerance", "0.5", "--duration", "1.0",
                 "--processes", "1", "--set", "solver.max_iterations=2",
                 "--set", "solver.kind=nlgs"]) == 0
    err = capsys.readouterr().err
    assert re.search(r"saxum: warning: the contact solver did not converge \(NLGS's cap of 2 "
                     r"sweeps\) at \d+ step\(s\) in \d+ of the \d+ trials at T_p = 0.5 s", err)


def test_harmonic_motion_of_growing_amplitude_reports_the_amplitude_at_collapse(block, capsys):
    """The amplitude grows as A t / ramp (1 Hz, 6 m/s^2 after 4 s); the block cannot start to
    rock before it exceeds the static uplift threshold g b/h = 1.962 m/s^2 (Housner 1963)."""
    results = block.with_name("harmonic.h5")
    assert main(["run", str(block), "--quiet", "-o", str(results),
                 "--set", 'loads.ground_motion.pulse="harmonic"',
                 "--set", "loads.ground_motion.period=1.0", "--set", "loads.ground_motion.cycles=4",
                 "--set", "loads.ground_motion.ramp=4.0", "--set", "output.duration=3.0",
                 "--set", "output.histories=[]"]) == 0
    assert main(["info", str(results)]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("harmonic amplitude"))
    large, began, at = (float(x) for x in re.findall(r"([0-9.]+) m/s\^2", line))
    assert 9.81 * 0.2 < min(large, began) and max(large, began) <= at <= 6.0


def test_collapse_curve_keeps_the_periods_whose_bracket_holds(block, capsys):
    """A 0.1 s pulse of 6 m/s^2 does not overturn the block: that period is reported, the
    other one is computed and drawn."""
    assert main(["collapse-curve", str(block), "--periods", "0.1,1.0", "--stands", "1",
                 "--collapses", "6", "--tolerance", "0.3", "--duration", "0.5",
                 "--processes", "1"]) == 0
    out = capsys.readouterr().out
    assert "0.1  not found: the structure still stands at 6; widen the bracket" in out
    assert out.count("hinge between ground and pier") == 1
    with open(block.with_name("block-curve.csv")) as f:
        rows = list(csv.DictReader(f))
    assert rows[0]["note"].startswith("the structure still stands") and rows[1]["note"] == ""


def test_a_run_that_ends_while_blocks_move_says_so(block, capsys):
    """No collapse yet at the end of a short run, but the block is rocking: the report says
    that the run may be too short to tell, instead of a bare "collapse: none"."""
    results = block.with_name("short.h5")
    assert main(["run", str(block), "--quiet", "-o", str(results), "--set",
                 "output.duration=0.3"]) == 0
    assert main(["info", str(results)]) == 0
    out = capsys.readouterr().out
    assert "collapse: none" in out
    assert re.search(r"but blocks were still moving at the end \('pier' at [0-9.e-]+ m/s\)",
                     out)
    still = block.with_name("still.h5")
    assert main(["run", str(block), "--quiet", "-o", str(still), "--unset",
                 "loads.ground_motion", "--set", "output.duration=0.1"]) == 0
    assert main(["info", str(still)]) == 0
    out = capsys.readouterr().out
    assert "collapse: none" in out and "still moving" not in out
    # its history's rotations are round-off: prefixed radians, not degrees with an offset
    from saxum.plot import plot_histories

    rotating = [ax for ax in plot_histories(Results(still)).axes
                if ax.get_ylabel().startswith("rotation")]
    assert len(rotating) == 1 and rotating[0].get_ylabel() in (
        "rotation [mrad]", "rotation [µrad]", "rotation [nrad]", "rotation [rad]")
    assert main(["plot", str(results), "--histories"]) == 0  # the rocking block: degrees
