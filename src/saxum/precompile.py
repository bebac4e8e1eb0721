"""The kernels of a run compiled before its first step, half of them in a second process.

On a first run (numba's cache empty: after an install, or after a kernel's source changed) a
2D run's kernels take ~8 s of CPU to compile, one after the other, in the process that calls
them: numba compiles under a global lock, so threads do not help. A second process that
compiles half of them into numba's cache (cache=True: both processes read and write the same
files) while this one compiles the other half shortens the wait by nearly half on a machine
of two cores or more (BENCHMARKS.md, the first run). Compiled for the argument types of the
run's calls, the machine code is the one a compile on the first call gives: results do not
change. A kernel called with other types (kernel_signatures out of date) compiles on its call, as
without this module; tests/test_precompile.py checks that the list matches a run's calls.

Only the kernels that every 2D run calls are listed for 2D: those of the rest solution,
floods or ground motions compile on their first call. The 3D list, those of a 3D arch's run
(the rest solution's too), is compiled by the package's build only (saxum._shipped_cache, which
ships the 2D ones too).

A Ctrl-C (SIGINT) while this module compiles stops the command as any other does (a
KeyboardInterrupt, after the kernel being compiled): Python runs its SIGINT handler at the next
Python instruction, which during a compile is often inside llvmlite's ctypes callback (the
object code handed back to numba), and a KeyboardInterrupt raised there is printed and dropped
("Exception ignored on calling ctypes callback"): the command went on and could exit 0.
"""

import atexit
import contextlib
import functools
import importlib
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Callable, Iterator
from pathlib import Path

__all__ = ["kernel_signatures", "precompile", "start"]

_CHILD_TIMEOUT = 300.0
"""[s] after which the second process is given up (its kernels then compile on their call)."""


