"""Running scenarios: the command line end to end, results left by a killed run, Ctrl-C, and
resume giving bit for bit what the run made in one go gives."""

import shutil
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from PIL import Image
from results_check import same_results, start_saxum, wait_for_frames

import saxum as sx
from saxum.cli import main
from saxum.results import Results, ResultsWriter
from saxum.runner import resume_run, run_scenario
from saxum.scenario import parse_scenario

# A collapsing arch (t/R = 0.09 < 0.1075): every step has work to do for the solver.
SCENARIO = textwrap.dedent("""\
    title = "thin arch"
    [structure]
    type = "semicircular_arch"
    radius = 1.0
    thickness = 0.09
    voussoirs = 15
    [[laws]]
    groups = ["voussoir", "voussoir"]
    friction = 0.6
    [[laws]]
    groups = ["voussoir", "support"]
    friction = 0.6
    [output]
    duration = 1.0
    interval = 0.01
    checkpoint_interval = 0.05
    histories = ["voussoir 8", 1]
""")


@pytest.fixture(scope="module")
def one_go(tmp_path_factory):
    """The reference: the scenario run in one go, in this process."""
    path = tmp_path_factory.mktemp("one_go") / "arch.h5"
    summary = run_scenario(parse_scenario(SCENARIO), path, quiet=True)
    assert summary.status == "finished" and summary.steps == 1000
    return path


def test_results_of_a_run(one_go):
    with Results(one_go) as r:
        assert r.status == "finished"
        assert r.frame_count == 101 and np.allclose(r.time, np.arange(101) * 0.01)
        assert r.steps["step"].tolist() == list(range(1, 1001))
        # times are k h from the step index, not sums of h (no round-off drift)
        assert np.array_equal(r.time, r.step * r.dt)
        assert np.array_equal(r.steps["time"], r.steps["step"] * r.dt)
        assert r.checkpoint_steps.tolist() == list(range(0, 1001, 50))
        assert r.units["body_q"] == "m, m, rad"
        crown = r.body_name.index("voussoir 8")
        assert r.body_q[-1, crown, 1] < r.body_q[0, crown, 1] - 0.1  # it collapsed
        c = r.contacts(-1)
        assert np.array_equal(c["force"], c["impulse"] / r.dt)
        ds = r.to_xarray()
        assert ds["body_q"].sel(body="voussoir 8").shape == (101, 3)
        h = r.histories  # every step, the frames' values at the frames' steps
        assert h["name"] == ["voussoir 8", "voussoir 1"] and h["step"].tolist() == list(
            range(1, 1001))
        assert np.array_equal(h["body_q"][9::10, 0], r.body_q[1:, crown])
        assert "ground_acceleration" not in h


def test_sigkill_leaves_a_readable_file_and_resume_matches_one_go(tmp_path, one_go):
    scenario = tmp_path / "arch.toml"
    scenario.write_text(SCENARIO)
    results = tmp_path / "arch.h5"
    proc = start_saxum(["run", str(scenario), "-o", str(results), "--quiet"], tmp_path)
    wait_for_frames(results, 12, proc)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    with Results(results) as r:  # everything up to the last flush, consistent
        # no process holds the file: the run is said interrupted, with how to resume it
        assert r.status == "interrupted" and f"saxum resume {results}" in r.message
        assert not r.damage
        assert 12 <= r.frame_count < 101
        assert r.steps["step"].size >= r.step[-1]
        assert r.checkpoint_steps.size >= 1
        left = r.frame_count
    _same_frames_prefix(results, one_go, left)
    summary = resume_run(results, quiet=True)
    assert summary.status == "finished"
    same_results(results, one_go)


def _same_frames_prefix(path, reference, count):
    with Results(path) as a, Results(reference) as b:
        assert np.array_equal(a.body_q[:count], b.body_q[:count])


def test_ctrl_c_stops_cleanly_says_how_to_resume_and_resume_matches(tmp_path, one_go):
    scenario = tmp_path / "arch.toml"
    scenario.write_text(SCENARIO)
    results = tmp_path / "arch.h5"
    proc = start_saxum(["run", str(scenario), "-o", str(results), "--quiet"], tmp_path)
    wait_for_frames(results, 8, proc)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 0, err
    assert "interrupted" in out and f"saxum resume {results}" in out
    with Results(results) as r:
        assert r.status == "interrupted"
        stopped = r.step[-1]
        # a checkpoint where it stopped (the solver's state there, the refinement's flags,
        # in it: saxum.solver.nlgs.Refinement)
        assert r.checkpoint_steps[-1] == stopped
    assert main(["resume", str(results), "--quiet"]) == 0
    same_results(results, one_go)


