"""Brick walls in running or stack bond, with half bricks at the ends and openings (doors,
windows) spanned by a lintel or an arch."""

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, plain
from ..laws import ContactLaw, LawKind
from ..model import BodyKind, Model, ModelBuilder
from ._common import (
    Assembly,
    add_ground,
    check_count,
    check_positive,
    course_groups,
    lay_courses,
    model_form,
    name_course_joints,
    rectangle,
    separated,
)
from .arch import ArchShape, arch_ring

__all__ = ["Opening", "add_grounded_running_bond_wall", "add_running_bond_wall", "add_wall",
           "running_bond_wall", "wall"]

HEADS = ("lintel", "flat_arch", "segmental_arch", "none")


@dataclass(frozen=True)
class Opening:
    """A door or window: lower-left corner (x, y) [m] from the wall's lower-left corner,
    width and height [m] (a door has y = 0).

    head: what spans it: "lintel" (one block head_depth [m] high, default two courses,
    resting `bearing` [m] on the wall at each side, default half a brick), "flat_arch" (a flat
    arch, ArchShape.flat, head_depth deep, default one brick length, its springing joints
    leaning out by `skewback` [rad]), "segmental_arch" (ArchShape.segmental of the opening's
    width and `rise` [m], default width / 4, ring head_depth thick) or "none". Arches have
    `voussoirs` voussoirs and spring from the top corners of the opening.
    """

    x: float
    y: float
    width: float
    height: float
    head: str = "lintel"
    head_depth: float | None = None
    bearing: float | None = None
    rise: float | None = None
    voussoirs: int = 7
    skewback: float = math.radians(20.0)


def _opening_blocks(op: Opening, i: int, origin: np.ndarray, brick_length: float,
                    brick_height: float) -> tuple[list[np.ndarray], list[tuple[str, np.ndarray,
                                                                                str, str]]]:
    """The convex holes that opening i leaves in the brickwork [m] and the blocks that span it:
    (part, vertices, group, name)."""
    where = f"openings[{i}]"
    if op.head not in HEADS:
        raise InputError(f"{where}.head must be one of {HEADS}, got {op.head!r}")
    check_positive(**{f"{where}.width": op.width, f"{where}.height": op.height})
    x0, y0 = origin[0] + op.x, origin[1] + op.y
    top = y0 + op.height
    holes = [rectangle(x0, y0, x0 + op.width, top)]
    heads = []
    if op.head == "lintel":
        depth = 2.0 * brick_height if op.head_depth is None else op.head_depth
        bearing = 0.5 * brick_length if op.bearing is None else op.bearing
        check_positive(**{f"{where}.head_depth": depth, f"{where}.bearing": bearing})
        lintel = rectangle(x0 - bearing, top, x0 + op.width + bearing, top + depth)
        holes.append(lintel)
        heads.append(("lintels", lintel, "lintel", f"opening {i + 1} lintel"))
    elif op.head != "none":
        depth = brick_length if op.head_depth is None else op.head_depth
        check_positive(**{f"{where}.head_depth": depth})
        try:
            if op.head == "flat_arch":
                shape = ArchShape.flat(span=op.width, depth=depth, skewback=op.skewback)
            else:
                rise = 0.25 * op.width if op.rise is None else op.rise
                shape = ArchShape.segmental(span=op.width, rise=rise, thickness=depth)
            cut = arch_ring(shape, op.voussoirs, origin=(x0 + 0.5 * op.width, top))
        except InputError as err:
            raise InputError(f"{where} ({op.head}): {err}") from None
        holes.append(cut.outline)
        heads += [("voussoirs", v, "voussoir", f"opening {i + 1} voussoir {k + 1}")
                  for k, v in enumerate(cut.voussoirs)]
    return holes, heads


