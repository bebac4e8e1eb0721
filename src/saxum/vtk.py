"""ParaView export: a .pvd time series with two datasets (parts) per output frame.

`export_vtk(results, directory)` writes

    directory/<stem>.pvd                    the collection to open in ParaView
    directory/<stem>/blocks_<frame>.vtu     part 0: one polygon cell per block
    directory/<stem>/contacts_<frame>.vtu   part 1: one vertex cell per contact

and, for results with deformable blocks, part 2:

    directory/<stem>/elements_<frame>.vtu   their triangle (3D: tetrahedron) meshes, with node
                                            displacement and velocity and cell stresses [Pa]
                                            (Results.stresses)

where <stem> is the results file's name without its suffix and <frame> the output frame index
(6 digits). Points are 3D (z = 0 for 2D results) and vectors have 3 components. Blocks carry cell
data: displacement [m] of the centre of mass from its initial position, velocity [m/s], rotation
[rad] from the initial orientation, angular_velocity [rad/s], body_index, body_kind (0 free,
1 fixed, 2 driven, 3 deformable: its polygon moved by its co-rotated frame). Contacts carry
point data: normal_force and tangential_force [N/m] (mean over the step, impulse / dt), force
[N/m] (world vector R_t t + R_n n), normal (unit, world), gap [m], candidate and antagonist
(body indices), and where the results have them the joint laws' damage [-] (0 intact, 1
cracked: saxum.laws), crush [m] (a cap's plastic closure) and area [m^2/m; 3D: m^2]; use
ParaView's Glyph filter on force.

3D results: each block is written as its polygonal faces (one polygon cell per face, every face
carrying its block's data, so that ParaView's Threshold on body_index picks whole blocks);
rotation is the rotation vector [rad] (world frame, length: the angle) from the initial
orientation, angular_velocity is in the world frame, forces are in N (not per metre), and
tangential_force is the magnitude of the friction force (R_t, R_s).
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Iterable
from pathlib import Path

import meshio
import numpy as np

from .errors import InputError
from .geometry3d import rotation_matrix, rotation_vectors, world_points
from .model import drawn_outlines, drawn_polyhedra
from .results import Results

__all__ = ["export_vtk"]


def export_vtk(results: Results | str | os.PathLike, directory: str | os.PathLike, *,
               frames: Iterable[int] | None = None) -> Path:
    """Write the output frames `frames` (indices, default all) of `results` (a Results or the
    path of a results file) as a ParaView time series under `directory`; returns the .pvd path.
    """
    if not isinstance(results, Results):
        with Results(results) as res:
            return export_vtk(res, directory, frames=frames)
    if results.dim not in (2, 3):
        raise InputError(f"{results.path}: dim {results.dim} is neither 2 nor 3")
    blocks = _blocks if results.dim == 2 else _faces
    directory = Path(directory)
    stem = results.path.stem
    (directory / stem).mkdir(parents=True, exist_ok=True)
    indices = range(results.frame_count)
    selected = indices if frames is None else [indices[k] for k in frames]
    collection = ET.Element("VTKFile", type="Collection", version="0.1",
                            byte_order="LittleEndian")
    datasets = ET.SubElement(collection, "Collection")
    for k in selected:
        parts = [("blocks", blocks(results, k)), ("contacts", _contacts(results, k))]
        if results.node_x is not None:
            parts.append(("elements", _elements(results, k)))
        for part, (name, mesh) in enumerate(parts):
            file = f"{stem}/{name}_{k:06d}.vtu"
            # A frame without contacts goes uncompressed: meshio's zlib header for 0 bytes
            # claims a last block of 32768 bytes.
            meshio.write(directory / file, mesh, file_format="vtu",
                         compression="zlib" if len(mesh.points) else None)
            ET.SubElement(datasets, "DataSet", timestep=repr(float(results.time[k])), group="",
                          part=str(part), name=name, file=file)
    ET.indent(collection)
    pvd = directory / f"{stem}.pvd"
    ET.ElementTree(collection).write(pvd, encoding="utf-8", xml_declaration=True)
    return pvd


def _pad3(a: np.ndarray) -> np.ndarray:
    """Vectors (..., d) with d <= 3 padded with zeros to (..., 3)."""
    return np.concatenate([a, np.zeros((*a.shape[:-1], 3 - a.shape[-1]))], axis=-1)


def _blocks(res: Results, k: int) -> meshio.Mesh:
    """The blocks at output frame k: polygon cells (one cell block per vertex count, as meshio
    needs equal-sized cells in a block) over the world vertices [m] of all blocks."""
    m = res.model
    start, loc = drawn_outlines(m["body_vertex_start"], m["vertex_local"],
                                m.get("body_round_radius"), shape=m.get("body_shape"),
                                contactor_start=m.get("contactor_vertex_start"))
    count = np.diff(start)
    q, v, q0 = res.body_q[k], res.body_v[k], m["body_q0"]
    # 2D: each vertex turned by its body's angle theta, then shifted to the centre of mass.
    owner = np.repeat(np.arange(count.size), count)
    x, y, th = q[owner, 0], q[owner, 1], q[owner, 2]
    c, s = np.cos(th), np.sin(th)
    points = _pad3(np.column_stack((x + c * loc[:, 0] - s * loc[:, 1],
                                    y + s * loc[:, 0] + c * loc[:, 1])))
    body_data = {
        "displacement": _pad3(q[:, :2] - q0[:, :2]),
        "velocity": _pad3(v[:, :2]),
        "rotation": q[:, 2] - q0[:, 2],
        "angular_velocity": v[:, 2],
        "body_index": np.arange(count.size, dtype=np.int32),
        "body_kind": m["body_kind"].astype(np.int32),
    }
    sizes = np.unique(count)
    members = [np.flatnonzero(count == n) for n in sizes]
    cells = [("polygon", start[b, None] + np.arange(n))
             for n, b in zip(sizes, members, strict=True)]
    cell_data = {name: [a[b] for b in members] for name, a in body_data.items()}
    return meshio.Mesh(points, cells, cell_data=cell_data)


def _faces(res: Results, k: int) -> meshio.Mesh:
    """3D blocks at output frame k: their faces as polygon cells over the world vertices."""
    m = res.model
    g = drawn_polyhedra(m)
    q, v, q0 = res.body_q[k], res.body_v[k], m["body_q0"]
    points = world_points(q, g["body_vertex_start"], g["vertex_local"])
    rot = rotation_matrix(q[:, 3:])
    body_data = {
        "displacement": q[:, :3] - q0[:, :3],
        "velocity": v[:, :3],
        "rotation": rotation_vectors(q[:, 3:], q0[:, 3:]),
        "angular_velocity": np.einsum("bij,bj->bi", rot, v[:, 3:]),
        "body_index": np.arange(len(q), dtype=np.int32),
        "body_kind": m["body_kind"].astype(np.int32),
    }
    # faces as runs of the face_vertex list, each with its block's data
    face_start = g["body_face_start"]
    owner = np.repeat(np.arange(len(q)), np.diff(face_start))
    fvs = g["face_vertex_start"]
    order = np.argsort(np.diff(fvs), kind="stable")  # group equal sizes, keep face order
    count = np.diff(fvs)
    cells = []
    data: dict[str, list] = {name: [] for name in body_data}
    for n in np.unique(count):
        faces = order[count[order] == n]
        cells.append(("polygon", g["face_vertex"][fvs[faces, None] + np.arange(n)]))
        for name, a in body_data.items():
            data[name].append(a[owner[faces]])
    return meshio.Mesh(points, cells, cell_data=data)


def _elements(res: Results, k: int) -> meshio.Mesh:
    """The deformable blocks' meshes at output frame k: triangle (3D: tetrahedron) cells over
    the nodes [m], with point data displacement [m] and velocity [m/s], cell data stress [Pa]
    (2D: sxx, syy, sxy; 3D: sxx, syy, szz, sxy, syz, sxz, the order of ParaView's symmetric
    tensors) and principal (ascending) [Pa], compression and tension (the largest of each,
    >= 0) [Pa] and body_index."""
    m = res.model
    stresses = res.stresses(k)
    owner = m["fe_body"][np.repeat(np.arange(len(m["fe_body"])), np.diff(m["fe_cell_start"]))]
    stress = stresses["stress"]
    # Results' 3D order is Voigt's (xx, yy, zz, yz, xz, xy)
    stress = _pad3(stress) if res.dim == 2 else stress[:, [0, 1, 2, 5, 3, 4]]
    cell_data = {"stress": [stress],
                 "principal": [_pad3(stresses["principal"])],
                 "compression": [stresses["compression"]], "tension": [stresses["tension"]],
                 "body_index": [owner.astype(np.int32)]}
    point_data = {"displacement": _pad3(res.node_x[k] - m["fe_node_x0"]),
                  "velocity": _pad3(res.node_v[k])}
    cell = "triangle" if res.dim == 2 else "tetra"
    return meshio.Mesh(_pad3(res.node_x[k]), [(cell, m["fe_cell_node"])],
                       point_data=point_data, cell_data=cell_data)


def _contacts(res: Results, k: int) -> meshio.Mesh:
    """The contacts at output frame k: one vertex cell at each contact point [m]."""
    c = res.contacts(k)
    f = c["force"]  # (t, n) or (t, n, s) components [N/m; 3D: N]
    point_data = {
        "normal_force": f[:, 1],
        "tangential_force": f[:, 0] if res.dim == 2 else np.hypot(f[:, 0], f[:, 2]),
        "force": _pad3(np.einsum("ki,kij->kj", f, c["frame"])),
        "normal": _pad3(c["frame"][:, 1]),
        "gap": c["gap"],
        "candidate": c["candidate"],
        "antagonist": c["antagonist"],
    }
    for name in ("damage", "crush", "area"):  # absent from files of saxum before them
        if name in c:
            point_data[name] = c[name]
    cells = [("vertex", np.arange(len(f))[:, None])]
    return meshio.Mesh(_pad3(c["point"]), cells, point_data=point_data)
