"""The mechanism of a structure that moves: which joints hinge, which slide, which open, which
blocks move, and the thrust line through the joints' force resultants.

A joint is the set of contacts between two bodies (two points for two faces in contact, one
for a corner on a face). A contact point is open when its gap exceeds a tolerance; a touching
point that carries compression is a hinge when the rest of its joint has opened, or when it is
the joint's only point and the two blocks have turned relative to each other since the start
by more than the gap tolerance over the smaller one's size (contacts' "opening"): the joint
turns about it. A block's edge that rests against another's face (a voussoir's edge against
a spandrel stone) carries load at rest without turning: no hinge. A joint slides when a
touching point carrying compression has a tangential relative velocity |U_t| larger than a
fraction of the fastest block's speed (and 0.1 % of the block size per second, so that a
structure at rest, whose velocities are round-off, shows no slide). The centre of pressure of
a joint is the point of its contacts weighted by their normal forces; the thrust line of an
arch joins the centres of pressure of its joints, which is where the resultant of the joint's
forces crosses it (J. Heyman, "The stone skeleton", 1995).

In 3D a joint between two faces has several points (the corners of their overlap); it hinges
when its loaded points lie on one line, the edge the joint turns about (within the gap
tolerance of the line through the two loaded points farthest apart), while the rest of it has
opened or all of its touching points lie on that line (an edge on a face) and the blocks have
turned as above; a single loaded point is a pivot (a corner the joint turns about). Hinges are
then reported as lines (Joint.hinge_line), centres of pressure and forces as 3D vectors.

A disc or sphere touches a body at one point, and turning about it is what a grain does, not
a hinge: contacts of round bodies are never hinges. Their joint rolls when its bodies turn
relative to each other (relative spin times the round body's radius above the slide
threshold) while the point does not slip, slides when it slips (as any joint), and sticks
otherwise (Joint.rolling; Mechanism.rolling).

In a wall, blocks named "<name> c<course>b<block>" (saxum.structures: walls, buttressed walls,
a bridge's spandrels and fill) locate a joint by course: a head joint in course k (between two
blocks of the course), a bed joint between courses k and k + 1, or course k against another
block (the ground, a lintel), and by its position along the course, from the wall's left end
(the leftmost initial vertex of the coursed blocks) [m]; arches keep their angles from the
crown (Mechanism.hinge_angles).

Joints of a COHESIVE law (mortar, saxum.laws) also report their bond: "cracked" when a point
has lost it (damage 1: friction alone is left there), else "damaged" when a point has begun
to soften (damage in (0, 1)), else "intact"; bond_states labels each contact so. A contact
made after the start (blocks that met corner to corner now touch) was never bonded: it
starts cracked under the law but is no crack, and has no bond state.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .contacts import Contacts
from .geometry3d import relative_quaternions, rotation_matrix, rotation_vectors
from .laws import LawKind
from .model import BodyKind, Model, Shape, body_vertices
from .state import State

__all__ = ["BOND_STATES", "CREEP", "Joint", "Mechanism", "bond_states", "course_of",
           "frame_contacts", "frame_mechanism", "hinge_lines", "joint_index", "joint_opening",
           "joint_resultants", "joint_states", "mechanism", "round_pairs", "thrust_line",
           "wall_frame"]

CREEP = 1e-3
"""[1/s]: a slip (or a block) slower than this times the smallest block's size per second is
not a slide (not moving): a structure at rest moves by round-off and creep."""
_COURSED = re.compile(r"\bc(\d+)[ab]\d+")  # "brick c3b5" (3D walls: "c3a5" too): course 3


BOND_STATES = ("intact", "damaged", "cracked")
"""The states of a cohesive joint's bond, from none to full damage (module doc)."""


def bond_states(law: np.ndarray, damage: np.ndarray, history: np.ndarray,
                law_kind: np.ndarray) -> np.ndarray:
    """Label each contact of a COHESIVE law (law: index into law_kind, Model.law_kind)
    "intact", "damaged" or "cracked" by its damage [-] (module doc); other contacts "", and
    so those of a cohesive law that were never bonded (made after the start: damage 1 with no
    opening in their history [-], saxum.laws), which are no crack."""
    cohesive = law_kind[law] == LawKind.COHESIVE
    state = np.where(damage >= 1.0, "cracked", np.where(damage > 0.0, "damaged", "intact"))
    return np.where(cohesive & ((damage < 1.0) | (history > 0.0)), state, "")


