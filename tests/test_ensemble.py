"""saxum ensemble: rows, resume, failed runs and bad input (a tiny model on a threaded
in-process Dask cluster, records of 0.6 s)."""

import time

import numpy as np
import pytest
from ensemble_case import write_scenario

import saxum as sx
from saxum import ensemble as ens
from saxum.cli import main
from saxum.scenario import load_scenario

pytest.importorskip("distributed")


def _run(path, output, **options):
    return ens.run_ensemble(load_scenario(path), output, workers=1, processes=False,
                            quiet=True, **options)


def test_interrupted_ensemble_resumes_without_redoing_runs(tmp_path):
    path = write_scenario(tmp_path)
    out = tmp_path / "e.h5"

    def stop_after_two(row, seen=[]):  # noqa: B006 - the rows seen so far
        seen.append(row)
        if len(seen) == 2:
            raise KeyboardInterrupt

    first = _run(path, out, on_row=stop_after_two)
    assert first.interrupted and first.runs == 2
    second = _run(path, out)
    assert not second.interrupted and second.new_runs == 4 and second.runs == 6
    runs = ens.read_ensemble(out).runs
    keys = sorted(zip(runs["record"].tolist(), runs["scale"].tolist(), strict=True))
    assert keys == [(k, s) for k in range(2) for s in (1.0, 2.0, 3.0)]
    assert (runs["collapsed"] >= 0).all() and runs["collapsed"].any()
    assert _run(path, out).new_runs == 0
    # the same runs again give the same rows, bit for bit (one machine)
    again = _run(path, tmp_path / "again.h5").path
    rerun = ens.read_ensemble(again).runs
    order = np.lexsort((runs["scale"], runs["record"]))
    order2 = np.lexsort((rerun["scale"], rerun["record"]))
    for name in ("peak_rotation", "peak_drift", "collapse_time"):
        np.testing.assert_array_equal(runs[name][order], rerun[name][order2])


def test_a_failing_run_is_a_row_with_its_error(tmp_path, monkeypatch):
    path = write_scenario(tmp_path)
    advance = ens._advance

    def failing(sim, model, duration, interval, task):
        if abs(task["scale"] - 2.0) < 1e-9 and task["record"] == 1:  # the stripes are 1 apart
            raise sx.SimulationError("NaN velocities at step 7 (made up by the test)")
        return advance(sim, model, duration, interval, task)

    monkeypatch.setattr(ens, "_advance", failing)
    summary = _run(path, tmp_path / "e.h5")
    assert summary.failed == 1 and summary.runs == 6
    runs = ens.read_ensemble(tmp_path / "e.h5").runs
    bad = (runs["record"] == 1) & np.isclose(runs["scale"], 2.0, rtol=0.0, atol=1e-9)
    assert runs["collapsed"][bad].tolist() == [-1]
    assert "NaN velocities at step 7" in runs["error"][bad][0]
    assert (runs["collapsed"][~bad] >= 0).all()


def test_a_bad_record_file_is_left_out_and_the_others_run(tmp_path):
    path = write_scenario(tmp_path)
    (tmp_path / "records" / "broken.csv").write_text("# units: g\n0.0,0.1\n0.01,0.2,\n")
    summary = _run(path, tmp_path / "e.h5")
    assert [name for name, _ in summary.bad_records] == ["broken"]
    assert "broken.csv line 3" in summary.bad_records[0][1]
    runs = ens.read_ensemble(tmp_path / "e.h5").runs
    assert summary.runs == 6 and sorted(set(runs["record"].tolist())) == [1, 2]  # (0: broken)


@pytest.mark.parametrize("scales, message", [
    ("2:1:0.5", "holds no scale factor"), ("-1:1:0.5", "must be > 0"),
    ("0.5:1:0", "step must be > 0"), ("1,0.5", "must increase")])
