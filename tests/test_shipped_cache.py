"""numba's cache compiled with the package and shipped inside it (saxum._shipped_cache): found
after the package moved (an install), ignored once the package's source changed."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import pytest

import saxum._shipped_cache as shipped

SRC = Path(shipped.__file__).resolve().parents[1]

# a package of two files, as saxum's kernels are: a kernel that calls a helper from another file
_PACKAGE = {
    "__init__.py": """\
        from pathlib import Path

        import numba  # noqa: F401 - register needs numba

        from saxum._shipped_cache import register

        register(Path(__file__).parent)
        """,
    "kernel.py": """\
        import numba

        from .helper import part


        @numba.njit(cache=True)
        def kernel(x):
            return 2.0 * x + part(x)
        """,
    "helper.py": """\
        import numba


        @numba.njit(cache=True)
        def part(x):
            return 0.5 * x
        """,
}

_CALL = textwrap.dedent("""\
    import json
    from pkg.kernel import kernel
    value = kernel(3.0)
    print(json.dumps({"value": value, "loaded": sum(kernel.stats.cache_hits.values()),
                      "compiled": sum(kernel.stats.cache_misses.values()),
                      "locator": type(kernel._cache._impl.locator).__name__}))
""")


def _package(root: Path) -> Path:
    package = root / "pkg"
    package.mkdir(parents=True)
    for name, text in _PACKAGE.items():
        (package / name).write_text(textwrap.dedent(text))
    return package


def _call(package: Path, tmp_path: Path, **env) -> dict:
    """The kernel called in a fresh process whose NUMBA_CACHE_DIR (numba's own cache) is empty."""
    env = {**os.environ, "NUMBA_CACHE_DIR": tempfile.mkdtemp(dir=tmp_path), **env,
           "PYTHONPATH": os.pathsep.join([str(package.parent), str(SRC)])}
    done = subprocess.run([sys.executable, "-c", _CALL], capture_output=True, text=True,
                          env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_a_shipped_cache_is_loaded_after_a_move_and_ignored_once_the_source_changed(tmp_path):
    built = _package(tmp_path / "build")
    shipped._prepare(built)
    first = _call(built, tmp_path)
    assert (first["locator"], first["compiled"], first["loaded"]) == ("ShippedCacheLocator", 1, 0)

    # installed elsewhere, every file newer (as pip writes them): loaded, nothing compiled
    installed = tmp_path / "site-packages" / "pkg"
    shutil.copytree(built, installed)
    stamp = shipped.source_hash(installed)
    for path in installed.rglob("*.py"):
        os.utime(path, (path.stat().st_atime + 3600.0, path.stat().st_mtime + 3600.0))
    assert shipped.source_hash(installed) == stamp  # the stamp ignores modification times
    moved = _call(installed, tmp_path)
    assert (moved["locator"], moved["compiled"], moved["loaded"]) == ("ShippedCacheLocator", 0, 1)
    # 2 x 3 + 0.5 x 3: exact binary fractions, the same in both processes
    assert moved["value"] == first["value"] == pytest.approx(7.5, rel=1e-15)

    # switched off: numba's own cache, where the kernel compiles
    off = _call(installed, tmp_path, SAXUM_SHIPPED_CACHE="0")
    assert off["locator"] != "ShippedCacheLocator" and off["compiled"] == 1

    # the helper's file edited (not the kernel's, whose numba stamp would not change): the
    # kernel's shipped machine code, which holds the old helper, is not used
    helper = installed / "helper.py"
    helper.write_text(helper.read_text().replace("0.5 * x", "0.25 * x"))
    edited = _call(installed, tmp_path)
    assert edited["locator"] != "ShippedCacheLocator" and edited["compiled"] == 1
    assert edited["value"] == pytest.approx(6.75, rel=1e-15)  # 2 x 3 + 0.25 x 3


def test_saxum_kernels_look_in_the_shipped_cache_when_it_matches_the_source(tmp_path):
    """The locator is registered before saxum's kernels are decorated (numba picks a kernel's
    locator then), though `import saxum` does not load numba."""
    package = tmp_path / "saxum"
    shutil.copytree(SRC / "saxum", package,
                    ignore=shutil.ignore_patterns("__pycache__", shipped.FOLDER))
    shipped._prepare(package)
    probe = ("import sys, saxum; assert 'numba' not in sys.modules; "
             "from saxum.bodies.rigid2d import predict_positions as k; "
             "print(type(k._cache._impl.locator).__name__, k._cache.cache_path)")
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(tmp_path)}, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["ShippedCacheLocator",
                                   str(package / shipped.FOLDER / "bodies")]


def test_a_build_that_cannot_compile_ships_no_cache(tmp_path):
    """A failed compile (here: the package cannot even be imported) is reported, and the
    half-made cache removed: the kernels then compile on their first call."""
    package = tmp_path / "saxum"
    package.mkdir()
    (package / "__init__.py").write_text("raise ImportError('broken')\n")
    why = shipped.build(package)
    assert why is not None and "broken" in why
    assert not (package / shipped.FOLDER).exists()


# A 3D arch's run (benchmarks/first_run.py's, 0.1 s): each saxum kernel it calls from Python,
# with its signatures and whether any was compiled (rather than loaded from a cache)
_RUN_3D = textwrap.dedent("""\
    import json, sys, tempfile
    from pathlib import Path
    from numba.core.dispatcher import Dispatcher
    called = {}
    compile_for_args = Dispatcher._compile_for_args
    def record(self, *args, **kwargs):
        called[f"{self.py_func.__module__[6:]}.{self.py_func.__name__}"] = self
        return compile_for_args(self, *args, **kwargs)
    Dispatcher._compile_for_args = record
    from saxum.cli import main
    folder = Path(tempfile.mkdtemp())
    (folder / "arch.toml").write_text(sys.argv[1])
    assert main(["run", str(folder / "arch.toml"), "--quiet", "-o", str(folder / "a.h5")]) == 0
    print(json.dumps({name: [[str(s) for s in d.signatures],
                             sum(d.stats.cache_misses.values()) > 0]
                      for name, d in called.items()}))
""")


@pytest.mark.skipif(shipped._stamp(SRC / "saxum") is None,
                    reason="no shipped cache for this source (pip install -e . builds one); "
                           "without it the 3D kernels compile, ~40 s of CPU")
def test_the_listed_3d_kernels_are_those_of_a_3d_run_and_shipped(tmp_path):
    """The build compiles the 3D kernels of saxum.precompile's list: each must be called by a
    3D run with its listed argument types (else the build compiles it for nothing), and the
    shipped cache must hold every kernel the run calls (nothing compiles)."""
    from saxum.precompile import kernel_signatures

    sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
    try:
        from first_run import ARCH3D_TOML
    finally:
        sys.path.pop(0)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(
        [sys.executable, "-c", _RUN_3D, ARCH3D_TOML.replace("duration = 1.0", "duration = 0.1")],
        capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    kernels = json.loads(done.stdout.splitlines()[-1])  # after the run's last line
    # nothing compiled: every kernel of the run is listed, or compiled by a listed one (a
    # helper that the run calls from Python too, loaded from the shipped cache then)
    assert [name for name, (_, compiled) in kernels.items() if compiled] == []
    for name, types in kernel_signatures()[3].items():
        assert kernels.get(name, [None])[0] == [str(types)], name
