"""benchmarks/shear_wall_sliding.py as a module, shared by test_shear_wall_bounds.py and
test_shear_wall_sliding.py (the guided-beam walls, their laws and their force read-out)."""

import importlib.util
from pathlib import Path

_SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "shear_wall_sliding.py"
_spec = importlib.util.spec_from_file_location("shear_wall_sliding", _SCRIPT)
wall = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(wall)