def kernel_signatures() -> dict[int, dict[str, tuple]]:
    """{dim: {"module.kernel": argument types}}; the child process compiles the first half of
    each 2D run's kernels, this process the second (their CPU times balance, less the
    child's start-up). The package's build compiles both dimensions' (saxum._shipped_cache)."""
    from numba import types as t

    f1, f2, f3 = t.float64[::1], t.float64[:, ::1], t.float64[:, :, ::1]
    i32_1, i32_2, i64_1, i8_1, b1 = t.int32[::1], t.int32[:, ::1], t.int64[::1], t.int8[::1], \
        t.boolean[::1]
    i64_2 = t.int64[:, ::1]
    F, I, B, N = t.float64, t.int64, t.boolean, t.none  # noqa: E741 - numba's scalar types
    return {2: {
        # the child's half: 5.4 s of CPU on a quiet machine, 2026-11-25, ~0.6x that since they
        # compile without the joint laws' and law points' code (BENCHMARKS.md)
        "detection.polygons.polygon_contacts": (
            i32_2, I, f2, f2, f1, i32_1, i32_1, i32_2, N, I, F, f1, f1, F, I, f2, f1, f1, f1, B,
            i32_2, f2, i32_1, i32_1, i64_1, i32_1, f2, f3, f1, f1),
        "solver.nlgs.nlgs_2d": (i32_1, i32_1, f3, f3, f3, f1, f1, b1, I, f2, f2, f2, f2, f2, f2,
                                f2, N, N, N, I, F, I, F),
        # this process's half, the smallest first (it tells whether the cache is empty)
        "bodies.rigid2d.predict_positions": (f2, f2, F, f2),
        "solver.nlgs._any_impulse": (f2, I),
        "solver.problem._end_gaps_2d": (i32_1, i32_1, f3, f3, f1, I, f2, f2, f2, F, F, F, f1),
        "contacts._carry": (I, I, i64_1, i64_1, f2, f2, f2, f2, f1, f1, f1, f1, f1, f1, f1, f1,
                            i32_1, i8_1),
        "detection.broadphase.grid_pairs": (f2, f2, b1, b1, F, i32_2),
        "solver.problem._assemble_2d": (I, I, f2, i32_1, i32_1, f2, f3, f1, i32_1, f2, f2,
                                        i8_1, f1, f1, F, F, f2, f3, f3, f3, f1, f1, b1, f2, B),
        "bodies.rigid2d.world_geometry": (f2, i32_1, f2, f2, f2, f2),
        "detection.broadphase.sort_pairs": (i32_2, I, I),
        "bodies.rigid2d.kinetic_energy": (f2, f1, f1, f2),
        "detection.detector._motion_since": (f2, f2, f1, f1, f1),
        "detection.broadphase.bounding_boxes": (f2, i32_1, F, f2, f2),
        "integrator.diagonal_free_velocity": (f2, f2, f2, F, f2),
        "solver.projection._projection_targets": (i32_1, f1, f1, I, i8_1, f2, F, f1, b1),
        "bodies.rigid2d.update_positions": (f2, f2, f2, F, F),
    }, 3: {
        # a 3D run's kernels, the rest solution's too (benchmarks/first_run.py's 3D arch and
        # tests/test_shipped_cache.py): compiled by the package's build (saxum._shipped_cache)
        # only, not at run time (no second process for 3D: _CHILD_SHARE). The build's first
        # process compiles the first two with the 2D ones above, the second the rest
        "detection.polyhedra.polyhedron_contacts": (
            i32_2, I, f2, f2, f2, i32_1, i32_1, i32_1, i32_1, i32_1, i32_2, i32_2, i32_1, i32_2,
            i32_1, I, F, f1, f1, F, I, I, I, i32_1, i32_1, i64_1, i32_1, f2, f3, f1, f1),
        "solver.nlgs.nlgs_3d": (i32_1, i32_1, f3, f3, f3, f1, f1, b1, I, f2, f2, f2, f2, f2, f2,
                                f2, N, N, N, I, F, I, F),
        "bodies.rigid3d.angular_velocity_to_body": (f2, i64_1, f2),
        "bodies.rigid3d.world_geometry": (f2, i32_1, f2, i32_1, f2, f2, f2),
        "detection.detector._largest_motion_3d": (f2, f2, f1),
        "detection.broadphase.bounding_boxes": (f2, i32_1, F, f2, f2),
        "detection.broadphase.grid_pairs": (f2, f2, b1, b1, F, i32_2),
        "detection.broadphase.sort_pairs": (i32_2, I, I),
        "bodies.rigid3d.gyroscopic_torques": (f2, f2, f2, f2, F, f2),
        "integrator.diagonal_free_velocity": (f2, f2, f2, F, f2),
        "bodies.rigid3d.predict_positions": (f2, f2, F, f2),
        "contacts._carry": (I, I, i64_1, i64_1, f2, f2, f2, f2, f1, f1, f1, f1, f1, f1, f1, f1,
                            i32_1, i8_1),
        "bodies.rigid3d.contact_jacobians": (f2, i32_1, i32_1, f2, f3, f1, I, f3, f3),
        "solver.problem._assemble": (i32_1, i32_1, i32_1, f1, I, f3, f3, f2, f2, i8_1, f1, f1, F,
                                     F, F, f3, f1, f1, b1),
        "solver.problem._apply": (i32_1, i32_1, f3, f3, b1, I, f2, f2, f2),
        "solver.equilibrium._rest_contacts": (i32_1, i32_1, f3, f3, f1, f1, b1, I, f2, f2, f2,
                                              i64_1, i64_1),
        "solver.equilibrium._pattern": (i32_1, i32_1, i64_1, i64_1, I, I),
        "solver.equilibrium._start": (i64_1, f1, f2, f2, F),
        "solver.equilibrium._residual": (i32_1, i32_1, f3, f3, i64_1, i64_1, f3, f2, f2, f2, f2),
        "solver.equilibrium._newton_system": (i32_1, i32_1, f3, f3, i64_1, i64_1, f3, f2, F,
                                              i64_2, i64_1, i64_1, f2, f1),
        "solver.equilibrium._newton_step": (i32_1, i32_1, f3, f3, i64_1, i64_1, f3, f2, F, f2, B,
                                            f2),
        "solver.block_cholesky._symbolic": (i64_1, i64_1, i64_1),
        "solver.block_cholesky._numeric": (i64_1, i64_1, i64_1, i64_1, f1, i64_1, f3),
        "solver.block_cholesky._solve": (i64_1, i64_1, i64_1, f3, f2, f2),
        "solver.equilibrium._step_length": (f2, f2),
        "solver.equilibrium._inside": (f2,),
        "solver.equilibrium._apply": (i32_1, i32_1, f3, f3, b1, I, i64_1, f3, f2, f2, f2, f2, f2),
        "bodies.rigid3d.update_positions": (f2, f2, f2, F, F),
        "solver.problem._end_gaps": (i32_1, i32_1, f3, f3, f1, I, f2, f2, f2, F, F, F, f1),
        "bodies.rigid3d.kinetic_energy": (f2, f1, f2, f2),
        "solver.load_following._equal": (i64_1, i64_1),
        "solver.load_following._distance": (f2, f2),
    }}


