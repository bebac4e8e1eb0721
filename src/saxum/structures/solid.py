"""Three-dimensional structures of convex polyhedral blocks (ModelBuilder(dim=3)).

Axes: z is vertical; a 2D elevation (x, y) becomes the plane (x, z) of the 3D model, and its
depth runs along y. Every dimension in metres, density in kg/m^3.

- extruded 2D structures (add_extruded, extruded): each block of a 2D model becomes a prism
  through the depth, optionally cut into pieces along it with staggered joints; arches and
  barrel vaults (add_arch3d, arch3d, add_semicircular_arch3d) and a single-span stone bridge
  with spandrel walls (add_bridge3d, bridge3d) are made this way from the 2D generators, so
  the 3D model of an arch is the 2D one given a depth;
- walls in running bond one brick thick, with an optional return wall making an L-shaped
  corner where the courses interlock (add_wall3d, wall3d);
- piers of courses of two blocks, crossed from course to course (add_pier3d, pier3d).
"""

import math
from collections.abc import Sequence

import numpy as np

from ..errors import InputError, plain
from ..laws import NO_CONTACT, LawKind
from ..model import BodyKind, Model, ModelBuilder
from ._common import (
    Assembly,
    check_count,
    check_positive,
    course_groups,
    finalize,
    fit_edges,
    name_course_joints,
)
from .arch import ArchShape, add_supported_arch, add_supported_semicircular_arch
from .bridge import add_arch_bridge, name_bridge_joints

__all__ = ["add_arch3d", "add_bridge3d", "add_extruded", "add_ground_slab", "add_pier3d",
           "add_semicircular_arch3d", "add_wall3d", "arch3d", "box", "bridge3d", "extruded",
           "pier3d", "prism", "wall3d"]

Span = tuple[float, float, str]
"""A depth span [m] from y0 to y1 and the group its blocks get."""


def prism(polygon, y0: float, y1: float) -> np.ndarray:
    """The points [m] of the prism of a 2D polygon (x, z) [m] from depth y0 to y1 [m]."""
    p = np.asarray(polygon, dtype=np.float64)
    front = np.column_stack((p[:, 0], np.full(len(p), y0), p[:, 1]))
    back = np.column_stack((p[:, 0], np.full(len(p), y1), p[:, 1]))
    return np.vstack((front, back))


