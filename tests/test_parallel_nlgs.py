"""The NLGS swept by domains (saxum.solver.nlgs.nlgs_2d_domains, issue 16): its partition, the
same result bit for bit with 1 and 2 numba threads, and with one domain nlgs_2d's result (the
runs compared inside each test, one machine); the sweeps' tasks handed between threads end
whatever runs them (more of the kernel's threads than numba's, numba's workqueue layer)."""

import dataclasses
import os
import subprocess
import sys

import numba
import numpy as np
import pytest
from results_check import same_runs
from test_joint_laws import COHESIVE

import saxum as sx
from saxum.errors import InputError
from saxum.ground import harmonic
from saxum.solver import nlgs
from saxum.solver.nlgs import body_domains, partition_contacts
from saxum.structures import running_bond_wall
from saxum.structures.wall import add_grounded_running_bond_wall


def _shaken_wall(threads, domains=None, accelerate=True):
    """A 10 x 8 running-bond wall on a base shaken at 0.7 g (2 Hz), 0.1 s: the wall slides on
    its fixed ground (mu 0.6), so the sweeps see changing contact sets. accelerate: NLGS's."""
    model = running_bond_wall(courses=10, bricks=8)
    load = harmonic(0.7 * 9.81, 0.5, 1.0).inertial_load()
    model = dataclasses.replace(model, accelerations=(load,))
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(threads=threads, domains=domains,
                                                          accelerate=accelerate))
    state = sim.initial_state()
    sim.run(state, 0.1)
    return sim, state


def test_partition_separates_free_bodies():
    sim, state = _shaken_wall(None)
    c = state.contacts
    active = np.ones(c.count, dtype=np.bool_)
    active[::7] = False  # inactive contacts are not swept
    free = (sim.model.body_inv_mass > 0.0).any(axis=1)
    assert body_domains(free, None)[1] == 1  # 85 bricks and halves: fewer than 256 a domain
    domain, n = body_domains(free, 4)
    assert n == 4 and np.all(domain[~free] == -1)
    assert np.ptp(np.bincount(domain[free])) <= 1  # of as many bodies as can be
    order, groups = partition_contacts(c.candidate, c.antagonist, active, c.count,
                                          domain, n)
    assert len(groups) == 2 * n + 1 and groups[0] == 0 and np.all(np.diff(groups) >= 0)
    assert np.array_equal(np.sort(order), np.flatnonzero(active[:c.count]))
    for g in range(2 * n):  # each group in nlgs_2d's order (last first)
        assert np.all(np.diff(order[groups[g]:groups[g + 1]]) < 0)
    # the domains, the even cuts (0, 2), the odd cut (1): no free body in two groups of one
    # phase; the domains' and cuts' contacts have their free bodies where the docstring says
    for phase in ((0, 1, 2, 3), (4, 5), (6,)):
        seen = np.zeros(len(free), dtype=np.int64)
        for g in phase:
            mine = order[groups[g]:groups[g + 1]]
            bodies = np.unique(np.concatenate([c.candidate[mine], c.antagonist[mine]]))
            bodies = bodies[free[bodies]]
            seen[bodies] += 1
            cut = {4: 0, 5: 2, 6: 1}.get(g)
            assert set(domain[bodies]) <= ({g} if cut is None else {cut, cut + 1})
        assert seen.max() <= 1, f"groups {phase} share a free body"
    assert groups[-1] - groups[-2] == 0  # no joint spans two cuts of a 10-course wall


def test_same_bits_with_one_and_two_threads():
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here")
    try:
        # four domains: both phases of cuts, one of them with two cuts in parallel
        same_runs(_shaken_wall(1, domains=4), _shaken_wall(2, domains=4))
        same_runs(_shaken_wall(1, domains=2), _shaken_wall(2, domains=2))
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)


def test_more_kernel_threads_than_numba_threads(monkeypatch):
    """nlgs_2d_domains told of 4 threads (so 4 of its threads claim the 4 domains' tasks and
    wait for each stage) where numba runs one: its threads run one after the other, the first
    sweeps everything and the others find it done; the same bits as with its threads told
    right."""
    right = _shaken_wall(1, domains=4)
    kernel = nlgs.nlgs_2d_domains
    # its argument threads, after inv_mass_x (NLGS passes numba's)
    monkeypatch.setattr(nlgs, "nlgs_2d_domains", lambda *args: kernel(*args[:28], 4, *args[29:]))
    try:
        same_runs(right, _shaken_wall(1, domains=4))
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)