def course_of(name: str) -> int | None:
    """The course of a block named "<name> c<course>b<block>" (module doc), else None."""
    match = _COURSED.search(name)
    return int(match.group(1)) if match else None


def joint_states(contacts: dict, gap_tolerance: float) -> np.ndarray:
    """Label each contact "closed", "hinge" or "open" (module doc).

    contacts: arrays candidate, antagonist [-], gap [m] and force [N/m] ((t, n) components;
    3D: point [m] and force [N], (t, n, s)), as from Results.contacts, and optionally
    opening [m] (joint_opening; without it every joint that touches at one point or along
    one line only counts as turned), and optionally round (True where a body is a disc or
    sphere: round_pairs; never a hinge). Every touching contact that is not a hinge is "closed",
    loaded or not (which points of a closed joint carry the load is not unique for rigid
    blocks, so an unloaded point is no sign of a mechanism)."""
    joint = joint_index(contacts["candidate"], contacts["antagonist"])
    is_open = contacts["gap"] > gap_tolerance
    loaded = ~is_open & (contacts["force"][:, 1] > 0.0)
    points = np.bincount(joint)[joint] if joint.size else joint
    opening = contacts.get("opening")
    rotated = np.ones(joint.size, dtype=bool) if opening is None else opening > gap_tolerance
    if contacts.get("round") is not None:  # a grain turning about its point is no hinge
        loaded &= ~contacts["round"]
    if contacts["force"].shape[1] == 2:
        turned = (np.bincount(joint, is_open)[joint] > 0) | ((points == 1) & rotated)
        return np.where(is_open, "open", np.where(loaded & turned, "hinge", "closed"))
    hinged = np.zeros(joint.max(initial=-1) + 1, dtype=bool)
    point = contacts["point"]
    for j in np.unique(joint[loaded]):
        rows = joint == j
        touching = rows & ~is_open
        opened = bool((rows & is_open).any())
        hinged[j] = (_line_of(point[rows & loaded], gap_tolerance) is not None
                     and (opened or (bool(rotated[rows].any())
                                     and _line_of(point[touching], gap_tolerance) is not None)))
    return np.where(is_open, "open", np.where(loaded & hinged[joint], "hinge", "closed"))


def round_pairs(body_shape: np.ndarray | None, candidate: np.ndarray,
                antagonist: np.ndarray) -> np.ndarray | None:
    """Per contact, whether one of its bodies is a disc, sphere or capsule (Model.body_shape
    ROUND, CAPSULE: it turns about a round end, never about a fixed hinge); None without
    body_shape (a model or file without round bodies)."""
    if body_shape is None:
        return None
    shape = np.asarray(body_shape)
    return (shape[candidate] != Shape.POLYGON) | (shape[antagonist] != Shape.POLYGON)


def joint_opening(body_q: np.ndarray, body_q0: np.ndarray, body_size: np.ndarray,
                  candidate: np.ndarray, antagonist: np.ndarray) -> np.ndarray:
    """Per contact, how far [m] the relative rotation of its two bodies since the initial
    configuration body_q0 moves a point at the smaller body's size (body_size [m]) from the
    joint: the angle [rad] between their turns, times that size (2D: theta [rad] in column
    2; 3D: unit quaternions (w, x, y, z) in columns 3-6)."""
    if body_q.shape[1] == 3:
        turn = body_q[:, 2] - body_q0[:, 2]
        angle = np.abs(turn[candidate] - turn[antagonist])
    else:
        turn = relative_quaternions(body_q[:, 3:], body_q0[:, 3:])
        angle = np.linalg.norm(rotation_vectors(turn[candidate], turn[antagonist]), axis=1)
    return angle * np.minimum(body_size[candidate], body_size[antagonist])


def frame_contacts(results, frame: int) -> dict:
    """The contacts of output frame `frame` of a saxum.results.Results (Results.contacts)
    with their opening (joint_opening), for joint_states and hinge_lines."""
    c = dict(results.contacts(frame))
    c["opening"] = joint_opening(results.body_q[frame], results.model["body_q0"],
                                 results.body_size, c["candidate"], c["antagonist"])
    c["round"] = round_pairs(results.model.get("body_shape"), c["candidate"], c["antagonist"])
    return c


def hinge_lines(contacts: dict, gap_tolerance: float) -> np.ndarray:
    """The lines the hinged joints of a 3D contacts dict turn about (module doc): their ends
    [m], shape (hinges, 2, 3) (a pivot: the same point twice)."""
    labels = joint_states(contacts, gap_tolerance)
    joint = joint_index(contacts["candidate"], contacts["antagonist"])
    return np.array([_hinge_line(contacts["point"], labels, joint == j, gap_tolerance)
                     for j in np.unique(joint[labels == "hinge"])]).reshape(-1, 2, 3)


