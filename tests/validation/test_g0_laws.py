"""The _g0 laws (ContactLaw.initial_gap, LMGC90's IQS_CLB_g0 and GAP_SGR_CLB_g0) against
closed forms, 2D and 3D.

Definition (LMGC90's nlgs, mod_nlgs.f90 and mod_nlgs_3D.f90, read for it): a contact's gap g0
at the first step is subtracted from its gap, g0 = max(g, 0) for IQS_CLB_g0 and g0 = g for
GAP_SGR_CLB_g0, kept while the contact persists; contacts that appear later have g0 = 0.

Closed forms:
- A rigid block held above a fixed ground by a gap g0 = 5 mm under a _g0 law is, for the law,
  resting on the ground: the static solution is that it does not move, and the ground's
  normal reaction on it is its weight m g. Tolerances: the block moves by less than 1e-9 m
  (measured 5e-12 m, 2e-12 m in 3D: the solver's tolerance) and the reaction is m g within
  1e-6 (measured 1e-16 in 2D, 1e-8 in 3D: the NLGS tolerance on the impulses). The same block
  under the plain law falls until the gap closes: it goes down by at least g0 (less 1e-6 m,
  the projection's tolerance).
- A second block 2 cm above the first (beyond the 1 cm alert, so not a contact on the first
  step) falls onto it: a contact that appears later has g0 = 0, so it rests on the first block
  (the gap law's projection: it goes down by 2 cm within 1e-6 m, measured 2e-10 m) while the
  first stays (1e-9 m), and the ground carries both weights (1e-6, measured 7e-8).
"""

import itertools

import numpy as np
import pytest

import saxum as sx

GAP = 0.005
"""[m] The block's initial gap above the ground."""
DT = 1e-3
"""[s]"""


def _box(lo, hi, dim):
    if dim == 2:
        return [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])]
    return list(itertools.product(*zip(lo, hi, strict=True)))


def _model(dim: int, kind: sx.LawKind, initial_gap: bool, above: float | None = None):
    """A 0.2 x 0.4 m (3D: 0.2 x 0.2 x 0.4 m) block GAP above a fixed ground slab and, with
    `above` [m], a 0.2 m high block that far above it; one law for all, alert 1 cm."""
    b = sx.ModelBuilder(dim=dim)
    up = dim - 1
    lo, hi = [-1.0] * dim, [1.0] * dim
    lo[up], hi[up] = -0.1, 0.0
    b.add_block(_box(lo, hi, dim), kind=sx.BodyKind.FIXED, group="ground", name="ground")
    lo, hi = [0.0] * dim, [0.2] * dim
    lo[up], hi[up] = GAP, GAP + 0.4
    b.add_block(_box(lo, hi, dim), density=2000.0, group="stone", name="block")
    if above is not None:
        lo[up], hi[up] = GAP + 0.4 + above, GAP + 0.6 + above
        b.add_block(_box(lo, hi, dim), density=2000.0, group="stone", name="top")
    law = sx.ContactLaw(friction=0.6, kind=kind, initial_gap=initial_gap, alert=0.01)
    b.set_law("stone", "ground", law)
    b.set_law("stone", "stone", law)
    return b.finalize()


def _run(model, duration: float):
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state()
    sim.run(state, duration)
    assert sim.log.converged.all()
    return state


def _drop(model, state, name: str) -> float:
    up = model.dim - 1
    b = model.body(name)
    return float(model.body_q0[b, up] - state.body_q[b, up])


def _ground_reaction(model, state) -> float:
    """The ground's normal force on the blocks [N/m; 3D: N]: its contacts' R_n / dt."""
    c = state.contacts
    n = c.count
    ground = model.body("ground")
    on_ground = (c.candidate[:n] == ground) | (c.antagonist[:n] == ground)
    return float(c.impulse[:n][on_ground, 1].sum() / DT)


KINDS = [sx.LawKind.SIGNORINI_COULOMB, sx.LawKind.GAP_SIGNORINI_COULOMB]


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("kind", KINDS, ids=["IQS_CLB_g0", "GAP_SGR_CLB_g0"])
def test_block_above_a_gap_rests_under_a_g0_law_and_falls_without(dim, kind):
    model = _model(dim, kind, True)
    state = _run(model, 0.5)
    assert abs(_drop(model, state, "block")) < 1e-9
    weight = float(model.body_mass[model.body("block")]) * 9.81
    assert _ground_reaction(model, state) == pytest.approx(weight, rel=1e-6)
    n = state.contacts.count
    np.testing.assert_allclose(state.contacts.initial_gap[:n], GAP, rtol=1e-12)
    plain = _model(dim, kind, False)
    assert _drop(plain, _run(plain, 0.5), "block") > GAP - 1e-6


@pytest.mark.parametrize("dim", [2, 3])
def test_a_contact_that_appears_later_has_no_initial_gap(dim):
    model = _model(dim, sx.LawKind.GAP_SIGNORINI_COULOMB, True, above=0.02)
    state = _run(model, 0.5)
    assert _drop(model, state, "top") == pytest.approx(0.02, abs=1e-6)
    assert abs(_drop(model, state, "block")) < 1e-9
    masses = model.body_mass[[model.body("block"), model.body("top")]]
    assert _ground_reaction(model, state) == pytest.approx(float(masses.sum()) * 9.81,
                                                           rel=1e-6)
    c = state.contacts
    top = model.body("top")
    later = (c.candidate[:c.count] == top) | (c.antagonist[:c.count] == top)
    # g0 = 0 (reset, not the 5 mm of the contacts below; 1e-9 m: far from either)
    assert later.any() and np.abs(c.initial_gap[:c.count][later]).max() < 1e-9
