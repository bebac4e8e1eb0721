"""Piers (columns of blocks, also under arches) and buttressed walls in cross-section."""

import numpy as np

from ..errors import InputError
from ..model import BodyKind, ModelBuilder
from ._common import (
    Assembly,
    add_ground,
    check_count,
    check_positive,
    clean,
    course_groups,
    fit_edges,
    lay_courses,
    model_form,
    name_course_joints,
    rectangle,
)

__all__ = ["add_buttressed_wall", "add_pier", "buttressed_wall", "pier"]

Face = tuple[np.ndarray, np.ndarray]
"""A springing face: its intrados point and its extrados point [m]."""


def pier_polygons(x_lo: float, x_hi: float, y_base: float, y_top: float, courses: int,
                  left_face: Face | None = None, right_face: Face | None = None,
                  ) -> list[np.ndarray]:
    """Blocks of a pier from x_lo to x_hi, y_base to y_top [m], in `courses` equal courses,
    bottom first. The top block carries the springing faces of the arches that rest on it
    (left_face: an arch on the left, springing at (x_lo, y_top); right_face: on the right, at
    x_hi), so it rises to their extrados points with a horizontal top between them."""
    levels = np.linspace(y_base, y_top, courses + 1)
    blocks = [rectangle(x_lo, levels[c], x_hi, levels[c + 1]) for c in range(courses - 1)]
    y_b = levels[-2]
    top = [(x_lo, y_b), (x_hi, y_b)]
    if right_face is not None:
        top += [tuple(right_face[0]), tuple(right_face[1])]
    else:
        top.append((x_hi, left_face[1][1] if left_face is not None else y_top))
    if left_face is not None:
        top += [tuple(left_face[1]), tuple(left_face[0])]
    else:
        top.append((x_lo, right_face[1][1] if right_face is not None else y_top))
    reach = [face[1][0] for face in (left_face, right_face) if face is not None]
    if not all(x_lo - 1e-12 <= x <= x_hi + 1e-12 for x in reach) or reach != sorted(reach):
        raise InputError(
            f"a pier from x = {x_lo:g} to {x_hi:g} m is narrower than the springing faces it "
            f"carries (to x = {', '.join(f'{x:g}' for x in reach)} m): make the pier "
            "(pier_width, abutment_width) wider"
        )
    cleaned = clean(np.array(top), x_hi - x_lo)
    if cleaned is None:
        raise InputError(f"degenerate pier top from x = {x_lo:g} to {x_hi:g} m")
    return blocks + [cleaned]


def add_pier(
    builder: ModelBuilder,
    *,
    width: float,
    height: float,
    courses: int = 1,
    density: float = 2000.0,
    origin: tuple[float, float] = (0.0, 0.0),
    kind: BodyKind = BodyKind.FREE,
    group: str = "pier",
    ground: bool = False,
) -> Assembly:
    """A pier: a column of `courses` equal blocks, width x height [m] in all, its lower-left
    corner at `origin` [m]; part "piers", bottom block first, named "pier c1", ....
    ground: first add a fixed "ground" block (part and group "ground") 3 widths wide and
    width deep, under the pier's middle. Assembly.joints: "bed" between the pier's blocks,
    "support" against the ground."""
    check_positive(width=width, height=height)
    check_count("courses", courses)
    x0, y0 = origin
    asm = Assembly()
    if ground:
        add_ground(builder, asm, x0 - width, x0 + 2.0 * width, y0, width)
    for c, poly in enumerate(pier_polygons(x0, x0 + width, y0, y0 + height, courses)):
        asm.add_block(builder, "piers", poly, group=group, density=density, kind=kind,
                      name=f"pier c{c + 1}")
    asm.add_joint("bed", group, group)
    if ground:
        asm.add_joint("support", "ground", group)
    return asm


pier = model_form(
    add_pier, "pier",
    """A free pier (add_pier) standing on a fixed ground block 3 widths wide and width deep (body
    0, group "ground"), friction mu [-] on every joint.""",
    ground=True)


def add_buttressed_wall(
    builder: ModelBuilder,
    *,
    height: float,
    thickness: float,
    courses: int,
    buttress_width: float,
    buttress_height: float | None = None,
    setbacks: int = 1,
    block_length: float | None = None,
    density: float = 2000.0,
    origin: tuple[float, float] = (0.0, 0.0),
    group: str = "wall",
    ground: bool = False,
    joint_groups: bool = False,
) -> Assembly:
    """A wall in cross-section with a stepped buttress on its right, as courses of blocks.

    The wall is `thickness` [m] wide and `height` [m] high in `courses` equal courses, its
    lower-left corner at `origin`; the buttress projects `buttress_width` [m] at its foot and
    rises `buttress_height` [m] (default: the full height; a whole number of courses) in
    `setbacks` equal stages, each narrower by buttress_width / setbacks. Blocks are
    `block_length` [m] long (default: the wall thickness); courses at least two blocks wide are
    laid in running bond (every other one starts with a half block), so that the buttress is
    bonded to the wall. Returns part "blocks", course by course from the left, named
    "wall c<course>b<block>". ground: first add a fixed "ground" block (part and group
    "ground") three section widths wide and `thickness` deep, under the section's middle.
    joint_groups: the blocks of odd courses (1, 3, ...: course 1 at the bottom) go into group
    "<group> odd", the others into "<group> even", and Assembly.joints names "bed" joints
    (between courses), "head" joints (within a course) and "support" joints (against the
    ground), as add_wall's joint_groups.
    """
    buttress_height = height if buttress_height is None else buttress_height
    block_length = thickness if block_length is None else block_length
    check_positive(height=height, thickness=thickness, buttress_width=buttress_width,
                   buttress_height=buttress_height, block_length=block_length)
    check_count("courses", courses)
    course = height / courses
    stacked = round(buttress_height / course)
    if not (1 <= stacked <= courses and abs(stacked * course - buttress_height) <= 1e-9 * height):
        raise InputError(
            f"buttress_height must be a whole number of courses of {course:g} m, from "
            f"{course:g} to height = {height:g} m, got {buttress_height:g}"
        )
    check_count("setbacks", setbacks)
    if setbacks > stacked:
        raise InputError(f"setbacks must be <= the buttress's {stacked} courses, got {setbacks}")
    x0, y0 = origin

    def edges(c: int) -> list[float]:
        stage = c * setbacks // stacked
        width = thickness + (buttress_width * (setbacks - stage) / setbacks if c < stacked
                             else 0.0)
        return fit_edges(x0, x0 + width, block_length,
                         shifted=c % 2 == 1 and width >= 2.0 * block_length)

    levels = [y0 + c * course for c in range(courses + 1)]
    asm = Assembly()
    if ground:
        width = thickness + buttress_width
        add_ground(builder, asm, x0 - width, x0 + 2.0 * width, y0, thickness)
    courses_in = course_groups(group, joint_groups)
    lay_courses(builder, asm, part="blocks", group=group, density=density, levels=levels,
                edges=edges, name="wall", course_groups=courses_in)
    if joint_groups:
        name_course_joints(asm, courses_in)
    return asm


buttressed_wall = model_form(
    add_buttressed_wall, "buttressed_wall",
    """A buttressed wall (add_buttressed_wall) on a fixed ground (body 0, group "ground", three
    section widths wide), friction mu [-] on every joint.""",
    ground=True)
