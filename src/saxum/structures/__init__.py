"""Parametric masonry structures. Every dimension in metres, density in kg/m^3."""

from .arch import add_semicircular_arch, add_supported_semicircular_arch, semicircular_arch
from .wall import add_grounded_running_bond_wall, add_running_bond_wall, running_bond_wall

__all__ = ["add_grounded_running_bond_wall", "add_running_bond_wall", "add_semicircular_arch",
           "add_supported_semicircular_arch", "running_bond_wall", "semicircular_arch"]
