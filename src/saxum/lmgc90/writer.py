"""Write a saxum model as an LMGC90 DATBOX folder (BODIES.DAT, BULK_BEHAV.DAT,
TACT_BEHAV.DAT, DRV_DOF.DAT, DOF.INI, MODELS.DAT) in the layout pylmgc90 writes.

Bodies: RBDY2 with one POLYG (3D: RBDY3 with one POLYR, its faces split into triangles; with
polyhedra="POLYF" one POLYF, each face a patch of its own, its triangles outward, the layout
LMGC90's read_BDARY_POLYF reads), a cluster (ModelBuilder.add_cluster) with one POLYG
(POLYR, POLYF) per part, numbered from 1, a
disc RBDY2 with one DISKx (a sphere RBDY3 with one SPHER) of radius `byrd=`, a capsule RBDY2
with one JONCx (ax1 = half its segment, ax2 = its radius, turned by DOF.INI's X(3); LMGC90
has no JONCx-JONCx contact, so capsules that could meet capsules are refused), the node at
the centre of mass, the vertices in the body frame (saxum's: world axes in 2D,
the principal frame in 3D, whose rotation DOF.INI gives as the frame a, b, g). Fixed blocks
have all their dofs imposed at 0 in DRV_DOF.DAT, driven ones at their velocity at t = 0
(written as constant). Groups become colours (5 characters), densities RIGID bulk laws.
Laws: SIGNORINI_COULOMB -> IQS_CLB, GAP_SIGNORINI_COULOMB -> GAP_SGR_CLB (with
ContactLaw.initial_gap: IQS_CLB_g0, GAP_SGR_CLB_g0), RESTITUTION_COULOMB -> RST_CLB
(rstt = 0), one see-table per pair of groups with a law (its alert, or `alert`) and pair of
contactor types the groups have (a disc or sphere the candidate, as in LMGC90's DKPLx);
NO_CONTACT pairs get none. Joint laws (elastic, viscous,
cohesive) are refused: LMGC90's joint laws are written in other terms.

precision "lmgc90" writes LMGC90's fixed columns (7 significant digits, what its Fortran
reader takes); "full" writes 17 significant digits (exact round trip through
saxum.lmgc90.import_lmgc90, which reads values in free format; LMGC90 itself may not).
Comments `! saxum name:` and `! saxum group:` keep block and group names for the way back.
With a state, DOF.INI holds its positions and velocities and Vloc_Rloc.INI its contacts'
impulses as mean forces over the step (saxum.lmgc90.vlocrloc).
"""

import math
import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..geometry2d import cluster_polygon_properties
from ..geometry3d import cluster_properties, convex_polyhedron, rotation_matrix
from ..laws import LawKind
from ..model import BodyKind, Model, Shape, capsule_axis, capsule_properties
from ..state import State
from .vlocrloc import write_vloc_rloc

__all__ = ["export_lmgc90"]

_LAW_TYPES = {LawKind.SIGNORINI_COULOMB: "IQS_CLB", LawKind.GAP_SIGNORINI_COULOMB: "GAP_SGR_CLB",
              LawKind.RESTITUTION_COULOMB: "RST_CLB"}
_PAD = " " * 29
"""Continuation lines start in column 30, as LMGC90 reads them."""


def _colours(names: tuple[str, ...]) -> list[str]:
    """A distinct 5-character colour per group: 3 letters of its name and a number."""
    out = []
    for k, name in enumerate(names):
        letters = re.sub(r"[^A-Za-z0-9]", "", name).upper()[:3].ljust(3, "x")
        out.append(f"{letters}{k + 1:02d}" if k < 99 else f"G{k + 1:04d}")
    return out


