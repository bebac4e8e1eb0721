"""A first step warm-started from given contact forces (another code's last impulses, e.g.
LMGC90's Vloc_Rloc.INI: saxum.lmgc90).

A contact force is given by the two blocks it joins (candidate, antagonist: names), its
point [m] and the force F [N] on the candidate in world axes: the mean force over a step, as
LMGC90 writes its impulses (r / H), so that the impulse of a step of dt is R = F dt whatever
step the other code took. `apply_warm_start` matches each given force to a contact that
saxum's detection finds at the state's configuration: the same two blocks (in either role)
and the nearest point, within the widest alert distance (the two codes place a contact's
point differently by at most a gap, which the alert bounds); one force per contact, the
nearest first. The matched contact's impulse is R = sign F dt in its frame (sign -1 where
saxum's candidate is the other block); the first step starts from it (Contacts'
warm start by key). Forces that match nothing are returned with the reason, never dropped
silently; contacts no force matches start from zero, as without a warm start.

File (JSON): {"contacts": [{"candidate": "b1", "antagonist": "b2", "point": [x, y],
"force": [Fx, Fy], "source": "Vloc_Rloc.INI line 12"}, ...]} (3D: three components), the
key `solver.warm_start` of a scenario (docs/scenario.md).
"""

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .contacts import Contacts
from .errors import InputError

__all__ = ["ContactForce", "apply_warm_start", "contact_forces", "read_warm_start",
           "write_warm_start"]


@dataclass(frozen=True)
class ContactForce:
    """A contact's mean force over a step: blocks (names), point [m], force F [N] on the
    candidate in world axes, and where it comes from (for messages)."""

    candidate: str
    antagonist: str
    point: tuple[float, ...]
    force: tuple[float, ...]
    source: str = ""

    def __str__(self) -> str:
        where = f"{self.source}: " if self.source else ""
        point = ", ".join(f"{x:.6g}" for x in self.point)
        return f"{where}{self.candidate!r} on {self.antagonist!r} at ({point})"


def apply_warm_start(sim, state, forces: Sequence[ContactForce]
                     ) -> list[tuple[ContactForce, str]]:
    """Give `state` (of sim's model, before its first step) the contacts detection finds at
    its configuration with the impulses R = F dt [N s] of the matched `forces` (module doc);
    other contacts keep what state.contacts held for them (a cohesive joint's bond) or start
    from zero. Returns the forces that match no contact, each with why."""
    model = sim.model
    names = {name: b for b, name in enumerate(model.body_name)}
    contacts = sim.detector.contacts_at(state.body_q,
                                        None if sim.fe is None else state.node_x)
    contacts.warm_start_from(state.contacts, model.law_kind)
    n = contacts.count
    rows: dict[tuple[int, int], list[int]] = {}
    for k in range(n):
        a, c = int(contacts.candidate[k]), int(contacts.antagonist[k])
        rows.setdefault((min(a, c), max(a, c)), []).append(k)
    tolerance = float(sim.detector.widest_alert)
    unmatched: list[tuple[ContactForce, str]] = []
    options = []  # (distance, force index, contact row)
    for i, f in enumerate(forces):
        missing = [x for x in (f.candidate, f.antagonist) if x not in names]
        if missing:
            unmatched.append((f, f"the model has no block {missing[0]!r}"))
            continue
        if len(f.point) != model.dim or len(f.force) != model.dim:
            unmatched.append((f, f"point and force need {model.dim} components"))
            continue
        a, c = names[f.candidate], names[f.antagonist]
        near = rows.get((min(a, c), max(a, c)), [])
        if not near:
            unmatched.append((f, "detection finds no contact between these blocks"))
            continue
        d = np.linalg.norm(contacts.point[near] - np.asarray(f.point), axis=1)
        options += [(float(d[j]), i, near[j]) for j in range(len(near)) if d[j] <= tolerance]
        if not (d <= tolerance).any():
            unmatched.append((f, f"no contact of these blocks within {tolerance:.3g} m of "
                                 f"the point (nearest {float(d.min()):.3g} m)"))
    options.sort()
    taken_force, taken_row = set(), set()
    for _, i, k in options:
        if i in taken_force or k in taken_row:
            continue
        taken_force.add(i)
        taken_row.add(k)
        f = forces[i]
        sign = 1.0 if names[f.candidate] == contacts.candidate[k] else -1.0
        contacts.impulse[k] = sign * sim.integrator.dt * (contacts.frame[k] @ np.asarray(f.force))
    placed = {i for _, i, _ in options}
    unmatched += [(forces[i], "another force of these blocks is nearer the only contact(s) "
                   "there") for i in sorted(placed - taken_force)]
    state.contacts = contacts
    return unmatched


def contact_forces(model, contacts: Contacts, dt: float) -> list[ContactForce]:
    """The mean forces F = R / dt [N] (world axes, on the candidate) of `contacts` (e.g. a
    state's, after a step of dt [s])."""
    out = []
    for k in range(contacts.count):
        force = contacts.frame[k].T @ contacts.impulse[k] / dt
        out.append(ContactForce(model.body_name[contacts.candidate[k]],
                                model.body_name[contacts.antagonist[k]],
                                tuple(float(x) for x in contacts.point[k]),
                                tuple(float(x) for x in force)))
    return out


def write_warm_start(path: str | Path, forces: Sequence[ContactForce]) -> None:
    """Write `forces` as a warm-start file (module doc), numbers exactly."""
    rows = [{"candidate": f.candidate, "antagonist": f.antagonist, "point": list(f.point),
             "force": list(f.force), **({"source": f.source} if f.source else {})}
            for f in forces]
    Path(path).write_text(json.dumps({"contacts": rows}, indent=1), encoding="utf-8")


def read_warm_start(path: str | Path) -> list[ContactForce]:
    """The contact forces of a warm-start file (module doc); InputError naming the file and
    the entry of anything it cannot read."""
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise InputError(f"{path}: cannot be read ({err.strerror})") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise InputError(f"{path}: not a JSON warm-start file: {err}") from None
    if not isinstance(data, dict) or not isinstance(data.get("contacts"), list):
        raise InputError(f'{path}: expected an object {{"contacts": [...]}}')
    out = []
    for i, row in enumerate(data["contacts"]):
        where = f"{path}: contacts[{i}]"
        try:
            point = tuple(float(x) for x in row["point"])
            force = tuple(float(x) for x in row["force"])
            if not np.all(np.isfinite(point + force)):
                raise ValueError("not finite")
            out.append(ContactForce(str(row["candidate"]), str(row["antagonist"]), point,
                                    force, str(row.get("source", where))))
        except (KeyError, TypeError, ValueError) as err:
            raise InputError(f'{where}: expected "candidate", "antagonist" (block names), '
                             f'"point" [m] and "force" [N] (finite numbers) ({err})') from None
    return out
