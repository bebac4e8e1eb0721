"""Bundled demonstrations, runnable as `saxum demo NAME`."""

import time
from pathlib import Path

import numpy as np

from .plot import save_states
from .simulation import Simulation
from .structures import semicircular_arch

__all__ = ["DEMOS", "arch_demo"]


def arch_demo(output: Path, *, duration: float = 2.0, radius: float = 2.0,
              voussoirs: int = 15, echo=print) -> dict[str, float]:
    """Two semicircular stone arches of 15 voussoirs (R = 2 m, 2000 kg/m^3, mu = 0.6) under
    self-weight: t/R = 0.15 stands, t/R = 0.09 is thinner than Milankovitch's minimum
    (t/R = 0.1075) and collapses. Writes a picture of both final states to `output` (PNG) and
    returns the crown voussoir's displacement [m] for each."""
    panels = []
    crown_moves = {}
    for ratio in (0.15, 0.09):
        model = semicircular_arch(radius=radius, thickness=ratio * radius, voussoirs=voussoirs)
        sim = Simulation(model, dt=1e-3)
        state = sim.initial_state()
        start = time.perf_counter()
        sim.run(state, duration)
        elapsed = time.perf_counter() - start
        crown = 1 + voussoirs // 2
        moved = float(np.hypot(*(state.body_q[crown, :2] - model.body_q0[crown, :2])))
        verdict = "stands" if moved < 1e-4 * radius else "collapses"
        crown_moves[f"t/R={ratio}"] = moved
        echo(f"arch t/R = {ratio:.2f}: {verdict}; crown moved {moved:.3g} m in {duration:g} s "
             f"({elapsed:.1f} s wall); solver: {sim.log.summary()}")
        panels.append((model, state.body_q, f"t/R = {ratio:.2f}: {verdict} "
                                            f"(crown moved {moved:.2g} m after {duration:g} s)"))
    output.parent.mkdir(parents=True, exist_ok=True)
    save_states(str(output), panels)
    echo(f"picture of the final states: {output.resolve()}")
    return crown_moves


DEMOS = {"arch": arch_demo}
