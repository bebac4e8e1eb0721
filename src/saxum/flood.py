"""Floods: hydrostatic pressure, buoyancy and drag of a river on the blocks of a 2D structure.

The water (density rho_w [kg/m^3], gravity g = |gravity| [m/s^2]) is described by its
piezometric head H(s) [m], a height measured along "up" (-gravity) from the origin, as a
function of the horizontal coordinate s [m] (along +x for gravity along -y):

    H(s) = level                  for s <= s_a        (upstream)
    H(s) = tailwater              for s >= s_b        (downstream)
    H(s) linear in between                            (the head drops across the structure)

with tailwater = level (still water on both sides) unless given, and s_a, s_b the most
upstream and most downstream points of the free blocks in the current configuration (so the
water follows a structure that slides). The pressure at a point of
height z is p = rho_w g max(H(s) - z, 0), on every face of every free block: water is assumed
to fill the joints (full uplift, the usual conservative assumption for masonry dams and
bridges in floods; faces in contact carry the pressure on both sides). The force and moment
on a block are the exact integrals of -p n over its edges (p is linear on each edge piece cut
at s_a, s_b and at the water line, so each piece integrates in closed form); by the divergence
theorem a block under still water thus gets the buoyancy rho_w g V_sub through the centroid of
its submerged part, and a wall with the head dropping across it gets the hydrostatic thrust on
its upstream face and the linear uplift on its base of gravity-dam practice (heel at the
upstream head, toe at the downstream one).

Drag of the flow, of velocity U [m/s] along +s (negative: along -s), is the pressure
p_d = 1/2 rho_w C_d U |U| on the area the structure presents to the flow: at each height z
under water the first face met coming from upstream (a face of any body, fixed ones included,
so that upstream blocks shield those behind them) gets p_d dz along the flow. C_d [-] is the
drag coefficient of the whole obstacle, 1.4 by default (square-ended pier, AASHTO LRFD Bridge
Design Specifications, 3.7.3.1; 0.7 semicircular-nosed, 0.8 wedge-nosed). The velocity is
uniform over the depth and the blocks' own velocity is neglected (no added mass, no damping).

Both loads depend on where the blocks are: they are field loads (Model.field_loads), evaluated
explicitly in the force stage of each step at the beginning-of-step configuration q_i and at
the time t_i + theta h (saxum.simulation.Simulation._step_force). Loads are per metre of depth
[N/m, N m/m]. Scenario keys: [loads.flood] (docs/scenario.md); write-up: docs/flood.md.
3D models (polyhedral blocks, the flow at any horizontal azimuth, drag on exposed projected
areas) run the kernels of saxum.flood3d behind the same FloodLoad.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numba as nb
import numpy as np

from . import flood3d
from .errors import InputError
from .model import BodyKind

__all__ = ["DRAG_COEFFICIENT", "FloodLoad", "drag_forces", "hydrostatic_forces",
           "series_problem"]

DRAG_COEFFICIENT = 1.4
"""Default drag coefficient C_d [-]: square-ended pier (AASHTO LRFD 3.7.3.1)."""


@nb.njit(cache=True)
def _head(s, h_up, h_down, s_a, s_b):
    """Piezometric head H(s) [m] (module doc)."""
    if s <= s_a:
        return h_up
    if s >= s_b:
        return h_down
    return h_up + (h_down - h_up) * (s - s_a) / (s_b - s_a)


@nb.njit(cache=True)
def _extent(q, kind, vertex_start, vertex_local, e):
    """(smallest, largest) coordinate [m] along the unit vector e of the free blocks'
    vertices at coordinates q."""
    lo = np.inf
    hi = -np.inf
    for b in range(q.shape[0]):
        if kind[b] != 0:
            continue
        c = math.cos(q[b, 2])
        s = math.sin(q[b, 2])
        for k in range(vertex_start[b], vertex_start[b + 1]):
            x = q[b, 0] + c * vertex_local[k, 0] - s * vertex_local[k, 1]
            y = q[b, 1] + s * vertex_local[k, 0] + c * vertex_local[k, 1]
            v = x * e[0] + y * e[1]
            lo = min(lo, v)
            hi = max(hi, v)
    return lo, hi


@nb.njit(cache=True)
def _wet_pieces(s0, ds, z0, dz, h_up, h_down, s_a, s_b, pieces):
    """The wet parts of the segment (s, z) = (s0 + t ds, z0 + t dz), t in [0, 1]: rows
    (t_begin, t_end, H - z at t_begin, H - z at t_end) of `pieces` (3 rows at most: the
    segment is cut where it crosses s_a and s_b, and each piece at the water line, where
    H - z changes sign); returns the number of rows."""
    c1 = 1.0  # the cuts at s_a and s_b, in order, clamped to [0, 1]
    c2 = 1.0
    if h_down != h_up and ds != 0.0:
        u = (s_a - s0) / ds
        v = (s_b - s0) / ds
        c1 = min(max(min(u, v), 0.0), 1.0)
        c2 = min(max(max(u, v), 0.0), 1.0)
    count = 0
    for i in range(3):
        ta = 0.0 if i == 0 else (c1 if i == 1 else c2)
        tb = c1 if i == 0 else (c2 if i == 1 else 1.0)
        if tb <= ta:
            continue
        fa = _head(s0 + ta * ds, h_up, h_down, s_a, s_b) - (z0 + ta * dz)
        fb = _head(s0 + tb * ds, h_up, h_down, s_a, s_b) - (z0 + tb * dz)
        if fa <= 0.0 and fb <= 0.0:
            continue
        if fa < 0.0:
            ta = ta + (tb - ta) * fa / (fa - fb)
            fa = 0.0
        elif fb < 0.0:
            tb = ta + (tb - ta) * fa / (fa - fb)
            fb = 0.0
        if tb > ta:
            pieces[count, 0] = ta
            pieces[count, 1] = tb
            pieces[count, 2] = fa
            pieces[count, 3] = fb
            count += 1
    return count


@nb.njit(cache=True)
def hydrostatic_forces(q, kind, radius, vertex_start, vertex_local, normal_local, rho_g, up,
                       h_up, h_down, s_a, s_b, out):
    """out[b] += (fx [N], fy [N], torque about the centre of mass [N m]) of the water
    pressure p = rho_g max(H(s) - z, 0) [Pa] on every edge of every free body b:
    F = -int p n dl, M = -int (r - G) x p n dl, exact for p linear on each wet piece (from
    p_0, p_1 at its ends Q_0, Q_1, length l: int p dl = l (p_0 + p_1)/2 and
    int p r dl = l [(2 p_0 + p_1) Q_0 + (p_0 + 2 p_1) Q_1]/6). rho_g = rho_w g [N/m^3];
    up: unit vector against gravity; heads h_up, h_down [m], s_a, s_b [m] (module doc);
    radius [m]: each body's largest distance from its centre of mass to a vertex."""
    pieces = np.empty((3, 4))
    ux = up[0]
    uy = up[1]
    ex = uy  # horizontal unit vector: up turned clockwise
    ey = -ux
    for b in range(q.shape[0]):
        if kind[b] != 0:
            continue
        zg = q[b, 0] * ux + q[b, 1] * uy
        if zg - radius[b] >= max(h_up, h_down):
            continue  # above the water
        c = math.cos(q[b, 2])
        s = math.sin(q[b, 2])
        sg = q[b, 0] * ex + q[b, 1] * ey
        fx = 0.0
        fy = 0.0
        torque = 0.0
        first = vertex_start[b]
        last = vertex_start[b + 1]
        for k in range(first, last):
            k1 = k + 1 if k + 1 < last else first
            ax = c * vertex_local[k, 0] - s * vertex_local[k, 1]
            ay = s * vertex_local[k, 0] + c * vertex_local[k, 1]
            bx = c * vertex_local[k1, 0] - s * vertex_local[k1, 1]
            by = s * vertex_local[k1, 0] + c * vertex_local[k1, 1]
            nx = c * normal_local[k, 0] - s * normal_local[k, 1]
            ny = s * normal_local[k, 0] + c * normal_local[k, 1]
            dx = bx - ax
            dy = by - ay
            length = math.sqrt(dx * dx + dy * dy)
            za = zg + ax * ux + ay * uy
            sa = sg + ax * ex + ay * ey
            m = _wet_pieces(sa, dx * ex + dy * ey, za, dx * ux + dy * uy, h_up, h_down, s_a,
                            s_b, pieces)
            for i in range(m):
                t0 = pieces[i, 0]
                t1 = pieces[i, 1]
                p0 = rho_g * pieces[i, 2]
                p1 = rho_g * pieces[i, 3]
                piece = length * (t1 - t0)
                mean = 0.5 * piece * (p0 + p1)
                fx -= nx * mean
                fy -= ny * mean
                w0 = piece * (2.0 * p0 + p1) / 6.0
                w1 = piece * (p0 + 2.0 * p1) / 6.0
                rx = w0 * (ax + t0 * dx) + w1 * (ax + t1 * dx)
                ry = w0 * (ay + t0 * dy) + w1 * (ay + t1 * dy)
                torque -= rx * ny - ry * nx
        out[b, 0] += fx
        out[b, 1] += fy
        out[b, 2] += torque


