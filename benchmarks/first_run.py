"""Benchmark: the first run after an install, `saxum demo arch` and a small 3D run, from an empty
numba cache and then from the cache that run filled.

Each case runs in a fresh Python process whose NUMBA_CACHE_DIR is a new empty directory (so
every kernel compiles, as on a fresh install), and then again in another fresh process on the
same, now filled, directory (every kernel loads from the cache). MPLCONFIGDIR is a new empty
directory too with --fresh-matplotlib (matplotlib then builds its font cache first, as on a
fresh machine; otherwise it is the user's, already built). Each process reports (seconds,
wall-clock by time.perf_counter unless said):

- total: the process from the interpreter's start to its end, as the user waits for it
  (measured by the parent around the subprocess), and its CPU time (user + system), the
  process's own (main) and that of the process compiling half of the kernels (saxum.precompile)
  (child); and the wall-clock time that this CPU time gives on an idle machine of two cores
  (idle 2-core: the process's own CPU time, plus the time it would wait for the child, which
  runs meanwhile on the other core: the child's CPU time less the CPU time this process spends
  while the child runs), an estimate that a shared, loaded machine cannot measure;
- import: `import saxum.cli` (what the console script imports first), and which heavy packages
  it pulled in;
- compile: the time numba spent in Dispatcher.compile (compiling, or loading from the cache),
  outermost calls; and its CPU time (a compile is single-threaded, so CPU time is what it costs
  without the other loads of a shared machine). Per dispatcher: its own CPU time (less the
  compiles of the dispatchers it calls, which compile while it is typed), and how many compiles
  or loads. (numba's event API, kind "numba:compile", reports compiles but not loads.)
- run: the simulation (run_scenario) less the compiles inside it: stepping and writing;
- plot: the picture (importing matplotlib and saxum.plot, plot_frame, savefig) less the compiles
  inside it; other: the rest of the command (parsing, the demo's own reading of results).

The cases:
- arch: `saxum demo arch` (the two 2D arches of the README, 2 s each);
- arch3d: `saxum run` on a semicircular_arch_3d of 15 voussoirs (1 s, the scenario below) then
  `saxum plot` of its last frame, in one process.

    python benchmarks/first_run.py                    # both cases, empty then filled cache
    python benchmarks/first_run.py --cases arch --top 25 --fresh-matplotlib
    python benchmarks/first_run.py --json /tmp/first_run.json
    python benchmarks/first_run.py --cases arch --src /work/main/src --src src --repeat 3

--src TREE (repeatable) runs each case with PYTHONPATH=TREE, the trees one after the other and
again --repeat times, so that two versions are compared on the same machine and minute. Each
TREE's bytecode is compiled first (python -m compileall, into its __pycache__), as `pip
install` does: otherwise, where PYTHONDONTWRITEBYTECODE is set, every process (the second one
too) would compile saxum's ~70 modules from source, ~0.3 s of CPU each time.

--python PY (repeatable, after the --src trees) runs each case with the interpreter PY and the
saxum installed for it (a virtual environment's bin/python after `pip install .`: the package
as a user gets it, with the numba cache its build shipped, saxum._shipped_cache), without
PYTHONPATH:

    python benchmarks/first_run.py --cases arch --python /tmp/v1/bin/python \
        --python /tmp/v2/bin/python
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent

ARCH3D_TOML = """\
title = "semicircular arch in 3D, t/R = 0.15"

[structure]
type = "semicircular_arch_3d"
radius = 2.0
thickness = 0.3
voussoirs = 15
depth = 0.5
density = 2000.0

[[laws]]
groups = ["voussoir", "voussoir"]
friction = 0.6

[[laws]]
groups = ["voussoir", "support"]
friction = 0.6

