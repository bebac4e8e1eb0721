"""numba's cache of saxum's kernels, compiled when the package is built and shipped inside it.

A first run compiles its kernels (~6 s of CPU for a 2D run, ~40 s for a 3D one, BENCHMARKS.md):
the package's build (setup.py, `pip install .` and `pip install -e .`) compiles those that
saxum.precompile lists into `saxum/_numba_cache/`, and this module makes numba load them from
there. numba's own cache locators cannot: they put a file's cache in a folder named by a hash
of the file's absolute path (NUMBA_CACHE_DIR, the user's cache) or next to it (`__pycache__`),
and an install moves the files. The locator here names the folder by the file's path inside
the package, and stamps each cache index with a hash of the whole package's source (every
`.py` file's path and bytes, not their modification times, which an install changes): a
kernel's machine code holds that of the helpers it calls, from other files too, which a stamp
of its own file would not see change.

The shipped cache is used only where it can be trusted; otherwise numba caches as without it
(NUMBA_CACHE_DIR, `__pycache__`, the user's cache), and the kernels compile on their first call:
- the package's source, or numpy's version, differs from those it was compiled with (an edited
  editable install, another numpy): the stamp in `_numba_cache/source.sha256` does not match;
- the folder is not writable (a system-wide install: numba saves each new compile, of
  argument types the build did not list, where it found the cache);
- SAXUM_SHIPPED_CACHE=0 in the environment.
numba itself checks each entry's numba version, Python version and CPU (name and features: the
build compiles for its own CPU) and compiles what does not match, adding it to the folder.
"""

import functools
import importlib.util
import os
import sys
from pathlib import Path

__all__ = ["FOLDER", "build", "install", "register", "source_hash"]

FOLDER = "_numba_cache"
"""The shipped cache's folder, inside the package."""

_STAMP = "source.sha256"
"""The file in FOLDER that holds the stamp of the package it was compiled from (_stamp_of)."""

_SWITCH = "SAXUM_SHIPPED_CACHE"
"""Environment variable: "0" leaves the shipped cache unused (compile as without it)."""

_BUILD_TIMEOUT = 1200.0
"""[s] after which a build's compile is given up (the package then ships no cache)."""

_PACKAGE = Path(__file__).resolve().parent


