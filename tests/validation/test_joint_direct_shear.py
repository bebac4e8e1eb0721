"""Direct shear of a bonded joint under a constant normal stress (mode II of the cohesive
joint, saxum.laws COHESIVE).

A free slab bonded to a fixed base by a cohesive joint of area A (the sum of its points'
Contacts.area) is pressed by a normal stress sigma and then sheared by a force that grows
linearly in time, gravity off; a moment H/2 times the shear force cancels the shear's lever
arm about the joint, so the joint's normal stress stays uniform. 2D, and 3D (a square slab on
4 points, sheared along x). The joint is a bond in
parallel with Coulomb friction: friction sticks up to mu sigma A, then the bond strains and
carries k_t s up to the cohesion c, then softens linearly to zero at the slip 2 G_II / c
(bilinear law, P.P. Camanho & C.G. Davila, NASA/TM-2002-211737, 2002; the Mohr-Coulomb
strength c + mu sigma of a mortar joint, e.g. P.B. Lourenco & J.G. Rots, J. Eng. Mech. 123
(1997) 660-668). Closed forms: peak shear force (c + mu sigma) A, residual mu sigma A once
the bond is broken, and the work of the bond's shear force (the joint's shear force minus
friction, mu times its normal force) over the slip is G_II A.

The joint is elastic (k_n) in compression too, so the slab has a normal vibration (period
2.8 ms): sigma rises over 20 ms with a half-cosine (what it leaves of that vibration is of
order (T_vib / T_rise)^2) before the shear starts, and theta = 1 damps the rest (with sigma
applied at once and theta = 1/2 the normal force swung by +-50 % and the peak came 11 % high).

Tolerances: peak within 1 % (reached within one step's slip increment, 6e-4 of the onset
slip c / k_t here), residual within 1 % (Coulomb's law, solved exactly per contact), bond
work within 2 % (damage is updated once per step from the converged slip, which overshoots
the softening branch by about a step's slip over the softening length; measured 1.3 %).
"""

import math

import numpy as np
import pytest
from test_joint_pull_off import box

import saxum as sx

C, MU, K, G_II, SIGMA = 2.0e5, 0.6, 1.0e10, 20.0, 1.0e5  # [Pa], [-], [Pa/m], [J/m^2], [Pa]
WIDTH, HEIGHT = 2.0, 0.2  # [m]: a flat slab, whose rocking the stiff joint keeps tiny
RATE = 2.0e7  # [N/m/s]: peak after ~0.026 s
H = 1.0e-5  # [s]
PRESS = 0.02  # [s]: the normal stress's rise, 7 periods of the slab on the joint's k_n


def _press(t: float) -> float:
    """The normal stress's share at t [s]: a half-cosine rise over PRESS, then 1."""
    return 0.5 * (1.0 - math.cos(math.pi * t / PRESS)) if t < PRESS else 1.0


def _shear(t: float) -> float:
    """The shear force [N/m] at t [s]: RATE from the end of the normal stress's rise."""
    return RATE * max(t - PRESS, 0.0)


def force_on(body: int, c, h: float = H) -> np.ndarray:
    """The contacts' force on `body` in world axes [N/m; 3D: N]: R / h in the frames, h the
    step [s]."""
    n = c.count
    world = np.einsum("ar,ard->ad", c.impulse[:n], c.frame[:n]) / h
    sign = np.where(c.candidate[:n] == body, 1.0, np.where(c.antagonist[:n] == body, -1.0, 0.0))
    return sign @ world


@pytest.mark.parametrize("dim", [2, 3])
def test_direct_shear_peak_residual_and_mode_two_energy(dim):
    b = sx.ModelBuilder(gravity=(0.0,) * dim, dim=dim)
    if dim == 2:
        b.add_block([(-0.4, -0.2), (2.6, -0.2), (2.6, 0.0), (-0.4, 0.0)],
                    kind=sx.BodyKind.FIXED, group="ground")
        slab = b.add_block([(0.0, 0.0), (WIDTH, 0.0), (WIDTH, HEIGHT), (0.0, HEIGHT)],
                           density=1.0e4)
        b.add_force([slab], lambda t: (_shear(t), -SIGMA * WIDTH * _press(t),
                                       _shear(t) * HEIGHT / 2.0))
    else:
        b.add_block(box(-0.4, 2.6, -0.4, 2.6, -0.2, 0.0), kind=sx.BodyKind.FIXED,
                    group="ground")
        slab = b.add_block(box(0.0, WIDTH, 0.0, WIDTH, 0.0, HEIGHT), density=1.0e4)
        b.add_force([slab], lambda t: (WIDTH * _shear(t), 0.0, -SIGMA * WIDTH**2 * _press(t),
                                       0.0, -WIDTH * _shear(t) * HEIGHT / 2.0, 0.0))
    law = sx.ContactLaw(friction=MU, kind=sx.LawKind.COHESIVE, k_n=K, k_t=K, f_t=1.0e5,
                        cohesion=C, g_i=10.0, g_ii=G_II)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", sx.ContactLaw(friction=MU))
    sim = sx.Simulation(b.finalize(), dt=H, theta=1.0)
    state = sim.initial_state()
    c = state.contacts
    area = c.area[: c.count].sum()
    x0 = state.body_q[slab, 0]
    shear, normal, slip = [0.0], [SIGMA * area], [0.0]
    broken = 0
    for _ in range(30_000):
        sim.step(state)
        c = state.contacts
        on_slab = force_on(slab, c)
        shear.append(-on_slab[0])
        normal.append(on_slab[dim - 1])
        slip.append(state.body_q[slab, 0] - x0)
        broken = broken + 1 if c.damage[: c.count].min() >= 1.0 else 0
        if broken == 20:  # sliding on friction alone for 20 steps
            break
    else:
        raise AssertionError("the joint did not break")
    shear, normal, slip = np.array(shear), np.array(normal), np.array(slip)
    assert abs(shear.max() / ((C + MU * SIGMA) * area) - 1.0) < 0.01
    assert abs(shear[-1] / (MU * SIGMA * area) - 1.0) < 0.01
    bond = shear - MU * normal
    work = np.sum(0.5 * (bond[1:] + bond[:-1]) * np.diff(slip))
    assert abs(work / (G_II * area) - 1.0) < 0.02
