"""The mechanism of a structure that moves: which joints hinge, which slide, which open, which
blocks move, and the thrust line through the joints' force resultants.

A joint is the set of contacts between two bodies (two points for two faces in contact, one
for a corner on a face). A contact point is open when its gap exceeds a tolerance; a touching
point that carries compression is a hinge when the rest of its joint has opened (or it is the
joint's only point): the joint turns about it. A joint slides when a touching point carrying
compression has a tangential relative velocity |U_t| larger than a fraction of the fastest
block's speed (and 0.1 % of the block size per second, so that a structure at rest, whose
velocities are round-off, shows no slide). The centre of pressure of a joint is the point of
its contacts weighted by their normal forces; the thrust line of an arch joins the centres of
pressure of its joints, which is where the resultant of the joint's forces crosses it
(J. Heyman, "The stone skeleton", 1995).

In a wall, blocks named "<name> c<course>b<block>" (saxum.structures: walls, buttressed walls,
a bridge's spandrels and fill) locate a joint by course: a head joint in course k (between two
blocks of the course), a bed joint between courses k and k + 1, or course k against another
block (the ground, a lintel), and by its position along the course, from the wall's left end
(the leftmost initial vertex of the coursed blocks) [m]; arches keep their angles from the
crown (Mechanism.hinge_angles).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .contacts import Contacts
from .errors import InputError
from .model import BodyKind, Model, body_vertices
from .state import State

__all__ = ["Joint", "Mechanism", "course_of", "frame_mechanism", "joint_resultants",
           "joint_states", "mechanism", "thrust_line"]

_CREEP = 1e-3  # [1/s]: a slip slower than 0.1 % of a block's size per second is not a slide
_COURSED = re.compile(r"\bc(\d+)b\d+")  # "brick c3b5": course 3


def course_of(name: str) -> int | None:
    """The course of a block named "<name> c<course>b<block>" (module doc), else None."""
    match = _COURSED.search(name)
    return int(match.group(1)) if match else None


def joint_states(contacts: dict, gap_tolerance: float) -> np.ndarray:
    """Label each contact "closed", "hinge" or "open" (module doc).

    contacts: arrays candidate, antagonist [-], gap [m] and force [N/m] ((t, n) components),
    as from Results.contacts. Every touching contact that is not a hinge is "closed", loaded
    or not (which points of a closed joint carry the load is not unique for rigid blocks, so
    an unloaded point is no sign of a mechanism)."""
    joint = _joint_index(contacts["candidate"], contacts["antagonist"])
    is_open = contacts["gap"] > gap_tolerance
    loaded = ~is_open & (contacts["force"][:, 1] > 0.0)
    points = np.bincount(joint)[joint] if joint.size else joint
    turned = (np.bincount(joint, is_open)[joint] > 0) | (points == 1)
    return np.where(is_open, "open", np.where(loaded & turned, "hinge", "closed"))


def joint_resultants(contacts: dict, gap_tolerance: float):
    """Per joint: the two bodies (lower index first), the centre of pressure [m] (contact
    points weighted by their compressive normal forces, touching points only; nan when the
    joint carries nothing) and the resultant force [N/m] in world axes, from a contacts dict
    with candidate, antagonist, point, frame, gap and force ((t, n) components)."""
    joint = _joint_index(contacts["candidate"], contacts["antagonist"])
    n = joint.max(initial=-1) + 1
    rn = np.where(contacts["gap"] <= gap_tolerance, np.maximum(contacts["force"][:, 1], 0.0),
                  0.0)
    total = np.bincount(joint, rn, n)
    with np.errstate(invalid="ignore", divide="ignore"):
        cop = np.column_stack([np.bincount(joint, rn * contacts["point"][:, d], n) / total
                               for d in range(2)])
    world = (contacts["force"][:, :1] * contacts["frame"][:, 0]
             + contacts["force"][:, 1:] * contacts["frame"][:, 1])
    resultant = np.column_stack([np.bincount(joint, world[:, d], n) for d in range(2)])
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


def _joint_index(candidate: np.ndarray, antagonist: np.ndarray) -> np.ndarray:
    a = np.minimum(candidate, antagonist).astype(np.int64)
    b = np.maximum(candidate, antagonist).astype(np.int64)
    return np.unique(a * (b.max(initial=0) + 1) + b, return_inverse=True)[1]


@dataclass(frozen=True)
class Joint:
    """One joint: its two bodies (names), whether it hinges (and about which point [m]),
    slides (largest slip velocity [m/s]) or is open, its centre of pressure [m] and the
    resultant of its contact forces [N/m] (world frame; nan when it carries nothing).
    In a wall (module doc): the courses of its coursed bodies (one or two) and its position
    along the course [m] (the hinge point's, else the centre of pressure's); None elsewhere."""

    bodies: tuple[str, str]
    hinge: bool
    hinge_point: tuple[float, float] | None
    sliding: bool
    slip: float
    open: bool
    centre_of_pressure: tuple[float, float]
    force: tuple[float, float]
    courses: tuple[int, ...] | None = None
    along: float | None = None

    @property
    def location(self) -> str | None:
        """Where the joint is in a wall, in words (None outside walls)."""
        if self.courses is None or self.along is None or not math.isfinite(self.along):
            return None
        if len(self.courses) == 1:
            other = next(b for b in self.bodies if not _COURSED.search(b))
            where = f"course {self.courses[0]} against {other}"
        elif self.courses[0] == self.courses[1]:
            where = f"head joint in course {self.courses[0]}"
        else:
            where = f"bed joint between courses {min(self.courses)} and {max(self.courses)}"
        return f"{where}, {_mm(self.along)} m along"


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

    def hinge_angles(self, centre: tuple[float, float] = (0.0, 0.0)) -> list[float]:
        """Angles of the hinge points from the crown [deg] (from the vertical through
        `centre` [m], the arch's centre), sorted."""
        cx, cy = centre
        return sorted(math.degrees(math.atan2(abs(x - cx), y - cy))
                      for x, y in (j.hinge_point for j in self.hinges))

    def text(self) -> str:
        """The mechanism in words, for a report."""
        lines = [f"moving blocks ({len(self.moving)}, moved > {self.threshold:.3g} m): "
                 + (", ".join(self.moving) if self.moving else "none")]
        for j in self.hinges:
            x, y = j.hinge_point
            where = f": {j.location}" if j.location else ""
            lines.append(f"hinge between {j.bodies[0]} and {j.bodies[1]} at "
                         f"({_mm(x)}, {_mm(y)}) m{where}")
        for j in self.sliding:
            where = f": {j.location}" if j.location else ""
            lines.append(f"sliding joint between {j.bodies[0]} and {j.bodies[1]} "
                         f"(slip {j.slip:.3g} m/s){where}")
        opened = [j for j in self.joints if j.open]
        if opened:
            lines.append("open joints: " + "; ".join(f"{a} | {b}" for a, b in
                                                      (j.bodies for j in opened)))
        return "\n".join(lines)


def _mm(x: float) -> str:
    """A coordinate [m] to the millimetre, without round-off digits (2.15, not 2.15000001)."""
    return f"{round(x, 3) + 0.0:g}"


def mechanism(model: Model, state: State, dt: float, *, gap_tolerance: float | None = None,
              threshold: float | None = None, slip_fraction: float = 0.05) -> Mechanism:
    """Classify the joints of `state` (contacts of its last step, impulses over dt [s]) of
    `model` (a Model, or anything with its body_kind, body_q0, body_size, body_radius and
    body_name, such as the bodies of a results file: frame_mechanism).
    gap_tolerance [m]: a point is open beyond it (default 0.1 % of the smallest free block's
    size, or 10 % of the largest displacement of a free block if smaller: a mechanism caught
    at its onset has opened its joints by a fraction of that; at least 1e-6 of that size);
    threshold [m]: a block moves when displaced by more (default 10 % of the largest
    displacement of a free block, and at least 1e-6 of that size: a slow mechanism caught
    early has moved little, a structure at rest only by round-off);
    slip_fraction: a joint slides when |U_t| exceeds it times the fastest point speed (and
    0.1 % of the smallest block size per second). 2D models only (hinges are points of
    polygon joints); for 3D results, look at the mechanism in ParaView."""
    if model.dim != 2:
        raise InputError("the mechanism report (hinges, sliding and open joints) is made for "
                         "2D models; export 3D results to ParaView (saxum export-vtk)")
    free = model.body_kind == BodyKind.FREE
    size = float(model.body_size[free].min()) if free.any() else float(model.body_size.min())
    moved = np.hypot(*(state.body_q[:, :2] - model.body_q0[:, :2]).T)
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
                "gap": gap, "force": force}
    labels = joint_states(contacts, gap_tol)
    # relative velocity of the candidate's material point over the antagonist's, world frame
    p_ant = point - gap[:, None] * frame[:, 1]
    q, v = state.body_q, state.body_v
    u = (_point_velocity(q, v, cand, point) - _point_velocity(q, v, ant, p_ant))
    slip = np.abs(np.einsum("kd,kd->k", u, frame[:, 0]))
    speed = float(np.abs(v[:, :2]).max(initial=0.0) + np.abs(v[:, 2] * model.body_radius).max(
        initial=0.0))
    touching = (labels != "open") & (force[:, 1] > 0.0)
    slides = touching & (slip > max(slip_fraction * speed, _CREEP * size))
    pairs, cop, resultant = joint_resultants(contacts, gap_tol)
    joint = _joint_index(cand, ant)
    names = model.body_name
    course = {b: c for b, name in enumerate(names) if (c := course_of(name)) is not None}
    left = min((float(model.vertices(b)[:, 0].min()) for b in course), default=0.0)
    joints = []
    for j, (a, b) in enumerate(pairs):
        rows = np.flatnonzero(joint == j)
        hinge_rows = rows[labels[rows] == "hinge"]
        carries = bool(np.isfinite(cop[j, 0]))
        coursed = tuple(course[i] for i in (a, b) if i in course)
        at = point[hinge_rows[0], 0] if hinge_rows.size else cop[j, 0]
        joints.append(Joint(
            bodies=(names[a], names[b]),
            hinge=hinge_rows.size > 0,
            hinge_point=tuple(map(float, point[hinge_rows[0]])) if hinge_rows.size else None,
            sliding=bool(slides[rows].any()),
            slip=float(slip[rows][touching[rows]].max(initial=0.0)),
            open=bool((labels[rows] == "open").all()),
            centre_of_pressure=(float(cop[j, 0]), float(cop[j, 1])),
            force=(float(resultant[j, 0]), float(resultant[j, 1])) if carries
            else (math.nan, math.nan),
            courses=coursed or None,
            along=float(at - left) if coursed else None,
        ))
    moving = [names[i] for i in np.flatnonzero(free & (moved > moved_by))]
    return Mechanism(joints, moving, moved_by)


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

    def vertices(self, b: int) -> np.ndarray:
        """Initial world vertices [m] of body b, as Model.vertices."""
        return body_vertices(self.body_q0[b], self.vertex_local[
            self.body_vertex_start[b]:self.body_vertex_start[b + 1]])


def frame_mechanism(results, frame: int, **options) -> Mechanism:
    """The mechanism (see mechanism(); same options) of output frame `frame` of a
    saxum.results.Results: its coordinates, velocities and contacts with their impulses."""
    k = range(results.frame_count)[frame]
    m = results.model
    bodies = _Bodies(m["body_kind"], m["body_q0"], results.body_size, results.body_radius,
                     results.body_name, results.dim, m["body_vertex_start"], m["vertex_local"])
    stored = results.contacts(k)
    contacts = Contacts(results.dim, max(1, stored["gap"].size))
    contacts.count = stored["gap"].size
    for name in Contacts._fields():
        getattr(contacts, name)[: contacts.count] = stored[name]
    state = State(float(results.time[k]), results.body_q[k], results.body_v[k], contacts,
                  int(results.step[k]))
    return mechanism(bodies, state, results.dt, **options)


def _point_velocity(q: np.ndarray, v: np.ndarray, body: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Velocity [m/s] of the material point of `body` at world position p: v + omega x r."""
    r = p - q[body, :2]
    w = v[body, 2]
    return v[body, :2] + np.column_stack((-w * r[:, 1], w * r[:, 0]))
