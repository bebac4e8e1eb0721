"""Translate an LMGC90 model (saxum.lmgc90.reader.Datbox) into a saxum model or scenario.

Bodies: a body's contactor is its block: POLYG -> a convex polygon, POLYR -> the convex hull
of its vertices, POLYF (a surface in patches, which LMGC90 joins into one POLYR) -> the convex
hull of its patches' vertices, if their triangles bound it (else an error: a non-convex
POLYF); a body with several POLYG (POLYR, POLYF) contactors of one colour, LMGC90's cluster
(a non-convex block cut into convex parts) -> a cluster (ModelBuilder.add_cluster: one rigid
body, its parts its contactors); DISKx -> a disc and SPHER -> a sphere of radius `byrd`
centred at the node (ModelBuilder.add_disc, add_sphere; a shifted one, `coo1=`..., is
refused: its centre would not be the centre of mass); JONCx (2D) -> a capsule (stadium) with
a segment 2 ax1 long and ends of radius ax2 (LMGC90's mod_a_BDARY_JONCx.f90 gives it the area
4 ax1 ax2 + pi ax2^2), along the body's x axis turned by X(3) (ModelBuilder.add_capsule);
PLANx (3D) -> the box 2 axe1 x 2 axe2 x 2 axe3, listed as approximated (a PLANx is a contact
plane). Positions: node coordinates + DOF.INI's X (2D: rotation by X(3); 3D: the frame a, b,
g). The group of a block is its contactor's colour.

Impulses (a Vloc_Rloc file, saxum.lmgc90.vlocrloc): the first step's warm start
(Lmgc90Import.warm_start, saxum.warmstart): each contact's mean force rl/H on the bodies
and point it names, matched to saxum's contacts there.

Drives (DRV_DOF.DAT): a body whose every dof is imposed becomes FIXED (all zero) or DRIVEN;
saxum drives all dofs of a body or none, so a body with only some dofs imposed stays FREE
and its imposed dofs are listed as not translated, as are imposed forces and evolution files.

Laws (TACT_BEHAV.DAT): IQS_CLB -> SIGNORINI_COULOMB, GAP_SGR_CLB -> GAP_SIGNORINI_COULOMB,
RST_CLB -> RESTITUTION_COULOMB (rstn), each with the see-table's alert (ContactLaw.alert);
IQS_CLB_g0 and GAP_SGR_CLB_g0 -> the same with ContactLaw.initial_gap (saxum.laws), the
dynamic-static (_DS_) ones approximated and listed. A pair of colours
without a see-table gets NO_CONTACT (LMGC90 never detects it). LMGC90's see-tables are
ordered (candidate, antagonist), saxum's laws are per unordered pair: two see-tables of one
pair with different laws are an error.
"""

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..detection import DetectionSettings, detector_for
from ..errors import InputError, OverlapError
from ..geometry3d import rotation_matrix
from ..laws import NO_CONTACT, ContactLaw, LawKind, NoContact
from ..model import BodyKind, Model, ModelBuilder
from ..warmstart import ContactForce, apply_warm_start, write_warm_start
from .reader import Body, Datbox, Drive, LawEntry, Where, read_datbox
from .vlocrloc import VlocEntry, read_vloc_rloc

__all__ = ["LAW_TYPES", "OVERLAP_TOLERANCE", "Lmgc90Import", "Untranslated", "import_lmgc90"]

OVERLAP_TOLERANCE = 1e-5
"""[m] Default deepest interpenetration accepted in an imported state: LMGC90 states at rest
carry micrometre interpenetrations (its Wall_PR example's DOF.INI: bricks 1.0e-6 m into the
ground); 10 um accepts them with a margin and refuses any overlap a drawing would show."""

LAW_TYPES = {"IQS_CLB": LawKind.SIGNORINI_COULOMB, "IQS_CLB_g0": LawKind.SIGNORINI_COULOMB,
             "IQS_DS_CLB": LawKind.SIGNORINI_COULOMB,
             "GAP_SGR_CLB": LawKind.GAP_SIGNORINI_COULOMB,
             "GAP_SGR_CLB_g0": LawKind.GAP_SIGNORINI_COULOMB,
             "GAP_SGR_DS_CLB": LawKind.GAP_SIGNORINI_COULOMB,
             "RST_CLB": LawKind.RESTITUTION_COULOMB, "RST_DS_CLB": LawKind.RESTITUTION_COULOMB}
