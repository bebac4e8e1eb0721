"""The bundled demos (`saxum demo NAME`) run end to end and leave a picture and results."""

import os
import signal
import subprocess
import sys

import numpy as np
from PIL import Image

from saxum.cli import main
from saxum.demos import arch_demo, bundled_scenario
from saxum.results import Results
from saxum.simulation import Simulation


def test_arch_demo_stands_and_collapses(tmp_path):
    """t/R = 0.15 stands and t/R = 0.09 collapses (the minimum is 0.1075, Milankovitch)."""
    out = tmp_path / "arch.png"
    moves = arch_demo(out, duration=1.0, echo=lambda *a: None)
    assert moves["arch-stands"] < 1e-4 * 2.0 and moves["arch-collapses"] > 0.1 * 2.0
    assert Image.open(out).format == "PNG"
    for case in ("stands", "collapses"):
        with Results(tmp_path / f"arch-{case}.h5") as r:
            assert r.status == "finished" and np.isclose(r.time[-1], 1.0)


def test_arch_demo_compiles_no_rest_solution_kernels(tmp_path):
    """The first run after an install compiles the kernels the demo uses (BENCHMARKS.md, the
    first run): the standing arch steps by NLGS alone, so the rest solution's kernels, most of
    a first run's compile time, are neither compiled nor loaded (a fresh process)."""
    code = ("import sys; from pathlib import Path; from saxum.demos import arch_demo; "
            "arch_demo(Path(sys.argv[1]), duration=0.2, echo=lambda *a: None); "
            "from saxum.solver import equilibrium as e; "
            "print(sum(len(k.signatures) for k in (e._rest_contacts, e._pattern, "
            "e._newton_system)))")
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path / "arch.png")],
                         capture_output=True, text=True, check=True)
    assert out.stdout.split()[-1] == "0"


def test_wall_demo_from_the_command_line(tmp_path, capsys):
    out = tmp_path / "wall.png"
    assert main(["demo", "wall", "-o", str(out), "--duration", "0.5"]) == 0
    text = capsys.readouterr().out
    assert "it stood up to lambda = 0.050" in text and str(out.resolve()) in text
    assert Image.open(out).format == "PNG"
    with Results(tmp_path / "wall.h5") as r:
        assert r.frame_count == 11


def test_bundled_scenarios_validate():
    for name in ("arch-stands", "arch-collapses", "wall"):
        scenario, text = bundled_scenario(name)
        assert scenario.title and text.startswith("# Bundled demo")


def test_ctrl_c_during_a_demo_run_stops_the_demo_and_keeps_its_results(tmp_path, monkeypatch,
                                                                       capsys):
    """Before: the run that Ctrl-C interrupted returned, and the demo went on to the next
    arch and its picture and exited 0; now it stops there as any Ctrl-C does (exit 130), the
    interrupted run's results kept (resumable)."""
    step = Simulation.step

    def step_then_ctrl_c(self, state):
        report = step(self, state)
        if state.step == 5:
            os.kill(os.getpid(), signal.SIGINT)  # the run's handler stops after this step
        return report

    monkeypatch.setattr(Simulation, "step", step_then_ctrl_c)
    code = main(["demo", "arch", "-o", str(tmp_path / "arch.png"), "--duration", "0.2"])
    assert code == 130 and capsys.readouterr().err.endswith("saxum: interrupted\n")
    with Results(tmp_path / "arch-stands.h5") as r:
        assert r.status == "interrupted"
    assert not (tmp_path / "arch-collapses.h5").exists() and not (tmp_path / "arch.png").exists()
