"""LMGC90's contact files Vloc_Rloc.INI (DATBOX) and Vloc_Rloc.OUT (OUTBOX): read them as
contact forces for a warm start (saxum.warmstart), write them from saxum contacts.

The layout (LMGC90's write_out_Vloc_Rloc of each contact module, e.g. mod_PLPLx.f90), per
contact:

    $icdan  PLPLx        1
     cdbdy  numbr  cdtac  numbr  vertx  numbr  behav  anbdy  numbr  antac  numbr  segmt ...
     RBDY2      2  POLYG      1  CDVER      3  law01  RBDY2      1  POLYG      1  ANSEG ...
                                 rlt/H 0.1000000D+01  rln/H 0.2000000D+02  rls/H 0.0...
                                 vlt = ...            vln = ...            vls = ...
                                 gapTT 0.0000000D+00
                                 n(1)= ...            n(2)= ...            n(3)= ...
                                 coo1= ...            coo2= ...            coo3= ...

rlt/H, rln/H (3D also rls/H) are the impulse over the step H: the mean force [N] in the
contact frame; n is the antagonist's normal (pointing to the candidate), in 2D t = (n2, -n1)
(mod_PLPLx.f90 sets tuc so), in 3D t(k)= and s(k)= lines give the frame (s = t x n in its
Wall_PR example's file, as in saxum's); coo the contact point [m] (3D files give it before
the frame, and rls/H first: values are read by their labels). The body line names the
candidate (cdbdy, its number, its contactor type) and the antagonist; between them a vertex
number (`CDVER 3`; 3D: a bare number) or nothing, after them a segment (`ANSEG 2`) or
nothing, then the status. Values are read in free format (`label
value`), so files with more digits than LMGC90's columns are read too. A contact of a law with
internal variables (LMGC90's _g0 laws: IQS_CLB_g0's g_ref, GAP_SGR_CLB_g0's taille_ele and
g_ref, the initial gap g0) ends with a comment line naming them (`#`, which LMGC90's reader
skips) and a line of their values, 15 characters each ((1X,D14.7), mod_PLPLx.f90's
read_ini_Vloc_Rloc takes them after the point); the reader here ignores them (a run
restarted from the file takes its g0 again, as LMGC90's does on its first step).
"""

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..laws import LawKind
from .reader import Where, number

__all__ = ["VlocEntry", "read_vloc_rloc", "write_vloc_rloc"]

_VALUE = re.compile(r"(rlt/H|rln/H|rls/H|rlt|rln|rls|vlt =|vln =|vls =|gapTT|gTT =|"
                    r"[nts]\(\d\)=|coo\d=)\s*([-+]?[0-9.]+(?:[EeDd][-+]?\d+)?)")
_BODIES = ("RBDY2", "RBDY3")


@dataclass
class VlocEntry:
    """A contact of a Vloc_Rloc file: its module (PLPLx, ...), candidate and antagonist
    (body type, number, contactor type), status, and the labelled values of its lines
    (`rln/H`, `n(1)=`, `coo1=`, ...)."""

    module: str
    candidate: tuple[str, int, str]
    antagonist: tuple[str, int, str]
    status: str
    where: Where
    values: dict[str, float]

    @property
    def zero(self) -> bool:
        """True if its impulses are all 0 (an open contact, `noctc`: nothing to start from)."""
        return all(value == 0.0 for label, value in self.values.items() if label.startswith("rl"))

    def force(self, dim: int) -> np.ndarray | None:
        """The mean force [N] on the candidate in world axes, or None without the frame
        (n lines; 3D also t and s)."""
        v = self.values
        try:
            n = np.array([v[f"n({k})="] for k in range(1, dim + 1)])
            if dim == 2:
                t = np.array([n[1], -n[0]])
                return v.get("rlt/H", v.get("rlt", 0.0)) * t + v.get(
                    "rln/H", v.get("rln", 0.0)) * n
            t = np.array([v[f"t({k})="] for k in (1, 2, 3)])
            s = np.array([v[f"s({k})="] for k in (1, 2, 3)])
        except KeyError:
            return None
        r = [v.get(f"{c}/H", v.get(c, 0.0)) for c in ("rlt", "rln", "rls")]
        return r[0] * t + r[1] * n + r[2] * s

    def point(self, dim: int) -> np.ndarray | None:
        """The contact point [m], or None if the file gives none (coo lines)."""
        try:
            return np.array([self.values[f"coo{k}="] for k in range(1, dim + 1)])
        except KeyError:
            return None