"""LMGC90 contact laws saxum translates, and their saxum kind."""

CONTACTORS = {"RBDY2": ("POLYG", "JONCx", "DISKx"),
              "RBDY3": ("POLYR", "POLYF", "PLANx", "SPHER")}
"""Contactors translated per body type."""

POLYHEDRA = {"RBDY2": ("POLYG",), "RBDY3": ("POLYR", "POLYF")}
"""The contactors a cluster's parts may be, per body type."""

POLYF_TOLERANCE = 1e-5
"""A POLYF is convex if each of its triangles lies in the boundary of the patches' convex
hull to within this fraction of the hull's size, and their areas add up to the hull's to
within this fraction of it: LMGC90's 7 significant digits move a vertex by less than 1e-7
of the block's size, a margin of 100 for the planes of small triangles; a real re-entrant
corner or a missing patch is far beyond it."""


@dataclass(frozen=True)
class Untranslated:
    """Something of the DATBOX that the translation leaves out or approximates."""

    what: str
    where: Where | str

    def __str__(self) -> str:
        return f"{self.where}: {self.what}"


@dataclass
class Block:
    """A translated body: world vertices [m] (a disc or sphere: its centre, one row, and
    its radius [m] > 0), velocity in world axes (2D: vx, vy, omega; 3D: vx, vy, vz, wx, wy,
    wz [m/s, rad/s]), and for a DRIVEN block its imposed dofs."""

    name: str
    group: str
    kind: BodyKind
    density: float
    vertices: np.ndarray
    velocity: np.ndarray
    drives: list[Drive] = field(default_factory=list)
    radius: float = 0.0
    length: float = 0.0
    """> 0: a capsule (JONCx): its segment's length [m], `radius` its ends' [m], `angle` the
    segment's direction [rad] from the x axis, `vertices` its centre."""
    angle: float = 0.0
    parts: list[np.ndarray] = field(default_factory=list)
    """A cluster's convex parts, world vertices [m] of each (empty: a single contactor);
    `vertices` then holds them all."""

    def motion(self, t: float) -> tuple[float, ...]:
        """The imposed velocity at time t [s] (DRIVEN blocks)."""
        return tuple(d.value(t) for d in self.drives)