def box(x0: float, y0: float, z0: float, x1: float, y1: float, z1: float) -> np.ndarray:
    """The 8 corners of an axis-aligned box [m]."""
    return np.array([(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])


def _cuts(y0: float, y1: float, pieces: int, shifted: bool) -> list[float]:
    """Joints along the depth: `pieces` equal pieces, or with the inner joints shifted by half
    a piece (two half pieces at the ends)."""
    step = (y1 - y0) / pieces
    if not shifted or pieces == 1:
        return [y0 + k * step for k in range(pieces + 1)]
    return [y0] + [y0 + (k + 0.5) * step for k in range(pieces)] + [y1]


def add_extruded(builder: ModelBuilder, model2d: Model, depth: float, *, pieces: int = 1,
                 stagger: bool = False, spans: dict[str, Sequence[Span]] | None = None,
                 densities: dict[str, float] | None = None) -> Assembly:
    """Add every block of the 2D model as a prism (x, z) through the depth y = 0 .. depth [m].

    pieces: free blocks through the whole depth are cut into this many equal pieces along it;
    stagger: every other such block (by index) has its joints shifted by half a piece, so
    that joints along the depth do not line up from one block to the next (a bonded barrel).
    spans: for the blocks of a group, the depth spans (y0, y1, group) they fill instead of the
    whole depth (e.g. a bridge's spandrel walls at the two faces, its fill between them);
    these are not cut.
    densities: the density [kg/m^3] of the blocks of these (3D) groups, instead of the 2D
    block's (e.g. a bridge's fill, lighter than its spandrel walls).
    Parts and names follow the 2D model's groups and names ("<name>" or "<name> p<k>").
    """
    return _extrude(builder, model2d, depth, pieces, stagger, spans, densities)[0]


def _extrude(builder, model2d, depth, pieces, stagger, spans, densities=None):
    """add_extruded, and the 3D bodies made of each 2D body."""
    if builder.dim != 3:
        raise InputError("add_extruded needs a ModelBuilder(dim=3)")
    if model2d.dim != 2:
        raise InputError("add_extruded extrudes a 2D model")
    if model2d.motions:
        raise InputError("a 2D model with driven blocks cannot be extruded; drive the 3D "
                         "model's supports instead (ModelBuilder.drive)")
    check_positive(depth=depth)
    check_count("pieces", pieces)
    densities = dict(densities or {})
    for group, density in densities.items():
        if not (math.isfinite(density) and density > 0.0):
            raise InputError(f"densities[{group!r}] must be a density > 0 [kg/m^3], got "
                             f"{plain(density)}")
    spans = dict(spans or {})
    for group, ranges in spans.items():
        for y0, y1, _ in ranges:
            if not 0.0 <= y0 < y1 <= depth:
                raise InputError(f"spans[{group!r}]: ({y0:g}, {y1:g}) is not within the depth "
                                 f"0 .. {depth:g} m")
    asm = Assembly()
    made: dict[int, list[int]] = {}
    free_count = 0
    for b in range(model2d.body_count):
        group = model2d.group_names[model2d.body_group[b]]
        kind = BodyKind(model2d.body_kind[b])
        parts = model2d.part_vertices(b)  # one, or a cluster's
        name = model2d.body_name[b]
        density = float(model2d.body_density[b])
        ranges = spans.get(group, [(0.0, depth, group)])
        for y0, y1, span_group in ranges:
            if kind == BodyKind.FREE and group not in spans:
                cuts = _cuts(y0, y1, pieces, stagger and free_count % 2 == 1)
            else:
                cuts = [y0, y1]
            for k in range(len(cuts) - 1):
                suffix = f" p{k + 1}" if len(cuts) > 2 else ""
                if len(ranges) > 1:
                    suffix = f" y{y0:g}" + suffix
                shapes = [prism(poly, cuts[k], cuts[k + 1]) for poly in parts]
                common = dict(group=span_group, name=name + suffix,
                              density=densities.get(span_group, density), kind=kind)
                made.setdefault(b, []).append(
                    asm.add_block(builder, span_group, shapes[0], **common) if len(shapes) == 1
                    else asm.add_cluster(builder, span_group, shapes, **common))
        free_count += kind == BodyKind.FREE
    return asm, made


def extruded(model2d: Model, depth: float, *, pieces: int = 1, stagger: bool = False,
             spans: dict[str, Sequence[Span]] | None = None) -> Model:
    """The 2D model given a depth (add_extruded): same groups and laws; gravity, uniform
    accelerations and applied forces carried over, (x, y) -> (x, 0, y); a 2D force per metre
    of depth on a block is applied, times each piece's depth, to the pieces of that block."""
    g = model2d.gravity
    builder = ModelBuilder(dim=3, gravity=(g[0], 0.0, g[1]))
    asm, made = _extrude(builder, model2d, depth, pieces, stagger, spans)
    groups = set(asm.groups)
    for i, a in enumerate(model2d.group_names):
        for j, b in enumerate(model2d.group_names):
            law = model2d.group_law[i, j]
            if i <= j:
                for ga in _renamed(a, spans, groups):
                    for gb in _renamed(b, spans, groups):
                        builder.set_law(ga, gb, model2d.laws[law] if law >= 0 else NO_CONTACT)
    for acc in model2d.accelerations:
        builder.add_acceleration(lambda t, acc=acc: (acc(t)[0], 0.0, acc(t)[1]))
    for bodies2d, force in model2d.forces:
        for b2 in bodies2d:
            for b3 in made[int(b2)]:
                thick = float(np.ptp(asm.outlines[b3][:, 1]))
                builder.add_force([b3], lambda t, f=force, d=thick: _force3d(f(t), d))
    return builder.finalize()


def _renamed(group: str, spans, groups: set[str]) -> list[str]:
    names = [g for _, _, g in (spans or {}).get(group, [(0, 0, group)])]
    return [g for g in dict.fromkeys(names) if g in groups]


def _force3d(force2d, depth: float) -> tuple[float, ...]:
    """(fx, fy, torque) per metre of depth -> (fx, 0, fy, 0, -torque, 0) times the depth: the
    2D out-of-plane axis e_x x e_y maps to e_x x e_z = -e_y."""
    fx, fy, torque = force2d
    return (fx * depth, 0.0, fy * depth, 0.0, -torque * depth, 0.0)


def _plane(add) -> Model:
    """The 2D model of the blocks that add(builder) adds, as a source of geometry for
    add_extruded (its contact laws are placeholders: the 3D model gets its own)."""
    builder = ModelBuilder()
    add(builder)
    return finalize(builder, builder.groups, 0.0, LawKind.SIGNORINI_COULOMB)


def add_arch3d(builder: ModelBuilder, shape: ArchShape, *, voussoirs: int, depth: float,
               pieces: int = 1, stagger: bool = False, **options) -> Assembly:
    """An arch or barrel vault: the 2D arch on its piers and ground (add_supported_arch;
    `options` are passed to it) through `depth` [m], the voussoirs cut into `pieces` along
    the depth, with staggered joints if `stagger` (add_extruded). Groups and Assembly.joints
    as in 2D: "ground", "pier", "voussoir" ("radial" joints include those between a
    voussoir's pieces)."""
    joints: dict[str, list[tuple[str, str]]] = {}
    model2d = _plane(lambda b: joints.update(
        add_supported_arch(b, shape, voussoirs=voussoirs, **options).joints))
    asm = add_extruded(builder, model2d, depth, pieces=pieces, stagger=stagger)
    asm.joints = joints
    return asm


def add_semicircular_arch3d(builder: ModelBuilder, *, radius: float, thickness: float,
                            voussoirs: int, depth: float, pieces: int = 1,
                            stagger: bool = False, density: float = 2000.0) -> Assembly:
    """The semicircular arch on its support block of saxum.structures.semicircular_arch (the
    2D validation arch) through `depth` [m] (add_extruded; groups "support", "voussoir");
    Assembly.joints "radial" (between voussoirs and their pieces) and "support"."""
    def add(b: ModelBuilder) -> None:
        add_supported_semicircular_arch(b, radius=radius, thickness=thickness,
                                        voussoirs=voussoirs, density=density)

    asm = add_extruded(builder, _plane(add), depth, pieces=pieces, stagger=stagger)
    asm.add_joint("radial", "voussoir", "voussoir")
    asm.add_joint("support", "support", "voussoir")
    return asm


def arch3d(shape: ArchShape, *, voussoirs: int, depth: float, pieces: int = 1,
           stagger: bool = False, friction: float = 0.6,
           law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
           gravity: tuple[float, float, float] = (0.0, 0.0, -9.81), **options) -> Model:
    """An arch or barrel vault (add_arch3d), friction mu [-] on every joint.

    >>> model = arch3d(ArchShape.segmental(span=4.0, rise=1.0, thickness=0.3), voussoirs=9,
    ...                depth=1.0, pieces=2, stagger=True)
    >>> model.dim, model.body_count
    (3, 25)
    """
    builder = ModelBuilder(dim=3, gravity=gravity)
    asm = add_arch3d(builder, shape, voussoirs=voussoirs, depth=depth, pieces=pieces,
                     stagger=stagger, **options)
    return finalize(builder, asm.groups, friction, law)


def add_bridge3d(builder: ModelBuilder, shape: ArchShape, *, voussoirs: int, width: float,
                 spandrel_thickness: float, abutment_width: float, pier_height: float,
                 fill: str = "blocks", fill_density: float | None = None,
                 parapet: tuple[float, float] | None = None, parapet_length: float = 1.0,
                 pieces: int = 1, stagger: bool = False, **options) -> Assembly:
    """A single-span stone bridge `width` [m] wide (along y): the barrel (the 2D
    arch_bridge's voussoirs through the width, `pieces` and `stagger` as add_arch3d),
    spandrel walls spandrel_thickness [m] thick at both faces (the 2D spandrel courses), and
    between them, if fill == "blocks", the same courses as fill blocks (group "fill", of
    fill_density [kg/m^3], default the masonry's), else ("none") nothing. With `parapet`
    (thickness, height) [m], a parapet on each spandrel wall, flush with the bridge's face,
    along the whole length of the walls, in blocks about parapet_length [m] long (the last
    one takes what is left; a joint that would fall on a head joint of the course below is
    moved along by a quarter block, as a mason breaks joints). `options` go to
    saxum.structures.add_arch_bridge (course_height, block_length, density, ...). Groups
    "ground", "pier" (the abutments), "voussoir", "spandrel", "fill" and "parapet"; the
    parapets' blocks are named "parapet b<k> y0" (the face y = 0) and "parapet b<k> y<width>"."""
    check_positive(width=width, spandrel_thickness=spandrel_thickness)
    if fill not in ("blocks", "none"):
        raise InputError(f"fill must be 'blocks' or 'none', got {fill!r}")
    if not 2.0 * spandrel_thickness < width:
        raise InputError(f"spandrel_thickness {spandrel_thickness:g} m leaves no room between "
                         f"the two spandrel walls of a bridge {width:g} m wide")
    if parapet is not None:
        if len(parapet) != 2:
            raise InputError(f"parapet must be (thickness, height) [m], got {plain(parapet)}")
        check_positive(parapet_thickness=parapet[0], parapet_height=parapet[1],
                       parapet_length=parapet_length)
        if parapet[0] > spandrel_thickness:
            raise InputError(f"parapet thickness {parapet[0]:g} m exceeds the spandrel walls' "
                             f"thickness {spandrel_thickness:g} m it stands on")
    model2d = _plane(lambda b: add_arch_bridge(
        b, shape, spans=1, voussoirs=voussoirs, pier_width=abutment_width,
        pier_height=pier_height, abutment_width=abutment_width, fill="surcharge",
        fill_depth=0.0, **options))
    t, w = spandrel_thickness, width
    walls = [(0.0, t, "spandrel"), (w - t, w, "spandrel")]
    if fill == "blocks":
        walls.insert(1, (t, w - t, "fill"))
    asm = add_extruded(builder, model2d, width, pieces=pieces, stagger=stagger,
                       spans={"spandrel": walls},
                       densities={"fill": fill_density} if fill_density is not None else None)
    if parapet is not None:
        thick, high = parapet
        density = float(model2d.body_density[model2d.group_names.index("spandrel")
                                             == model2d.body_group].max())
        tops = np.vstack([asm.outlines[b] for b in asm["spandrel"]])
        x0, x1, deck = float(tops[:, 0].min()), float(tops[:, 0].max()), float(tops[:, 2].max())
        xs = _staggered(fit_edges(x0, x1, parapet_length, shifted=False),
                        [asm.outlines[b] for b in asm.bodies], deck, parapet_length)
        for y0 in (0.0, w - thick):
            for k in range(len(xs) - 1):
                asm.add_block(builder, "parapets", box(xs[k], y0, deck, xs[k + 1], y0 + thick,
                                                      deck + high),
                              group="parapet", density=density,
                              name=f"parapet b{k + 1} y{y0:g}")
    name_bridge_joints(asm)
    return asm


def _staggered(edges: list[float], outlines, level: float, length: float) -> list[float]:
    """The inner joints `edges` [m] of a course laid at `level` [m] on blocks of `outlines`
    ((n, 3) world points [m]), each moved by length/4 [m] if it falls on a vertical edge of a
    block below (a vertex at `level` with the same x): forward, or back where the next block
    is shorter than length/2 (only the last may be: fit_edges)."""
    tol = 1e-9 * length
    below = np.concatenate([o[np.abs(o[:, 2] - level) <= tol, 0] for o in outlines])
    moved = list(edges)
    for k in range(1, len(edges) - 1):
        if np.any(np.abs(below - edges[k]) <= tol):
            forward = edges[k + 1] - edges[k] > 0.5 * length
            moved[k] = edges[k] + (0.25 if forward else -0.25) * length
    return moved


def bridge3d(shape: ArchShape, *, voussoirs: int, width: float, spandrel_thickness: float,
             abutment_width: float, pier_height: float, fill: str = "blocks",
             fill_density: float | None = None, parapet: tuple[float, float] | None = None,
             parapet_length: float = 1.0, pieces: int = 1, stagger: bool = False,
             friction: float = 0.6, law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
             gravity: tuple[float, float, float] = (0.0, 0.0, -9.81), **options) -> Model:
    """A single-span stone bridge with spandrel walls, fill and parapets (add_bridge3d),
    friction mu [-] on every joint.

    >>> shape = ArchShape.segmental(span=4.0, rise=2.0, thickness=0.5)
    >>> model = bridge3d(shape, voussoirs=5, width=4.0, spandrel_thickness=0.6,
    ...                  abutment_width=1.5, pier_height=2.0, parapet=(0.4, 1.0),
    ...                  parapet_length=2.5, course_height=1.0, block_length=2.0)
    >>> sorted(set(model.group_names))
    ['fill', 'ground', 'parapet', 'pier', 'spandrel', 'voussoir']
    """
    builder = ModelBuilder(dim=3, gravity=gravity)
    asm = add_bridge3d(builder, shape, voussoirs=voussoirs, width=width,
                       spandrel_thickness=spandrel_thickness, abutment_width=abutment_width,
                       pier_height=pier_height, fill=fill, fill_density=fill_density,
                       parapet=parapet, parapet_length=parapet_length, pieces=pieces,
                       stagger=stagger, **options)
    return finalize(builder, asm.groups, friction, law)


def _edges(x0: float, x1: float, start: float, length: float) -> list[float]:
    """Head joints from x0 to x1 [m]: the first at `start` (a shorter block before it if
    start > x0), then every `length`; the last block takes what is left, merged with the one
    before if shorter than a quarter block."""
    edges = [x0] if start > x0 + 1e-9 * length else []
    x = start
    while x < x1 - 0.25 * length:
        edges.append(x)
        x += length
    return edges + [x1]


def add_wall3d(builder: ModelBuilder, *, courses: int, length: float,
               return_length: float | None = None, thickness: float = 0.12,
               brick_length: float = 0.25, brick_height: float = 0.065,
               density: float = 1800.0, origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
               group: str = "brick", joint_groups: bool = False) -> Assembly:
    """A wall one brick thick in running bond, `courses` courses of brick_length x thickness x
    brick_height bricks [m], along x from the origin over `length` [m], y from 0 to thickness.

    Without return_length, every other course is shifted by half a brick with half bricks at
    both ends (flush ends). With return_length [m], a second wall runs along y from the origin
    (x from 0 to thickness) and the corner interlocks: in even courses the first wall's brick
    runs through the corner and the return wall starts behind it, in odd courses the other way
    round; within each wall the courses are thus shifted by the thickness (half a brick for
    bricks twice as long as thick). Bricks touch exactly (no mortar joints). Parts "bricks"
    ("brick c<course>a<k>" along x, "brick c<course>b<k>" along y). joint_groups: the bricks
    of odd courses (1, 3, ...) go into group "<group> odd", the others into "<group> even",
    and Assembly.joints names "head" (within a course) and "bed" joints (between courses), as
    add_wall's joint_groups (name_course_joints: "support" once a "ground" is merged in).
    """
    check_count("courses", courses)
    check_positive(length=length, thickness=thickness, brick_length=brick_length,
                   brick_height=brick_height)
    if return_length is not None:
        check_positive(return_length=return_length)
        if not (length > thickness and return_length > thickness):
            raise InputError(f"length {length:g} m and return_length {return_length:g} m must "
                             f"exceed the thickness {thickness:g} m")
    x0, y0, z0 = origin
    asm = Assembly()
    half = 0.5 * brick_length
    groups = course_groups(group, joint_groups) or (group,)
    for c in range(courses):
        course_group = groups[c % len(groups)]
        z1, z2 = z0 + c * brick_height, z0 + (c + 1) * brick_height
        if return_length is None:
            xs = _edges(0.0, length, half if c % 2 else 0.0, brick_length)
            ys: list[float] = []
        else:
            through = c % 2 == 0  # this course's first wall runs through the corner
            xs = _edges(0.0 if through else thickness, length, 0.0 if through else thickness,
                        brick_length)
            ys = _edges(thickness if through else 0.0, return_length,
                        thickness if through else 0.0, brick_length)
        for k in range(len(xs) - 1):
            asm.add_block(builder, "bricks", box(x0 + xs[k], y0, z1, x0 + xs[k + 1],
                                                 y0 + thickness, z2),
                          group=course_group, density=density, name=f"brick c{c + 1}a{k + 1}")
        for k in range(len(ys) - 1):
            asm.add_block(builder, "bricks", box(x0, y0 + ys[k], z1, x0 + thickness,
                                                 y0 + ys[k + 1], z2),
                          group=course_group, density=density, name=f"brick c{c + 1}b{k + 1}")
    if joint_groups:
        name_course_joints(asm, groups)
    return asm


def add_ground_slab(builder: ModelBuilder, lo: Sequence[float], hi: Sequence[float],
                    top: float) -> Assembly:
    """A fixed "ground" slab, its top at `top` [m], under the rectangle lo..hi (x, y) [m] and
    reaching beyond it by the rectangle's larger side (part and group "ground")."""
    size = max(hi[0] - lo[0], hi[1] - lo[1])
    asm = Assembly()
    asm.add_block(builder, "ground", box(lo[0] - size, lo[1] - size, top - 0.25 * size,
                                         hi[0] + size, hi[1] + size, top),
                  group="ground", kind=BodyKind.FIXED, name="ground")
    return asm


def wall3d(*, courses: int, length: float, return_length: float | None = None,
           thickness: float = 0.12, brick_length: float = 0.25, brick_height: float = 0.065,
           density: float = 1800.0, friction: float = 0.6,
           law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
           gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)) -> Model:
    """A 3D wall (add_wall3d) on a fixed ground slab (body 0, group "ground"), friction mu [-]
    on every joint.

    >>> model = wall3d(courses=4, length=1.0, return_length=0.5)
    >>> model.dim, model.body_count
    (3, 25)
    """
    builder = ModelBuilder(dim=3, gravity=gravity)
    asm = add_ground_slab(builder, (0.0, 0.0), (length, return_length or thickness), 0.0)
    asm.merge(add_wall3d(builder, courses=courses, length=length, return_length=return_length,
                         thickness=thickness, brick_length=brick_length,
                         brick_height=brick_height, density=density))
    return finalize(builder, asm.groups, friction, law)


