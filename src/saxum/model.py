"""The model: what the structure is (bodies, shapes, materials, contact laws, loads).

A `ModelBuilder` collects blocks in Python lists; `finalize()` freezes them into a `Model` of flat
structure-of-arrays (one array per attribute, `body_<field>`), which the compiled kernels read.
Where the structure is now (positions, velocities, impulses) lives in `saxum.state.State`.

2D conventions: generalized coordinates q = (x, y, theta) of the centre of mass [m, m, rad],
velocities v = (vx, vy, omega) [m/s, m/s, rad/s]; a block has unit out-of-plane depth, so its
density [kg/m^3] times its area [m^2] is its mass per metre of depth [kg].

3D conventions (`ModelBuilder(dim=3)`): a block is a convex polyhedron whose body frame is its
principal frame (saxum.geometry3d), so its inertia tensor there is diagonal and constant;
q = (x, y, z, qw, qx, qy, qz): the centre of mass [m] and the unit quaternion of the body-to-world
rotation; v = (vx, vy, vz, wx, wy, wz): the velocity of the centre of mass in the world frame
[m/s] and the angular velocity in the BODY frame [rad/s] (NSCD.md), so that M stays diagonal.
"""

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Protocol

import numpy as np

from .bodies.fe import FEBodies, build_fe_bodies
from .errors import InputError, plain
from .fe.material import Elastic
from .fe.mesh import Mesh
from .geometry2d import normalize_polygon, polygon_properties
from .geometry3d import (
    Polyhedron,
    PolyhedronProperties,
    convex_polyhedron,
    polyhedron_properties,
    quaternion_from_matrix,
    rotation_matrix,
)
from .laws import ContactLaw, NoContact, Parameter

__all__ = ["DENSITY_RANGE", "BodyKind", "FieldLoad", "Model", "ModelBuilder", "Shape",
           "capsule_axis", "capsule_properties", "spherocylinder_properties"]

DENSITY_RANGE = (1.0, 1.0e5)
"""Densities a free block may have [kg/m^3]: masonry is 1000-3000 and the densest metal
(osmium) 22 600; below 1 (lighter than air) or above 1e5 a value is a unit mistake, and 1e300 or
1e-300 would overflow or underflow the masses and the Delassus operator."""

Motion = Callable[[float], Sequence[float]]
"""Imposed velocity of a driven body: t [s] -> (vx [m/s], vy [m/s], omega [rad/s]) in 2D,
(vx, vy, vz [m/s], wx, wy, wz [rad/s]) in 3D with the angular velocity in the world frame."""
TimeVector = Callable[[float], Sequence[float]]


class FieldLoad(Protocol):
    """A load that depends on where the blocks are (e.g. water: saxum.flood.FloodLoad).

    `add` runs once per step over all bodies at once (a compiled kernel, no Python loop over
    bodies): out [N, N, N m] per body (2D; in 3D the 6 components of force and torque) +=
    the load at coordinates q (model.body_q layout: 3 columns in 2D, 7 in 3D) and time t [s].
    The time loop calls it explicitly, at the beginning-of-step configuration and at
    t_i + theta h (saxum.simulation). `check` raises InputError if the load cannot act on
    the model (ModelBuilder.finalize calls it).
    """

    def check(self, model: "Model") -> None: ...

    def add(self, model: "Model", q: np.ndarray, t: float, out: np.ndarray) -> None: ...


class BodyKind(IntEnum):
    """FREE bodies move under forces and contacts; FIXED never move; DRIVEN follow a Motion;
    DEFORMABLE blocks are finite-element meshes (saxum.bodies.fe), whose body row holds their
    co-rotated frame."""

    FREE = 0
    FIXED = 1
    DRIVEN = 2
    DEFORMABLE = 3


class Shape(IntEnum):
    """What the narrow phase takes a body's geometry to be: POLYGON (a convex polygon, in 3D a
    convex polyhedron: its vertices, edges and faces) or ROUND (a disc, in 3D a sphere, of
    radius Model.body_round_radius about its centre of mass; its vertices are the corners of
    its bounding square (cube), which only the broad phase and plots of polygons read) or
    CAPSULE (2D: a segment with round ends of radius Model.body_round_radius, the stadium; its
    vertices are its bounding rectangle, whose first edge runs along the segment; 3D: the
    spherocylinder, a cylinder with hemispherical ends, its segment along the body frame's z
    axis and its vertices its bounding box)."""

    POLYGON = 0
    ROUND = 1
    CAPSULE = 2


