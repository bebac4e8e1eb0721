"""The build step that ships numba's cache of the first run's kernels (saxum/_shipped_cache.py).

Everything else about the package is in pyproject.toml. After setuptools' build_py (which
copies the package into the wheel's tree, or does nothing for an editable install, whose
package is the source folder itself), the kernels listed in saxum.precompile are compiled
into saxum/_numba_cache/ for this machine's CPU (NUMBA_CPU_NAME and NUMBA_CPU_FEATURES as
numba reads them). A failure only warns: the package then ships no cache and its kernels
compile on their first call. SAXUM_SHIPPED_CACHE=0 skips the step.
"""

import os
import subprocess
import sys
import time
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py


class BuildPyWithKernels(build_py):
    """build_py, then the kernels compiled into the built package (module doc)."""

    def run(self) -> None:
        super().run()
        if os.environ.get("SAXUM_SHIPPED_CACHE") == "0":
            return
        if self.editable_mode:
            package = Path(self.get_package_dir("saxum")).resolve()
        else:
            package = Path(self.build_lib, "saxum").resolve()
        start = time.perf_counter()
        try:
            done = subprocess.run(
                [sys.executable, "-c", "import sys; from pathlib import Path; "
                 "from saxum._shipped_cache import build; "
                 "why = build(Path(sys.argv[1])); why and sys.exit(why)", str(package)],
                env={**os.environ, "PYTHONPATH": os.pathsep.join(
                    [str(package.parent), *filter(None, [os.environ.get("PYTHONPATH")])])},
                cwd=package.parent, stdin=subprocess.DEVNULL, capture_output=True, text=True)
            why = (done.stderr.strip()[-4000:] or f"exit {done.returncode}") if (
                done.returncode or done.stderr.strip()) else None
        except Exception as error:  # noqa: BLE001 - the build must go on without the cache
            why = repr(error)
        took = time.perf_counter() - start
        if why is None:
            print(f"saxum: the first run's numba kernels compiled into {package.name}/"
                  f"_numba_cache in {took:.1f} s")
        else:
            print(f"WARNING: saxum: the first run's numba kernels ({took:.1f} s): {why}; those "
                  f"compile on their first call", file=sys.stderr)


setup(cmdclass={"build_py": BuildPyWithKernels})
