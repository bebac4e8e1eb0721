"""The 3D step on threads (issue 16): NLGS by domains (saxum.solver.nlgs.nlgs_3d_domains), the
parallel narrow phase (polyhedron_contacts_parallel), world geometry and assembly: the same
result bit for bit with 1 and 2 numba threads, and with one domain the serial step's (the
runs compared inside each test, one machine)."""

import dataclasses

import numba
import numpy as np
import pytest
from results_check import same_runs

import saxum as sx
from saxum.ground import harmonic
from saxum.structures import wall3d

pytestmark = pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2,
                                reason="numba has one thread here")


def _run(model, threads, domains, duration):
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(threads=threads, domains=domains))
    state = sim.initial_state()
    try:
        sim.run(state, duration)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    return sim, state


def test_shaken_3d_wall_same_bits_with_one_and_two_threads():
    """An L wall of 8 courses (81 blocks) on a base shaken at 0.7 g (2 Hz) across and along
    it, 0.04 s: with four domains (both phases of cuts) the same bits on 1 and 2 threads; with
    one domain (which NLGS sweeps by nlgs_3d_domains only with two or more: forced here after
    the first step, NLGS._split), the serial sweep's order and arithmetic, so the serial run's
    bits."""
    load = harmonic(0.7 * 9.81, 0.5, 1.0, direction=(0.6, 0.8, 0.0)).inertial_load()
    model = dataclasses.replace(wall3d(courses=8, length=1.5, return_length=1.0),
                                accelerations=(load,))
    same_runs(_run(model, 1, 4, 0.04), _run(model, 2, 4, 0.04))
    serial = _run(model, None, None, 0.04)
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS())
    state = sim.initial_state()
    sim.step(state)
    sim.solver._split = True
    sim.run(state, 0.039)  # 0.04 s in all
    assert sim.solver._domains[1] == 1
    same_runs(serial, (sim, state))
    assert not serial[0].problem.parallel and np.all(serial[0].log.converged)


def test_narrow_phase_in_place_and_not():
    """A small L wall (4 courses) whose courses are 6 % of their height apart, so that they
    fall until the first lands: the parallel narrow phase writes its contacts in place where
    it found as many as in the step before and through its scratch rows where not, and with
    one domain on 2 threads the run is the serial one bit for bit."""
    model = wall3d(courses=4, length=1.0, return_length=1.0)
    q0 = model.body_q0.copy()
    free = model.body_kind == sx.BodyKind.FREE
    q0[free, 2] += 0.06 * q0[free, 2]
    model = dataclasses.replace(model, body_q0=q0)
    runs = [_run(model, threads, domains, 0.03) for threads, domains in ((1, 1), (2, 1))]
    sim = runs[1][0]
    assert np.count_nonzero(np.diff(sim.log.contacts))  # contacts found as the first lands
    assert 0 < sim.detector.in_place_count < len(sim.log.step) - 1  # in place, and not
    same_runs(*runs)


def test_parallel_3d_kernels_are_the_serial_ones():
    """An L wall of about 900 blocks at rest (over 2 x 4096 contacts: three blocks of
    saxum.solver.problem._BLOCK, and of pairs of saxum.detection.polyhedra.PAIR_BLOCK_3D) on 2
    threads with one domain: parallel world geometry, narrow phase (in place after its
    first) and assembly with its warm start, the serial step bit for bit."""
    model = wall3d(courses=20, length=6.0, return_length=6.0)
    runs = [_run(model, threads, domains, 0.003) for threads, domains in ((1, 1), (2, 1))]
    assert runs[0][1].contacts.count > 2 * 4096
    assert runs[1][0].problem.parallel and not runs[0][0].problem.parallel
    assert runs[1][0].detector.parallel and runs[1][0].detector.pair_count > 2 * 512
    assert runs[1][0].detector.in_place_count >= 1
    same_runs(*runs)