@nb.njit(cache=True)
def drag_forces(q, kind, vertex_start, vertex_local, normal_local, pressure, flow, up, h_up,
                h_down, s_a, s_b, segments, heights, best, owner, out):
    """out[b] += the drag on free body b: p_d = `pressure` [Pa] (1/2 rho_w C_d U^2) times the
    height dz [m] of each band of heights where b's face is the first met coming from upstream
    (faces of all bodies, wet parts only), along the unit vector `flow`, applied at the face's
    mid-band point. Scratch arrays: segments (>= 3 per vertex, 7), heights, best, owner
    (>= 6 per vertex)."""
    pieces = np.empty((3, 4))
    ux = up[0]
    uy = up[1]
    ex = uy
    ey = -ux
    count = 0
    for b in range(q.shape[0]):
        c = math.cos(q[b, 2])
        s = math.sin(q[b, 2])
        first = vertex_start[b]
        last = vertex_start[b + 1]
        for k in range(first, last):
            nx = c * normal_local[k, 0] - s * normal_local[k, 1]
            ny = s * normal_local[k, 0] + c * normal_local[k, 1]
            if nx * flow[0] + ny * flow[1] >= 0.0:
                continue  # not facing upstream
            k1 = k + 1 if k + 1 < last else first
            ax = q[b, 0] + c * vertex_local[k, 0] - s * vertex_local[k, 1]
            ay = q[b, 1] + s * vertex_local[k, 0] + c * vertex_local[k, 1]
            dx = q[b, 0] + c * vertex_local[k1, 0] - s * vertex_local[k1, 1] - ax
            dy = q[b, 1] + s * vertex_local[k1, 0] + c * vertex_local[k1, 1] - ay
            za = ax * ux + ay * uy
            dz = dx * ux + dy * uy
            m = _wet_pieces(ax * ex + ay * ey, dx * ex + dy * ey, za, dz, h_up, h_down, s_a,
                            s_b, pieces)
            for i in range(m):
                z0 = za + pieces[i, 0] * dz
                z1 = za + pieces[i, 1] * dz
                if z0 == z1:
                    continue
                segments[count, 0] = b
                segments[count, 1] = ax + pieces[i, 0] * dx  # end points [m]
                segments[count, 2] = ay + pieces[i, 0] * dy
                segments[count, 3] = ax + pieces[i, 1] * dx
                segments[count, 4] = ay + pieces[i, 1] * dy
                segments[count, 5] = min(z0, z1)
                segments[count, 6] = max(z0, z1)
                heights[2 * count] = z0
                heights[2 * count + 1] = z1
                count += 1
    if count == 0:
        return
    heights[: 2 * count].sort()
    # Band edges: the heights, those within tol of the previous edge merged into it (the
    # blocks of a course share their heights, give or take the micrometres they settle by),
    # so that each face spans few bands; the drag moves by p_d tol at most per edge.
    tol = 1e-6 * (heights[2 * count - 1] - heights[0])
    unique = 1
    for j in range(1, 2 * count):
        if heights[j] - heights[unique - 1] > tol:
            heights[unique] = heights[j]
            unique += 1
    bands = heights[:unique]
    best[:unique] = np.inf
    owner[:unique] = -1
    for i in range(count):
        lo = np.searchsorted(bands, segments[i, 5] - tol)
        hi = np.searchsorted(bands, segments[i, 6] - tol)
        x0 = segments[i, 1] * flow[0] + segments[i, 2] * flow[1]
        x1 = segments[i, 3] * flow[0] + segments[i, 4] * flow[1]
        z0 = segments[i, 1] * ux + segments[i, 2] * uy
        z1 = segments[i, 3] * ux + segments[i, 4] * uy
        for j in range(lo, hi):
            zm = 0.5 * (bands[j] + bands[j + 1])
            x = x0 + (x1 - x0) * (zm - z0) / (z1 - z0)
            if x < best[j]:
                best[j] = x
                owner[j] = i
    for j in range(unique - 1):
        i = owner[j]
        if i < 0:
            continue
        b = int(segments[i, 0])
        height = bands[j + 1] - bands[j]
        if kind[b] != 0 or height <= 0.0:
            continue
        z0 = segments[i, 1] * ux + segments[i, 2] * uy
        z1 = segments[i, 3] * ux + segments[i, 4] * uy
        u = (0.5 * (bands[j] + bands[j + 1]) - z0) / (z1 - z0)
        px = segments[i, 1] + u * (segments[i, 3] - segments[i, 1]) - q[b, 0]
        py = segments[i, 2] + u * (segments[i, 4] - segments[i, 2]) - q[b, 1]
        fx = pressure * height * flow[0]
        fy = pressure * height * flow[1]
        out[b, 0] += fx
        out[b, 1] += fy
        out[b, 2] += px * fy - py * fx


