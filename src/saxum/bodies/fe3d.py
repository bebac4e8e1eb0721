"""Deformable blocks in 3D: what the FE body kind (saxum.bodies.fe) needs beyond what is
the same in both dimensions. The mechanics (tetrahedra, co-rotated frames, M~^-1) are
saxum.fe's and the contact rows saxum.bodies.fe's, for any dimension; here are the meshes of
polyhedra with their nodes' tributary boundary and the body rows' quaternions of the frames.
"""

import numpy as np

from ..fe.mesh import Mesh, fit_mesh, mesh_polyhedron
from ..geometry3d import Polyhedron, rotation_matrix

__all__ = ["frame_quaternions", "mesh_polyhedra", "principal_axes"]


def mesh_polyhedra(polyhedra: list[Polyhedron], sizes: list[float | None],
                   names: list[str]) -> tuple[list[Mesh], list[np.ndarray]]:
    """Tetrahedral meshes of the polyhedra (saxum.fe.mesh_polyhedron) with elements of about
    their size [m] (None: half the block's shortest edge, at least two elements through it;
    a saxum.fe.Mesh: that mesh, checked to fill the block, saxum.fe.mesh.fit_mesh),
    and each mesh's node sides [n, K, 3]: a third of the area vector (outward normal times
    area [m^2]) of each boundary triangle at the node, in K slots (zeros beyond its count), so
    that a node's contact area on a face of normal n is sum max(0, -n . R s)."""
    meshes, sides = [], []
    for poly, size, name in zip(polyhedra, sizes, names, strict=True):
        if isinstance(size, Mesh):
            offsets = np.array([n @ poly.vertices[f[0]] for n, f in zip(poly.normals,
                                                                         poly.faces,
                                                                         strict=True)])
            # the divergence theorem: V = sum over faces of (n . x_f) A_f / 3
            areas = [0.5 * np.linalg.norm(sum(np.cross(poly.vertices[f[k]] - poly.vertices[f[0]],
                                                       poly.vertices[f[k + 1]]
                                                       - poly.vertices[f[0]])
                                              for k in range(1, len(f) - 1)))
                     for f in poly.faces]
            mesh = fit_mesh(size, poly.normals, offsets, float(offsets @ areas) / 3.0,
                            name=name)
        else:
            if size is None:
                ends = poly.vertices[poly.edges]
                size = 0.5 * float(np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1).min())
            mesh = mesh_polyhedron(poly.vertices, poly.faces, size, name=name)
        meshes.append(mesh)
        a, b, c = (mesh.nodes[mesh.facets[:, k]] for k in range(3))
        share = np.repeat(np.cross(b - a, c - a) / 6.0, 3, axis=0)  # (area / 3) n per corner
        node = mesh.facets.ravel()
        order = np.argsort(node, kind="stable")
        first = np.searchsorted(node[order], node[order])
        slot = np.empty_like(node)
        slot[order] = np.arange(len(node)) - first
        side = np.zeros((len(mesh.nodes), slot.max() + 1, 3))
        side[node, slot] = share
        sides.append(side)
    widest = max(s.shape[1] for s in sides)
    return meshes, [np.pad(s, ((0, 0), (0, widest - s.shape[1]), (0, 0))) for s in sides]


def frame_quaternions(rotation: np.ndarray, axes0: np.ndarray) -> np.ndarray:
    """Unit quaternions (w, x, y, z), w >= 0, of the blocks' body frames R R0 [nb, 4]: the
    co-rotated frame R [nb, 3, 3] turning the principal axes R0 [nb, 3, 3] of the reference
    block (the body row's frame, saxum.model)."""
    from scipy.spatial.transform import Rotation  # scipy.spatial: ~0.5 s, not at import

    xyzw = Rotation.from_matrix(rotation @ axes0).as_quat()
    q = np.concatenate((xyzw[:, 3:], xyzw[:, :3]), axis=1)
    return np.where(q[:, :1] < 0.0, -q, q)


def principal_axes(body_q0: np.ndarray) -> np.ndarray:
    """Rotation matrices [n, 3, 3] of the body rows' quaternions body_q0 [n, 7]."""
    return np.array([rotation_matrix(q[3:]) for q in body_q0]).reshape(-1, 3, 3)
