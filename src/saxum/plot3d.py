"""Pictures and animation frames of 3D results with matplotlib's 3D axes (for `saxum plot` and
`saxum animate`; for anything more, export to ParaView: saxum export-vtk).

The blocks' faces are filled by the block's displacement from its initial position (fixed and
driven bodies light grey; a support much larger than the structure, such as a ground slab, is
shown as a floor under it; a structure at rest, saxum.plot_common.REST, plain with its largest
displacement written instead of a colour scale), and the contact points carrying load are
drawn on top as red dots whose area is proportional to the normal force (the scale in the
legend). Hinges (saxum.mechanism: joints whose loaded points lie on a line while the rest has
opened) are drawn as thick black lines along the edge they turn about, open contact points as
orange crosses, the points of cohesive joints (mortar) as squares coloured by their bond
(intact, damaged, cracked: saxum.mechanism.bond_states; as saxum.plot's strokes) whose area
is proportional to the share of the joint each stands for, a scenario's point loads as green
arrows onto their blocks' centres of mass and, with a mechanism, its sliding joints as purple
diamonds at their centres of pressure.
Flood water (saxum.flood) is its surface at the frame's time, translucent, drawn over the
faces under water (their centre below the surface: the ground, the submerged blocks) and
under those above it, with the flow's direction and speed. An animation keeps the axes,
colour scale and dot scale of its first frame's look over all frames. In a picture of one
frame, deformable blocks are drawn as their meshes' boundary triangles filled by the largest
compression of their tetrahedra [MPa], as saxum.plot fills the 2D triangles (an animation
shows their polyhedra moved by their frames).
"""

from dataclasses import dataclass
from os import PathLike

import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from .errors import InputError
from .fe.mesh import boundary_facets
from .geometry3d import relative_quaternions, world_points
from .mechanism import (
    BOND_STATES,
    Mechanism,
    bond_states,
    frame_contacts,
    hinge_lines,
    joint_states,
)
from .model import BodyKind, drawn_polyhedra
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

__all__ = ["frames_3d", "plot_frame_3d", "plot_limit_3d"]

_DOT = 40.0  # area [pt^2] of the dot of the largest normal force
_BOND = 30.0  # area [pt^2] of the square of the largest bonded point


@dataclass(frozen=True)
class _Look3d:
    """What stays the same on every frame of one 3D picture or animation."""

    centre: np.ndarray  # [m]
    half: float  # half the side of the cube drawn [m]
    floor: np.ndarray  # bodies drawn as a floor instead of as blocks
    floor_height: float  # [m]
    mappable: ScalarMappable | None  # None: at rest, plain blocks
    factor: float  # from metres to the colour bar's unit
    unit: str
    largest: float  # largest displacement of a free block [m]
    force_full: float  # normal force drawn as the largest dot [N]; 0: none loaded
    force_clipped: bool  # some drawn force exceeds force_full (drawn as the largest dot)
    gap_tolerance: float  # [m]
    size: float  # median block size [m]


def _look_3d(results, ks) -> _Look3d:
    m = results.model
    g = drawn_polyhedra(m)
    start, local = g["body_vertex_start"], g["vertex_local"]
    q = results.body_q[ks]
    owner = np.repeat(np.arange(q.shape[1]), np.diff(start))
    free = m["body_kind"] == BodyKind.FREE
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for qk in q:  # frame by frame: an animation of a large model holds one frame's points
        points = world_points(qk, start, local)
        shown = points[free[owner]] if free.any() else points
        lo, hi = np.minimum(lo, shown.min(axis=0)), np.maximum(hi, shown.max(axis=0))
    centre, half = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
    initial = world_points(m["body_q0"], start, local)
    extent = np.array([np.ptp(initial[owner == b], axis=0).max() for b in range(q.shape[1])])
    floor = ~free & (extent > 4.0 * half)
    moved = np.linalg.norm(q[..., :3] - m["body_q0"][:, :3], axis=-1)
    largest = float(moved[:, free].max(initial=0.0))
    factor, unit = length_unit(largest)
    peaks = np.array([results.contacts(k)["force"][:, 1].max(initial=0.0) for k in ks])
    size = float(np.median(results.body_size[free] if free.any() else results.body_size))
    reference = float(np.percentile(peaks, 90)) if peaks.size else 0.0
    full = nice_ceil(reference) if reference > 0.0 else 0.0
    mappable = (None if largest < REST * size
                else ScalarMappable(Normalize(0.0, factor * largest), "viridis"))
    return _Look3d(centre, half, floor, float(lo[2]), mappable, factor, unit, largest, full,
                   peaks.size > 0 and float(peaks.max()) > full, 1e-3 * size, size)


