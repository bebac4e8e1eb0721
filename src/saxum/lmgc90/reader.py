"""Read LMGC90's DATBOX text files (the formats written by its pre-processor pylmgc90).

What is read (every value keeps the file and line it came from, for messages):

- BODIES.DAT: `$bdyty` records ended by `$$$$$$`: the body type (RBDY2, RBDY3), `$blmty`
  PLAIN with its bulk law (`behav`), `$nodty` NO3xx / NO6xx with the reference coordinates
  `coo1..` of the node (the centre of mass), `$tacty` contactors: POLYG (2D, `nb_vertex`
  lines of `coo1 coo2` in the body frame), POLYR (3D, `nb_vertex` lines `coo1..3`, then
  `nb_face` triangles `ver1..3`, numbered from 1), POLYF (3D, a polyhedron's surface in
  `nb_patch` patches, each a line `nb_vertex= nb_faces=`, its vertex lines `coo1..3`, then
  its triangles `ver1..3` numbered from 1 within the patch: the layout of LMGC90's
  read_BDARY_POLYF, mod_a_BDARY_POLYR.f90), JONCx (2D, half-lengths `ax1`, `ax2`), PLANx
  (3D, half-lengths `axe1..3`), each with its colour.
- DOF.INI: per body the displacement X of the node from its reference coordinates (2D:
  x, y, theta [m, m, rad]; 3D: x, y, z, then rotation increments, with the frame `a`, `b`,
  `g`: the body axes in world coordinates, the columns of the rotation body -> world) and the
  velocity V (2D: vx, vy, omega; 3D: vx, vy, vz, then the angular velocity).
- DRV_DOF.DAT: per body the imposed dofs: `vlocy DOF CT AMP OMEGA PHI RAMPI RAMP`, the
  velocity [CT + AMP cos(OMEGA t + PHI)] [RAMPI + RAMP t] (the formula in the files' own
  header line); `force` lines (imposed forces) and evolution files are kept as such.
- BULK_BEHAV.DAT: `$gravy` grv1..3 [m/s^2] and the RIGID laws' densities `Umas` [kg/m^3].
- TACT_BEHAV.DAT: `$behav` contact laws (name, law type, parameters `key= value`) and
  `$seety` see-tables (candidate body, contactor, colour, law, antagonist body,
  contactor, colour, alert [m]).
- MODELS.DAT: its `$model` entries counted. (Vloc_Rloc.INI: saxum.lmgc90.vlocrloc.)

Numbers are Fortran reals (`0.5000000D-01`) or plain ones; values are read in free format
(key= value), so files with more digits than LMGC90's fixed columns are read too.
"""

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError

__all__ = ["Body", "Contactor", "Datbox", "Drive", "LawEntry", "Patch", "SeeTable",
           "read_datbox"]

_PAIR = re.compile(r"([A-Za-z_][A-Za-z0-9_()]*)\s*=\s*([^\s=]+)")


@dataclass(frozen=True)
class Where:
    """A place in a DATBOX file: file name and line (from 1)."""

    file: str
    line: int

    def __str__(self) -> str:
        return f"{self.file} line {self.line}"


@dataclass
class Patch:
    """A patch of a POLYF: where its `nb_vertex=` line is, its vertices [m] (body frame) and
    its triangles (vertex numbers from 1, within the patch)."""

    where: Where
    vertices: list[list[float]] = field(default_factory=list)
    faces: list[list[int]] = field(default_factory=list)


@dataclass
class Contactor:
    kind: str
    colour: str
    where: Where
    values: dict[str, float] = field(default_factory=dict)
    vertices: list[list[float]] = field(default_factory=list)
    faces: list[list[int]] = field(default_factory=list)
    patches: list[Patch] = field(default_factory=list)
    """A POLYF's patches (other contactors: none)."""


@dataclass
class Body:
    """A body of BODIES.DAT: type (RBDY2, RBDY3), number, bulk law, node coordinates, its
    contactors, and from DOF.INI its displacement, velocity and 3D frame."""

    type: str
    number: int
    where: Where
    behav: str = ""
    node: list[float] = field(default_factory=list)
    contactors: list[Contactor] = field(default_factory=list)
    displacement: list[float] | None = None
    velocity: list[float] | None = None
    frame: list[list[float]] | None = None
    """3D: the body axes a, b, g in world coordinates (rows here; columns of the rotation)."""
    dof_where: Where | None = None
    name: str | None = None
    """A name given by saxum's writer (comment `! saxum name: ...`)."""

    @property
    def key(self) -> tuple[str, int]:
        return self.type, self.number


