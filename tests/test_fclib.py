"""FCLIB problems: reading and writing, the natural-map error, the Delassus NLGS, and the export
of a saxum step (saxum.fclib, saxum.solver.residual, saxum.solver.delassus_nlgs).

The shared problems live in ../shared/fclib (see its README); tests that need them are skipped
where that folder is absent.
"""

import math
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.sparse as sp

import saxum as sx
from saxum.errors import InputError
from saxum.fclib import (
    GlobalProblem,
    Info,
    LocalProblem,
    MatrixInfo,
    Solution,
    export_step,
    format_table,
    read_fclib,
    solve_fclib_files,
    solve_global,
    solve_local,
    step_problem,
    write_fclib,
)
from saxum.solver.residual import natural_map, natural_map_error, project_on_cone
from saxum.structures import semicircular_arch

SHARED = Path(__file__).resolve().parents[2] / "shared" / "fclib"
FILES = sorted(SHARED.glob("*.hdf5"))
needs_shared = pytest.mark.skipif(not FILES, reason=f"no FCLIB problems in {SHARED}")
# contacts and spacedim of each shared problem (from its README)
EXPECTED = {
    "LMGC_100_PR_PerioBox-i00361-60-03000.hdf5": (60, 3, "local"),
    "BoxesStack-local_problem_test.hdf5": (48, 3, "local"),
    "Capsules-i125-1213.hdf5": (286, 3, "local"),
    "Box_Stacks-i0122-82-5.hdf5": (82, 3, "global"),
    "LMGC_GlobalFrictionContactProblem00046.hdf5": (9, 3, "global"),
    "LMGC_GFC3D-i00001-1-00000.hdf5": (1, 3, "global"),
    "siconosdat_OneObject-i100000-499.hdf5": (24, 3, "local"),
    "siconosdat_Capsules-i101-404.hdf5": (225, 3, "local"),
    "siconosdat_NESpheres_10_1.hdf5": (9, 3, "local"),
    "siconosdat_FC3D_Example1.hdf5": (3, 3, "local"),
    "siconosdat_FrictionContactProblem00071.hdf5": (89, 2, "local"),
    "siconosdat_FrictionContactProblem00374.hdf5": (28, 2, "local"),
    "siconosdat_FC2D_SliderCrankLagrangian00000.hdf5": (2, 2, "local"),
}


def _same_matrix(a, b):
    a, b = sp.csr_matrix(a), sp.csr_matrix(b)
    a.sort_indices()
    b.sort_indices()
    return (a.shape == b.shape and np.array_equal(a.indptr, b.indptr)
            and np.array_equal(a.indices, b.indices) and np.array_equal(a.data, b.data))


def _same_solution(a, b):
    if a is None or b is None:
        return a is b
    return all((x is None and y is None) or np.array_equal(x, y)
               for x, y in ((a.u, b.u), (a.r, b.r), (a.v, b.v)))


def _same_attributes(a, b):
    return a.keys() == b.keys() and all(
        a[k].keys() == b[k].keys()
        and all(np.array_equal(a[k][j], b[k][j]) for j in a[k]) for k in a)


def _assert_same_problem(a, b):
    assert type(a) is type(b)
    matrices = ("W",) if isinstance(a, LocalProblem) else ("M", "H")
    vectors = ("q", "mu") if isinstance(a, LocalProblem) else ("f", "w", "mu")
    for name in matrices:
        assert _same_matrix(getattr(a, name), getattr(b, name)), name
    for name in vectors:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.spacedim == b.spacedim
    assert a.info == b.info
    assert a.matrix_info == b.matrix_info
    assert _same_attributes(a.attributes, b.attributes)
    assert _same_solution(a.solution, b.solution)
    assert len(a.guesses) == len(b.guesses)
    assert all(_same_solution(x, y) for x, y in zip(a.guesses, b.guesses, strict=True))


