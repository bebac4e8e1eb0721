"""Deformable (finite-element) blocks: material, meshing, assembly (scikit-fem) and the
compiled co-rotational kernels of the Moreau-Jean step over all blocks (see blocks.py).

The names load on first use: a run of rigid blocks imports saxum.fe.blocks' kernels and not
scikit-fem and scipy.sparse (~0.3 s), which only assembly needs."""

from .. import _lazy_names

_EXPORTS = {
    "DEFAULT_MAX_NODES": "mesh",
    "Elastic": "material",
    "FEBlocks": "blocks",
    "Mesh": "mesh",
    "damping": "assembly",
    "mass_stiffness": "assembly",
    "mesh_polygon": "mesh",
    "mesh_polyhedron": "mesh",
}
"""Each public name: the module that defines it."""

__all__ = sorted(_EXPORTS)
__getattr__, __dir__ = _lazy_names(__name__, _EXPORTS, globals())
