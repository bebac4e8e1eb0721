"""Deformable (finite-element) blocks: material, meshing, assembly (scikit-fem) and the
compiled co-rotational kernels of the Moreau-Jean step over all blocks (see blocks.py).

The names load on first use: a run of rigid blocks imports saxum.fe.blocks' kernels and not
scikit-fem and scipy.sparse (~0.3 s), which only assembly needs."""

import importlib

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


def __getattr__(name: str):
    """A public name, imported from its module on first use."""
    if name in _EXPORTS:
        value = getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_EXPORTS})