def _hinge_line(point: np.ndarray, labels: np.ndarray, rows: np.ndarray, tolerance: float):
    """The ends [m] of the line a hinged 3D joint (its contacts: the mask `rows`) turns
    about: the line of its touching points if they lie on one (an edge, though only some of
    its points carry load), else that of its loaded points."""
    touching = _line_of(point[rows & (labels != "open")], tolerance)
    return touching if touching is not None else _line_of(point[rows & (labels == "hinge")],
                                                          tolerance)


def _line_of(p: np.ndarray, tolerance: float):
    """The ends (two points [m]) of the segment through the two points of p farthest apart,
    if every point of p lies within `tolerance` [m] of its line, else None."""
    if len(p) == 1:
        return p[0], p[0]
    d = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=-1)
    a, b = np.unravel_index(int(np.argmax(d)), d.shape)
    length = d[a, b]
    if length == 0.0:
        return p[a], p[a]
    axis = (p[b] - p[a]) / length
    rel = p - p[a]
    off = np.linalg.norm(rel - np.outer(rel @ axis, axis), axis=1)
    return (p[a], p[b]) if off.max() <= tolerance else None


def joint_resultants(contacts: dict, gap_tolerance: float):
    """Per joint: the two bodies (lower index first), the centre of pressure [m] (contact
    points weighted by their compressive normal forces, touching points only; nan when the
    joint carries nothing) and the resultant force [N/m; 3D: N] in world axes, from a
    contacts dict with candidate, antagonist, point, frame, gap and force ((t, n) components;
    3D (t, n, s))."""
    joint = joint_index(contacts["candidate"], contacts["antagonist"])
    n = joint.max(initial=-1) + 1
    dim = contacts["point"].shape[1]
    rn = np.where(contacts["gap"] <= gap_tolerance, np.maximum(contacts["force"][:, 1], 0.0),
                  0.0)
    total = np.bincount(joint, rn, n)
    with np.errstate(invalid="ignore", divide="ignore"):
        cop = np.column_stack([np.bincount(joint, rn * contacts["point"][:, d], n) / total
                               for d in range(dim)]).reshape(n, dim)
    world = np.einsum("ci,cij->cj", contacts["force"], contacts["frame"])
    resultant = np.column_stack([np.bincount(joint, world[:, d], n)
                                 for d in range(dim)]).reshape(n, dim)
    first = np.zeros(n, dtype=np.int64)
    first[joint[::-1]] = np.arange(joint.size)[::-1]
    pairs = np.sort(np.column_stack((contacts["candidate"][first],
                                     contacts["antagonist"][first])), axis=1)
    return pairs, cop, resultant


def thrust_line(contacts: dict, gap_tolerance: float, centre: tuple[float, float]):
    """The centres of pressure of the loaded joints [m], ordered by their angle about `centre`
    [m] (an arch's centre) measured from the vertical, so that both springings (at angles
    -90 and 90 degrees) are the ends: the thrust line of an arch, shape (joints, 2)."""
    _, cop, _ = joint_resultants(contacts, gap_tolerance)
    cop = cop[np.isfinite(cop[:, 0])]
    order = np.argsort(np.arctan2(cop[:, 0] - centre[0], cop[:, 1] - centre[1]))
    return cop[order]


def wall_frame(model) -> tuple[dict[int, int], float]:
    """The course of each coursed body of a wall (course_of: body index -> course) and the
    wall's left end [m] (the leftmost initial vertex of the coursed bodies; 0 without any),
    from which joints are located along their course (module doc)."""
    course = {b: c for b, name in enumerate(model.body_name)
              if (c := course_of(name)) is not None}
    return course, min((float(model.vertices(b)[:, 0].min()) for b in course), default=0.0)


def joint_index(candidate: np.ndarray, antagonist: np.ndarray) -> np.ndarray:
    """The joint (pair of bodies, numbered 0, 1, ... in increasing order) of each contact."""
    a = np.minimum(candidate, antagonist).astype(np.int64)
    b = np.maximum(candidate, antagonist).astype(np.int64)
    return np.unique(a * (b.max(initial=0) + 1) + b, return_inverse=True)[1]


