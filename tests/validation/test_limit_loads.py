"""saxum.limit with water and settlements as the live load, against closed forms.

- Water (live="water": the flood's pressures times lambda, a factor on rho_w g): a block b
  wide and h tall (density rho_m) on a rigid plane, water of depth d upstream, none
  downstream (tailwater at its base), the joint wet (saxum.flood: full uplift, linear from
  rho_w g d at the heel to 0 at the toe). Moment balance about the toe (any statics text;
  the gravity-dam check of e.g. USBR, "Design of small dams", 1987, ch. 9): the thrust
  rho_w g d^2 / 2 at d/3 and the uplift rho_w g d b / 2 at 2b/3 from the toe against the
  weight rho_m g b h at b/2,
      lambda = 3 rho_m h b^2 / (rho_w (d^3 + 2 d b^2)),
  and at lambda = 1 the depth that overturns the block is the root of
  d^3 + 2 b^2 d = 3 (rho_m / rho_w) h b^2. Friction (mu = 0.9) is high enough that the
  block does not slide first (it would need mu < 0.67 at these figures).
- Settlement (live="settlement": a support moving at a given velocity; the state of least
  power on it, the maximum plastic work of the joints): a semicircular arch (mean radius
  R = 1 m, t = 0.15 m) whose right support moves outward takes the minimum-thrust state
  (J. Ochsendorf, "The masonry arch on spreading supports", The Structural Engineer 84,
  2006): thrust line through the extrados at the crown and the intrados at the haunches,
  the springing parts turning about them. The equilibrium of the continuous ring between
  the crown (pressure point at the extrados, radius R_e) and a radial joint at phi from the
  crown (weights of the annulus sectors, as in test_limit_analysis.py) puts the pressure
  point of the joint inside the intrados (radius R_i) iff
      H (R_e - R_i cos phi) >= R_i A(phi) sin phi - M(phi),
  so H_min = max over phi of the right-hand side over (R_e - R_i cos phi) (per unit weight
  density; A, M as in test_limit_analysis.py), at the haunch angle of the maximum. The
  120-voussoir arch (polygonal voussoirs, hinges only at joints) differs from the ring by
  a discretisation error of order n^-2 (measured: 1.6e-4 relative at 60 voussoirs, 7e-5 at
  120): tolerance 2e-4; the haunch hinge within half a joint spacing (0.75 deg) of the
  ring's. The mechanism does the work of the support's force (energy balance: hinges
  dissipate nothing): gravity's power = the power on the support, to the solver's 1e-9.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import saxum as sx
from saxum.flood import FloodLoad
from saxum.limit import _loads, limit_analysis, stands
from saxum.model import BodyKind
from saxum.structures.arch import add_semicircular_arch

EXACT = 1e-7
"""[-] relative: HiGHS's feasibility tolerance 1e-9 on loads of order one."""


def _block_in_water(b: float, h: float, depth: float, density: float = 2000.0) -> sx.Model:
    builder = sx.ModelBuilder()
    builder.add_block([(-1.0, -0.2), (2.0, -0.2), (2.0, 0.0), (-1.0, 0.0)],
                      kind=BodyKind.FIXED, group="ground", name="ground")
    builder.add_block([(0.0, 0.0), (b, 0.0), (b, h), (0.0, h)], density=density,
                      group="block", name="block")
    builder.set_law("ground", "block", sx.ContactLaw(friction=0.9))
    builder.set_law("block", "block", sx.ContactLaw(friction=0.9))
    builder.add_field_load(FloodLoad(level=depth, tailwater=0.0))
    return builder.finalize()


def test_hydrostatic_pressure_overturns_a_block_at_the_moment_balance():
    b, h, d = 0.4, 1.0, 0.8
    result = limit_analysis(_block_in_water(b, h, d), live="water")
    assert result.factor == pytest.approx(3 * 2.0 * h * b**2 / (d**3 + 2 * d * b**2),
                                          rel=EXACT)
    (joint,) = result.mechanism.joints
    assert joint.hinge and joint.hinge_point == pytest.approx((b, 0.0), abs=1e-12)
    # the water depth that overturns it (lambda = 1), by the static verdict
    exact = brentq(lambda x: x**3 + 2 * b**2 * x - 3 * 2.0 * h * b**2, 0.0, h)
    lo, hi = 0.5 * exact, min(1.5 * exact, h)
    while hi - lo > 1e-9:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stands(_block_in_water(b, h, mid)) else (lo, mid)
    assert hi == pytest.approx(exact, rel=1e-8)  # the bisection's width, 1e-9 m


def _arch_on_two_supports(voussoirs: int) -> sx.Model:
    builder = sx.ModelBuilder()
    for name, (x0, x1) in (("left", (-2.0, -0.5)), ("right", (0.5, 2.0))):
        builder.add_block([(x0, -0.2), (x1, -0.2), (x1, 0.0), (x0, 0.0)],
                          kind=BodyKind.FIXED, group="support", name=name)
    add_semicircular_arch(builder, radius=1.0, thickness=0.15, voussoirs=voussoirs)
    builder.set_law("voussoir", "voussoir", sx.ContactLaw(friction=1.0))
    builder.set_law("voussoir", "support", sx.ContactLaw(friction=1.0))
    return builder.finalize()


def _minimum_thrust(t: float) -> tuple[float, float]:
    """(H_min / (W / 2), haunch angle from the crown [deg]) of the continuous semicircular
    ring of mean radius 1 (module doc), W / 2 the half-arch's weight."""
    phi = np.linspace(1e-9, 0.5 * np.pi, 200001)
    r_e, r_i = 1.0 + t / 2, 1.0 - t / 2
    area = 0.5 * (r_e**2 - r_i**2) * phi
    moment = (r_e**3 - r_i**3) * (1.0 - np.cos(phi)) / 3.0
    need = (r_i * area * np.sin(phi) - moment) / (r_e - r_i * np.cos(phi))
    return need.max() / area[-1], math.degrees(phi[np.argmax(need)])


def test_an_arch_on_spreading_supports_takes_the_minimum_thrust():
    model = _arch_on_two_supports(120)
    result = limit_analysis(model, live="settlement", settlement={"right": (1.0, 0.0, 0.0)})
    half = 0.5 * float(model.body_mass[model.body_kind == BodyKind.FREE].sum()) * 9.81
    thrust, haunch = _minimum_thrust(0.15)
    assert result.support_power / half == pytest.approx(thrust, rel=2e-4)
    hinges = sorted((j.hinge_point for j in result.mechanism.hinges), key=lambda p: p[0])
    assert len(hinges) == 3 and not result.mechanism.sliding
    assert hinges[1] == pytest.approx((0.0, 1.075), abs=1e-12)  # crown, extrados
    for x, y in (hinges[0], hinges[2]):  # haunches, intrados
        assert math.hypot(x, y) == pytest.approx(0.925, rel=1e-3)  # on an intrados chord
        assert math.degrees(math.atan2(abs(x), y)) == pytest.approx(haunch, abs=0.75)
    dead, _, _ = _loads(model, "settlement", 1.0)
    u = result.velocity
    right = model.body_name.index("right")
    assert (dead * u).sum() == pytest.approx(result.support_power * u[right, 0], rel=1e-7)
