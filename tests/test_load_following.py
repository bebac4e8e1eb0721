"""NLGS's warm start that follows the loads of an assembly at rest (saxum.solver.load_following):
a wall on a base shaken below its sliding threshold stays at rest relative to the base, and
after the first steps each step starts from the last rest solution plus the impulse change
that balances the change of the loads, which the first sweep confirms."""

import dataclasses

import numpy as np

import saxum as sx
from saxum.ground import harmonic
from saxum.results import _pack_state, _unpack_state
from saxum.structures import running_bond_wall


def _shaken_wall(amplitude_g: float = 0.3):
    model = running_bond_wall(courses=8, bricks=6)
    g = float(np.hypot(*model.gravity))
    motion = harmonic(amplitude_g * g, 0.5, 1)
    return dataclasses.replace(model, accelerations=(motion.inertial_load(),))


def _run(model, solver, steps):
    sim = sx.Simulation(model, dt=1e-3, solver=solver)
    state = sim.initial_state()
    for _ in range(steps):
        sim.step(state)
    return sim, state


def test_steps_at_rest_under_changing_loads_take_one_sweep():
    model = _shaken_wall()
    solver = sx.NLGS()
    sim, state = _run(model, solver, 300)
    iterations = sim.log.iterations
    assert sim.log.converged.all()
    # without following, every step sweeps rest_after times and then finds the rest solution
    assert np.median(iterations) == 1
    assert solver.rest_solutions <= 30
    free = model.body_kind == sx.BodyKind.FREE
    assert np.abs(state.body_q[free] - model.body_q0[free]).max() < 1e-8  # at rest on the base

    plain = sx.NLGS(follow_loads=False)
    sim_plain, state_plain = _run(model, plain, 300)
    assert np.median(sim_plain.log.iterations) > 10
    assert plain.rest_solutions > 200
    # the same motion: both end every step at rest relative to the base
    assert np.abs(state_plain.body_q - state.body_q).max() < 1e-8


def test_reruns_are_bit_identical():
    model = _shaken_wall()
    _, a = _run(model, sx.NLGS(), 120)
    _, b = _run(model, sx.NLGS(), 120)
    assert np.array_equal(a.body_q, b.body_q) and np.array_equal(a.body_v, b.body_v)
    k = a.contacts.count
    assert np.array_equal(a.contacts.impulse[:k], b.contacts.impulse[:k])


def test_a_restored_solver_follows_the_loads_as_the_original():
    """A solver restored from its checkpoint (ContactSolver.checkpoint, restore: the anchors
    of the loads it follows, packed as a results file packs them) steps on as the original,
    bit for bit; restored without them (a file written before they were stored), its first
    step looks for the rest solution again (76 sweeps instead of 1, measured) and the course
    leaves the original's: 9.4e-13 m (coordinates) and 3.2e-10 m/s (velocities) apart after
    10 steps, measured."""
    model = _shaken_wall()
    sim, state = _run(model, sx.NLGS(), 100)
    saved = _unpack_state(_pack_state(sim.solver.checkpoint()))
    assert int(saved["following.anchors"]) > 0  # it follows the loads
    runs = []
    for restored in (saved, {"refinement": saved["refinement"]}):
        fresh = sx.Simulation(model, dt=1e-3, solver=sx.NLGS())
        fresh.detector.restore(sim.detector.checkpoint())
        fresh.solver.restore(restored)
        runs.append((fresh, state.copy()))
    for _ in range(10):
        for s, st in [(sim, state), *runs]:
            s.step(st)
    (whole, whole_state), (bare, bare_state) = runs
    assert np.array_equal(whole.log.iterations, sim.log.iterations[-10:])
    assert np.array_equal(whole_state.body_q, state.body_q)
    assert np.array_equal(whole_state.body_v, state.body_v)
    assert bare.log.iterations[0] > 1 and not np.array_equal(bare_state.body_v, state.body_v)


