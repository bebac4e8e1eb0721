"""Parametric masonry structures, each ready to simulate. Every dimension in metres, density in
kg/m^3.

Each generator has an add_...(builder, ...) form that adds its blocks to a ModelBuilder and
returns an Assembly (body indices by part, groups used, loads applied), and a form that returns
a finalized Model with one Coulomb law (friction=...) between every pair of its groups:

- arches (ArchShape: semicircular, circular of any embrace, segmental, pointed, elliptical,
  basket-handle, flat; radial or vertical joints; in several rings: arch_rings): add_arch,
  add_supported_arch, arch;
- walls in running or stack bond with openings (Opening): add_wall, wall;
- piers and buttressed walls: add_pier, pier, add_buttressed_wall, buttressed_wall;
- multi-span arch bridges: add_arch_bridge, arch_bridge;
- granular fill: discs or spheres of random radii, seeded, in a box (add_granular_fill) or in
  a 2D container (add_granular_box);
- blocks from JSON, CSV or DXF files (JSON and CSV also 3D): read_blocks,
  add_blocks_from_file, blocks_model, write_blocks, block_file_dim;
- in 3D (saxum.structures.solid): extruded 2D structures (add_extruded, extruded), arches and
  barrel vaults (add_arch3d, arch3d, add_semicircular_arch3d), a single-span bridge with
  spandrel walls (add_bridge3d, bridge3d), walls in running bond with an L-shaped corner
  (add_wall3d, wall3d), piers (add_pier3d, pier3d), a ground slab (add_ground_slab), blocks from
  mesh files: OBJ, STL, PLY, OFF, VTU... (read_mesh_blocks, add_blocks_from_mesh).
"""

from ._common import Assembly
from .arch import (
    ArchShape,
    Ring,
    add_arch,
    add_semicircular_arch,
    add_supported_arch,
    add_supported_semicircular_arch,
    arch,
    arch_ring,
    arch_rings,
    semicircular_arch,
)
from .blockfile import (
    BlockSpec,
    add_blocks_from_file,
    block_file_dim,
    blocks_model,
    read_blocks,
    write_blocks,
)
from .bridge import add_arch_bridge, arch_bridge
from .granular import add_granular_box, add_granular_fill
from .meshfile import add_blocks_from_mesh, read_mesh_blocks
from .piers import add_buttressed_wall, add_pier, buttressed_wall, pier
from .solid import (
    add_arch3d,
    add_bridge3d,
    add_extruded,
    add_ground_slab,
    add_pier3d,
    add_semicircular_arch3d,
    add_wall3d,
    arch3d,
    bridge3d,
    extruded,
    pier3d,
    wall3d,
)
from .wall import (
    Opening,
    add_grounded_running_bond_wall,
    add_running_bond_wall,
    add_wall,
    running_bond_wall,
    wall,
)

__all__ = [
    "ArchShape",
    "Assembly",
    "BlockSpec",
    "Opening",
    "Ring",
    "add_arch",
    "add_arch3d",
    "add_arch_bridge",
    "add_blocks_from_mesh",
    "add_bridge3d",
    "add_blocks_from_file",
    "add_buttressed_wall",
    "add_granular_box",
    "add_granular_fill",
    "add_extruded",
    "add_ground_slab",
    "add_pier3d",
    "add_wall3d",
    "add_grounded_running_bond_wall",
    "add_pier",
    "add_running_bond_wall",
    "add_semicircular_arch",
    "add_semicircular_arch3d",
    "add_supported_arch",
    "add_supported_semicircular_arch",
    "add_wall",
    "arch",
    "arch_bridge",
    "arch3d",
    "arch_ring",
    "arch_rings",
    "block_file_dim",
    "blocks_model",
    "bridge3d",
    "buttressed_wall",
    "extruded",
    "pier",
    "pier3d",
    "read_blocks",
    "read_mesh_blocks",
    "running_bond_wall",
    "semicircular_arch",
    "wall",
    "wall3d",
    "write_blocks",
]
