"""Granular fill: discs (2D) or spheres (3D) of random radii placed without overlap in a box,
e.g. the fill of an arch bridge or the rubble core of a wall, and a fixed container for them.

The grains are placed by random sequential addition (each new grain at a uniformly random
centre, kept if it clears every grain placed before by `clearance`), from a seeded generator:
the same seed gives the same grains. Dropped under gravity they settle into a packing.
"""

from collections.abc import Sequence

import numpy as np

from ..errors import InputError
from ..model import BodyKind, ModelBuilder
from ._common import Assembly

__all__ = ["add_granular_box", "add_granular_fill"]


def add_granular_fill(builder: ModelBuilder, low: Sequence[float], high: Sequence[float], *,
                      radius: tuple[float, float], count: int, seed: int = 0,
                      density: float = 2000.0, group: str = "grain",
                      attempts: int = 200) -> Assembly:
    """Add `count` discs (spheres in 3D) of radii uniform in radius = (r_min, r_max) [m]
    inside the box low..high [m] (corners, dim coordinates each), none closer to another than
    1e-3 r_min, named "grain k"; part "grains". Raises InputError when `attempts` x count
    random tries do not place them all (a denser fill than random addition reaches: at most
    about 50 % of a square's area, 30 % of a cube's volume)."""
    dim = builder.dim
    lo = np.asarray(low, dtype=np.float64)
    hi = np.asarray(high, dtype=np.float64)
    r_min, r_max = (float(r) for r in radius)
    if lo.shape != (dim,) or hi.shape != (dim,) or not np.all(np.isfinite(lo) & np.isfinite(hi)):
        raise InputError(f"granular fill: low and high must be {dim} finite coordinates [m]")
    if not 0.0 < r_min <= r_max:
        raise InputError(f"granular fill: radius must be (r_min, r_max) with 0 < r_min <= "
                         f"r_max [m], got {radius}")
    if np.any(hi - lo <= 2.0 * r_max):
        raise InputError(f"granular fill: the box {lo.tolist()} .. {hi.tolist()} must be wider "
                         f"than the largest grain (diameter {2.0 * r_max:g} m) in every direction")
    if count < 1:
        raise InputError(f"granular fill: count must be >= 1, got {count}")
    rng = np.random.default_rng(seed)
    clearance = 1e-3 * r_min
    centres = np.empty((count, dim))
    radii = np.empty(count)
    placed = 0
    for _ in range(attempts * count):
        r = rng.uniform(r_min, r_max)
        c = rng.uniform(lo + r, hi - r)
        apart = np.linalg.norm(centres[:placed] - c, axis=1) - radii[:placed]
        if apart.size == 0 or apart.min() >= r + clearance:
            centres[placed], radii[placed] = c, r
            placed += 1
            if placed == count:
                break
    if placed < count:
        raise InputError(f"granular fill: placed {placed} of {count} grains in {attempts} "
                         "tries each; give fewer or smaller grains, or a larger box")
    asm = Assembly()
    for k in range(count):
        asm.add_round(builder, "grains", centres[k], radii[k], group=group, name=f"grain {k}",
                      density=density)
    return asm


def add_granular_box(builder: ModelBuilder, width: float, height: float, *,
                     radius: tuple[float, float], count: int, seed: int = 0,
                     density: float = 2000.0, wall: float | None = None) -> Assembly:
    """A 2D container (fixed blocks "floor", "left wall", "right wall" of thickness wall [m],
    default width / 10, group "container") of inner width x height [m] with its left inner
    corner at the origin, filled with `count` grains (add_granular_fill over the whole inside;
    group "grain")."""
    if builder.dim != 2:
        raise InputError("add_granular_box builds a 2D container; in 3D place the grains with "
                         "add_granular_fill over blocks of your own")
    t = width / 10.0 if wall is None else wall
    asm = Assembly()
    for name, (x0, y0, x1, y1) in (("floor", (-t, -t, width + t, 0.0)),
                                   ("left wall", (-t, 0.0, 0.0, height)),
                                   ("right wall", (width, 0.0, width + t, height))):
        asm.add_block(builder, "container", [(x0, y0), (x1, y0), (x1, y1), (x0, y1)],
                      group="container", name=name, kind=BodyKind.FIXED)
    asm.merge(add_granular_fill(builder, (0.0, 0.0), (width, height), radius=radius,
                                count=count, seed=seed, density=density))
    return asm
