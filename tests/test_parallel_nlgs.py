"""The coloured NLGS (saxum.solver.nlgs.nlgs_2d_coloured, issue 16): its colouring, and the same
result bit for bit with 1 and 2 numba threads (both runs inside this test, one machine)."""

import dataclasses

import numba
import numpy as np
import pytest

import saxum as sx
from saxum.errors import InputError
from saxum.ground import harmonic
from saxum.solver.nlgs import body_strips, colour_contacts_2d
from saxum.structures import running_bond_wall


def _shaken_wall(threads):
    """A 10 x 8 running-bond wall on a base shaken at 0.7 g (2 Hz), 0.1 s: the wall slides on
    its fixed ground (mu 0.6), so the sweeps see changing contact sets."""
    model = running_bond_wall(courses=10, bricks=8)
    load = harmonic(0.7 * 9.81, 0.5, 1.0).inertial_load()
    model = dataclasses.replace(model, accelerations=(load,))
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(threads=threads))
    state = sim.initial_state()
    sim.run(state, 0.1)
    return sim, state


def _check_colouring(c, active, free, order, chunks, colours):
    """Each active contact once, and no free body in two chunks of one colour."""
    assert np.array_equal(np.sort(order), np.flatnonzero(active[:c.count]))
    assert chunks[0] == 0 and chunks[-1] == len(order) and np.all(np.diff(chunks) > 0)
    assert colours[0] == 0 and colours[-1] == len(chunks) - 1 and np.all(np.diff(colours) >= 0)
    for k in range(len(colours) - 1):
        seen = np.zeros(len(free), dtype=np.int64)
        for u in range(colours[k], colours[k + 1]):
            mine = order[chunks[u]:chunks[u + 1]]
            bodies = np.unique(np.concatenate([c.candidate[mine], c.antagonist[mine]]))
            seen[bodies[free[bodies]]] += 1
        assert seen.max() <= 1, f"chunks of colour {k} share a free body"


def test_colouring_separates_free_bodies():
    sim, state = _shaken_wall(None)
    c = state.contacts
    active = np.ones(c.count, dtype=np.bool_)
    active[::7] = False  # inactive contacts take no colour
    free = (sim.model.body_inv_mass > 0.0).any(axis=1)
    strip, nstrips = body_strips(free)
    assert nstrips == 4 and np.all(strip[~free] == -1)  # 85 bricks and halves: 4 strips
    assert np.ptp(np.bincount(strip[free])) <= 1  # of as many as can be
    order, chunks, colours = colour_contacts_2d(c.candidate, c.antagonist, active, c.count,
                                                strip, nstrips)
    assert len(chunks) == 5 and len(colours) == 3  # the strips are wider than a brick
    _check_colouring(c, active, free, order, chunks, colours)
    # strips of one brick each: a brick has contacts in strips of one colour (those of the
    # bricks two further along its course), so they are merged until none has
    strip[free] = np.arange(free.sum())
    order, chunks, colours = colour_contacts_2d(c.candidate, c.antagonist, active, c.count,
                                                strip, free.sum())
    assert 1 < len(chunks) - 1 < free.sum()
    _check_colouring(c, active, free, order, chunks, colours)


def test_same_bits_with_one_and_two_threads():
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here")
    runs = [_shaken_wall(n) for n in (1, 2)]
    (sim1, s1), (sim2, s2) = runs
    assert np.array_equal(s1.body_q, s2.body_q)
    assert np.array_equal(s1.body_v, s2.body_v)
    assert np.array_equal(s1.contacts.impulse[:s1.contacts.count],
                          s2.contacts.impulse[:s2.contacts.count])
    assert np.array_equal(sim1.log.iterations, sim2.log.iterations)
    assert np.all(sim1.log.converged)
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)


def test_threads_out_of_range():
    with pytest.raises(InputError, match="solver.threads"):
        sx.NLGS(threads=-1)