@dataclass(frozen=True)
class Joint:
    """One joint: its two bodies (names), whether it hinges (and about which point [m]; 3D:
    the middle of its hinge line), slides (largest slip velocity [m/s]) or is open, its
    centre of pressure [m] and the resultant of its contact forces [N/m; 3D: N] (world
    frame; nan when it carries nothing). In a wall (module doc): the courses of its coursed
    bodies (one or two) and, in 2D, its position along the course [m] (the hinge point's,
    else the centre of pressure's); None elsewhere. 3D: hinge_line, the ends [m] of the line
    the joint turns about (the same point twice for a pivot). bond: the state of a cohesive
    joint's bond (BOND_STATES: its most damaged point's), None for other laws. rolling: a
    joint of a disc or sphere that rolls (module doc)."""

    bodies: tuple[str, str]
    hinge: bool
    hinge_point: tuple[float, ...] | None
    sliding: bool
    slip: float
    open: bool
    centre_of_pressure: tuple[float, ...]
    force: tuple[float, ...]
    courses: tuple[int, ...] | None = None
    along: float | None = None
    hinge_line: tuple[tuple[float, ...], tuple[float, ...]] | None = None
    bond: str | None = None
    rolling: bool = False

    @property
    def location(self) -> str | None:
        """Where the joint is in a wall, in words (None outside walls)."""
        if self.courses is None or (self.along is not None and not math.isfinite(self.along)):
            return None
        if len(self.courses) == 1:
            other = next(b for b in self.bodies if not _COURSED.search(b))
            where = f"course {self.courses[0]} against {other}"
        elif self.courses[0] == self.courses[1]:
            where = f"head joint in course {self.courses[0]}"
        else:
            where = f"bed joint between courses {min(self.courses)} and {max(self.courses)}"
        return where if self.along is None else f"{where}, {_mm(self.along)} m along"


@dataclass(frozen=True)
class Mechanism:
    """The joints of a configuration and the blocks that moved by more than `threshold` [m]."""

    joints: list[Joint]
    moving: list[str]
    threshold: float

    @property
    def hinges(self) -> list[Joint]:
        return [j for j in self.joints if j.hinge]

    @property
    def sliding(self) -> list[Joint]:
        return [j for j in self.joints if j.sliding]

    @property
    def rolling(self) -> list[Joint]:
        return [j for j in self.joints if j.rolling]

    def hinge_angles(self, centre: tuple[float, float] = (0.0, 0.0)) -> list[float]:
        """Angles of the hinge points from the crown [deg] (from the vertical through
        `centre` [m], the arch's centre), sorted; in 3D in the arch's plane (x, z)."""
        cx, cy = centre
        return sorted(math.degrees(math.atan2(abs(p[0] - cx), p[-1] - cy))
                      for p in (j.hinge_point for j in self.hinges))

    def text(self) -> str:
        """The mechanism in words, for a report."""
        lines = [f"moving blocks ({len(self.moving)}, moved > {self.threshold:.3g} m): "
                 + (", ".join(self.moving) if self.moving else "none")]
        for j in self.hinges:
            where = f": {j.location}" if j.location else ""
            if j.hinge_line is None:
                at = f"at {_point(j.hinge_point)}"
            elif j.hinge_line[0] == j.hinge_line[1]:
                at = f"(a pivot) at {_point(j.hinge_line[0])}"
            else:
                at = f"along {_point(j.hinge_line[0])}-{_point(j.hinge_line[1])}"
            lines.append(f"hinge between {j.bodies[0]} and {j.bodies[1]} {at} m{where}")
        for j in self.sliding:
            where = f": {j.location}" if j.location else ""
            lines.append(f"sliding joint between {j.bodies[0]} and {j.bodies[1]} "
                         f"(slip {j.slip:.3g} m/s){where}")
        if self.rolling:
            lines.append("rolling contacts (discs, spheres): " + "; ".join(
                f"{j.bodies[0]} | {j.bodies[1]}" for j in self.rolling))
        opened = [j for j in self.joints if j.open]
        if opened:
            lines.append("open joints: " + "; ".join(f"{a} | {b}" for a, b in
                                                      (j.bodies for j in opened)))
        for bond, what in (("cracked", "bond broken"), ("damaged", "bond softening")):
            joints = [j for j in self.joints if j.bond == bond]
            if joints:
                lines.append(f"{bond} joints ({what}): "
                             + "; ".join(f"{j.bodies[0]} | {j.bodies[1]}"
                                         + (f" ({j.location})" if j.location else "")
                                         for j in joints))
        return "\n".join(lines)