def series_problem(series) -> str | None:
    """What is wrong with a time series of (time [s], value) pairs, or None if nothing."""
    data = np.asarray(series, dtype=np.float64)
    if data.ndim != 2 or data.shape[1] != 2 or len(data) < 2:
        return f"give at least two [time, value] pairs, got shape {data.shape}"
    if not np.all(np.isfinite(data)):
        return "NaN or infinite values"
    bad = np.flatnonzero(np.diff(data[:, 0]) <= 0.0)
    if bad.size:
        k = int(bad[0]) + 1
        return (f"times must increase, but entry {k} (t = {data[k, 0]:g} s) does not come "
                f"after entry {k - 1} (t = {data[k - 1, 0]:g} s)")
    return None


class _Series:
    """A quantity constant (`value`) or linear between (time [s], value) samples, held at the
    first and last values outside them."""

    def __init__(self, key: str, value: float | None, series, unit: str) -> None:
        if (value is None) == (series is None):
            raise InputError(f"{key}: give {key.rsplit('.', 1)[-1]} or "
                             f"{key.rsplit('.', 1)[-1]}_series, not both or neither")
        if series is None:
            if not math.isfinite(value):
                raise InputError(f"{key} must be a finite number [{unit}], got {value}")
            self.time = np.zeros(1)
            self.value = np.array([float(value)])
        else:
            problem = series_problem(series)
            if problem is not None:
                raise InputError(f"{key}_series ([time [s], {unit}] pairs): {problem}")
            data = np.asarray(series, dtype=np.float64)
            self.time, self.value = data[:, 0].copy(), data[:, 1].copy()

    def at(self, t: float) -> float:
        if len(self.time) == 1:
            return float(self.value[0])
        return float(np.interp(t, self.time, self.value))