@dataclass
class Lmgc90Import:
    """An LMGC90 model translated: blocks, laws per pair of groups (ContactLaw or
    NO_CONTACT), gravity [m/s^2], and what was not translated (`untranslated`)."""

    folder: Path
    dim: int
    gravity: tuple[float, ...]
    blocks: list[Block]
    laws: dict[tuple[str, str], ContactLaw | NoContact]
    untranslated: list[Untranslated]
    no_contact: list[tuple[str, str]]
    """Pairs of groups without a see-table: NO_CONTACT."""
    impulses: list[VlocEntry] = field(default_factory=list)
    """The contacts of the Vloc_Rloc file (`impulses_file`): the first step's warm start."""
    impulses_file: Path | None = None
    body_names: dict[tuple[str, int], str] = field(default_factory=dict)
    """(body type, number) -> block name."""

    def builder(self) -> ModelBuilder:
        """A ModelBuilder with the blocks (driven ones following their DRV_DOF formula
        exactly), the laws and gravity."""
        b = ModelBuilder(gravity=self.gravity, dim=self.dim)
        for blk in self.blocks:
            common = dict(density=blk.density, group=blk.group, kind=blk.kind, name=blk.name,
                          motion=blk.motion if blk.kind == BodyKind.DRIVEN else None)
            if blk.length > 0.0:
                b.add_capsule(blk.vertices[0], blk.length, blk.radius, angle=blk.angle,
                              **common)
            elif blk.radius > 0.0:
                add = b.add_disc if self.dim == 2 else b.add_sphere
                add(blk.vertices[0], blk.radius, **common)
            elif blk.parts:
                b.add_cluster(blk.parts, **common)
            else:
                b.add_block(blk.vertices, **common)
        for (a, c), law in self.laws.items():
            b.set_law(a, c, law)
        return b

    def model(self) -> Model:
        """The saxum Model."""
        return self.builder().finalize()

    def set_initial_velocities(self, model: Model, state) -> None:
        """Give the free blocks of `state` (a saxum.state.State of `model`, e.g.
        Simulation.initial_state()) DOF.INI's velocities, in saxum's layout (3D: the angular
        velocity in the body frame); fixed and driven blocks keep theirs (their drives')."""
        v = np.array([blk.velocity for blk in self.blocks], dtype=np.float64)
        if self.dim == 3:
            r = rotation_matrix(model.body_q0[:, 3:])
            v[:, 3:] = np.einsum("bji,bj->bi", r, v[:, 3:])
        free = model.body_kind == BodyKind.FREE
        state.body_v[free] = v[free]

    def contact_forces(self) -> tuple[list[ContactForce], list[Untranslated]]:
        """The Vloc_Rloc file's contacts with impulses (not the open ones, all 0: a warm start
        from 0 is no warm start) as mean forces [N] on the candidate in world axes
        (saxum.warmstart), and those that cannot be: a body the model lacks, no normal or
        frame (n lines; 3D also t, s), no point (coo lines)."""
        forces, notes = [], []
        for e in self.impulses:
            if e.zero:
                continue
            a, c = (self.body_names.get(x[:2]) for x in (e.candidate, e.antagonist))
            force, point = e.force(self.dim), e.point(self.dim)
            why = ("a body the model does not have" if a is None or c is None else
                   "no frame (n(k)= lines; 3D also t(k)=, s(k)=)" if force is None else
                   "no contact point (coo lines)" if point is None else None)
            if why:
                notes.append(Untranslated(f"contact {e.module} {e.candidate[0]} "
                                          f"{e.candidate[1]} - {e.antagonist[0]} "
                                          f"{e.antagonist[1]}: {why}; not a warm start",
                                          e.where))
                continue
            forces.append(ContactForce(a, c, tuple(point.tolist()), tuple(force.tolist()),
                                       str(e.where)))
        return forces, notes

    def warm_start(self, sim, state) -> tuple[list[ContactForce], list[Untranslated]]:
        """Give `state` (sim's, before its first step) the Vloc_Rloc file's impulses as the
        first step's warm start (saxum.warmstart.apply_warm_start: R = F dt); returns the
        forces used and what was not: contacts that match none of saxum's (each with why)
        and those contact_forces cannot read. Open contacts (impulses 0) are neither."""
        forces, notes = self.contact_forces()
        unmatched = apply_warm_start(sim, state, forces)
        left = {id(f) for f, _ in unmatched}
        notes += [Untranslated(f"contact {f.candidate!r} - {f.antagonist!r}: {why}; it "
                               "starts from zero", f.source) for f, why in unmatched]
        return [f for f in forces if id(f) not in left], notes

    def deepest_overlap(self, model: Model) -> tuple[float, str, str]:
        """The deepest interpenetration at the start [m] and the two blocks (0 if none)."""
        detector = detector_for(model, DetectionSettings())
        probe = detector.contacts_at(model.body_q0)
        if probe.count == 0:
            return 0.0, "", ""
        k = int(np.argmin(probe.gap[:probe.count]))
        depth = max(0.0, -float(probe.gap[k]))
        return (depth, model.body_name[probe.candidate[k]], model.body_name[probe.antagonist[k]])

    def check_overlaps(self, model: Model, tolerance: float = OVERLAP_TOLERANCE) -> float:
        """Raise OverlapError if two blocks interpenetrate deeper than tolerance [m]; return
        the deepest interpenetration [m]."""
        depth, a, c = self.deepest_overlap(model)
        if depth > tolerance:
            raise OverlapError(f"blocks {a!r} and {c!r} overlap by {depth:.3g} m in the "
                               f"imported state, more than the tolerance {tolerance:g} m: a "
                               "real overlap, not a solver's micrometre interpenetration "
                               "(raise --overlap-tolerance only if that is what it is)")
        return depth

    def write_scenario(self, path: str | Path, *, duration: float = 1.0, dt: float = 1e-3,
                       overlap_tolerance: float = OVERLAP_TOLERANCE,
                       warm_start: Sequence[ContactForce] = ()) -> list[Untranslated]:
        """Write the scenario `path` (TOML) and its blocks file (`<stem>.blocks.json` next to
        it), and with `warm_start` (contact forces, e.g. from Lmgc90Import.warm_start) the
        first step's warm start (`<stem>.impulses.json`, key solver.warm_start); returns
        what the scenario cannot hold beyond `untranslated` (time-varying drives, written as
        their velocity at t = 0; initial velocities). A driven block is a settlement at its
        constant velocity over `duration` [s]."""
        path = Path(path)
        blocks_path = path.with_name(path.stem + ".blocks.json")
        impulses_path = path.with_name(path.stem + ".impulses.json")
        extra = []
        rows = []
        for blk in self.blocks:
            row = {"name": blk.name, "group": blk.group,
                   "kind": "free" if blk.kind == BodyKind.FREE else "fixed"}
            if blk.length > 0.0:
                row.update(centre=blk.vertices[0].tolist(), length=blk.length,
                           radius=blk.radius, angle=blk.angle)
            elif blk.radius > 0.0:
                row.update(centre=blk.vertices[0].tolist(), radius=blk.radius)
            elif blk.parts:
                row["parts"] = [part.tolist() for part in blk.parts]
            else:
                row["vertices"] = blk.vertices.tolist()
            if blk.kind == BodyKind.FREE:
                row["density"] = blk.density
            rows.append(row)
            if blk.kind == BodyKind.FREE and np.any(blk.velocity != 0.0):
                extra.append(Untranslated(
                    f"{blk.name}: initial velocity {_vector(blk.velocity)} (scenarios start "
                    "at rest; Lmgc90Import.set_initial_velocities sets it in Python)",
                    "DOF.INI"))
        blocks_path.write_text(json.dumps({"blocks": rows}, indent=1), encoding="utf-8")
        lines = ["", f"title = {_string('LMGC90 ' + self.folder.resolve().parent.name)}", "",
                 "[structure]", 'type = "blocks"', f"file = {_string(blocks_path.name)}", "",
                 "[loads]", f"gravity = {_vector(self.gravity)}"]
        for blk in self.blocks:
            if blk.kind != BodyKind.DRIVEN:
                continue
            v = np.array(blk.motion(0.0))
            varying = [d for d in blk.drives if not d.constant]
            if varying:
                extra.append(Untranslated(f"{blk.name}: a time-varying drive, written as its "
                                          f"velocity at t = 0, {_vector(v)}", varying[0].where))
            lines += self._settlement(blk.name, v, duration)
        for (a, c), law in self.laws.items():
            lines += ["", "[[laws]]", f"groups = [{_string(a)}, {_string(c)}]"]
            if isinstance(law, NoContact):
                lines += ['kind = "none"  # no see-table: LMGC90 never detects these pairs']
                continue
            lines += [f'kind = "{law.kind.name.lower()}"', f"friction = {law.friction!r}"]
            if law.kind == LawKind.RESTITUTION_COULOMB:
                lines += [f"restitution = {law.restitution!r}"]
            if law.initial_gap:
                lines += ["initial_gap = true  # a _g0 law"]
            lines += [f"alert = {law.alert!r}"]
        lines += ["", "[solver]", f"dt = {dt!r}"]
        if warm_start:
            write_warm_start(impulses_path, warm_start)
            lines += [f"warm_start = {_string(impulses_path.name)}  # {len(warm_start)} "
                      f"contacts of {self.impulses_file}"]
        lines += ["", "[detection]",
                  f"initial_overlap = {overlap_tolerance!r}", "", "[output]",
                  f"duration = {duration!r}", ""]
        head = [f"# Imported from the LMGC90 DATBOX {self.folder} by saxum import-lmgc90.",
                "# Not translated or approximated:"]
        head += [f"#   {item}" for item in [*self.untranslated, *extra]] or ["#   nothing"]
        path.write_text("\n".join(head + lines), encoding="utf-8")
        return extra

    def _settlement(self, name: str, v: np.ndarray, duration: float) -> list[str]:
        move, turn = v[:self.dim], v[self.dim:]
        speed = float(np.linalg.norm(move))
        rows = ["", "[[loads.settlements]]  # DRV_DOF.DAT: an imposed velocity",
                f"block = {_string(name)}", f"magnitude = {speed * duration!r}"]
        if speed > 0.0:
            rows.append(f"direction = {_vector(move / speed)}")
        rotation = turn * duration
        if np.any(rotation != 0.0):
            turned = _vector(rotation) if self.dim == 3 else repr(float(rotation[0]))
            rows.append(f"rotation = {turned}")
        rows.append(f"time = {duration!r}")
        return rows