def test_cli_run_and_info(tmp_path, capsys):
    scenario = tmp_path / "short.toml"
    scenario.write_text(SCENARIO.replace("duration = 1.0", "duration = 0.05"))
    assert main(["run", str(scenario), "--quiet"]) == 0
    out = capsys.readouterr().out
    results = tmp_path / "short.h5"
    assert "finished: 50 steps" in out and str(results) in out
    assert main(["info", str(results)]) == 0
    out = capsys.readouterr().out
    assert "status: finished" in out and "thin arch" in out and "steps: 50" in out
    assert main(["resume", str(results), "--quiet"]) == 0
    assert "already finished at t = 0.05 s (step 50): nothing to resume" in (
        capsys.readouterr().out)
    # saxum info RESULTS | head: the reader has gone before saxum writes; no error for that
    proc = subprocess.Popen([sys.executable, "-m", "saxum", "info", str(results)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    proc.stdout.close()
    err = proc.stderr.read()
    assert proc.wait(timeout=60) == 0 and "Broken" not in err, err


def test_cli_pictures_animation_and_paraview(tmp_path, capsys):
    scenario = tmp_path / "short.toml"
    scenario.write_text(SCENARIO.replace("duration = 1.0", "duration = 0.05"))
    assert main(["run", str(scenario), "--quiet"]) == 0
    results = tmp_path / "short.h5"
    assert main(["plot", str(results)]) == 0
    assert main(["plot", str(results), "--histories", "--body", "voussoir 8", "-o",
                 str(tmp_path / "h.png")]) == 0
    assert main(["animate", str(results), "--fps", "5"]) == 0
    assert main(["export-vtk", str(results)]) == 0
    out = capsys.readouterr().out

    assert Image.open(tmp_path / "short.png").format == "PNG"
    assert Image.open(tmp_path / "h.png").format == "PNG"
    gif = Image.open(tmp_path / "short.gif")
    assert gif.format == "GIF" and gif.n_frames == 6  # frames at 0, 0.01, ..., 0.05 s
    assert (tmp_path / "short.pvd").is_file()
    assert len(list((tmp_path / "short").glob("*.vtu"))) == 12  # blocks + contacts per frame
    assert "ParaView collection" in out
    assert main(["plot", str(results), "--frame", "99"]) == 2  # no such frame
    assert main(["animate", str(results), "-o", str(tmp_path / "a.avi")]) == 2


def test_cli_exit_codes(tmp_path, capsys):
    assert main(["run", str(tmp_path / "absent.toml")]) == 2
    assert "no scenario file" in capsys.readouterr().err
    bad = tmp_path / "bad.toml"
    bad.write_text(SCENARIO.replace("voussoirs = 15", "voussoirs = -1"))
    assert main(["run", str(bad)]) == 2
    assert "line 6: structure.voussoirs" in capsys.readouterr().err
    assert main(["info", str(bad)]) == 2  # not a results file
    assert main(["run", str(bad), "--set", "structure.voussoirs=15", "--set",
                 "structure.radius=0.04", "--quiet"]) == 2  # thickness >= 2 radius
    with pytest.raises(SystemExit) as info:
        main(["frobnicate"])
    assert info.value.code == 2
    module = subprocess.run([sys.executable, "-m", "saxum", "info", str(bad)],
                            capture_output=True, text=True, timeout=60)
    assert module.returncode == 2 and "saxum: bad input" in module.stderr  # python -m saxum
    good = tmp_path / "good.toml"
    good.write_text(SCENARIO)
    with pytest.raises(SystemExit) as info:  # argparse's own error: usage, exit code 2
        main(["collapse-curve", str(good), "--periods", "0.5,a", "--stands", "1",
              "--collapses", "2"])
    assert info.value.code == 2 and "give periods in seconds" in capsys.readouterr().err
    assert main(["collapse-curve", str(good), "--periods", "0.5", "--stands", "1",
                 "--collapses", "2"]) == 2
    assert "varies the period of a pulse, and this scenario has none" in (
        capsys.readouterr().err)


def test_cli_collapse_finds_the_overturning_load_of_a_block(tmp_path, capsys):
    """A 0.5 x 1 m block overturns at lambda = b/h = 0.5 (statics of a rigid block)."""
    (tmp_path / "block.json").write_text(
        '{"blocks": [{"vertices": [[-2, -0.2], [2, -0.2], [2, 0], [-2, 0]], "kind": "fixed",'
        ' "group": "ground", "name": "ground"},'
        ' {"vertices": [[0, 0], [0.5, 0], [0.5, 1], [0, 1]], "density": 2000, "name": "pier"}]}')
    (tmp_path / "block.toml").write_text(textwrap.dedent("""\
        [structure]
        type = "blocks"
        file = "block.json"
        [[laws]]
        groups = ["block", "ground"]
        friction = 1.0
        [[laws]]
        groups = ["block", "block"]
        friction = 1.0
        [output]
        duration = 1.0
    """))
    assert main(["collapse", str(tmp_path / "block.toml"), "--vary",
                 "loads.horizontal_acceleration", "--stands", "1", "--collapses", "8",
                 "--tolerance", "0.01"]) == 0
    out = capsys.readouterr().out
    factor = float(out.split("lambda = a/g: ")[1].split()[0])
    assert factor == pytest.approx(0.5, rel=0.01)
    assert "hinge between ground and pier at (0.5" in out
    assert Image.open(tmp_path / "block-collapse.png").format == "PNG"
    assert "NLGS" not in capsys.readouterr().err  # converged at every step of every trial
    # an NLGS that cannot converge in 2 sweeps is reported (in one line, no Python source;
    # NLGS alone: the default hybrid's conic step finishes such steps)
    assert main(["collapse", str(tmp_path / "block.toml"), "--vary",
                 "loads.horizontal_acceleration", "--stands", "1", "--collapses", "8",
                 "--tolerance", "0.2", "--set", "solver.max_iterations=2",
                 "--set", "solver.kind=nlgs"]) == 0
    err = capsys.readouterr().err
    assert "saxum: warning: the contact solver did not converge (NLGS's cap of 2 sweeps)" in err
    assert "warnings.warn" not in err and ".py:" not in err


def test_cli_fclib_solve(capsys):
    from pathlib import Path

    shared = Path(__file__).resolve().parents[2] / "shared" / "fclib"
    problem = shared / "siconosdat_FrictionContactProblem00071.hdf5"
    if not problem.is_file():
        pytest.skip("the shared FCLIB problems are not next to this checkout")
    assert main(["fclib", "solve", str(problem)]) == 0
    row = capsys.readouterr().out.splitlines()[-1]
    assert "| 89 | 2 |" in row and row.endswith("yes (<= 1e-08) |")
    assert main(["fclib", "solve", str(shared / "README.md")]) == 2


def test_cli_collapse_of_a_wall_reports_courses(tmp_path, capsys):
    """A 12-course wall two bricks long (0.5 x 0.78 m) on a tilting table: the report and
    the picture locate its joints by course and position along the course."""
    (tmp_path / "wall.toml").write_text(textwrap.dedent("""\
        [structure]
        type = "wall"
        courses = 12
        bricks = 2
        [[laws]]
        groups = ["*", "*"]
        friction = 1.0
        [output]
        duration = 1.0
    """))
    assert main(["collapse", str(tmp_path / "wall.toml"), "--vary",
                 "loads.horizontal_acceleration", "--stands", "1", "--collapses", "9",
                 "--tolerance", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "course 1 against ground, 0.5 m along" in out  # rocking about the toe
    assert Image.open(tmp_path / "wall-collapse.png").format == "PNG"


def test_collapse_picture_marks_slides_and_courses(tmp_path):
    import dataclasses

    from saxum.mechanism import mechanism
    from saxum.plot import plot_frame
    from saxum.results import Results, ResultsWriter
    from saxum.structures import wall

    model = wall(courses=6, bricks=2, friction=0.3)
    model = dataclasses.replace(model, accelerations=((lambda t: (0.6 * 9.81, 0.0)),))
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    with ResultsWriter(tmp_path / "w.h5", model, dt=1e-3, theta=0.5) as w:
        sim.run(state, 0.1)
        w.write_frame(state)
    mech = mechanism(model, state, 1e-3)
    assert mech.sliding
    with Results(tmp_path / "w.h5") as r:
        ax = plot_frame(r, -1, mechanism=mech).axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert f"sliding ({len(mech.sliding)})" in labels
    assert [t.get_text() for t in ax.texts] == [f"c{c}" for c in range(1, 7)]


# A wall shaken below its sliding threshold: NLGS follows the changing loads from step to step
# (saxum.solver.load_following), state that a checkpoint written at Ctrl-C would not carry.
SHAKEN_WALL = textwrap.dedent("""\
    title = "shaken wall"
    [structure]
    type = "wall"
    courses = 8
    bricks = 6
    [[laws]]
    groups = ["*", "*"]
    friction = 0.6
    [loads.ground_motion]
    pulse = "harmonic"
    amplitude = 2.9
    period = 0.5
    cycles = 4
    [output]
    duration = 2.0
    interval = 0.01
    checkpoint_interval = 0.5
    histories = [1]
""")


def test_ctrl_c_while_following_loads_resumes_bit_for_bit(tmp_path):
    """Stopped between periodic checkpoints while NLGS follows the loads, the run writes a
    checkpoint where it stopped (with the anchors of the loads followed) and resumes from it:
    the same results, bit for bit, as the run in one go."""
    scenario = tmp_path / "wall.toml"
    scenario.write_text(SHAKEN_WALL)
    one_go = tmp_path / "one_go.h5"
    run_scenario(parse_scenario(SHAKEN_WALL), one_go, quiet=True)
    results = tmp_path / "wall.h5"
    proc = start_saxum(["run", str(scenario), "-o", str(results), "--quiet"], tmp_path)
    wait_for_frames(results, 60, proc)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 0, err
    with Results(results) as r:
        assert r.status == "interrupted"
        stopped = r.step[-1]
        assert stopped < 2000  # stopped before the end
        assert r.checkpoint_steps[-1] == stopped
        # its solver (the hybrid's NLGS, "first.") follows the loads
        assert int(r.checkpoint(-1)["first.following.anchors"]) > 0
    assert main(["resume", str(results), "--quiet"]) == 0
    same_results(results, one_go)



# The wall above shaken at 0.7 g, above its sliding threshold (friction 0.6): its first steps
# follow the loads (anchors that checkpoints hold) up to the slide's onset at step 82 (674
# sweeps after a step of 1), whose refinement (saxum.solver.nlgs.Refinement) goes on over the
# steps of the slide after it, which follow no loads; a checkpoint every 60 steps.
SLIDING_WALL = SHAKEN_WALL.replace("amplitude = 2.9", "amplitude = 6.9").replace(
    "duration = 2.0", "duration = 0.1").replace("checkpoint_interval = 0.5",
                                                 "checkpoint_interval = 0.06")
# A wall of 4 courses x 3 bricks under the same shaking slides from its first step, in 40 to
# 220 sweeps a step up to step 82, a sweep or a few after: no onset, and the refinement does
# not carry; a solver with a new one's flags would refine the cheap steps (measured: block
# coordinates 6.4e-9 apart at the end, 10 steps after step 90), so only the flags of the
# checkpoint give the run in one go.
SMALL_SLIDING_WALL = SLIDING_WALL.replace("courses = 8", "courses = 4").replace(
    "bricks = 6", "bricks = 3")

# The same in 3D: a straight wall of 3 courses, 0.75 m long (wall_3d), shaken along it; its
# refinement does not carry at step 120 (with a new one's flags there, coordinates 3.5e-9
# apart at the end, 30 steps after it).
SMALL_SLIDING_WALL_3D = SMALL_SLIDING_WALL.replace('type = "wall"', 'type = "wall_3d"').replace(
    "courses = 4\nbricks = 3", "courses = 3\nlength = 0.75").replace("duration = 0.1",
                                                                     "duration = 0.15")


def _stop_after(monkeypatch, step: int) -> None:
    """Ctrl-C, as the runner sees it (its SIGINT handler), right after step `step`."""
    log_step = ResultsWriter.log_step

    def log_and_stop(self, report):
        log_step(self, report)
        if report.step == step:
            signal.getsignal(signal.SIGINT)(signal.SIGINT, None)

    monkeypatch.setattr(ResultsWriter, "log_step", log_and_stop)


@pytest.fixture(scope="module")
def straight(tmp_path_factory):
    """The run in one go of a scenario text, made once."""
    runs = {}

    def run(text):
        if text not in runs:
            runs[text] = tmp_path_factory.mktemp("straight") / "one_go.h5"
            run_scenario(parse_scenario(text), runs[text], quiet=True)
        return runs[text]

    return run


@pytest.mark.parametrize("wall, kind, stop, resumed_from, flags", [
    (SLIDING_WALL, "nlgs", 90, 90, [1, 1, 1]),  # inside the refined slide: a checkpoint there
    (SLIDING_WALL, "nlgs", 70, 70, [0, 1, 0]),  # following the loads: a checkpoint there too
    # the refinement not carrying: a checkpoint there, which only its flags resume bit for bit
    (SMALL_SLIDING_WALL, "nlgs", 90, 90, [0, 1, 0]),
    (SMALL_SLIDING_WALL, "hybrid", 90, 90, [0, 1, 0]),
    (SMALL_SLIDING_WALL_3D, "nlgs", 120, 120, [0, 1, 0]),
    (SMALL_SLIDING_WALL_3D, "hybrid", 120, 120, [0, 1, 0]),
], ids=["refined", "following", "not-carrying", "not-carrying-hybrid", "not-carrying-3d",
        "not-carrying-3d-hybrid"])
def test_a_sliding_wall_stopped_and_resumed_is_the_run_in_one_go(
        tmp_path, monkeypatch, straight, wall, kind, stop, resumed_from, flags):
    """A run stopped by Ctrl-C in motion writes a checkpoint where it stopped, with the
    solver's state (the refinement flags (carrying, cheap, sliding), and where the solver
    follows the loads, their anchors); resumed from it, its results are the run in one go's
    bit for bit."""
    text = wall + f'[solver]\nkind = "{kind}"\n'
    one_go = straight(text)
    results = tmp_path / "wall.h5"
    with monkeypatch.context() as m:
        _stop_after(m, stop)
        assert run_scenario(parse_scenario(text), results, quiet=True).status == "interrupted"
    with Results(results) as r:
        assert r.step[-1] == stop and r.checkpoint_steps[-1] == resumed_from
        assert r.checkpoint(-1)["refinement"].tolist() == flags
    with Results(one_go) as r:
        assert (r.steps["iterations"][81] >= 200) == (wall == SLIDING_WALL)  # the onset
    assert resume_run(results, quiet=True).status == "finished"
    same_results(results, one_go)


def _without_solver_state(monkeypatch) -> None:
    """Checkpoints read without the solver's state that _SOLVER_STATE packs (the rest
    solution's and the hybrid's back-offs, the loads followed), as before it was stored."""
    from saxum import results as layout

    monkeypatch.setattr(layout, "_unpack_state", lambda data: {})


def _stopped_resumed(tmp_path, monkeypatch, text: str, stop: int):
    """(results file, its last checkpoint, the same file resumed without the solver's packed
    state) of `text` stopped by Ctrl-C after step `stop` and resumed."""
    path, ignored = tmp_path / "run.h5", tmp_path / "ignored.h5"
    with monkeypatch.context() as m:
        _stop_after(m, stop)
        assert run_scenario(parse_scenario(text), path, quiet=True).status == "interrupted"
    with Results(path) as r:
        assert r.checkpoint_steps[-1] == stop
        saved = r.checkpoint(-1)
    shutil.copyfile(path, ignored)
    assert resume_run(path, quiet=True).status == "finished"
    with monkeypatch.context() as m:
        _without_solver_state(m)
        assert resume_run(ignored, quiet=True).status == "finished"
    return path, saved, ignored


# A wall under a horizontal load that grows slowly (the first quarter of a 2 s sine at 0.3 g,
# below its sliding threshold, friction 0.6): at rest relative to its base, NLGS follows the
# loads from step to step (saxum.solver.load_following); checkpoints every 100 steps.
GROWING_LOAD = SHAKEN_WALL.replace('pulse = "harmonic"', 'pulse = "one_sine"').replace(
    "period = 0.5\ncycles = 4", "period = 2.0").replace("duration = 2.0", "duration = 0.2").replace(
    "checkpoint_interval = 0.5", "checkpoint_interval = 0.1") + '[solver]\nkind = "nlgs"\n'


def test_a_wall_following_a_growing_load_stopped_and_resumed_is_the_run_in_one_go(
        tmp_path, monkeypatch, straight):
    """Stopped by Ctrl-C at step 150, between periodic checkpoints, while NLGS follows the
    growing load, the run writes a checkpoint there with the anchors of the loads followed
    (their rest solutions, load changes and Newton systems) and resumes from it bit for bit;
    without them (a file written before they were stored), the first step resumed looks for
    the rest solution again (measured: 76 sweeps where the run in one go took 1) and the
    motion leaves the run in one go's (measured, 50 steps later: coordinates 4.0e-13 m and
    velocities 2.2e-11 m/s apart)."""
    one_go = straight(GROWING_LOAD)
    path, saved, ignored = _stopped_resumed(tmp_path, monkeypatch, GROWING_LOAD, 150)
    assert int(saved["following.anchors"]) > 0
    same_results(path, one_go)
    with Results(ignored) as a, Results(one_go) as b:
        assert a.steps["iterations"][150] > b.steps["iterations"][150] == 1
        assert not np.array_equal(a.body_v[-1], b.body_v[-1])


# A tower of 25 courses x 2 bricks pushed by a 0.7 g pulse of 30 ms (above its sliding
# threshold) under the hybrid with a cap of 1000 sweeps: step 12 ends at the cap, where the
# hybrid tried other solvers and none was kept, so that its back-off (saxum.solver.hybrid,
# _BACKOFF) has it wait a solve; its NLGS has put off the rest solution (saxum.solver.nlgs,
# _REST_BACKOFF) since step 7, whose attempt found none.
PUSHED_TOWER = SHAKEN_WALL.replace("courses = 8", "courses = 25").replace(
    "bricks = 6", "bricks = 2").replace('pulse = "harmonic"', 'pulse = "rectangular"').replace(
    "amplitude = 2.9", "amplitude = 6.9").replace("period = 0.5\ncycles = 4", "period = 0.03"
    ).replace("duration = 2.0", "duration = 0.013").replace(
    "checkpoint_interval = 0.5", "checkpoint_interval = 0.01") + (
    '[solver]\nkind = "hybrid"\nmax_iterations = 1000\n')


def test_a_run_whose_solvers_back_off_stopped_and_resumed_is_the_run_in_one_go(
        tmp_path, monkeypatch, straight):
    """Stopped by Ctrl-C at step 12, between periodic checkpoints, the run writes a checkpoint
    there with the hybrid's back-off (a failed attempt, a solve to wait) and its NLGS's (the
    rest solution put off twice as long) and resumes from it bit for bit; without them,
    step 13 tries the other solvers again, which the run in one go does not (measured: it
    reports 1002 sweeps instead of 1000, the 2 sweeps that judged the rejected iterates)."""
    one_go = straight(PUSHED_TOWER)
    path, saved, ignored = _stopped_resumed(tmp_path, monkeypatch, PUSHED_TOWER, 12)
    assert saved["switch"].tolist() == [1, 1] and saved["first.rest"][0] > 0
    same_results(path, one_go)
    with Results(ignored) as a, Results(one_go) as b:
        assert b.steps["iterations"][12] == 1000
        assert a.steps["iterations"][12] == 1002


def test_a_file_whose_checkpoints_lack_the_solver_state_resumes_with_a_new_one(
        tmp_path, monkeypatch):
    """A results file as saxum wrote it before checkpoints held the solver's state (the
    refinement's flags, the packed rest: with row checksums) resumes, its solver a new one's
    (as saxum resumed every file then), and takes the layout that holds them from there on:
    its earlier checkpoints read as holding none (-1 flags), and nothing reads as damaged."""
    from saxum import results as layout

    text = GROWING_LOAD
    path = tmp_path / "old.h5"
    columns, ragged = layout._ROWS["checkpoints"]
    with monkeypatch.context() as m:
        m.setattr(layout, "_SOLVER_FIELDS", {})
        m.setattr(layout, "_SOLVER_STATE", {})
        m.setitem(layout._ROWS, "checkpoints", (
            tuple(c for c in columns if c not in ("refinement", "solver_state_size")),
            tuple(part for part in ragged if part[2] != "solver_state_size")))
        _stop_after(m, 150)
        run_scenario(parse_scenario(text), path, quiet=True)
    with Results(path) as r:
        assert r.checkpoint_steps[-1] == 150 and not r.damage
        saved = r.checkpoint(-1)
    assert "refinement" not in saved and "following.anchors" not in saved
    sim = parse_scenario(text).build_simulation()
    sim.restore(saved)
    new = sx.NLGS().checkpoint()
    assert {k: v.tolist() for k, v in sim.solver.checkpoint().items()} == {
        k: v.tolist() for k, v in new.items()}  # a new one's
    assert resume_run(path, quiet=True).status == "finished"
    with Results(path) as r:
        assert r.status == "finished" and not r.damage and r.step[-1] == 200
        assert r.steps["step"].tolist() == list(range(1, 201))
        assert r.checkpoint(-2)["refinement"].tolist() == [-1, -1, -1]  # step 150's
        assert "following.anchors" not in r.checkpoint(-2)
        assert int(r.checkpoint(-1)["following.anchors"]) > 0  # the end's, written resumed
