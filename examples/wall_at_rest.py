"""A running-bond brick wall (25 courses of 20 bricks) standing on the ground for a while.

Run: python examples/wall_at_rest.py
"""

import numpy as np

import saxum as sx
from saxum.structures import running_bond_wall


def main(duration: float = 0.5) -> float:
    """Simulate the wall at rest; returns the largest brick displacement [m]."""
    model = running_bond_wall(courses=25, bricks=20)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, duration)
    drift = float(np.hypot(*(state.body_q[:, :2] - model.body_q0[:, :2]).T).max())
    print(f"{model.body_count - 1} bricks, largest displacement {drift:.3g} m; "
          f"{sim.log.summary()}")
    return drift


if __name__ == "__main__":
    main()