def test_bad_scale_ranges_are_refused(tmp_path, capsys, scales, message):
    path = write_scenario(tmp_path)
    assert main(["ensemble", str(path), f"--scales={scales}", "-o",
                 str(tmp_path / "e.h5")]) == 2
    err = capsys.readouterr().err
    assert "ensemble.scales" in err and message in err
    assert not (tmp_path / "e.h5").exists()


def test_a_scheduler_that_does_not_answer_is_an_error_within_seconds(tmp_path, capsys):
    path = write_scenario(tmp_path)
    start = time.perf_counter()
    assert main(["ensemble", str(path), "--scheduler", "tcp://127.0.0.1:9", "-o",
                 str(tmp_path / "e.h5")]) == 2
    # the connection timeout (5 s) and the time to read the scenario and records
    assert time.perf_counter() - start < ens.CONNECT_TIMEOUT + 10.0
    err = capsys.readouterr().err
    assert "tcp://127.0.0.1:9: no Dask scheduler answers" in err
    assert not (tmp_path / "e.h5").exists()


def test_another_ensemble_in_the_file_is_refused(tmp_path):
    path = write_scenario(tmp_path)
    _run(path, tmp_path / "e.h5")
    other = load_scenario(path, ["ensemble.scales=\"1:2:1\""])
    with pytest.raises(sx.InputError, match="holds another ensemble .*spec_json"):
        ens.run_ensemble(other, tmp_path / "e.h5", workers=1, processes=False, quiet=True)


def test_plot_draws_ida_and_fragility_and_info_says_what_ran(tmp_path, capsys):
    path = write_scenario(tmp_path)
    _run(path, tmp_path / "e.h5")
    assert main(["plot", str(tmp_path / "e.h5"), "-o", str(tmp_path / "e.png")]) == 0
    assert (tmp_path / "e.png").stat().st_size > 10_000
    assert main(["info", str(tmp_path / "e.h5")]) == 0
    runs = ens.read_ensemble(tmp_path / "e.h5").runs["collapsed"]
    out = capsys.readouterr().out
    assert f"runs: 6 ({int((runs == 1).sum())} collapsed, {int((runs == 0).sum())} stood" in out


def test_a_demand_threshold_fails_every_collapse_and_the_runs_above_it(tmp_path, capsys):
    """The fragility of a demand above a threshold (saxum plot --edp --threshold): a threshold
    below every standing run's demand fails every run that ran, one above them all only the
    collapses, and each run it fails in between has its demand above the threshold."""
    path = write_scenario(tmp_path)
    # scales 0.5 and 1: standing runs with different drifts (at 2 and 3 most runs collapse)
    ens.run_ensemble(load_scenario(path, ['ensemble.scales="0.5:1:0.5"']), tmp_path / "e.h5",
                     workers=1, processes=False, quiet=True)
    e = ens.read_ensemble(tmp_path / "e.h5")
    collapsed, drift = e.runs["collapsed"], e.runs["peak_drift"]
    stood = collapsed == 0
    assert stood.sum() >= 2, "the case must have standing runs with a spread of demands"
    low, high = drift[stood].min(), drift[stood].max()
    assert low < high
    np.testing.assert_array_equal(e.failed("peak_drift", 0.5 * low), collapsed >= 0)
    np.testing.assert_array_equal(e.failed("peak_drift", 2.0 * high), collapsed == 1)
    middle = 0.5 * (low + high)
    between = e.failed("peak_drift", middle)
    assert (collapsed[between] == 1).sum() == (collapsed == 1).sum()
    assert (drift[between & stood] > middle).all() and (drift[~between & stood] <= middle).all()
    assert main(["plot", str(tmp_path / "e.h5"), "-o", str(tmp_path / "t.png"),
                 "--edp", "peak_drift", "--threshold", f"{middle:g}"]) == 0
    assert (tmp_path / "t.png").stat().st_size > 10_000
    with pytest.raises(sx.InputError, match="no demand 'scale'"):
        e.failed("scale", 1.0)
