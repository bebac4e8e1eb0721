"""Bundled demonstrations, runnable as `saxum demo NAME`: the scenarios in saxum/scenarios, run
to results files next to the picture they end with (so that `saxum animate`, `saxum info` and
`saxum export-vtk` work on them too)."""

from importlib.resources import files
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .plot import plot_frame
from .results import Results
from .runner import RunSummary, run_scenario
from .scenario import Scenario, parse_scenario

__all__ = ["DEMOS", "arch_demo", "bundled_scenario", "wall_demo"]


def bundled_scenario(name: str, duration: float | None = None) -> tuple[Scenario, str]:
    """The bundled scenario `name` (and its TOML text), optionally with another duration [s]."""
    text = (files("saxum") / "scenarios" / f"{name}.toml").read_text()
    overrides = [f"output.duration={duration!r}"] if duration is not None else []
    return parse_scenario(text, overrides=overrides, source=f"bundled {name}.toml"), text


def _run(name: str, results: Path, duration: float | None, echo) -> tuple[Path, RunSummary]:
    scenario, text = bundled_scenario(name, duration)
    # a demo's results are its own: running it again replaces them
    summary = run_scenario(scenario, results, quiet=True, scenario_text=text, overwrite=True)
    echo(f"{scenario.title}: {summary.steps} steps in {summary.wall_time:.1f} s; "
         f"results {results}")
    if summary.status == "interrupted":  # Ctrl-C during the run: the demo stops there too
        raise KeyboardInterrupt
    return results, summary


def _largest_motion(r: Results) -> np.ndarray:
    """Largest displacement of any free block [m] at each output frame."""
    free = r.model["body_kind"] == 0
    return np.linalg.norm(r.body_q[:, free, :2] - r.body_q[:1, free, :2], axis=-1).max(axis=1)


def arch_demo(output: Path, *, duration: float | None = None, echo=print) -> dict[str, float]:
    """Two semicircular stone arches of 15 voussoirs (R = 2 m, 2000 kg/m^3, mu = 0.6) under
    self-weight: t/R = 0.15 stands, t/R = 0.09 is thinner than Milankovitch's minimum
    (t/R = 0.1075) and collapses. Writes both final states side by side to `output` (PNG) and
    returns the crown voussoir's displacement [m] for each."""
    fig = Figure(figsize=(13, 3.9), layout="constrained")
    crown_moves = {}
    for ax, case in zip(fig.subplots(1, 2), ("stands", "collapses"), strict=True):
        name = f"arch-{case}"
        path, summary = _run(name, output.with_name(f"{output.stem}-{case}.h5"), duration,
                             echo)
        with Results(path) as r:
            crown = r.body_name.index("voussoir 8")
            moved = float(np.linalg.norm(r.body_q[-1, crown, :2] - r.body_q[0, crown, :2]))
            verdict = "stands" if moved < 1e-4 * 2.0 else "collapses"
            echo(f"  {verdict}: the crown moved {moved:.3g} m in {summary.time:g} s; solver: "
                 f"sweeps mean {r.steps['iterations'].mean():.1f}, not converged at "
                 f"{summary.non_converged} step(s), largest interpenetration "
                 f"{r.steps['max_interpenetration'].max():.2g} m")
            plot_frame(r, -1, ax=ax,
                       title=f"t/R = {0.15 if case == 'stands' else 0.09}: {verdict}")
        crown_moves[name] = moved
    output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(output, dpi=120)
    echo(f"picture of the final states: {output.resolve()}\n"
         f"animate one: saxum animate {output.with_name(output.stem + '-collapses.h5')}")
    return crown_moves


def wall_demo(output: Path, *, duration: float | None = None, echo=print) -> float | None:
    """A slender brick wall on a tilting table: the horizontal load factor grows until it
    overturns. Writes the wall when it fails to `output` (PNG); returns the load factor at
    which a block first moved by 1 % of the wall's height (None if none did)."""
    path, summary = _run("wall", output.with_suffix(".h5"), duration, echo)
    scenario, _ = bundled_scenario("wall", duration)
    st = scenario.structure
    height = st.courses * st.brick_height
    with Results(path) as r:
        moved = _largest_motion(r)
        failing = np.flatnonzero(moved > 0.01 * height)
        g = float(np.linalg.norm(r.model["gravity"]))
        rate = scenario.loads.load_factor_rate
        if failing.size:
            k = int(failing[0])
            factor = rate * r.time[k]
            echo(f"  it fails at load factor lambda = {factor:.3f} (t = {r.time[k]:g} s: a block "
                 f"moved by 1 % of the height; a rigid block of the same b/h would overturn at "
                 f"{st.bricks * st.brick_length / height:.3f}; g = {g:g} m/s^2)")
            frame = min(k + max(1, round(0.5 / (r.time[1] - r.time[0]))), r.frame_count - 1)
        else:
            factor, frame = None, -1
            echo(f"  it stood up to lambda = {rate * r.time[-1]:.3f}")
        fig = plot_frame(r, frame)
    output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(output, dpi=120)
    echo(f"picture of the failing wall: {output.resolve()}\n"
         f"animate it: saxum animate {path}")
    return factor


DEMOS = {"arch": arch_demo, "wall": wall_demo}
