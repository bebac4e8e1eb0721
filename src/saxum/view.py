"""An interactive viewer of a results file in one self-contained HTML page (`saxum view`).

The page holds the blocks' geometry once, the output frames packed as binary arrays in base64,
three.js (vendored in saxum/viewer, MIT) and saxum's viewer script, all inline: it opens from
disk in a current browser with no server and no network, and can be sent on as one file.

Frames are packed so that a 1000-block, 200-frame 3D run stays under 10 MB:
- a body's position as its displacement u from the initial position q0 [m], quantized to 16
  bits over the range of u on each axis (all bodies, all frames shown): the error is at most
  half a step, (u_max - u_min) / 65535 / 2 on that axis (`quantize`);
- its orientation as a unit quaternion (w, x, y, z; 2D: a turn theta about z,
  (cos theta/2, 0, 0, sin theta/2)), each component times 32767 rounded to int16: at most
  0.5 / 32767 per component;
- the loaded contact points (normal force > 0) as 16-bit positions over their bounding box
  and 16-bit normal forces over the largest, with the mechanism of saxum.mechanism (hinges,
  sliding joints, open points), for every frame or, when the contacts of all frames exceed
  CONTACT_POINTS, for every c-th frame (the page says so);
- per block and frame, the largest damage [-] of its bonded joints (cohesive laws,
  saxum.mechanism.bond_states) and the largest compression [Pa] of its cells (deformable
  blocks), where the run has them. Deformable blocks are drawn as their undeformed shapes
  moved by their co-rotated frames (body_q), not as their meshes.

The solver log (sweeps, error, kinetic energy per step) goes in at most STEP_POINTS points:
longer logs keep each bin's largest value. Water levels of a flood are sampled along the flow
at every frame shown.
"""

from __future__ import annotations

import base64
import fnmatch
import html
import json
import math
import os
import webbrowser
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from .errors import InputError
from .laws import LawKind
from .mechanism import bond_states, frame_mechanism
from .model import BodyKind, drawn_outlines, drawn_polyhedra
from .plot_common import results_floods, results_heading

__all__ = ["CONTACT_POINTS", "MAX_BYTES", "STEP_POINTS", "View", "dequantize",
           "open_in_browser", "quantize", "quantize_quaternions", "view_data", "view_html",
           "write_view"]

MAX_BYTES = 64 * 2**20
"""Largest page written [bytes]: a browser opens larger ones slowly or not at all."""
CONTACT_POINTS = 300_000
"""Most contact points packed over all frames shown (8 bytes each, before base64)."""
STEP_POINTS = 2000
"""Most points of the solver log's plot."""
_WATER_SAMPLES = 48
_LEVELS = 65535  # steps of a 16-bit quantization
_UNIT_QUATERNION = 32767  # int16 scale of a quaternion component