def export_lmgc90(model: Model, folder: str | Path, *, precision: str = "lmgc90",
                  alert: float | None = None, velocities: np.ndarray | None = None,
                  state: State | None = None, dt: float | None = None,
                  polyhedra: str = "POLYR") -> Path:
    """Write `model` to the DATBOX `folder` (created): its initial configuration, at rest
    or with `velocities` (model.body_v's layout), or with `state` the state's positions,
    velocities and contacts, whose impulses over the step dt [s] Vloc_Rloc.INI holds as
    LMGC90's mean forces R / dt [N] (the next run's warm start). alert [m] for laws
    without their own (default: saxum's default, 2 % of the smallest free block's size).
    polyhedra: the contactor of 3D blocks, "POLYR" or "POLYF" (see-tables and Vloc_Rloc.INI
    name POLYR either way: LMGC90 detects a POLYF as a POLYR).
    Returns the folder. Raises InputError for deformable blocks, joint laws and capsules
    that LMGC90 cannot make meet (module doc)."""
    if precision not in ("lmgc90", "full"):
        raise InputError(f"precision must be 'lmgc90' or 'full', got {precision!r}")
    if polyhedra not in ("POLYR", "POLYF"):
        raise InputError(f"polyhedra must be 'POLYR' or 'POLYF', got {polyhedra!r}")
    if (model.body_kind == BodyKind.DEFORMABLE).any():
        raise InputError("export_lmgc90 writes rigid blocks; this model has deformable ones")
    if model.dim == 3 and (model.body_shape == Shape.CAPSULE).any():
        raise InputError("export_lmgc90 does not write 3D capsules (LMGC90's CYLND) yet; "
                         "replace them by polyhedra or spheres to export this model")
    if state is not None and dt is None:
        raise InputError("export_lmgc90: a state's impulses need the step dt [s] they were "
                         "taken over (dt=...), to write LMGC90's mean forces R / dt")
    for law in model.laws:
        if law.kind not in _LAW_TYPES:
            raise InputError(f"{law.name or 'a law'} is {law.kind.name}: export_lmgc90 writes "
                             f"{', '.join(k.name for k in _LAW_TYPES)} laws only")
    fmt = (lambda x: f"{x:14.7E}".replace("E", "D")) if precision == "lmgc90" else (
        lambda x: f"{x: .16E}".replace("E", "D"))
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    colours = _colours(model.group_names)
    q = model.body_q0 if state is None else state.body_q
    v = (state.body_v if state is not None else np.zeros((model.body_count, model.dof))
         if velocities is None else np.asarray(velocities))
    free = model.body_kind == BodyKind.FREE
    if alert is None:
        alert = 0.02 * float(model.body_size[free].min() if free.any() else model.body_size.min())
    densities = sorted({float(d) for d in model.body_density[free]})
    behav = {d: f"ST{k + 1:03d}" for k, d in enumerate(densities)}
    _write_bodies(folder / "BODIES.DAT", model, colours, behav, fmt, polyhedra)
    _write_dof(folder / "DOF.INI", model, q, v, fmt)
    _write_drives(folder / "DRV_DOF.DAT", model, fmt)
    g = [*model.gravity, 0.0][:3]
    bulk = ["! File BULK_BEHAV (saxum export_lmgc90)", "$gravy",
            f"{' ' * 19}grv1={fmt(g[0])}  grv2={fmt(g[1])}  grv3={fmt(g[2])}"]
    for d, name in behav.items():
        bulk += ["$behav  lawty", f" {name}  RIGID{' ' * 27}Umas={fmt(d)}"]
    bulk += ["! fixed and driven blocks: their dofs are all imposed, their mass is not used",
             "$behav  lawty", f" FIXED  RIGID{' ' * 27}Umas={fmt(1000.0)}"]
    (folder / "BULK_BEHAV.DAT").write_text("\n".join(bulk) + "\n", encoding="latin-1")
    _write_tact(folder / "TACT_BEHAV.DAT", model, colours, alert, fmt)
    (folder / "MODELS.DAT").write_text("! File MODELS (rigid blocks need none)\n",
                                       encoding="latin-1")
    if state is not None:
        write_vloc_rloc(folder / "Vloc_Rloc.INI", model, q, state.contacts, dt,
                        lambda b: _contactor(model, b), fmt)
    return folder