def _mm(x: float) -> str:
    """A coordinate [m] to the millimetre, without round-off digits (2.15, not 2.15000001)."""
    return f"{round(x, 3) + 0.0:g}"


def _point(p) -> str:
    return "(" + ", ".join(_mm(x) for x in p) + ")"


def mechanism(model: Model, state: State, dt: float, *, gap_tolerance: float | None = None,
              threshold: float | None = None, slip_fraction: float = 0.05) -> Mechanism:
    """Classify the joints of `state` (contacts of its last step, impulses over dt [s]) of
    `model` (a Model, or anything with its body_kind, body_q0, body_size, body_radius and
    body_name, such as the bodies of a results file: frame_mechanism), 2D or 3D.
    gap_tolerance [m]: a point is open beyond it (default 0.1 % of the smallest free block's
    size, or 10 % of the largest displacement of a free block if smaller: a mechanism caught
    at its onset has opened its joints by a fraction of that; at least 1e-6 of that size); in
    3D also how far loaded points may lie from a hinge's line;
    threshold [m]: a block moves when displaced by more (default 10 % of the largest
    displacement of a free block, and at least 1e-6 of that size: a slow mechanism caught
    early has moved little, a structure at rest only by round-off);
    slip_fraction: a joint slides when |U_t| exceeds it times the fastest point speed (and
    0.1 % of the smallest block size per second)."""
    d = model.dim
    free = np.isin(model.body_kind, (BodyKind.FREE, BodyKind.DEFORMABLE))
    size = float(model.body_size[free].min()) if free.any() else float(model.body_size.min())
    moved = np.linalg.norm(state.body_q[:, :d] - model.body_q0[:, :d], axis=1)
    largest = float(moved[free].max(initial=0.0))
    gap_tol = (gap_tolerance if gap_tolerance is not None
               else max(min(1e-3 * size, 0.1 * largest), 1e-6 * size))
    moved_by = threshold if threshold is not None else max(0.1 * largest, 1e-6 * size)
    c = state.contacts
    k = c.count
    cand, ant = c.candidate[:k], c.antagonist[:k]
    point, frame, gap = c.point[:k], c.frame[:k], c.gap[:k]
    force = c.impulse[:k] / dt
    contacts = {"candidate": cand, "antagonist": ant, "point": point, "frame": frame,
                "gap": gap, "force": force,
                "opening": joint_opening(state.body_q, model.body_q0, model.body_size, cand,
                                         ant),
                "round": round_pairs(getattr(model, "body_shape", None), cand, ant)}
    labels = joint_states(contacts, gap_tol)
    law_kind = getattr(model, "law_kind", None)
    bonds = (bond_states(c.law[:k], c.damage[:k], c.history[:k], law_kind)
             if law_kind is not None else np.full(k, ""))
    # relative velocity of the candidate's material point over the antagonist's, world frame
    p_ant = point - gap[:, None] * frame[:, 1]
    q, v = state.body_q, _with_deformable(model, state)
    u = (_point_velocity(q, v, cand, point) - _point_velocity(q, v, ant, p_ant))
    normal = frame[:, 1]
    slip = np.linalg.norm(u - np.einsum("kd,kd->k", u, normal)[:, None] * normal, axis=1)
    spin = np.linalg.norm(v[:, d:], axis=1)
    speed = float(np.abs(v[:, :d]).max(initial=0.0) + (spin * model.body_radius).max(
        initial=0.0))
    touching = (labels != "open") & (force[:, 1] > 0.0)
    slide_speed = max(slip_fraction * speed, CREEP * size)
    slides = touching & (slip > slide_speed)
    rolls = np.zeros(k, dtype=bool)
    if contacts["round"] is not None:  # relative spin times the round body's radius
        radius = np.maximum(model.body_round_radius[cand], model.body_round_radius[ant])
        w = v[:, d:] if d == 2 else np.einsum("bij,bj->bi", rotation_matrix(q[:, 3:]),
                                               v[:, d:])
        turning = np.linalg.norm(w[cand] - w[ant], axis=1) * radius
        rolls = touching & contacts["round"] & ~slides & (turning > slide_speed)
    pairs, cop, resultant = joint_resultants(contacts, gap_tol)
    joint = joint_index(cand, ant)
    names = model.body_name
    course, left = wall_frame(model)
    joints = []
    for j, (a, b) in enumerate(pairs):
        rows = np.flatnonzero(joint == j)
        hinge_rows = rows[labels[rows] == "hinge"]
        carries = bool(np.isfinite(cop[j, 0]))
        coursed = tuple(course[i] for i in (a, b) if i in course)
        line = None
        if hinge_rows.size and d == 3:
            ends = _hinge_line(point, labels, joint == j, gap_tol)
            line = tuple(tuple(map(float, e)) for e in ends)
            at = 0.5 * (ends[0] + ends[1])
        elif hinge_rows.size:
            at = point[hinge_rows[0]]
        joints.append(Joint(
            bodies=(names[a], names[b]),
            hinge=hinge_rows.size > 0,
            hinge_point=tuple(map(float, at)) if hinge_rows.size else None,
            sliding=bool(slides[rows].any()),
            slip=float(slip[rows][touching[rows]].max(initial=0.0)),
            open=bool((labels[rows] == "open").all()),
            centre_of_pressure=tuple(map(float, cop[j])),
            force=tuple(map(float, resultant[j])) if carries else (math.nan,) * d,
            courses=coursed or None,
            along=(float((at if hinge_rows.size else cop[j])[0] - left)
                   if coursed and d == 2 else None),
            hinge_line=line,
            bond=next((s for s in reversed(BOND_STATES) if (bonds[rows] == s).any()), None),
            rolling=bool(rolls[rows].any()),
        ))
    moving = [names[i] for i in np.flatnonzero(free & (moved > moved_by))]
    return Mechanism(joints, moving, moved_by)