_CHILD_SHARE = {2: 2}
"""How many of kernel_signatures()[dim], from the first, the second process compiles."""


def _kernel(name: str):
    module, _, attr = name.rpartition(".")
    return getattr(importlib.import_module(f"saxum.{module}"), attr)


def _compile(names: list[str], signatures: dict[str, tuple]) -> list[bool]:
    """Compile each kernel for its listed types, unless this process has it already or numba's
    cache holds it; for each, whether it was compiled."""
    from numba.core.errors import NumbaError

    compiled = []
    with _sigint_after_compiles() as interrupted:
        for name in names:
            try:
                kernel = _kernel(name)
            except (ImportError, AttributeError):  # moved or renamed: it compiles on its call
                compiled.append(False)
                continue
            args = signatures[name]
            if not hasattr(kernel, "compile"):  # NUMBA_DISABLE_JIT: plain Python
                return compiled
            known = args in kernel.overloads
            try:
                kernel.compile(args)
            except (TypeError, NumbaError):  # the list is out of date: it compiles on its call
                compiled.append(False)
                continue
            finally:
                interrupted()
            compiled.append(not known and kernel.stats.cache_hits.get(args, 0) == 0)
    return compiled


@contextlib.contextmanager
def _sigint_after_compiles() -> Iterator[Callable[[], None]]:
    """While numba compiles: a SIGINT only sets a flag, and the function this yields raises
    KeyboardInterrupt if one came (module doc), as does the exit, where the previous handler
    is back. Only where SIGINT raises KeyboardInterrupt (Python's default handler, in the
    main thread): an ignored SIGINT, or a run's own handler, stays."""
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield lambda: None
        return
    came = []

    def interrupted() -> None:
        if came:
            came.clear()
            raise KeyboardInterrupt

    previous = signal.signal(signal.SIGINT, lambda signum, frame: came.append(signum))
    try:
        yield interrupted
    finally:
        signal.signal(signal.SIGINT, previous)
    interrupted()


def _cores() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (
        os.cpu_count() or 1)


_children: dict[int, subprocess.Popen] = {}
"""The second process of each dimension, once started."""


def start(dim: int) -> None:
    """Start the second process on its half of the kernels of a run in `dim` dimensions (once,
    and only with two cores or more), as early as a command knows `dim`: it compiles while
    this process loads the rest of what the command needs. It loads its kernels from the
    cache, or compiles them into it; precompile(dim) waits for it, and an exit before that
    stops it."""
    if dim in _CHILD_SHARE and dim not in _children and _cores() > 1:
        if not _children:
            atexit.register(_stop_children)
        _children[dim] = subprocess.Popen(
            [sys.executable, "-c", "import sys; sys.path.insert(0, sys.argv[1]); "
             "from saxum.precompile import _child; _child(int(sys.argv[2]))",
             str(Path(__file__).resolve().parents[1]), str(dim)],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def _stop_children() -> None:
    """At exit (a command that failed or was interrupted before precompile waited): a second
    process still compiling for this one stops with it."""
    for child in _children.values():
        if child.poll() is None:
            child.kill()
            child.wait()


@functools.cache
def precompile(dim: int) -> None:
    """Compile the kernels that every run in `dim` dimensions calls, if numba's cache does not
    hold them yet: half in the second process (start), meanwhile half here. Once per
    process."""
    if dim not in _CHILD_SHARE:
        return
    signatures = kernel_signatures()[dim]
    mine = list(signatures)[_CHILD_SHARE[dim]:]
    if _compile(mine[:1], signatures) != [True]:
        # loaded from the cache: so are the others (or they compile on their call), and a
        # second process started early has nothing to do that this one needs
        if dim in _children:
            _children[dim].kill()
            _children[dim].wait()
        return
    start(dim)
    child = _children.get(dim)
    try:
        _compile(mine[1:], signatures)
        if child is not None:
            child.wait(timeout=_CHILD_TIMEOUT)
    except subprocess.TimeoutExpired:
        pass
    finally:
        if child is not None and child.poll() is None:
            child.kill()
            child.wait()


def _child(dim: int) -> None:
    """The second process: the first _CHILD_SHARE[dim] kernels, into numba's cache."""
    signatures = kernel_signatures()[dim]
    _compile(list(signatures)[:_CHILD_SHARE[dim]], signatures)