@dataclass(frozen=True)
class Model:
    """A frozen model as structure-of-arrays. Build it with `ModelBuilder`. Shapes are given
    for 2D; 3D differences are noted (and 3D adds the face and edge arrays at the end)."""

    body_count: int
    body_name: tuple[str, ...]
    """Block names, shape [body_count], used in messages and outputs."""
    body_kind: np.ndarray
    """BodyKind, shape [body_count], int8."""
    body_group: np.ndarray
    """Index into `group_names`, shape [body_count], int32."""
    body_density: np.ndarray
    """Density [kg/m^3], shape [body_count], float64 (0 for fixed and driven bodies)."""
    body_mass: np.ndarray
    """Mass per metre of depth [kg] (3D: mass [kg]), shape [body_count], float64."""
    body_inertia: np.ndarray
    """Polar moment of inertia about the centre of mass [kg m^2], shape [body_count], float64
    (3D: principal moments J_1, J_2, J_3 [kg m^2], shape [body_count, 3])."""
    body_inv_mass: np.ndarray
    """Diagonal of M^-1 per dof [1/kg, 1/kg, 1/(kg m^2)], shape [body_count, dof]; 0 unless
    FREE."""
    body_q0: np.ndarray
    """Initial coordinates (x, y, theta) [m, m, rad], shape [body_count, 3], float64 (3D:
    (x, y, z, qw, qx, qy, qz), shape [body_count, 7])."""
    body_radius: np.ndarray
    """Largest distance from centre of mass to a vertex [m], shape [body_count], float64."""
    body_size: np.ndarray
    """Square root of the area (3D: cube root of the volume) [m], shape [body_count]."""
    body_vertex_start: np.ndarray
    """Body b owns vertices body_vertex_start[b]:body_vertex_start[b+1], shape [body_count+1]."""
    vertex_local: np.ndarray
    """Vertices in the body frame [m], shape [vertex_count, dim], float64 (2D: CCW)."""
    edge_normal_local: np.ndarray
    """2D: outward unit normal of the edge from vertex k to the next, body frame, shape
    [vertex_count, 2], float64 (3D: empty)."""
    edge_length: np.ndarray
    """2D: length of the edge from vertex k to the next [m], shape [vertex_count], float64."""
    body_motion: np.ndarray
    """Index into `motions` for DRIVEN bodies, -1 otherwise, shape [body_count], int32."""
    motions: tuple[Motion, ...]
    group_names: tuple[str, ...]
    group_law: np.ndarray
    """Law index for each pair of groups, -1 if none (no contacts: NO_CONTACT, or no free
    block in either group), shape [group_count, group_count], int32."""
    laws: tuple[ContactLaw, ...]
    law_kind: np.ndarray
    """LawKind per law, shape [law_count], int8."""
    law_friction: np.ndarray
    """Coulomb coefficient mu [-], shape [law_count], float64."""
    law_restitution: np.ndarray
    """Newton restitution e_n [-], shape [law_count], float64."""
    law_points: np.ndarray
    """Contact points of a face-to-face contact (ContactLaw.points), shape [law_count], int32."""
    law_parameter: np.ndarray
    """Joint law parameters, columns saxum.laws.Parameter (k_n, k_t [Pa/m], c_n, eta [Pa s/m],
    f_t, cohesion [Pa], G_I, G_II [J/m^2]), shape [law_count, len(Parameter)], float64."""
    law_initial_gap: np.ndarray
    """The _g0 laws (ContactLaw.initial_gap), shape [law_count], bool."""
    gravity: np.ndarray
    """Gravitational acceleration [m/s^2], shape [2], float64."""
    accelerations: tuple[TimeVector, ...] = ()
    """Uniform accelerations t -> (ax, ay) [m/s^2] applied as m a to every free body."""
    forces: tuple[tuple[np.ndarray, TimeVector], ...] = ()
    """(body indices, t -> (fx [N], fy [N], torque [N m])) applied to each listed body."""
    field_loads: tuple[FieldLoad, ...] = ()
    """Loads that depend on the blocks' positions (FieldLoad), e.g. a flood."""
    dim: int = 2
    dof: int = 3
    body_face_start: np.ndarray = field(default_factory=lambda: np.zeros(1, np.int32))
    """3D: body b owns faces body_face_start[b]:body_face_start[b+1], shape [body_count+1]."""
    face_vertex_start: np.ndarray = field(default_factory=lambda: np.zeros(1, np.int32))
    """3D: face f has the vertices face_vertex[face_vertex_start[f]:face_vertex_start[f+1]],
    shape [face_count+1], int32."""
    face_vertex: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    """3D: indices into vertex_local, CCW seen from outside, per face, int32."""
    face_normal_local: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    """3D: outward unit normal of each face in the body frame, shape [face_count, 3]."""
    body_edge_start: np.ndarray = field(default_factory=lambda: np.zeros(1, np.int32))
    """3D: body b owns edges body_edge_start[b]:body_edge_start[b+1], shape [body_count+1]."""
    edge_vertex: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int32))
    """3D: the two vertices (indices into vertex_local) of each edge, shape [edge_count, 2]."""
    edge_face: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int32))
    """3D: the faces left and right of each edge (from its first vertex to its second, seen
    from outside), indices into the face arrays, shape [edge_count, 2], int32."""
    fe: "FEBodies | None" = None
    """The deformable blocks' meshes and matrices (saxum.bodies.fe), None if there are none."""
    body_shape: np.ndarray | None = None
    """Shape per body (POLYGON, ROUND or CAPSULE), shape [body_count], int8 (default: all
    POLYGON)."""
    body_round_radius: np.ndarray | None = None
    """Radius of a ROUND body, of a CAPSULE's ends [m] (0 for polygons), shape [body_count],
    float64."""
    max_vertices: int = field(init=False)
    has_round: bool = field(init=False)
    """Some body is a disc (sphere) or a capsule: detection runs the round pairs' kernel."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "max_vertices", int(np.diff(self.body_vertex_start).max()))
        if self.body_shape is None:
            object.__setattr__(self, "body_shape", np.zeros(self.body_count, dtype=np.int8))
        if self.body_round_radius is None:
            object.__setattr__(self, "body_round_radius", np.zeros(self.body_count))
        object.__setattr__(self, "has_round", bool((self.body_shape != Shape.POLYGON).any()))

    def body(self, name: str) -> int:
        """Index of the body called `name`."""
        try:
            return self.body_name.index(name)
        except ValueError:
            raise KeyError(f"no body named {name!r}") from None

    def vertices(self, b: int, q: np.ndarray | None = None) -> np.ndarray:
        """World vertices [m] of body b at coordinates q (default: initial), shape (n, dim)."""
        return body_vertices((self.body_q0 if q is None else q)[b],
                             self.vertex_local[self.body_vertex_start[b]:
                                               self.body_vertex_start[b + 1]])


def body_vertices(qb: np.ndarray, local: np.ndarray) -> np.ndarray:
    """World vertices [m], shape (n, dim), of a body at coordinates qb ((x, y, theta), or in 3D
    (x, y, z, qw, qx, qy, qz)) from its vertices in the body frame `local` [m]."""
    if local.shape[1] == 3:
        return qb[:3] + local @ rotation_matrix(qb[3:]).T
    x, y, th = qb
    c, s = math.cos(th), math.sin(th)
    return np.column_stack((x + c * local[:, 0] - s * local[:, 1],
                            y + s * local[:, 0] + c * local[:, 1]))


def drawn_outlines(vertex_start: np.ndarray, vertex_local: np.ndarray,
                   round_radius: np.ndarray | None, sides: int = 48,
                   shape: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(vertex_start, vertex_local [m]) of the polygons that draw 2D bodies (plots, VTK): a
    disc's (round_radius > 0, as Model.body_round_radius; None: no discs) bounding square is
    replaced by the regular polygon of `sides` sides inscribed in its circle, a capsule's
    (shape, as Model.body_shape, CAPSULE) bounding rectangle by its stadium, each end a half
    of that polygon."""
    if round_radius is None or not (round_radius > 0.0).any():
        return vertex_start, vertex_local
    turn = 2.0 * np.pi * np.arange(sides) / sides
    circle = np.column_stack((np.cos(turn), np.sin(turn)))
    rings = []
    for b, r in enumerate(round_radius):
        local = vertex_local[vertex_start[b]:vertex_start[b + 1]]
        if shape is not None and shape[b] == Shape.CAPSULE:
            along = local[1] - local[0]  # the bounding rectangle's first edge: the axis
            length = float(np.hypot(*along))
            t = along / length
            half = 0.5 * length - r
            ends = np.linspace(-0.5 * np.pi, 0.5 * np.pi, sides // 2 + 1)
            arc = r * (np.outer(np.cos(ends), t) + np.outer(np.sin(ends), (-t[1], t[0])))
            rings.append(np.concatenate((half * t + arc, -half * t - arc)))
        else:
            rings.append(circle * r if r > 0.0 else local)
    start = np.zeros(len(rings) + 1, dtype=vertex_start.dtype)
    start[1:] = np.cumsum([len(ring) for ring in rings])
    return start, np.concatenate(rings)


def drawn_polyhedra(m) -> dict[str, np.ndarray]:
    """The 3D geometry that draws bodies (plots, VTK, viewer) from a mapping m of the Model's
    arrays (a results file's /model): body_vertex_start, vertex_local [m], body_face_start,
    face_vertex_start, face_vertex, each sphere's (m["body_round_radius"] > 0) bounding cube
    replaced by a polyhedron inscribed in it (8 rings of 16 vertices and the poles), a 3D
    capsule's (m["body_shape"] CAPSULE) bounding box by that polyhedron cut at its equator,
    the halves moved apart along the body z axis to the ends of its segment (its
    cylinder drawn as the band between them)."""
    keys = ("body_vertex_start", "vertex_local", "body_face_start", "face_vertex_start",
            "face_vertex")
    radius = m.get("body_round_radius")
    if radius is None or not (radius > 0.0).any():
        return {k: m[k] for k in keys}
    rings, around = 8, 16
    polar = np.pi * np.arange(1, rings + 1) / (rings + 1)
    turn = 2.0 * np.pi * np.arange(around) / around
    sin = np.sin(polar)
    unit = np.concatenate([[[0.0, 0.0, 1.0]], np.column_stack((
        np.outer(sin, np.cos(turn)).ravel(), np.outer(sin, np.sin(turn)).ravel(),
        np.repeat(np.cos(polar), around))), [[0.0, 0.0, -1.0]]])

    def ring(r: int, k: int) -> int:
        """Index in unit of vertex k of ring r (from the north pole, 0)."""
        return 1 + r * around + k % around

    south = len(unit) - 1
    # faces counter-clockwise seen from outside: caps of triangles, bands of quads
    unit_faces = ([[0, ring(0, k), ring(0, k + 1)] for k in range(around)]
                  + [[ring(r, k), ring(r + 1, k), ring(r + 1, k + 1), ring(r, k + 1)]
                     for r in range(rings - 1) for k in range(around)]
                  + [[south, ring(rings - 1, k + 1), ring(rings - 1, k)] for k in range(around)])
    vs, fs, fvs = m["body_vertex_start"], m["body_face_start"], m["face_vertex_start"]
    local, rings_of = [], []
    capsule = m.get("body_shape", np.zeros(len(radius))) == Shape.CAPSULE
    for b, r in enumerate(radius):
        if r > 0.0:
            # a capsule's segment: its bounding box's half extent along z less r
            half = m["vertex_local"][vs[b]:vs[b + 1], 2].max() - r if capsule[b] else 0.0
            local.append(unit * r + np.outer(np.sign(unit[:, 2]), (0.0, 0.0, half)))
            rings_of.append([np.array(f) for f in unit_faces])
        else:
            local.append(m["vertex_local"][vs[b]:vs[b + 1]])
            rings_of.append([m["face_vertex"][fvs[f]:fvs[f + 1]] - vs[b]
                             for f in range(fs[b], fs[b + 1])])
    vertex_start = np.concatenate([[0], np.cumsum([len(v) for v in local])]).astype(np.int32)
    faces = [f + vertex_start[b] for b, body in enumerate(rings_of) for f in body]
    return {"body_vertex_start": vertex_start, "vertex_local": np.concatenate(local),
            "body_face_start": np.concatenate([[0], np.cumsum([len(f) for f in rings_of])]
                                              ).astype(np.int32),
            "face_vertex_start": np.concatenate([[0], np.cumsum([len(f) for f in faces])]
                                                ).astype(np.int32),
            "face_vertex": np.concatenate(faces).astype(np.int32)}


def capsule_axis(model: "Model", b: int) -> tuple[float, float]:
    """A 2D capsule's segment at the start: its direction from the x axis [rad] and its
    length [m] (its bounding rectangle's first edge runs along it, 2 r longer)."""
    if model.dim != 2:
        raise InputError(f"capsule_axis is for 2D capsules; {model.body_name[b]!r} is in a "
                         "3D model (its axis is the body frame's z axis)")
    start = model.body_vertex_start[b]
    e = model.vertex_local[start + 1] - model.vertex_local[start]
    return math.atan2(e[1], e[0]), math.hypot(e[0], e[1]) - 2.0 * float(
        model.body_round_radius[b])


def capsule_properties(length: float, radius: float) -> tuple[float, float]:
    """(area [m^2], polar moment of area about the centre [m^4]) of a capsule: a segment of
    `length` L [m] with round ends of `radius` r [m]: a rectangle L x 2r and two half discs.
    A = 2 r L + pi r^2; J = rectangle (2 r L) (L^2 + 4 r^2) / 12 + the two half discs moved by
    the parallel-axis theorem from their centroids, 4 r / (3 pi) beyond the rectangle's ends
    (Beer and Johnston, Vector Mechanics for Engineers: Statics, table of centroids and
    moments of inertia): pi r^2 (r^2 / 2 + L^2 / 4 + 4 r L / (3 pi))."""
    rectangle = 2.0 * radius * length
    disc = math.pi * radius * radius
    polar = (rectangle * (length * length + 4.0 * radius * radius) / 12.0
             + disc * (0.5 * radius * radius + 0.25 * length * length
                       + 4.0 * radius * length / (3.0 * math.pi)))
    return rectangle + disc, polar


def spherocylinder_properties(length: float, radius: float) -> tuple[float, float, float]:
    """(volume [m^3], axial, transverse second moment of volume about the centre [m^5]) of a
    3D capsule: a cylinder of `length` L [m] and `radius` r [m] with hemispherical ends;
    times the density, its mass and principal moments of inertia. With V_c = pi r^2 L and
    V_s = 4/3 pi r^3 (the two ends together, a sphere): V = V_c + V_s, J_axis = V_c r^2 / 2
    + 2/5 V_s r^2, J_across = V_c (L^2 / 12 + r^2 / 4) + V_s (2/5 r^2 + L^2 / 4 + 3 L r / 8),
    each hemisphere's moment about its base's diameter (2/5 of its mass r^2) moved by the
    parallel-axis theorem to its centroid, 3 r / 8 from its base, then to the centre (J. L.
    Meriam, L. G. Kraige, Engineering Mechanics: Dynamics, table D/4, properties of
    homogeneous solids: circular cylinder, hemisphere)."""
    cylinder = math.pi * radius * radius * length
    sphere = 4.0 / 3.0 * math.pi * radius**3
    axial = 0.5 * cylinder * radius * radius + 0.4 * sphere * radius * radius
    across = (cylinder * (length * length / 12.0 + 0.25 * radius * radius)
              + sphere * (0.4 * radius * radius + 0.25 * length * length
                          + 0.375 * length * radius))
    return cylinder + sphere, axial, across


def _shape_of(block: "_Block") -> Shape:
    if block.length > 0.0:
        return Shape.CAPSULE
    return Shape.ROUND if block.round_radius > 0.0 else Shape.POLYGON


@dataclass
class _Block:
    name: str
    vertices: np.ndarray | Polyhedron
    density: float
    group: str
    kind: BodyKind
    motion: Motion | None
    material: Elastic | None = None
    mesh_size: float | Mesh | None = None
    """The element size [m] of a deformable block, or its given mesh."""
    round_radius: float = 0.0
    """> 0: a disc (sphere) of this radius [m] whose vertices are its bounding square (cube), or
    with `length` > 0 a capsule's."""
    length: float = 0.0
    """> 0: a capsule whose segment is this long [m], vertices its bounding rectangle."""
    axes: np.ndarray | None = None
    """A 3D capsule's body frame: columns two unit vectors across it and its axis."""


class ModelBuilder:
    """Collects blocks, contact laws and loads, then `finalize()`s them into a `Model`.

    >>> b = ModelBuilder()
    >>> ground = b.add_block([(-1, -0.1), (1, -0.1), (1, 0), (-1, 0)], kind=BodyKind.FIXED,
    ...                      group="support")
    >>> stone = b.add_block([(0, 0), (0.2, 0), (0.2, 0.4), (0, 0.4)], density=2500.0)
    >>> b.set_law("block", "support", ContactLaw(friction=0.6))
    >>> b.set_law("block", "block", ContactLaw(friction=0.6))
    >>> model = b.finalize()
    >>> round(float(model.body_mass[stone]), 6)
    200.0

    dim=3 builds a 3D model of convex polyhedra (gravity default (0, 0, -9.81) m/s^2);
    add_block then takes (x, y, z) points and the block is their convex hull.
    """

    def __init__(self, *, gravity: Sequence[float] | None = None, dim: int = 2) -> None:
        if dim not in (2, 3):
            raise InputError(f"dim must be 2 or 3, got {dim}")
        self.dim = dim
        self._blocks: list[_Block] = []
        self._laws: dict[frozenset[str], ContactLaw | NoContact] = {}
        self._accelerations: list[TimeVector] = []
        self._forces: list[tuple[np.ndarray, TimeVector]] = []
        self._field_loads: list[FieldLoad] = []
        if gravity is None:
            gravity = (0.0, -9.81) if dim == 2 else (0.0, 0.0, -9.81)
        g = np.array(gravity, dtype=np.float64)
        if g.shape != (dim,) or not np.all(np.isfinite(g)):
            names = "(gx, gy)" if dim == 2 else "(gx, gy, gz)"
            raise InputError(f"gravity must be {dim} finite numbers {names} [m/s^2], got "
                             f"{plain(gravity)}")
        self._gravity = g

    @property
    def body_count(self) -> int:
        return len(self._blocks)

    @property
    def gravity(self) -> tuple[float, ...]:
        """Gravity (gx, gy) (3D: (gx, gy, gz)) [m/s^2] of the model being built."""
        return tuple(float(g) for g in self._gravity)

    @property
    def groups(self) -> list[str]:
        """The groups of the blocks added so far, sorted."""
        return sorted({blk.group for blk in self._blocks})

    def add_block(
        self,
        vertices,
        *,
        density: float = 0.0,
        group: str = "block",
        kind: BodyKind = BodyKind.FREE,
        motion: Motion | None = None,
        name: str | None = None,
        material: Elastic | None = None,
        mesh_size: float | None = None,
        mesh: Mesh | None = None,
    ) -> int:
        """Add a convex block; returns its body index.

        vertices: 2D: (x, y) pairs [m] in world coordinates, either orientation, of a convex
        polygon; 3D: (x, y, z) points [m] whose convex hull is the block (a point strictly
        inside the hull means a non-convex block, which is refused).
        density [kg/m^3]: required for FREE blocks, within DENSITY_RANGE; ignored otherwise.
        motion: for DRIVEN blocks, t [s] -> velocity of the centre of mass (see `Motion`).
        material: an elastic material (saxum.fe.Elastic) makes the block DEFORMABLE, a
        finite-element mesh (triangles; 3D tetrahedra) of elements of about mesh_size [m]
        (default: 2D a fifth of the block's smallest side, 3D half its shortest edge) whose
        density is the material's, or the given `mesh` (saxum.fe.Mesh.from_cells(nodes [m],
        cells): linear triangles, 3D tetrahedra, in world coordinates), which must fill the
        block (saxum.fe.mesh.fit_mesh).
        """
        index = len(self._blocks)
        name = name if name is not None else f"block {index}"
        kind = BodyKind(kind)
        if self.dim == 3:
            verts = convex_polyhedron(vertices, name=name)
        else:
            verts = normalize_polygon(vertices, name=name)
        if material is not None:
            if kind != BodyKind.FREE:
                raise InputError(f"{name}: only a free block can be deformable (material=); "
                                 f"this one is {kind.name}")
            kind, density = BodyKind.DEFORMABLE, material.density
        elif mesh_size is not None or mesh is not None:
            raise InputError(f"{name}: mesh_size and mesh are for deformable blocks; give "
                             "material=")
        if mesh is not None and mesh_size is not None:
            raise InputError(f"{name}: give mesh_size or mesh, not both")
        low, high = DENSITY_RANGE
        massive = kind in (BodyKind.FREE, BodyKind.DEFORMABLE)
        if massive and not (math.isfinite(density) and density > 0.0):
            raise InputError(f"{name}: density must be a finite number > 0 [kg/m^3], got {density}")
        if massive and not low <= density <= high:
            raise InputError(f"{name}: density {density:g} kg/m^3 is outside {low:g} .. {high:g} "
                             "kg/m^3 (masonry is 1000 .. 3000 kg/m^3; is it in kg/m^3?)")
        if kind == BodyKind.DRIVEN and motion is None:
            raise InputError(f"{name}: a DRIVEN block needs motion=t -> (vx, vy, omega)")
        if kind != BodyKind.DRIVEN and motion is not None:
            raise InputError(
                f"{name}: motion is only used by DRIVEN blocks, this one is {kind.name}"
            )
        if not group:
            raise InputError(f"{name}: group must be a non-empty name")
        density = density if massive else 0.0
        self._blocks.append(_Block(name, verts, float(density), group, kind, motion, material,
                                   mesh if mesh is not None else mesh_size))
        return index

    def add_disc(self, centre: Sequence[float], radius: float, *, density: float = 0.0,
                 group: str = "block", kind: BodyKind = BodyKind.FREE,
                 motion: Motion | None = None, name: str | None = None) -> int:
        """Add a disc (2D) of `radius` [m] centred at (x, y) [m]; returns its body index.
        Mass rho pi r^2 [kg per metre of depth], polar moment m r^2 / 2 [kg m^2]; density,
        group, kind, motion, name as in add_block. Discs touch polygons and discs with the
        laws of their groups, one contact point per pair (saxum.detection.round)."""
        return self._add_round(centre, radius, 2, "add_disc", density=density, group=group,
                               kind=kind, motion=motion, name=name)

    def add_sphere(self, centre: Sequence[float], radius: float, *, density: float = 0.0,
                   group: str = "block", kind: BodyKind = BodyKind.FREE,
                   motion: Motion | None = None, name: str | None = None) -> int:
        """Add a sphere (3D) of `radius` [m] centred at (x, y, z) [m]; returns its body index.
        Mass rho 4/3 pi r^3 [kg], principal moments 2/5 m r^2 [kg m^2]; the other arguments as
        in add_block (add_disc)."""
        return self._add_round(centre, radius, 3, "add_sphere", density=density, group=group,
                               kind=kind, motion=motion, name=name)

    def add_capsule(self, centre: Sequence[float], length: float, radius: float, *,
                    angle: float = 0.0, axis: Sequence[float] | None = None,
                    density: float = 0.0, group: str = "block",
                    kind: BodyKind = BodyKind.FREE, motion: Motion | None = None,
                    name: str | None = None) -> int:
        """Add a capsule (2D, LMGC90's JONCx): a segment of `length` L [m] centred at (x, y)
        [m] and turned by `angle` [rad] from the x axis, with round ends of `radius` r [m] (the
        stadium, L + 2 r long and 2 r wide); returns its body index. Mass rho (2 r L + pi r^2)
        [kg per metre of depth], polar moment saxum.model.capsule_properties; the other
        arguments as in add_block. Capsules touch polygons, discs and capsules with the laws
        of their groups (saxum.detection.round).

        3D (LMGC90's CYLND, the spherocylinder): a cylinder of `length` L and `radius` r
        centred at (x, y, z) [m] along `axis` (a direction of any length; default x) with
        hemispherical ends; `angle` is for 2D only. Mass rho (pi r^2 L + 4/3 pi r^3) [kg],
        principal moments saxum.model.spherocylinder_properties; it touches polyhedra,
        spheres and capsules."""
        name = name if name is not None else f"block {len(self._blocks)}"
        c = np.asarray(centre, dtype=np.float64)
        if c.shape != (self.dim,) or not np.all(np.isfinite(c)):
            raise InputError(f"{name}: the centre must be {self.dim} finite coordinates [m], "
                             f"got {plain(centre)}")
        if self.dim == 2 and axis is not None:
            raise InputError(f"{name}: axis is for 3D capsules; in 2D give angle= [rad]")
        if self.dim == 3 and angle != 0.0:
            raise InputError(f"{name}: angle is for 2D capsules; in 3D give axis=(x, y, z)")
        sizes = {"length": length, "radius": radius, "angle": angle}
        round_body = "a disc: add_disc" if self.dim == 2 else "a sphere: add_sphere"
        for what, value in sizes.items():
            if not math.isfinite(float(value)) or (what != "angle" and not float(value) > 0.0):
                must = "a finite angle [rad]" if what == "angle" else "a finite length > 0 [m]"
                raise InputError(f"{name}: the capsule's {what} must be {must}, got "
                                 f"{plain(value)}" + (f" ({round_body})" if what == "length"
                                                      else ""))
        half, r = 0.5 * float(length), float(radius)
        if self.dim == 3:
            return self._add_capsule_3d(c, half, r, (1.0, 0.0, 0.0) if axis is None else axis,
                                        density=density, group=group, kind=kind,
                                        motion=motion, name=name)
        t = np.array([math.cos(angle), math.sin(angle)])
        n = np.array([-t[1], t[0]])
        # CCW, the first edge along the segment (saxum.detection.round reads it so)
        corners = [c + a * (half + r) * t + b * r * n for a, b in ((-1, -1), (1, -1), (1, 1),
                                                                   (-1, 1))]
        index = self.add_block(corners, density=density, group=group, kind=kind,
                               motion=motion, name=name)
        self._blocks[index].round_radius, self._blocks[index].length = r, float(length)
        return index

    def _add_capsule_3d(self, centre: np.ndarray, half: float, r: float, axis, **block) -> int:
        """A 3D capsule as a block whose vertices are its bounding box (along t, the unit
        axis, and n1, n2 = t x n1 across it, n1 the world axis least along t made normal to
        t), its body frame (n1, n2, t)."""
        t = np.asarray(axis, dtype=np.float64)
        norm = float(np.linalg.norm(t)) if t.shape == (3,) else 0.0
        if not (math.isfinite(norm) and norm > 0.0):
            raise InputError(f"{block['name']}: the capsule's axis must be a non-zero direction "
                             f"(x, y, z), got {plain(axis)}")
        t = t / norm
        n1 = np.eye(3)[int(np.argmin(np.abs(t)))]
        n1 = n1 - (n1 @ t) * t
        n1 /= np.linalg.norm(n1)
        axes = np.column_stack((n1, np.cross(t, n1), t))
        corners = [centre + axes @ (a * r, b * r, d * (half + r))
                   for a in (-1, 1) for b in (-1, 1) for d in (-1, 1)]
        index = self.add_block(corners, **block)
        blk = self._blocks[index]
        blk.round_radius, blk.length, blk.axes = r, 2.0 * half, axes
        return index

    def add_plane(self, point: Sequence[float], normal: Sequence[float],
                  half_size: float | Sequence[float], *, thickness: float | None = None,
                  group: str = "ground", kind: BodyKind = BodyKind.FIXED,
                  motion: Motion | None = None, name: str | None = None) -> int:
        """Add a ground plane (LMGC90's JONCx in 2D, PLANx in 3D) as a slab: a FIXED (or
        DRIVEN) block whose face through `point` [m] has the outward `normal` (any length),
        half_size [m] its half length along the face (3D: (a, b), its half sizes along t1 =
        the world axis least along n made normal to n, and t2 = n x t1), `thickness` [m]
        behind the face (default: the smaller half size / 10). Returns its body index; it
        meets blocks, discs and spheres as any block does."""
        name = name if name is not None else f"block {len(self._blocks)}"
        kind = BodyKind(kind)
        if kind == BodyKind.FREE or kind == BodyKind.DEFORMABLE:
            raise InputError(f"{name}: a plane is a support, FIXED or DRIVEN, not {kind.name}")
        n = np.asarray(normal, dtype=np.float64)
        half = np.atleast_1d(np.asarray(half_size, dtype=np.float64))
        p = np.asarray(point, dtype=np.float64)
        length = float(np.linalg.norm(n)) if n.shape == (self.dim,) else 0.0
        if not (math.isfinite(length) and length > 0.0) or p.shape != (self.dim,) \
                or not np.all(np.isfinite(p)):
            raise InputError(f"{name}: a plane needs a point and a non-zero normal of "
                             f"{self.dim} finite coordinates each, got point {plain(point)}, "
                             f"normal {plain(normal)}")
        if half.shape != (self.dim - 1,) or not np.all(np.isfinite(half) & (half > 0.0)):
            raise InputError(f"{name}: half_size must be {self.dim - 1} length(s) > 0 [m] "
                             f"along the plane, got {plain(half_size)}")
        t = 0.1 * float(half.min()) if thickness is None else float(thickness)
        if not (math.isfinite(t) and t > 0.0):
            raise InputError(f"{name}: thickness must be a length > 0 [m], got {thickness}")
        n = n / length
        axis = np.eye(self.dim)[int(np.argmin(np.abs(n)))]
        t1 = axis - (axis @ n) * n
        t1 /= np.linalg.norm(t1)
        if self.dim == 2:
            corners = [p + s * half[0] * t1 - d * n for s, d in ((-1, 0), (1, 0), (1, t),
                                                                 (-1, t))]
        else:
            t2 = np.cross(n, t1)
            corners = [p + a * half[0] * t1 + b * half[1] * t2 - d * n
                       for a in (-1, 1) for b in (-1, 1) for d in (0.0, t)]
        return self.add_block(corners, group=group, kind=kind, motion=motion, name=name)

    def _add_round(self, centre, radius, dim: int, call: str, **block) -> int:
        """A disc (dim 2) or sphere (dim 3) as a block whose vertices are its bounding square
        (cube) and whose round_radius is `radius`."""
        name = block["name"] if block["name"] is not None else f"block {len(self._blocks)}"
        if self.dim != dim:
            other = "add_sphere" if dim == 2 else "add_disc"
            raise InputError(f"{name}: {call} is for {dim}D models; this one is {self.dim}D "
                             f"(use {other})")
        c = np.asarray(centre, dtype=np.float64)
        if c.shape != (dim,) or not np.all(np.isfinite(c)):
            raise InputError(f"{name}: the centre must be {dim} finite coordinates [m], got "
                             f"{plain(centre)}")
        r = float(radius)
        if not (math.isfinite(r) and r > 0.0):
            raise InputError(f"{name}: the radius must be a finite length > 0 [m], got "
                             f"{plain(radius)}")
        square = [(-r, -r), (r, -r), (r, r), (-r, r)]
        corners = np.array(square if dim == 2 else [(x, y, z) for x, y in square for z in (-r, r)])
        index = self.add_block(c + corners, **{**block, "name": name})
        self._blocks[index].round_radius = r
        return index

    def set_material(self, group: str, material: Elastic, mesh_size: float | None = None) -> int:
        """Make every free block of `group` deformable: a finite-element mesh of elements of
        about mesh_size [m] (default as in add_block) of `material` (saxum.fe.Elastic), whose
        density replaces the block's. Returns how many blocks."""
        if not isinstance(material, Elastic):
            raise InputError(f"materials: group {group!r} needs a saxum.fe.Elastic material, "
                             f"got {material!r}")
        if group not in self.groups:
            raise InputError(f"materials names group {group!r}, which no block has; groups: "
                             f"{self.groups}")
        changed = 0
        for block in self._blocks:
            if block.group == group and block.kind in (BodyKind.FREE, BodyKind.DEFORMABLE):
                if block.round_radius > 0.0:
                    raise InputError(f"materials: group {group!r} has the disc (sphere, "
                                     "capsule) "
                                     f"{block.name!r}, which cannot be deformable; put it in "
                                     "another group")
                block.kind, block.density = BodyKind.DEFORMABLE, material.density
                block.material, block.mesh_size = material, mesh_size
                changed += 1
        if not changed:
            raise InputError(f"materials: group {group!r} has no free block to make deformable")
        return changed

    def drive(self, name: str, motion: Motion) -> int:
        """Make the FIXED block called `name` (a support) DRIVEN by motion: t [s] -> velocity
        of its centre of mass (see `Motion`), e.g. a settlement; returns its index."""
        index = self.index(name)
        block = self._blocks[index]
        if block.kind != BodyKind.FIXED:
            raise InputError(f"{name}: only a FIXED block (a support) can be driven, this one "
                             f"is {block.kind.name}")
        block.kind, block.motion = BodyKind.DRIVEN, motion
        return index

    def index(self, name: str) -> int:
        """Body index of the block called `name`."""
        for index, block in enumerate(self._blocks):
            if block.name == name:
                return index
        raise InputError(f"no block named {name!r}; the blocks are: "
                         + ", ".join(b.name for b in self._blocks[:20])
                         + (" ..." if len(self._blocks) > 20 else ""))

    def set_law(self, group_a: str, group_b: str, law: ContactLaw | NoContact) -> None:
        """Use `law` for every contact between a body of group_a and one of group_b;
        saxum.laws.NO_CONTACT: bodies of the two groups never touch (no contacts)."""
        if not isinstance(law, ContactLaw | NoContact):
            raise InputError(f"law for ({group_a}, {group_b}) must be a ContactLaw or "
                             f"NO_CONTACT, got {law!r}")
        self._laws[frozenset((group_a, group_b))] = law

    def add_acceleration(self, acceleration: TimeVector) -> None:
        """Apply m a(t) to every free body; a: t [s] -> (ax, ay) [m/s^2] ((ax, ay, az) in 3D),
        e.g. a load factor."""
        self._accelerations.append(acceleration)

    def add_force(self, bodies: Sequence[int], force: TimeVector) -> None:
        """Apply force(t) = (fx, fy [N/m], torque [N m/m]) at the centre of mass of each body
        (2D: per metre of depth); in 3D (fx, fy, fz [N], mx, my, mz [N m]) in the world frame."""
        idx = np.atleast_1d(np.asarray(bodies, dtype=np.int64))
        bad = idx[(idx < 0) | (idx >= len(self._blocks))]
        if bad.size:
            raise InputError(f"add_force: no body with index {int(bad[0])}")
        self._forces.append((idx, force))

    def add_field_load(self, load: FieldLoad) -> None:
        """Apply a load that depends on where the blocks are (FieldLoad, e.g.
        saxum.flood.FloodLoad); it is checked against the model in finalize()."""
        if not (callable(getattr(load, "add", None)) and callable(getattr(load, "check", None))):
            raise InputError(f"add_field_load: {load!r} has no add(model, q, t, out) and "
                             "check(model) methods")
        self._field_loads.append(load)

    def finalize(self) -> "Model":
        """Freeze into a Model; checks that every pair of groups that can meet has a law."""
        if not self._blocks:
            raise InputError("the model has no blocks")
        n = len(self._blocks)
        groups = sorted({blk.group for blk in self._blocks})
        gidx = {g: i for i, g in enumerate(groups)}
        self._check_laws(groups)
        laws = tuple(law for law in dict.fromkeys(self._laws.values())
                     if isinstance(law, ContactLaw))
        group_law = np.full((len(groups), len(groups)), -1, dtype=np.int32)
        for key, law in self._laws.items():
            if isinstance(law, NoContact):
                continue  # -1: no contacts between the two groups
            members = sorted(key) * (2 if len(key) == 1 else 1)
            if members[0] in gidx and members[1] in gidx:
                i, j = gidx[members[0]], gidx[members[1]]
                group_law[i, j] = group_law[j, i] = laws.index(law)

        motions: list[Motion] = []
        body_motion = np.full(n, -1, dtype=np.int32)
        for b, blk in enumerate(self._blocks):
            if blk.motion is not None:
                if blk.motion not in motions:
                    motions.append(blk.motion)
                body_motion[b] = motions.index(blk.motion)
        kind = np.array([blk.kind for blk in self._blocks], dtype=np.int8)
        geometry = self._geometry_2d() if self.dim == 2 else self._geometry_3d()
        mass = geometry.pop("body_mass")
        inertia = geometry["body_inertia"]
        dof = 3 * (self.dim - 1)
        inv_mass = np.zeros((n, dof))
        free = kind == BodyKind.FREE
        inv_mass[free, : self.dim] = 1.0 / mass[free, None]
        inv_mass[free, self.dim :] = 1.0 / inertia[free].reshape(-1, dof - self.dim)
        model = Model(
            body_count=n,
            body_name=tuple(blk.name for blk in self._blocks),
            body_kind=kind,
            body_group=np.array([gidx[blk.group] for blk in self._blocks], dtype=np.int32),
            body_density=np.array([blk.density for blk in self._blocks]),
            body_mass=mass,
            body_inv_mass=inv_mass,
            body_motion=body_motion,
            motions=tuple(motions),
            group_names=tuple(groups),
            group_law=group_law,
            laws=laws,
            law_kind=np.array([law.kind for law in laws], dtype=np.int8),
            law_friction=np.array([law.friction for law in laws], dtype=np.float64),
            law_restitution=np.array([law.restitution for law in laws], dtype=np.float64),
            law_points=np.array([law.points for law in laws], dtype=np.int32),
            law_parameter=np.array([law.parameters for law in laws],
                                   dtype=np.float64).reshape(len(laws), len(Parameter)),
            law_initial_gap=np.array([law.initial_gap for law in laws], dtype=np.bool_),
            gravity=self._gravity.copy(),
            accelerations=tuple(self._accelerations),
            forces=tuple(self._forces),
            field_loads=tuple(self._field_loads),
            dim=self.dim,
            dof=dof,
            fe=self._deformable(),
            body_shape=np.array([_shape_of(blk) for blk in self._blocks], dtype=np.int8),
            body_round_radius=np.array([blk.round_radius for blk in self._blocks]),
            **geometry,
        )
        for load in model.field_loads:
            load.check(model)
        return model

    def _deformable(self) -> "FEBodies | None":
        """The meshes and matrices of the DEFORMABLE blocks (None if there are none)."""
        blocks = [(b, blk) for b, blk in enumerate(self._blocks)
                  if blk.kind == BodyKind.DEFORMABLE]
        if not blocks:
            return None
        return build_fe_bodies([b for b, _ in blocks], [blk.vertices for _, blk in blocks],
                               [blk.material for _, blk in blocks],
                               [blk.mesh_size for _, blk in blocks],
                               [blk.name for _, blk in blocks], len(self._blocks))

    def _geometry_2d(self) -> dict:
        """Mass properties and the polygons' vertex and edge arrays, body frame = world axes
        through the centroid."""
        n = len(self._blocks)
        mass, inertia, radius, size = (np.zeros(n) for _ in range(4))
        q0 = np.zeros((n, 3))
        starts = np.zeros(n + 1, dtype=np.int32)
        local = []
        for b, blk in enumerate(self._blocks):
            props = polygon_properties(blk.vertices)
            mass[b] = blk.density * props.area
            inertia[b] = blk.density * props.polar_moment
            q0[b, :2] = props.centroid
            rel = blk.vertices - props.centroid
            local.append(rel)
            radius[b] = np.hypot(rel[:, 0], rel[:, 1]).max()
            size[b] = math.sqrt(props.area)
            if blk.length > 0.0:  # a capsule inside its bounding rectangle rel
                area, polar = capsule_properties(blk.length, blk.round_radius)
                mass[b], inertia[b] = blk.density * area, blk.density * polar
                size[b] = math.sqrt(area)
            elif blk.round_radius > 0.0:  # a disc inside its bounding square rel
                r = blk.round_radius
                mass[b] = blk.density * math.pi * r * r
                inertia[b] = 0.5 * mass[b] * r * r
                size[b] = math.sqrt(math.pi) * r
            starts[b + 1] = starts[b] + len(rel)
        vertex_local = np.ascontiguousarray(np.concatenate(local))
        following = np.concatenate([np.roll(rel, -1, axis=0) for rel in local]) - vertex_local
        edge_length = np.hypot(following[:, 0], following[:, 1])
        edge_normal = np.column_stack((following[:, 1], -following[:, 0])) / edge_length[:, None]
        return dict(body_mass=mass, body_inertia=inertia, body_q0=q0, body_radius=radius,
                    body_size=size, body_vertex_start=starts, vertex_local=vertex_local,
                    edge_normal_local=np.ascontiguousarray(edge_normal), edge_length=edge_length)

    def _geometry_3d(self) -> dict:
        """Mass properties and the polyhedra's vertex, face and edge arrays in the principal
        frame of each block (saxum.geometry3d)."""
        n = len(self._blocks)
        mass, radius, size = (np.zeros(n) for _ in range(3))
        inertia = np.zeros((n, 3))
        q0 = np.zeros((n, 7))
        vstart, fstart, estart = (np.zeros(n + 1, dtype=np.int32) for _ in range(3))
        local, normals, rings, edges, edge_faces = [], [], [], [], []
        for b, blk in enumerate(self._blocks):
            poly = blk.vertices
            props = polyhedron_properties(poly)
            if blk.axes is not None:  # a capsule inside its bounding box, its axis z
                volume, axial, across = spherocylinder_properties(blk.length, blk.round_radius)
                props = PolyhedronProperties(volume, props.centroid,
                                             np.array([across, across, axial]), blk.axes)
            elif blk.round_radius > 0.0:  # a sphere inside its bounding cube, axes the world's
                r = blk.round_radius
                volume = 4.0 / 3.0 * math.pi * r**3
                props = PolyhedronProperties(volume, props.centroid,
                                             np.full(3, 0.4 * volume * r * r), np.eye(3))
            mass[b] = blk.density * props.volume
            inertia[b] = blk.density * props.moments
            q0[b, :3] = props.centroid
            q0[b, 3:] = quaternion_from_matrix(props.axes)
            rel = (poly.vertices - props.centroid) @ props.axes
            local.append(rel)
            normals.append(poly.normals @ props.axes)
            rings.extend(ring + vstart[b] for ring in poly.faces)
            edges.append(poly.edges + vstart[b])
            edge_faces.append(poly.edge_faces + fstart[b])
            radius[b] = np.linalg.norm(rel, axis=1).max()
            size[b] = props.volume ** (1.0 / 3.0)
            vstart[b + 1] = vstart[b] + len(rel)
            fstart[b + 1] = fstart[b] + len(poly.faces)
            estart[b + 1] = estart[b] + len(poly.edges)
        face_vertex_start = np.zeros(len(rings) + 1, dtype=np.int32)
        face_vertex_start[1:] = np.cumsum([len(r) for r in rings])
        return dict(body_mass=mass, body_inertia=inertia, body_q0=q0, body_radius=radius,
                    body_size=size, body_vertex_start=vstart,
                    vertex_local=np.ascontiguousarray(np.concatenate(local)),
                    edge_normal_local=np.zeros((0, 3)), edge_length=np.zeros(0),
                    body_face_start=fstart, face_vertex_start=face_vertex_start,
                    face_vertex=np.concatenate(rings).astype(np.int32),
                    face_normal_local=np.ascontiguousarray(np.concatenate(normals)),
                    body_edge_start=estart,
                    edge_vertex=np.concatenate(edges).astype(np.int32),
                    edge_face=np.concatenate(edge_faces).astype(np.int32))

    def _check_laws(self, groups: list[str]) -> None:
        mobile = {blk.group for blk in self._blocks
                  if blk.kind in (BodyKind.FREE, BodyKind.DEFORMABLE)}
        for key, law in self._laws.items():
            if self.dim == 3 and isinstance(law, ContactLaw) and law.points > 3:
                raise InputError(
                    f"the law between groups {sorted(key)} asks for {law.points} points per "
                    "contact; 3D contacts take 2 (the corners) or 3 (corners, edge midpoints "
                    "and a centre)"
                )
            unknown = [g for g in key if g not in groups]
            if unknown:
                raise InputError(
                    f"set_law names group {unknown[0]!r}, which no block has; groups: {groups}"
                )
        for a in groups:
            for b in groups:
                if a <= b and (a in mobile or b in mobile) and frozenset((a, b)) not in self._laws:
                    raise InputError(
                        f"no contact law between groups {a!r} and {b!r}; "
                        f"call set_law({a!r}, {b!r}, ContactLaw(friction=...)), or "
                        f"set_law({a!r}, {b!r}, NO_CONTACT) if they must pass through each other"
                    )
