"""3D blocks from mesh files: OBJ, STL, PLY, OFF, VTK/VTU and the other formats meshio reads.

Each connected part of the file's surface is one block. A block must be a closed surface
(every edge shared by exactly two faces) around a convex solid: its volume, from the surface
by the divergence theorem, must equal the volume of the convex hull of its vertices; the block
is then that hull (saxum.geometry3d). Volume cells (tetrahedra, hexahedra, ...) are accepted
too: the cells of each block are those with the same tag, the first of the cell data "block",
"gmsh:physical" and "gmsh:geometrical" the file has (gmsh gives each volume its own), or
without a tag each connected group of cells (sharing a node: a conforming mesh of stones in
contact is then one group, and must be tagged); the cells' volumes must add up to the hull's
(a convex block), and the block is the hull of its points. Points closer than 1e-9 of the
file's size are merged first (STL repeats them for every triangle).

Faces are connected through their edges. Blocks that touch (stacked stones, whose joint faces
share corners and edges) meet at edges of more than two faces; there each face is joined to
the first face with the opposite sense along the edge that one meets turning about the edge
from the face into its solid side (the face that closes its solid wedge), so touching blocks
stay apart.
"""

import warnings
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..geometry3d import convex_polyhedron, polyhedron_properties
from ..model import BodyKind, ModelBuilder
from ._common import Assembly

__all__ = ["add_blocks_from_mesh", "read_mesh_blocks"]

_SURFACE = ("triangle", "quad", "polygon")
_VOLUME = {"tetra": 4, "hexahedron": 8, "wedge": 6, "pyramid": 5, "tetra10": 4,
           "hexahedron20": 8}
"""Volume cell types, and how many of their nodes are corners (the first ones)."""
_TAGS = ("block", "gmsh:physical", "gmsh:geometrical")


