"""Horizontal collapse load factor of a mortared semicircular arch: with a vanishing bond
(f_t, c -> 0) it is the dry arch's; with tensile strength it rises.

Arch: mean radius R = 1 m, t/R = 0.15, 15 voussoirs, 2000 kg/m^3 on a fixed support, as
test_arch_horizontal.py (whose dry factor is checked against a rigid-block limit analysis,
J. Heyman, Int. J. Mech. Sci. 11, 1969); every joint (voussoir-voussoir and
voussoir-support) a COHESIVE law (saxum.laws) with mu = 1 (no joint slides), k_n = 1e11 Pa/m,
k_t = 4e10 Pa/m (stiff: a bonded joint is elastic in compression too, and the arch's
settlement on joints of 1e9 Pa/m, 1.8 mm, was already the 1 % of a voussoir at which a trial
counts as collapsed), c = 2 f_t, fracture energies 10 times the least that does not snap back, and
3 points per contact (ContactLaw.points: Simpson, exact for the bond's linear stress).

Tests: (1) with f_t = 1 Pa the bond holds at most 0.15 N/m across a joint (against a thrust of
order 300 N/m) and breaks within nanometres of opening, so the arch is the dry arch: the
collapse factors of the two, each bisected to 0.5 % (saxum.collapse.critical_value, same
bracket and criterion), agree within 1 % (issue 15): each bisection's midpoint is within
0.25 % of its critical value, the rest is left for the bond. (2) the factor rises with the
tensile strength: f_t = 3000 and 10000 Pa give larger factors than the dry arch, in that
order. (A bonded joint is elastic in compression, so it cracks at Navier's edge stress, long
before its rocking moment, and this brittle bond (G 10 times the least) cracks through before
a hinge forms: f_t = 1000 Pa gave 0.1491, 1.0 % below the dry arch's 0.1505, main 7e3970f;
a bond rigid in compression, cracking only at N b / 2 + f_t b^2 / 3, gave +11 %.)
The curve (`PYTHONPATH=src python tests/validation/test_mortared_arch.py`) is in
docs/structures.md.
"""

import dataclasses
import functools
import math

import numpy as np
import pytest
from limit_analysis import semicircular_four_hinge

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value
from saxum.laws import LawKind
from saxum.structures import add_supported_semicircular_arch

RADIUS, RATIO, VOUSSOIRS = 1.0, 0.15, 15
K_N, K_T = 1.0e11, 4.0e10
RAMP = 0.5  # [s]: the load factor's rise, ~30 periods of the arch's sway on its joints


def mortared_arch(f_t: float | None) -> sx.Model:
    """The arch with dry joints (f_t None) or cohesive ones of tensile strength f_t [Pa]."""
    builder = sx.ModelBuilder()
    add_supported_semicircular_arch(builder, radius=RADIUS, thickness=RATIO * RADIUS,
                                    voussoirs=VOUSSOIRS)
    if f_t is None:
        law = sx.ContactLaw(friction=1.0)
    else:
        c = 2.0 * f_t
        law = sx.ContactLaw(friction=1.0, kind=LawKind.COHESIVE, k_n=K_N, k_t=K_T, f_t=f_t,
                            cohesion=c, g_i=10.0 * f_t**2 / (2.0 * K_N),
                            g_ii=10.0 * c**2 / (2.0 * K_T), points=3)
    builder.set_law("voussoir", "voussoir", law)
    builder.set_law("voussoir", "support", law)
    return builder.finalize()


@functools.cache
def collapse_factor(f_t: float | None) -> float:
    """The horizontal collapse load factor [-], bisected to 0.5 % from rest (as
    limit_analysis.saxum_horizontal_collapse: bracket 0.5 to 3 times the dry limit
    analysis's, 1 s per trial after the load's rise), the load rising over RAMP and
    theta = 1: a bonded joint is elastic (k_n) in compression, and a load applied at once
    sets the arch vibrating on its joints (theta = 1/2 keeps a spring's energy: the mortared
    arch rocked open at half its factor) and, near the limit where its hinges have softened
    it, overshoots (collapse 2.4 % below the dry arch's with theta = 1 alone); a rigid-block
    arch's factor does not depend on either (both arches get them)."""
    lam_ref, _ = semicircular_four_hinge(RADIUS, RATIO * RADIUS, VOUSSOIRS)
    model = mortared_arch(f_t)
    return critical_value(lambda x: _ramped(model, x), 0.5 * lam_ref, 3.0 * lam_ref,
                          tolerance=0.005,
                          criterion=CollapseCriterion(duration=1.0, not_before=RAMP)).value


def _ramped(model: sx.Model, factor: float) -> sx.Simulation:
    """A simulation of `model` under a horizontal load factor that rises to `factor` over
    RAMP with a half-cosine, then stays; theta = 1."""
    g = float(np.hypot(*model.gravity))

    def acceleration(t: float) -> tuple[float, float]:
        share = 0.5 * (1.0 - math.cos(math.pi * t / RAMP)) if t < RAMP else 1.0
        return factor * g * share, 0.0

    return sx.Simulation(dataclasses.replace(model, accelerations=(acceleration,)), dt=1e-3,
                         theta=1.0)


def test_vanishing_bond_gives_the_dry_collapse_factor():
    dry = collapse_factor(None)
    assert collapse_factor(1.0) == pytest.approx(dry, rel=0.01)


def test_tensile_strength_raises_the_collapse_factor():
    dry = collapse_factor(None)
    weak, strong = collapse_factor(3000.0), collapse_factor(10000.0)
    assert dry * 1.01 < weak < strong


if __name__ == "__main__":
    dry = collapse_factor(None)
    print("| f_t [Pa] | c [Pa] | collapse factor | / dry |")
    print("|---|---|---|---|")
    print(f"| dry | - | {dry:.4f} | 1 |")
    for f_t in (1.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0):
        lam = collapse_factor(f_t)
        print(f"| {f_t:g} | {2 * f_t:g} | {lam:.4f} | {lam / dry:.3f} |", flush=True)