_WORKQUEUE = """
import numba
from test_parallel_nlgs import _shaken_wall
from results_check import same_runs
same_runs(_shaken_wall(1, domains=4), _shaken_wall(2, domains=4))
print(numba.threading_layer())
"""


def test_workqueue_layer_same_bits():
    """Under numba's workqueue threading layer (no OpenMP), 1 and 2 threads: the sweeps end
    (a child process, as the layer is chosen once per process) with the same bits."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here")
    env = {**os.environ, "NUMBA_THREADING_LAYER": "workqueue"}
    done = subprocess.run([sys.executable, "-c", _WORKQUEUE], env=env, cwd=os.path.dirname(
        __file__), capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-1] == "workqueue"


def test_joint_laws_same_bits_with_one_and_two_threads():
    """Cohesive joints between the bricks (nlgs_2d_domains sweeps them after the dry contacts
    and sums the error by blocks of bodies) under a horizontal load, two domains."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here")
    b = sx.ModelBuilder(gravity=(4.0, -9.81))
    add_grounded_running_bond_wall(b, courses=12, bricks=6)
    b.set_law("brick", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("brick", "brick", sx.ContactLaw(friction=0.6, **COHESIVE))
    model = b.finalize()
    runs = []
    try:
        for threads in (1, 2):
            sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(threads=threads, domains=2))
            state = sim.initial_state()
            sim.run(state, 0.02)
            runs.append((sim, state))
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    assert runs[0][0].problem.joint_laws
    same_runs(*runs)


def test_one_domain_is_the_serial_sweep():
    """One domain: nlgs_2d's order and arithmetic (its fixed ground's copy apart); the serial
    run without the refinement's Anderson acceleration, which only the serial sweep has
    (nlgs_2d_anderson)."""
    run = _shaken_wall(1, domains=1)
    same_runs(_shaken_wall(None, accelerate=False), run)
    assert np.all(run[0].log.converged)


def test_bad_settings():
    with pytest.raises(InputError, match="solver.threads"):
        sx.NLGS(threads=-1)
    with pytest.raises(InputError, match="solver.domains"):
        sx.NLGS(domains=0)


def test_parallel_kernels_are_the_serial_ones():
    """A 40 x 50 wall (over 10 000 contacts: three blocks of saxum.solver.problem._BLOCK,
    and of pairs of saxum.detection.polygons.PAIR_BLOCK) whose first four courses are 6 % of
    their height apart, so that they fall and land on each other one after the other, on 2
    threads with one domain: parallel narrow phase (in place where its blocks found as many
    contacts as in the step before, copied from scratch rows where they did not), assembly
    and end gaps, the serial step bit for bit."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here")
    model = running_bond_wall(courses=40, bricks=50, brick_height=0.065)
    q0 = model.body_q0.copy()
    free = model.body_kind == sx.BodyKind.FREE
    q0[free, 1] += 0.06 * np.minimum(q0[free, 1], 4 * 0.065)
    model = dataclasses.replace(model, body_q0=q0)
    runs = []
    for threads, domains in ((None, None), (2, 1)):
        sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(threads=threads, domains=domains))
        state = sim.initial_state()
        counts = []
        sim.run(state, 0.05, callback=lambda s, r, found=counts: found.append(s.contacts.count))
        runs.append((sim, state))
    assert runs[0][1].contacts.count > 2 * 4096
    assert runs[1][0].problem.parallel and not runs[0][0].problem.parallel
    detector = runs[1][0].detector
    assert detector.parallel and detector.pair_count > 2 * 2048
    assert np.count_nonzero(np.diff(counts)) >= 2  # contacts found as courses land
    assert 0 < detector.in_place_count < len(counts) - 1  # in place, and not
    same_runs(*runs)
    assert np.array_equal(runs[0][0].problem.gap_end, runs[1][0].problem.gap_end)
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
