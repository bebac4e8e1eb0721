"""Multi-span masonry arch bridges: arches on piers between abutments, spandrel walls over
the haunches and piers, and the fill over them as blocks or as a surcharge."""

import math
from collections.abc import Sequence

import numpy as np

from ..errors import InputError, plain
from ..geometry2d import normalize_polygon, polygon_properties
from ..model import BodyKind, ModelBuilder
from ._common import (
    Assembly,
    Force,
    add_ground,
    check_convex,
    check_count,
    check_positive,
    fit_edges,
    lay_courses,
    model_form,
)
from .arch import ArchShape, _add_voussoirs, _name_joints, arch_ring
from .piers import pier_polygons

__all__ = ["add_arch_bridge", "arch_bridge"]


def _tops(poly: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Height [m] of the top of the convex polygon above each x [m]; -inf outside it."""
    top = np.full(len(x), -np.inf)
    for p, q in zip(poly, np.roll(poly, -1, axis=0), strict=True):
        if q[0] != p[0]:
            t = (x - p[0]) / (q[0] - p[0])
            inside = (t >= -1e-12) & (t <= 1.0 + 1e-12)
            top = np.where(inside, np.maximum(top, p[1] + t * (q[1] - p[1])), top)
    return top


def surcharge(outlines: dict[int, np.ndarray], x0: float, x1: float, deck: float,
              weight: np.ndarray) -> list[tuple[int, Force]]:
    """The weight of the fill between the top of the blocks and the deck level `deck` [m],
    from x0 to x1 [m], as a force on the block it rests on (the topmost at each x).

    weight: the fill's weight per unit area [N/m^2] as a vector (density times gravity).
    Between two consecutive vertex abscissae the top is one edge of one block, so each fill
    column is a trapezoid, applied at its centroid's abscissa on the top face; returns
    (body, (fx [N], fy [N], torque about the centre of mass [N m])).
    """
    ids = list(outlines)
    xs = np.unique(np.clip(np.concatenate([outlines[b][:, 0] for b in ids] + [[x0, x1]]),
                           x0, x1))
    a, b = xs[:-1], xs[1:]
    keep = b - a > 1e-12 * (x1 - x0)
    a, b = a[keep], b[keep]
    probe = np.concatenate((a, 0.5 * (a + b), b))
    tops = np.array([_tops(outlines[k], probe) for k in ids]).reshape(len(ids), 3, len(a))
    best = np.argmax(tops[:, 1], axis=0)
    cols = np.arange(len(a))
    ya, yb = tops[best, 0, cols], tops[best, 2, cols]
    da, db = np.maximum(deck - ya, 0.0), np.maximum(deck - yb, 0.0)
    area = 0.5 * (da + db) * (b - a)
    frac = np.divide(da + 2.0 * db, 3.0 * (da + db), out=np.full(len(a), 0.5),
                     where=da + db > 0.0)
    xc = a + frac * (b - a)
    yc = ya + frac * (yb - ya)
    totals: dict[int, np.ndarray] = {}
    for k in np.flatnonzero(area > 0.0):
        body = ids[best[k]]
        centre = polygon_properties(normalize_polygon(outlines[body])).centroid
        f = area[k] * weight
        torque = (xc[k] - centre[0]) * f[1] - (yc[k] - centre[1]) * f[0]
        totals[body] = totals.get(body, np.zeros(3)) + (f[0], f[1], torque)
    return [(body, (float(v[0]), float(v[1]), float(v[2]))) for body, v in totals.items()]


def add_arch_bridge(
    builder: ModelBuilder,
    shape: ArchShape,
    *,
    spans: int,
    voussoirs: int | Sequence[int],
    pier_width: float,
    pier_height: float,
    abutment_width: float,
    joints: str = "radial",
    pier_courses: int = 1,
    pier_kind: BodyKind = BodyKind.FREE,
    spandrel_height: float | None = None,
    fill: str = "surcharge",
    fill_depth: float = 0.5,
    course_height: float = 0.5,
    block_length: float = 1.0,
    min_piece: float = 0.1,
    density: float = 2200.0,
    fill_density: float = 1800.0,
    gravity: tuple[float, float] = (0.0, -9.81),
    origin: tuple[float, float] = (0.0, 0.0),
    rings: int = 1,
    ring_thicknesses: Sequence[float] | None = None,
    ring_stagger: bool = False,
) -> Assembly:
    """A bridge of `spans` equal arches of `shape` (ArchShape, e.g. segmental) on piers.

    Elevation, `origin` [m] at the foot of the left abutment's outer face: a fixed ground
    (top at the origin's level, reaching abutment_width beyond each end); a left abutment
    abutment_width [m] wide, the arches with piers pier_width [m] wide between them and a right
    abutment; piers and abutments rise pier_height [m] to the springings, in pier_courses
    blocks of kind pier_kind, their top blocks carrying the skewbacks. Spandrel walls of blocks
    (course_height x block_length [m], running bond) fill the space above the piers and
    haunches from the top of the piers up to spandrel_height [m] above the springings (default:
    the top of the rings), cut to fit the extrados; pieces under min_piece [-] of a block are
    left out. The fill, fill_depth [m] deep above the spandrel walls, of density fill_density
    [kg/m^3], is either "blocks" (courses like the spandrels) or "surcharge": its weight
    (under `gravity` [m/s^2], which must be the builder's) on the block under each column,
    applied with add_force as constant forces, also listed in Assembly.loads.
    Parts "ground", "abutments", "piers", "voussoirs", "spandrels", "fill"; groups "ground",
    "pier", "voussoir", "spandrel", "fill"; masonry of density [kg/m^3]. rings,
    ring_thicknesses, ring_stagger: arches of several rings (saxum.structures.arch_rings;
    voussoirs named "arch <a> ring <i> voussoir <k>", in groups "voussoir ring <i>").
    Assembly.joints (name_bridge_joints): "radial", "ring", "support" and "bed" as an arch on
    piers (add_supported_arch) names them, "fill" and "spandrel" joints.
    """
    check_count("spans", spans)
    check_positive(pier_width=pier_width, pier_height=pier_height,
                   abutment_width=abutment_width, course_height=course_height,
                   block_length=block_length)
    check_count("pier_courses", pier_courses)
    if fill not in ("blocks", "surcharge"):
        raise InputError(f"fill must be 'blocks' or 'surcharge', got {fill!r}")
    if not (math.isfinite(fill_depth) and fill_depth >= 0.0):
        raise InputError(f"fill_depth must be a finite length >= 0 [m], got {plain(fill_depth)}")
    if not 0.0 <= min_piece < 1.0:
        raise InputError(f"min_piece must be in [0, 1), got {plain(min_piece)}")
    x0, y0 = origin
    layers = {"rings": rings, "ring_thicknesses": ring_thicknesses, "ring_stagger": ring_stagger}
    alone = arch_ring(shape, voussoirs, joints, **layers)
    left, right = alone.left[0], alone.right[0]
    pitch = right[0] - left[0] + pier_width
    rings = [arch_ring(shape, voussoirs, joints,
                  origin=(x0 + abutment_width - left[0] + i * pitch, y0 + pier_height - left[1]),
                  **layers)
             for i in range(spans)]
    x1 = rings[-1].right[0][0] + abutment_width
    supports = [("abutments", "left abutment",
                 pier_polygons(x0, rings[0].left[0][0], y0, rings[0].left[0][1], pier_courses,
                               right_face=rings[0].left))]
    supports += [("piers", f"pier {i + 1}",
                  pier_polygons(rings[i].right[0][0], rings[i + 1].left[0][0], y0,
                                rings[i].right[0][1], pier_courses, left_face=rings[i].right,
                                right_face=rings[i + 1].left)) for i in range(spans - 1)]
    supports.append(("abutments", "right abutment",
                     pier_polygons(rings[-1].right[0][0], x1, y0, rings[-1].right[0][1],
                                   pier_courses, left_face=rings[-1].right)))
    check_convex([p for _, _, polys in supports for p in polys],
                 [f"{name} c{c + 1}" for _, name, polys in supports for c in range(len(polys))],
                 "check pier_width, abutment_width and pier_height")
    springing = max(max(r.left[1][1], r.right[1][1]) for r in rings)
    crown = max(float(v[:, 1].max()) for r in rings for v in r.voussoirs)
    top = crown if spandrel_height is None else y0 + pier_height + spandrel_height
    if not top > springing + 1e-9 * pitch:
        raise InputError(f"spandrel_height must put the spandrel walls' top above the top of "
                         f"the piers, {springing - y0 - pier_height:g} m above the springings; "
                         f"got {plain(spandrel_height)}")

    def levels(bottom: float, height: float) -> list[float]:
        return list(np.linspace(bottom, bottom + height,
                                max(1, round(height / course_height)) + 1))

    def edges(c: int) -> list[float]:
        return fit_edges(x0, x1, block_length, shifted=c % 2 == 1)

    holes = [r.outline for r in rings]
    asm = Assembly()
    add_ground(builder, asm, x0 - abutment_width, x1 + abutment_width, y0, pier_width)
    for part, name, polys in supports:
        for c, poly in enumerate(polys):
            asm.add_block(builder, part, poly, group="pier", density=density, kind=pier_kind,
                          name=f"{name} c{c + 1}")
    for i, r in enumerate(rings):
        _add_voussoirs(builder, asm, r, density, "voussoir", "voussoir", f"arch {i + 1} ")
    lay_courses(builder, asm, part="spandrels", group="spandrel", density=density,
                levels=levels(springing, top - springing), edges=edges, holes=holes,
                min_piece=min_piece, name="spandrel")
    if fill_depth > 0.0 and fill == "blocks":
        lay_courses(builder, asm, part="fill", group="fill", density=fill_density,
                    levels=levels(top, fill_depth), edges=edges, holes=holes,
                    min_piece=min_piece, name="fill")
    elif fill_depth > 0.0:
        masonry = {b: asm.outlines[b] for b in asm.bodies if b not in asm["ground"]}
        weight = fill_density * np.asarray(gravity, dtype=np.float64)
        for body, force in surcharge(masonry, x0, x1, top + fill_depth, weight):
            builder.add_force([body], lambda t, f=force: f)
            asm.loads.append((body, force))
    name_bridge_joints(asm)
    return asm


def name_bridge_joints(asm: Assembly) -> None:
    """Assembly.joints of a bridge (2D or 3D): the arch's and the piers' as add_supported_arch
    names them (voussoirs in "voussoir" or "voussoir ring <i>"), "support" for any block
    against the ground, then "parapet" for the other joints of the parapets (between their
    blocks and on what they stand on), "fill" for the other joints of the fill (between its
    blocks, against the spandrel walls, on the voussoirs and piers) and "spandrel" for the
    other joints of the spandrel walls (between their blocks, on the voussoirs and piers);
    a pair of groups has one kind."""
    _name_joints(asm, "voussoir")
    for kind in ("support", "parapet", "fill", "spandrel"):
        own = "ground" if kind == "support" else kind
        if own not in asm.groups:
            continue
        for g in asm.groups:
            if {own, g} != {"ground"} and asm.joint_kind(own, g) is None:
                asm.add_joint(kind, own, g)


arch_bridge = model_form(
    add_arch_bridge, "arch_bridge",
    """A multi-span arch bridge (add_arch_bridge; body 0 is the ground), friction mu [-] on every
    joint.

    >>> shape = ArchShape.segmental(span=6.0, rise=2.0, thickness=0.5)
    >>> model = arch_bridge(shape, spans=3, voussoirs=11, pier_width=1.5, pier_height=3.0,
    ...                     abutment_width=2.0)
    >>> len(model.forces) > 0
    True
""")