def _with_deformable(model, state: State) -> np.ndarray:
    """The body velocities, with the rows of deformable blocks (whose body rows hold only
    their frames) set to their nodes' nearest rigid motion (FEBlocks.rigid_velocities)."""
    fe = getattr(model, "fe", None)
    if fe is None or not state.node_v.size:
        return state.body_v
    from .fe.blocks import FEBlocks

    velocity, spin = FEBlocks.geometry(list(fe.meshes), list(fe.materials)).rigid_velocities(
        state.node_x, state.node_v)
    v = state.body_v.copy()
    v[fe.body, : model.dim] = velocity
    v[fe.body, model.dim:] = spin
    return v


class _Bodies(NamedTuple):
    """The bodies of a results file, as mechanism() reads them from a Model."""

    body_kind: np.ndarray
    body_q0: np.ndarray
    body_size: np.ndarray
    body_radius: np.ndarray
    body_name: list[str]
    dim: int
    body_vertex_start: np.ndarray
    vertex_local: np.ndarray
    law_kind: np.ndarray
    body_shape: np.ndarray | None
    body_round_radius: np.ndarray | None

    def vertices(self, b: int) -> np.ndarray:
        """Initial world vertices [m] of body b, as Model.vertices."""
        return body_vertices(self.body_q0[b], self.vertex_local[
            self.body_vertex_start[b]:self.body_vertex_start[b + 1]])


def frame_mechanism(results, frame: int, *, contacts: dict | None = None,
                    **options) -> Mechanism:
    """The mechanism (see mechanism(); same options) of output frame `frame` of a
    saxum.results.Results: its coordinates, velocities and contacts with their impulses
    (`contacts`: Results.contacts(frame), when the caller has read them already)."""
    k = range(results.frame_count)[frame]
    m = results.model
    bodies = _Bodies(m["body_kind"], m["body_q0"], results.body_size, results.body_radius,
                     results.body_name, results.dim, m["body_vertex_start"], m["vertex_local"],
                     m["law_kind"], m.get("body_shape"), m.get("body_round_radius"))
    stored = results.contacts(k) if contacts is None else contacts
    contacts = Contacts(results.dim, max(1, stored["gap"].size))
    contacts.count = stored["gap"].size
    for name in Contacts._fields():
        if name in stored:  # files from before a field existed
            getattr(contacts, name)[: contacts.count] = stored[name]
    state = State(float(results.time[k]), results.body_q[k], results.body_v[k], contacts,
                  int(results.step[k]))
    return mechanism(bodies, state, results.dt, **options)


def _point_velocity(q: np.ndarray, v: np.ndarray, body: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Velocity [m/s] of the material point of `body` at world position p: v + omega x r
    (3D: omega turned from the body frame to the world's)."""
    d = p.shape[1]
    r = p - q[body, :d]
    if d == 3:
        w = np.einsum("kij,kj->ki", rotation_matrix(q[body, 3:]), v[body, 3:])
        return v[body, :3] + np.cross(w, r)
    w = v[body, 2]
    return v[body, :2] + np.column_stack((-w * r[:, 1], w * r[:, 0]))
