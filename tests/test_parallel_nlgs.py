"""The NLGS swept by domains (saxum.solver.nlgs.nlgs_2d_domains, issue 16): its partition, the
same result bit for bit with 1 and 2 numba threads and with the default threads, and with one
domain nlgs_2d's result (the runs compared inside each test, one machine); the sweeps' tasks
handed between threads end whatever runs them (more of the kernel's threads than numba's,
numba's workqueue layer); the default plan (step_plan): domains from the model only, never the
machine's cores."""

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
from saxum.solver.nlgs import body_domains, default_domains, partition_contacts, step_plan
from saxum.structures import running_bond_wall, semicircular_arch
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
    assert body_domains(free, None)[1] == 1  # 85 bricks and halves: fewer than 4096
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
    """nlgs_2d_domains with one domain (which NLGS runs only with two or more: forced here
    after the first step, NLGS._split): nlgs_2d's order and arithmetic (its fixed ground's copy
    apart); the serial run without the refinement's Anderson acceleration, which only the
    serial sweep has (nlgs_2d_anderson)."""
    serial = _shaken_wall(None, accelerate=False)
    sim = sx.Simulation(serial[0].model, dt=1e-3, solver=sx.NLGS(accelerate=False))
    state = sim.initial_state()
    sim.step(state)
    sim.solver._split = True
    sim.run(state, 0.099)  # 0.1 s in all
    assert sim.solver._domains[1] == 1  # swept by nlgs_2d_domains, one domain
    same_runs(serial, (sim, state))
    assert np.all(sim.log.converged)


def test_domains_do_not_depend_on_the_cores(monkeypatch):
    """step_plan's domains are the model's (default_domains: one below 4096 free blocks, then
    the largest power of two of at least 2048 free blocks each) on 2 and on 16 cores (numba's
    NUMBA_NUM_THREADS, patched): only the default threads follow the cores, all of them where
    there are two domains or more; SAXUM_THREADS and SAXUM_DOMAINS replace the defaults."""
    monkeypatch.delenv("SAXUM_THREADS", raising=False)
    monkeypatch.delenv("SAXUM_DOMAINS", raising=False)
    assert [default_domains(n) for n in (0, 4095, 4096, 8191, 8192, 16080, 16384)] == [
        1, 1, 2, 2, 4, 4, 8]
    small = running_bond_wall(courses=10, bricks=8)
    large = running_bond_wall(courses=64, bricks=64)  # 4128 free blocks
    plans = {}
    for cores in (2, 16):
        monkeypatch.setattr(numba.config, "NUMBA_NUM_THREADS", cores)
        plans[cores] = (step_plan(None, None, small), step_plan(None, None, large),
                        step_plan(1, None, large), step_plan(0, 3, small))
        assert plans[cores] == ((1, 1), (cores, 2), (1, 2), (cores, 3))
    monkeypatch.setenv("SAXUM_THREADS", "1")
    monkeypatch.setenv("SAXUM_DOMAINS", "4")
    assert step_plan(None, None, small) == (1, 4) and step_plan(2, 1, small) == (2, 1)
    monkeypatch.setenv("SAXUM_THREADS", "-1")
    with pytest.raises(InputError, match="SAXUM_THREADS"):
        step_plan(None, None, small)


def test_default_threads_same_bits():
    """A 64 x 64 wall at rest (4128 free blocks: two domains by default), two steps: the
    default threads (all cores, the parallel kernels) and one thread (the same two domains,
    the serial kernels) give the same bits."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here")
    model = running_bond_wall(courses=64, bricks=64)
    runs = []
    try:
        for threads in (None, 1):
            sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(threads=threads))
            state = sim.initial_state()
            sim.run(state, 0.002)
            runs.append((sim, state))
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    assert runs[0][0].problem.parallel and not runs[1][0].problem.parallel
    assert runs[0][0].solver._plan[1] == runs[1][0].solver._plan[1] == 2
    same_runs(*runs)


@pytest.mark.parametrize("domains", [1, 2])
def test_collapsing_arch_same_bits_on_any_threads(domains):
    """The thin arch of tests/validation/test_arch.py (15 voussoirs, t/R = 0.09, the default
    hybrid solver) over the first 0.1 s of its collapse (the crown down 4.5 mm): the same
    bits on 1 and 2 threads and with the default threads, in one domain (its default: the
    serial sweep, the parallel kernels on 2 threads) and in two (the sweep by domains)."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here")
    model = semicircular_arch(radius=1.0, thickness=0.09, voussoirs=15, density=2000.0,
                              friction=0.6)
    runs = []
    try:
        for threads in (1, 2, None):
            sim = sx.Simulation(model, dt=1e-3,
                                solver=sx.Hybrid(threads=threads, domains=domains))
            state = sim.initial_state()
            sim.run(state, 0.1)
            runs.append((sim, state))
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    crown = model.body("voussoir 8")
    assert model.body_q0[crown, 1] - runs[0][1].body_q[crown, 1] > 1e-3  # it is collapsing
    assert runs[1][0].problem.parallel and not runs[0][0].problem.parallel
    same_runs(runs[0], runs[1])
    same_runs(runs[0], runs[2])


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
    for threads, domains in ((1, 1), (2, 1)):
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