def _string(text: str) -> str:
    return json.dumps(text)


def _vector(values: Sequence[float]) -> str:
    return "[" + ", ".join(repr(float(x)) for x in values) + "]"


def _local_shape(body: Body, problems: list[str], notes: list[Untranslated]
                 ) -> tuple[list[np.ndarray], float, float] | None:
    """The vertices in the body frame [m] of each of the body's contactors (a disc, sphere
    or capsule: its centre, the origin), the radius [m] (0: polygons) and a capsule's
    segment length [m] (0: not a capsule), or None (a problem is recorded). Several
    contactors: a cluster, which they must all be polygons (polyhedra) of one colour."""
    if not body.contactors:
        problems.append(f"{body.where}: {body.type} {body.number} has no contactor")
        return None
    if len(body.contactors) == 1:
        shape = _contactor_shape(body, body.contactors[0], problems, notes)
        return None if shape is None else ([shape[0]], shape[1], shape[2])
    polygon = POLYHEDRA[body.type]
    kinds = sorted({t.kind for t in body.contactors})
    colours = sorted({t.colour for t in body.contactors})
    mixed = not set(kinds) <= set(polygon)
    if mixed or len(colours) > 1:
        what = (f"contactors {', '.join(kinds)}" if mixed else
                f"contactors of colours {', '.join(colours)}")
        problems.append(f"{body.where}: {body.type} {body.number} is a cluster of "
                        f"{len(body.contactors)} contactors with {what}; saxum translates "
                        f"a cluster whose contactors are all {' or '.join(polygon)} of one "
                        "colour (one group per block)")
        return None
    parts = [_contactor_shape(body, tact, problems, notes) for tact in body.contactors]
    if any(part is None for part in parts):
        return None
    return [part[0] for part in parts], 0.0, 0.0


