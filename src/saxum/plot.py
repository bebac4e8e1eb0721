"""Pictures and animations of results with matplotlib.

Figures are made with matplotlib.figure.Figure, never pyplot, so nothing here changes the
backend or leaves figures open in the caller's session. A frame shows the blocks filled by
their displacement (or rotation) from the initial position, fixed and driven bodies hatched
grey, and the contact forces: at each contact point a segment along the reaction whose width
is proportional to the normal force |R_n|/dt [N/m], hinges (a joint loaded at one point only)
as white circles and open contact points as crosses; a scenario's point loads as arrows onto
their blocks' centres of mass. A structure at rest (every free block moved by less than
REST times the blocks' size: round-off) has no colour scale, only its largest displacement
written in a corner. Flood water (saxum.flood), from a results file's scenario or a model's
field loads, is drawn behind the blocks from the ground's top (the highest fixed body at each
x) up to its level at the frame's time, with the flow velocity. Joints of a cohesive law
(mortar) show their bond: each contact point as a stroke along the joint as long as the share
of it the point stands for (its area), coloured intact, damaged or cracked
(saxum.mechanism.bond_states).
"""

import dataclasses
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import NamedTuple

import numpy as np
from matplotlib import animation
from matplotlib.cm import ScalarMappable
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.transforms import offset_copy

from .errors import InputError
from .flood import FloodLoad
from .geometry3d import rotation_vectors
from .mechanism import (
    BOND_STATES,
    Mechanism,
    bond_states,
    course_of,
    frame_contacts,
    joint_index,
    joint_states,
    thrust_line,
)
from .model import BodyKind, Model, drawn_outlines
from .plot3d import frames_3d, plot_frame_3d
from .plot_common import (
    BOND_COLOURS,
    LOAD_COLOUR,
    REST,
    length_unit,
    nice_ceil,
    prefixed_unit,
    results_floods,
    results_heading,
    results_point_loads,
)

__all__ = ["REST", "animate", "joint_states", "plot_collapse_curve", "plot_frame", "plot_limit",
           "plot_histories", "plot_model", "save_states"]

_WIDEST = 6.0  # line width [pt] of a segment carrying the full-scale force
_FORCE_COLOUR = "#c0152f"
_MARKS = {  # joint_states label: marker style (white circle: the usual symbol of a hinge)
    "hinge": dict(marker="o", markersize=6.5, markerfacecolor="white", markeredgecolor="k",
                  markeredgewidth=1.1),
    "open": dict(marker="x", markersize=5, markeredgecolor="#e07b00", markeredgewidth=1.2),
}
_SLIDE = dict(marker="D", markersize=5.5, markerfacecolor="#7b2cbf", markeredgecolor="k",
              markeredgewidth=0.6)
_COLOUR_BY = ("displacement", "rotation", None)


# -- geometry -------------------------------------------------------------------------------


class _Blocks(NamedTuple):
    """The model's polygons as plain arrays, from a Model or from a results file's /model."""

    vertex_start: np.ndarray
    vertex_local: np.ndarray
    kind: np.ndarray
    q0: np.ndarray

    def world(self, q: np.ndarray) -> np.ndarray:
        """World vertices [m] at coordinates q [..., bodies, 3], shape [..., vertices, 2]."""
        owner = np.repeat(np.arange(len(self.kind)), np.diff(self.vertex_start))
        x, y, th = np.moveaxis(q[..., owner, :], -1, 0)
        c, s = np.cos(th), np.sin(th)
        lx, ly = self.vertex_local.T
        return np.stack((x + c * lx - s * ly, y + s * lx + c * ly), axis=-1)

    def polygons(self, q: np.ndarray) -> list[np.ndarray]:
        return np.split(self.world(q), self.vertex_start[1:-1])

    def size(self) -> float:
        """Median sqrt(area) of the free blocks (of all bodies if none is free) [m]."""
        x, y = self.vertex_local.T
        nxt = np.arange(len(x)) + 1
        nxt[self.vertex_start[1:] - 1] = self.vertex_start[:-1]  # each polygon closes on itself
        area = 0.5 * np.add.reduceat(x * y[nxt] - x[nxt] * y, self.vertex_start[:-1])
        free = self.kind == BodyKind.FREE
        return float(np.median(np.sqrt(np.abs(area[free] if free.any() else area))))


def _results_blocks(results) -> _Blocks:
    m = results.model
    return _Blocks(*drawn_outlines(m["body_vertex_start"], m["vertex_local"],
                                   m.get("body_round_radius"), shape=m.get("body_shape"),
                                   contactor_start=m.get("contactor_vertex_start")),
                   m["body_kind"], m["body_q0"])


def _model_blocks(model: Model) -> _Blocks:
    return _Blocks(*drawn_outlines(model.body_vertex_start, model.vertex_local,
                                   model.body_round_radius, shape=model.body_shape,
                                   contactor_start=model.contactor_vertex_start),
                   model.body_kind, model.body_q0)


# -- units ----------------------------------------------------------------------------------


def _force_unit(largest: float) -> tuple[float, str]:
    """(factor from N/m, unit) for line forces up to `largest` [N/m]."""
    if largest >= 1e6:
        return 1e-6, "MN/m"
    return (1e-3, "kN/m") if largest >= 1e3 else (1.0, "N/m")


# -- drawing --------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Look:
    """What stays the same on every frame of one picture or animation."""

    xlim: tuple[float, float]
    ylim: tuple[float, float]
    colour_by: str | None
    factor: float  # from metres or degrees to the colour bar's unit
    mappable: ScalarMappable | None  # colour scale of the free blocks; None: plain fill
    colour_label: str  # the colour bar's label; without a colour scale, a note (at rest)
    force_full: float  # |R_n|/dt drawn at _WIDEST [N/m]; 0 when nothing is loaded
    force_clipped: bool  # some drawn force exceeds force_full (drawn at _WIDEST)
    strut: float  # length of a force segment [m]
    gap_tolerance: float  # [m]


def _colour_values(blocks: _Blocks, q: np.ndarray, colour_by: str) -> np.ndarray:
    """Displacement [m] or rotation [deg] of each body from its initial position."""
    if colour_by == "displacement":
        return np.linalg.norm(q[..., :2] - blocks.q0[:, :2], axis=-1)
    return np.degrees(q[..., 2] - blocks.q0[:, 2])


def _look(blocks: _Blocks, qs: np.ndarray, colour_by: str | None,
          forces: Sequence[np.ndarray] = (), floods: Sequence[FloodLoad] = ()) -> _Look:
    """Axes limits covering the initial and all given positions qs [frames, bodies, 3] and
    the highest water level of `floods`, colour scale over them and force scale over the
    normal forces [N/m] of their frames."""
    if colour_by not in _COLOUR_BY:
        raise InputError(f"colour_by must be one of {_COLOUR_BY}, got {colour_by!r}")
    pts = np.concatenate([blocks.world(blocks.q0), *blocks.world(qs)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    for flood in floods:
        hi[1] = max(hi[1], float(flood.level.value.max()), flood.heads(0.0)[1])
    pad = 0.05 * float((hi - lo).max())
    factor, mappable, label = 1.0, None, ""
    size = blocks.size()
    if colour_by is not None:
        values = np.abs(_colour_values(blocks, qs, colour_by)[:, blocks.kind == BodyKind.FREE])
        top = float(values.max(initial=0.0))
        if colour_by == "displacement":
            factor, unit = length_unit(top)
            if top < REST * size:
                label = f"at rest: largest displacement {top:.2g} m"
            else:
                mappable = ScalarMappable(Normalize(0.0, top * factor), "YlGnBu")
                label = f"displacement [{unit}]"
        elif top < np.degrees(REST):
            label = f"at rest: largest rotation {top:.2g} deg"
        else:
            mappable = ScalarMappable(Normalize(-top, top), "RdBu_r")
            label = "rotation [deg], anticlockwise +"
    # An impact lasts a step or two: scaling an animation by its largest force would draw
    # every other frame with hairlines, so the scale follows the typical frame's largest force.
    peaks = np.array([f.max(initial=0.0) for f in forces])
    reference = float(np.percentile(peaks, 90)) if peaks.size else 0.0
    full = nice_ceil(reference) if reference > 0 else 0.0
    return _Look((lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad), colour_by, factor,
                 mappable, label, full, peaks.size > 0 and float(peaks.max()) > full,
                 0.6 * size, 1e-3 * size)


def _draw_blocks(ax, look: _Look, blocks: _Blocks, q: np.ndarray) -> None:
    now = blocks.polygons(q)
    free = blocks.kind == BodyKind.FREE
    # The initial outline goes under the blocks: it shows only where a block has moved.
    ax.add_collection(PolyCollection([p for p, f in zip(blocks.polygons(blocks.q0), free,
                                                        strict=True) if f],
                                     facecolors="none", edgecolors="0.55", linestyles="--",
                                     linewidths=0.6, zorder=1))
    ax.add_collection(PolyCollection([p for p, f in zip(now, free, strict=True) if not f],
                                     facecolors="0.82", edgecolors="0.3", hatch="///",
                                     linewidths=0.6, zorder=2))
    moving = PolyCollection([p for p, f in zip(now, free, strict=True) if f],
                            edgecolors="k", linewidths=0.6, zorder=2)
    if look.mappable is None:
        moving.set_facecolor("#e3d5b8")  # sandstone
    else:
        moving.set_facecolor(look.mappable.to_rgba(
            look.factor * _colour_values(blocks, q, look.colour_by)[free]))
    ax.add_collection(moving)


def _model_floods(model: Model) -> list[FloodLoad]:
    return [load for load in model.field_loads if isinstance(load, FloodLoad)]


def _bed(blocks: _Blocks, q: np.ndarray, x: np.ndarray, floor: float) -> np.ndarray:
    """The top of the fixed and driven bodies at each x [m] (the river bed, a pier's
    footing): the highest point of their outlines' edges over x; beyond them, the nearest
    such top (the ground goes on past the edge of the picture); `floor` [m] without any."""
    owner = np.repeat(np.arange(len(blocks.kind)), np.diff(blocks.vertex_start))
    nxt = np.arange(len(owner)) + 1
    nxt[blocks.vertex_start[1:] - 1] = blocks.vertex_start[:-1]
    support = np.flatnonzero(blocks.kind[owner] != BodyKind.FREE)
    p = blocks.world(q)
    (x0, y0), (x1, y1) = p[support].T, p[nxt[support]].T
    lo, hi = np.minimum(x0, x1), np.maximum(x0, x1)
    over = (lo[:, None] <= x) & (x <= hi[:, None])
    sloped = (hi > lo)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(sloped, (x - x0[:, None]) / (x1 - x0)[:, None], 0.0)
    y = np.where(sloped, y0[:, None] + s * (y1 - y0)[:, None], np.maximum(y0, y1)[:, None])
    top = np.where(over, y, -np.inf).max(axis=0, initial=-np.inf)
    covered = np.isfinite(top)
    return np.interp(x, x[covered], top[covered]) if covered.any() else np.full_like(x, floor)


def _draw_water(ax, look: _Look, blocks: _Blocks, q: np.ndarray, floods: Sequence[FloodLoad],
                t: float) -> None:
    """Water between the ground's top (_bed) and its surface H(x) at time t [s] across the
    axes (gravity along -y), and the flow velocity in a corner."""
    free = blocks.kind == BodyKind.FREE
    owner = np.repeat(np.arange(len(blocks.kind)), np.diff(blocks.vertex_start))
    xs = blocks.world(q)[free[owner], 0]
    x = np.linspace(*look.xlim, 400)
    bed = _bed(blocks, q, x, look.ylim[0]) if floods else x
    for flood in floods:
        extent = (float(xs.min()), float(xs.max())) if xs.size else (0.0, 1.0)
        surface = flood.surface(x, t, extent)
        wet = surface > bed
        ax.fill_between(x, bed, surface, where=wet, color="#9cc8e8", alpha=0.5, lw=0,
                        zorder=0)
        ax.plot(x, np.where(wet, surface, np.nan), color="#2a6fa8", lw=1.0, zorder=0.5)
        u = flood.velocity.at(t)
        if u != 0.0:
            ax.text(0.01, 0.98, f"flow {'→' if u > 0 else '←'} {abs(u):.3g} m/s",
                    transform=ax.transAxes, va="top", fontsize=8, color="#2a6fa8")


def _draw_contacts(ax, look: _Look, contacts: dict,
                   slides: np.ndarray | None = None) -> list:
    """Force segments, hinges and open points (and sliding joints at `slides` [m], when
    given); returns their legend handles, the force scale first."""
    rn = contacts["force"][:, 1]
    on = rn > 0
    handles = []
    if look.force_full > 0:
        # The segment follows the reaction R_t t + R_n n, centred on the contact point.
        reaction = np.einsum("ci,cij->cj", contacts["force"][on], contacts["frame"][on])
        half = 0.5 * look.strut * reaction / np.linalg.norm(reaction, axis=1)[:, None]
        p = contacts["point"][on]
        ax.add_collection(LineCollection(
            np.stack((p - half, p + half), axis=1),
            linewidths=_WIDEST * np.minimum(rn[on] / look.force_full, 1.0),
            colors=_FORCE_COLOUR, capstyle="butt", zorder=3))
        factor, unit = _force_unit(look.force_full)
        for fraction in (1.0, 0.5):
            label = f"{look.force_full * fraction * factor:g} {unit}"
            if fraction == 1.0 and look.force_clipped:
                label = "≥ " + label
            handles.append(Line2D([], [], color=_FORCE_COLOUR, lw=_WIDEST * fraction,
                                  solid_capstyle="butt", label=label))
    state = joint_states(contacts, look.gap_tolerance)
    for label, style in _MARKS.items():
        pts = contacts["point"][state == label]
        handles += ax.plot(pts[:, 0], pts[:, 1], ls="none", zorder=4,
                           label=f"{label} ({len(pts)})", **style)
    if slides is not None:
        handles += ax.plot(slides[:, 0], slides[:, 1], ls="none", zorder=5,
                           label=f"sliding ({len(slides)})", **_SLIDE)
    return handles


def _draw_bonds(ax, contacts: dict, law_kind: np.ndarray) -> list:
    """The bonds of cohesive joints (module doc), if the contacts have a damage field (files
    from before the joint laws do not); returns their legend handles."""
    if any(name not in contacts for name in ("damage", "history", "area")):
        return []
    state = bond_states(contacts["law"], contacts["damage"], contacts["history"], law_kind)
    # strokes along the joint, clipped to its end points (those of a joint's ends stand for
    # the joint beside them only)
    t = contacts["frame"][:, 0]
    s = np.einsum("kd,kd->k", contacts["point"], t)
    joint = joint_index(contacts["candidate"], contacts["antagonist"])
    lo = np.full(joint.max(initial=-1) + 1, np.inf)
    hi = -lo
    np.minimum.at(lo, joint, s)
    np.maximum.at(hi, joint, s)
    lo, hi = lo[joint], hi[joint]
    half = 0.5 * contacts["area"]
    single = lo == hi  # a corner against a face: the stroke as it is
    a = np.where(single, s - half, np.clip(s - half, lo, hi)) - s
    b = np.where(single, s + half, np.clip(s + half, lo, hi)) - s
    handles = []
    for label in BOND_STATES:
        rows = state == label
        if not rows.any():
            continue
        p = contacts["point"][rows]
        ends = np.stack((p + a[rows, None] * t[rows], p + b[rows, None] * t[rows]), axis=1)
        ax.add_collection(LineCollection(ends, linewidths=3, colors=BOND_COLOURS[label],
                                         capstyle="butt", zorder=3.5))
        handles.append(Line2D([], [], color=BOND_COLOURS[label], lw=3, solid_capstyle="butt",
                              label=f"{label} bond ({rows.sum()})"))
    return handles


def _legend(ax, handles: list, forces: bool) -> None:
    """One legend of everything drawn, below the x axis label whatever the axes' height
    (anchored a fixed distance in points), titled by the force scale when forces are drawn."""
    if not handles:
        return
    below = offset_copy(ax.transAxes, ax.figure, y=-34, units="points")
    ax.legend(handles=handles, title="normal force |R_n|/dt" if forces else None,
              loc="upper center", bbox_to_anchor=(0.5, 0.0), bbox_transform=below,
              ncol=min(len(handles), 6), fontsize=8, title_fontsize=8, frameon=False,
              handlelength=2.5)


def _draw_point_loads(ax, look: _Look, loads: list[tuple[int, np.ndarray]],
                      q: np.ndarray) -> list:
    """Arrows onto the loaded blocks' centres of mass, 2.5 force struts long; returns the
    legend handle (none without loads)."""
    if not loads:
        return []
    for b, force in loads:
        tip = q[b, :2]
        tail = tip - 2.5 * look.strut * force / np.linalg.norm(force)
        ax.annotate("", xy=tip, xytext=tail, zorder=7, annotation_clip=False,
                    arrowprops=dict(arrowstyle="-|>", color=LOAD_COLOUR, lw=1.8,
                                    mutation_scale=14, shrinkA=0.0, shrinkB=0.0))
    largest = max(float(np.linalg.norm(f)) for _, f in loads)
    factor, unit = _force_unit(largest)
    sizes = ", ".join(f"{np.linalg.norm(f) * factor:.3g}" for _, f in loads)
    return [Line2D([], [], color=LOAD_COLOUR, lw=1.8, marker=">", markevery=[-1],
                   label=f"point load{'s' if len(loads) > 1 else ''} {sizes} {unit}")]


def _finish_axes(ax, look: _Look, title: str) -> None:
    ax.set_xlim(*look.xlim)
    ax.set_ylim(*look.ylim)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title, fontsize=10, wrap=True)
    if look.mappable is None and look.colour_label:  # at rest: no colour scale, a note
        ax.text(0.99, 0.98, look.colour_label, transform=ax.transAxes, ha="right", va="top",
                fontsize=8, color="0.25", zorder=8)


def _draw_elements(ax, results, k: int) -> None:
    """The deformable blocks' triangles at frame k over their polygons, filled by the largest
    compression (the smallest principal stress, when negative) [MPa], with its colour bar."""
    cells = results.model["fe_cell_node"]
    compression = results.stresses(k)["compression"] * 1e-6
    mappable = ScalarMappable(Normalize(0.0, max(float(compression.max()), 1e-12)), "magma_r")
    triangles = PolyCollection(results.node_x[k][cells], facecolors=mappable.to_rgba(
        compression), edgecolors="0.5", linewidths=0.2, zorder=2.5)
    ax.add_collection(triangles)
    ax.figure.colorbar(mappable, ax=ax, shrink=0.8, label="largest compression [MPa]")


def _colourbar(ax, look: _Look) -> None:
    if look.mappable is not None:
        ax.figure.colorbar(look.mappable, ax=ax, shrink=0.8, label=look.colour_label)


def _draw_frame(ax, results, k: int, look: _Look, blocks: _Blocks, forces: bool,
                title: str | None, floods: Sequence[FloodLoad] = (), *,
                slides: np.ndarray | None = None) -> list:
    """Draws output frame k; returns the legend handles of what it drew."""
    _draw_water(ax, look, blocks, results.body_q[k], floods, float(results.time[k]))
    _draw_blocks(ax, look, blocks, results.body_q[k])
    contacts = frame_contacts(results, k)
    handles = _draw_contacts(ax, look, contacts, slides) if forces else []
    handles += _draw_bonds(ax, contacts, results.model["law_kind"])
    handles += _draw_point_loads(ax, look, results_point_loads(results), results.body_q[k])
    heading = title if title is not None else results_heading(results)
    _finish_axes(ax, look, f"{heading}: t = {results.time[k]:.3f} s (step {results.step[k]})")
    return handles


def _draw_thrust_line(ax, results, k: int, look: _Look, blocks: _Blocks) -> list:
    """The thrust line of frame k (mechanism.thrust_line); returns its legend handle."""
    free = np.isin(blocks.kind, (BodyKind.FREE, BodyKind.DEFORMABLE))
    pts = blocks.world(blocks.q0[None])[0]
    owner = np.repeat(np.arange(len(blocks.kind)), np.diff(blocks.vertex_start))
    on_free = free[owner]
    centre = (float(pts[on_free, 0].mean()), float(pts[on_free, 1].min()))
    line = thrust_line(results.contacts(k), look.gap_tolerance, centre)
    return ax.plot(line[:, 0], line[:, 1], "-o", color="k", lw=1.2, ms=2.5, zorder=6,
                   label="thrust line")


def _draw_courses(ax, names: Sequence[str], blocks: _Blocks) -> None:
    """Course numbers of a wall's coursed blocks (mechanism.course_of) in the left margin,
    at the middle of each course's initial height, so that the report's courses can be
    found on the picture."""
    course = np.array([course_of(n) or 0 for n in names])
    if not course.any():
        return
    owner = np.repeat(np.arange(len(names)), np.diff(blocks.vertex_start))
    pts = blocks.world(blocks.q0[None])[0]
    left = float(pts[course[owner] > 0, 0].min())
    for c in np.unique(course[course > 0]):
        y = pts[course[owner] == c, 1]
        ax.annotate(f"c{c}", (left, 0.5 * (y.min() + y.max())), xytext=(-4, 0),
                    textcoords="offset points", ha="right", va="center", fontsize=6,
                    color="0.35", zorder=6)


def _figsize(look: _Look) -> tuple[float, float]:
    """A figure 9 in wide whose axes fit the structure's aspect ratio, with room for the
    title, axis labels and legend [in]."""
    aspect = (look.ylim[1] - look.ylim[0]) / (look.xlim[1] - look.xlim[0])
    return 9.0, float(np.clip(7.0 * aspect + 1.6, 3.5, 10.0))


def _frame_index(results, frame: int) -> int:
    try:
        return range(results.frame_count)[frame]
    except IndexError:
        raise InputError(f"frame {frame} is out of range: {results.path} has "
                         f"{results.frame_count} output frame(s)") from None


def _normal_forces(results, frames: Iterable[int]) -> list[np.ndarray]:
    return [results.contacts(k)["force"][:, 1] for k in frames]


# -- public ---------------------------------------------------------------------------------


def plot_frame(results, frame: int = -1, path: str | PathLike | None = None, *, ax=None,
               forces: bool = True, colour_by: str | None = "displacement",
               title: str | None = None, figsize: tuple[float, float] | None = None,
               dpi: int = 150, thrust_line: bool = False,
               mechanism: Mechanism | None = None) -> Figure:
    """The structure at output frame `frame` of saxum.results.Results: blocks coloured by
    displacement [mm or m] or rotation [deg] (colour_by "displacement", "rotation" or None),
    with the contact forces when `forces`, and for an arch the thrust line (the joints'
    centres of pressure, ordered about the arch's centre: mid-span on the springing line)
    when `thrust_line`; with a `mechanism` (saxum.mechanism, of this frame's state) its
    sliding joints (at their centres of pressure) and, for a wall, the course numbers in the
    left margin. Draws into `ax` if given, else a new figure of
    figsize [in] (default: 9 in wide, as tall as the structure needs); saved to `path` at dpi
    when given (figsize * dpi pixels). 3D results: a perspective picture
    (saxum.plot3d.plot_frame_3d), coloured by displacement, with hinge lines and the
    mechanism's sliding joints. Deformable blocks (results with node positions) are drawn as
    their meshes, filled by the largest compression [MPa]."""
    k = _frame_index(results, frame)
    if results.dim == 3:
        if thrust_line or ax is not None or colour_by != "displacement":
            raise InputError("a 3D picture is drawn in its own figure, coloured by "
                             "displacement: thrust_line, ax and colour_by are for 2D results; "
                             "leave them out")
        return plot_frame_3d(results, k, path, forces=forces, title=title, figsize=figsize,
                             dpi=dpi, mechanism=mechanism)
    blocks = _results_blocks(results)
    floods = results_floods(results)
    look = _look(blocks, results.body_q[k:k + 1], colour_by,
                 _normal_forces(results, [k]) if forces else (), floods)
    if ax is None:
        ax = Figure(figsize=figsize or _figsize(look), layout="constrained").add_subplot()
    fig = ax.figure
    slides = None if mechanism is None else np.array(
        [j.centre_of_pressure for j in mechanism.sliding]).reshape(-1, 2)
    handles = _draw_frame(ax, results, k, look, blocks, forces, title, floods, slides=slides)
    if results.node_x is not None:
        _draw_elements(ax, results, k)
    if thrust_line:
        handles += _draw_thrust_line(ax, results, k, look, blocks)
    _legend(ax, handles, forces)
    if mechanism is not None:
        _draw_courses(ax, results.body_name, blocks)
    _colourbar(ax, look)
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig


def _body_index(results, body: int | str | None) -> int:
    """The block named or numbered `body`; None: the free block that moved most."""
    if body is None:
        d = results.dim
        moved = np.linalg.norm(results.body_q[..., :d] - results.model["body_q0"][:, :d],
                               axis=-1).max(axis=0)
        moved[results.model["body_kind"] != BodyKind.FREE] = -1.0
        return int(np.argmax(moved))
    if body in results.body_name:
        return results.body_name.index(body)
    try:
        return range(len(results.body_name))[int(body)]
    except (ValueError, IndexError):
        raise InputError(f"no block {body!r}: give a name (such as "
                         f"{results.body_name[-1]!r}) or an index below "
                         f"{len(results.body_name)}") from None


def plot_histories(results, path: str | PathLike | None = None, *,
                   body: int | str | None = None, figsize: tuple[float, float] | None = None,
                   dpi: int = 150) -> Figure:
    """Time histories in stacked panels: the blocks of the run's `histories` output at every
    step (horizontal displacement [mm or m] and rotation [deg]; ground acceleration
    [m/s^2] under a ground motion) or, without them or when `body` (name or index) is given,
    the displacement of that block at the output frames (default: the free block that moved
    most); then kinetic energy [J/m, mJ/m, ... as fits; 3D: J, mJ, ...], NLGS iterations per
    step (non-converged steps in red) and the largest interpenetration [nm, µm, mm or m].
    Saved to `path` at dpi when given."""
    if results.frame_count == 0:
        raise InputError(f"{results.path} has no output frame")
    h = results.histories if body is None else None
    s = results.steps
    ground = h is not None and "ground_acceleration" in h
    top = 2 + ground if h is not None else 1
    fig = Figure(figsize=figsize or (8.0, 7.0 + 2.0 * top), layout="constrained")
    axes = fig.subplots(top + 3, 1, sharex=True)
    if h is not None:
        _draw_block_histories(axes[:top], results, h)
    else:
        _draw_block_displacement(axes[0], results, _body_index(results, body))
    ax_e, ax_it, ax_pen = axes[top:]

    factor, unit = prefixed_unit(float(s["kinetic_energy"].max(initial=0.0)),
                                 results.units["kinetic_energy"])
    ax_e.plot(s["time"], factor * s["kinetic_energy"], lw=1.0, color="C3")
    ax_e.set_ylabel(f"kinetic energy [{unit}]")

    ax_it.plot(s["time"], s["iterations"], lw=0.7, color="0.3")
    bad = ~s["converged"]
    ax_it.scatter(s["time"][bad], s["iterations"][bad], s=12, color="red", zorder=3,
                  label=f"not converged ({int(bad.sum())} steps)")
    ax_it.legend(fontsize=8, loc="upper right")
    ax_it.set_ylabel("NLGS iterations [-]")

    factor, unit = length_unit(float(s["max_interpenetration"].max(initial=0.0)))
    ax_pen.plot(s["time"], factor * s["max_interpenetration"], lw=1.0, color="C4")
    ax_pen.set_ylabel(f"largest interpenetration [{unit}]")
    ax_pen.set_xlabel("time [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig


def _draw_block_displacement(ax, results, b: int) -> None:
    d = results.dim
    u = results.body_q[:, b, :d] - results.model["body_q0"][b, :d]
    magnitude = np.linalg.norm(u, axis=1)
    factor, unit = length_unit(float(magnitude.max()))
    for values, label in (*((u[:, i], f"$u_{'xyz'[i]}$") for i in range(d)),
                          (magnitude, "$|u|$")):
        ax.plot(results.time, factor * values, label=label, lw=1.2)
    ax.set_ylabel(f"displacement [{unit}]")
    ax.set_title(f"block {results.body_name[b]!r} (index {b})", fontsize=10)
    ax.legend(fontsize=8, ncol=d + 1)


def _draw_block_histories(axes, results, h: dict) -> None:
    """Horizontal displacement and rotation of each history block, and a_g(t)."""
    q0 = results.model["body_q0"][h["body"]]
    ux = h["body_q"][:, :, 0] - q0[:, 0]
    if results.dim == 2:
        turned = h["body_q"][:, :, 2] - q0[:, 2]
    else:  # the angle of the rotation from the initial orientation
        turned = np.linalg.norm(rotation_vectors(h["body_q"][:, :, 3:], q0[None, :, 3:]),
                                axis=-1)
    factor, unit = length_unit(float(np.abs(ux).max(initial=0.0)))
    # degrees from one degree up; below, prefixed radians rather than an axis offset
    largest = float(np.abs(turned).max(initial=0.0))
    turn_factor, turn_unit = ((180.0 / np.pi, "deg") if largest >= np.pi / 180.0
                              else prefixed_unit(largest, "rad"))
    for j, name in enumerate(h["name"]):
        axes[0].plot(h["time"], factor * ux[:, j], lw=1.0, label=name)
        axes[1].plot(h["time"], turn_factor * turned[:, j], lw=1.0)
    axes[0].set_ylabel(f"$u_x$ [{unit}]")
    axes[0].legend(fontsize=8, ncol=min(4, len(h["name"])))
    axes[0].set_title("blocks of output.histories, every step", fontsize=10)
    axes[1].set_ylabel(f"rotation [{turn_unit}]" if results.dim == 2
                       else f"rotation angle [{turn_unit}]")
    if len(axes) > 2:
        a = h["ground_acceleration"]
        names = ("horizontal", "vertical") if results.dim == 2 else ("x", "y", "z")
        for k, name in enumerate(names):
            if k == 0 or np.any(a[:, k]):
                axes[2].plot(h["time"], a[:, k], lw=0.8, label=name,
                             color="0.2" if k == 0 else None)
        axes[2].set_ylabel("ground acc. [m/s$^2$]")
        axes[2].legend(fontsize=8)


def plot_collapse_curve(points, path: str | PathLike | None = None, *, g: float = 9.81,
                        static: float | None = None, title: str = "",
                        figsize: tuple[float, float] = (7.0, 4.5), dpi: int = 150) -> Figure:
    """The collapse curve of saxum.collapse.collapse_curve: the critical pulse amplitude
    [g] against the pulse period [s], each point with its bisection bracket (stood at the
    lower end, collapsed at the upper; periods whose bracket failed are left out); the region
    above the curve collapses. `static`: the static horizontal load factor [-], drawn as the
    long-period limit."""
    pts = sorted((p for p in points if np.isfinite(p.collapses)), key=lambda p: p.period)
    if not pts:
        raise InputError("no period of the collapse curve has a critical amplitude to draw")
    t = np.array([p.period for p in pts])
    lo = np.array([p.stands for p in pts]) / g
    hi = np.array([p.collapses for p in pts]) / g
    mid = 0.5 * (lo + hi)
    fig = Figure(figsize=figsize, layout="constrained")
    ax = fig.add_subplot()
    ax.fill_between(t, mid, max(hi.max(), 1e-9) * 1.15, color="#c0152f", alpha=0.08,
                    label="collapses")
    ax.errorbar(t, mid, yerr=(mid - lo, hi - mid), fmt="o-", color="k", ms=4, lw=1.2,
                capsize=3, label="critical amplitude (bracket)")
    if static is not None:
        ax.axhline(static, color="#1f5fa8", ls="--", lw=1.0,
                   label=f"static load factor {static:.3g}")
    ax.set_xlabel("period of the ground motion $T_p$ [s]")
    ax.set_ylabel("amplitude [g]")
    ax.set_ylim(0.0, max(hi.max(), 1e-9) * 1.15)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    if title:
        ax.set_title(title, fontsize=10)
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig


def animate(results, path: str | PathLike, *, fps: int = 20, frames: Iterable[int] | None = None,
            forces: bool = True, figsize: tuple[float, float] | None = None,
            dpi: int = 100) -> Path:
    """Write the output frames (all, or the indices in `frames`) as a GIF, or an MP4 when
    path ends in .mp4 (needs ffmpeg), at fps frames per second and figsize [in] * dpi pixels
    (default figsize: 9 in wide, as tall as the structure needs; an MP4's size is rounded to
    even pixels). Axes limits, colour scale and force scale are the same on every frame.
    3D results: perspective frames (saxum.plot3d.frames_3d). Returns the path."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".mp4":
        if not animation.writers.is_available("ffmpeg"):
            raise InputError(f"cannot write {path}: MP4 needs ffmpeg, which was not found; "
                             "use a .gif file name or install ffmpeg")
        writer = animation.FFMpegWriter(fps=fps)
    elif suffix == ".gif":
        writer = animation.PillowWriter(fps=fps)
    else:
        raise InputError(f"cannot write {path}: the animation's file name must end in .gif "
                         "or .mp4")
    ks = [_frame_index(results, k) for k in
          (range(results.frame_count) if frames is None else frames)]
    if not ks:
        raise InputError(f"no frame to animate in {results.path}")
    if results.dim == 3:
        fig, draw = frames_3d(results, ks, forces=forces, figsize=figsize)
    else:
        fig, draw = _frames_2d(results, ks, forces, figsize)
    path.parent.mkdir(parents=True, exist_ok=True)
    with writer.saving(fig, str(path), dpi):
        for k in ks:
            draw(k)
            writer.grab_frame()
            # Laid out once, on the first frame: the axes then stay put while titles change,
            # and each frame is drawn once instead of twice (layout, then picture).
            fig.set_layout_engine(None)
    return path


def _frames_2d(results, ks: list[int], forces: bool, figsize):
    """(figure, draw) for an animation of the 2D output frames ks: draw(k) draws frame k,
    with the same axes, colour scale and force scale on every frame."""
    blocks = _results_blocks(results)
    floods = results_floods(results)
    look = _look(blocks, results.body_q[ks], "displacement",
                 _normal_forces(results, ks) if forces else (), floods)
    fig = Figure(figsize=figsize or _figsize(look), layout="constrained")
    ax = fig.add_subplot()
    _colourbar(ax, look)
    heading = results_heading(results)

    def draw(k: int) -> None:
        ax.clear()
        _legend(ax, _draw_frame(ax, results, k, look, blocks, forces, heading, floods),
                forces)
    return fig, draw


_GROUP_COLOURS = {"brick": "#d9b99b", "voussoir": "#9fb7c9", "pier": "#e3d5b8",
                  "spandrel": "#c9a27e", "fill": "#b5c99f", "lintel": "#a07850",
                  "wall": "#e3d5b8", "block": "#e3d5b8", "stone": "#cdbfa8"}
_OTHER_COLOURS = ("#d9a5a5", "#c4b5d9", "#a5d9d0", "#d9cfa5")


def plot_model(model: Model, path: str | PathLike | None = None, *, ax=None, title: str = "",
               dpi: int = 150) -> Figure:
    """The blocks of `model` at their initial positions, free blocks filled by group (named
    in the legend), fixed and driven ones hatched grey, framed on the free blocks (a wide
    ground is cut at the edges): what a generator or a scenario built, before any run.
    Draws into `ax` if given; saved to `path` at dpi when given. 2D models only."""
    if model.dim != 2:
        raise InputError("plot_model draws 2D models; for a 3D one, run it for a step and "
                         "use saxum plot, or export to ParaView")
    blocks = _model_blocks(model)
    look = _look(blocks, blocks.q0[None], None)
    free = model.body_kind == BodyKind.FREE
    if free.any():
        owner = np.repeat(np.arange(model.body_count), np.diff(blocks.vertex_start))
        pts = blocks.world(blocks.q0)[free[owner]]
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        pad = 0.08 * float((hi - lo).max())
        look = dataclasses.replace(look, xlim=(lo[0] - pad, hi[0] + pad),
                                   ylim=(lo[1] - pad, hi[1] + pad))
    if ax is None:
        ax = Figure(figsize=_figsize(look), layout="constrained").add_subplot()
    _draw_blocks(ax, look, blocks, blocks.q0)
    polygons = blocks.polygons(blocks.q0)
    handles, others = [], 0
    for g in np.unique(model.body_group[free]):
        mine = free & (model.body_group == g)
        colour = _GROUP_COLOURS.get(model.group_names[g])
        if colour is None:
            colour, others = _OTHER_COLOURS[others % len(_OTHER_COLOURS)], others + 1
        ax.add_collection(PolyCollection([p for p, m in zip(polygons, mine, strict=True) if m],
                                         facecolors=colour, edgecolors="k", linewidths=0.6,
                                         zorder=3))
        handles.append(Patch(facecolor=colour, edgecolor="k", label=model.group_names[g]))
    if handles:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=7,
                  frameon=False)
    _finish_axes(ax, look, title)
    if path is not None:
        ax.figure.savefig(path, dpi=dpi)
    return ax.figure


def save_states(path: str | PathLike, panels: Sequence[tuple[Model, np.ndarray, str]]) -> None:
    """Write a PNG with one panel per (model, q [m, m, rad] per body, title), blocks coloured
    by displacement from the initial position [mm or m], with the model's flood water (at
    t = 0)."""
    fig = Figure(figsize=(6 * len(panels), 4.5), layout="constrained")
    for ax, (model, q, title) in zip(fig.subplots(1, len(panels), squeeze=False)[0], panels,
                                     strict=True):
        blocks = _model_blocks(model)
        floods = _model_floods(model)
        look = _look(blocks, q[None], "displacement", (), floods)
        _draw_water(ax, look, blocks, q, floods, 0.0)
        _draw_blocks(ax, look, blocks, q)
        _finish_axes(ax, look, title)
        _colourbar(ax, look)
    fig.savefig(path, dpi=120)


def plot_limit(result, path: str | PathLike | None = None, *, title: str = "",
               thrust_line: bool | None = None, dpi: int = 150) -> Figure:
    """The mechanism of a limit analysis (saxum.limit.LimitAnalysis, 2D): the blocks moved
    by their virtual velocities, scaled so that the fastest point moves by 5 % of the
    structure's extent (the initial outlines dashed), the hinges (white circles) and
    sliding joints (diamonds), and for an arch (thrust_line None: a model without coursed
    wall blocks) the thrust line at collapse (the joints' centres of pressure). Saved to
    `path` at dpi when given."""
    model = result.model
    if model.dim != 2:
        raise InputError("plot_limit draws 2D mechanisms; a 3D one is reported in words "
                         "(LimitAnalysis.text)")
    blocks = _model_blocks(model)
    free = model.body_kind == BodyKind.FREE
    owner = np.repeat(np.arange(model.body_count), np.diff(blocks.vertex_start))
    pts = blocks.world(blocks.q0)[free[owner]]
    extent = float((pts.max(axis=0) - pts.min(axis=0)).max())
    q = blocks.q0 + 0.05 * extent * result.velocity  # fastest point at 1 m/s
    look = _look(blocks, q[None], None)
    lo, hi = np.minimum(pts.min(axis=0), blocks.world(q)[free[owner]].min(axis=0)), np.maximum(
        pts.max(axis=0), blocks.world(q)[free[owner]].max(axis=0))
    pad = 0.08 * float((hi - lo).max())
    look = dataclasses.replace(look, xlim=(lo[0] - pad, hi[0] + pad),
                               ylim=(lo[1] - pad, hi[1] + pad))
    ax = Figure(figsize=_figsize(look), layout="constrained").add_subplot()
    _draw_blocks(ax, look, blocks, q)
    mech = result.mechanism
    hinges = np.array([j.hinge_point for j in mech.hinges]).reshape(-1, 2)
    slides = np.array([j.centre_of_pressure for j in mech.sliding]).reshape(-1, 2)
    handles = ax.plot(hinges[:, 0], hinges[:, 1], ls="none", zorder=5,
                      label=f"hinge ({len(hinges)})", **_MARKS["hinge"])
    handles += ax.plot(slides[:, 0], slides[:, 1], ls="none", zorder=5,
                       label=f"sliding ({len(slides)})", **_SLIDE)
    wall = any(j.courses for j in mech.joints)
    if thrust_line or (thrust_line is None and not wall):
        centre = (float(pts[:, 0].mean()), float(pts[:, 1].min()))
        line = result.thrust_line(centre)
        handles += ax.plot(line[:, 0], line[:, 1], "-o", color="k", lw=1.2, ms=2.5,
                           zorder=6, label="thrust line at collapse")
    _draw_courses(ax, model.body_name, blocks)
    _legend(ax, handles, False)
    _finish_axes(ax, look, f"{title + ': ' if title else ''}{result.heading()}, mechanism "
                           "(virtual displacement, scaled)")
    if path is not None:
        ax.figure.savefig(path, dpi=dpi)
    return ax.figure
