"""Deformable (finite-element) blocks: material, meshing, assembly (scikit-fem) and the
compiled co-rotational kernels of the Moreau-Jean step over all blocks (see blocks.py)."""

from saxum.fe.assembly import damping, mass_stiffness
from saxum.fe.blocks import FEBlocks
from saxum.fe.material import Elastic
from saxum.fe.mesh import DEFAULT_MAX_NODES, Mesh, mesh_polygon, mesh_polyhedron

__all__ = ["DEFAULT_MAX_NODES", "Elastic", "FEBlocks", "Mesh", "damping", "mass_stiffness",
           "mesh_polygon", "mesh_polyhedron"]