[output]
duration = 1.0
interval = 0.02
"""

HEAVY = ("matplotlib", "h5py", "scipy", "pydantic", "numba", "meshio", "tqdm", "tomllib")


# --------------------------------------------------------------------------------------------
# the worker: one case in this (fresh) process


class _CompileTimes:
    """Times numba's Dispatcher.compile (a compile, or a load from the cache): wall-clock time
    of the outermost calls, and CPU time (this process's, less sensitive to a loaded machine
    than wall-clock) per dispatcher, its own: less the compiles nested in it [s]."""

    def __init__(self):
        self.stack = []  # [wall start, CPU start, CPU time in nested compiles]
        self.self_time = {}
        self.count = {}
        self.loads = {}  # dispatcher -> loads from the cache
        self.outer = 0.0  # wall-clock time of the outermost compiles and loads [s]
        self.outer_cpu = 0.0  # their CPU time [s]

    def install(self) -> None:
        """Wraps numba.core.dispatcher.Dispatcher.compile (numba is imported in the worker)."""
        from numba.core.dispatcher import Dispatcher

        compile_, times = Dispatcher.compile, self

        def compile(dispatcher, sig):
            hits, known = sum(dispatcher._cache_hits.values()), len(dispatcher.overloads)
            times.stack.append([time.perf_counter(), time.process_time(), 0.0])
            try:
                return compile_(dispatcher, sig)
            finally:
                start, cpu_start, nested = times.stack.pop()
                took = time.process_time() - cpu_start
                py_func = dispatcher.py_func
                name = f"{py_func.__module__}.{py_func.__qualname__}"
                times.self_time[name] = times.self_time.get(name, 0.0) + took - nested
                new = len(dispatcher.overloads) - known
                if sum(dispatcher._cache_hits.values()) > hits:
                    times.loads[name] = times.loads.get(name, 0) + new
                else:
                    times.count[name] = times.count.get(name, 0) + new
                if times.stack:
                    times.stack[-1][2] += took
                else:
                    times.outer += time.perf_counter() - start
                    times.outer_cpu += took

        Dispatcher.compile = compile


class _Phase:
    """Wraps a function: accumulates wall time in it and the compile time inside it [s],
    unless called inside another phase (plot_frame saves its figure itself)."""

    running = []

    def __init__(self, fn, compiles: _CompileTimes):
        self.fn, self.compiles = fn, compiles
        self.total = self.compile = 0.0

    def __call__(self, *args, **kwargs):
        if self.running:
            return self.fn(*args, **kwargs)
        c0, t0 = self.compiles.outer, time.perf_counter()
        self.running.append(self)
        try:
            return self.fn(*args, **kwargs)
        finally:
            self.running.pop()
            self.total += time.perf_counter() - t0
            self.compile += self.compiles.outer - c0


class _ChildTimes:
    """CPU time [s] of saxum.precompile's second process, and of this process while it ran
    (from its start to the end of the wait for it)."""

    def __init__(self):
        self.child = self.overlap = 0.0

    def install(self) -> None:
        import saxum.precompile

        times, popen = self, subprocess.Popen

        class Child(popen):
            def __init__(self, *args, **kwargs):
                self.cpu_start = time.process_time()
                super().__init__(*args, **kwargs)

            def wait(self, timeout=None):
                before = _children_cpu()
                try:
                    return super().wait(timeout)
                finally:
                    times.child += _children_cpu() - before
                    times.overlap += time.process_time() - self.cpu_start

        saxum.precompile.subprocess = type("subprocess", (), {
            "Popen": Child, "DEVNULL": subprocess.DEVNULL,
            "TimeoutExpired": subprocess.TimeoutExpired})


def _worker(case: str, folder: Path) -> dict:
    t0 = time.perf_counter()
    import saxum.cli

    t_import = time.perf_counter() - t0
    loaded = [m for m in HEAVY if m in sys.modules]

    import saxum.runner

    compiles = _CompileTimes()
    compiles.install()
    child = _ChildTimes()
    try:
        child.install()
    except ImportError:  # a version without saxum.precompile
        pass
    run = _Phase(saxum.runner.run_scenario, compiles)
    saxum.runner.run_scenario = run

    t1 = time.perf_counter()
    # the picture's modules (matplotlib) load in the command; their import counts as plotting
    from matplotlib.figure import Figure

    import saxum.plot

    t_plot_import = time.perf_counter() - t1
    save = _Phase(Figure.savefig, compiles)
    Figure.savefig = lambda fig, *args, **kwargs: save(fig, *args, **kwargs)
    plot = _Phase(saxum.plot.plot_frame, compiles)
    saxum.plot.plot_frame = plot
    if case == "arch":
        import saxum.demos

        saxum.demos.run_scenario = run
        saxum.demos.plot_frame = plot
        code = saxum.cli.main(["demo", "arch", "-o", str(folder / "arch.png")])
    else:
        toml = folder / "arch3d.toml"
        toml.write_text(ARCH3D_TOML)
        code = saxum.cli.main(["run", str(toml), "-o", str(folder / "arch3d.h5"), "--quiet"])
        if code == 0:
            code = saxum.cli.main(["plot", str(folder / "arch3d.h5"), "-o",
                                   str(folder / "arch3d.png")])
    t_command = time.perf_counter() - t1
    plot_total = plot.total + save.total + t_plot_import
    plot_compile = plot.compile + save.compile
    cpu = resource.getrusage(resource.RUSAGE_SELF)
    main_cpu = cpu.ru_utime + cpu.ru_stime
    return {
        "main_cpu": main_cpu,
        "child_cpu": child.child,
        "idle_2core": main_cpu + max(0.0, child.child - child.overlap),
        "exit_code": code,
        "import": t_import,
        "imported": loaded,
        "command": t_command,
        "compile": compiles.outer,
        "compile_cpu": compiles.outer_cpu,
        "run": run.total - run.compile,
        "plot": plot_total - plot_compile,
        "other": t_command - compiles.outer - (run.total - run.compile)
        - (plot_total - plot_compile),
        "kernels": {k: [v, compiles.count.get(k, 0), compiles.loads.get(k, 0)] for k, v in
                    sorted(compiles.self_time.items(), key=lambda kv: -kv[1])},
    }


# --------------------------------------------------------------------------------------------
# the parent: fresh processes, empty then filled cache


def _measure(case: str, cache: Path, mpl: Path | None, folder: Path,
             src: str | None, python: str = sys.executable) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    if python != sys.executable:  # its own installed saxum
        env.pop("PYTHONPATH", None)
    if src is not None:
        env["PYTHONPATH"] = src
    if mpl is not None:
        env["MPLCONFIGDIR"] = str(mpl)
    out = folder / f"{case}.json"
    t0, cpu0 = time.perf_counter(), _children_cpu()
    subprocess.run([python, __file__, "--worker", case, "--folder", str(folder),
                    "--out", str(out)], env=env, check=True, stdout=subprocess.DEVNULL)
    total, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    result = json.loads(out.read_text())
    result["total"], result["total_cpu"] = total, cpu
    return result


def _children_cpu() -> float:
    """CPU time (user + system) of the finished child processes [s]."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