def source_hash(package: Path) -> str:
    """SHA-256 of the package's Python source: each `.py` file's path inside it and bytes, in
    path order (FOLDER left out)."""
    import hashlib  # here: 3 ms that `import saxum` would spend

    digest = hashlib.sha256()
    files = sorted((path.relative_to(package).as_posix(), path)
                   for path in package.rglob("*.py") if FOLDER not in path.parts)
    for name, path in files:
        digest.update(name.encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


def _stamp_of(package: Path) -> str:
    """The package's source hash and numpy's version: numba's cache index checks numba's and
    Python's, not numpy's, on which numba's typing depends (NumPy 2's promotion rules), and a
    build's isolated environment may hold another numpy than the one the package runs with."""
    import numpy

    return f"{source_hash(package)} numpy-{numpy.__version__}"


@functools.cache
def _stamp(package: Path) -> str | None:
    """_stamp_of(package) if its shipped cache was compiled from this source with this numpy,
    else None. Once per process: a source changed while it runs is the one already
    imported."""
    try:
        shipped = (package / FOLDER / _STAMP).read_text().strip()
        current = _stamp_of(package)
    except OSError:  # no shipped cache, or a file that cannot be read: numba's own locators
        return None
    return current if current == shipped else None


def register(package: Path) -> None:
    """Make numba look for the cache of the kernels defined in `package`'s files in its
    FOLDER first (numba must be imported; once per package)."""
    from numba.core import caching

    # the class of cache implementations: CacheImpl in numba 0.68, _CacheImpl in older ones
    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
    package = package.resolve()
    if any(getattr(cls, "package", None) == package for cls in impl._locator_classes):
        return

    class ShippedCacheLocator(caching._CacheLocator):
        """The cache of a function defined in `package`, in its FOLDER; None (numba's other
        locators) where that cache is stale, unwritable or switched off."""

        def __init__(self, py_func, py_file: str, folder: Path):
            self._py_file = py_file  # numba names it in a warning that a kernel is not cachable
            self._lineno = py_func.__code__.co_firstlineno
            self._folder = str(folder)

        def get_cache_path(self) -> str:
            return self._folder

        def get_source_stamp(self) -> str:
            return _stamp(package)

        def get_disambiguator(self) -> str:
            return str(self._lineno)  # numba's: functions of one name in one file

        @classmethod
        def from_function(cls, py_func, py_file: str):
            if os.environ.get(_SWITCH) == "0":
                return None
            try:
                inside = Path(py_file).resolve().relative_to(package)
            except ValueError:  # another package's function
                return None
            if _stamp(package) is None:
                return None
            locator = cls(py_func, py_file, package.joinpath(FOLDER, *inside.parent.parts))
            try:
                locator.ensure_cache_path()  # numba's check: the folder can be written
            except OSError:
                return None
            return locator

    ShippedCacheLocator.package = package
    impl._locator_classes.insert(0, ShippedCacheLocator)


class _AfterNumba:
    """Registers saxum's locator right after numba's own import: `import saxum` does not load
    numba, and the locator must be in place before the first kernel is decorated (numba picks
    a function's locator then). A finder of sys.meta_path that finds nothing itself."""

    def find_spec(self, name, path, target=None):
        if name != "numba":
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec(name)
        if spec is None or not hasattr(spec.loader, "exec_module"):
            return spec
        exec_module = spec.loader.exec_module

        def then_register(module) -> None:
            exec_module(module)
            _register_quietly()

        spec.loader.exec_module = then_register
        return spec


def _register_quietly() -> None:
    try:
        register(_PACKAGE)
    except Exception:  # another numba's internals: kernels then compile as without a cache
        pass


def install() -> None:
    """Register saxum's locator with numba: now if numba is loaded, else once it is."""
    if os.environ.get(_SWITCH) == "0":
        return
    if "numba" in sys.modules:
        _register_quietly()
    elif not any(isinstance(finder, _AfterNumba) for finder in sys.meta_path):
        sys.meta_path.insert(0, _AfterNumba())


_FIRST_SHARE = {3: 2}
"""How many of a dimension's kernels, from the first, the build's first process compiles (2D:
those of precompile's second process; 3D: polyhedron_contacts and nlgs_3d, with the 2D
ones ~half the CPU time of all, BENCHMARKS.md)."""


def _shares() -> list[list[tuple[int, str]]]:
    """The kernels of saxum.precompile in two shares of similar compile time, one per
    process (_FIRST_SHARE): [(dim, name)] each."""
    from saxum.precompile import _CHILD_SHARE, kernel_signatures

    first = {**_CHILD_SHARE, **_FIRST_SHARE}
    shares = [[], []]
    for dim, signatures in kernel_signatures().items():
        for k, name in enumerate(signatures):
            shares[k >= first[dim]].append((dim, name))
    return shares


def _compile_share(share: int) -> None:
    """One build process: its share of the kernels, into FOLDER (the locator is registered).
    A kernel that does not compile (its listed types out of date, or an error: a package
    missing from the build's environment, say) is left out, named on stderr, and compiles on
    its first call; the others are shipped."""
    from saxum.precompile import _compile, kernel_signatures

    signatures = kernel_signatures()
    for dim, name in _shares()[share]:
        try:
            _compile([name], signatures[dim])
        except Exception as error:  # noqa: BLE001 - any error: this kernel is not shipped
            print(f"{_LEFT_OUT}{name} ({dim}D): {error!r}"[:500], file=sys.stderr)


_LEFT_OUT = "not compiled ahead: "
"""How a build process names a kernel it could not compile (_compile_share)."""


def _prepare(package: Path) -> Path:
    """An empty FOLDER in `package`, stamped with its source hash: numba saves the kernels
    that `package`'s files define there from now on."""
    import shutil

    folder = package / FOLDER
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir()
    (folder / _STAMP).write_text(_stamp_of(package) + "\n")
    return folder


def build(package: Path, timeout: float = _BUILD_TIMEOUT) -> str | None:
    """Compile saxum.precompile's kernels into `package`'s FOLDER, two processes at once; the
    package's source must be importable from `package`'s parent. None if all were compiled,
    else what was not: the kernels left out (their names), or, where a process failed, all
    (the folder is then removed). Those compile on their first call."""
    import shutil
    import subprocess
    import tempfile
    import time

    folder = _prepare(package)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(package.parent), *filter(None, [os.environ.get("PYTHONPATH")])])}
    env.pop(_SWITCH, None)
    deadline = time.monotonic() + timeout
    failed = None
    with tempfile.TemporaryFile("w+") as log:  # a file, not a pipe: no worker waits on it
        workers = [subprocess.Popen(
            [sys.executable, "-c", "from saxum._shipped_cache import _compile_share; "
             f"_compile_share({share})"], env=env, cwd=package.parent,
            stdin=subprocess.DEVNULL, stdout=log, stderr=log) for share in range(2)]
        try:
            for worker in workers:
                if worker.wait(timeout=max(0.0, deadline - time.monotonic())) != 0:
                    failed = f"exit {worker.returncode}"
        except subprocess.TimeoutExpired:
            failed = f"not done in {timeout:.0f} s"
        finally:
            for worker in workers:
                if worker.poll() is None:
                    worker.kill()
                    worker.wait()
        log.seek(0)
        output = log.read()
    if failed is not None:
        shutil.rmtree(folder, ignore_errors=True)
        return f"no kernel shipped: {failed}: {output.strip()[-2000:]}"
    left_out = [line for line in output.splitlines() if line.startswith(_LEFT_OUT)]
    return "; ".join(left_out) or None
