"""Brick walls in running bond on a fixed ground."""

from ..errors import InputError
from ..laws import ContactLaw, LawKind
from ..model import BodyKind, Model, ModelBuilder

__all__ = ["add_grounded_running_bond_wall", "add_running_bond_wall", "running_bond_wall"]


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
    if courses < 1 or bricks < 1:
        raise InputError(f"wall needs courses >= 1 and bricks >= 1, got {courses}, {bricks}")
    if not (brick_length > 0.0 and brick_height > 0.0):
        raise InputError(f"brick size must be > 0, got {brick_length} x {brick_height}")
    x0, y0 = origin
    bodies = []
    for c in range(courses):
        y = y0 + c * brick_height
        if c % 2 == 0:
            edges = [x0 + k * brick_length for k in range(bricks + 1)]
        else:
            edges = ([x0] + [x0 + (k + 0.5) * brick_length for k in range(bricks)]
                     + [x0 + bricks * brick_length])
        for k, (a, b) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
            bodies.append(builder.add_block(
                [(a, y), (b, y), (b, y + brick_height), (a, y + brick_height)],
                density=density, group=group, name=f"brick c{c + 1}b{k + 1}",
            ))
    return bodies


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
