"""Helpers shared by the tests of runs, resumes and results files: start `saxum` in a
subprocess, wait for its first frames, and compare two results files bit for bit (two runs of
the same scenario on this machine: a resumed run and the run in one go), or two simulations'
end states (the step on 1 and 2 threads)."""

import signal
import subprocess
import sys
import time

import numpy as np

from saxum.results import Results


def sigint_as_from_a_terminal() -> None:
    """preexec_fn of a child that a test interrupts with SIGINT: the default disposition, as
    when started from a terminal (a shell that runs the tests in the background ignores SIGINT,
    its children inherit that, and Python then installs no KeyboardInterrupt handler)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def start_saxum(args: list[str], cwd, **kw) -> subprocess.Popen:
    """`python -m saxum ARGS` in `cwd`, with its output captured."""
    return subprocess.Popen([sys.executable, "-m", "saxum", *args], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=sigint_as_from_a_terminal, **kw)


def wait_for_frames(path, count: int, proc: subprocess.Popen, timeout: float = 120.0) -> None:
    """Until the results file at `path` holds `count` frames (fails if `proc` ends first or
    `timeout` [s] passes)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise AssertionError(f"the run ended before it could be stopped: {proc.stderr.read()}")
        if path.exists():
            try:
                with Results(path) as r:
                    if r.frame_count >= count:
                        return
            except Exception:  # noqa: BLE001 - the file is still being created
                pass
        time.sleep(0.02)
    raise AssertionError("no frames appeared")


def same_results(a_path, b_path, *, checkpoints: bool = False) -> None:
    """The two files hold the same frames (with their contacts), step reports and histories,
    bit for bit, and neither lost anything; `checkpoints`: at the same steps too."""
    with Results(a_path) as a, Results(b_path) as b:
        assert a.frame_count == b.frame_count and not a.damage and not b.damage
        for name in ("time", "step", "body_q", "body_v"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name
        for k in range(a.frame_count):
            ca, cb = a.contacts(k), b.contacts(k)
            for name in ca:
                assert np.array_equal(ca[name], cb[name]), (k, name)
        for name in a.steps:
            # natural_map and rate are nan where a step converged: nan == nan here
            assert np.array_equal(a.steps[name], b.steps[name],
                                  equal_nan=a.steps[name].dtype.kind == "f"), name
        assert (a.histories is None) == (b.histories is None)
        for name in a.histories or ():
            assert np.array_equal(a.histories[name], b.histories[name]), name
        if checkpoints:
            assert np.array_equal(a.checkpoint_steps, b.checkpoint_steps)


def same_runs(run1, run2) -> None:
    """Two runs, each (Simulation, State) after the same steps: their positions, velocities,
    impulses and sweeps, bit for bit."""
    (sim1, s1), (sim2, s2) = run1, run2
    assert np.array_equal(s1.body_q, s2.body_q)
    assert np.array_equal(s1.body_v, s2.body_v)
    assert np.array_equal(s1.contacts.impulse[:s1.contacts.count],
                          s2.contacts.impulse[:s2.contacts.count])
    assert np.array_equal(sim1.log.iterations, sim2.log.iterations)
