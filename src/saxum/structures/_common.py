"""What the generators share: the Assembly they return, convex polygon clipping (bricks cut
around openings and arches), courses of blocks, and default contact laws.

Polygons are float arrays (n, 2) [m], counter-clockwise.
"""

import inspect
import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, plain
from ..geometry2d import normalize_polygon
from ..laws import ContactLaw, LawKind
from ..model import BodyKind, Model, ModelBuilder

__all__ = ["JOINT_TYPES", "Assembly"]

JOINT_TYPES = ("bed", "head", "radial", "ring", "support", "spandrel", "fill", "parapet")
"""Kinds of joints a generator names (Assembly.joints), so that a law can be given per kind:
bed joints (between courses, and under what an opening's head bears on), head joints (within
a course), radial joints (between the voussoirs of one ring), ring interfaces (between rings
of an arch), support joints (blocks against a fixed support, ground or pier), and a bridge's
parapet, fill and spandrel joints (every joint of a parapet's, the fill's or a spandrel
wall's block but those against the ground, in this order where two meet)."""

Force = tuple[float, float, float]


@dataclass
class Assembly:
    """What a generator added to a ModelBuilder.

    parts: body indices by part ("voussoirs", "piers", "bricks", ...), in the order added;
    groups: the contact groups used, in order of first use; outlines: the world vertices [m]
    of each added block, by body index; loads: the constant forces the generator applied with
    ModelBuilder.add_force, as (body, (fx [N], fy [N], torque [N m])) at the centre of mass;
    joints: the pairs of groups of each kind of joint (JOINT_TYPES) where the generator tells
    them apart, every pair of its groups under one kind (pairs that never touch included, as
    every pair with a free block needs a law).
    """

    parts: dict[str, list[int]] = field(default_factory=dict)
    groups: list[str] = field(default_factory=list)
    outlines: dict[int, np.ndarray] = field(default_factory=dict, repr=False)
    loads: list[tuple[int, Force]] = field(default_factory=list)
    joints: dict[str, list[tuple[str, str]]] = field(default_factory=dict)

    def __getitem__(self, part: str) -> list[int]:
        return self.parts.get(part, [])

    @property
    def bodies(self) -> list[int]:
        """Every body index added, in increasing order."""
        return sorted(self.outlines)

    def add_block(self, builder: ModelBuilder, part: str, vertices, *, group: str,
                  name: str, density: float = 0.0, kind: BodyKind = BodyKind.FREE) -> int:
        """Add one block to `builder` and record it under `part`."""
        index = builder.add_block(vertices, density=density, group=group, kind=kind, name=name)
        return self._record(part, group, index, vertices)

    def add_cluster(self, builder: ModelBuilder, part: str, parts, *, group: str, name: str,
                    density: float = 0.0, kind: BodyKind = BodyKind.FREE) -> int:
        """Add a cluster of convex `parts` (ModelBuilder.add_cluster) to `builder` and record
        it under `part`; its outline is all its parts' vertices."""
        index = builder.add_cluster(parts, density=density, group=group, kind=kind, name=name)
        return self._record(part, group, index, np.concatenate(parts))

    def add_round(self, builder: ModelBuilder, part: str, centre, radius: float, *,
                  group: str, name: str, density: float = 0.0,
                  kind: BodyKind = BodyKind.FREE) -> int:
        """Add a disc (a sphere in a 3D builder) of radius [m] at centre [m] to `builder` and
        record it under `part`; its outline is two corners of its bounding box, c -+ r."""
        add = builder.add_disc if builder.dim == 2 else builder.add_sphere
        index = add(centre, radius, density=density, group=group, kind=kind, name=name)
        c = np.asarray(centre, dtype=np.float64)
        return self._record(part, group, index, np.array([c - radius, c + radius]))

    def add_capsule(self, builder: ModelBuilder, part: str, centre, length: float,
                    radius: float, angle: float, *, group: str, name: str,
                    density: float = 0.0, kind: BodyKind = BodyKind.FREE) -> int:
        """Add a capsule (ModelBuilder.add_capsule: segment `length` [m], ends' `radius`
        [m], `angle` [rad]) to `builder` and record it under `part`; its outline is two
        corners of its bounding box."""
        index = builder.add_capsule(centre, length, radius, angle=angle, density=density,
                                    group=group, kind=kind, name=name)
        c = np.asarray(centre, dtype=np.float64)
        reach = 0.5 * length * np.abs((np.cos(angle), np.sin(angle))) + radius
        return self._record(part, group, index, np.array([c - reach, c + reach]))

    def _record(self, part: str, group: str, index: int, outline) -> int:
        self.parts.setdefault(part, []).append(index)
        if group not in self.groups:
            self.groups.append(group)
        self.outlines[index] = np.asarray(outline, dtype=np.float64)
        return index

    def merge(self, other: "Assembly") -> None:
        """Take in the parts, groups, outlines and loads of `other`."""
        for part, bodies in other.parts.items():
            self.parts.setdefault(part, []).extend(bodies)
        self.groups.extend(g for g in other.groups if g not in self.groups)
        self.outlines.update(other.outlines)
        self.loads.extend(other.loads)
        for kind, pairs in other.joints.items():
            for pair in pairs:
                self.add_joint(kind, *pair)

    def add_joint(self, kind: str, group_a: str, group_b: str) -> None:
        """Record the pair of groups (group_a, group_b) as joints of `kind` (JOINT_TYPES)."""
        pairs = self.joints.setdefault(kind, [])
        if {group_a, group_b} not in [set(p) for p in pairs]:
            pairs.append((group_a, group_b))

    def joint_kind(self, group_a: str, group_b: str) -> str | None:
        """The kind of joint recorded for the pair (group_a, group_b), or None."""
        for kind, pairs in self.joints.items():
            if {group_a, group_b} in [set(p) for p in pairs]:
                return kind
        return None


