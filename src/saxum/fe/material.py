"""Material of a deformable (finite-element) block: isotropic linear elasticity with Rayleigh
damping C = alpha M + beta K.

In 2D a block is either a slab of given thickness t [m] in plane stress (sigma_zz = 0), or a
slice of a long body in plane strain (epsilon_zz = 0), computed per metre of depth. Plane stress
is plane strain with the effective first Lame parameter lambda* = 2 lambda mu / (lambda + 2 mu)
(e.g. Zienkiewicz & Taylor, The Finite Element Method, vol. 1, 6th ed., sec. 6.2).
"""

import math
from dataclasses import dataclass

import numpy as np

from saxum.errors import InputError, plain

__all__ = ["Elastic"]


@dataclass(frozen=True)
class Elastic:
    """Isotropic linear elastic material.

    E: Young's modulus [Pa]; nu: Poisson's ratio [-], in (-1, 0.5); density [kg/m^3];
    damping: Rayleigh coefficients (alpha [1/s], beta [s]), C = alpha M + beta K;
    thickness [m]: 2D only, plane stress of that thickness; None is plane strain (per metre
    of depth) in 2D and is required in 3D.
    """

    E: float
    nu: float
    density: float
    damping: tuple[float, float] = (0.0, 0.0)
    thickness: float | None = None

    def __post_init__(self):
        def finite(name, value):
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise InputError(f"Elastic material: {name} = {plain(value)} is not a number; "
                                 f"give {name} as a number in SI units") from None
            if not math.isfinite(value):
                raise InputError(f"Elastic material: {name} = {plain(value)} is not finite; "
                                 f"give a finite {name}")
            return value

        E = finite("E", self.E)
        if E <= 0.0:
            raise InputError(f"Elastic material: Young's modulus E = {plain(self.E)} Pa must be "
                             "positive; give E in Pa (stone: about 1e10)")
        nu = finite("nu", self.nu)
        if not -1.0 < nu < 0.5:
            raise InputError(f"Elastic material: Poisson's ratio nu = {plain(self.nu)} must lie "
                             "in (-1, 0.5) (0.5 is incompressible, which P1 elements lock on); "
                             "stone: about 0.2")
        density = finite("density", self.density)
        if density <= 0.0:
            raise InputError(f"Elastic material: density = {plain(self.density)} kg/m^3 must be "
                             "positive; give it in kg/m^3 (stone: about 2500)")
        try:
            alpha, beta = self.damping
        except (TypeError, ValueError):
            raise InputError(f"Elastic material: damping = {plain(self.damping)} must be a pair "
                             "(alpha [1/s], beta [s]) of Rayleigh coefficients") from None
        alpha = finite("damping alpha", alpha)
        beta = finite("damping beta", beta)
        if alpha < 0.0 or beta < 0.0:
            raise InputError(f"Elastic material: damping = {plain(self.damping)} has a negative "
                             "coefficient; Rayleigh alpha [1/s] and beta [s] must be >= 0")
        thickness = self.thickness
        if thickness is not None:
            thickness = finite("thickness", thickness)
            if thickness <= 0.0:
                raise InputError(f"Elastic material: thickness = {plain(self.thickness)} m must "
                                 "be positive (plane stress), or None for plane strain")
        object.__setattr__(self, "E", E)
        object.__setattr__(self, "nu", nu)
        object.__setattr__(self, "density", density)
        object.__setattr__(self, "damping", (alpha, beta))
        object.__setattr__(self, "thickness", thickness)

    def lame(self, dim: int) -> tuple[float, float]:
        """(lambda, mu) [Pa] of the stress-strain law sigma = lambda tr(eps) I + 2 mu eps in
        `dim` dimensions: the effective lambda* = 2 lambda mu / (lambda + 2 mu) in plane stress."""
        mu = self.E / (2.0 * (1.0 + self.nu))
        lam = self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))
        if dim == 2 and self.thickness is not None:
            lam = 2.0 * lam * mu / (lam + 2.0 * mu)
        return lam, mu

    def depth(self, dim: int) -> float:
        """Out-of-plane depth [m] that multiplies 2D integrals: the thickness in plane stress,
        1 m in plane strain (results per metre); 1 in 3D (no factor)."""
        if dim == 3:
            if self.thickness is not None:
                raise InputError(f"Elastic material: thickness = {plain(self.thickness)} m is "
                                 "for 2D plane stress only; leave it None for a 3D block")
            return 1.0
        return 1.0 if self.thickness is None else self.thickness

    def row(self) -> np.ndarray:
        """[E, nu, density, alpha, beta, thickness or 0 (plane strain)] in SI units, the row of
        a material table."""
        return np.array([self.E, self.nu, self.density, self.damping[0], self.damping[1],
                         0.0 if self.thickness is None else self.thickness])
