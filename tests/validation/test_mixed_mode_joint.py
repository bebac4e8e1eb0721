"""A bonded joint opened and sheared at a fixed mixed-mode ratio: onset and dissipated energy
of the COHESIVE law's damage against Camanho and Davila's closed forms.

A free slab bonded to a fixed base by a cohesive joint of area A (the sum of its points'
Contacts.area) is pulled by a force that grows linearly in time along a fixed direction
(F_t, F_n) = F(t) (c, f_t) / sqrt(c^2 + f_t^2), gravity off, a moment H/2 times F_t
cancelling the shear's lever arm about the joint (as test_joint_direct_shear.py). With
k_t = k_n = k the joint's stiffness is isotropic, so the jump (s, g) stays parallel to the
force (before the onset: the elastic jump; after: the slab's acceleration is along the force
minus the joint's (1 - d) k (s, g), both along the same line): a proportional path, the
case of the closed forms. In the openings scaled by the onset openings delta_n = f_t / k,
delta_t = c / k the path is at 45 degrees, cos phi = sin phi = 1 / sqrt(2) (saxum.laws).

Closed forms (P.P. Camanho & C.G. Davila, "Mixed-mode decohesion finite elements for the
simulation of delamination in composite materials", NASA/TM-2002-211737, 2002: quadratic
onset, linear energy criterion, bilinear softening):
- onset at lambda = 1: sigma = f_t cos phi, tau = c sin phi (on the quadratic criterion
  (sigma / f_t)^2 + (tau / c)^2 = 1), the joint's peak normal and shear forces;
- failure at lambda_f, 1 / lambda_f = cos^2 phi / lambda_I + sin^2 phi / lambda_II with
  lambda_I = 2 G_I k / f_t^2, lambda_II = 2 G_II k / c^2; each mode's stress falls linearly
  to zero there, so the work per unit area of the normal stress is
  G_n = lambda_f cos^2 phi f_t^2 / (2 k) and of the shear stress G_t = lambda_f sin^2 phi
  c^2 / (2 k), which satisfy G_n / G_I + G_t / G_II = 1 (their linear criterion).
Here lambda_I = 20, lambda_II = 10, lambda_f = 13.33: G_n = 3.33 J/m^2 (1/3 of G_I),
G_t = 13.3 J/m^2 (2/3 of G_II).

Past the peak the slab accelerates, and the applied moment H/2 F_t no longer balances the
joint's shear force's lever arm: the moment H/2 m a_t turns the slab, which would open the
joint unevenly and bend the path; a thin slab (H = 0.02 m) keeps that small: the test
checks that its turn times the half width stays below 5 % of the opening when the joint has
broken (measured 2.8 %; the two ends open by +- that, so the mean path and the works change
only to second order).

Tolerances (as test_joint_pull_off.py): peaks within 1 % (the law's peak is reached within
one step's increment of the opening, ~5e-4 of the onset opening here), energies within 2 %
(damage is updated once per step from the converged jump, which overshoots the softening
branch by about one step's increment over the softening length). Measured (2026-11-28):
peaks +0.06 % (normal) and +0.05 % (shear), works +1.1 % (both).
"""

import math

import numpy as np

import saxum as sx

F_T, C, K = 1.0e5, 2.0e5, 1.0e10  # [Pa], [Pa], [Pa/m]
G_I, G_II = 10.0, 20.0  # [J/m^2]: lambda_I = 20, lambda_II = 10
WIDTH, HEIGHT = 2.0, 0.02  # [m]: thin and dense (1e5 kg/m^3), see the module doc
RATE = 2.0e7  # [N/m/s]: the force's growth, peak after ~0.016 s
H = 1.0e-5  # [s]


def _force_on(body: int, c) -> np.ndarray:
    """The contacts' force on `body` in world axes [N/m]: R / h in the frames."""
    n = c.count
    world = np.einsum("ar,ard->ad", c.impulse[:n], c.frame[:n]) / H
    sign = np.where(c.candidate[:n] == body, 1.0, np.where(c.antagonist[:n] == body, -1.0, 0.0))
    return sign @ world


def test_mixed_mode_onset_and_energies():
    b = sx.ModelBuilder(gravity=(0.0, 0.0))
    b.add_block([(-0.4, -0.2), (2.4, -0.2), (2.4, 0.0), (-0.4, 0.0)],
                kind=sx.BodyKind.FIXED, group="ground")
    slab = b.add_block([(0.0, 0.0), (WIDTH, 0.0), (WIDTH, HEIGHT), (0.0, HEIGHT)],
                       density=1.0e5)
    unit = math.hypot(C, F_T)
    b.add_force([slab], lambda t: (RATE * t * C / unit, RATE * t * F_T / unit,
                                   RATE * t * C / unit * HEIGHT / 2.0))
    law = sx.ContactLaw(friction=0.6, kind=sx.LawKind.COHESIVE, k_n=K, k_t=K, f_t=F_T,
                        cohesion=C, g_i=G_I, g_ii=G_II)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    sim = sx.Simulation(b.finalize(), dt=H)
    state = sim.initial_state()
    c = state.contacts
    area = c.area[: c.count].sum()
    q0 = state.body_q[slab].copy()
    tangential, normal, slip, opening = [0.0], [0.0], [0.0], [0.0]
    for _ in range(20_000):
        sim.step(state)
        c = state.contacts
        joint = -_force_on(slab, c)  # the joint's pull on the slab, as stresses would be
        tangential.append(joint[0])
        normal.append(joint[1])
        slip.append(state.body_q[slab, 0] - q0[0])
        opening.append(state.body_q[slab, 1] - q0[1])
        if c.count == 0 or c.damage[: c.count].min() >= 1.0:
            break
    else:
        raise AssertionError("the joint did not break")
    tangential, normal = np.array(tangential), np.array(normal)
    slip, opening = np.array(slip), np.array(opening)
    turn = abs(state.body_q[slab, 2] - q0[2]) * WIDTH / 2.0
    assert turn < 0.05 * opening[-1], (turn, opening[-1])

    cos2 = sin2 = 0.5
    lam_i, lam_ii = 2.0 * G_I * K / F_T**2, 2.0 * G_II * K / C**2
    lam_f = 1.0 / (cos2 / lam_i + sin2 / lam_ii)
    peak_n, peak_t = normal.max() / area, tangential.max() / area
    assert abs(peak_n / (F_T * math.sqrt(cos2)) - 1.0) < 0.01, peak_n
    assert abs(peak_t / (C * math.sqrt(sin2)) - 1.0) < 0.01, peak_t
    work_n = np.sum(0.5 * (normal[1:] + normal[:-1]) * np.diff(opening)) / area
    work_t = np.sum(0.5 * (tangential[1:] + tangential[:-1]) * np.diff(slip)) / area
    g_n, g_t = lam_f * cos2 * F_T**2 / (2.0 * K), lam_f * sin2 * C**2 / (2.0 * K)
    assert abs(work_n / g_n - 1.0) < 0.02, (work_n, g_n)
    assert abs(work_t / g_t - 1.0) < 0.02, (work_t, g_t)