def _hand_local():
    """A 2-contact 3D local problem with every optional part, non-UTF-8 bytes in its info."""
    w = sp.csr_matrix(np.array([[2.0, 0.1, 0, 0.3, 0, 0], [0.1, 1, 0, 0, 0, 0],
                                [0, 0, 1, 0, 0, 0], [0.3, 0, 0, 2, 0, 0],
                                [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1.5]]))
    return LocalProblem(
        w, np.array([-1.0, 0.5, 0, -2, 0, 0.25]), np.array([0.3, 0.6]), 3,
        info=Info(title="hand", description="caf\udce9 (latin-1 byte)", math_info=""),
        guesses=[Solution(u=np.arange(6.0), r=np.ones(6))],
        solution=Solution(r=np.linspace(0, 1, 6)),
        matrix_info={"W": MatrixInfo(comment="hand", conditioning=4.0, rank=6)},
        attributes={"fclib_local/info": {"numberOfInvolvedDS": np.int64(2)}})


# --- reading and writing ----------------------------------------------------------------------


@pytest.mark.parametrize("storage", ["csr", "csc", "triplet"])
def test_round_trip_of_a_hand_made_local_problem(tmp_path, storage):
    problem = _hand_local()
    write_fclib(tmp_path / "p.hdf5", problem, storage)
    _assert_same_problem(read_fclib(tmp_path / "p.hdf5"), problem)
    with h5py.File(tmp_path / "p.hdf5") as h5:
        nz = h5["fclib_local/W/nz"]
        assert nz.dtype == np.int32 and nz.shape == (1,)
        assert nz[0] == {"csr": -2, "csc": -1, "triplet": 10}[storage]
        assert h5["fclib_local/W/p"].size == (7 if storage != "triplet" else 10)
        assert h5["fclib_local/info/description"][()] == b"caf\xe9 (latin-1 byte)"


@needs_shared
@pytest.mark.parametrize("storage", ["csr", "csc", "triplet"])
@pytest.mark.parametrize("name", ["BoxesStack-local_problem_test.hdf5",
                                  "LMGC_100_PR_PerioBox-i00361-60-03000.hdf5",
                                  "Box_Stacks-i0122-82-5.hdf5"])
def test_round_trip_of_shared_problems(tmp_path, name, storage):
    """Local with guesses/solution, local with HDF5 attributes, global stored as triplets."""
    problem = read_fclib(SHARED / name)
    write_fclib(tmp_path / "p.hdf5", problem, storage)
    _assert_same_problem(read_fclib(tmp_path / "p.hdf5"), problem)


@needs_shared
def test_rewritten_fclib_file_is_identical(tmp_path):
    """A file written by the FCLIB library, in canonical CSR, comes back dataset for dataset."""
    src = SHARED / "BoxesStack-local_problem_test.hdf5"
    write_fclib(tmp_path / "p.hdf5", read_fclib(src), "csr")

    def datasets(path):
        out = {}
        with h5py.File(path) as h5:
            h5.visititems(lambda k, o: out.__setitem__(k, (o.dtype, o.shape, o[()]))
                          if isinstance(o, h5py.Dataset) else None)
        return out

    a, b = datasets(src), datasets(tmp_path / "p.hdf5")
    assert a.keys() == b.keys()
    for key, (dtype, shape, value) in a.items():
        assert (dtype, shape) == b[key][:2], key
        assert np.array_equal(value, b[key][2]), key


@needs_shared
@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_every_shared_problem_is_read(path):
    problem = read_fclib(path)
    contacts, spacedim, kind = EXPECTED[path.name]
    assert problem.contacts == contacts and problem.spacedim == spacedim
    assert isinstance(problem, LocalProblem if kind == "local" else GlobalProblem)
    if kind == "local":
        assert problem.W.shape == (contacts * spacedim,) * 2
    else:
        assert problem.H.shape == (problem.f.size, contacts * spacedim)


def _fclib_file(path, edit):
    write_fclib(path, _hand_local())
    with h5py.File(path, "a") as h5:
        edit(h5)
    return path


@pytest.mark.parametrize("edit, message", [
    (lambda h5: h5.move("fclib_local", "something_else"), "not an FCLIB problem"),
    (lambda h5: h5.move("fclib_local", "fclib_global_rolling"), "rolling friction"),
    (lambda h5: h5["fclib_local/spacedim"].write_direct(np.array([5], np.int32)),
     "spacedim 5"),
    (lambda h5: h5["fclib_local"].create_group("R"), "equality-constraint"),
    (lambda h5: h5["fclib_local/W/nz"].write_direct(np.array([-3], np.int32)),
     "unknown sparse storage"),
    (lambda h5: h5.__delitem__("fclib_local/vectors/q"), "not a valid FCLIB file"),
    (lambda h5: h5["fclib_local/W/m"].write_direct(np.array([5], np.int32)),
     "inconsistent"),
])
def test_bad_files_are_refused_with_a_message(tmp_path, edit, message):
    with pytest.raises(InputError, match=message):
        read_fclib(_fclib_file(tmp_path / "p.hdf5", edit))


