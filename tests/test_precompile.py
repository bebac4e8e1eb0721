"""The first run's kernels compiled ahead, half in a second process (saxum.precompile)."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from results_check import sigint_as_from_a_terminal

import saxum.precompile
from saxum.precompile import _CHILD_SHARE, kernel_signatures

_EMPTY = {"SAXUM_SHIPPED_CACHE": "0"}
"""With an empty NUMBA_CACHE_DIR: no kernel loaded from the package's shipped cache either
(saxum._shipped_cache; an install compiles one)."""

# The bundled demo's two arches, 1 s each (long enough for a position projection), in a
# process whose numba cache starts empty; then, for each saxum kernel this process holds: its
# signatures and whether it was loaded from the cache (so compiled by the second process).
_RUN = textwrap.dedent("""\
    import gc, json, sys, tempfile
    from pathlib import Path
    from numba.core.dispatcher import Dispatcher
    from saxum.demos import bundled_scenario
    from saxum.runner import run_scenario
    folder = Path(tempfile.mkdtemp())
    for name in ("arch-stands", "arch-collapses"):
        scenario, _ = bundled_scenario(name, 1.0)
        run_scenario(scenario, folder / f"{name}.h5", quiet=True)
    out = {}
    for d in gc.get_objects():
        if isinstance(d, Dispatcher) and d.py_func.__module__.startswith("saxum.") and d.overloads:
            name = f"{d.py_func.__module__[6:]}.{d.py_func.__name__}"
            out[name] = [[str(s) for s in d.signatures], sum(d.stats.cache_hits.values()) > 0]
    print(json.dumps(out))
""")


def test_a_first_2d_run_compiles_each_kernel_once_for_the_listed_types(tmp_path):
    """The listed argument types are those of a 2D run's calls (else a kernel would compile
    twice: for the list, then for the call), every kernel a 2D run calls is listed (else it
    would compile on its call, after the others), and the second process compiled its share
    into the cache, from which this process loaded it."""
    src = str(Path(saxum.precompile.__file__).parents[1])  # this saxum, in the child too
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), **_EMPTY,
           "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, "-c", _RUN], capture_output=True, text=True,
                          timeout=600, env=env)
    assert done.returncode == 0, done.stderr
    kernels = json.loads(done.stdout)
    listed = kernel_signatures()[2]
    assert sorted(kernels) == sorted(listed)
    for k, (name, types) in enumerate(listed.items()):
        signatures, from_cache = kernels[name]
        assert signatures == [str(types)], name
        assert from_cache == (k < _CHILD_SHARE[2]), name  # the second process's share


def test_a_kernel_whose_listed_types_no_longer_fit_is_left_to_compile_on_its_call():
    """A kernel's arguments changed without its list: no error (before: a TypeError from
    numba stopped the run); the kernel compiles on its first call, as without the list."""
    from numba import types

    from saxum.precompile import _compile

    listed = {"rigid2d.predict_positions": (types.float64[:, ::1],),  # a missing argument
              "rigid2d.update_positions": (types.int8,) * 5}  # arguments of other types
    assert _compile(list(listed), listed) == [False, False]


def _children(pid: int) -> list[int]:
    """Processes whose parent is `pid` (Linux's /proc)."""
    kids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:  # ended meanwhile
            continue
        if int(fields[1]) == pid:
            kids.append(int(stat.parent.name))
    return kids


def _first_demo(tmp_path) -> subprocess.Popen:
    """`saxum demo arch` (this saxum) started with an empty numba cache, as from a terminal."""
    src = str(Path(saxum.precompile.__file__).parents[1])
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), **_EMPTY,
           "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    return subprocess.Popen([sys.executable, "-m", "saxum", "demo", "arch", "-o",
                             str(tmp_path / "demo.png")], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True,
                            preexec_fn=sigint_as_from_a_terminal)


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads Linux's /proc")
def test_ctrl_c_on_a_first_demo_stops_the_second_process_too(tmp_path):
    """Before: the second process went on compiling after the command had said interrupted."""
    proc = _first_demo(tmp_path)
    try:
        deadline = time.monotonic() + 240
        while not (kids := _children(proc.pid)) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert kids, "no second process started"
        # a Ctrl-C that lands inside llvmlite's ctypes callback while numba compiles outside
        # saxum.precompile (which defers it: the test below) is printed and dropped by Python
        # ("Exception ignored on calling ctypes callback"): the run goes on, as it would for a
        # user, who presses Ctrl-C again; so interrupt until it ends (or it finishes first:
        # seen in CI). Either way no second process may be left running
        while True:
            proc.send_signal(signal.SIGINT)
            try:
                _, err = proc.communicate(timeout=10)
                break
            except subprocess.TimeoutExpired:
                assert time.monotonic() < deadline, "the demo did not stop"
    finally:
        proc.kill()
    dropped = err.count("Exception ignored on calling ctypes callback")
    assert err.count("Traceback") == dropped, err  # no traceback but llvmlite's dropped ones
    if not (dropped and proc.returncode == 0):  # else the demo ended before the next Ctrl-C
        assert proc.returncode == 130 and err.endswith("saxum: interrupted\n"), err
    assert not [k for k in kids if Path(f"/proc/{k}").exists()
                and Path(f"/proc/{k}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"]


# A Ctrl-C in the middle of the first compile of `saxum demo arch` (numba's cache empty), made
# to arrive where a real one often does: while LLVM emits the object code, so that Python runs
# its handler in the next Python code, numba's hook that llvmlite calls back through ctypes.
_CTRL_C_WHILE_LLVM_COMPILES = textwrap.dedent("""\
    import os, signal, sys
    from numba.core.codegen import CPUCodeLibrary
    hook = CPUCodeLibrary._object_compiled_hook.__func__
    sent = []
    def compiled(cls, ll_module, buf):
        if not sent:
            sent.append(True)
            os.kill(os.getpid(), signal.SIGINT)
        return hook(cls, ll_module, buf)
    CPUCodeLibrary._object_compiled_hook = classmethod(compiled)
    from saxum.cli import main
    sys.exit(main(sys.argv[1:]))
""")


def test_ctrl_c_while_llvm_compiles_stops_the_first_demo(tmp_path):
    """Before: the KeyboardInterrupt raised in llvmlite's ctypes callback was printed and
    dropped ("Exception ignored on calling ctypes callback"), and the demo went on to the end
    and exited 0; now it stops after that kernel's compile, as for any Ctrl-C."""
    src = str(Path(saxum.precompile.__file__).parents[1])
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), **_EMPTY,
           "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, "-c", _CTRL_C_WHILE_LLVM_COMPILES, "demo", "arch",
                           "-o", str(tmp_path / "demo.png")], env=env, capture_output=True,
                          text=True, timeout=600, preexec_fn=sigint_as_from_a_terminal)
    assert done.returncode == 130, done.stderr
    assert done.stderr == "saxum: interrupted\n"
    assert not (tmp_path / "demo.png").exists()