@dataclass
class Drive:
    """An imposed dof of DRV_DOF.DAT: what (vlocy, force), dof (from 1), the coefficients
    (CT, AMP, OMEGA, PHI, RAMPI, RAMP), or `evolution`, the name of a file."""

    what: str
    dof: int
    where: Where
    coefficients: tuple[float, ...] = ()
    evolution: str | None = None

    @property
    def zero(self) -> bool:
        """True if the imposed value is 0 at all times."""
        ct, amp, _, _, rampi, ramp = self.coefficients
        return (ct == 0.0 and amp == 0.0) or (rampi == 0.0 and ramp == 0.0)

    @property
    def constant(self) -> bool:
        """True if the imposed value does not change with time."""
        _, amp, _, _, _, ramp = self.coefficients
        return self.zero or (amp == 0.0 and ramp == 0.0)

    def value(self, t: float) -> float:
        """[CT + AMP cos(OMEGA t + PHI)] [RAMPI + RAMP t] at time t [s]."""
        import math

        ct, amp, omega, phi, rampi, ramp = self.coefficients
        return (ct + amp * math.cos(omega * t + phi)) * (rampi + ramp * t)


@dataclass
class LawEntry:
    name: str
    type: str
    where: Where
    values: dict[str, float] = field(default_factory=dict)


@dataclass
class SeeTable:
    candidate: tuple[str, str, str]
    """(body type, contactor type, colour) of the candidate."""
    law: str
    antagonist: tuple[str, str, str]
    alert: float
    where: Where


@dataclass
class Datbox:
    """The contents of a DATBOX folder (module doc)."""

    folder: Path
    bodies: list[Body]
    drives: dict[tuple[str, int], list[Drive]]
    gravity: list[float]
    densities: dict[str, tuple[float, Where]]
    bulk_laws: dict[str, tuple[str, Where]]
    laws: dict[str, LawEntry]
    see_tables: list[SeeTable]
    groups: dict[str, str] = field(default_factory=dict)
    """Colour -> saxum group name, from saxum's writer's comments (`! saxum group: ...`)."""
    models: list[Where] = field(default_factory=list)
    """The `$model` entries of MODELS.DAT."""


