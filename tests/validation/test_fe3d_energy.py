"""Energy of a deformable 3D block dropped on rigid ground (issue 14, validation "Energy", 3D;
the 2D block: test_fe_energy.py).

theta = 1/2 without damping is the trapezoidal rule on the linear system of the co-rotated
block, which conserves its energy when the frame does not turn [Jean99, sec. 3; Hughes, The
Finite Element Method, sec. 9.1]; an inelastic impact (Signorini, velocity level, e_n = 0)
can only take energy away (M. Jean, CMAME 177 (1999), sec. 4). So the total energy kinetic +
strain + potential of the block never exceeds its initial value. Tolerance: 1e-9 of the
initial energy (round-off of some 400 steps of sums of order the energy).
"""

import numpy as np

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

G = 9.81


def test_inelastic_bounce_never_gains_energy():
    b = ModelBuilder(dim=3, gravity=(0.0, 0.0, -G))
    b.add_block([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-0.2, 0)],
                kind=BodyKind.FIXED, group="ground")
    drop = 0.002
    b.add_block([(x, y, z) for x in (-0.2, 0.2) for y in (-0.1, 0.1)
                 for z in (drop, drop + 0.2)],
                material=Elastic(1.0e7, 0.2, 2000.0), mesh_size=0.1, group="block")
    law = sx.ContactLaw(friction=0.5)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    sim = Simulation(b.finalize(), dt=2e-4, theta=0.5,
                     detection=sx.DetectionSettings(alert=0.004))
    state = sim.initial_state()
    mass = sim.fe.blocks.node_mass

    def energy():
        potential = G * float(mass @ state.node_x[:, 2])
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