def read_vloc_rloc(path: Path) -> list[VlocEntry]:
    """The contacts of a Vloc_Rloc file (module doc); InputError naming the file and line of
    a contact line it cannot read."""
    try:
        lines = path.read_text(encoding="latin-1").splitlines()
    except OSError as err:
        raise InputError(f"{path}: cannot be read ({err.strerror})") from None
    out: list[VlocEntry] = []
    entry = None
    expect = 0  # lines to the body line after $icdan: the header, then the body line
    for i, line in enumerate(lines):
        where = Where(path.name, i + 1)
        words = line.split()
        if not words or words[0].startswith("!"):
            continue
        if words[0] == "$icdan":
            if len(words) < 2:
                raise InputError(f"{where}: expected '$icdan  MODULE  number', found "
                                 f"{line.strip()!r}")
            entry = VlocEntry(words[1], ("", 0, ""), ("", 0, ""), "", where, {})
            out.append(entry)
            expect = 2
        elif words[0].startswith("$"):
            entry = None  # $steps, ...
        elif entry is not None and expect == 2:
            expect = 1  # the column header
        elif entry is not None and expect == 1:
            expect = 0
            entry.where = where
            _bodies(entry, words, where)
        elif entry is not None:
            for label, value in _VALUE.findall(line):
                entry.values[label] = number(value, where)
    return out


def _bodies(entry: VlocEntry, words: list[str], where: Where) -> None:
    """Read the body line: cdbdy numbr cdtac numbr [CDVER n | n] behav anbdy numbr antac
    numbr [ANSEG n] sttus [iadj]."""
    try:
        i = 6 if words[4] in ("CDVER", "vertx") else (5 if words[4].isdigit() else 4)
        cd = (words[0], int(words[1]), words[2])
        an = (words[i + 1], int(words[i + 2]), words[i + 3])
        j = i + 5  # after the antagonist's contactor number: [ANSEG n] sttus
        j += 2 if j < len(words) and words[j] in ("ANSEG", "segmt") else 0
        status = words[j] if j < len(words) else ""
    except (IndexError, ValueError):
        cd = an = ("", 0, "")
        status = ""
    if cd[0] not in _BODIES or an[0] not in _BODIES:
        raise InputError(f"{where}: cannot read the contact {' '.join(words)!r} (expected: "
                         "cdbdy numbr cdtac numbr [CDVER n] behav anbdy numbr antac numbr "
                         "[ANSEG n] sttus, rigid bodies RBDY2 or RBDY3)")
    entry.candidate, entry.antagonist, entry.status = cd, an, status


_MODULES = {("POLYG", "POLYG"): "PLPLx", ("POLYG", "JONCx"): "PLJCx",
            ("DISKx", "POLYG"): "DKPLx", ("DISKx", "DISKx"): "DKDKx",
            ("DISKx", "JONCx"): "DKJCx", ("POLYR", "POLYR"): "PRPRx",
            ("SPHER", "POLYR"): "SPPRx", ("SPHER", "SPHER"): "SPSPx"}
"""LMGC90's contact module per (candidate, antagonist) contactor types."""
_G0_INTERNALS = {LawKind.SIGNORINI_COULOMB: ("g_ref",),
                 LawKind.GAP_SIGNORINI_COULOMB: ("taille_ele", "g_ref")}
"""The internal variables LMGC90 keeps per contact of a _g0 law (mod_tact_behav.f90): g_ref,
the initial gap g0 [m], and for GAP_SGR_CLB_g0 first the contact's length (0 for rigid
contactors, which LMGC90 leaves it at)."""


