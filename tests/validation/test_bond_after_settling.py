"""Bonding after settling (ContactLaw.bond_at): a block dropped from 0.1 mm onto a fixed one
lands and settles as a Coulomb contact, its joint bonds at bond_at, and then a pull-off breaks
it at the cohesive law's strength.

Before bond_at the cohesive law's contacts are the gap law's (never bonded: damage 1, so no
tension); at bond_at the joint closed then bonds (damage 0). Pulled up by a force that grows
linearly from 10 ms after bonding, the joint's tension (-sum R_n / h) peaks at f_t A, A the
sum of its points' areas (the bilinear law's strength; P.P. Camanho & C.G. Davila,
NASA/TM-2002-211737, 2002). Tolerance 1 %, test_joint_pull_off's: the peak is reached within
one step's opening increment, and theta = 1 damps the block's vibration on the joint's
stiffness (period 3 ms) that the bonding under its weight starts (measured: 0.4 % high).
"""

import pytest
from test_joint_pull_off import cohesive

import saxum as sx
from saxum.errors import InputError

F_T, WIDTH = 1.0e5, 0.2  # [Pa] (test_joint_pull_off's law), [m]
BOND_AT, PULL_AT, RATE = 0.02, 0.03, 1.0e6  # [s], [s], [N/m/s]
H = 1.0e-5  # [s]


def _dropped(law: sx.ContactLaw):
    b = sx.ModelBuilder()
    b.add_block([(-0.2, -0.2), (0.4, -0.2), (0.4, 0.0), (-0.2, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground")
    top = b.add_block([(0.0, 1e-4), (WIDTH, 1e-4), (WIDTH, 2.0), (0.0, 2.0)], density=2500.0)
    b.add_force([top], lambda t: (0.0, RATE * max(t - PULL_AT, 0.0), 0.0))
    b.set_law("block", "ground", law)
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    return b.finalize(), top


def test_joint_bonds_after_settling_and_breaks_at_its_strength():
    model, top = _dropped(cohesive(bond_at=BOND_AT))
    sim = sx.Simulation(model, dt=H, theta=1.0)
    state = sim.initial_state()
    force, landed = [], False
    for _ in range(10_000):
        sim.step(state)
        c = state.contacts
        n = c.count
        if state.time < BOND_AT - 0.5 * H:
            landed = landed or n > 0
            assert (c.damage[:n] >= 1.0).all()  # not bonded yet: Coulomb contacts
            continue
        if abs(state.time - BOND_AT) < 0.5 * H:
            area = c.area[:n].sum()
            assert n == 2 and (c.damage[:n] <= 0.0).all()  # the settled joint bonded
        force.append(-c.impulse[:n, 1].sum() / H)
        if n == 0 or c.damage[:n].min() >= 1.0:
            break
    else:
        raise AssertionError("the joint did not break")
    assert landed
    assert abs(area / WIDTH - 1.0) < 1e-12  # the two ends' halves: round-off only
    assert abs(max(force) / (F_T * area) - 1.0) < 0.01


def test_bond_at_is_for_cohesive_laws_and_needs_a_closed_joint():
    with pytest.raises(InputError, match="bond_at"):
        sx.ContactLaw(friction=0.6, bond_at=0.1)
    model, _ = _dropped(cohesive(bond_at=1e-4))  # still falling then
    sim = sx.Simulation(model, dt=H)
    state = sim.initial_state()
    with pytest.raises(InputError, match="no closed joint at t = 0.0001 s"):
        for _ in range(20):
            sim.step(state)