def test_a_file_that_is_not_hdf5_is_refused(tmp_path):
    (tmp_path / "p.hdf5").write_text("not hdf5")
    with pytest.raises(InputError, match="not a readable HDF5 file"):
        read_fclib(tmp_path / "p.hdf5")


def test_writer_refuses_unknown_storage_and_bad_sizes(tmp_path):
    with pytest.raises(InputError, match="storage"):
        write_fclib(tmp_path / "p.hdf5", _hand_local(), "dense")
    problem = _hand_local()
    problem.mu = np.array([0.3])
    with pytest.raises(InputError, match="sizes do not match"):
        write_fclib(tmp_path / "p.hdf5", problem)
    problem = _hand_local()
    problem.guesses.append(Solution(r=np.ones(3)))
    with pytest.raises(InputError, match="solution or guess"):
        write_fclib(tmp_path / "p.hdf5", problem)


# --- the error measure on problems with known solutions ---------------------------------------


def test_cone_projection_in_its_three_regions():
    mu = np.array([0.5, 0.5, 0.5, 0.0, 0.0])
    z = np.array([[2.0, 0.6, -0.8],     # inside: |z_T| = 1 <= 0.5 * 2
                  [-1.0, 0.3, 0.4],     # polar cone: 0.5 * 0.5 <= 1
                  [1.0, 3.0, 4.0],      # boundary: a = (2.5 + 1) / 1.25 = 2.8
                  [1.0, 3.0, 4.0],      # mu = 0: the half-line r_T = 0
                  [-1.0, 0.0, 0.0]])    # mu = 0, z_T = 0, z_N < 0: the polar cone
    p = project_on_cone(z, mu)
    assert p[0] == pytest.approx(z[0])
    assert np.all(p[1] == 0.0)
    assert p[2] == pytest.approx([2.8, 0.5 * 2.8 * 0.6, 0.5 * 2.8 * 0.8])
    assert p[3] == pytest.approx([1.0, 0.0, 0.0])
    assert np.all(p[4] == 0.0)


# One contact, W = diag(W_nn = 1, W_tt = 2), FCLIB order [n, t], mu = 0.5:
#   sticking:   q = (-2, 0.5)  -> r = (2, -0.25), u = 0
#   sliding:    q = (-2, 3)    -> r = (2, -1),    u = (0, 1)
#   separating: q = (1, 3)     -> r = 0,          u = q
SINGLE = [("sticking", [-2.0, 0.5], [2.0, -0.25]), ("sliding", [-2.0, 3.0], [2.0, -1.0]),
          ("separating", [1.0, 3.0], [0.0, 0.0])]


@pytest.mark.parametrize("case, q, r", SINGLE, ids=[c[0] for c in SINGLE])
@pytest.mark.parametrize("spacedim", [2, 3])
def test_single_contact_known_solution(case, q, r, spacedim):
    """Exact solution: error 0; the NLGS finds it; a perturbed r has a positive error. In 3D
    the second tangent is idle (q_s = 0)."""
    w = np.diag([1.0, 2.0, 2.0][:spacedim])
    q = np.array(q + [0.0] * (spacedim - 2))
    r = np.array(r + [0.0] * (spacedim - 2))
    mu = np.array([0.5])
    assert natural_map_error(w, q, mu, r, spacedim) <= 1e-15
    row = solve_local(LocalProblem(sp.csr_matrix(w), q, mu, spacedim))
    assert row.solved and row.r == pytest.approx(r, abs=1e-14)
    wrong = r + 0.1
    assert natural_map_error(w, q, mu, wrong, spacedim) > 1e-3