def _contactor_shape(body: Body, tact, problems: list[str], notes: list[Untranslated]
                     ) -> tuple[np.ndarray, float, float] | None:
    """One contactor's vertices in the body frame [m], radius [m] and a capsule's segment
    length [m], as _local_shape; None if it cannot be translated (a problem is recorded)."""
    allowed = CONTACTORS[body.type]
    if tact.kind not in allowed:
        problems.append(f"{tact.where}: contactor {tact.kind} of {body.type} {body.number} is "
                        f"not translated (translated: {', '.join(allowed)})")
        return None
    v = tact.values
    if tact.kind in ("POLYG", "POLYR"):
        dim = 2 if tact.kind == "POLYG" else 3
        pts = np.array(tact.vertices, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != dim or len(pts) != int(v.get("nb_vertex", len(pts))):
            problems.append(f"{tact.where}: {tact.kind} of {body.type} {body.number}: expected "
                            f"{int(v.get('nb_vertex', 0))} vertices of {dim} coordinates")
            return None
        return pts, 0.0, 0.0
    if tact.kind == "POLYF":
        pts = _polyf_vertices(body, tact, problems)
        return None if pts is None else (pts, 0.0, 0.0)
    if tact.kind in ("DISKx", "SPHER"):
        dim = 2 if tact.kind == "DISKx" else 3
        r = v.get("byrd", 0.0)
        shift = [k for k in ("coo1", "coo2", "coo3") if v.get(k, 0.0) != 0.0]
        if not (math.isfinite(r) and r > 0.0) or shift:
            what = (f"a shift {', '.join(shift)} from the node (saxum's discs and spheres are "
                    "centred at their centre of mass)" if shift else
                    f"byrd = {r:g}, not a radius > 0 [m]")
            problems.append(f"{tact.where}: {tact.kind} of {body.type} {body.number} has {what}")
            return None
        return np.zeros((1, dim)), r, 0.0
    if tact.kind == "JONCx":  # mod_a_BDARY_JONCx.f90: area 4 ax1 ax2 + pi ax2^2
        a, r = v.get("ax1", 0.0), v.get("ax2", 0.0)
        if not (math.isfinite(a) and math.isfinite(r) and a > 0.0 and r > 0.0):
            problems.append(f"{tact.where}: JONCx of {body.type} {body.number} has ax1 = "
                            f"{a:g}, ax2 = {r:g}; a JONCx needs both > 0 [m] (ax1 its "
                            "segment's half-length, ax2 its radius)")
            return None
        return np.zeros((1, 2)), r, 2.0 * a
    a, b, c = (v.get(f"axe{k}", 0.0) for k in (1, 2, 3))
    notes.append(Untranslated(f"PLANx of {body.type} {body.number}: taken as the box "
                              f"{2 * a:g} x {2 * b:g} x {2 * c:g} m", tact.where))
    return (np.array([(x, y, z) for x in (-a, a) for y in (-b, b) for z in (-c, c)]), 0.0,
            0.0)


def _polyf_vertices(body: Body, tact, problems: list[str]) -> np.ndarray | None:
    """The vertices [m] (body frame) of a convex POLYF's hull: LMGC90 joins the patches'
    triangles into one surface (read_BDARY_POLYF); it is convex if every triangle lies in
    the boundary of the hull of all the vertices (its centroid no deeper inside than
    POLYF_TOLERANCE of the hull's size: a triangle whose centroid is on a supporting plane
    lies in it) and the triangles cover that boundary (their areas add up to the hull's).
    None if not (a problem is recorded, naming the patch)."""
    from scipy.spatial import ConvexHull, QhullError  # as geometry3d: a 2D import skips it

    pts = np.array([v for patch in tact.patches for v in patch.vertices], dtype=np.float64)
    first = np.cumsum([0] + [len(patch.vertices) for patch in tact.patches])
    tris = np.array([np.array(face) - 1 + first[k] for k, patch in enumerate(tact.patches)
                     for face in patch.faces], dtype=np.int64)
    owner = np.repeat(np.arange(len(tact.patches)), [len(p.faces) for p in tact.patches])
    name = f"POLYF of {body.type} {body.number}"
    try:
        hull = ConvexHull(pts)
    except QhullError:
        problems.append(f"{tact.where}: {name}: its vertices lie in one plane (no volume)")
        return None
    size = float(np.ptp(pts, axis=0).max())
    corners = pts[tris]
    centroids = corners.mean(axis=1)
    depth = -(centroids @ hull.equations[:, :3].T + hull.equations[:, 3]).max(axis=1)
    k = int(np.argmax(depth))
    if depth[k] > POLYF_TOLERANCE * size:
        p = int(owner[k])
        problems.append(
            f"{tact.patches[p].where}: {name} is not convex: triangle "
            f"{k - int(np.searchsorted(owner, p)) + 1} of its patch {p + 1} (this line) lies "
            f"{depth[k]:.3g} m inside the convex hull of "
            "its patches; saxum takes a convex POLYF as one polyhedron: give a non-convex "
            "block as convex parts, each a POLYF or POLYR contactor of the body, of one "
            "colour (a cluster)")
        return None
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0],
                                         corners[:, 2] - corners[:, 0]), axis=1).sum()
    if abs(area - hull.area) > POLYF_TOLERANCE * hull.area:
        problems.append(f"{tact.where}: {name}: its triangles' area, {area:.6g} m^2, is not "
                        f"that of the solid they bound, {hull.area:.6g} m^2: a patch is "
                        "missing or given twice (the patches must close the surface once)")
        return None
    return pts[hull.vertices]