def _write_bodies(path: Path, model: Model, colours: list[str], behav: dict, fmt,
                  polyhedra: str) -> None:
    body, node = ("RBDY2", "NO3xx") if model.dim == 2 else ("RBDY3", "NO6xx")
    out = ["! File BODIES (saxum export_lmgc90)"]
    out += [f"! saxum group: {c} = {g}" for c, g in zip(colours, model.group_names, strict=True)]
    for b in range(model.body_count):
        contactors = range(*np.searchsorted(model.contactor_body, (b, b + 1)))
        cvs = model.contactor_vertex_start
        parts = [model.vertex_local[cvs[c]:cvs[c + 1]] for c in contactors]
        kind = BodyKind(int(model.body_kind[b]))
        law = behav[float(model.body_density[b])] if kind == BodyKind.FREE else "FIXED"
        colour = colours[model.body_group[b]]
        r = float(model.body_round_radius[b])
        if model.body_shape[b] == Shape.CAPSULE:  # LMGC90's JONCx formulas
            area, polar = capsule_properties(capsule_axis(model, b)[1], r)
            avrd, gyrd = math.sqrt(area / math.pi), math.sqrt(polar / area)
            inertia = []
        elif r > 0.0:  # a disc (sphere): both formulas below give r
            avrd = gyrd = r
            moment = 0.4 * (4.0 / 3.0 * math.pi * r**3) * r * r
            inertia = [] if model.dim == 2 else [
                f"{_PAD}I1  ={fmt(moment)}  I2  ={fmt(moment)}  I3  ={fmt(moment)}"]
        elif model.dim == 2:
            props = cluster_polygon_properties(parts)
            area, polar = props.area, props.polar_moment
            avrd, gyrd = math.sqrt(area / math.pi), math.sqrt(2.0 * polar / area)
            inertia = []
        else:
            volume, moments = _volume_moments(model, b, parts)
            avrd = (3.0 * volume / (4.0 * math.pi)) ** (1.0 / 3.0)
            gyrd = math.sqrt(2.5 * float(np.mean(moments)) / volume)
            inertia = [f"{_PAD}I1  ={fmt(moments[0])}  I2  ={fmt(moments[1])}  "
                       f"I3  ={fmt(moments[2])}"]
        centre = model.body_q0[b, :model.dim]
        coo = "  ".join(f"coo{k + 1}={fmt(x)}" for k, x in enumerate(
            [*centre, 0.0] if model.dim == 2 else centre))
        out += [f"! saxum name: {model.body_name[b]}", "$bdyty", f" {body}{b + 1:7d}",
                "$blmty", f" PLAIN      1  behav  {law}  avrd={fmt(avrd)}  gyrd={fmt(gyrd)}",
                *inertia, "$nodty", f" {node}      1{' ' * 16}{coo}", "$tacty"]
        if model.body_shape[b] == Shape.CAPSULE:
            half = 0.5 * capsule_axis(model, b)[1]
            out.append(f" JONCx      1  color  {colour}  ax1 ={fmt(half)}  ax2 ={fmt(r)}")
        elif r > 0.0:
            out.append(f" {_contactor(model, b)}      1  color  {colour}  byrd={fmt(r)}")
        elif model.dim == 2:
            for k, local in enumerate(parts):
                out.append(f" POLYG {k + 1:6d}  color  {colour}  nb_vertex={len(local):5d}")
                out += [f"{_PAD}coo1={fmt(x)}  coo2={fmt(y)}" for x, y in local]
        elif polyhedra == "POLYF":
            for k, c in enumerate(contactors):
                out += _polyf(model, c, k + 1, colour, fmt)
        else:
            for k, (c, local) in enumerate(zip(contactors, parts, strict=True)):
                triangles = _triangles(model, c) - cvs[c] + 1
                out.append(f" POLYR {k + 1:6d}  color  {colour}  nb_vertex={len(local):5d}"
                           f"      nb_face={len(triangles):5d}")
                out += _surface(local, triangles, fmt)
        out.append("$$$$$$")
    path.write_text("\n".join(out) + "\n", encoding="latin-1")


def _surface(vertices: np.ndarray, triangles, fmt) -> list[str]:
    """Vertex lines and triangle lines (numbered from 1) in the columns LMGC90 reads them
    (read_BDARY_POLYR, read_BDARY_POLYF: coo at 35:48, 56:69, 77:90; ver at 35:47, 56:68,
    77:89)."""
    return ([f"{_PAD}coo1={fmt(x)}  coo2={fmt(y)}  coo3={fmt(z)}" for x, y, z in vertices]
            + [f"{_PAD}ver1={i:7d}{' ' * 9}ver2={j:7d}{' ' * 9}ver3={k:7d}"
               for i, j, k in triangles])