# A 3D arch (that Ctrl-C stops during its first compile)
_ARCH3D = textwrap.dedent("""\
    structure.type = "semicircular_arch_3d"
    structure.radius = 1.0
    structure.thickness = 0.2
    structure.voussoirs = 9
    structure.depth = 0.4
    laws = [{groups = ["voussoir", "voussoir"], friction = 0.6},
            {groups = ["voussoir", "support"], friction = 0.6}]
    output.duration = 0.1
""")


def test_ctrl_c_while_llvm_compiles_a_kernel_outside_precompile_stops_the_run(tmp_path):
    """A 3D run's kernels compile on their first call (saxum.precompile lists 2D ones only),
    the first while the initial contacts are found, before the run's own handler. Before: the
    KeyboardInterrupt was printed with a traceback and dropped, and the run went on to the end
    and exited 0; now the Ctrl-C is sent again (saxum.cli) and the command stops, 130."""
    src = str(Path(saxum.precompile.__file__).parents[1])
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), **_EMPTY,
           "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    (tmp_path / "arch3d.toml").write_text(_ARCH3D)
    done = subprocess.run([sys.executable, "-c", _CTRL_C_WHILE_LLVM_COMPILES, "run",
                           str(tmp_path / "arch3d.toml"), "--quiet"], env=env,
                          capture_output=True, text=True, timeout=600,
                          preexec_fn=sigint_as_from_a_terminal)
    assert done.returncode == 130, done.stderr
    assert done.stderr == "saxum: interrupted\n"
    assert not (tmp_path / "arch3d.h5").exists()


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads Linux's /proc")
@pytest.mark.parametrize("delay", [0.0, 0.7, 2.0])
def test_one_ctrl_c_at_any_moment_of_a_first_demo_stops_it(tmp_path, delay):
    """A single Ctrl-C, `delay` seconds [s] after the second process started (numba's cache
    empty: imports, compiles in both processes, or the first steps), stops the demo: 130, one
    line, no traceback. Before: one that Python dropped during a compile let the demo go on."""
    proc = _first_demo(tmp_path)
    try:
        deadline = time.monotonic() + 240
        while not _children(proc.pid) and time.monotonic() < deadline:
            time.sleep(0.02)
        time.sleep(delay)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=240)
    finally:
        proc.kill()
    assert (proc.returncode, err) == (130, "saxum: interrupted\n")
