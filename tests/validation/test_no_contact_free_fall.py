"""The "no contact" law (saxum.laws.NO_CONTACT, scenario kind = "none"): blocks of two groups
with it pass through each other, as LMGC90's blocks do when no see-table names their pair.

A free block (group "stone") starts 5 mm above a fixed block (group "floor"), the pair
with NO_CONTACT, and falls through it, in 2D and 3D. Closed form: free fall,
y(t) = y0 - g t^2 / 2 (Newton). Moreau-Jean with theta = 1/2 integrates a constant
acceleration exactly (the velocity is linear in t and q_{n+1} = q_n + h (v_n + v_{n+1}) / 2
is the trapezoid rule), so the only error is round-off: tolerance 1e-9 relative on the drop
after 300 steps (round-off is ~1e-13 per step). No contact rows are made at any step.
Control: the same model with a Coulomb law instead stops the block on the fixed one (its
drop stays below 1 cm, the start gap plus the alert).
"""

import numpy as np
import pytest

import saxum as sx
from saxum.structures.solid import box

G = 9.81
DT = 1e-3
STEPS = 300  # 0.3 s: a drop of 0.44 m, through the whole 0.2 m high fixed block
START = 0.005  # [m] gap between the falling block and the fixed one at t = 0


def _model(dim, law):
    if dim == 2:
        b = sx.ModelBuilder(gravity=(0.0, -G))
        b.add_block([(-0.5, -0.2), (0.5, -0.2), (0.5, 0.0), (-0.5, 0.0)],
                    kind=sx.BodyKind.FIXED, group="floor")
        b.add_block([(-0.1, START), (0.1, START), (0.1, START + 0.1), (-0.1, START + 0.1)],
                    density=2000.0, group="stone")
    else:
        b = sx.ModelBuilder(dim=3, gravity=(0.0, 0.0, -G))
        b.add_block(box(-0.5, -0.5, -0.2, 0.5, 0.5, 0.0), kind=sx.BodyKind.FIXED, group="floor")
        b.add_block(box(-0.1, -0.1, START, 0.1, 0.1, START + 0.1), density=2000.0,
                    group="stone")
    b.set_law("stone", "stone", sx.ContactLaw(friction=0.5))
    b.set_law("stone", "floor", law)
    return b.finalize()


def _drop(dim, law):
    model = _model(dim, law)
    sim = sx.Simulation(model, dt=DT, theta=0.5)
    state = sim.initial_state()
    height = dim - 1  # the vertical coordinate of q
    y0 = float(state.body_q[1, height])
    for _ in range(STEPS):
        sim.step(state)
    return y0 - float(state.body_q[1, height]), sim


@pytest.mark.parametrize("dim", [2, 3])
def test_no_contact_blocks_fall_through_each_other(dim):
    drop, sim = _drop(dim, sx.NO_CONTACT)
    t = STEPS * DT
    assert drop == pytest.approx(0.5 * G * t**2, rel=1e-9)
    assert np.max(sim.log.contacts) == 0


@pytest.mark.parametrize("dim", [2, 3])
def test_a_coulomb_law_in_its_place_stops_the_block(dim):
    drop, sim = _drop(dim, sx.ContactLaw(friction=0.5))
    assert drop < 0.01
    assert np.max(sim.log.contacts) > 0