def _draw_frame_3d(ax, results, k: int, look: _Look3d, forces: bool, title: str,
                   mechanism: Mechanism | None = None, meshes: bool = False) -> None:
    """meshes: the deformable blocks as their meshes filled by the stress (_draw_elements_3d)
    instead of their polyhedra moved by their frames."""
    m = results.model
    q = results.body_q[k]
    free = m["body_kind"] == BodyKind.FREE
    g = drawn_polyhedra(m)
    points = world_points(q, g["body_vertex_start"], g["vertex_local"])
    fvs, fv = g["face_vertex_start"], g["face_vertex"]
    owner = np.repeat(np.arange(len(q)), np.diff(g["body_face_start"]))
    hidden = look.floor | (meshes & (m["body_kind"] == BodyKind.DEFORMABLE))
    keep = np.flatnonzero(~hidden[owner])
    faces = [points[fv[fvs[f]:fvs[f + 1]]] for f in keep]
    moved = np.linalg.norm(q[:, :3] - m["body_q0"][:, :3], axis=1)
    fill = ((0.89, 0.835, 0.72, 1.0) if look.mappable is None  # at rest: sandstone
            else look.mappable.to_rgba(look.factor * moved[owner[keep]]))
    colours = np.where(free[owner[keep], None], fill, (0.85, 0.85, 0.85, 1.0))
    ax.computed_zorder = False  # the contact dots and hinges stay on top of the faces
    c0, half = look.centre, look.half
    if look.floor.any():
        x0, x1, y0, y1 = c0[0] - half, c0[0] + half, c0[1] - half, c0[1] + half
        z = look.floor_height
        ax.add_collection3d(Poly3DCollection([[(x0, y0, z), (x1, y0, z), (x1, y1, z),
                                               (x0, y1, z)]], facecolors="0.92",
                                             edgecolors="0.6", zorder=0))
    shown = points[free[np.repeat(np.arange(len(q)), np.diff(g["body_vertex_start"]))]]
    shown = shown if len(shown) else points
    t = float(results.time[k])
    floods = results_floods(results)
    middle = np.array([f.mean(axis=0) for f in faces]).reshape(-1, 3)
    wet = np.zeros(len(faces), dtype=bool)
    for flood in floods:
        wet |= middle[:, 2] < _surface(flood, t, middle[:, :2], shown)
    # Faces under water first, then the water over them, then the faces above it.
    for under, z in ((True, 1), (False, 3)):
        pick = np.flatnonzero(wet == under)
        if pick.size:
            ax.add_collection3d(Poly3DCollection([faces[i] for i in pick],
                                                 facecolors=colours[pick], edgecolors="0.25",
                                                 linewidths=0.3, zorder=z))
        if under:
            for flood in floods:
                _draw_water(ax, flood, t, shown, c0, half)
    if meshes:
        _draw_elements_3d(ax, results, k)
    handles = _draw_point_loads(ax, results_point_loads(results), q, look)
    contacts = frame_contacts(results, k)
    handles = _draw_bonds(ax, contacts, m["law_kind"]) + handles
    if forces:
        handles = _draw_contacts(ax, contacts, look, mechanism) + handles
    if handles:
        ax.legend(handles=handles, fontsize=8, loc="upper left",
                  title="normal force" if forces and look.force_full > 0.0 else None,
                  title_fontsize=8)
    _cube(ax, c0, half)
    ax.set_title(f"{title}: t = {results.time[k]:.3f} s (step {results.step[k]})",
                 fontsize=10, wrap=True)


def _cube(ax, centre: np.ndarray, half: float) -> None:
    """Axes limits: the cube of side 2 half [m] about centre [m], equal scales, labels."""
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
        setter(c - half, c + half)
    ax.set_box_aspect((1.0, 1.0, 1.0))
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")


