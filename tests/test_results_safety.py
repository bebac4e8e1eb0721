"""Results files that cannot lie: one writer at a time, no silent overwrite, truncated and
damaged files read for what is intact (never hanging), a full disk, a killed run said
interrupted, a failing run said failed, densities that are not masonry refused."""

import os
import re
import shutil
import signal
import subprocess
import sys
import textwrap

import h5py
import numpy as np
import pytest
from results_check import same_results, start_saxum, wait_for_frames

from saxum.cli import main
from saxum.errors import InputError, ResultsDamageWarning
from saxum.model import ModelBuilder
from saxum.results import Results
from saxum.runner import resume_run, run_scenario
from saxum.scenario import parse_scenario

# A collapsing arch (t/R = 0.09 < 0.1075), 500 steps: every step has work for the solver.
SCENARIO = textwrap.dedent("""\
    title = "thin arch"
    [structure]
    type = "semicircular_arch"
    radius = 1.0
    thickness = 0.09
    voussoirs = 15
    [[laws]]
    groups = ["*", "*"]
    friction = 0.6
    [output]
    duration = 0.5
    interval = 0.01
    checkpoint_interval = 0.05
    histories = ["voussoir 8"]
""")
HANG = 120  # [s] a command that takes longer has hung (they take seconds; CI machines are slow)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The scenario run in one go, in this process."""
    path = tmp_path_factory.mktemp("reference") / "arch.h5"
    assert run_scenario(parse_scenario(SCENARIO), path, quiet=True).status == "finished"
    return path


def test_a_second_writer_is_refused_and_the_first_file_stays_intact(tmp_path):
    # 2000 steps, so that on a loaded machine the first run is surely still going when stopped
    scenario = SCENARIO.replace("duration = 0.5", "duration = 2.0")
    (tmp_path / "arch.toml").write_text(scenario)
    out = tmp_path / "arch.h5"
    reference = tmp_path / "reference.h5"
    assert run_scenario(parse_scenario(scenario), reference, quiet=True).status == "finished"
    first = start_saxum(["run", "arch.toml", "-q"], tmp_path)
    wait_for_frames(out, 3, first)
    first.send_signal(signal.SIGSTOP)  # so that it is surely still writing meanwhile
    try:
        with Results(out) as r:
            assert r.status == "running"  # its writer holds the file
        second = start_saxum(["run", "arch.toml", "-q", "--overwrite"], tmp_path)
        _, err = second.communicate(timeout=HANG)
    finally:
        first.send_signal(signal.SIGCONT)
    assert second.returncode == 2, err
    assert f"{out.name} is being written by another saxum process (pid {first.pid})" in err
    assert "Traceback" not in err and "HDF5" not in err
    stdout, err = first.communicate(timeout=HANG)
    assert first.returncode == 0 and "finished" in stdout, err
    same_results(out, reference)


def test_an_existing_results_file_is_not_overwritten_without_overwrite(tmp_path, capsys):
    scenario = tmp_path / "short.toml"
    scenario.write_text(SCENARIO.replace("duration = 0.5", "duration = 0.02"))
    out = tmp_path / "short.h5"
    assert main(["run", str(scenario), "-q"]) == 0
    with Results(out) as r:
        steps = r.steps["step"].size
    assert main(["run", str(scenario), "-q", "--set", "solver.dt=5e-4"]) == 2
    err = capsys.readouterr().err
    assert f"{out} already exists and holds a finished run" in err and "--overwrite" in err
    with Results(out) as r:
        assert r.steps["step"].size == steps  # untouched
    # an interrupted run is what the message points at, with how to continue it
    with h5py.File(out, "r+") as f:
        f["run/status"][0] = 2
    assert main(["run", str(scenario), "-q"]) == 2
    assert f"holds an interrupted run (t = 0.02 s) that saxum resume {out} continues" in (
        capsys.readouterr().err)
    assert main(["run", str(scenario), "-q", "--overwrite", "--set", "solver.dt=5e-4"]) == 0
    with Results(out) as r:
        assert r.status == "finished" and r.steps["step"].size == 2 * steps
    assert not list(tmp_path.glob(".*.lock"))  # the lock goes with its writer


_COMMANDS = textwrap.dedent("""\
    import sys, time
    from saxum.cli import main
    path, png = sys.argv[1:]
    for args in (["info", path], ["plot", path, "-o", png], ["resume", path, "-q"]):
        sys.stdout.flush()
        code = main(args)
        print(f"@@ {args[0]} {code}", flush=True)
        print(f"@@ {args[0]} {code}", file=sys.stderr, flush=True)
""")


