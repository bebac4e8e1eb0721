"""A semicircular arch of 15 voussoirs under self-weight: does t/R = 0.15 stand?

Run: python examples/arch_standing.py
"""

import numpy as np

import saxum as sx
from saxum.structures import semicircular_arch


def main(duration: float = 1.0) -> float:
    """Simulate the arch; returns the crown voussoir's displacement [m]."""
    model = semicircular_arch(radius=2.0, thickness=0.3, voussoirs=15, friction=0.6)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, duration)
    crown = 8
    moved = float(np.hypot(*(state.body_q[crown, :2] - model.body_q0[crown, :2])))
    print(f"crown moved {moved:.3g} m; {sim.log.summary()}")
    return moved


if __name__ == "__main__":
    main()
