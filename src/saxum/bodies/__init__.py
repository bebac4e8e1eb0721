"""Body kinds: one module per kind of body the time loop steps (issue 14 item 5).

A kind module provides what the Moreau-Jean loop (saxum.simulation) needs that depends on how
a body moves, over the model's structure-of-arrays (compiled where it runs in a step):

    free_velocity(q, v, inertia, inv_mass, force, h, out)    v_free = v + h M~^-1 F_theta
    driven_velocity(q, bodies, v)        imposed world-frame velocities -> the kind's own
    predict_positions(q, v, step, out)   configuration for detection, step = (1 - theta) h
    update_positions(q, v_begin, v_end, h, theta)
    contact_jacobians(q, candidate, antagonist, point, frame, gap, count, h_cand, h_ant)
    kinetic_energy(v, mass, inertia, inv_mass)

`KINDS` names them; `rigid(dim)` is the rigid kind of a model's dimension.
"""

from types import ModuleType

from . import rigid2d, rigid3d

__all__ = ["KINDS", "rigid"]

KINDS: dict[str, ModuleType] = {"rigid2d": rigid2d, "rigid3d": rigid3d}
"""Body kind modules by name."""


def rigid(dim: int) -> ModuleType:
    """The rigid body kind of spatial dimension dim (2 or 3)."""
    return KINDS[f"rigid{dim}d"]
