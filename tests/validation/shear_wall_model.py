"""benchmarks/shear_wall_sliding.py and benchmarks/shear_wall.py as modules: `wall` (the
guided-beam walls, their laws and their force read-out), shared by test_shear_wall_bounds.py
and test_shear_wall_sliding.py, and `eindhoven` (the TU Eindhoven wall), used by
test_shear_wall_cracks.py."""

import importlib.util
from pathlib import Path


def _load(name: str):
    """The benchmark script benchmarks/<name>.py as a module."""
    path = Path(__file__).resolve().parents[2] / "benchmarks" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


wall = _load("shear_wall_sliding")
eindhoven = _load("shear_wall")
