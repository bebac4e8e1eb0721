"""A picture of a 3D output frame with matplotlib's 3D axes (for `saxum plot`; for anything
more, export to ParaView: saxum export-vtk).

The blocks' faces are filled by the block's displacement from its initial position (fixed and
driven bodies light grey; a support much larger than the structure, such as a ground slab, is
shown as a floor under it), and the contact points carrying load are drawn on top as red dots
whose area is proportional to the normal force. Flood water (saxum.flood) is its surface at
the frame's time, translucent, drawn under the blocks, with the flow's direction and speed.
"""

from os import PathLike

import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from .geometry3d import world_points
from .model import BodyKind
from .plot import _results_floods, length_unit, results_heading

__all__ = ["plot_frame_3d"]


def plot_frame_3d(results, k: int, path: str | PathLike | None = None, *, forces: bool = True,
                  title: str | None = None, figsize: tuple[float, float] | None = None,
                  dpi: int = 150) -> Figure:
    """The 3D structure at output frame index k of saxum.results.Results (see module doc);
    saved to `path` at dpi when given."""
    m = results.model
    q = results.body_q[k]
    points = world_points(q, m["body_vertex_start"], m["vertex_local"])
    vertex_owner = np.repeat(np.arange(len(q)), np.diff(m["body_vertex_start"]))
    free = m["body_kind"] == BodyKind.FREE
    shown = points[free[vertex_owner]] if free.any() else points
    lo, hi = shown.min(axis=0), shown.max(axis=0)
    centre, half = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
    extent = np.array([np.ptp(points[vertex_owner == b], axis=0).max() for b in range(len(q))])
    floor = ~free & (extent > 4.0 * half)  # drawn as a floor, not as a body
    fvs, fv = m["face_vertex_start"], m["face_vertex"]
    owner = np.repeat(np.arange(len(q)), np.diff(m["body_face_start"]))
    keep = np.flatnonzero(~floor[owner])
    faces = [points[fv[fvs[f]:fvs[f + 1]]] for f in keep]
    moved = np.linalg.norm(q[:, :3] - m["body_q0"][:, :3], axis=1)
    largest = float(moved[free].max(initial=0.0))
    factor, unit = length_unit(largest)
    mappable = ScalarMappable(Normalize(0.0, factor * largest or 1.0), "viridis")
    colours = np.where(free[owner[keep], None], mappable.to_rgba(factor * moved[owner[keep]]),
                       (0.85, 0.85, 0.85, 1.0))

    fig = Figure(figsize=figsize or (9.0, 7.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    ax.computed_zorder = False  # the contact dots stay on top of the faces
    if floor.any():
        x0, x1, y0, y1 = (centre[0] - half, centre[0] + half, centre[1] - half,
                          centre[1] + half)
        z = float(lo[2])
        ax.add_collection3d(Poly3DCollection([[(x0, y0, z), (x1, y0, z), (x1, y1, z),
                                               (x0, y1, z)]], facecolors="0.92",
                                             edgecolors="0.6", zorder=0))
    for flood in _results_floods(results):
        _draw_water(ax, flood, float(results.time[k]), shown, centre, half)
    ax.add_collection3d(Poly3DCollection(faces, facecolors=colours, edgecolors="0.25",
                                         linewidths=0.3, zorder=1))
    if forces:
        c = results.contacts(k)
        normal = c["force"][:, 1]
        loaded = normal > 0.0
        if loaded.any():
            size = 40.0 * normal[loaded] / normal[loaded].max()
            ax.scatter(*c["point"][loaded].T, s=size, color="#c0152f", depthshade=False,
                       zorder=2, label="contact forces (area ~ normal force)")
            ax.legend(fontsize=8, loc="upper left")
    for setter, c0 in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
        setter(c0 - half, c0 + half)
    ax.set_box_aspect((1.0, 1.0, 1.0))
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    heading = title if title is not None else results_heading(results)
    ax.set_title(f"{heading}: t = {results.time[k]:.3f} s (step {results.step[k]})",
                 fontsize=10)
    fig.colorbar(mappable, ax=ax, shrink=0.6, label=f"displacement [{unit}]")
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig


def _draw_water(ax, flood, t: float, points: np.ndarray, centre: np.ndarray,
                half: float) -> None:
    """The water surface z = H(s) [m] at time t [s] over the square drawn (centre, half
    width [m]), s along the flow's azimuth from the free blocks' extent `points` [m]; the
    flow's speed and direction in a corner."""
    a = np.radians(flood.azimuth)
    e = np.array([np.cos(a), np.sin(a)])
    s = points[:, :2] @ e
    x, y = np.meshgrid(*(np.linspace(c - half, c + half, 25) for c in centre[:2]))
    z = flood.surface(x * e[0] + y * e[1], t, (float(s.min()), float(s.max())))
    ax.plot_surface(x, y, z, color="#9cc8e8", alpha=0.45, linewidth=0, shade=False,
                    zorder=0.5)
    u = flood.velocity.at(t)
    if u != 0.0:
        heading = flood.azimuth if u > 0 else flood.azimuth + 180.0
        ax.text2D(0.99, 0.98, f"flow {abs(u):.3g} m/s towards {heading % 360:g}° from x",
                  transform=ax.transAxes, ha="right", va="top", fontsize=8, color="#2a6fa8")