def name_course_joints(asm: Assembly, course_groups: Sequence[str]) -> None:
    """Assembly.joints of courses that alternate between the two course_groups: "head" within
    a course group, "bed" between them; the other groups but "ground" (an opening's head:
    lintel or voussoirs) make "bed" joints with the bricks and each other ("radial" between
    voussoirs); "support" against the ground."""
    odd, even = course_groups
    heads = [g for g in asm.groups if g not in (*course_groups, "ground")]
    asm.add_joint("head", odd, odd)
    asm.add_joint("head", even, even)
    asm.add_joint("bed", odd, even)
    for g in heads:
        for brick in course_groups:
            asm.add_joint("bed", g, brick)
    for a, b in itertools.combinations_with_replacement(heads, 2):
        asm.add_joint("radial" if a == b == "voussoir" else "bed", a, b)
    if "ground" in asm.groups:
        for g in asm.groups:
            if g != "ground":
                asm.add_joint("support", "ground", g)


def course_groups(group: str, joint_groups: bool) -> tuple[str, ...]:
    """The groups of odd and even courses ("<group> odd", "<group> even") where joint_groups,
    else none (every course in `group`)."""
    return (f"{group} odd", f"{group} even") if joint_groups else ()


def finalize(builder: ModelBuilder, groups: Sequence[str], friction: float,
             law: LawKind, joints: Mapping[str, Sequence[tuple[str, str]]] | None = None,
             joint_laws: Mapping[str, ContactLaw] | None = None) -> Model:
    """Set one Coulomb law (mu = friction [-]) between every pair of `groups`, then
    joint_laws[kind] between the pairs of groups of each kind of joint (joints:
    Assembly.joints), and finalize."""
    contact = ContactLaw(friction=friction, kind=law)
    for a, b in itertools.combinations_with_replacement(groups, 2):
        builder.set_law(a, b, contact)
    for kind, joint_law in (joint_laws or {}).items():
        if kind not in (joints or {}):
            raise InputError(f"joint_laws[{kind!r}]: the structure has no {kind!r} joints; its "
                             f"joints are: {', '.join(joints or {}) or 'none'} (walls name "
                             "theirs with joint_groups=True)")
        for pair in joints[kind]:
            builder.set_law(*pair, joint_law)
    return builder.finalize()


def model_form(add: Callable[..., "Assembly"], name: str, doc: str,
               **preset) -> Callable[..., Model]:
    """The form `name` of a generator add(builder, ...) -> Assembly that returns a Model:
    the same arguments without the builder (those in `preset` fixed), plus friction mu [-]
    and law (one ContactLaw between every pair of the assembly's groups), joint_laws (a
    ContactLaw per kind of joint the assembly names, Assembly.joints, instead) and gravity
    [m/s^2]; `doc` is its docstring."""
    params = inspect.signature(add).parameters
    passes_gravity = "gravity" in params

    def build(*args, friction: float = 0.6, law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
              joint_laws: Mapping[str, ContactLaw] | None = None,
              gravity: tuple[float, float] = (0.0, -9.81), **kwargs) -> Model:
        builder = ModelBuilder(gravity=gravity)
        if passes_gravity:
            kwargs["gravity"] = gravity
        asm = add(builder, *args, **preset, **kwargs)
        return finalize(builder, asm.groups, friction, law, asm.joints, joint_laws)

    kept = [p for name, p in params.items() if name not in ("builder", "gravity", *preset)]
    extra = [inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=default,
                               annotation=kind)
             for name, default, kind in (("friction", 0.6, float),
                                         ("law", LawKind.GAP_SIGNORINI_COULOMB, LawKind),
                                         ("joint_laws", None, Mapping[str, ContactLaw] | None),
                                         ("gravity", (0.0, -9.81), tuple[float, float]))]
    split = next((i for i, p in enumerate(kept) if p.kind == p.VAR_KEYWORD), len(kept))
    build.__signature__ = inspect.Signature(kept[:split] + extra + kept[split:],
                                            return_annotation=Model)
    build.__name__ = build.__qualname__ = name
    build.__doc__ = inspect.cleandoc(doc)
    build.__module__ = add.__module__
    return build


