"""Package layout (issue 14 item 5): body kinds as modules with one set of functions, and no
import circle between the 2D and 3D pictures."""

import subprocess
import sys

import pytest

from saxum import bodies

STAGES = ("free_velocity", "driven_velocity", "predict_positions", "update_positions",
          "contact_jacobians", "kinetic_energy")
"""What the time loop (saxum.simulation) calls on a body kind."""


@pytest.mark.parametrize("name", sorted(bodies.KINDS))
def test_every_body_kind_provides_the_loop_stages(name):
    kind = bodies.KINDS[name]
    missing = [stage for stage in STAGES if not callable(getattr(kind, stage, None))]
    assert not missing, f"body kind {name} lacks {missing}"


@pytest.mark.parametrize("dim", [2, 3])
def test_rigid_kind_by_dimension(dim):
    assert bodies.rigid(dim) is bodies.KINDS[f"rigid{dim}d"]


def test_plot3d_does_not_import_plot():
    """plot.py and plot3d.py share plot_common.py instead of importing each other."""
    code = "import sys, saxum.plot3d; print('saxum.plot' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"