def _place(body: Body, local: np.ndarray) -> np.ndarray:
    """World vertices [m]: node coordinates + DOF.INI's displacement and rotation."""
    dim = local.shape[1]
    node = np.zeros(dim)
    node[:min(dim, len(body.node))] = body.node[:dim]
    x = np.zeros(3 if dim == 2 else 6) if body.displacement is None else np.array(
        body.displacement)
    if dim == 2:
        c, s = math.cos(x[2]), math.sin(x[2])
        rot = np.array([[c, -s], [s, c]])
    else:
        rot = np.eye(3) if body.frame is None else np.array(body.frame).T
    return node + x[:dim] + local @ rot.T


def _law(entry: LawEntry, alert: float, notes: list[Untranslated], problems: list[str]):
    kind = LAW_TYPES.get(entry.type)
    if kind is None:
        problems.append(f"{entry.where}: contact law {entry.name!r} of type {entry.type} has "
                        f"no saxum equivalent (translated: {', '.join(LAW_TYPES)})")
        return None
    v = entry.values
    if "_DS_" in entry.type:
        mu = v.get("dyfr", 0.0)
        if v.get("stfr", mu) != mu:
            notes.append(Untranslated(f"law {entry.name!r} ({entry.type}): saxum has one "
                                      f"friction coefficient; the dynamic one, {mu:g}, is "
                                      f"used (static {v['stfr']:g} not translated)", entry.where))
    else:
        mu = v.get("fric")
        if mu is None:
            problems.append(f"{entry.where}: law {entry.name!r} ({entry.type}) has no fric=")
            return None
    restitution = 0.0
    if kind == LawKind.RESTITUTION_COULOMB:
        restitution = v.get("rstn", 0.0)
        if v.get("rstt", 0.0) != 0.0:
            notes.append(Untranslated(f"law {entry.name!r}: tangential restitution rstt = "
                                      f"{v['rstt']:g} (saxum's restitution is normal only)",
                                      entry.where))
    try:
        return ContactLaw(friction=mu, kind=kind, restitution=restitution, alert=alert,
                          name=f"{entry.name} ({entry.where})",
                          initial_gap=entry.type.endswith("_g0"))
    except InputError as err:
        problems.append(f"{entry.where}: law {entry.name!r}: {err}")
        return None


