"""The state: where the structure is now (time, coordinates, velocities, contact impulses)."""

from dataclasses import dataclass

import numpy as np

from . import bodies
from .contacts import Contacts
from .model import Model

__all__ = ["State"]


@dataclass
class State:
    """Time [s], body_q (x, y, theta) [m, m, rad] and body_v (vx, vy, omega) [m/s, m/s, rad/s],
    both shape [body_count, 3] (3D: body_q [body_count, 7], body_v [body_count, 6], see
    saxum.model), and the contacts of the last step with their impulses. `step` counts the
    steps since `start_time` [s]: step k ends at start_time + k h, computed from k rather than
    summed, so that frame times carry no accumulated round-off."""

    time: float
    body_q: np.ndarray
    body_v: np.ndarray
    contacts: Contacts
    step: int = 0
    start_time: float = 0.0

    @classmethod
    def initial(cls, model: Model, *, time: float = 0.0) -> "State":
        """The model in its initial position, at rest except driven bodies, which move with
        their imposed velocity at `time` [s]."""
        body_v = np.zeros((model.body_count, model.dof))
        for k, motion in enumerate(model.motions):
            body_v[model.body_motion == k] = np.asarray(motion(time), dtype=np.float64)
        bodies.rigid(model.dim).driven_velocity(
            model.body_q0, np.flatnonzero(model.body_motion >= 0), body_v)
        return cls(time=time, body_q=model.body_q0.copy(), body_v=body_v,
                   contacts=Contacts(model.dim), start_time=time)

    def copy(self) -> "State":
        return State(self.time, self.body_q.copy(), self.body_v.copy(), self.contacts.copy(),
                     self.step, self.start_time)
