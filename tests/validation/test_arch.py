"""Semicircular masonry arch: stability above, collapse below the minimum thickness.

Limit analysis of a semicircular arch of rigid voussoirs with no tensile strength and no
sliding (J. Heyman, "The safety of masonry arches", Int. J. Mech. Sci. 11, 363-385, 1969;
the Milankovitch solution, re-derived by G. Cocchetti, G. Colasante & E. Rizzi, "On the
analysis of minimum thickness in circular masonry arches", Appl. Mech. Rev. 64, 2011, and by
Cocchetti & Rizzi, 2020): the minimum thickness-to-radius ratio of a continuous semicircular
arch under its own weight is t/R = 0.1075 (five-hinge mechanism, haunch hinges about 54.5
degrees from the crown). An arch of a finite number of voussoirs can only hinge at its joints,
so its limit differs a little; the two ratios tested are far from 0.1075 on either side.
(Observed with this model: 0.11 stands, 0.105 collapses.) Heyman assumes no sliding;
mu = 0.6 is used here.

Model: saxum.structures.semicircular_arch, mean radius R = 1 m, 15 voussoirs, density
2000 kg/m^3, mu = 0.6, default (gap-based Signorini-Coulomb) law, dt = 1e-3 s, default NLGS.
- t/R = 0.15 (well above 0.1075): the arch stands: the crown voussoir moves by less than
  1e-4 R in 2 s (round-off and solver tolerance only), and every voussoir by less than 1e-4 R.
- t/R = 0.09 (well below): it collapses: the crown voussoir falls by more than 0.1 R within 2 s.
"""

import numpy as np

import saxum as sx
from saxum.structures import semicircular_arch

RADIUS = 1.0
VOUSSOIRS = 15
DT = 1e-3
DURATION = 2.0


def _run_arch(thickness_ratio):
    model = semicircular_arch(radius=RADIUS, thickness=thickness_ratio * RADIUS,
                              voussoirs=VOUSSOIRS, density=2000.0, friction=0.6)
    crown = model.body(f"voussoir {VOUSSOIRS // 2 + 1}")
    # the crown voussoir straddles the key: its centre of mass is on the axis of symmetry
    assert abs(model.body_q0[crown, 0]) < 1e-12 * RADIUS
    assert model.body_q0[crown, 1] > 0.9 * RADIUS
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state()
    crown_drop = []
    for _ in range(round(DURATION / DT)):
        sim.step(state)
        crown_drop.append(model.body_q0[crown, 1] - state.body_q[crown, 1])
    return model, sim, state, crown, np.array(crown_drop)


def test_thick_arch_stands():
    model, sim, state, crown, _ = _run_arch(0.15)
    moved = np.hypot(*(state.body_q[:, :2] - model.body_q0[:, :2]).T)
    assert moved[crown] < 1e-4 * RADIUS
    assert moved.max() < 1e-4 * RADIUS
    assert np.abs(state.body_q[:, 2] - model.body_q0[:, 2]).max() < 1e-4
    assert np.all(sim.log.converged)


def test_thin_arch_collapses():
    _, sim, _, _, crown_drop = _run_arch(0.09)
    assert crown_drop.max() > 0.1 * RADIUS
    # it is a collapse, not a numerical blow-up: the crown falls, it does not fly up
    assert crown_drop.min() > -1e-3 * RADIUS
    assert np.all(np.isfinite(sim.log.kinetic_energy))


def test_standing_arch_joints_do_not_interpenetrate():
    """The gap-based law keeps the joints closed, not crushed: < 1e-5 R interpenetration."""
    _, sim, _, _, _ = _run_arch(0.15)
    assert sim.log.max_interpenetration.max() < 1e-5 * RADIUS


def test_collapsing_arch_interpenetrates_only_at_impacts_and_recovers():
    """An inelastic impact with theta = 1/2 leaves the end-of-step interpenetration
    (1 - theta) h |U_n^-| (the first part of the step moves with the approach velocity;
    saxum.laws), which the gap-based law then removes. Bound on |U_n^-|: no point of a voussoir
    is faster than sqrt(2 g H) with H = 2 (R + t) (the energy released by a fall from the crown,
    all of it kinetic, point speed <= centroid speed + spin x radius, both bounded by it),
    two voussoirs approaching each other: 2 sqrt(2 g H). After the collapse has come to rest
    (last 0.5 s) the interpenetration is back below 1e-5 R."""
    _, sim, _, _, _ = _run_arch(0.09)
    g = 9.81
    theta = sim.integrator.theta
    bound = (1.0 - theta) * DT * 2.0 * np.sqrt(2.0 * g * 2.0 * (RADIUS + 0.09 * RADIUS))
    pen = sim.log.max_interpenetration
    assert pen.max() < bound
    assert pen[-round(0.5 / DT):].max() < 1e-5 * RADIUS