@pytest.mark.parametrize("percent", [1, 10, 50, 90, 99])
def test_a_truncated_file_is_said_truncated_and_never_resumed_from_lost_data(
        tmp_path, reference, percent):
    """Before: 1-50 % hung info, plot and resume (an SWMR reader retries damaged metadata);
    90-99 % read lost frames as t = 0 and resumed from zeros."""
    cut = tmp_path / "cut.h5"
    shutil.copy(reference, cut)
    os.truncate(cut, os.path.getsize(reference) * percent // 100)
    done = subprocess.run([sys.executable, "-c", _COMMANDS, str(cut), str(tmp_path / "p.png")],
                          capture_output=True, text=True, timeout=HANG)
    assert done.returncode == 0, done.stderr
    out = dict(line[3:].split() for line in done.stdout.splitlines() if line.startswith("@@"))
    err = dict(zip(["info", "plot", "resume"], done.stderr.split("@@ ")[:3], strict=True))
    assert "Traceback" not in done.stderr
    if out["info"] == "2":  # nothing is left of what the file is
        assert "is damaged beyond reading" in err["info"] and "truncated" in err["info"]
        assert out["plot"] == out["resume"] == "2"
        return
    assert out["info"] == "0" and "damaged: the file is truncated" in done.stdout
    assert "is damaged" in err["plot"] or out["plot"] == "2"
    if out["resume"] == "2":
        assert "no intact checkpoint" in err["resume"]
        return
    # it resumed from an intact checkpoint: then it gives what the run in one go gives
    assert out["resume"] == "0" and "resuming from its last intact checkpoint" in err["resume"]
    same_results(cut, reference)


_HOLD_LOCK = textwrap.dedent("""\
    import sys
    from pathlib import Path
    from saxum.results import _Lock
    lock = _Lock(Path(sys.argv[1]))  # as a live writer holds it
    print("held", flush=True)
    sys.stdin.readline()
""")


@pytest.mark.skipif(sys.platform == "win32", reason="no advisory locks: no live writer to tell")
@pytest.mark.parametrize("percent", [1, 10, 50])
def test_a_file_damaged_while_its_writer_runs_is_read_without_hanging(tmp_path, reference,
                                                                       percent):
    """Before: a file whose writer holds its lock is read as an SWMR reader, which retries
    damaged metadata with sleeps that double each time (hours): info and plot hung."""
    cut = tmp_path / "cut.h5"
    shutil.copy(reference, cut)
    os.truncate(cut, os.path.getsize(reference) * percent // 100)
    holder = subprocess.Popen([sys.executable, "-c", _HOLD_LOCK, str(cut)],
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline() == "held\n"
        done = subprocess.run([sys.executable, "-c", _COMMANDS, str(cut),
                               str(tmp_path / "p.png")],
                              capture_output=True, text=True, timeout=HANG)
    finally:
        holder.communicate("\n", timeout=HANG)
    assert done.returncode == 0, done.stderr
    out = dict(line[3:].split() for line in done.stdout.splitlines() if line.startswith("@@"))
    err = dict(zip(["info", "plot", "resume"], done.stderr.split("@@ ")[:3], strict=True))
    assert "Traceback" not in done.stderr
    for command in ("info", "plot"):  # read, or refused with a message (no frame is left)
        assert out[command] == "0" or (out[command] == "2" and "bad input" in err[command])
    assert out["resume"] == "2" and "is being written" in err["resume"]  # never resumed


def test_a_damaged_frame_drops_it_and_what_follows_and_resume_starts_before(tmp_path,
                                                                              reference):
    bad = tmp_path / "bad.h5"
    shutil.copy(reference, bad)
    with h5py.File(bad, "r") as f:
        ds = f["frames/body_q"]
        offset = ds.id.get_chunk_info(0).byte_offset + 12 * ds.dtype.itemsize * np.prod(
            ds.shape[1:])  # frame 12's first coordinate (one chunk holds all frames)
    with open(bad, "r+b") as f:
        f.seek(int(offset) + 3)
        byte = f.read(1)
        f.seek(int(offset) + 3)
        f.write(bytes([byte[0] ^ 0x10]))
    with pytest.warns(ResultsDamageWarning, match="output frames: 39 of 51 lost, from row 12"):
        r = Results(bad)
    with r:
        assert r.frame_count == 12 and r.time[-1] == pytest.approx(0.11)
        assert r.checkpoint_steps[r.resumable - 1] == 100  # the last that the frames reach
    with pytest.warns(ResultsDamageWarning, match="resuming from its last intact checkpoint, "
                                                  "step 100"):
        resume_run(bad, quiet=True)
    same_results(bad, reference)


_FULL_DISK = textwrap.dedent("""\
    import resource, signal, sys
    from saxum.cli import main
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # write() then fails with EFBIG
    # mid-run: the whole run's file is 1.7 MB, its first frame and checkpoint ~1.1 MB
    # (HDF5 chunks; checkpoints hold the solver's state and crush since 2026-11-28)
    resource.setrlimit(resource.RLIMIT_FSIZE, (1_300_000, 1_300_000))
    if sys.argv[3] == "cli":
        sys.exit(main(["run", sys.argv[1], "-o", sys.argv[2], "-q"]))
    from saxum.errors import ResultsWriteError
    from saxum.runner import run_scenario
    from saxum.scenario import load_scenario
    try:
        run_scenario(load_scenario(sys.argv[1]), sys.argv[2], quiet=True)
    except ResultsWriteError:
        print("caught")
""")


def test_a_full_disk_is_a_clear_failure_and_the_file_resumes(tmp_path, reference):
    """Before: an HDF5 error, then a segmentation fault (exit 139)."""
    (tmp_path / "arch.toml").write_text(SCENARIO)
    out = tmp_path / "arch.h5"
    done = subprocess.run([sys.executable, "-c", _FULL_DISK, "arch.toml", str(out), "cli"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=HANG)
    assert done.returncode == 1, done.stderr
    assert f"could not write {out} (File too large: a full disk or a file-size limit?)" in (
        done.stderr)
    assert f"make room and continue with saxum resume {out}" in done.stderr
    assert "Traceback" not in done.stderr and done.stderr.count("\n") == 1  # one line
    with Results(out) as r:
        assert r.status == "interrupted" and r.frame_count > 1 and r.resumable >= 1
    resume_run(out, quiet=True)
    same_results(out, reference)
    # in Python: the error to catch, and no crash when the interpreter exits afterwards
    done = subprocess.run([sys.executable, "-c", _FULL_DISK, "arch.toml", "py.h5", "python"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=HANG)
    assert done.returncode == 0 and done.stdout == "caught\n", done.stderr


_HOLD = textwrap.dedent("""\
    import os, sys
    from saxum.structures import semicircular_arch
    from saxum.results import ResultsWriter
    w = ResultsWriter(sys.argv[1], semicircular_arch(radius=1.0, thickness=0.15, voussoirs=5),
                      dt=1e-3, theta=0.5)
    print("open", flush=True)
    sys.stdin.readline()
    os._exit(0)  # dies without closing the file, as a killed run
""")


def test_a_run_that_died_is_interrupted_and_a_live_one_running(tmp_path, capsys):
    out = tmp_path / "r.h5"
    proc = subprocess.Popen([sys.executable, "-c", _HOLD, str(out)], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline() == "open\n"
    with Results(out) as r:
        assert r.status == "running"
    proc.communicate("\n", timeout=HANG)
    assert main(["info", str(out)]) == 0
    assert f"status: interrupted (resume with saxum resume {out})" in capsys.readouterr().out


def test_a_run_failing_with_any_error_says_failed(tmp_path, monkeypatch):
    from saxum.simulation import Simulation

    original = Simulation.step

    def step(self, state):
        if state.step == 7:
            raise ZeroDivisionError("float division by zero")
        return original(self, state)

    monkeypatch.setattr(Simulation, "step", step)
    with pytest.raises(ZeroDivisionError):
        run_scenario(parse_scenario(SCENARIO), tmp_path / "f.h5", quiet=True)
    with Results(tmp_path / "f.h5") as r:
        assert r.status == "failed" and "ZeroDivisionError: float division by zero" in r.message


@pytest.mark.parametrize("density", [1e300, 1e-300, 0.5, 2e5])
def test_a_density_that_is_not_masonry_is_refused(tmp_path, capsys, density):
    with pytest.raises(InputError, match=re.escape(f"stone: density {density:g} kg/m^3 is "
                                                   "outside 1 .. 100000 kg/m^3")):
        ModelBuilder().add_block([(0, 0), (1, 0), (1, 1), (0, 1)], density=density,
                                 name="stone")
    scenario = tmp_path / "a.toml"
    scenario.write_text(SCENARIO)
    assert main(["run", str(scenario), "--set", f"structure.density={density!r}", "-q"]) == 2
    assert "density" in capsys.readouterr().err
    assert not (tmp_path / "a.h5").exists()


def test_a_resume_that_fails_while_copying_leaves_no_stray_file(tmp_path, reference,
                                                                 monkeypatch):
    """Resuming rewrites the file through FILE.resume-tmp; a failure there (a full disk, an
    interrupt) removes that file and leaves the results as they were, resumable again."""
    import saxum.results

    path = tmp_path / "arch.h5"
    shutil.copy(reference, path)

    def fail(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(saxum.results, "_copy_rows", fail)
    with pytest.raises(OSError):
        saxum.results.ResultsWriter.resume(path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arch.h5"]
    monkeypatch.undo()
    same_results(path, reference, checkpoints=True)
    writer, _ = saxum.results.ResultsWriter.resume(path)  # and the lock was released
    writer.close()
