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
import pytest
from test_joint_pull_off import box

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


PUSH = 0.8  # the horizontal force P over the weight m g [-]
ETA_PUSH = 4000.0  # [Pa s/m]: tau = m / (eta A) = 0.1 s for both blocks below
TURN = 0.6  # [rad] the 3D force's direction in the horizontal plane, off the block's axes


@pytest.mark.parametrize("dim", [2, 3])
def test_pushed_block_reaches_the_steady_sliding_speed(dim):
    """A block on a flat viscous-frictional joint pushed by a constant horizontal force P
    [N; 2D N/m] at its centre of mass: the joint's shear force is mu N + eta A U (the law,
    saxum.laws: |R_t| <= mu R_n + h A eta |U_t|, on the bound against U_t when sliding), so
    from rest m dU/dt = P - mu m g - eta A U and
        U(t) = U_s (1 - exp(-t / tau)),  U_s = (P - mu m g) / (eta A),  tau = m / (eta A)
    with eta [Pa s/m], A [m^2] (2D: m per metre) the sum of the points' Contacts.area,
    U [m/s]. 2D: a 0.4 x 0.2 m block; 3D: a 0.4 x 0.3 x 0.2 m one pushed at TURN to its
    axes (the viscous and Coulomb parts are isotropic: it slides along the force).
    Tolerance: the speed within 1 % of U_s at every step, the issue's bound (the implicit
    viscous term's error on this ODE is of order h / tau = 1e-2 of U_s at most, measured
    0.18 % in 2D and 3D), and after 10 tau (exp(-10) = 5e-5 of the transient left, measured
    4.8e-5) within 1e-3 of U_s: the backward-Euler step has U_s as its exact fixed point;
    sideways speed below 1e-6 U_s (the law is isotropic; measured 1e-10)."""
    g = 9.81
    b = sx.ModelBuilder(gravity=(0.0,) * (dim - 1) + (-g,), dim=dim)
    if dim == 2:
        b.add_block([(-1.0, -0.2), (40.0, -0.2), (40.0, 0.0), (-1.0, 0.0)],
                    kind=sx.BodyKind.FIXED, group="ground")
        body = b.add_block([(0.0, 0.0), (0.4, 0.0), (0.4, 0.2), (0.0, 0.2)], density=2000.0)
        along = np.array([1.0, 0.0])
    else:
        b.add_block(box(-2.0, 2.0, -2.0, 2.0, -0.2, 0.0), kind=sx.BodyKind.FIXED,
                    group="ground")
        body = b.add_block(box(-0.2, 0.2, -0.15, 0.15, 0.0, 0.2), density=2000.0)
        along = np.array([math.cos(TURN), math.sin(TURN), 0.0])
    b.set_law("block", "ground", sx.ContactLaw(friction=MU, kind=sx.LawKind.VISCOUS_COULOMB,
                                               eta=ETA_PUSH))
    b.set_law("block", "block", sx.ContactLaw(friction=MU))
    mass = float(b.finalize().body_mass[body])
    push = PUSH * mass * g
    b.add_force([body], lambda t: tuple(push * along) + (0.0,) * (3 if dim == 3 else 1))
    model = b.finalize()
    sim = sx.Simulation(model, dt=H)
    state = sim.initial_state()
    area = 0.4 * (0.3 if dim == 3 else 1.0)
    tau = mass / (ETA_PUSH * area)
    steady = (push - MU * mass * g) / (ETA_PUSH * area)
    errors = []
    for _ in range(round(10.0 * tau / H)):
        sim.step(state)
        c = state.contacts
        assert np.isclose(c.area[: c.count].sum(), area, rtol=1e-9)
        v = state.body_v[body, :dim]
        errors.append(abs(v @ along - steady * (1.0 - math.exp(-state.time / tau))))
        assert np.linalg.norm(v - (v @ along) * along) < 1e-6 * steady
    assert max(errors) < 0.01 * steady
    assert abs(state.body_v[body, :dim] @ along - steady) < 1e-3 * steady