def check_positive(**values: float) -> None:
    """InputError naming the first value that is not a finite number > 0 [m]."""
    for name, value in values.items():
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0.0):
            raise InputError(f"{name} must be a finite length > 0 [m], got {plain(value)}")


def check_count(name: str, value, least: int = 1) -> None:
    """InputError unless value is a whole number >= least."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < least:
        raise InputError(f"{name} must be a whole number >= {least}, got {plain(value)}")


def rectangle(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], dtype=np.float64)


def area(poly: np.ndarray) -> float:
    """Signed area [m^2] (shoelace), > 0 for counter-clockwise."""
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def clean(poly: np.ndarray, scale: float) -> np.ndarray | None:
    """Drop repeated and collinear vertices (those that normalize_polygon refuses, within
    1e-8 of `scale` [m]); None when less than a polygon is left."""
    pts = [np.asarray(p, dtype=np.float64) for p in poly]
    changed = True
    while changed and len(pts) >= 3:
        changed = False
        for k in range(len(pts)):
            prev, cur, nxt = pts[k - 1], pts[k], pts[(k + 1) % len(pts)]
            a, b = cur - prev, nxt - cur
            la, lb = math.hypot(*a), math.hypot(*b)
            if la <= 1e-8 * scale or lb <= 1e-8 * scale or abs(a[0] * b[1] - a[1] * b[0]) <= (
                    1e-8 * la * lb):
                del pts[k]
                changed = True
                break
    if len(pts) < 3:
        return None
    out = np.array(pts)
    if abs(area(out)) <= 1e-12 * scale * scale:
        return None
    return out if area(out) > 0 else out[::-1].copy()


def clip(poly: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The part of the convex polygon on the left of the line a -> b (Sutherland-Hodgman)."""
    d = (b[0] - a[0]) * (poly[:, 1] - a[1]) - (b[1] - a[1]) * (poly[:, 0] - a[0])
    out = []
    n = len(poly)
    for k in range(n):
        j = (k + 1) % n
        if d[k] >= 0.0:
            out.append(poly[k])
        if (d[k] > 0.0 > d[j]) or (d[k] < 0.0 < d[j]):
            out.append(poly[k] + (poly[j] - poly[k]) * (d[k] / (d[k] - d[j])))
    return np.array(out).reshape(-1, 2)


def hull(points: np.ndarray) -> np.ndarray:
    """Convex hull, counter-clockwise (Andrew's monotone chain, 1979)."""
    pts = sorted({(float(x), float(y)) for x, y in points})

    def half(seq):
        chain: list[tuple[float, float]] = []
        for p in seq:
            while len(chain) >= 2 and ((chain[-1][0] - chain[-2][0]) * (p[1] - chain[-2][1])
                                       - (chain[-1][1] - chain[-2][1]) * (p[0] - chain[-2][0])
                                       ) <= 0.0:
                chain.pop()
            chain.append(p)
        return chain[:-1]

    return np.array(half(pts) + half(pts[::-1]))


def separated(p: np.ndarray, q: np.ndarray, tol: float) -> bool:
    """True if the convex polygons p and q overlap by no more than tol [m] (separating axis
    theorem: some edge normal of either polygon separates them)."""
    for poly in (p, q):
        e = np.roll(poly, -1, axis=0) - poly
        normals = np.column_stack((e[:, 1], -e[:, 0]))
        normals /= np.hypot(normals[:, 0], normals[:, 1])[:, None]
        pp, qq = p @ normals.T, q @ normals.T
        if np.any((pp.max(axis=0) <= qq.min(axis=0) + tol)
                  | (qq.max(axis=0) <= pp.min(axis=0) + tol)):
            return True
    return False


