"""The smallest one-sine pulse that overturns a slender block, against Housner's rocking
equation integrated independently here.

Reference model (G.W. Housner, BSSA 53, 1963; N. Makris & Y. Roussos, Geotechnique 50, 2000):
a rigid block of half-diagonal R and slenderness alpha rocking on a rigid base without sliding,
    theta'' = -p^2 [ sin(alpha sgn(theta) - theta) + (a_g / g) cos(alpha sgn(theta) - theta) ],
p^2 = 3 g / (4 R); it uplifts when |a_g| > g tan(alpha); at each impact (theta = 0) the angular
velocity is multiplied by Housner's r = 1 - 3/2 sin^2(alpha). Integrated with scipy's
solve_ivp (RK45, rtol 1e-10) between impacts during the pulse; overturned when |theta|
exceeds alpha, during the pulse or, by the energy integral of free rocking, after it.
For the antisymmetric one-sine pulse a_g = A sin(2 pi t / T_p), the smallest overturning
amplitude is found by bisection (the overturning set is not always an interval, Zhang &
Makris 2001; both models are bisected on the same bracket, so they find the same boundary).

saxum: block 0.2 x 1 m on a fixed base, mu = 1, inelastic law, dt = 5e-4 s, pulse as inertial
forces, `saxum.collapse.critical_value` with trials judged after the pulse (collapsed when the
block has moved by half its size). Tolerance: 3 % on the overturning amplitude (bisections to
1 %; time discretization of the impacts).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value
from saxum.ground import one_sine

B, H, G = 0.2, 1.0, 9.81
ALPHA = math.atan(B / H)
P2 = 3.0 * G / (4.0 * 0.5 * math.hypot(B, H))
R_HOUSNER = 1.0 - 1.5 * math.sin(ALPHA) ** 2


def _housner_overturns(amplitude, period):
    def ground(t):
        return amplitude * math.sin(2.0 * math.pi * t / period) if t <= period else 0.0

    ts = np.linspace(0.0, period, 20001)
    pushes = np.abs(amplitude * np.sin(2.0 * np.pi * ts / period)) > G * math.tan(ALPHA)

    def uplift_after(time):
        """The first time after `time` at which the ground lifts the block, and the side."""
        later = np.flatnonzero(pushes & (ts > time))
        if later.size == 0:
            return None, 0.0
        return ts[later[0]], -math.copysign(1.0, ground(ts[later[0]]))

    t, side = uplift_after(-1.0)
    theta = omega = 0.0
    while t is not None and t < period:
        def rhs(time, y, side=side):
            return [y[1], -P2 * (math.sin(side * ALPHA - y[0])
                                 + ground(time) / G * math.cos(side * ALPHA - y[0]))]

        def impact(time, y, side=side, start=t):
            return y[0] if abs(y[0]) > 0.0 or time > start + 1e-9 else side

        impact.terminal, impact.direction = True, -side
        sol = solve_ivp(rhs, (t, period), [theta + side * 1e-12, omega], events=impact,
                        rtol=1e-10, atol=1e-12, max_step=period / 50)
        if np.abs(sol.y[0]).max() > ALPHA:
            return True
        if sol.status != 1:  # the pulse is over with the block rocking on `side`
            theta, omega = sol.y[0, -1], sol.y[1, -1]
            break
        t, omega = sol.t_events[0][0], R_HOUSNER * sol.y_events[0][0][1]
        theta, side = 0.0, -side
        if abs(omega) < 1e-6:  # back at rest: uplift again only if the ground still pushes
            t, side = uplift_after(t)
            theta = omega = 0.0
    # Free rocking conserves E = omega^2 / 2 + p^2 cos(alpha - |theta|) between impacts and
    # loses energy at each; the block overturns iff it reaches |theta| = alpha (E >= p^2)
    # before its next impact, or, moving back towards it, after that impact.
    energy = 0.5 * omega * omega + P2 * math.cos(ALPHA - abs(theta))
    if theta * omega < 0.0:
        energy = R_HOUSNER**2 * (energy - P2 * math.cos(ALPHA)) + P2 * math.cos(ALPHA)
    return energy >= P2


def _saxum(amplitude, period):
    b = sx.ModelBuilder(gravity=(0.0, -G))
    b.add_block([(-2.0, -0.2), (2.0, -0.2), (2.0, 0.0), (-2.0, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground")
    b.add_block([(0.0, 0.0), (B, 0.0), (B, H), (0.0, H)], density=2000.0)
    law = sx.ContactLaw(friction=1.0, kind=sx.LawKind.SIGNORINI_COULOMB)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    one_sine(amplitude, period).apply_as_inertial_forces(b)
    return sx.Simulation(b.finalize(), dt=5e-4)


@pytest.mark.parametrize("period", [0.5, 2.0])
def test_overturning_amplitude_matches_housner(period):
    lo, hi = G * math.tan(ALPHA), 4.0 * G * math.tan(ALPHA)
    assert not _housner_overturns(lo, period) and _housner_overturns(hi, period)
    stands, falls = lo, hi
    while falls - stands > 0.01 * falls:
        mid = 0.5 * (stands + falls)
        stands, falls = (stands, mid) if _housner_overturns(mid, period) else (mid, falls)
    reference = 0.5 * (stands + falls)
    result = critical_value(lambda a: _saxum(a, period), lo, hi, tolerance=0.01,
                            criterion=CollapseCriterion(fraction=0.5, duration=4.0,
                                                        not_before=period))
    assert result.value == pytest.approx(reference, rel=0.03)