def _drives(body: Body, drives: list[Drive], n: int, notes: list[Untranslated]
            ) -> tuple[BodyKind, list[Drive]]:
    velocity = {d.dof: d for d in drives if d.what == "vlocy" and d.evolution is None}
    for d in drives:
        if d.what != "vlocy" or d.evolution is not None:
            what = (f"an evolution file {d.evolution!r}" if d.evolution is not None
                    else f"an imposed {d.what}")
            notes.append(Untranslated(f"{body.type} {body.number} dof {d.dof}: {what} "
                                      "(saxum imposes velocities given by a formula)", d.where))
    if not velocity:
        return BodyKind.FREE, []
    if sorted(velocity) != list(range(1, n + 1)):
        for d in velocity.values():
            notes.append(Untranslated(
                f"{body.type} {body.number}: only dofs {sorted(velocity)} of {n} are imposed; "
                "saxum drives all dofs of a body or none, so this body is FREE and its "
                f"imposed dof {d.dof} is left out", d.where))
        return BodyKind.FREE, []
    ordered = [velocity[k] for k in range(1, n + 1)]
    if all(d.zero for d in ordered):
        return BodyKind.FIXED, []
    return BodyKind.DRIVEN, ordered


def import_lmgc90(folder: str | Path, impulses: str | Path | None = None) -> Lmgc90Import:
    """Read and translate the DATBOX `folder` (module doc) and the contacts of `impulses`, a
    Vloc_Rloc file (default: DATBOX/Vloc_Rloc.INI, else OUTBOX/Vloc_Rloc.OUT beside the
    DATBOX, if there is one), the first step's warm start (Lmgc90Import.warm_start).
    Raises InputError listing, with file and line, every body type, contactor or law that
    cannot be translated, see-tables naming colours no body has or laws TACT_BEHAV does not
    define, and DOF.INI or DRV_DOF.DAT entries for bodies not in BODIES.DAT."""
    box = read_datbox(folder)
    if impulses is None:
        impulses = next((p for p in (box.folder / "Vloc_Rloc.INI",
                                     box.folder.parent / "OUTBOX" / "Vloc_Rloc.OUT")
                         if p.is_file()), None)
    elif not Path(impulses).is_file():
        raise InputError(f"{impulses}: no such Vloc_Rloc file")
    if impulses is None:
        return translate(box)
    return translate(box, read_vloc_rloc(Path(impulses)), Path(impulses))