class FloodLoad:
    """Water of a flood on the free blocks (module doc): a field load for
    ModelBuilder.add_field_load.

    level [m] (constant) or level_series ((time [s], level [m]) pairs, time increasing):
    the water level upstream (on the -x side), and everywhere unless tailwater [m]
    (constant) is given: the level downstream (+x side), the head falling linearly across
    the structure. velocity [m/s] or velocity_series: the flow along +x (negative: along -x);
    water_density [kg/m^3]; drag_coefficient C_d [-]. Levels are heights along -gravity from
    the origin; none may lie below the lowest point of the free blocks (the ground they stand
    on). 3D models: the flow runs along the horizontal direction at `azimuth` [deg] from x
    towards y (upstream, downstream and the sign of the velocity as +x and -x in 2D); 2D
    models flow along x (azimuth 0). `name` prefixes the parameters in error messages (e.g.
    "loads.flood").
    """

    def __init__(self, *, level: float | None = None,
                 level_series: Sequence[Sequence[float]] | None = None,
                 velocity: float | None = None,
                 velocity_series: Sequence[Sequence[float]] | None = None,
                 tailwater: float | None = None,
                 water_density: float = 1000.0,
                 drag_coefficient: float = DRAG_COEFFICIENT,
                 azimuth: float = 0.0,
                 name: str = "flood") -> None:
        self.name = name
        self.level = _Series(f"{name}.level", level, level_series, "m")
        if velocity is None and velocity_series is None:
            velocity = 0.0
        self.velocity = _Series(f"{name}.velocity", velocity, velocity_series, "m/s")
        if not (math.isfinite(water_density) and water_density > 0.0):
            raise InputError(f"{name}.water_density must be a finite number > 0 [kg/m^3], "
                             f"got {water_density}")
        if not (math.isfinite(drag_coefficient) and drag_coefficient >= 0.0):
            raise InputError(f"{name}.drag_coefficient must be a finite number >= 0 [-] "
                             f"(1.4 for a square-ended pier), got {drag_coefficient}")
        if tailwater is not None and not math.isfinite(tailwater):
            raise InputError(f"{name}.tailwater must be a finite number [m], got {tailwater}")
        if not math.isfinite(azimuth):
            raise InputError(f"{name}.azimuth must be a finite number [deg], got {azimuth}")
        self.azimuth = float(azimuth)
        self.tailwater = None if tailwater is None else float(tailwater)
        self.water_density = float(water_density)
        self.drag_coefficient = float(drag_coefficient)
        self._scratch: tuple | None = None

    def heads(self, t: float) -> tuple[float, float]:
        """(upstream, downstream) water levels [m] at time t [s]."""
        h = self.level.at(t)
        return h, (h if self.tailwater is None else self.tailwater)

    def surface(self, s: np.ndarray, t: float, extent: tuple[float, float]) -> np.ndarray:
        """Piezometric head H(s) [m] at horizontal coordinates s [m] and time t [s], for a
        structure spanning `extent` = (s_a, s_b) [m] along the flow."""
        h_up, h_down = self.heads(t)
        return np.interp(s, extent, [h_up, h_down])

    def check(self, model) -> None:
        """InputError if this load cannot act on `model` (ModelBuilder.finalize calls it)."""
        if model.dim == 2 and self.azimuth != 0.0:
            raise InputError(f"{self.name}.azimuth is for 3D models; in 2D the river flows "
                             "along x (give a negative velocity for -x)")
        if model.has_round:  # its pressures integrate over polygon faces
            raise InputError(f"{self.name} acts on polygons (polyhedra); this model has discs "
                             "(spheres, capsules), which a flood does not load yet")
        if model.clustered:  # its kernels take a body's vertices for one convex block
            clusters = np.flatnonzero(np.bincount(model.contactor_body) > 1)
            raise InputError(f"{self.name} acts on convex blocks; {len(clusters)} block(s) "
                             f"are clusters (e.g. {model.body_name[clusters[0]]!r}), which a "
                             "flood does not load yet")
        up = self._up(model)
        self.along(model)
        free = np.flatnonzero(model.body_kind == BodyKind.FREE)
        if not free.size:
            return
        foot = min(float((model.vertices(b) @ up).min()) for b in free)
        levels = [("level", float(self.level.value.min()))]
        if self.tailwater is not None:
            levels.append(("tailwater", self.tailwater))
        for key, value in levels:
            if value < foot - 1e-9 * max(1.0, abs(foot)):
                series = "_series" if key == "level" and len(self.level.time) > 1 else ""
                raise InputError(
                    f"{self.name}.{key}{series}: a water level of {value:g} m is below the "
                    f"ground: the structure stands at {foot:g} m (the lowest point of its free "
                    f"blocks); levels are heights from the origin, give {key} >= {foot:g} m")

    @staticmethod
    def _up(model) -> np.ndarray:
        g = np.asarray(model.gravity, dtype=np.float64)
        norm = float(np.linalg.norm(g))
        if norm == 0.0:
            raise InputError("a flood needs gravity: hydrostatic pressure is rho_w g depth")
        return -g / norm

    def along(self, model) -> np.ndarray:
        """Unit vector of the flow's direction (horizontal: normal to gravity): +x for gravity
        along -y in 2D; in 3D (cos a, sin a, 0) at the azimuth a, made normal to gravity."""
        up = self._up(model)
        if model.dim == 2:
            return np.array([up[1], -up[0]])
        a = math.radians(self.azimuth)
        e = np.array([math.cos(a), math.sin(a), 0.0])
        e -= (e @ up) * up
        norm = float(np.linalg.norm(e))
        if norm < 1e-6:
            raise InputError(f"{self.name}.azimuth: the direction at {self.azimuth:g} degrees "
                             "is vertical under this gravity; give gravity along -z")
        return e / norm

    def add(self, model, q: np.ndarray, t: float, out: np.ndarray) -> None:
        """out [N, N, N m] per body (3D: force [N] and moment [N m], world frame) += the
        water's forces on the free blocks at coordinates q (model.body_q layout) and time
        t [s]."""
        up = self._up(model)
        g = float(np.linalg.norm(model.gravity))
        along = self.along(model)
        h_up, h_down = self.heads(t)
        s_a, s_b = 0.0, 1.0
        if h_down != h_up:
            extent = _extent if model.dim == 2 else flood3d.extent_3d
            s_a, s_b = extent(q, model.body_kind, model.body_vertex_start, model.vertex_local,
                              along)
        if model.dim == 3:
            self._add_3d(model, q, t, out, up, g, along, h_up, h_down, s_a, s_b)
            return
        hydrostatic_forces(q, model.body_kind, model.body_radius, model.body_vertex_start,
                           model.vertex_local, model.edge_normal_local, self.water_density * g,
                           up, h_up, h_down, s_a, s_b, out)
        u = self.velocity.at(t)
        pressure = 0.5 * self.water_density * self.drag_coefficient * u * u
        if pressure == 0.0:
            return
        n = len(model.vertex_local)
        if self._scratch is None or len(self._scratch[1]) < 6 * n:
            self._scratch = (np.empty((3 * n, 7)), np.empty(6 * n), np.empty(6 * n),
                             np.empty(6 * n, dtype=np.int64))
        drag_forces(q, model.body_kind, model.body_vertex_start, model.vertex_local,
                    model.edge_normal_local, pressure, math.copysign(1.0, u) * along, up,
                    h_up, h_down, s_a, s_b, *self._scratch, out)

    def _add_3d(self, model, q, t, out, up, g, along, h_up, h_down, s_a, s_b) -> None:
        """add() for 3D models: the kernels of saxum.flood3d."""
        geometry = (model.body_kind, model.body_radius, model.body_vertex_start,
                    model.vertex_local, model.body_face_start, model.face_vertex_start,
                    model.face_vertex, model.face_normal_local)
        flood3d.hydrostatic_forces_3d(q, *geometry, self.water_density * g, up, along, h_up,
                                      h_down, s_a, s_b, out)
        u = self.velocity.at(t)
        pressure = 0.5 * self.water_density * self.drag_coefficient * u * u
        if pressure == 0.0:
            return
        status = flood3d.drag_forces_3d(q, *geometry, pressure, math.copysign(1.0, u) * along,
                                        up, along, h_up, h_down, s_a, s_b, out)
        if status == flood3d.DRAG_OVERFLOW:
            raise RuntimeError(f"{self.name}: at t = {t:g} s a face's part exposed to the flow "
                               "was cut into more pieces than saxum.flood3d holds; its drag "
                               "would be incomplete")

    def forces(self, model, q: np.ndarray | None = None, t: float = 0.0) -> np.ndarray:
        """The water's forces alone [N, N, N m] per body, shape (bodies, 3) (3D: force [N] and
        moment [N m] in the world frame, shape (bodies, 6)), at q (default: the initial
        coordinates) and time t [s]."""
        out = np.zeros((model.body_count, model.dof))
        self.add(model, model.body_q0 if q is None else np.asarray(q, dtype=np.float64), t,
                 out)
        return out