def _draw_elements_3d(ax, results, k: int) -> None:
    """The deformable blocks' boundary triangles at frame k, each filled by the largest
    compression of its tetrahedron (the smallest principal stress, when negative) [MPa], with
    its colour bar (saxum.plot's colours for the 2D triangles)."""
    facets, cell = boundary_facets(results.model["fe_cell_node"], 3)
    compression = results.stresses(k)["compression"][cell] * 1e-6
    mappable = ScalarMappable(Normalize(0.0, max(float(compression.max()), 1e-12)), "magma_r")
    ax.add_collection3d(Poly3DCollection(results.node_x[k][facets],
                                         facecolors=mappable.to_rgba(compression),
                                         edgecolors="0.4", linewidths=0.2, zorder=3))
    ax.figure.colorbar(mappable, ax=ax, shrink=0.6, label="largest compression [MPa]")


def _draw_contacts(ax, c: dict, look: _Look3d, mechanism: Mechanism | None) -> list:
    """Loaded points as dots (area ~ normal force), hinge lines, open points and, with a
    mechanism, its sliding joints; returns the legend handles, the dots' scale first."""
    normal = c["force"][:, 1]
    loaded = normal > 0.0
    handles = []
    if loaded.any() and look.force_full > 0.0:
        size = _DOT * np.minimum(normal[loaded] / look.force_full, 1.0)
        ax.scatter(*c["point"][loaded].T, s=size, color="#c0152f", depthshade=False,
                   zorder=4)
        factor, unit = prefixed_unit(look.force_full, "N")
        for fraction in (1.0, 0.5):
            label = f"{look.force_full * fraction * factor:g} {unit}"
            handles.append(Line2D([], [], ls="none", marker="o", color="#c0152f",
                                  markersize=np.sqrt(_DOT * fraction),
                                  label=("≥ " if fraction == 1.0 and look.force_clipped
                                         else "") + label))
    opened = c["point"][joint_states(c, look.gap_tolerance) == "open"]
    if len(opened):
        handles += ax.plot(*opened.T, ls="none", marker="x", markersize=4, color="#e07b00",
                           zorder=5, label=f"open ({len(opened)})")
    return handles + _draw_hinges(ax, hinge_lines(c, look.gap_tolerance),
                                  [] if mechanism is None else mechanism.sliding)


def _draw_hinges(ax, lines: list, sliding: list) -> list:
    """Hinge lines ((end, end) pairs [m]; a point where the ends coincide) thick black, and
    the sliding joints (saxum.mechanism.Joint) as purple diamonds at their centres of
    pressure; returns the legend handles."""
    handles = []
    for i, (a, b) in enumerate(lines):
        drawn = ax.plot(*np.array([a, b]).T, color="k", lw=3.0, solid_capstyle="round",
                        zorder=6, marker="o" if np.array_equal(a, b) else None, markersize=5,
                        label=f"hinges ({len(lines)})")
        handles += drawn if i == 0 else []
    if sliding:
        cop = np.array([j.centre_of_pressure for j in sliding])
        handles += ax.plot(*cop.T, ls="none", marker="D", markersize=5.5,
                           markerfacecolor="#7b2cbf", markeredgecolor="k", markeredgewidth=0.6,
                           zorder=7, label=f"sliding ({len(cop)})")
    return handles


def _draw_bonds(ax, c: dict, law_kind: np.ndarray) -> list:
    """The points of cohesive joints as squares coloured by their bond (module doc), if the
    contacts have a damage field (files from before the joint laws do not); returns their
    legend handles."""
    if any(name not in c for name in ("damage", "history", "area")):
        return []
    state = bond_states(c["law"], c["damage"], c["history"], law_kind)
    bonded = state != ""
    if not bonded.any():
        return []
    size = _BOND * c["area"] / c["area"][bonded].max()
    handles = []
    for label in BOND_STATES:
        rows = state == label
        if not rows.any():
            continue
        ax.scatter(*c["point"][rows].T, s=size[rows], marker="s", color=BOND_COLOURS[label],
                   depthshade=False, zorder=3.5)
        handles.append(Line2D([], [], ls="none", marker="s", color=BOND_COLOURS[label],
                              markersize=np.sqrt(0.5 * _BOND),
                              label=f"{label} bond ({rows.sum()})"))
    return handles