def number(text: str, where: Where) -> float:
    """A Fortran or plain real: 0.5000000D-01 -> 0.05."""
    try:
        return float(text.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise InputError(f"{where}: {text!r} is not a number") from None


def _pairs(text: str, where: Where) -> dict[str, float]:
    return {k: number(v, where) for k, v in _PAIR.findall(text)}


class _Lines:
    """The lines of a file, numbered from 1, without blank and comment lines ('!'), except
    saxum's own comments (`! saxum ...`), which carry names."""

    def __init__(self, path: Path) -> None:
        self.file = path.name
        try:
            text = path.read_text(encoding="latin-1")
        except OSError as err:
            raise InputError(f"{path}: cannot be read ({err.strerror})") from None
        self.items = [(i + 1, line.rstrip()) for i, line in enumerate(text.splitlines())
                      if line.strip() and (not line.lstrip().startswith("!")
                                           or line.lstrip().startswith("! saxum "))]
        self.pos = 0

    def where(self, k: int | None = None) -> Where:
        k = self.pos if k is None else k
        line = self.items[min(k, len(self.items) - 1)][0] if self.items else 1
        return Where(self.file, line)

    def peek(self) -> str | None:
        return self.items[self.pos][1] if self.pos < len(self.items) else None

    def next(self) -> str:
        if self.pos >= len(self.items):
            raise InputError(f"{self.file}: ends in the middle of a record (line "
                             f"{self.items[-1][0] if self.items else 1})")
        self.pos += 1
        return self.items[self.pos - 1][1]


def _keyword(line: str | None) -> str | None:
    return line.strip().split()[0] if line and line.strip().startswith("$") else None


def _continues(line: str | None) -> bool:
    """True for a line that continues a record's entry (`coo1= ...`, `ver1= 1 ...`, `I1 =
    ...`), False at a keyword or the head of a new entry (`POLYG      2  color ...`)."""
    if line is None or _keyword(line) is not None:
        return False
    parts = line.split()
    return not (len(parts) >= 2 and "=" not in parts[0] and parts[1].isdigit())


def _read_bodies(path: Path) -> tuple[list[Body], dict[str, str]]:
    lines = _Lines(path)
    bodies: list[Body] = []
    groups: dict[str, str] = {}
    name = None
    while lines.peek() is not None:
        where, line = lines.where(), lines.next()
        if line.startswith("! saxum group: "):
            colour, _, group = line[len("! saxum group: "):].partition(" = ")
            groups[colour.strip()] = group
            continue
        if line.startswith("! saxum name: "):
            name = line[len("! saxum name: "):]
            continue
        if _keyword(line) != "$bdyty":
            raise InputError(f"{where}: expected $bdyty (a body record), found {line.strip()!r}")
        where = lines.where()
        head = lines.next().split()
        if len(head) < 2 or not head[1].isdigit():
            raise InputError(f"{where}: expected a body type and number, found {' '.join(head)!r}")
        body = Body(head[0], int(head[1]), where, name=name)
        name = None
        bodies.append(body)
        while True:
            where, line = lines.where(), lines.next()
            key = _keyword(line)
            if key == "$$$$$$":
                break
            if key == "$blmty":
                text = lines.next()
                parts = text.split()
                if "behav" in parts:
                    body.behav = parts[parts.index("behav") + 1]
                while _continues(lines.peek()):
                    lines.next()  # inertia (I1, I2, I3): recomputed from the shape
            elif key == "$nodty":
                text = lines.next()
                while _continues(lines.peek()):
                    text += " " + lines.next()
                values = _pairs(text, where)
                body.node = [values[f"coo{k}"] for k in range(1, 7) if f"coo{k}" in values]
            elif key == "$tacty":
                while _keyword(lines.peek()) is None:
                    body.contactors.append(_read_contactor(lines))
            else:
                raise InputError(f"{where}: unexpected {line.strip()!r} in the record of "
                                 f"{body.type} {body.number} (expected $blmty, $nodty, $tacty "
                                 "or $$$$$$)")
    return bodies, groups


def _read_contactor(lines: _Lines) -> Contactor:
    where = lines.where()
    text = lines.next()
    parts = text.split()
    kind = parts[0]
    colour = parts[parts.index("color") + 1] if "color" in parts else ""
    tact = Contactor(kind, colour, where, _pairs(text, where))
    if kind == "POLYF":
        _read_patches(lines, tact)
        return tact
    while _continues(lines.peek()):
        lw = lines.where()
        values = _pairs(lines.next(), lw)
        if "ver1" in values:
            tact.faces.append(_triangle(values, lw, None))
        elif "coo1" in values and kind in ("POLYG", "POLYR"):
            tact.vertices.append([values[f"coo{k}"] for k in (1, 2, 3) if f"coo{k}" in values])
        else:
            tact.values.update(values)
    return tact


def _count_of(values: dict[str, float], keys: tuple[str, ...], least: int, where: Where,
              what: str) -> int:
    """The integer value >= least of the first of `keys` in values; InputError if none."""
    key = next((k for k in keys if k in values), None)
    value = values.get(key, math.nan)
    if not (math.isfinite(value) and value >= least and value == int(value)):
        raise InputError(f"{where}: {what} needs {keys[0]}= an integer >= {least}, found "
                         + (f"{value:g}" if key else "none"))
    return int(value)


def _triangle(values: dict[str, float], where: Where, vertices: int | None,
              what: str = "a triangle") -> list[int]:
    """The vertex numbers ver1..3 of a triangle line (from 1; at most `vertices`)."""
    ver = [values.get(f"ver{k}", math.nan) for k in (1, 2, 3)]
    top = math.inf if vertices is None else vertices
    if not all(math.isfinite(v) and 1 <= v <= top and v == int(v) for v in ver):
        raise InputError(f"{where}: {what} needs ver1= ver2= ver3=, vertex numbers from 1"
                         + ("" if vertices is None else f" to {vertices}")
                         + f", found {', '.join(f'{v:g}' for v in ver)}")
    return [int(v) for v in ver]


def _patch_line(lines: _Lines, tact: Contactor, what: str) -> tuple[dict[str, float], Where]:
    """The next line of a POLYF's patches, as key = value pairs; InputError naming what was
    expected if the entry ends there."""
    where = lines.where()
    if not _continues(lines.peek()):
        found = lines.peek()
        raise InputError(f"{where}: the POLYF of {tact.where} ends before {what} "
                         + (f"(found {found.strip()!r})" if found is not None else
                            "(the file ends)"))
    return _pairs(lines.next(), where), where


def _read_patches(lines: _Lines, tact: Contactor) -> None:
    """A POLYF's patches, read by their counts as LMGC90 does (read_BDARY_POLYF)."""
    count = _count_of(tact.values, ("nb_patch",), 1, tact.where, "a POLYF")
    for p in range(1, count + 1):
        values, where = _patch_line(lines, tact, f"patch {p} of {count} (its line "
                                    "nb_vertex= nb_faces=)")
        what = f"patch {p} of the POLYF of {tact.where}"
        nv = _count_of(values, ("nb_vertex",), 3, where, what)
        nf = _count_of(values, ("nb_faces", "nb_face"), 1, where, what)
        patch = Patch(where)
        for k in range(1, nv + 1):
            values, w = _patch_line(lines, tact, f"vertex {k} of {nv} of patch {p}")
            if not all(f"coo{i}" in values for i in (1, 2, 3)):
                raise InputError(f"{w}: vertex {k} of {nv} of {what} needs coo1= coo2= coo3=")
            patch.vertices.append([values[f"coo{i}"] for i in (1, 2, 3)])
        for k in range(1, nf + 1):
            values, w = _patch_line(lines, tact, f"triangle {k} of {nf} of patch {p}")
            patch.faces.append(_triangle(values, w, nv, f"triangle {k} of {nf} of {what}"))
        tact.patches.append(patch)
    if _continues(lines.peek()):
        raise InputError(f"{lines.where()}: the POLYF of {tact.where} has {count} patches "
                         f"(nb_patch=), which end before this line: {lines.peek().strip()!r}")


def _body_key(lines: _Lines, bodies: dict[tuple[str, int], Body], what: str
              ) -> tuple[str, int]:
    """The (type, number) of the body a record of DOF.INI or DRV_DOF.DAT is about; an
    InputError if BODIES.DAT has no such body."""
    where = lines.where()
    head = lines.next().split()
    if len(head) < 2 or not head[1].isdigit():
        raise InputError(f"{where}: expected a body type and number, found {' '.join(head)!r}")
    key = (head[0], int(head[1]))
    if key not in bodies:
        raise InputError(f"{where}: {what} {head[0]} {head[1]}, which BODIES.DAT does not "
                         "have; are the files of the same model?")
    return key


def _read_dof(path: Path, bodies: dict[tuple[str, int], Body]) -> None:
    lines = _Lines(path)
    while lines.peek() is not None:
        if _keyword(lines.next()) != "$bdyty":
            continue  # $steps, separators
        bwhere = lines.where()
        body = bodies[_body_key(lines, bodies, "DOF.INI gives")]
        text = ""
        while (nxt := lines.peek()) is not None and _keyword(nxt) != "$$$$$$":
            text += " " + lines.next()
        lines.next()
        values = _pairs(text, bwhere)
        n = 3 if body.type == "RBDY2" else 6
        try:
            body.displacement = [values[f"X({k})"] for k in range(1, n + 1)]
            body.velocity = [values[f"V({k})"] for k in range(1, n + 1)]
            if n == 6:
                body.frame = [[values[f"{a}({k})"] for k in (1, 2, 3)] for a in "abg"]
        except KeyError as err:
            raise InputError(f"{bwhere}: {body.type} {body.number} lacks {err.args[0]}") from None
        body.dof_where = bwhere


def _read_drives(path: Path, bodies: dict[tuple[str, int], Body]
                 ) -> dict[tuple[str, int], list[Drive]]:
    lines = _Lines(path)
    drives: dict[tuple[str, int], list[Drive]] = {}
    key = None
    while lines.peek() is not None:
        where, line = lines.where(), lines.next()
        word = _keyword(line)
        if word == "$bdyty":
            key = _body_key(lines, bodies, "DRV_DOF.DAT drives")
            drives.setdefault(key, [])
        elif word in ("$nodty", "$dofty", "$$$$$$"):
            if word == "$nodty":
                lines.next()
        elif key is not None and word is None:
            parts = line.split()
            if len(parts) >= 8:
                drives[key].append(Drive(parts[0], int(parts[1]), where,
                                         tuple(number(p, where) for p in parts[2:8])))
            elif len(parts) >= 3 and parts[2].lower() == "evolution":
                drives[key].append(Drive(parts[0], int(parts[1]), where,
                                         evolution=parts[3] if len(parts) > 3 else ""))
            else:
                raise InputError(f"{where}: cannot read the imposed dof {line.strip()!r} "
                                 "(expected: vlocy DOF CT AMP OMEGA PHI RAMPI RAMP)")
    return drives


def _read_bulk(path: Path):
    lines = _Lines(path)
    gravity = [0.0, 0.0, 0.0]
    densities: dict[str, tuple[float, Where]] = {}
    kinds: dict[str, tuple[str, Where]] = {}
    while lines.peek() is not None:
        where, line = lines.where(), lines.next()
        word = _keyword(line)
        if word == "$gravy":
            values = _pairs(lines.next(), where)
            gravity = [values.get(f"grv{k}", 0.0) for k in (1, 2, 3)]
        elif word == "$behav":
            while (nxt := lines.peek()) is not None and _keyword(nxt) is None:
                w = lines.where()
                parts = lines.next().split()
                if len(parts) >= 2 and "=" not in parts[0]:
                    kinds[parts[0]] = (parts[1], w)
                    values = _pairs(" ".join(parts[2:]), w)
                    if "Umas" in values:
                        densities[parts[0]] = (values["Umas"], w)
    return gravity, densities, kinds


def _read_tact(path: Path) -> tuple[dict[str, LawEntry], list[SeeTable]]:
    lines = _Lines(path)
    laws: dict[str, LawEntry] = {}
    tables: list[SeeTable] = []
    while lines.peek() is not None:
        word = _keyword(lines.next())
        if word == "$behav":
            entry = None
            while (nxt := lines.peek()) is not None and _keyword(nxt) is None:
                w = lines.where()
                text = lines.next()
                parts = text.split()
                if entry is None or (len(parts) >= 2 and "=" not in parts[0]
                                     and "=" not in parts[1]):
                    if len(parts) < 2:
                        raise InputError(f"{w}: expected a law's name and type, found "
                                         f"{text.strip()!r}")
                    entry = LawEntry(parts[0], parts[1], w, _pairs(" ".join(parts[2:]), w))
                    laws[entry.name] = entry
                else:
                    entry.values.update(_pairs(text, w))
        elif word == "$seety":
            while (nxt := lines.peek()) is not None and _keyword(nxt) is None:
                w = lines.where()
                parts = lines.next().split()
                if parts[:3] == ["cdbdy", "cdtac", "cdcol"]:
                    continue
                if len(parts) < 8:
                    raise InputError(f"{w}: a see-table line needs cdbdy cdtac cdcol behav "
                                     f"anbdy antac ancol alert, found {' '.join(parts)!r}")
                tables.append(SeeTable(tuple(parts[0:3]), parts[3], tuple(parts[4:7]),
                                       number(parts[7], w), w))
    return laws, tables


def _count(path: Path, keyword: str) -> list[Where]:
    if not path.is_file():
        return []
    lines = _Lines(path)
    return [Where(lines.file, n) for n, text in lines.items if _keyword(text) == keyword]


def read_datbox(folder: str | Path) -> Datbox:
    """Read a DATBOX folder (module doc); raises InputError naming the file and line of
    anything it cannot read, or a missing BODIES.DAT / TACT_BEHAV.DAT."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(f"{folder}: no such DATBOX folder")
    for required in ("BODIES.DAT", "TACT_BEHAV.DAT"):
        if not (folder / required).is_file():
            raise InputError(f"{folder}: no {required}; a DATBOX folder holds BODIES.DAT, "
                             "BULK_BEHAV.DAT, TACT_BEHAV.DAT and optionally DOF.INI, "
                             "DRV_DOF.DAT, Vloc_Rloc.INI")
    bodies, groups = _read_bodies(folder / "BODIES.DAT")
    index: dict[tuple[str, int], Body] = {}
    for body in bodies:
        if body.key in index:
            raise InputError(f"{body.where}: {body.type} {body.number} is defined twice "
                             f"(also at {index[body.key].where})")
        index[body.key] = body
    if (folder / "DOF.INI").is_file():
        _read_dof(folder / "DOF.INI", index)
    drives = (_read_drives(folder / "DRV_DOF.DAT", index)
              if (folder / "DRV_DOF.DAT").is_file() else {})
    gravity, densities, kinds = ((_read_bulk(folder / "BULK_BEHAV.DAT"))
                                 if (folder / "BULK_BEHAV.DAT").is_file() else
                                 ([0.0, 0.0, 0.0], {}, {}))
    laws, tables = _read_tact(folder / "TACT_BEHAV.DAT")
    return Datbox(folder, bodies, drives, gravity, densities, kinds, laws, tables, groups,
                  models=_count(folder / "MODELS.DAT", "$model"))