def read_mesh_blocks(path: str | Path) -> list[np.ndarray]:
    """The blocks of a mesh file as point sets [m] (n, 3), one per connected part, checked
    (module doc); InputError naming the file and the block otherwise."""
    import meshio  # here, not at import: a run without mesh files does without its 0.1 s
    from scipy.spatial import ConvexHull

    path = Path(path)
    if not path.is_file():
        raise InputError(f"no mesh file at {path}")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # meshio's harmless format chatter
            mesh = meshio.read(path)
    except Exception as err:  # meshio raises ReadError, KeyError, ValueError... by format
        raise InputError(f"{path}: not a mesh file meshio can read ({err}); use OBJ, STL, "
                         "PLY, OFF or VTU") from None
    points = np.asarray(mesh.points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3 or not np.all(np.isfinite(points)):
        raise InputError(f"{path}: the points must be finite (x, y, z) coordinates")
    faces = [list(map(int, f)) for c in mesh.cells if c.type in _SURFACE for f in c.data]
    solids = [list(map(int, f[:_VOLUME[c.type]])) for c in mesh.cells if c.type in _VOLUME
              for f in c.data]
    if not faces and not solids:
        raise InputError(f"{path}: no faces (triangles, quads, polygons) or volume cells")
    scale = float(np.ptp(points, axis=0).max()) or 1.0
    points, index = _merge(points, 1e-9 * scale)
    faces = [[int(index[k]) for k in f] for f in faces]
    solids = [[int(index[k]) for k in s] for s in solids]
    blocks = []
    tags = _cell_tags(mesh) if solids else None
    if tags is not None:
        parts = [([], [s for s, t in zip(solids, tags, strict=True) if t == tag])
                 for tag in dict.fromkeys(tags.tolist())]
    elif solids:
        parts = _parts(len(points), faces, solids)
    else:
        parts = [(part, []) for part in _surface_parts(points, faces)]
    for number, (part_faces, part_solids) in enumerate(parts):
        near = points[(part_faces or part_solids)[0][0]]
        where = f"{path}: block {number} (near {_xyz(near)})"
        used = np.unique(np.concatenate([np.asarray(c) for c in part_faces + part_solids]))
        if part_faces:
            _check_closed(part_faces, points, where)
        poly = convex_polyhedron(points[used], name=where)
        hull_volume = polyhedron_properties(poly).volume
        if part_solids:
            volume = sum(ConvexHull(points[s]).volume for s in part_solids)
            if abs(volume - hull_volume) > 1e-6 * hull_volume:
                raise InputError(f"{where}: its {len(part_solids)} volume cells fill "
                                 f"{volume:.6g} m^3, their convex hull {hull_volume:.6g} m^3: "
                                 "not one convex block; tag each block's cells (cell data "
                                 f"{' or '.join(repr(t) for t in _TAGS)}) or split it into "
                                 "convex blocks")
        elif part_faces:
            volume = abs(_surface_volume(part_faces, points))
            if abs(volume - hull_volume) > 1e-6 * hull_volume:
                raise InputError(f"{where}: not convex: it encloses {volume:.6g} m^3, its "
                                 f"convex hull {hull_volume:.6g} m^3; split it into convex "
                                 "blocks")
        blocks.append(points[used])
    return blocks


def _cell_tags(mesh) -> np.ndarray | None:
    """The block tag of each volume cell, in file order: the first of _TAGS in the file's cell
    data, or None."""
    for key in _TAGS:
        data = mesh.cell_data.get(key)
        if data is not None:
            return np.concatenate([np.asarray(d).ravel() for c, d in zip(mesh.cells, data,
                                                                         strict=True)
                                   if c.type in _VOLUME])
    return None


def _merge(points: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Points closer than about tol merged: (unique points, index of each input point)."""
    keys = np.round(points / tol).astype(np.int64)
    _, first, index = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    return points[first], index.ravel()


def _parts(n: int, faces: list[list[int]], solids: list[list[int]]):
    """(faces, solids) of each connected part, ordered by their first cell in the file."""
    parent = np.arange(n)

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for cell in faces + solids:
        root = find(cell[0])
        for k in cell[1:]:
            other = find(k)
            if other != root:
                parent[other] = root
    parts: dict[int, tuple[list, list]] = {}
    for cell in faces:
        parts.setdefault(find(cell[0]), ([], []))[0].append(cell)
    for cell in solids:
        parts.setdefault(find(cell[0]), ([], []))[1].append(cell)
    return list(parts.values())


def _surface_parts(points: np.ndarray, faces: list[list[int]]) -> list[list[list[int]]]:
    """The faces of each block (module doc), ordered by their first face in the file."""
    edges: dict[tuple[int, int], list[int]] = {}
    for f, face in enumerate(faces):
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            edges.setdefault((min(a, b), max(a, b)), []).append(f)
    parent = list(range(len(faces)))

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for (a, b), at_edge in edges.items():
        pairs = ([tuple(at_edge)] if len(at_edge) <= 2
                 else _pair_at_edge(points, faces, a, b, at_edge))
        for f, g in (p for p in pairs if len(p) == 2):
            parent[find(g)] = find(f)
    parts: dict[int, list[list[int]]] = {}
    for f, face in enumerate(faces):
        parts.setdefault(find(f), []).append(face)
    return list(parts.values())


def _pair_at_edge(points: np.ndarray, faces: list[list[int]], a: int, b: int,
                  at_edge: list[int]) -> list[tuple[int, int]]:
    """(face, the face that closes its solid wedge) for the faces meeting at edge a-b."""
    axis = points[b] - points[a]
    axis /= np.linalg.norm(axis)
    side = np.cross(axis, _any_normal(axis))
    angle, forward, into = [], [], []
    for f in at_edge:
        p = points[faces[f]]
        wing = p.mean(axis=0) - points[a]
        wing -= (wing @ axis) * axis
        angle.append(float(np.arctan2(wing @ side, wing @ _any_normal(axis))))
        k = faces[f].index(a)
        forward.append(faces[f][(k + 1) % len(faces[f])] == b)
        # outward normal (Newell); the solid is on its other side
        normal = np.sum(np.cross(p, np.roll(p, -1, axis=0)), axis=0)
        into.append(1.0 if normal @ np.cross(axis, wing) < 0.0 else -1.0)
    pairs = []
    for i, f in enumerate(at_edge):
        turns = [((into[i] * (angle[j] - angle[i])) % (2.0 * np.pi), g)
                 for j, g in enumerate(at_edge) if forward[j] != forward[i]]
        turns = [(t if 1e-9 < t < 2.0 * np.pi - 1e-9 else 2.0 * np.pi, g) for t, g in turns]
        if turns:
            pairs.append((f, min(turns)[1]))
    return pairs


def _any_normal(u: np.ndarray) -> np.ndarray:
    """A unit vector normal to the unit vector u."""
    v = np.cross(u, (1.0, 0.0, 0.0) if abs(u[0]) < 0.9 else (0.0, 1.0, 0.0))
    return v / np.linalg.norm(v)


def _check_closed(faces: list[list[int]], points: np.ndarray, where: str) -> None:
    """Every edge in exactly two faces, run through in opposite senses (consistently
    oriented faces, which the volume needs)."""
    count: dict[tuple[int, int], int] = {}
    directed: dict[tuple[int, int], int] = {}
    for f in faces:
        for a, b in zip(f, f[1:] + f[:1], strict=True):
            key = (min(a, b), max(a, b))
            count[key] = count.get(key, 0) + 1
            directed[(a, b)] = directed.get((a, b), 0) + 1
    bad = [(e, c) for e, c in count.items() if c != 2]
    if bad:
        (a, b), c = bad[0]
        raise InputError(
            f"{where}: the surface is not closed: the edge from {_xyz(points[a])} to "
            f"{_xyz(points[b])} belongs to {c} face(s), not 2 ({len(bad)} such edge(s)); "
            "close the mesh (a block must be a solid)"
        )
    twice = [e for e, c in directed.items() if c != 1]
    if twice:
        a, b = twice[0]
        raise InputError(f"{where}: the faces are not consistently oriented (two faces run "
                         f"through the edge from {_xyz(points[a])} to {_xyz(points[b])} the "
                         "same way); orient the mesh's faces consistently")


def _xyz(p: np.ndarray) -> tuple[float, ...]:
    return tuple(float(x) for x in p.round(6))


def _surface_volume(faces: list[list[int]], points: np.ndarray) -> float:
    """Signed volume enclosed by consistently oriented faces (divergence theorem, fans)."""
    origin = points[faces[0][0]]
    total = 0.0
    for f in faces:
        a = points[f[0]] - origin
        for k in range(1, len(f) - 1):
            total += float(a @ np.cross(points[f[k]] - origin, points[f[k + 1]] - origin))
    return total / 6.0


def add_blocks_from_mesh(builder: ModelBuilder, path: str | Path, *, density: float,
                         group: str = "block", kind: BodyKind = BodyKind.FREE) -> Assembly:
    """Add the blocks of a mesh file (read_mesh_blocks) to a ModelBuilder(dim=3); part
    "blocks", named "<file stem> <k>" in the file's order."""
    if builder.dim != 3:
        raise InputError("blocks from a mesh file need a ModelBuilder(dim=3)")
    asm = Assembly()
    stem = Path(path).stem
    for k, points in enumerate(read_mesh_blocks(path)):
        asm.add_block(builder, "blocks", points, group=group, density=density, kind=kind,
                      name=f"{stem} {k}")
    return asm