def _draw_point_loads(ax, loads: list, q: np.ndarray, look: _Look3d) -> list:
    """Arrows onto the loaded blocks' centres of mass (1.5 median block sizes long); returns
    the legend handle (none without loads)."""
    if not loads:
        return []
    for b, force in loads:
        arrow = 1.5 * look.size * force / np.linalg.norm(force)
        ax.quiver(*(q[b, :3] - arrow), *arrow, color=LOAD_COLOUR, lw=2.0,
                  arrow_length_ratio=0.3, zorder=8)
    largest = max(float(np.linalg.norm(f)) for _, f in loads)
    factor, unit = prefixed_unit(largest, "N")
    sizes = ", ".join(f"{np.linalg.norm(f) * factor:.3g}" for _, f in loads)
    return [Line2D([], [], color=LOAD_COLOUR, lw=2.0, marker=">", markevery=[-1],
                   label=f"point load{'s' if len(loads) > 1 else ''} {sizes} {unit}")]


def _surface(flood, t: float, xy: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The water level H(s) [m] at time t [s] at the plan positions xy [m], s along the
    flow's azimuth, the free blocks' extent `points` [m] setting where the head changes."""
    a = np.radians(flood.azimuth)
    e = np.array([np.cos(a), np.sin(a)])
    s = points[:, :2] @ e
    return flood.surface(xy @ e, t, (float(s.min()), float(s.max())))


def _draw_water(ax, flood, t: float, points: np.ndarray, centre: np.ndarray,
                half: float) -> None:
    """The water surface z = H(s) [m] at time t [s] over the square drawn (centre, half
    width [m]) (_surface); the flow's speed and direction in a corner."""
    x, y = np.meshgrid(*(np.linspace(c - half, c + half, 25) for c in centre[:2]))
    z = _surface(flood, t, np.stack((x, y), axis=-1), points)
    ax.plot_surface(x, y, z, color="#9cc8e8", alpha=0.45, linewidth=0, shade=False,
                    zorder=2)
    u = flood.velocity.at(t)
    if u != 0.0:
        heading = flood.azimuth if u > 0 else flood.azimuth + 180.0
        ax.text2D(0.99, 0.98, f"flow {abs(u):.3g} m/s towards {heading % 360:g}° from x",
                  transform=ax.transAxes, ha="right", va="top", fontsize=8, color="#2a6fa8")


def _figure(look: _Look3d, figsize) -> tuple[Figure, object]:
    fig = Figure(figsize=figsize or (9.0, 7.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    if look.mappable is None:
        fig.text(0.99, 0.01, f"at rest: largest displacement {look.largest:.2g} m",
                 ha="right", va="bottom", fontsize=8, color="0.25")
    else:
        fig.colorbar(look.mappable, ax=ax, shrink=0.6, label=f"displacement [{look.unit}]")
    return fig, ax


def plot_frame_3d(results, k: int, path: str | PathLike | None = None, *, forces: bool = True,
                  title: str | None = None, figsize: tuple[float, float] | None = None,
                  dpi: int = 150, mechanism: Mechanism | None = None) -> Figure:
    """The 3D structure at output frame index k of saxum.results.Results (see module doc),
    with the sliding joints of `mechanism` (saxum.mechanism, of this frame's state) when
    given; saved to `path` at dpi when given."""
    look = _look_3d(results, [k])
    fig, ax = _figure(look, figsize)
    _draw_frame_3d(ax, results, k, look, forces,
                   title if title is not None else results_heading(results), mechanism,
                   meshes=results.node_x is not None)
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig


def frames_3d(results, ks, *, forces: bool = True,
              figsize: tuple[float, float] | None = None):
    """(figure, draw) for an animation of the output frames ks of 3D results: draw(k) draws
    frame k into the figure, with the same axes, colour scale and dot scale on every frame."""
    look = _look_3d(results, ks)
    fig, ax = _figure(look, figsize)
    heading = results_heading(results)

    def draw(k: int) -> None:
        ax.clear()
        _draw_frame_3d(ax, results, k, look, forces, heading)
    return fig, draw


def plot_limit_3d(result, path: str | PathLike | None = None, *, title: str = "",
                  dpi: int = 150, figsize: tuple[float, float] | None = None) -> Figure:
    """The mechanism of a 3D limit analysis (saxum.limit.LimitAnalysis), as plot.plot_limit
    draws a 2D one: every block moved rigidly by its virtual velocity (translation and the
    rotation vector omega, world frame) times a scale that moves the fastest block point by
    5 % of the structure's extent, the moving blocks filled by their speed (centre of mass
    [m/s], the fastest block point at 1 m/s), the still ones sandstone, supports grey (a
    support much larger than the structure left out), the hinge lines thick black, the
    sliding joints purple diamonds at their centres of pressure. Saved to `path` at dpi
    when given."""
    model = result.model
    if model.dim != 3:
        raise InputError("plot_limit_3d draws 3D mechanisms; plot.plot_limit draws 2D ones")
    start, local = model.body_vertex_start, model.vertex_local
    owner = np.repeat(np.arange(model.body_count), np.diff(start))
    free = model.body_kind == BodyKind.FREE
    initial = world_points(model.body_q0, start, local)
    span = np.ptp(initial[free[owner]], axis=0)
    scale = 0.05 * float(span.max())
    turn = scale * result.velocity[:, 3:]
    angle = np.linalg.norm(turn, axis=1, keepdims=True)
    axis = np.divide(turn, angle, out=np.zeros_like(turn), where=angle > 0.0)
    dq = np.hstack((np.cos(0.5 * angle), np.sin(0.5 * angle) * axis))
    q = model.body_q0.copy()
    q[:, :3] += scale * result.velocity[:, :3]
    q0_inverse = model.body_q0[:, 3:] * np.array([1.0, -1.0, -1.0, -1.0])
    q[:, 3:] = relative_quaternions(dq, q0_inverse)  # dq q0: turned by dq in the world
    points = world_points(q, start, local)
    extent = np.array([np.ptp(initial[owner == b], axis=0).max()
                       for b in range(model.body_count)])
    shown = free | (extent <= 2.0 * float(span.max()))
    fvs, fv = model.face_vertex_start, model.face_vertex
    face_owner = np.repeat(np.arange(model.body_count), np.diff(model.body_face_start))
    keep = np.flatnonzero(shown[face_owner])
    speed = np.linalg.norm(result.velocity[:, :3], axis=1)
    mappable = ScalarMappable(Normalize(0.0, max(float(speed.max()), 1e-12)), "viridis")
    moving = np.isin(np.array(model.body_name), result.mechanism.moving)
    colours = np.where((free & moving)[face_owner[keep], None],
                       mappable.to_rgba(speed[face_owner[keep]]),
                       np.where(free[face_owner[keep], None], (0.89, 0.835, 0.72, 1.0),
                                (0.85, 0.85, 0.85, 1.0)))
    fig = Figure(figsize=figsize or (9.0, 7.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    ax.computed_zorder = False  # hinges and sliding joints stay on top of the faces
    ax.add_collection3d(Poly3DCollection([points[fv[fvs[f]:fvs[f + 1]]] for f in keep],
                                         facecolors=colours, edgecolors="0.25",
                                         linewidths=0.3, zorder=1))
    fig.colorbar(mappable, ax=ax, shrink=0.6, label="virtual speed [m/s]")
    # the hinges of the initial configuration: the mechanism's first instant
    mech = result.mechanism
    handles = _draw_hinges(ax, [j.hinge_line or (j.hinge_point,) * 2 for j in mech.hinges],
                           mech.sliding)
    if handles:
        ax.legend(handles=handles, fontsize=8, loc="upper left")
    every = np.concatenate((points[shown[owner]], initial[free[owner]]))
    lo, hi = every.min(axis=0), every.max(axis=0)
    _cube(ax, 0.5 * (lo + hi), 0.55 * float((hi - lo).max()))
    ax.set_title(f"{title + ': ' if title else ''}{result.heading()}, mechanism (virtual "
                 "displacement, scaled)", fontsize=10, wrap=True)
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig
