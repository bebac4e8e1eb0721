"""Energy of a deformable block (issue 14, validation "Energy"), 2D and 3D.

theta = 1/2 without damping is the trapezoidal rule on the linear system of the co-rotated
block, which conserves its energy exactly when the frame does not turn [Jean99, sec. 3; any
text on the Newmark average-acceleration method, e.g. Hughes, The Finite Element Method,
sec. 9.1]; an inelastic impact (Signorini, velocity level, e_n = 0) can only take energy
away (M. Jean, CMAME 177 (1999), sec. 4: the impulse does non-positive work with theta = 1/2).
So the total energy kinetic + strain + potential of a block dropped on rigid ground never
exceeds its initial value. Tolerance: 1e-9 of the initial energy (round-off of some 1000
steps of sums of order the energy).
"""

import numpy as np
import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

G = 9.81
DROP = 0.002


def _dropped(dim):
    """A 0.4 x 0.2 (3D: x 0.2) block DROP above fixed ground, as a builder."""
    if dim == 2:
        b = ModelBuilder(gravity=(0.0, -G))
        b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=BodyKind.FIXED,
                    group="ground")
        b.add_block([(-0.2, DROP), (0.2, DROP), (0.2, DROP + 0.2), (-0.2, DROP + 0.2)],
                    material=Elastic(1.0e7, 0.2, 2000.0), mesh_size=0.05, group="block")
        return b
    b = ModelBuilder(dim=3, gravity=(0.0, 0.0, -G))
    b.add_block([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-0.2, 0)],
                kind=BodyKind.FIXED, group="ground")
    b.add_block([(x, y, z) for x in (-0.2, 0.2) for y in (-0.1, 0.1)
                 for z in (DROP, DROP + 0.2)],
                material=Elastic(1.0e7, 0.2, 2000.0), mesh_size=0.1, group="block")
    return b


@pytest.mark.parametrize("dim", [2, 3])
def test_inelastic_bounce_never_gains_energy(dim):
    b = _dropped(dim)
    law = sx.ContactLaw(friction=0.5)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    sim = Simulation(b.finalize(), dt=2e-4, theta=0.5,
                     detection=sx.DetectionSettings(alert=0.004))
    state = sim.initial_state()
    mass = sim.fe.blocks.node_mass

    def energy():
        potential = G * float(mass @ state.node_x[:, dim - 1])
        return (sim.fe.kinetic_energy(state.node_v) + sim.fe.strain_energy(state.node_x)
                + potential)

    start = energy()
    history = []
    landed = False
    for _ in range(400):
        sim.step(state)
        history.append(energy())
        landed |= bool(state.contacts.impulse[: state.contacts.count, 1].sum() > 0.0)
    history = np.array(history)
    assert landed
    assert history.max() <= start + 1e-9 * abs(start)
    assert history[-1] < start  # and the impact took energy away
