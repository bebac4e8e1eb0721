"""Blocks from files: a JSON or CSV list of polygons (or of 3D point sets), or the closed
polylines of a DXF drawing.

JSON: {"blocks": [{"vertices": [[x, y], ...], "density": 2000.0, "group": "stone",
"kind": "free", "name": "keystone"}, ...]}; only "vertices" is required. A disc (a sphere in
a 3D file) has "centre": [x, y] and "radius" [m] instead of "vertices"; a capsule (2D: a
segment with round ends, LMGC90's JONCx) "centre", "radius" (its ends' [m]), "length" (its
segment's [m], > 0) and optionally "angle" (the segment's direction from the x axis [rad],
default 0) (JSON only). A cluster (a non-convex block made of convex parts,
ModelBuilder.add_cluster) has "parts": [[[x, y], ...], ...] instead of "vertices", each part
as "vertices" is (JSON only).

CSV: a header row naming the columns, then one row per vertex: `block` (the block's name),
`x`, `y` [m] (required) and `density` [kg/m^3], `group`, `kind` (optional: given on any row
of the block, on several rows they must agree, an empty cell gives nothing). A block's rows
are consecutive, in order around the polygon.

3D blocks (convex polyhedra, ModelBuilder(dim=3)): vertices [[x, y, z], ...] in JSON, or a
`z` column in CSV; a block is the convex hull of its points (in any order), as
ModelBuilder.add_block takes it. A file holds 2D or 3D blocks, not both.

DXF (read with ezdxf, an optional dependency: pip install ezdxf): every closed LWPOLYLINE or
2D/3D POLYLINE of the model space is a block (an open one whose last point repeats its first
counts as closed); its layer is its group, and layers named in `fixed_layers` hold fixed
blocks. Anything else in the model space (an open polyline, a LINE, TEXT, a dimension...) is an
error naming it, unless it is on a layer named in `ignore_layers` (notes, dimensions): a block
drawn with lines or left open would otherwise be lost without a word. Arc segments (bulges)
are refused. DXF blocks are 2D.

In all formats kind is "free" or "fixed" (any case), the group defaults to `group`, and a
free block without a density takes `density` (a number, or a mapping from group to number).
Coordinates are multiplied by `scale` (e.g. 0.001 for a drawing in mm). Errors name the file
and the block, with its line (CSV), index (JSON) or handle and layer (DXF).
"""

import csv
import io
import json
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..geometry2d import normalize_polygon
from ..geometry3d import convex_polyhedron
from ..laws import LawKind
from ..model import BodyKind, Model, ModelBuilder, Shape, capsule_axis
from ._common import Assembly, finalize

__all__ = ["BlockSpec", "add_blocks_from_file", "block_file_dim", "blocks_model", "read_blocks",
           "write_blocks"]

FORMATS = ("json", "csv", "dxf")
KINDS = {"free": BodyKind.FREE, "fixed": BodyKind.FIXED}
CSV_COLUMNS = ("block", "x", "y", "density", "group", "kind")
CSV_COLUMNS_3D = ("block", "x", "y", "z", "density", "group", "kind")
JSON_KEYS = ("vertices", "parts", "centre", "radius", "length", "angle", "density", "group",
             "kind", "name")


@dataclass(frozen=True)
class BlockSpec:
    """A block read from a file: vertices [m] (n, 2) counter-clockwise (3D: (n, 3), the
    vertices of its convex hull), density [kg/m^3] (0 for fixed blocks), group, kind, name,
    and where it is in the file (for messages); a disc (sphere) has radius > 0 [m] and its
    centre as its one vertex, a capsule also its segment's length > 0 [m] and angle [rad];
    a cluster its convex parts' vertices (as `vertices`, which holds the first part's)."""

    vertices: np.ndarray
    density: float
    group: str
    kind: BodyKind
    name: str
    where: str
    radius: float = 0.0
    length: float = 0.0
    angle: float = 0.0
    parts: tuple[np.ndarray, ...] = ()


def _format(path: Path, format: str | None) -> str:
    fmt = (format or path.suffix.lstrip(".")).lower()
    if fmt not in FORMATS:
        raise InputError(f"{path}: unknown block file format {fmt!r}; use one of {FORMATS} "
                         "(from the file's extension or format=...)")
    return fmt