def test_natural_map_of_zero_impulse_on_a_closing_contact():
    # r = 0, u = q = (-1, 0): F = 0 - proj(0 - u_hat) = -proj((1, 0)) = (-1, 0); ||q|| = 1
    f = natural_map(np.zeros(2), np.array([-1.0, 0.0]), np.array([0.3]), 2)
    assert f == pytest.approx([-1.0, 0.0])
    assert natural_map_error(np.eye(2), np.array([-1.0, 0.0]), np.array([0.3]),
                             np.zeros(2), 2) == pytest.approx(1.0)


def test_two_stacked_blocks_known_solution():
    """Unit-mass blocks 1 (on the ground) and 2 (on block 1), translations only, 2D. Free
    velocities v1 = (0, -1), v2 = (3, -1) [m/s]; contact 1 ground-block 1 (U = v1), contact 2
    block 1-block 2 (U = v2 - v1), mu = 0.5. Both stop vertically: R_n2 = 1, R_n1 = 2; block 2
    slides on block 1 (R_t2 = -mu R_n2 = -0.5, U_t2 = 2.5), block 1 sticks (R_t1 = -0.5,
    |R_t1| <= mu R_n1)."""
    hstar = np.zeros((4, 4))  # rows [n1, t1, n2, t2], columns (v1x, v1y, v2x, v2y)
    hstar[0, 1] = hstar[1, 0] = 1.0
    hstar[2, 3] = hstar[3, 2] = 1.0
    hstar[2, 1] = hstar[3, 0] = -1.0
    v_free = np.array([0.0, -1.0, 3.0, -1.0])
    w, q = hstar @ hstar.T, hstar @ v_free
    mu = np.array([0.5, 0.5])
    r = np.array([2.0, -0.5, 1.0, -0.5])
    assert w @ r + q == pytest.approx([0.0, 0.0, 0.0, 2.5])
    assert natural_map_error(w, q, mu, r, 2) <= 1e-15
    row = solve_local(LocalProblem(sp.csr_matrix(w), q, mu, 2), tolerance=1e-12)
    assert row.r == pytest.approx(r, abs=1e-11)
    assert row.error <= 1e-12
    wrong = r.copy()
    wrong[1] = -0.6  # block 1 would be pushed back
    assert natural_map_error(w, q, mu, wrong, 2) > 1e-2
    # the same problem in global form: M = I, H = H*^T, f = v_free, w = 0
    glob = GlobalProblem(sp.identity(4, format="csr"), sp.csr_matrix(hstar.T), v_free,
                         np.zeros(4), mu, 2)
    row = solve_global(glob, tolerance=1e-12)
    assert row.r == pytest.approx(r, abs=1e-11)
    assert row.v == pytest.approx([0.0, 0.0, 2.5, 0.0], abs=1e-11)


# --- the shared problems ----------------------------------------------------------------------


@needs_shared
@pytest.mark.parametrize("name, relaxation", [
    ("siconosdat_FrictionContactProblem00071.hdf5", 1.0),
    ("siconosdat_FrictionContactProblem00374.hdf5", 1.0),
    ("siconosdat_FC2D_SliderCrankLagrangian00000.hdf5", 1.0),
    ("siconosdat_FC3D_Example1.hdf5", 1.0),
    ("siconosdat_NESpheres_10_1.hdf5", 1.0),
    ("LMGC_100_PR_PerioBox-i00361-60-03000.hdf5", 1.0),
    ("siconosdat_OneObject-i100000-499.hdf5", 0.7),  # cycles without relaxation
    ("Box_Stacks-i0122-82-5.hdf5", 1.0),
    ("LMGC_GlobalFrictionContactProblem00046.hdf5", 1.0),
    ("LMGC_GFC3D-i00001-1-00000.hdf5", 1.0),
])
def test_shared_problem_is_solved_by_nlgs(name, relaxation):
    row = solve_fclib_files([SHARED / name], relaxation=relaxation, solver="nlgs")[0]
    assert row.solved and row.error <= 1e-8
    problem = read_fclib(SHARED / name)
    if isinstance(problem, LocalProblem):
        # the reported error is the natural map of the returned r, recomputed here
        assert row.error == natural_map_error(problem.W, problem.q, problem.mu, row.r,
                                              problem.spacedim)
    assert name in format_table([row])


# --- export of a saxum step -------------------------------------------------------------------