def translate(box: Datbox, impulses: Sequence[VlocEntry] = (),
              impulses_file: Path | None = None) -> Lmgc90Import:
    """Translate a Datbox read by read_datbox, with the contacts of a Vloc_Rloc file
    (saxum.lmgc90.vlocrloc.read_vloc_rloc), see import_lmgc90."""
    problems: list[str] = []
    notes: list[Untranslated] = []
    types = {b.type for b in box.bodies}
    for b in box.bodies:
        if b.type not in CONTACTORS:
            problems.append(f"{b.where}: body type {b.type} ({b.type} {b.number}) is not "
                            "translated (translated: RBDY2, RBDY3 rigid bodies)")
    if not problems and len(types) > 1:
        problems.append(f"{box.folder / 'BODIES.DAT'}: RBDY2 and RBDY3 bodies in one model")
    if not box.bodies:
        problems.append(f"{box.folder / 'BODIES.DAT'}: no bodies")
    if problems:
        raise InputError(_listing(box, problems))
    dim = 2 if types == {"RBDY2"} else 3
    n = 3 * (dim - 1)
    blocks: list[Block] = []
    for body in box.bodies:
        shape = _local_shape(body, problems, notes)
        if shape is None:
            continue
        parts, radius, length = shape
        kind, drives = _drives(body, box.drives.get(body.key, []), n, notes)
        density = 0.0
        if kind == BodyKind.FREE:
            if body.behav not in box.densities:
                problems.append(
                    f"{body.where}: {body.type} {body.number}: bulk law {body.behav!r} has no "
                    "density (Umas) in BULK_BEHAV.DAT" + (
                        f" (it is a {box.bulk_laws[body.behav][0]} law; saxum's blocks are "
                        "RIGID)" if body.behav in box.bulk_laws else ""))
            else:
                density = box.densities[body.behav][0]
        velocity = np.zeros(n) if body.velocity is None else np.array(body.velocity, float)
        if dim == 3 and body.frame is not None:
            velocity[3:] = np.array(body.frame).T @ velocity[3:]  # LMGC90: body axes
        colour = body.contactors[0].colour
        placed = [_place(body, local) for local in parts]
        blocks.append(Block(body.name or f"{body.type} {body.number}",
                            box.groups.get(colour, colour), kind, density,
                            np.concatenate(placed), velocity, drives, radius, length,
                            0.0 if body.displacement is None else body.displacement[2],
                            placed if len(placed) > 1 else []))
    laws, no_contact = _laws(box, blocks, notes, problems)
    if problems:
        raise InputError(_listing(box, problems))
    if impulses_file is not None and impulses_file.suffix.upper() == ".OUT":
        notes.append(Untranslated("the impulses are LMGC90's output (Vloc_Rloc.OUT): DOF.INI "
                                  "must hold the positions of the same step (its DOF.OUT)",
                                  str(impulses_file)))
    notes += [Untranslated("a model of deformable bodies (MODELS.DAT is for MAILx bodies)", w)
              for w in box.models]
    gravity = tuple(box.gravity[:dim])
    names = {b.key: blk.name for b, blk in zip(box.bodies, blocks, strict=True)}
    return Lmgc90Import(box.folder, dim, gravity, blocks, laws, notes, no_contact,
                        list(impulses), impulses_file, names)


def _laws(box: Datbox, blocks: list[Block], notes: list[Untranslated], problems: list[str]):
    groups = {blk.group for blk in blocks}
    by_colour = {c: box.groups.get(c, c) for c in {b.contactors[0].colour for b in box.bodies
                                                     if b.contactors}}
    laws: dict[frozenset, tuple[ContactLaw, Where]] = {}
    for table in box.see_tables:
        missing = [c for c in (table.candidate[2], table.antagonist[2]) if c not in by_colour]
        if missing:
            problems.append(f"{table.where}: the see-table names colour {missing[0]!r}, which "
                            f"no body has (colours: {', '.join(sorted(by_colour))})")
            continue
        if table.law not in box.laws:
            problems.append(f"{table.where}: the see-table names law {table.law!r}, which "
                            "TACT_BEHAV.DAT does not define")
            continue
        law = _law(box.laws[table.law], table.alert, notes, problems)
        if law is None:
            continue
        key = frozenset((by_colour[table.candidate[2]], by_colour[table.antagonist[2]]))
        if key in laws and laws[key][0] != law:
            problems.append(f"{table.where}: colours {table.candidate[2]} and "
                            f"{table.antagonist[2]} already have another law or alert "
                            f"({laws[key][1]}); saxum has one law per pair of groups")
            continue
        laws.setdefault(key, (law, table.where))
    mobile = {blk.group for blk in blocks if blk.kind != BodyKind.FIXED}
    result: dict[tuple[str, str], ContactLaw | NoContact] = {}
    none = []
    ordered = sorted(groups)
    for i, a in enumerate(ordered):
        for c in ordered[i:]:
            key = frozenset((a, c))
            if key in laws:
                result[(a, c)] = laws[key][0]
            elif a in mobile or c in mobile:
                result[(a, c)] = NO_CONTACT
                none.append((a, c))
    return result, none


def _listing(box: Datbox, problems: list[str]) -> str:
    head = f"{box.folder}: {len(problems)} thing(s) cannot be translated:"
    return "\n  ".join([head, *problems])