def _polyf(model: Model, c: int, number: int, colour: str, fmt) -> list[str]:
    """3D contactor c as POLYF `number`: a patch per face, its triangles a fan of the face
    (counter-clockwise seen from outside, as saxum's faces are: LMGC90 computes the volume
    from them), the counts in the columns LMGC90 reads (40:47 and 60:67)."""
    faces = range(model.contactor_face_start[c], model.contactor_face_start[c + 1])
    out = [f" POLYF  {number:5d}  color  {colour}  nb_patch=  {len(faces):5d}"]
    for f in faces:
        ring = model.face_vertex[model.face_vertex_start[f]:model.face_vertex_start[f + 1]]
        fan = [(1, k, k + 1) for k in range(2, len(ring))]
        out.append(f"{_PAD}nb_vertex=  {len(ring):5d}  nb_faces=  {len(fan):5d}")
        out += _surface(model.vertex_local[ring], fan, fmt)
    return out


def _contactor(model: Model, b: int) -> str:
    """LMGC90's contactor type of body b: DISKx, SPHER, JONCx, POLYG or POLYR."""
    if model.body_shape[b] == Shape.CAPSULE:
        return "JONCx"
    if model.body_round_radius[b] > 0.0:
        return "DISKx" if model.dim == 2 else "SPHER"
    return "POLYG" if model.dim == 2 else "POLYR"


def _triangles(model: Model, c: int) -> np.ndarray:
    """The faces of 3D contactor c split into triangles (fans), vertex indices into
    vertex_local."""
    tris = []
    for f in range(model.contactor_face_start[c], model.contactor_face_start[c + 1]):
        ring = model.face_vertex[model.face_vertex_start[f]:model.face_vertex_start[f + 1]]
        tris += [(ring[0], ring[k], ring[k + 1]) for k in range(1, len(ring) - 1)]
    return np.array(tris, dtype=np.int64)


def _volume_moments(model: Model, b: int, parts: list[np.ndarray]
                    ) -> tuple[float, np.ndarray]:
    """Volume [m^3] and principal second moments of volume [m^5] of 3D body b made of
    `parts` (its contactors' vertices; its inertia over its density, from the vertices for
    fixed bodies, whose density is 0)."""
    props = cluster_properties([convex_polyhedron(local, name=model.body_name[b])
                                for local in parts])
    return props.volume, props.moments


def _write_dof(path: Path, model: Model, q: np.ndarray, v: np.ndarray, fmt) -> None:
    out = ["! File DOF (saxum export_lmgc90)", "$steps      0                time= "
           + fmt(0.0)]
    x = q[:, :model.dim] - model.body_q0[:, :model.dim]
    for b in range(model.body_count):
        if model.dim == 2:
            node = " NO3xx      1" + " " * 16
            rows = [[*x[b], q[b, 2] + _capsule_angle(model, b)], list(v[b])]
            labels = ["X", "V"]
        else:
            rot = rotation_matrix(q[b, 3:])
            node = " NO6xx      1" + " " * 16
            rows = [list(x[b]), [0.0] * 3, list(v[b, :3]), list(v[b, 3:]), *(list(rot[:, k])
                                                                              for k in range(3))]
            labels = ["X", "X", "V", "V", "a", "b", "g"]
        out += ["$bdyty", f" {'RBDY2' if model.dim == 2 else 'RBDY3'}{b + 1:7d}", "$nodty"]
        for r, (label, row) in enumerate(zip(labels, rows, strict=True)):
            first = 4 if (model.dim == 3 and label in "XV" and r in (1, 3)) else 1
            cells = "  ".join(f"{label}({first + k})={fmt(x)}" for k, x in enumerate(row))
            out.append((node if r == 0 else _PAD) + cells)
        out.append("$$$$$$")
    path.write_text("\n".join(out) + "\n", encoding="latin-1")