@pytest.fixture(scope="module")
def arch_step():
    model = semicircular_arch(radius=1.0, thickness=0.15, voussoirs=9)
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(tolerance=1e-10))
    state = sim.initial_state()
    sweeps = [sim.step(state).iterations for _ in range(3)]
    return sim, state, sweeps


def _stepper_impulses(sim, state):
    active = np.flatnonzero(sim.problem.active[: sim.problem.count])
    return state.contacts.impulse[active][:, [1, 0]].ravel()  # (t, n) -> [n, t]


@pytest.mark.parametrize("kind", ["local", "global"])
def test_exported_step_resolved_gives_the_time_steppers_impulses(tmp_path, arch_step, kind):
    sim, state, sweeps = arch_step
    export_step(sim, state, tmp_path / "step.hdf5", kind=kind)
    problem = read_fclib(tmp_path / "step.hdf5")
    impulses = _stepper_impulses(sim, state)
    assert problem.contacts == impulses.size // 2 and problem.spacedim == 2
    assert np.array_equal(problem.solution.r, impulses)
    solve = solve_local if kind == "local" else solve_global
    # From the stepper's warm start, as many sweeps as it did: the same iterates.
    same = solve(problem, r0=problem.guesses[0].r, max_iterations=sweeps[-1], tolerance=1e-30,
                 solver="nlgs")
    assert same.iterations == sweeps[-1]
    assert same.r == pytest.approx(impulses, rel=1e-12, abs=1e-12 * np.abs(impulses).max())
    # Solved to 1e-10 from zero: the stepper's local velocities to its own tolerance, and the
    # stepper's impulses solve the exported problem. (Not the same impulses: the arch's joints
    # have two contact points each, so its impulses are statically indeterminate, and its
    # first step ends from a rest solution, saxum.solver.equilibrium, not from NLGS.)
    cold = solve(problem, tolerance=1e-10)
    assert cold.solved
    w, q = (problem.W, problem.q) if kind == "local" else problem.delassus()
    u = w @ impulses + q
    assert cold.u == pytest.approx(u, abs=1e-9 * np.abs(w @ impulses).max())
    assert natural_map_error(w, q, problem.mu, impulses, 2) <= 1e-10
    if kind == "global":
        free = sim.model.body_inv_mass.ravel() > 0.0
        assert same.v == pytest.approx(state.body_v.ravel()[free], abs=1e-12)


def test_export_of_the_first_step_cold_start(tmp_path):
    """Step 1 starts from zero impulses and takes many sweeps: the re-solve follows it (NLGS
    alone: no rest solution, which the Delassus NLGS does not look for)."""
    model = semicircular_arch(radius=1.0, thickness=0.15, voussoirs=5)
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(rest_after=0))
    state = sim.initial_state()
    report = sim.step(state)
    problem = export_step(sim, state, tmp_path / "step.hdf5", storage="triplet")
    assert np.all(problem.guesses[0].r == 0.0)
    same = solve_local(read_fclib(tmp_path / "step.hdf5"), max_iterations=report.iterations,
                       tolerance=1e-30, solver="nlgs")
    impulses = _stepper_impulses(sim, state)
    assert same.r == pytest.approx(impulses, abs=1e-10 * np.abs(impulses).max())


def test_export_needs_the_state_that_was_stepped(arch_step):
    sim, state, _ = arch_step
    with pytest.raises(InputError, match="stepped last"):
        step_problem(sim, state.copy())
    with pytest.raises(InputError, match="kind"):
        step_problem(sim, state, kind="mixed")


def test_natural_map_error_is_independent_of_the_solver_report():
    """A solve stopped early reports the error of what it returns, not its own test."""
    w = np.array([[2.0, 1.0, 0.5, 0.0], [1.0, 2.0, 0.0, 0.0],
                  [0.5, 0.0, 2.0, 1.0], [0.0, 0.0, 1.0, 2.0]])
    problem = LocalProblem(sp.csr_matrix(w), np.array([-1.0, 0.2, -1, 0]), np.array([0.1, 0.1]),
                           2)
    row = solve_local(problem, max_iterations=1, tolerance=1e-12, solver="nlgs")
    assert row.iterations == 1 and not row.solved
    assert row.error > 1e-3
    assert math.isclose(row.error, natural_map_error(w, problem.q, problem.mu, row.r, 2))
