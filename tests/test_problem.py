"""The 2D kernels of the contact problem, written out for 3 dof, against the generic ones that
loop over the dimension and the dof (the path other dimensions take): the same numbers to
round-off, on every contact law. Two code paths are not compared bit for bit (a compiler may
order or fuse the operations differently): each entry of H, W, the bias and the velocities is
a sum of at most ~10 products of quantities no larger than the array's largest entry, so the
paths agree within ~10 eps of it; _ROUND_OFF allows 1e-13 (about 450 eps). Copies (friction,
the active flags, warm-started impulses) and counts stay exact."""

import numpy as np
import pytest

import saxum as sx
from saxum.laws import SMOOTH_KINDS, LawKind
from saxum.solver import ContactProblem
from saxum.structures import running_bond_wall


@pytest.fixture(scope="module", params=[k for k in LawKind if k not in SMOOTH_KINDS])
def stepped(request):
    """A small wall a few steps into a settlement (impulses, velocities and gaps of either
    sign), with the generic twin of its contact problem."""
    model = running_bond_wall(courses=3, bricks=3, law=request.param)
    if request.param == LawKind.RESTITUTION_COULOMB:
        model.law_restitution[:] = 0.5  # so that b_n = e_n min(U_n, 0) is not 0
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    state.body_q[1:, 1] += 2e-6 * np.arange(1, model.body_count)  # open some joints
    state.body_v[1:, 2] = 1e-3 * np.sin(np.arange(1, model.body_count))
    for _ in range(3):
        sim.step(state)
    generic = ContactProblem(model)
    generic._written_out = False
    return sim, state, generic


_ROUND_OFF = 1e-13


def _close(a, b):
    """a and b agree to round-off of the size of b's largest entry (module doc)."""
    scale = np.abs(b).max(initial=0.0)
    return a.shape == b.shape and np.all(np.abs(a - b) <= _ROUND_OFF * scale)


def _assembled(problem, contacts, q, v_begin, v):
    contacts = contacts.copy()
    v = v.copy()
    problem.assemble(contacts, q, v_begin, 1e-3, 0.5, 1e-9, v)
    k = problem.count
    arrays = [problem.h_cand[:k], problem.h_ant[:k], problem.delassus[:k], problem.bias[:k],
              problem.friction[:k], problem.active[:k], contacts.impulse[:k], v]
    return [a.copy() for a in arrays]


def test_assembly_and_warm_start_match_the_generic_kernels(stepped):
    sim, state, generic = stepped
    contacts, q, v_begin = state.contacts, state.body_q, state.body_v
    v = sim.free_velocity.copy()
    fast = _assembled(sim.problem, contacts, q, v_begin, v)
    slow = _assembled(generic, contacts, q, v_begin, v)
    assert contacts.count > 0 and np.any(contacts.impulse[: contacts.count] != 0.0)
    assert np.any(slow[3] != 0.0)  # some contacts have a shift b_n
    if sim.model.law_kind[0] == LawKind.RESTITUTION_COULOMB:
        assert not slow[5].all()  # and some are inactive
    for name, a, b in zip(("H_cand", "H_ant", "W", "bias", "friction", "active", "impulse",
                           "v"), fast, slow, strict=True):
        if name in ("friction", "active", "impulse"):  # copies and flags
            assert np.array_equal(a, b), name
        else:
            assert _close(a, b), name
    # the structure of rigid 2D contact rows that saxum.solver.nlgs.nlgs_2d relies on
    assert np.array_equal(fast[1][:, :, :2], -fast[0][:, :, :2])


def test_end_of_step_gaps_match_the_generic_kernel(stepped):
    sim, state, generic = stepped
    for problem in (sim.problem, generic):
        problem.assemble(state.contacts.copy(), state.body_q, state.body_v, 1e-3, 0.5, 1e-9,
                         state.body_v.copy())
    k = generic.count
    w = np.cos(np.arange(state.body_v.size)).reshape(state.body_v.shape) * 1e-4
    r = state.contacts.impulse
    for extra in (None, w):
        fast = sim.problem.end_gaps(r, state.body_v, 1e-3, 0.5, extra)
        slow = generic.end_gaps(r, state.body_v, 1e-3, 0.5, extra)
        assert _close(sim.problem.gap_end[:k], generic.gap_end[:k])
        # (contacts with r_n > 0, deepest end-of-step penetration [m]): the penetration is
        # the largest -gap_end, so the two agree as the gaps do
        gap_scale = np.abs(generic.gap_end[:k]).max()
        assert fast[0] == slow[0]
        assert fast[1] == pytest.approx(slow[1], abs=_ROUND_OFF * gap_scale)
        assert slow[1] == max(0.0, -generic.gap_end[:k].min())
        assert fast[0] == np.count_nonzero(r[:k, 1] > 0.0)
