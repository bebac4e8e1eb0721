"""What the 2D and 3D pictures share (saxum.plot, saxum.plot3d): the rest threshold, units,
scale rounding, and the loads and heading read from a results file's scenario."""

import json

import numpy as np

from .flood import FloodLoad
from .mechanism import BOND_STATES

__all__ = ["BOND_COLOURS", "LOAD_COLOUR", "REST", "length_unit", "nice_ceil", "prefixed_unit",
           "results_floods", "results_heading", "results_point_loads"]

REST = 1e-6
"""[-]: free blocks that all moved by less than this times their median size [m] (or turned
by less than this [rad]) are at rest: what they moved is round-off, not worth a colour scale."""

LOAD_COLOUR = "#1b7837"
"""Colour of point-load arrows (2D and 3D)."""

BOND_COLOURS = dict(zip(BOND_STATES, ("#1a9850", "#e6ab02", "#000000"), strict=True))
"""Colour of a cohesive joint's bond per state (saxum.mechanism.bond_states; 2D and 3D)."""


def length_unit(largest: float) -> tuple[float, str]:
    """(factor from metres, unit) that shows lengths up to `largest` [m] with few digits."""
    if largest >= 1.0:
        return 1.0, "m"
    if largest >= 1e-3:
        return 1e3, "mm"
    return (1e6, "µm") if largest >= 1e-6 else (1e9, "nm")


def prefixed_unit(largest: float, unit: str) -> tuple[float, str]:
    """(factor, prefixed unit) that shows values up to `largest` (in `unit`) with at most three
    digits before the point: M, k, none, m, µ, n (n for anything smaller)."""
    for power, prefix in ((6, "M"), (3, "k"), (0, ""), (-3, "m"), (-6, "µ")):
        if largest >= 10.0**power:
            return 10.0**-power, prefix + unit
    return (1e9, "n" + unit) if largest > 0.0 else (1.0, unit)


def nice_ceil(value: float) -> float:
    """The smallest of 1, 2, 5 times a power of ten that is >= value > 0."""
    power = 10.0 ** np.floor(np.log10(value))
    return next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= value * (1 - 1e-12))


def results_floods(results) -> list[FloodLoad]:
    """The flood of the scenario a results file was run from (none for a run built in
    Python)."""
    if not results.scenario_json:
        return []
    from .scenario import Scenario

    flood = Scenario.model_validate_json(results.scenario_json).loads.flood
    return [] if flood is None else [flood.load()]


def results_point_loads(results) -> list[tuple[int, np.ndarray]]:
    """The point loads of the scenario a results file was run from: (body index, force
    [N/m; 3D: N] in world axes) each."""
    if not results.scenario_json:
        return []
    from .scenario import Scenario

    loads = Scenario.model_validate_json(results.scenario_json).loads.point_loads
    down = -np.eye(results.dim)[-1]
    out = []
    for load in loads:
        direction = np.asarray(load.direction or down, dtype=np.float64)
        out.append((results.body_name.index(load.block),
                    load.magnitude * direction / np.linalg.norm(direction)))
    return out


def results_heading(results) -> str:
    """The scenario's title and the results file's name, or the name alone."""
    title = json.loads(results.scenario_json).get("title") if results.scenario_json else ""
    return f"{title} ({results.path.name})" if title else results.path.stem