HEADER = (f"{'case':<34} {'total':>6} {'CPU':>6} {'main':>5} {'child':>5} {'idle2':>5} "
          f"{'import':>6} {'compile':>7} {'CPU':>6} {'run':>5} {'plot':>5} {'other':>5} "
          f"{'jits':>4}")


def _row(label: str, r: dict) -> str:
    return (f"{label:<34} {r['total']:6.2f} {r['total_cpu']:6.2f} {r['main_cpu']:5.2f} "
            f"{r['child_cpu']:5.2f} {r['idle_2core']:5.2f} {r['import']:6.2f} "
            f"{r['compile']:7.2f} {r['compile_cpu']:6.2f} {r['run']:5.2f} {r['plot']:5.2f} "
            f"{r['other']:5.2f} {len(r['kernels']):4d}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default="arch,arch3d", help="comma-separated: arch, arch3d")
    parser.add_argument("--top", type=int, default=12,
                        help="kernels listed per case, by compile time (default 12)")
    parser.add_argument("--fresh-matplotlib", action="store_true",
                        help="an empty MPLCONFIGDIR too (matplotlib builds its font cache)")
    parser.add_argument("--json", type=Path, help="write all figures to this file")
    parser.add_argument("--src", action="append",
                        help="a source tree to import saxum from (PYTHONPATH); repeatable")
    parser.add_argument("--python", action="append",
                        help="an interpreter whose installed saxum to run; repeatable")
    parser.add_argument("--repeat", type=int, default=1, help="runs of each case and tree")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("--folder", type=Path, help=argparse.SUPPRESS)
    parser.add_argument("--out", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        args.out.write_text(json.dumps(_worker(args.worker, args.folder)))
        return

    results = {}
    for src in args.src or []:
        subprocess.run([sys.executable, "-m", "compileall", "-q", src], check=True)
    import numba

    print(f"python {sys.version.split()[0]}, numba {numba.__version__}, {sys.platform}; "
          f"seconds (wall-clock; CPU where said)")
    print(HEADER)
    for repeat in range(args.repeat):
        for case in args.cases.split(","):
            variants = [(src, sys.executable) for src in args.src or []] + [
                (None, python) for python in args.python or []]
            for src, python in variants or [(None, sys.executable)]:
                with tempfile.TemporaryDirectory() as tmp:
                    tmp = Path(tmp)
                    cache = tmp / "numba-cache"
                    cache.mkdir()
                    mpl = None
                    if args.fresh_matplotlib:
                        mpl = tmp / "mplconfig"
                        mpl.mkdir()
                    for label in ("empty cache", "filled cache"):
                        folder = tmp / label.replace(" ", "-")
                        folder.mkdir()
                        r = _measure(case, cache, mpl, folder, src, python)
                        key = (f"{case}, {label}" + (f" [{src}]" if src else "")
                               + (f" [{python}]" if python != sys.executable else "")
                               + (f" #{repeat + 1}" if args.repeat > 1 else ""))
                        results[key] = r
                        print(_row(key, r), flush=True)
    for key, r in results.items():
        print(f"\n{key}: imported {', '.join(r['imported'])}; CPU time [s] per dispatcher "
              f"(its own; compiles or loads):")
        for name, (took, count, loads) in list(r["kernels"].items())[:args.top]:
            how = f"{loads} from the cache" if loads else f"{count} compiled"
            print(f"  {took:7.3f} ({how}) {name}")
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
