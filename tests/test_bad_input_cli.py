"""Bad input to scenarios and to the command line is named (the key and its line, the file,
the option) and exits with code 2 (issue 12): counts bounded by [limits], strict numbers,
binary block files, absurd lengths, unknown law groups, FCLIB files one by one, -o, Ctrl-C,
and numbers in messages as Python writes them."""

import re
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.sparse as sp
from results_check import sigint_as_from_a_terminal

import saxum as sx
from saxum.cli import main
from saxum.fclib import LocalProblem, write_fclib
from saxum.scenario import parse_scenario
from saxum.structures import ArchShape
from saxum.structures._common import check_count

ARCH = (Path(__file__).parents[1] / "examples" / "arch.toml").read_text()


def _arch(tmp_path, old="", new="", extra=""):
    """examples/arch.toml with `old` replaced by `new` and `extra` appended, in tmp_path."""
    assert old in ARCH
    path = tmp_path / "arch.toml"
    path.write_text(ARCH.replace(old, new) + extra)
    return path


def _line(path, key):
    return next(n for n, line in enumerate(path.read_text().splitlines(), start=1)
                if line.startswith(f"{key} ="))


def _bad(capsys, argv) -> str:
    """Run the CLI: it must exit 2 and say "bad input"; the message."""
    assert main([str(a) for a in argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("saxum: bad input: ") and "Traceback" not in err
    return err


# --- counts and limits --------------------------------------------------------------------------


@pytest.mark.parametrize("voussoirs", ["10000000", "99999999999999999999"])
def test_a_huge_count_is_refused_naming_the_key_and_the_limit(tmp_path, capsys, voussoirs):
    path = _arch(tmp_path, "voussoirs = 15", f"voussoirs = {voussoirs}")
    err = _bad(capsys, ["run", path, "-q"])
    assert f"line {_line(path, 'voussoirs')}: structure.voussoirs = {voussoirs}" in err
    assert "limits.count" in err and "[limits] count = " in err  # and how to raise it
    assert not (tmp_path / "arch.h5").exists()


def test_raising_the_count_limit_lets_the_count_through_to_the_blocks_limit(tmp_path, capsys):
    path = _arch(tmp_path, "voussoirs = 15", "voussoirs = 200000", "\n[limits]\ncount = 300000\n")
    err = _bad(capsys, ["run", path, "-q"])
    assert "structure: its counts multiply to 200000 (voussoirs 200000)" in err
    assert "limits.blocks" in err


def test_the_product_of_counts_is_bounded():
    text = ARCH.replace('type = "semicircular_arch"', 'type = "semicircular_arch_3d"').replace(
        "voussoirs = 15", "voussoirs = 5000\npieces = 5000\ndepth = 1.0").replace(
        "gravity = [0.0, -9.81]", "gravity = [0.0, 0.0, -9.81]")
    with pytest.raises(sx.InputError, match=re.escape("voussoirs 5000 x pieces 5000")):
        parse_scenario(text)


@pytest.mark.parametrize(("override", "words"), [
    ("output.duration=1e9", "1e+12 steps, above the limit of 100000000 steps (limits.steps)"),
    ("output.interval=1e-3", None),  # a frame per step is fine for 2000 steps
    ("solver.max_iterations=100000000", "solver.max_iterations = 100000000"),
    ("detection.refresh_every=1000000000", "detection.refresh_every = 1000000000"),
    ("opening", "structure.openings[0].voussoirs = 20000"),
])
def test_steps_frames_sweeps_and_nested_counts_are_bounded(override, words):
    if override == "opening":
        text = ARCH.replace('type = "semicircular_arch"', 'type = "wall"\ncourses = 10\n'
                            'bricks = 8').replace("radius = 2.0", "").replace(
            "thickness = 0.3", "").replace("voussoirs = 15", "") + (
            '\n[[structure.openings]]\nx = 0.5\nwidth = 0.5\nheight = 0.3\n'
            'head = "flat_arch"\nvoussoirs = 20000\n')
        overrides = []
    else:
        text, overrides = ARCH, [override]
    if words is None:
        parse_scenario(text, overrides=overrides)
        return
    with pytest.raises(sx.InputError, match=re.escape(words)) as info:
        parse_scenario(text, overrides=overrides)
    assert "[limits]" in str(info.value)


def test_frames_are_bounded_by_limits_frames():
    with pytest.raises(sx.InputError, match=re.escape("limits.frames")) as info:
        parse_scenario(ARCH, overrides=["output.duration=1000", "output.interval=1e-3"])
    assert "output.duration / output.interval = 1e+06 frames" in str(info.value)
    parse_scenario(ARCH, overrides=["output.duration=1000", "output.interval=1e-3",
                                    "limits.frames=1000000"])


def test_limits_are_strict_whole_numbers():
    from saxum.scenario import LimitsSpec

    with pytest.raises(sx.InputError, match="limits.count"):
        parse_scenario(ARCH, overrides=["limits.count=1e9"])
    assert LimitsSpec().count == 10_000


# --- strict numbers -----------------------------------------------------------------------------


@pytest.mark.parametrize(("old", "new", "key", "words"), [
    ("density = 2000.0", "density = true", "structure.density",
     "a number is needed, not true"),
    ("voussoirs = 15", "voussoirs = false", "structure.voussoirs",
     "a whole number is needed, not false"),
    ("voussoirs = 15", "voussoirs = 15.0", "structure.voussoirs", "valid integer"),
    ("density = 2000.0", 'density = "2000"', "structure.density", "valid number"),
    ("friction = 0.6", "friction = true", "laws[0].friction", "not true"),
    ("duration = 2.0", "duration = true", "output.duration", "not true"),
])
def test_booleans_and_strings_are_not_numbers(tmp_path, capsys, old, new, key, words):
    path = _arch(tmp_path, old, new)
    err = _bad(capsys, ["run", path, "-q"])
    assert f"{key}: " in err and words in err
    assert f"line {_line(path, new.split(' =')[0])}:" in err


def test_an_integer_is_a_number():
    sc = parse_scenario(ARCH.replace("density = 2000.0", "density = 2000"))
    # the integer 2000 read as a number (exactly representable; approx guards the comparison
    # against any conversion path)
    assert sc.structure.density == pytest.approx(2000.0, rel=1e-15)


def test_numpy_numbers_are_numbers_in_python_but_numpy_booleans_are_not():
    from pydantic import ValidationError

    from saxum.scenario import ArchStructure

    arch = ArchStructure(radius=np.float32(2.0), thickness=np.int64(1), voussoirs=np.int64(9))
    assert (arch.radius, arch.thickness, arch.voussoirs) == (2.0, 1.0, 9)
    assert type(arch.voussoirs) is int
    with pytest.raises(ValidationError, match="valid number"):
        ArchStructure(radius=np.bool_(True), thickness=0.3, voussoirs=9)


# --- files --------------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", ["json", "csv"])
def test_a_binary_block_file_is_named(tmp_path, capsys, suffix):
    (tmp_path / f"blocks.{suffix}").write_bytes(b"\x00\x01\xff\xfe{binary")
    path = tmp_path / "blocks.toml"
    path.write_text(f'[structure]\ntype = "blocks"\nfile = "blocks.{suffix}"\n\n[[laws]]\n'
                    'groups = ["*", "*"]\nfriction = 0.6\n\n[output]\nduration = 0.1\n')
    err = _bad(capsys, ["run", path, "-q"])
    assert f"blocks.{suffix}: not a text file" in err and "UnicodeDecodeError" not in err


# --- the key at fault, not what it broke ----------------------------------------------------------


@pytest.mark.parametrize(("old", "new"), [("radius = 2.0", "radius = 1e300"),
                                          ("thickness = 0.3", "thickness = 1e-300")])
def test_an_absurd_length_blames_the_key_not_a_block(tmp_path, capsys, old, new):
    path = _arch(tmp_path, old, new)
    key = new.split(" =")[0]
    err = _bad(capsys, ["run", path, "-q"])
    assert f"line {_line(path, key)}: structure.{key}: not a length of a masonry" in err
    assert "support" not in err


def test_an_unknown_group_of_an_exact_law_pair_names_the_scenario_key(tmp_path, capsys):
    path = _arch(tmp_path, 'groups = ["voussoir", "support"]',
                 'groups = ["voussoir", "suport"]')
    err = _bad(capsys, ["run", path, "-q"])
    assert "laws[1].groups names group 'suport', which no block has" in err
    assert "set_law" not in err


# --- FCLIB files --------------------------------------------------------------------------------


def _fclib(tmp_path):
    w = sp.csr_matrix(np.array([[2.0, 1.0], [1.0, 2.0]]))
    good = tmp_path / "good.hdf5"
    write_fclib(good, LocalProblem(w, np.array([-1.0, 0.2]), np.array([0.3]), 2))
    nan = tmp_path / "nan.hdf5"
    nan.write_bytes(good.read_bytes())
    with h5py.File(nan, "r+") as h5:
        h5["fclib_local/vectors/q"][0] = np.nan
    junk = tmp_path / "junk.hdf5"
    junk.write_bytes(b"not an HDF5 file")
    return good, nan, junk


def test_nan_in_an_fclib_file_is_bad_input(tmp_path, capsys):
    _, nan, _ = _fclib(tmp_path)
    err = _bad(capsys, ["fclib", "solve", nan])
    assert "nan.hdf5: q has 1 value(s) that are not finite numbers" in err


def test_bad_fclib_files_are_named_and_the_others_solved(tmp_path, capsys):
    good, nan, junk = _fclib(tmp_path)
    assert main(["fclib", "solve", str(good), str(nan), str(junk), str(good)]) == 2
    out, err = capsys.readouterr()
    assert out.count("| good.hdf5 | local |") == 2 and "yes" in out  # both good ones solved
    assert "nan.hdf5: q has 1 value(s)" in err and "junk.hdf5: not a readable HDF5" in err
    assert "2 of 4 file(s) left out" in err and "Traceback" not in err


# --- the command line ---------------------------------------------------------------------------


def test_output_that_is_a_folder_or_in_no_folder_is_bad_input(tmp_path, capsys):
    path = _arch(tmp_path)
    err = _bad(capsys, ["run", path, "-o", tmp_path, "-q"])
    assert f"-o {tmp_path}: is a folder" in err
    err = _bad(capsys, ["run", path, "-o", tmp_path / "no" / "r.h5", "-q"])
    assert f"there is no folder {tmp_path / 'no'}" in err


@pytest.mark.parametrize(("argv", "option"), [
    (["animate", "r.h5", "--fps", "0"], "--fps"),
    (["view", "r.h5", "--every", "0"], "--every"),
    (["demo", "arch", "--duration", "1e12"], "--duration"),
    (["demo", "arch", "--duration", "nan"], "--duration"),
    (["fclib", "solve", "p.hdf5", "--max-iterations", "99999999999999999999"],
     "--max-iterations"),
    (["collapse-curve", "s.toml", "--periods", "1", "--stands", "0", "--collapses", "1",
      "--processes", "100000000"], "--processes"),
    (["collapse-curve", "s.toml", "--periods", ",".join(["1"] * 1001), "--stands", "0",
      "--collapses", "1"], "--periods"),
])
def test_count_options_are_bounded(capsys, argv, option):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    assert f"argument {option}" in capsys.readouterr().err


def test_ctrl_c_during_start_up_is_a_short_message_and_exit_130(tmp_path, capsys, monkeypatch):
    import saxum.scenario

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(saxum.scenario, "load_scenario", interrupted)
    assert main(["run", str(_arch(tmp_path)), "-q"]) == 130
    err = capsys.readouterr().err
    assert err == "saxum: interrupted\n"


# `python -m saxum` with an import hook that stops the import of module sys.argv[1] (its first
# import, before saxum.cli.main runs) until a signal comes, having said so on stdout
_SLOW_IMPORT = textwrap.dedent("""\
    import runpy, sys, time

    stalled = sys.argv[1]

    class Stall:
        def find_spec(self, name, path=None, target=None):
            if name == stalled:
                sys.meta_path.remove(self)
                print("importing", flush=True)
                time.sleep(60)

    sys.meta_path.insert(0, Stall())
    sys.argv = ["saxum", *sys.argv[2:]]
    runpy.run_module("saxum", run_name="__main__", alter_sys=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
@pytest.mark.parametrize("module", ["saxum.cli", "numpy"])
def test_ctrl_c_while_the_command_loads_is_a_short_message_and_exit_130(tmp_path, module):
    """Before: a KeyboardInterrupt traceback (saxum/__init__.py imported the whole package
    before any handler was in place)."""
    proc = subprocess.Popen([sys.executable, "-c", _SLOW_IMPORT, module, "info",
                             str(tmp_path / "none.h5")], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True,
                            preexec_fn=sigint_as_from_a_terminal)
    try:
        assert proc.stdout.readline() == "importing\n"
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 130 and err == "saxum: interrupted\n", err


# --- numbers in messages ------------------------------------------------------------------------


@pytest.mark.parametrize(("call", "shown"), [
    (lambda: check_count("voussoirs", np.int64(0)), "got 0"),
    (lambda: ArchShape.circular(span=2.0, thickness=0.2, embrace=np.float64(4.0)), "got 4.0"),
    (lambda: sx.ModelBuilder(gravity=np.array([0.0, np.nan])), "got [0.0, nan]"),
    (lambda: sx.ModelBuilder(gravity=(np.float64(0.0), np.float64(np.inf))),
     "got (0.0, inf)"),
    (lambda: sx.ModelBuilder().add_block([(0, 0), (2, 0), (1, 0.5), (2, 2), (0, 2)],
                                         density=1.0), "vertex 2 at (1, 0.5) is a reflex"),
])
def test_numbers_in_messages_are_plain(call, shown):
    with pytest.raises(sx.InputError) as info:
        call()
    assert shown in str(info.value) and "np." not in str(info.value)