def add_wall(
    builder: ModelBuilder,
    *,
    courses: int,
    bricks: int,
    bond: str = "running",
    brick_length: float = 0.25,
    brick_height: float = 0.065,
    half_bricks: bool = True,
    openings: tuple[Opening, ...] | list[Opening] = (),
    min_piece: float = 0.1,
    density: float = 1800.0,
    origin: tuple[float, float] = (0.0, 0.0),
    group: str = "brick",
    ground: bool = False,
    ground_splits: Sequence[float] = (),
    joint_groups: bool = False,
) -> Assembly:
    """A wall of `courses` courses of `bricks` bricks, brick_length x brick_height [m], its
    lower-left corner at `origin` [m]; head and bed joints are exact (bricks touch).

    bond: "stack" (every course alike) or "running" (every other course shifted by half a
    brick, with a half brick at both ends if half_bricks, so that the ends are flush; without
    them the shifted courses hold bricks - 1 bricks and the ends are toothed).
    openings: doors and windows (Opening); the bricks are cut around each opening and what
    spans it, and a piece smaller than min_piece [-] of a brick is left out.
    Parts "bricks" (course by course from the left, named "brick c<course>b<brick>", a cut
    brick's pieces ".1", ".2"), "lintels" and "voussoirs" (group "lintel", "voussoir"); all of
    density [kg/m^3]. ground: first add a fixed "ground" block (part and group "ground") three
    wall lengths wide and one course deep, under the wall's middle, cut at ground_splits [m]
    (from the wall's left end) into "ground 1", "ground 2", ... so that a part can settle.
    joint_groups: the bricks of odd courses (1, 3, ...: course 1 at the bottom) go into group
    "<group> odd", the others into "<group> even", so that bed joints (odd against even) and
    head joints (odd against odd, even against even) can have their own laws; Assembly.joints
    names them, with "support" for the ground's joints, "bed" for those between an opening's
    head (lintel or voussoirs) and the bricks, below or beside it, and "radial" between the
    voussoirs.
    """
    check_count("courses", courses)
    check_count("bricks", bricks)
    check_positive(brick_length=brick_length, brick_height=brick_height)
    if bond not in ("running", "stack"):
        raise InputError(f"bond must be 'running' or 'stack', got {bond!r}")
    if not 0.0 <= min_piece < 1.0:
        raise InputError(f"min_piece must be in [0, 1), got {plain(min_piece)}")
    x0, y0 = origin
    length, height = bricks * brick_length, courses * brick_height
    holes, heads, owner = [], [], []
    for i, op in enumerate(openings):
        for size, name, bound in ((op.width, "width", length), (op.height, "height", height)):
            if isinstance(size, int | float) and size > bound:
                raise InputError(
                    f"openings[{i}].{name} = {size:g} m is larger than the wall's {name} "
                    f"({bound:g} m); make the opening smaller or add "
                    f"{'bricks' if name == 'width' else 'courses'}")
        more, spans = _opening_blocks(op, i, np.array(origin, dtype=np.float64), brick_length,
                                      brick_height)
        lo = np.min([h.min(axis=0) for h in more], axis=0)
        hi = np.max([h.max(axis=0) for h in more], axis=0)
        tol = 1e-9 * max(length, height)
        if (lo[0] < x0 - tol or lo[1] < y0 - tol or hi[0] > x0 + length + tol
                or hi[1] > y0 + height + tol):
            raise InputError(
                f"openings[{i}] and its head reach from ({lo[0] - x0:g}, {lo[1] - y0:g}) to "
                f"({hi[0] - x0:g}, {hi[1] - y0:g}) m, outside the wall (0..{length:g}, "
                f"0..{height:g}) m; move or shrink it, or add courses or bricks"
            )
        holes += more
        heads += spans
        owner += [i] * len(more)
    for (a, ha), (b, hb) in itertools.combinations(zip(owner, holes, strict=True), 2):
        if a != b and not separated(ha, hb, 1e-9 * max(length, height)):
            raise InputError(f"openings[{a}] and openings[{b}] (with their heads) overlap; "
                             "move them apart")

    def edges(c: int) -> list[float]:
        if bond == "stack" or c % 2 == 0:
            return [x0 + k * brick_length for k in range(bricks + 1)]
        inner = [x0 + (k + 0.5) * brick_length for k in range(bricks)]
        return [x0] + inner + [x0 + bricks * brick_length] if half_bricks else inner

    asm = Assembly()
    if ground:
        add_ground(builder, asm, x0 - length, x0 + 2.0 * length, y0, brick_height,
                   [x0 + x for x in ground_splits])
    elif len(ground_splits):
        raise InputError("ground_splits needs ground=True")
    courses_in = course_groups(group, joint_groups)
    lay_courses(builder, asm, part="bricks", group=group, density=density,
                levels=[y0 + c * brick_height for c in range(courses + 1)], edges=edges,
                holes=holes, min_piece=min_piece, course_groups=courses_in)
    for part, poly, head_group, name in heads:
        asm.add_block(builder, part, poly, group=head_group, density=density, name=name)
    if joint_groups:
        name_course_joints(asm, courses_in)
    return asm


wall = model_form(
    add_wall, "wall",
    """A wall (add_wall) on a fixed ground three wall lengths wide and one course deep (body 0,
    group "ground"; cut at ground_splits [m] from the wall's left end into "ground 1",
    "ground 2", ...), friction mu [-] on every joint.""",
    ground=True)


def add_running_bond_wall(
    builder: ModelBuilder,
    *,
    courses: int,
    bricks: int,
    brick_length: float = 0.25,
    brick_height: float = 0.065,
    density: float = 1800.0,
    origin: tuple[float, float] = (0.0, 0.0),
    group: str = "brick",
) -> list[int]:
    """Add a running-bond wall: `courses` courses of `bricks` bricks [m], every other course
    shifted by half a brick with half bricks at both ends so that the wall ends are flush.
    The wall's lower-left corner is at `origin`. Returns the body indices, course by course."""
    return add_wall(builder, courses=courses, bricks=bricks, brick_length=brick_length,
                    brick_height=brick_height, density=density, origin=origin,
                    group=group)["bricks"]
def add_grounded_running_bond_wall(
    builder: ModelBuilder, *, courses: int, bricks: int, brick_length: float = 0.25,
    brick_height: float = 0.065, density: float = 1800.0,
) -> list[int]:
    """A fixed "ground" block three wall lengths wide and a running-bond wall on it
    (add_running_bond_wall, groups "ground" and "brick"); returns the bricks' body indices."""
    length = bricks * brick_length
    builder.add_block([(-length, -brick_height), (2 * length, -brick_height), (2 * length, 0.0),
                       (-length, 0.0)], kind=BodyKind.FIXED, group="ground", name="ground")
    return add_running_bond_wall(builder, courses=courses, bricks=bricks,
                                 brick_length=brick_length, brick_height=brick_height,
                                 density=density)


def running_bond_wall(
    *,
    courses: int,
    bricks: int,
    brick_length: float = 0.25,
    brick_height: float = 0.065,
    density: float = 1800.0,
    friction: float = 0.6,
    law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
) -> Model:
    """A running-bond wall on a fixed ground (add_grounded_running_bond_wall; body 0 is the
    ground), friction mu [-] on every joint."""
    builder = ModelBuilder()
    add_grounded_running_bond_wall(builder, courses=courses, bricks=bricks,
                                   brick_length=brick_length, brick_height=brick_height,
                                   density=density)
    contact = ContactLaw(friction=friction, kind=law)
    builder.set_law("brick", "brick", contact)
    builder.set_law("brick", "ground", contact)
    return builder.finalize()