def write_vloc_rloc(path: Path, model, q: np.ndarray, contacts, dt: float, contactor,
                    fmt) -> None:
    """Write the contacts' mean forces R / dt [N] as a Vloc_Rloc file in the columns and line
    order LMGC90's readers take (module doc; relative velocities written as 0: saxum keeps
    none per contact); bodies are numbered from 1 in model order and laws law01, ...
    as export_lmgc90 writes them, at coordinates q [m, rad]; `contactor(b)` gives body b's
    contactor type, `fmt` a number's text. A pair LMGC90 orders the other way (a disc is its
    candidate, a JONCx its antagonist) is written swapped: the opposite force on the other
    body, n reversed (2D: t too; 3D: s = t x n, rt reversed). A contact of a _g0 law ends
    with its internal variables (module doc)."""
    body = "RBDY2" if model.dim == 2 else "RBDY3"
    out = ["! File Vloc_Rloc (saxum export_lmgc90): rl/H, the impulses over the step, "
           "are mean forces [N]", f"$steps      0                time= {fmt(0.0)}"]
    for k in range(contacts.count):
        cd, an = int(contacts.candidate[k]), int(contacts.antagonist[k])
        frame, point = contacts.frame[k], contacts.point[k]
        r = [*(contacts.impulse[k] / dt), 0.0][:3]
        if (contactor(cd), contactor(an)) not in _MODULES:
            # minus the force on the other body; 2D: t = (n2, -n1) turns with n, so rt and
            # rn keep their values; 3D: t kept, n and s = t x n reversed, rt changes sign
            cd, an = an, cd
            frame = -frame if model.dim == 2 else frame * np.array([[1.0], [-1.0], [-1.0]])
            r[0] = r[0] if model.dim == 2 else -r[0]
        module = _MODULES[(contactor(cd), contactor(an))]
        head = f" {body}  {cd + 1:5d}  {contactor(cd)}      1"
        tail = f"  nknow  {1:5d}"
        if module in ("PLPLx", "PLJCx"):  # the candidate's vertex, the antagonist's side
            head += f"  CDVER  {_nearest_vertex(model, q, cd, point):5d}"
            if module == "PLPLx":
                tail = f"  ANSEG  {_nearest_side(model, q, an, point, frame[1]):5d}" + tail
            else:
                tail = " " * 16 + f"nknow {1:5d}"
        elif module == "PRPRx":
            head += f"  {0:5d}"
        elif module.startswith("SP"):
            head += " " * 7
        order = "stn" if module.startswith("SP") else "tns"
        out += [f"$icdan  {module}  {k + 1:7d}",
                " cdbdy  numbr  cdtac  numbr  ...  behav  anbdy  numbr  antac  numbr  ...",
                f"{head}  law{int(contacts.law[k]) + 1:02d}  {body}  {an + 1:5d}  "
                f"{contactor(an)}      1{tail}",
                # LMGC90's readers take these three lines by position: the sphere modules
                # s, t, n (mod_SPSPx.f90), the others t, n, s; the velocities are not kept
                _row(*((f"rl{c}/H", r["tns".index(c)]) for c in order), fmt=fmt),
                _row(*((f"vl{c} =", 0.0) for c in order), fmt=fmt),
                _row(("gapTT", float(contacts.gap[k])), fmt=fmt)]
        coo = _row(*((f"coo{j + 1}=", x) for j, x in enumerate([*point, 0.0][:3])), fmt=fmt)
        frames = [_row(*((f"{c}({j + 1})=", x) for j, x in enumerate([*frame[i], 0.0][:3])),
                       fmt=fmt) for i, c in enumerate("tns") if model.dim == 3 or c == "n"]
        # what the readers look for after gapTT: 2D n(1)= then coo1=, 3D coo1= then the frame
        out += ([*frames, coo] if model.dim == 2 else [coo, *frames])
        law = model.laws[int(contacts.law[k])]
        if law.initial_gap:
            names = _G0_INTERNALS[law.kind]
            values = [0.0] * (len(names) - 1) + [float(contacts.initial_gap[k])]
            out += ["#" + " ".join(f"{name:<14s}" for name in names),
                    "".join(f" {fmt(x)}" for x in values)]
        out += [""]
    path.write_text("\n".join(out) + "\n", encoding="latin-1")


def _nearest_vertex(model, q: np.ndarray, b: int, point: np.ndarray) -> int:
    """The number (from 1) of body b's vertex nearest `point` [m]."""
    return int(np.argmin(np.linalg.norm(model.vertices(b, q) - point, axis=1))) + 1


def _nearest_side(model, q: np.ndarray, b: int, point: np.ndarray, normal: np.ndarray) -> int:
    """The number (from 1) of body b's side (vertex k to k + 1) nearest `point` [m]; at a
    corner, of the two the one whose outward normal is nearest `normal`."""
    a = model.vertices(b, q)  # counter-clockwise
    e = np.roll(a, -1, axis=0) - a
    s = np.clip(np.einsum("ij,ij->i", point - a, e) / np.einsum("ij,ij->i", e, e), 0.0, 1.0)
    d = np.linalg.norm(a + s[:, None] * e - point, axis=1)
    outward = np.column_stack((e[:, 1], -e[:, 0])) / np.linalg.norm(e, axis=1)[:, None]
    # distance first; sides as near to round-off (1e-9 of the side) go by the normal
    near = d <= d.min() + 1e-9 * np.linalg.norm(e, axis=1).max()
    return int(np.argmax(np.where(near, outward @ normal, -np.inf))) + 1


def _row(*cells: tuple[str, float], fmt) -> str:
    """A value line in LMGC90's columns: 27 blanks, then per value 2 blanks, a 5-character
    label and the number."""
    return " " * 27 + "".join(f"  {label:<5s}{fmt(float(x))}" for label, x in cells)