def subtract(piece: np.ndarray, hole: np.ndarray, scale: float) -> list[np.ndarray]:
    """Convex pieces of piece minus hole (both convex, CCW).

    The piece is first cut by vertical lines through the hole's vertices, so that within each
    strip one edge of the hole bounds it from above (a piece resting on an extrados rests on
    one voussoir along its whole underside); then each strip gives its part outside the first
    edge of the hole, its part inside that edge but outside the second, and so on. Pieces
    whose union is convex are merged again, so that a block is cut no more than it must be."""
    if separated(piece, hole, 1e-9 * scale):
        return [piece]
    strips, rest = [], piece
    lo, hi = piece[:, 0].min(), piece[:, 0].max()
    for x in sorted(x for x in hole[:, 0] if lo + 1e-9 * scale < x < hi - 1e-9 * scale):
        strips.append(clip(rest, np.array([x, 0.0]), np.array([x, 1.0])))
        rest = clip(rest, np.array([x, 1.0]), np.array([x, 0.0]))
    pieces = []
    for strip in [*strips, rest]:
        for a, b in zip(hole, np.roll(hole, -1, axis=0), strict=True):
            if len(strip) < 3:
                break
            outside = clean(clip(strip, b, a), scale)
            if outside is not None:
                pieces.append(outside)
            strip = clip(strip, a, b)
    merged = True
    while merged:
        merged = False
        for i, j in itertools.combinations(range(len(pieces)), 2):
            union = hull(np.vstack((pieces[i], pieces[j])))
            if abs(area(union) - area(pieces[i]) - area(pieces[j])) <= 1e-9 * area(union):
                joined = clean(union, scale)
                pieces = [p for k, p in enumerate(pieces) if k not in (i, j)] + [joined]
                merged = True
                break
    return pieces


def fit_edges(x0: float, x1: float, length: float, shifted: bool) -> list[float]:
    """Head joints [m] of a course from x0 to x1 of blocks `length` long, starting with a half
    block if `shifted`; the last block takes what is left (between 1/4 and 5/4 of a block)."""
    edges = [x0]
    k = 0.5 if shifted else 1.0
    while x0 + k * length < x1 - 0.25 * length:
        edges.append(x0 + k * length)
        k += 1.0
    return edges + [x1]


def lay_courses(builder: ModelBuilder, asm: Assembly, *, part: str, group: str, density: float,
                levels: Sequence[float], edges: Callable[[int], Sequence[float]],
                holes: Sequence[np.ndarray] = (), min_piece: float = 0.0,
                name: str = "brick", course_groups: Sequence[str] = ()) -> None:
    """Lay courses of rectangular blocks: course c from levels[c] to levels[c + 1] [m] with head
    joints edges(c) [m], in `group` or, if course_groups is given, in course_groups[c modulo
    its length]. Blocks are cut around the convex `holes`; a piece smaller than
    min_piece times the area of a whole block of its course is left out (a mason would fill it
    with mortar), so that no sliver makes the time step or the contact detection fragile."""
    for c in range(len(levels) - 1):
        y0, y1 = levels[c], levels[c + 1]
        xs = list(edges(c))
        whole = max(b - a for a, b in itertools.pairwise(xs)) * (y1 - y0)
        for k, (a, b) in enumerate(itertools.pairwise(xs)):
            pieces = [rectangle(a, y0, b, y1)]
            scale = max(b - a, y1 - y0)
            for hole in holes:
                pieces = [q for p in pieces for q in subtract(p, hole, scale)]
            pieces = [p for p in pieces if area(p) >= min_piece * whole]
            for j, p in enumerate(pieces):
                suffix = f".{j + 1}" if len(pieces) > 1 else ""
                asm.add_block(builder, part, p, density=density,
                              group=course_groups[c % len(course_groups)] if course_groups
                              else group, name=f"{name} c{c + 1}b{k + 1}{suffix}")


def add_ground(builder: ModelBuilder, asm: Assembly, x0: float, x1: float, top: float,
               depth: float, splits: Sequence[float] = ()) -> int:
    """A fixed "ground" block from x0 to x1 [m], its top at `top` [m], `depth` [m] deep; cut
    at the abscissae `splits` [m] (increasing, inside (x0, x1)) into "ground 1", "ground 2",
    ... from the left, so that one part can settle. Returns the first block's index."""
    edges = [x0, *splits, x1]
    if any(b <= a for a, b in itertools.pairwise(edges)):
        raise InputError(f"ground_splits must increase strictly inside ({x0:g}, {x1:g}) m, "
                         f"got {plain(splits)}")
    names = ["ground"] if not splits else [f"ground {k + 1}" for k in range(len(edges) - 1)]
    return [asm.add_block(builder, "ground", rectangle(a, top - depth, b, top), group="ground",
                          kind=BodyKind.FIXED, name=name)
            for (a, b), name in zip(itertools.pairwise(edges), names, strict=True)][0]


def check_convex(polygons: Sequence[np.ndarray], names: Sequence[str], hint: str) -> None:
    """InputError naming the first polygon that is not a convex block, with `hint`; called
    before anything is added so that a refused structure leaves the builder unchanged."""
    for poly, name in zip(polygons, names, strict=True):
        try:
            normalize_polygon(poly, name=name)
        except InputError as err:
            raise InputError(f"{err}; {hint}") from None
