"""A block sliding down an incline on a viscous-frictional joint (saxum.laws VISCOUS_COULOMB)
reaches a terminal velocity.

Coulomb friction plus a viscous shear stress eta U_t over the joint's area A (the sum of its
points' Contacts.area): m dv/dt = m g (sin a - mu cos a) - eta A v, so from rest
    v(t) = v_inf (1 - exp(-t / tau)),  v_inf = m g (sin a - mu cos a) / (eta A),
    tau = m / (eta A)
(a first-order linear ODE). Set up as test_incline's "rotated gravity" case: gravity
|g| (sin a, -cos a) on a horizontal plane.
Tolerance: within 1 % of v_inf at every step. The viscous stress is taken at the end of the
step (implicit), whose error on this ODE is of order h / tau = 1e-3 of v_inf (measured
1.8e-4).
"""

import math

import numpy as np

import saxum as sx

G = 9.81
SLOPE = math.atan(0.8)
MU = 0.5
ETA = 400.0  # [Pa s/m]
H = 1.0e-3


def test_viscous_friction_terminal_velocity():
    b = sx.ModelBuilder(gravity=(G * math.sin(SLOPE), -G * math.cos(SLOPE)))
    b.add_block([(-5.0, -0.2), (40.0, -0.2), (40.0, 0.0), (-5.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="plane")
    body = b.add_block([(0.0, 0.0), (0.4, 0.0), (0.4, 0.2), (0.0, 0.2)], density=2000.0)
    b.set_law("block", "plane", sx.ContactLaw(friction=MU, kind=sx.LawKind.VISCOUS_COULOMB,
                                              eta=ETA))
    b.set_law("block", "block", sx.ContactLaw(friction=MU))
    model = b.finalize()
    sim = sx.Simulation(model, dt=H)
    state = sim.initial_state()
    mass = float(model.body_mass[body])
    area = 0.4
    tau = mass / (ETA * area)
    v_inf = mass * G * (math.sin(SLOPE) - MU * math.cos(SLOPE)) / (ETA * area)
    errors = []
    for _ in range(3000):
        sim.step(state)
        c = state.contacts
        assert np.isclose(c.area[: c.count].sum(), area, rtol=1e-9)
        exact = v_inf * (1.0 - math.exp(-state.time / tau))
        errors.append(abs(state.body_v[body, 0] - exact))
    assert state.time > 2.5 * tau  # past most of the transient
    assert max(errors) < 0.01 * v_inf