def _not_text(path: Path, err: UnicodeDecodeError) -> InputError:
    return InputError(f"{path}: not a text file (byte {err.object[err.start]:#04x} at offset "
                      f"{err.start} is not UTF-8); a JSON or CSV block file is UTF-8 text "
                      "(docs/scenario.md)")


def _kind(value, where: str) -> BodyKind:
    if not isinstance(value, str) or value.lower() not in KINDS:
        raise InputError(f"{where}: kind must be one of {tuple(KINDS)}, got {value!r}")
    return KINDS[value.lower()]


def _number(value, what: str, where: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not math.isfinite(number):
        raise InputError(f"{where}: {what} must be a finite number, got {value!r}")
    return number


class _Defaults:
    """Turns raw values into a BlockSpec: default group and density, checks, scale."""

    def __init__(self, density, group: str, scale: float) -> None:
        self.density, self.group = density, group
        self.scale = _number(scale, "scale", "read_blocks")

    def spec(self, vertices, density, group, kind: BodyKind, name: str,
             where: str, radius=None, length=None, angle=0.0, parts=()) -> BlockSpec:
        group = self.group if group in (None, "") else str(group)
        points = np.asarray(vertices, dtype=np.float64) * self.scale
        parts = tuple(self._convex(np.asarray(part, dtype=np.float64) * self.scale,
                                   f"{where} part {k}") for k, part in enumerate(parts))
        if parts:
            verts = parts[0]
        elif radius is not None:  # a disc (sphere): its centre as its one vertex
            radius = _number(radius, "radius [m]", where) * self.scale
            if radius <= 0.0 or points.shape not in ((1, 2), (1, 3)):
                raise InputError(f"{where}: a disc (sphere) needs a radius > 0 [m] and a "
                                 f"centre [x, y] (3D [x, y, z]); got radius {radius:g}")
            verts = points
            if length is not None:
                length = _number(length, "length [m]", where) * self.scale
                angle = _number(angle, "angle [rad]", where)
                if length <= 0.0 or points.shape != (1, 2):
                    raise InputError(f"{where}: a capsule needs a length > 0 [m] (its "
                                     "segment's; a disc has no length) and a centre [x, y]; "
                                     f"got length {length:g}")
        else:
            verts = self._convex(points, where)
        if kind != BodyKind.FREE:
            density = 0.0
        elif density in (None, ""):
            default = (self.density.get(group) if isinstance(self.density, Mapping)
                       else self.density)
            if default is None:
                raise InputError(f"{where}: no density for this free block; give one in the "
                                 "file or read it with density=... [kg/m^3]")
            density = default
        density = _number(density, "density [kg/m^3]", where)
        if kind == BodyKind.FREE and density <= 0.0:
            raise InputError(f"{where}: density must be > 0 [kg/m^3], got {density:g}")
        return BlockSpec(verts, density, group, kind, name, where, radius or 0.0,
                         length or 0.0, float(angle) if length else 0.0, parts)

    @staticmethod
    def _convex(points: np.ndarray, where: str) -> np.ndarray:
        """The vertices [m] of a convex polygon (CCW) or of the hull of 3D points."""
        if points.ndim == 2 and points.shape[1] == 3:
            return convex_polyhedron(points, name=where).vertices
        return normalize_polygon(points, name=where)


def _read_json(path: Path, defaults: _Defaults) -> list[BlockSpec]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as err:
        raise InputError(f"{path}: not valid JSON: {err}") from None
    except UnicodeDecodeError as err:
        raise _not_text(path, err) from None
    if not isinstance(data, dict) or not isinstance(data.get("blocks"), list):
        raise InputError(f'{path}: expected an object {{"blocks": [...]}}')
    specs = []
    for i, block in enumerate(data["blocks"]):
        where = f"{path}: blocks[{i}]"
        round_ = isinstance(block, dict) and "vertices" not in block and "centre" in block
        clustered = isinstance(block, dict) and "parts" in block
        if clustered and ("vertices" in block or "centre" in block or not isinstance(
                block["parts"], list) or not block["parts"]):
            raise InputError(f'{where}: a cluster has "parts": [[[x, y], ...], ...], a list of '
                             'convex parts, and neither "vertices" nor "centre"')
        if not isinstance(block, dict) or not (round_ or clustered) and "vertices" not in block:
            raise InputError(f'{where}: expected an object with "vertices": [[x, y], ...] or, '
                             'for a disc, "centre": [x, y] and "radius" (a capsule also '
                             '"length")')
        if isinstance(block.get("name"), str):
            where += f" ({block['name']!r})"
        unknown = sorted(set(block) - set(JSON_KEYS))
        if unknown:
            raise InputError(f"{where}: unknown key {unknown[0]!r}; keys are {JSON_KEYS}")
        if not round_ and ("length" in block or "angle" in block):
            raise InputError(f'{where}: "length" and "angle" are a capsule\'s, which has '
                             '"centre" and "radius", not "vertices"')
        kind = _kind(block.get("kind", "free"), where)
        try:
            parts = [np.array(part, dtype=np.float64) for part in block.get("parts", ())]
            vertices = (parts[0] if clustered else
                        np.array([block["centre"]] if round_ else block["vertices"],
                                 dtype=np.float64))
        except (TypeError, ValueError):
            raise InputError(f"{where}: vertices must be a list of [x, y] (3D: [x, y, z]) "
                             "numbers") from None
        dim = vertices.shape[-1] if vertices.ndim == 2 else 0
        if specs and dim != specs[0].vertices.shape[1]:
            raise InputError(f"{where}: vertices of {dim} coordinates, but the blocks above "
                             f"have {specs[0].vertices.shape[1]}; a file holds 2D or 3D "
                             "blocks, not both")
        specs.append(defaults.spec(vertices, block.get("density"), block.get("group"), kind,
                                   str(block.get("name", f"block {i + 1}")), where,
                                   block.get("radius", 0.0) if round_ else None,
                                   block.get("length"), block.get("angle", 0.0), parts))
    return specs


def _read_csv(path: Path, defaults: _Defaults) -> list[BlockSpec]:
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as err:
        raise _not_text(path, err) from None
    with io.StringIO(text, newline="") as stream:
        reader = csv.DictReader(stream)
        columns = [c.strip() for c in reader.fieldnames or ()]
        missing = [c for c in CSV_COLUMNS[:3] if c not in columns]
        unknown = [c for c in columns if c not in CSV_COLUMNS_3D]
        if missing or unknown:
            raise InputError(f"{path}, line 1: the header must name the columns block, x, y "
                             f"and optionally z (3D blocks), density, group, kind; "
                             + (f"missing {missing}" if missing else f"unknown {unknown}"))
        axes = ("x", "y", "z") if "z" in columns else ("x", "y")
        reader.fieldnames = columns
        rows: list[tuple[int, dict]] = []
        for row in reader:
            rows.append((reader.line_num, {k: (v or "").strip() for k, v in row.items()
                                           if k is not None}))
    blocks: dict[str, list[tuple[int, dict]]] = {}
    last = None
    for line, row in rows:
        name = row["block"]
        if not name:
            raise InputError(f"{path}, line {line}: empty block name")
        if name in blocks and name != last:
            raise InputError(f"{path}, line {line}: block {name!r} appears again after other "
                             "blocks; keep a block's vertices on consecutive lines")
        blocks.setdefault(name, []).append((line, row))
        last = name
    specs = []
    for name, block in blocks.items():
        where = f"{path}, block {name!r} (lines {block[0][0]}-{block[-1][0]})"
        attrs = {}
        for line, row in block:
            for key in ("density", "group", "kind"):
                value = row.get(key, "")
                if value and attrs.setdefault(key, value) != value:
                    raise InputError(f"{path}, line {line}: block {name!r} has {key} "
                                     f"{value!r} here and {attrs[key]!r} above")
        vertices = [[_number(row[a], f"{a} [m]", f"{path}, line {line}") for a in axes]
                    for line, row in block]
        specs.append(defaults.spec(vertices, attrs.get("density"), attrs.get("group"),
                                   _kind(attrs.get("kind", "free"), where), name, where))
    return specs


def _read_dxf(path: Path, defaults: _Defaults, fixed_layers: Iterable[str],
              ignore_layers: Iterable[str]) -> list[BlockSpec]:
    try:
        import ezdxf
    except ImportError:
        raise InputError("reading DXF drawings needs the ezdxf package: pip install ezdxf"
                         ) from None
    try:
        doc = ezdxf.readfile(path)
    except (OSError, ezdxf.DXFError) as err:
        raise InputError(f"{path}: cannot read the DXF drawing: {err}") from None
    fixed = {layer.upper() for layer in fixed_layers}
    ignored = {layer.upper() for layer in ignore_layers}
    hint = "or put it on a layer listed in ignore_layers"
    specs = []
    for entity in doc.modelspace():
        layer, kind = entity.dxf.get("layer", "0"), entity.dxftype()
        if layer.upper() in ignored:
            continue
        where = f"{path}: {kind} handle {entity.dxf.handle} on layer {layer!r}"
        if kind == "LWPOLYLINE":
            bulges = [b for *_, b in entity.get_points("xyb")]
            points = [(v.x, v.y) for v in entity.vertices_in_wcs()]
            closed = entity.closed
        elif kind == "POLYLINE" and (entity.is_2d_polyline or entity.is_3d_polyline):
            bulges = [v.dxf.bulge for v in entity.vertices]
            points = [(v.x, v.y) for v in entity.points_in_wcs()]
            closed = entity.is_closed
        else:
            raise InputError(f"{where}: not a block (a block is a closed LWPOLYLINE or "
                             f"POLYLINE); redraw it as one, delete it, {hint}")
        if len(points) > 3 and points[0] == points[-1]:
            points, bulges, closed = points[:-1], bulges[:-1], True
        if not closed:
            raise InputError(f"{where}: an open polyline ({len(points)} points); a block "
                             f"must be closed: close it, {hint}")
        if any(bulges):
            raise InputError(f"{where}: has arc segments (bulges); a block is a polygon of "
                             "straight edges, so replace the arcs by chords")
        specs.append(defaults.spec(points, None, layer,
                                   BodyKind.FIXED if layer.upper() in fixed else BodyKind.FREE,
                                   f"{layer} {entity.dxf.handle}", where))
    if not specs:
        raise InputError(f"{path}: no closed polyline in the drawing's model space")
    return specs


def block_file_dim(path: str | Path, *, format: str | None = None) -> int:
    """2 or 3: whether the block file at `path` holds polygons or 3D point sets (JSON: its
    first block's first vertex; CSV: a z column; DXF: 2), without checking the rest."""
    path = Path(path)
    fmt = _format(path, format)
    if fmt == "dxf" or not path.is_file():
        return 2
    if fmt == "csv":
        try:
            with path.open(newline="", encoding="utf-8") as stream:
                header = next(csv.reader(stream), [])
        except UnicodeDecodeError:
            return 2  # read_blocks says what is wrong
        return 3 if "z" in (c.strip() for c in header) else 2
    try:
        block = json.loads(path.read_text(encoding="utf-8"))["blocks"][0]
        first = (block["parts"][0][0] if "parts" in block else
                 block["centre"] if "vertices" not in block else block["vertices"][0])
        return 3 if len(first) == 3 else 2
    except (json.JSONDecodeError, UnicodeDecodeError, KeyError, IndexError, TypeError):
        return 2  # read_blocks says what is wrong


def read_blocks(
    path: str | Path,
    *,
    format: str | None = None,
    density: float | Mapping[str, float] | None = None,
    group: str = "block",
    fixed_layers: Iterable[str] = ("FIXED",),
    scale: float = 1.0,
    ignore_layers: Iterable[str] = (),
) -> list[BlockSpec]:
    """The blocks of a JSON, CSV or DXF file (format from the extension unless given); see
    the module's description for the formats, defaults, `scale` and the DXF layers
    (`fixed_layers`, `ignore_layers`, any case)."""
    path = Path(path)
    fmt = _format(path, format)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    defaults = _Defaults(density, group, scale)
    if fmt == "json":
        return _read_json(path, defaults)
    if fmt == "csv":
        return _read_csv(path, defaults)
    return _read_dxf(path, defaults, fixed_layers, ignore_layers)


def write_blocks(path: str | Path, model: Model, *, format: str | None = None) -> None:
    """Write the blocks of `model` at their initial positions to a JSON or CSV file that
    read_blocks reads back (coordinates [m] written exactly)."""
    path = Path(path)
    fmt = _format(path, format)
    if fmt == "dxf":
        raise InputError(f"{path}: write_blocks writes JSON or CSV, not DXF")
    blocks = []
    for b in range(model.body_count):
        kind = BodyKind(int(model.body_kind[b]))
        if kind == BodyKind.DRIVEN:
            raise InputError(f"block {model.body_name[b]!r} is DRIVEN; block files hold free "
                             "and fixed blocks only")
        block = {"name": model.body_name[b], "group": model.group_names[model.body_group[b]],
                 "kind": kind.name.lower(), "density": float(model.body_density[b])}
        if model.body_round_radius[b] > 0.0:
            capsule = model.body_shape[b] == Shape.CAPSULE
            if fmt == "csv":
                raise InputError(f"block {model.body_name[b]!r} is a "
                                 f"{'capsule' if capsule else 'disc (sphere)'}; CSV block "
                                 "files hold polygons only: write JSON")
            block.update(centre=model.body_q0[b, : model.dim].tolist(),
                         radius=float(model.body_round_radius[b]))
            if capsule and model.dim == 3:
                raise InputError(f"block {model.body_name[b]!r} is a 3D capsule; block files "
                                 "hold 2D capsules only (centre, length, angle)")
            if capsule:
                angle, length = capsule_axis(model, b)
                block.update(length=length, angle=angle)
        else:
            parts = model.part_vertices(b)
            if len(parts) > 1 and fmt == "csv":
                raise InputError(f"block {model.body_name[b]!r} is a cluster (non-convex); CSV "
                                 "block files hold convex blocks only: write JSON")
            if len(parts) > 1:
                block["parts"] = [part.tolist() for part in parts]
            else:
                block["vertices"] = parts[0].tolist()
        blocks.append(block)
    if fmt == "json":
        path.write_text(json.dumps({"blocks": blocks}, indent=1), encoding="utf-8")
        return
    with path.open("w", newline="", encoding="utf-8") as stream:
        out = csv.writer(stream)
        out.writerow(CSV_COLUMNS if model.dim == 2 else CSV_COLUMNS_3D)
        for block in blocks:
            for k, point in enumerate(block["vertices"]):
                attrs = ([repr(block["density"]), block["group"], block["kind"]] if k == 0
                         else ["", "", ""])
                out.writerow([block["name"], *map(repr, point), *attrs])


def add_blocks_from_file(builder: ModelBuilder, path: str | Path, **options) -> Assembly:
    """Add the blocks of a file (read_blocks(path, **options)); part "blocks", in file order.
    The builder's dim must be the file's (3D blocks: ModelBuilder(dim=3))."""
    asm = Assembly()
    specs = read_blocks(path, **options)
    if specs and specs[0].vertices.shape[1] != builder.dim:
        d = specs[0].vertices.shape[1]
        raise InputError(f"{path} holds {d}D blocks and the model is {builder.dim}D: build it "
                         f"with ModelBuilder(dim={d})")
    for spec in specs:
        common = dict(group=spec.group, density=spec.density, kind=spec.kind, name=spec.name)
        if spec.length > 0.0:
            asm.add_capsule(builder, "blocks", spec.vertices[0], spec.length, spec.radius,
                            spec.angle, **common)
        elif spec.radius > 0.0:
            asm.add_round(builder, "blocks", spec.vertices[0], spec.radius, **common)
        elif spec.parts:
            asm.add_cluster(builder, "blocks", spec.parts, **common)
        else:
            asm.add_block(builder, "blocks", spec.vertices, **common)
    return asm


def blocks_model(path: str | Path, *, friction: float = 0.6,
                 law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
                 gravity: tuple[float, ...] | None = None, **options) -> Model:
    """A model of the blocks of a file (add_blocks_from_file; 2D or 3D as the file is),
    friction mu [-] between every pair of groups, gravity [m/s^2] (default downward)."""
    builder = ModelBuilder(dim=block_file_dim(path, format=options.get("format")),
                           gravity=gravity)
    asm = add_blocks_from_file(builder, path, **options)
    return finalize(builder, asm.groups, friction, law)