def add_pier3d(builder: ModelBuilder, *, width: float, depth: float, courses: int,
               course_height: float, density: float = 2200.0,
               origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
               group: str = "pier", joint_groups: bool = False) -> Assembly:
    """A pier width (x) x depth (y) [m], `courses` courses course_height [m] high, each of two
    blocks side by side, split across x in even courses and across y in odd ones so that the
    joints cross. Part "piers" ("pier c<course>b<k>"). joint_groups: as add_wall3d's ("head"
    between the two blocks of a course, "bed" between courses)."""
    check_positive(width=width, depth=depth, course_height=course_height)
    check_count("courses", courses)
    x0, y0, z0 = origin
    asm = Assembly()
    groups = course_groups(group, joint_groups) or (group,)
    for c in range(courses):
        z1, z2 = z0 + c * course_height, z0 + (c + 1) * course_height
        if c % 2 == 0:
            halves = [(x0, y0, x0 + 0.5 * width, y0 + depth),
                      (x0 + 0.5 * width, y0, x0 + width, y0 + depth)]
        else:
            halves = [(x0, y0, x0 + width, y0 + 0.5 * depth),
                      (x0, y0 + 0.5 * depth, x0 + width, y0 + depth)]
        for k, (a, b, c_, d) in enumerate(halves):
            asm.add_block(builder, "piers", box(a, b, z1, c_, d, z2),
                          group=groups[c % len(groups)], density=density,
                          name=f"pier c{c + 1}b{k + 1}")
    if joint_groups:
        name_course_joints(asm, groups)
    return asm


def pier3d(*, width: float, depth: float, courses: int, course_height: float,
           density: float = 2200.0, friction: float = 0.6,
           law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
           gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)) -> Model:
    """A 3D pier (add_pier3d) on a fixed ground slab (body 0), friction mu [-] on every joint."""
    builder = ModelBuilder(dim=3, gravity=gravity)
    asm = add_ground_slab(builder, (0.0, 0.0), (width, depth), 0.0)
    asm.merge(add_pier3d(builder, width=width, depth=depth, courses=courses,
                         course_height=course_height, density=density))
    return finalize(builder, asm.groups, friction, law)

