"""A body on an inclined plane run for a while: how far it went down the slope and how far it
strayed from the plane (shared by test_rolling.py and test_capsule.py)."""

import numpy as np


def run_on_slope(sim, state, body: int, down: np.ndarray, normal: np.ndarray,
                 duration: float) -> float:
    """Step `sim` from `state` for `duration` [s] (its integrator's steps), every step converged;
    returns the largest motion of `body`'s centre along the plane's `normal` [m]."""
    dim = len(down)
    x0 = state.body_q[body, :dim].copy()
    off = 0.0
    for _ in range(round(duration / sim.integrator.dt)):
        sim.step(state)
        off = max(off, abs(float((state.body_q[body, :dim] - x0) @ normal)))
    assert np.all(sim.log.converged)
    return off
