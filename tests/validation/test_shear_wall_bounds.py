"""A small mortared shear wall under the TU Eindhoven tests' boundary conditions: what saxum
can claim without the measured peak loads (see benchmarks/shear_wall.py and BENCHMARKS.md).

The wall (4 courses of 2 bricks in running bond, cohesive joints) stands on a fixed ground and
carries a top beam that is guided: free to move, its rotation held (inverse rotational
inertia 0), under a constant vertical force N; a DRIVEN block pushes the beam sideways through
a frictionless contact at 0.01 m/s. Gravity is off, so every horizontal section of the wall
carries the same N and the same horizontal force H. Closed forms (Coulomb's law and the
Mohr-Coulomb strength c + mu sigma of a bonded joint, e.g. P.B. Lourenco & J.G. Rots,
J. Eng. Mech. 123 (1997) 660-668):

- a bed joint of length L (every bed joint in running bond spans the wall's width) carries at
  most c L + mu N, so H <= c L + mu N at every step;
- once a bed joint has broken and slides, H = mu N (its points are Coulomb contacts whose
  normal forces sum to N).

Tolerances: the bound holds within 1 % (H is read from the contact impulses of a step, in
which the beam's inertia adds m a; the pusher's speed is constant, so that is small), the
residual within 1 % (Coulomb's law is solved exactly per contact; the damping of the joints'
vibration by theta = 1 leaves a small dynamic part). The beam's rotation is checked to stay 0
and the vertical reaction to equal N within 1 %, the boundary conditions the test claims.
"""

import math

import numpy as np
from shear_wall_model import wall as benchmark

import saxum as sx

UNIT, COURSE, COURSES = 0.22, 0.0625, 4  # [m]: brick + head joint, brick + bed joint
WIDTH = 2 * UNIT  # [m]
SIGMA = 0.30e6  # [Pa]: the vertical pre-compression
N = SIGMA * WIDTH  # [N/m]
MU, C = 0.75, 0.35e6  # [-], [Pa]
H = 1.0e-4  # [s]
SPEED, PRESS, HOLD = 0.01, 0.02, 0.01  # [m/s], [s], [s]


def _rise(t: float) -> float:
    """The vertical force's share at t [s]: a half-cosine rise over PRESS, then 1."""
    return 0.5 * (1.0 - math.cos(math.pi * t / PRESS)) if t < PRESS else 1.0


def _wall():
    """(model, beam, pusher): ground, 4 courses, the guided beam and its pusher."""
    b = sx.ModelBuilder(gravity=(0.0, 0.0))
    b.add_block([(-0.2, -0.1), (WIDTH + 0.2, -0.1), (WIDTH + 0.2, 0.0), (-0.2, 0.0)],
                kind=sx.BodyKind.FIXED, group="ground")
    for c in range(COURSES):
        y0, y1 = c * COURSE, (c + 1) * COURSE
        cuts = [0.0, UNIT, WIDTH] if c % 2 == 0 else [0.0, 0.5 * UNIT, 1.5 * UNIT, WIDTH]
        for x0, x1 in zip(cuts[:-1], cuts[1:], strict=True):
            b.add_block([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], density=1800.0,
                        group="brick")
    top = COURSES * COURSE
    beam = b.add_block([(0.0, top), (WIDTH, top), (WIDTH, top + 0.1), (0.0, top + 0.1)],
                       density=7850.0, group="beam")
    b.add_force([beam], lambda t: (0.0, -N * _rise(t), 0.0))
    pusher = b.add_block([(-0.1, top + 0.01), (0.0, top + 0.01), (0.0, top + 0.09),
                          (-0.1, top + 0.09)], kind=sx.BodyKind.DRIVEN,
                         motion=lambda t: (SPEED if t > PRESS + HOLD else 0.0, 0.0, 0.0),
                         group="pusher")
    joint = sx.ContactLaw(friction=MU, kind=sx.LawKind.COHESIVE, k_n=4.0e10, k_t=2.0e10,
                          f_t=0.25e6, cohesion=C, g_i=18.0, g_ii=125.0, points=3)
    benchmark.set_laws(b, joint)
    model = b.finalize()
    model.body_inv_mass[beam, 2] = 0.0  # guided: the beam stays horizontal
    return model, beam, pusher


def test_guided_wall_is_bounded_by_mohr_coulomb_and_slides_at_mu_n():
    model, beam, pusher = _wall()
    sim = sx.Simulation(model, dt=H, theta=1.0)
    state = sim.initial_state()
    loads, verticals, broken = [], [], 0
    for _ in range(3000):
        sim.step(state)
        if state.time <= PRESS + HOLD:
            continue
        # the beam cannot turn (inverse rotational inertia 0): no rotation beyond round-off
        assert abs(state.body_q[beam, 2]) < 1e-12
        h_force, v_force = benchmark.forces(state.contacts, beam, pusher, H)
        loads.append(h_force)
        verticals.append(v_force)
        c = state.contacts
        bed = np.abs(c.frame[: c.count, 1, 1]) > 0.99  # horizontal joints: normal along y
        broken = broken + 1 if (c.damage[: c.count][bed] >= 1.0).any() else 0
        if broken == 200:  # a broken bed joint, sliding for 0.02 s
            break
    else:
        raise AssertionError("no bed joint broke")
    loads = np.array(loads)
    assert loads.max() <= (C * WIDTH + MU * N) * 1.01
    assert loads.max() > MU * N * 1.05  # the bond carried more than friction alone
    assert abs(loads[-1] / (MU * N) - 1.0) < 0.01
    assert abs(np.mean(verticals) / N - 1.0) < 0.01
