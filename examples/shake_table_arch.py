"""A stone arch on a shaking table under one-sine pulses: the collapse curve (smallest pulse
amplitude that collapses the arch, per pulse period) and the hinges of the mechanism, against
the arch's static horizontal load factor and its mechanism (after Albuerne, Williams & Lawson,
"Prediction of the failure mechanism of arches under base motion using DEM based on the NSCD
method", 2013; the scenario and what was assumed: examples/shake_table_arch.toml,
docs/applications.md).

    python examples/shake_table_arch.py      (under a minute on 2 cores)
    option: --out DIR (where the picture goes: default the current directory)

Prints the static load factor with its hinges, then per period the critical amplitude [g],
the time of collapse and the hinge positions as angles from the crown [deg] (negative: left
of the crown; +-90: the springings), and draws the curve (shake_table_arch-curve.png).
"""

import math
from pathlib import Path

from saxum.collapse import (
    DYNAMIC_FRACTION,
    CollapseCriterion,
    collapse_curve,
    scenario_critical_value,
)
from saxum.mechanism import mechanism
from saxum.plot import plot_collapse_curve

SCENARIO = Path(__file__).with_name("shake_table_arch.toml")
PERIODS = (0.25, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0)
G = 9.81


def hinge_angles(mech) -> list[float]:
    """Angles of the hinges from the crown [deg], about the arch's centre (0, 0)."""
    return sorted(round(math.degrees(math.atan2(x, y)), 1)
                  for x, y in (j.hinge_point for j in mech.hinges))


def static_factor(tolerance: float = 0.005):
    """The horizontal load factor that collapses the arch statically, and its hinge angles."""
    crit = scenario_critical_value(SCENARIO, "loads.horizontal_acceleration", 0.5, 5.0,
                                   overrides=("loads.ground_motion.amplitude=0.0",),
                                   tolerance=tolerance)
    trial = crit.collapse()
    trial.simulation.run(trial.state, 0.05)  # let the mechanism open so that hinges show
    mech = mechanism(trial.simulation.model, trial.state, trial.simulation.integrator.dt)
    return crit.value / G, hinge_angles(mech)


def main(periods=PERIODS, *, tolerance: float = 0.02, stands: float = 0.5,
         collapses: float = 25.0, duration: float = 2.0, processes: int | None = None,
         static: bool = True, picture: str | Path | None = "shake_table_arch-curve.png"):
    """Returns (static load factor or None, [(period [s], amplitude [g], collapse time [s],
    hinge angles [deg]), ...])."""
    lam = None
    if static:
        lam, angles = static_factor()
        print(f"static horizontal load factor: {lam:.4f}; hinges at {angles} deg")
    rows = collapse_curve(SCENARIO, periods, stands, collapses, tolerance=tolerance,
                          criterion=CollapseCriterion(duration=duration,
                                                      fraction=DYNAMIC_FRACTION),
                          processes=processes)
    out = []
    print("T_p [s]  amplitude [g]  collapse at [s]  hinges [deg from the crown]")
    for p in rows:
        angles = hinge_angles(p.mechanism)
        out.append((p.period, p.amplitude / G, p.collapse_time, angles))
        print(f"{p.period:7.3g}  {p.amplitude / G:13.4f}  {p.collapse_time:15.3f}  {angles}")
    if picture is not None:
        plot_collapse_curve(rows, picture, g=G, static=lam,
                            title="arch on a shaking table: one-sine pulses")
        print(f"picture: {Path(picture).resolve()}")
    return lam, out


def cli(argv: list[str] | None = None):
    """The command line (module doc): the picture goes to the current directory unless --out."""
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path(),
                        help="folder of the picture (default: the current directory)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    return main(picture=args.out / "shake_table_arch-curve.png")


if __name__ == "__main__":
    cli()
