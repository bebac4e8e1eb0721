"""Semicircular arches of equal voussoirs with radial joints, on a fixed support."""

import math

import numpy as np

from ..errors import InputError
from ..laws import ContactLaw, LawKind
from ..model import BodyKind, Model, ModelBuilder

__all__ = ["add_semicircular_arch", "add_supported_semicircular_arch", "semicircular_arch"]


def add_semicircular_arch(
    builder: ModelBuilder,
    *,
    radius: float,
    thickness: float,
    voussoirs: int,
    density: float = 2000.0,
    centre: tuple[float, float] = (0.0, 0.0),
    group: str = "voussoir",
) -> list[int]:
    """Add the voussoirs of a semicircular arch; returns their body indices, right to left.

    radius: mean radius R [m] (centre line of the ring); thickness t [m] of the ring;
    voussoirs: number of equal voussoirs, each spanning pi/voussoirs of the ring, with radial
    joints; intrados and extrados are chords between joint ends. The springings lie on the
    horizontal line through `centre`.
    """
    if not (radius > 0.0 and 0.0 < thickness < 2.0 * radius):
        raise InputError(f"arch needs radius > 0 and 0 < thickness < 2 radius, got "
                         f"radius={radius}, thickness={thickness}")
    if voussoirs < 1:
        raise InputError(f"arch needs at least 1 voussoir, got {voussoirs}")
    cx, cy = centre
    r_in, r_out = radius - 0.5 * thickness, radius + 0.5 * thickness
    phi = np.linspace(0.0, math.pi, voussoirs + 1)
    cos, sin = np.cos(phi), np.sin(phi)
    # Mirror the right half so that the arch is exactly symmetric and both springings are level.
    cos[::-1][: (voussoirs + 1) // 2] = -cos[: (voussoirs + 1) // 2]
    sin[::-1][: (voussoirs + 1) // 2] = sin[: (voussoirs + 1) // 2]
    if voussoirs % 2 == 0:
        cos[voussoirs // 2], sin[voussoirs // 2] = 0.0, 1.0
    bodies = []
    for k in range(voussoirs):
        a, b = k, k + 1
        verts = [
            (cx + r_in * cos[a], cy + r_in * sin[a]),
            (cx + r_out * cos[a], cy + r_out * sin[a]),
            (cx + r_out * cos[b], cy + r_out * sin[b]),
            (cx + r_in * cos[b], cy + r_in * sin[b]),
        ]
        bodies.append(builder.add_block(verts, density=density, group=group,
                                        name=f"voussoir {k + 1}"))
    return bodies


def add_supported_semicircular_arch(
    builder: ModelBuilder, *, radius: float, thickness: float, voussoirs: int,
    density: float = 2000.0,
) -> list[int]:
    """A fixed support block ("support", t deep, 5 R wide, so that a collapsing arch falls
    onto it) and a semicircular arch on it (add_semicircular_arch, groups "support" and
    "voussoir"); returns the voussoirs' body indices."""
    half = 2.5 * radius
    builder.add_block([(-half, -thickness), (half, -thickness), (half, 0.0), (-half, 0.0)],
                      kind=BodyKind.FIXED, group="support", name="support")
    return add_semicircular_arch(builder, radius=radius, thickness=thickness,
                                 voussoirs=voussoirs, density=density)


def semicircular_arch(
    *,
    radius: float,
    thickness: float,
    voussoirs: int,
    density: float = 2000.0,
    friction: float = 0.6,
    law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
    gravity: tuple[float, float] = (0.0, -9.81),
) -> Model:
    """A semicircular arch on its support (add_supported_semicircular_arch), friction mu [-] on
    every joint. Voussoirs are bodies 1..voussoirs, right springing first; body 0 is the
    support."""
    builder = ModelBuilder(gravity=gravity)
    add_supported_semicircular_arch(builder, radius=radius, thickness=thickness,
                                    voussoirs=voussoirs, density=density)
    contact = ContactLaw(friction=friction, kind=law)
    builder.set_law("voussoir", "voussoir", contact)
    builder.set_law("voussoir", "support", contact)
    return builder.finalize()