def quantize(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """`values` in [lo, hi] (per last axis) as uint16 levels 0..65535; dequantize returns them
    within (hi - lo) / 65535 / 2."""
    span = np.where(hi > lo, hi - lo, 1.0)
    scaled = np.rint((values - lo) / span * _LEVELS)
    return np.clip(scaled, 0, _LEVELS).astype(np.uint16)


def dequantize(levels: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The values that `quantize` packed into `levels` (the viewer computes the same)."""
    return lo + levels.astype(np.float64) / _LEVELS * (hi - lo)


def quantize_quaternions(q: np.ndarray) -> np.ndarray:
    """Unit quaternions [..., 4] as int16 (component x 32767); error <= 0.5 / 32767."""
    return np.clip(np.rint(q * _UNIT_QUATERNION), -_UNIT_QUATERNION,
                   _UNIT_QUATERNION).astype(np.int16)


@dataclass
class _Packer:
    """Binary arrays laid one after the other (4-byte aligned) and their index."""

    chunks: list[bytes] = field(default_factory=list)
    index: dict[str, list] = field(default_factory=dict)
    size: int = 0

    def add(self, name: str, array: np.ndarray) -> None:
        array = np.ascontiguousarray(array)
        kind = {np.dtype(np.float32): "f32", np.dtype(np.float64): "f64",
                np.dtype(np.int32): "i32", np.dtype(np.uint32): "u32",
                np.dtype(np.int16): "i16", np.dtype(np.uint16): "u16",
                np.dtype(np.uint8): "u8"}[array.dtype]
        data = array.astype(array.dtype.newbyteorder("<"), copy=False).tobytes()
        self.index[name] = [kind, self.size, array.size, list(array.shape)]
        pad = -len(data) % 8
        self.chunks.append(data + b"\0" * pad)
        self.size += len(data) + pad

    def base64(self) -> str:
        return base64.b64encode(b"".join(self.chunks)).decode("ascii")


def _frames(count: int, every: int) -> np.ndarray:
    """Every `every`-th output frame from the first, and the last."""
    ks = np.arange(0, count, every)
    return ks if ks.size == 0 or ks[-1] == count - 1 else np.append(ks, count - 1)


def _moving(kind: np.ndarray) -> np.ndarray:
    """Which bodies move under forces: free and deformable ones (not the fixed and driven
    supports)."""
    return (kind == BodyKind.FREE) | (kind == BodyKind.DEFORMABLE)


def _select_bodies(results, blocks: str | None) -> np.ndarray:
    """Indices of the bodies shown: all, or those whose name or group matches the glob
    pattern `blocks`, with every fixed or driven body (the supports stay in view)."""
    n = len(results.body_name)
    if blocks is None:
        return np.arange(n)
    groups = results.group_names
    group = results.model["body_group"]
    match = np.array([fnmatch.fnmatchcase(name, blocks) or fnmatch.fnmatchcase(
        groups[group[b]], blocks) for b, name in enumerate(results.body_name)])
    if not match.any():
        raise InputError(f"--blocks {blocks!r} matches no block name or group of "
                         f"{results.path} (groups: {', '.join(groups)})")
    return np.flatnonzero(match | ~_moving(results.model["body_kind"]))


def _estimate(results, bodies: int, ks: np.ndarray) -> int:
    """Bytes of the page, roughly: the frames' 14 bytes per body, the contacts' 8 per point
    (at most CONTACT_POINTS), times 4/3 for base64, and three.js."""
    contacts = min(int(results.contact_counts[ks].sum()), CONTACT_POINTS)
    return int(4 / 3 * (14 * bodies * ks.size + 8 * contacts)) + 10**6


def _geometry(results, shown: np.ndarray, pack: _Packer) -> None:
    """Each shown body's vertices in its own frame [m] and, in 3D, its faces as triangles
    (fans: saxum's faces are convex polygons) in body-local vertex indices; 2D discs as
    polygons inscribed in their circles (saxum.model.drawn_outlines)."""
    m = results.model
    vs, local = m["body_vertex_start"], m["vertex_local"]
    if results.dim == 2:
        vs, local = drawn_outlines(vs, local, m.get("body_round_radius"),
                                   shape=m.get("body_shape"),
                                   contactor_start=m.get("contactor_vertex_start"))
    else:
        m = drawn_polyhedra(m)
        vs, local = m["body_vertex_start"], m["vertex_local"]
    counts = np.diff(vs)[shown]
    take = np.concatenate([np.arange(vs[b], vs[b + 1]) for b in shown])
    pack.add("vertex", local[take].astype(np.float32))
    pack.add("vertex_start", np.concatenate([[0], np.cumsum(counts)]).astype(np.int32))
    if results.dim == 2:
        return
    fs, fvs, fv = m["body_face_start"], m["face_vertex_start"], m["face_vertex"]
    faces = np.concatenate([np.arange(fs[b], fs[b + 1]) for b in shown])
    owner = np.repeat(np.arange(shown.size), np.diff(fs)[shown])
    n = fvs[faces + 1] - fvs[faces]  # vertices of each face
    fan = n - 2
    face = np.repeat(np.arange(faces.size), fan)
    corner = np.arange(fan.sum()) - np.repeat(np.cumsum(fan) - fan, fan)  # 0.. per face
    first = fvs[faces][face]
    base = vs[shown][owner][face]
    tri = np.stack((fv[first], fv[first + corner + 1], fv[first + corner + 2]), axis=1)
    pack.add("triangle", (tri - base[:, None]).astype(np.int32))
    per_body = np.bincount(owner[face], minlength=shown.size)
    pack.add("triangle_start", np.concatenate([[0], np.cumsum(per_body)]).astype(np.int32))


def _rotations(results, q: np.ndarray) -> np.ndarray:
    """Unit quaternions (w, x, y, z) [frames, bodies, 4] of coordinates q."""
    if results.dim == 3:
        r = q[..., 3:7]
        return r / np.linalg.norm(r, axis=-1, keepdims=True)
    half = 0.5 * q[..., 2]
    zero = np.zeros_like(half)
    return np.stack((np.cos(half), zero, zero, np.sin(half)), axis=-1)


def _positions(results, q: np.ndarray) -> np.ndarray:
    d = results.dim
    return q[..., :3] if d == 3 else np.concatenate((q[..., :2], np.zeros_like(q[..., :1])),
                                                    axis=-1)


def _world_box(results, shown: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bounding box [m] of the free shown bodies (all shown if none is free) over the frames:
    their initial vertices moved by the range of their displacements."""
    m = results.model
    free = _moving(m["body_kind"][shown])
    pick = shown[free] if free.any() else shown
    vs, local = m["body_vertex_start"], m["vertex_local"]
    radius = np.array([np.linalg.norm(local[vs[b]:vs[b + 1]], axis=1).max() for b in pick])
    p = _positions(results, q[:, np.searchsorted(shown, pick)])
    lo = (p - radius[:, None]).min(axis=(0, 1))
    hi = (p + radius[:, None]).max(axis=(0, 1))
    return lo, hi


def _steps(results) -> dict[str, list]:
    """The solver log at most STEP_POINTS long: each bin's largest value (its last time), and
    whether all its steps converged."""
    s = results.steps
    if "step" not in s or s["step"].size == 0:
        return {}
    n = s["step"].size
    bins = math.ceil(n / STEP_POINTS)
    starts = np.arange(0, n, bins)
    out = {"time": s["time"][np.minimum(starts + bins, n) - 1]}
    for name in ("iterations", "error", "kinetic_energy"):
        if name in s:
            out[name] = np.maximum.reduceat(s[name].astype(np.float64), starts)
    if "converged" in s:
        out["converged"] = np.minimum.reduceat(s["converged"].astype(np.int8), starts)
    return {k: np.asarray(v).tolist() for k, v in out.items()}


def _water(results, floods, times: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> dict | None:
    """The flood's water surface: levels H(s) [m] at _WATER_SAMPLES points along the flow
    over the view's box, for each frame shown (plot.py and plot3d.py draw the same)."""
    if not floods:
        return None
    flood = floods[0]
    a = math.radians(flood.azimuth)
    e = np.array([math.cos(a), math.sin(a)]) if results.dim == 3 else np.array([1.0, 0.0])
    corners = np.array([[x, y] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])])
    along = corners @ e
    m = results.model
    free = np.flatnonzero(_moving(m["body_kind"]))
    pts = np.concatenate([results.vertices(b, 0)[:, :2] for b in free]) if free.size else corners
    extent = (float((pts @ e).min()), float((pts @ e).max()))
    pad = 0.25 * float(along.max() - along.min())
    s = np.linspace(float(along.min()) - pad, float(along.max()) + pad, _WATER_SAMPLES)
    level = np.array([flood.surface(s, float(t), extent) for t in times])
    speed = [float(flood.velocity.at(float(t))) for t in times]
    return {"s": s.tolist(), "direction": e.tolist(), "level": level.astype(np.float32),
            "speed": speed, "azimuth": flood.azimuth}


@dataclass
class _Overlays:
    """Contacts and mechanism of the frames that carry them."""

    frames: list[int] = field(default_factory=list)  # positions in the frames shown
    point: list[np.ndarray] = field(default_factory=list)
    force: list[np.ndarray] = field(default_factory=list)
    opened: list[np.ndarray] = field(default_factory=list)
    hinge: list[np.ndarray] = field(default_factory=list)  # 2 ends each (2D: twice a point)
    sliding: list[np.ndarray] = field(default_factory=list)
    damage: list[np.ndarray] = field(default_factory=list)


def _overlays(results, ks: np.ndarray, shown: np.ndarray) -> tuple[_Overlays, int]:
    """Loaded contact points with their normal force, open points, hinges and sliding joints
    (saxum.mechanism) of every c-th frame shown, c the smallest stride whose contacts stay
    within CONTACT_POINTS; and c."""
    total = int(results.contact_counts[ks].sum())
    stride = max(1, math.ceil(total / CONTACT_POINTS))
    out = _Overlays()
    keep = np.zeros(len(results.body_name), dtype=bool)
    keep[shown] = True
    law_kind = results.model["law_kind"]
    moving = _moving(results.model["body_kind"])
    # open beyond 0.1 % of the median block size, as saxum plot draws them
    gap_tolerance = 1e-3 * float(np.median(results.body_size[moving] if moving.any()
                                           else results.body_size))
    cohesive = ("damage" in results.file["frames/contacts"]
                and bool((law_kind == LawKind.COHESIVE).any()))
    for i in range(0, ks.size, stride):
        k = int(ks[i])
        c = results.contacts(k)
        mech = frame_mechanism(results, k, contacts=c)
        rows = keep[c["candidate"]] | keep[c["antagonist"]]
        normal = c["force"][:, 1]
        loaded = rows & (normal > 0.0)
        out.frames.append(i)
        out.point.append(_pad3(c["point"][loaded]))
        out.force.append(normal[loaded])
        out.opened.append(_pad3(c["point"][rows & (c["gap"] > gap_tolerance)]))
        ends = [j.hinge_line if j.hinge_line is not None else (j.hinge_point, j.hinge_point)
                for j in mech.hinges]
        out.hinge.append(_pad3(np.array(ends, dtype=np.float64).reshape(-1, results.dim)))
        out.sliding.append(_pad3(np.array([j.centre_of_pressure for j in mech.sliding],
                                          dtype=np.float64).reshape(-1, results.dim)))
        if cohesive:  # bonded contacts only: one made after the start is no crack
            bonded = bond_states(c["law"], c["damage"], c["history"], law_kind) != ""
            damage = np.where(bonded, c["damage"], 0.0)
            worst = np.zeros(len(results.body_name))
            np.maximum.at(worst, c["candidate"], damage)
            np.maximum.at(worst, c["antagonist"], damage)
            out.damage.append(worst[shown])
    return out, stride


def _pad3(p: np.ndarray) -> np.ndarray:
    """Points [n, 2 or 3] as [n, 3] (2D: z = 0)."""
    return p if p.shape[1] == 3 else np.concatenate((p, np.zeros((len(p), 1))), axis=1)


def _pack_points(pack: _Packer, name: str, points: list[np.ndarray]) -> dict:
    """Points of the overlay frames as 16-bit positions over their box, and where each
    frame's begin; returns the box."""
    every = np.concatenate(points) if points else np.zeros((0, 3))
    lo = every.min(axis=0) if len(every) else np.zeros(3)
    hi = every.max(axis=0) if len(every) else np.ones(3)
    pack.add(name, quantize(every, lo, hi))
    pack.add(name + "_start", np.concatenate([[0], np.cumsum([len(p) for p in points])])
             .astype(np.int32))
    return {"lo": lo.tolist(), "hi": hi.tolist()}


def _stresses(results, ks: np.ndarray, shown: np.ndarray) -> np.ndarray | None:
    """The largest compression [Pa] of each shown block's cells at each frame shown (0 for
    rigid blocks); None without deformable blocks."""
    if results.node_x is None:
        return None
    m = results.model
    start = m["fe_cell_start"]
    out = np.zeros((ks.size, len(results.body_name)))
    for i, k in enumerate(ks):
        comp = results.stresses(int(k))["compression"]
        out[i, m["fe_body"]] = np.maximum.reduceat(comp, start[:-1])
    return out[:, shown]


def view_data(results, *, every: int = 1, blocks: str | None = None,
              max_bytes: int = MAX_BYTES) -> tuple[dict, _Packer]:
    """The page's data: a JSON-able dict and the binary arrays (module doc)."""
    if results.frame_count == 0:
        why = results.message or results.status
        raise InputError(f"{results.path} has no output frame yet ({why}): nothing to view")
    shown = _select_bodies(results, blocks)
    ks = _frames(results.frame_count, every)
    size = _estimate(results, shown.size, ks)
    if size > max_bytes:
        need = math.ceil(size / max_bytes * every)
        raise InputError(
            f"{results.path}: {shown.size} blocks x {ks.size} frames would make a page of "
            f"about {size / 2**20:.0f} MB, more than the {max_bytes / 2**20:.0f} MB a browser "
            f"opens well: show fewer frames (--every {need}: one output frame in {need}) or "
            "a subset of the blocks (--blocks 'PATTERN', a glob on block names or groups)")
    m = results.model
    pack = _Packer()
    _geometry(results, shown, pack)
    q = results.body_q[ks][:, shown]
    q0 = m["body_q0"][shown]
    p0 = _positions(results, q0[None])[0]
    u = _positions(results, q) - p0
    u_lo, u_hi = u.min(axis=(0, 1)), u.max(axis=(0, 1))
    pack.add("p0", p0.astype(np.float64))
    pack.add("u", quantize(u, u_lo, u_hi))
    pack.add("rotation", quantize_quaternions(_rotations(results, q)))
    lo, hi = _world_box(results, shown, q)
    overlays, stride = _overlays(results, ks, shown)
    forces = np.concatenate(overlays.force) if overlays.force else np.zeros(0)
    force_max = float(forces.max(initial=0.0))
    pack.add("force", quantize(forces, np.float64(0.0), np.float64(force_max or 1.0)))
    boxes = {name: _pack_points(pack, name, getattr(overlays, attr)) for name, attr in
             (("contact", "point"), ("open", "opened"), ("hinge", "hinge"),
              ("sliding", "sliding"))}
    colours = {}
    if overlays.damage:
        pack.add("damage", quantize(np.array(overlays.damage), 0.0, 1.0))
        colours["damage"] = {"max": 1.0, "unit": "-"}
    stress = _stresses(results, ks, shown)
    if stress is not None:
        top = float(stress.max(initial=0.0)) or 1.0
        pack.add("stress", quantize(stress, 0.0, top))
        colours["stress"] = {"max": top, "unit": "Pa"}
    group = m["body_group"][shown]
    per_depth = " per metre of depth" if results.dim == 2 else ""
    data = {
        "title": results_heading(results),
        "file": results.path.name,
        "dim": results.dim,
        "saxum": results.version,
        "status": results.status,
        "message": results.message,
        "damage": list(results.damage),
        "frame_count": int(results.frame_count),
        "every": every,
        "frames": ks.tolist(),
        "time": results.time[ks].tolist(),
        "step": results.step[ks].astype(int).tolist(),
        "body": {"name": [results.body_name[b] for b in shown],
                 "group": group.astype(int).tolist(),
                 "kind": m["body_kind"][shown].astype(int).tolist(),
                 "mass": m["body_mass"][shown].tolist(),
                 "subset": blocks, "total": len(results.body_name)},
        "groups": list(results.group_names),
        "mass_unit": "kg/m" if results.dim == 2 else "kg",
        "force_unit": "N/m" if results.dim == 2 else "N",
        "per_depth": per_depth,
        "u_lo": u_lo.tolist(), "u_hi": u_hi.tolist(),
        "box": {"lo": lo.tolist(), "hi": hi.tolist()},
        "overlay": {"frames": overlays.frames, "stride": stride, "force_max": force_max,
                    "boxes": boxes},
        "colours": colours,
        "steps": _steps(results),
        "water": None,
    }
    water = _water(results, results_floods(results), results.time[ks], lo, hi)
    if water is not None:
        pack.add("water", water.pop("level"))
        data["water"] = water
    data["binary"] = pack.index
    return data, pack


def _asset(name: str) -> str:
    """A file of saxum/viewer (package data: the folder is no Python package)."""
    return resources.files("saxum").joinpath("viewer", name).read_text(encoding="utf-8")


def view_html(results, *, every: int = 1, blocks: str | None = None,
              max_bytes: int = MAX_BYTES) -> str:
    """The page of saxum.results.Results `results` (module doc): every `every`-th output
    frame and the last, the bodies whose name or group matches the glob `blocks` (and the
    supports) or all; InputError when it would exceed `max_bytes` [bytes]."""
    data, pack = view_data(results, every=every, blocks=blocks, max_bytes=max_bytes)
    # '<' escaped: a name holding "</script>" cannot end the data's script element
    text = json.dumps(data, separators=(",", ":")).replace("<", "\\u003c")
    parts = {"TITLE": html.escape(data["title"]), "DATA": text, "BINARY": pack.base64(),
             "THREE": _asset("three.module.min.js"), "VIEWER": _asset("viewer.js")}
    page = _asset("viewer.html")
    pieces = page.split("@@")
    # the template's @@NAME@@ markers, replaced in one pass (no content is scanned again)
    return "".join(parts.get(p, p) if i % 2 else p for i, p in enumerate(pieces))


@dataclass
class View:
    """A page written by view_html: `html`; shown inline in Jupyter (an iframe whose
    srcdoc is the page; IPython itself is not needed)."""

    html: str
    height: int = 640  # [px]

    def _repr_html_(self) -> str:
        return (f'<iframe srcdoc="{html.escape(self.html, quote=True)}" '
                f'style="width:100%;height:{self.height}px;border:0" '
                'allow="fullscreen"></iframe>')

    def save(self, path: str | os.PathLike) -> Path:
        path = Path(path)
        path.write_text(self.html, encoding="utf-8")
        return path


def write_view(results, path: str | os.PathLike | None = None, *, every: int = 1,
               blocks: str | None = None, max_bytes: int = MAX_BYTES) -> Path:
    """Write the page of `results` (view_html) to `path` (default: the results file with
    suffix .html); returns its path."""
    out = Path(path) if path is not None else results.path.with_suffix(".html")
    return View(view_html(results, every=every, blocks=blocks, max_bytes=max_bytes)).save(out)


def open_in_browser(page: Path) -> bool:
    """Open `page` in the default browser; False where none could be started."""
    return webbrowser.open(page.resolve().as_uri())