def _capsule_angle(model: Model, b: int) -> float:
    """A capsule's segment direction at the start [rad] (LMGC90's JONCx lies along its
    body's x axis, turned by DOF.INI's X(3)); 0 for other blocks, whose vertices BODIES.DAT
    gives as they are."""
    return capsule_axis(model, b)[0] if model.body_shape[b] == Shape.CAPSULE else 0.0


def _write_drives(path: Path, model: Model, fmt) -> None:
    out = []
    for b in np.flatnonzero(model.body_kind != BodyKind.FREE):
        velocity = ([0.0] * model.dof if model.body_kind[b] == BodyKind.FIXED
                    else list(model.motions[model.body_motion[b]](0.0)))
        out += ["$bdyty", f" {'RBDY2' if model.dim == 2 else 'RBDY3'}{b + 1:7d}", "$nodty",
                f" {'NO3xx' if model.dim == 2 else 'NO6xx'}      1",
                "$dofty        [CT......+......AMP..*..cos.(..OMEGA.*.time.+.PHI..)]...*..."
                "[RAMPI.....+.....RAMP.*.time]"]
        out += [f" vlocy {k + 1:6d} " + "  ".join(fmt(x) for x in (c, 0.0, 0.0, 0.0, 1.0, 0.0))
                for k, c in enumerate(velocity)]
        out.append("$$$$$$")
    path.write_text("\n".join(out) + "\n", encoding="latin-1")


def _loose_capsule(model: Model, i: int, j: int) -> bool:
    """True if groups i and j have capsules and one of them is not fixed."""
    capsule = model.body_shape == Shape.CAPSULE
    both = capsule & np.isin(model.body_group, (i, j))
    return bool((model.body_kind[both] != BodyKind.FIXED).any())


def _write_tact(path: Path, model: Model, colours: list[str], alert: float, fmt) -> None:
    body = "RBDY2" if model.dim == 2 else "RBDY3"
    # LMGC90 detects a pair of contactor types only where a see-table names it: one per
    # pair of types the two groups have, the disc (sphere) the candidate
    order = ("DISKx", "SPHER", "POLYG", "POLYR", "JONCx")  # JONCx: always the antagonist
    tacts = [sorted({_contactor(model, b) for b in np.flatnonzero(model.body_group == g)},
                    key=order.index) for g in range(len(model.group_names))]
    out = ["! File TACT_BEHAV (saxum export_lmgc90)"]
    names = [f"law{k + 1:02d}" for k in range(len(model.laws))]
    for name, law in zip(names, model.laws, strict=True):
        params = f"fric={fmt(law.friction)}"
        if law.kind == LawKind.RESTITUTION_COULOMB:
            params = f"rstn={fmt(law.restitution)}  rstt={fmt(0.0)}  {params}"
        lawty = _LAW_TYPES[law.kind] + ("_g0" if law.initial_gap else "")
        out += ["$behav  lawty", f" {name}  {lawty:<30s}  {params}"]
    n = len(model.group_names)
    for i in range(n):
        for j in range(i, n):
            k = model.group_law[i, j]
            if k < 0:
                continue
            a = model.laws[k].alert if model.laws[k].alert is not None else alert
            if "JONCx" in tacts[i] and "JONCx" in tacts[j] and _loose_capsule(model, i, j):
                raise InputError(f"groups {model.group_names[i]!r} and {model.group_names[j]!r}"
                                 " both have capsules, one of them not fixed: LMGC90 has no "
                                 "JONCx-JONCx contact; give them no contact (NO_CONTACT) or "
                                 "make one side polygons to export")
            out += ["$seety", " cdbdy  cdtac  cdcol  behav  anbdy  antac  ancol       alert"]
            seen = set()
            for ti in tacts[i]:
                for tj in tacts[j]:
                    (ci, cti), (cj, ctj) = sorted(((i, ti), (j, tj)),
                                                  key=lambda x: order.index(x[1]))
                    if (ci, cti, cj, ctj) not in seen and cti != "JONCx":
                        seen.add((ci, cti, cj, ctj))
                        out.append(f" {body}  {cti}  {colours[ci]}  {names[k]}  {body}  {ctj}  "
                                   f"{colours[cj]}     {fmt(a)}")
    path.write_text("\n".join(out) + "\n", encoding="latin-1")
