"""Benchmark of the contact solver's convergence: NLGS sweeps per step and steps not converged
on structures at rest and one collapsing, from the cold start on.

    python benchmarks/convergence.py                  # every case (about a minute)
    python benchmarks/convergence.py --cases tower,arch --rest-after 0 --spectral --orders
    python benchmarks/convergence.py --cases pier3d,wall3d --rest-after 0   # a few minutes
    python benchmarks/convergence.py --cases stack-shaken,wall512-shaken --diagnose

Cases (dt = 1e-3 s, theta = 0.5, default law and NLGS: tolerance 1e-6, at most 5000 sweeps,
unless --rest-after is given):
- tower: stack-bond tower of 40 courses x 2 bricks 0.25 x 0.065 m, density 1800 kg/m^3,
  mu = 0.6, at rest on a fixed ground, 1 s;
- wall512 / wall2025: running-bond walls of 25 x 20 and 50 x 40 bricks (512 and 2025 with the
  half bricks), same bricks, at rest, 1 s;
- arch: semicircular arch of 15 voussoirs, R = 1 m, t/R = 0.15, density 2000 kg/m^3,
  mu = 0.6, on fixed supports (it stands), 2 s;
- arch-collapse: the same with t/R = 0.09 (it collapses), 2 s: a dynamic case;
- wall512-shaken: the 512-brick wall under a horizontal acceleration of 0.7 g (it slides and
  overturns), 0.3 s: a dynamic case on which the rest solution is looked for and not found;
- wall512-shaken-margin: the same with mu = 0.8 between bricks (0.6 on the ground): the bed
  joints keep a margin while the wall slides on its base (with one mu for every joint, a wall
  sliding as a whole needs exactly mu N in every bed joint: m (a - (a - mu g)) = mu m g);
- stack-shaken: a stack-bond wall of 10 courses x 2 bricks (the tower's bricks) under 0.7 g,
  0.1 s: the smallest case found whose steps in motion hit the cap (for --diagnose);
- pier3d: a 3D pier of 40 courses 0.065 m high, each of two blocks 0.125 x 0.25 m crossed from
  course to course (0.25 x 0.25 x 2.6 m), density 1800 kg/m^3, mu = 0.6, at rest, 1 s;
- wall3d: a 3D L-shaped running-bond wall (saxum.structures.wall3d, 20 courses, two walls 3 m
  long meeting at an interlocking corner, 480 bricks 0.25 x 0.12 x 0.065 m, 1800 kg/m^3,
  mu = 0.6), at rest, 0.3 s (benchmarks/wall3d.py times the 1920-brick one);
- wall3d-shaken: the L wall of tests/validation/test_wall_rest3d.py (8 courses, walls 1.5 and
  0.75 m long, 72 bricks) under a horizontal acceleration of 0.7 g along x (the x wall slides
  in its plane, the y wall overturns out of its plane), 0.3 s: the dynamic case in 3D.
For each: the first step (a cold start from zero impulses: sweeps, error, converged, time),
the steps after it (sweeps mean, median, 95th percentile, max; steps not converged; steps
with more sweeps than rest_after), the steps whose contact set changed from the step before,
rest-solution attempts and successes (saxum.solver.equilibrium, if the installed saxum has
it), the time per step, the largest displacement of a block [m] and interpenetration [m].

--spectral: the factor by which one sweep shrinks the slowest deformation mode, on the tower's
first step (and on towers of 10 and 20 courses) linearized with every closed contact sticking
(a bilateral problem, W R = -u): the spectral radius rho of the block Gauss-Seidel iteration
matrix I - (D/omega + L)^-1 W on the range of W (its null space, self-equilibrated impulses,
has eigenvalue 1 and moves nothing), for the sweep's order (last contact first), the forward
order, over-relaxation omega = 1.5, 1.8, 1.95 and symmetric sweeps; and W's smallest nonzero
eigenvalue relative to its largest. Dense, so a few tens of seconds.

--orders: the first step of the tower, the 512-brick wall and the two arches, solved by NLGS
alone from zero impulses (cap 20 000 sweeps) with the contacts visited in other orders: the
sweep's own (last contact first), forward, by height of the contact point (highest or lowest
first), and symmetric (alternating directions); the sweeps to converge are compared.

--diagnose: for each case, the first --diagnose-steps steps that hit the cap are captured and
replayed by NLGS alone (nlgs_2d / nlgs_3d, as the step ran: the rest solution is not found in
motion): the error after 1000, 2000, ... sweeps, the contacts' states at the cap (open, sticking
inside the cone, on the cone's edge), then NLGS goes on from there to tolerance 1e-10 (at most
--reference-sweeps more sweeps) for a reference solution of the same step problem, and reports
how far the capped iterate was from it (|v - v_ref|_M / |v_ref - v_free|_M), how many contacts
changed state, and the reference's degeneracy: closed contacts within 0.1 % of the cone's edge
and open contacts (R = 0) whose normal velocity U_n + b_n is below 1e-6 of the largest |U|
(grazing).

--tolerance: the solvers' tolerance instead of saxum's default 1e-6 (the shaken cases: a
tighter one leaves less drift between the blocks for the steps after, docs/method.md).

Kernels are compiled (a warm-up run) before the clock starts. The figures are printed and
written as JSON (benchmarks/results/convergence.json by default) with the machine, the package
versions and the git commit; per-step sweeps are kept in the JSON.
"""

import argparse
import dataclasses
import json
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import saxum as sx
from saxum.solver import SolverReport
from saxum.structures import pier3d, running_bond_wall, semicircular_arch, wall, wall3d

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from wall import machine_info  # noqa: E402  (benchmarks/ is not a package)

DEFAULT_JSON = HERE / "results" / "convergence.json"
DT = 1e-3

CASES = {
    "tower": (lambda: wall(courses=40, bricks=2, bond="stack"), 1.0),
    "wall512": (lambda: running_bond_wall(courses=25, bricks=20), 1.0),
    "wall2025": (lambda: running_bond_wall(courses=50, bricks=40), 1.0),
    "arch": (lambda: semicircular_arch(radius=1.0, thickness=0.15, voussoirs=15,
                                       density=2000.0, friction=0.6), 2.0),
    "arch-collapse": (lambda: semicircular_arch(radius=1.0, thickness=0.09, voussoirs=15,
                                                density=2000.0, friction=0.6), 2.0),
    "wall512-shaken": (lambda: _shaken(running_bond_wall(courses=25, bricks=20)), 0.3),
    "wall512-shaken-margin": (lambda: _shaken(_margin_wall(courses=25, bricks=20)), 0.3),
    "stack-shaken": (lambda: _shaken(wall(courses=10, bricks=2, bond="stack")), 0.1),
    "pier3d": (lambda: pier3d(width=0.25, depth=0.25, courses=40, course_height=0.065,
                              density=1800.0), 1.0),
    "wall3d": (lambda: wall3d(courses=20, length=3.0, return_length=3.0), 0.3),
    "wall3d-shaken": (lambda: _shaken(wall3d(courses=8, length=1.5, return_length=0.75)), 0.3),
}


def _shaken(model):
    """model under a constant horizontal acceleration of 0.7 g along x: it slides and
    overturns."""
    if model.dim == 2:
        g = float(np.hypot(*model.gravity))
        return dataclasses.replace(model, accelerations=((lambda t: (0.7 * g, 0.0)),))
    g = float(np.linalg.norm(model.gravity))
    return dataclasses.replace(model, accelerations=((lambda t: (0.7 * g, 0.0, 0.0)),))


def _margin_wall(courses: int, bricks: int):
    """running_bond_wall with mu = 0.8 between bricks and 0.6 on the ground."""
    from saxum.laws import ContactLaw
    from saxum.structures.wall import add_grounded_running_bond_wall

    builder = sx.ModelBuilder()
    add_grounded_running_bond_wall(builder, courses=courses, bricks=bricks)
    builder.set_law("brick", "brick", ContactLaw(friction=0.8))
    builder.set_law("brick", "ground", ContactLaw(friction=0.6))
    return builder.finalize()


SOLVERS = {"nlgs": lambda **k: sx.NLGS(**k), "hybrid": lambda **k: sx.Hybrid(**k)}
"""--solvers: NLGS alone, or saxum.solver.Hybrid (NLGS, the conic fixed point where it
stalls)."""


def _solver(rest_after: int | None, solver: str = "nlgs", tolerance: float | None = None):
    options = {} if tolerance is None else {"tolerance": tolerance}
    if rest_after is not None:
        options["rest_after"] = rest_after  # TypeError on a saxum without it
    return SOLVERS[solver](**options)


def _warm_up(rest_after: int | None) -> None:
    """Compile (or load) every kernel a step uses, the rest solution's included (a tower's
    cold start needs it), in 2D and 3D."""
    for model in (wall(courses=10, bricks=2, bond="stack"),
                  semicircular_arch(radius=1.0, thickness=0.09, voussoirs=5),
                  pier3d(width=0.25, depth=0.25, courses=10, course_height=0.065)):
        sim = sx.Simulation(model, dt=DT, solver=_solver(rest_after))
        sim.run(sim.initial_state(), 0.01)


def run_case(name: str, rest_after: int | None, solver_name: str = "nlgs",
             duration: float | None = None, tolerance: float | None = None) -> dict:
    build, default_duration = CASES[name]
    duration = default_duration if duration is None else duration
    model = build()
    solver = _solver(rest_after, solver_name, tolerance)
    sim = sx.Simulation(model, dt=DT, solver=solver)
    state = sim.initial_state()
    times, cpu, changed = [], [], []
    previous = [None]
    clock = [time.perf_counter(), time.thread_time()]

    def after_step(state, report):
        now, now_cpu = time.perf_counter(), time.thread_time()
        times.append(now - clock[0])
        cpu.append(now_cpu - clock[1])
        c = state.contacts
        keys = c.key[: c.count].copy()
        changed.append(previous[0] is not None and not np.array_equal(keys, previous[0]))
        previous[0] = keys
        clock[0], clock[1] = time.perf_counter(), time.thread_time()

    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sx.SolverWarning)
        sim.run(state, duration, callback=after_step)
    log = sim.log
    sweeps = np.asarray(log.iterations)
    converged = np.asarray(log.converged)
    later = sweeps[1:]
    free = model.body_kind == sx.BodyKind.FREE
    moved = np.linalg.norm(state.body_q[free, :model.dim] - model.body_q0[free, :model.dim],
                           axis=1)
    threshold = getattr(solver, "rest_after", 0) or None
    finished = np.bincount(np.asarray(log.solver), minlength=5)
    out = {
        "case": name,
        "solver": solver_name,
        "finished_nlgs": int(finished[0]),
        "finished_conic": int(finished[1]),
        "finished_newton": int(finished[2]),
        "finished_smoothing": int(finished[3]),
        "finished_proximal": int(finished[4]),
        "error_max": float(np.max(log.error)),
        # the natural-map error of the steps that ended above the tolerance, where the solver
        # measured it (saxum.solver.Hybrid; nan for NLGS alone or a saxum without it)
        "natural_map_max": _largest_measured(getattr(log, "natural_map", None), converged),
        "bodies": int(model.body_count),
        "duration_s": duration,
        "steps": len(sweeps),
        "contacts_min": int(np.min(log.contacts)),
        "contacts_max": int(np.max(log.contacts)),
        "rest_after": getattr(solver, "rest_after", None),
        "tolerance": solver.tolerance,
        "first_sweeps": int(sweeps[0]),
        "first_error": float(log.error[0]),
        "first_converged": bool(converged[0]),
        "first_ms": 1e3 * times[0],
        "sweeps_mean": float(later.mean()),
        "sweeps_median": float(np.median(later)),
        "sweeps_p95": float(np.percentile(later, 95)),
        "sweeps_max": int(later.max()),
        "not_converged": int(np.count_nonzero(~converged)),
        "not_converged_after_first": int(np.count_nonzero(~converged[1:])),
        "steps_over_rest_after": (int(np.count_nonzero(later > threshold))
                                  if threshold else None),
        "steps_contacts_changed": int(np.count_nonzero(changed)),
        "rest_attempts": getattr(solver, "rest_attempts", None),
        "rest_solutions": getattr(solver, "rest_solutions", None),
        "ms_per_step_mean": 1e3 * statistics.fmean(times[1:]),
        "ms_per_step_median": 1e3 * statistics.median(times[1:]),
        "cpu_ms_per_step_mean": 1e3 * statistics.fmean(cpu[1:]),
        "why": log.why() if hasattr(log, "why") else None,
        "largest_displacement_m": float(moved.max()),
        "largest_interpenetration_m": float(np.max(log.max_interpenetration)),
        "sweeps": sweeps.tolist(),
    }
    return out


def _largest_measured(values, converged) -> float:
    """The largest finite entry of values on the steps not converged (nan if none)."""
    if values is None:
        return math.nan
    measured = np.asarray(values)[~converged]
    measured = measured[np.isfinite(measured)]
    return float(measured.max()) if measured.size else math.nan


# --------------------------------------------------------------------------------------------
# the first step's problem: the sweep in other orders, the spectral radius of the linearized sweep


_ARRAYS = ("h_cand", "h_ant", "delassus", "bias", "friction", "active")


def _capture_first(model) -> dict:
    """Copies of the first step's problem (before the solve): the arrays NLGS reads, the
    contact points, v_free."""
    captured = {}

    class Capture(sx.ContactSolver):
        def solve(self, problem, impulse, v_free, v):
            if not captured:
                k = problem.count
                c = problem.contacts
                captured.update({name: getattr(problem, name)[:k].copy() for name in _ARRAYS})
                captured.update(cand=c.candidate[:k].copy(), ant=c.antagonist[:k].copy(),
                                point=c.point[:k].copy(), v_free=v_free.copy())
            return SolverReport(iterations=0, error=0.0, converged=True)

    sim = sx.Simulation(model, dt=DT, solver=Capture())
    sim.step(sim.initial_state())
    return captured


def _cold_sweeps(model, p, orders, cap=20_000, tolerance=1e-6) -> int:
    """Sweeps NLGS (nlgs_2d) takes from zero impulses on problem p when its successive sweeps
    visit the contacts in orders[0], orders[1], ... (cycling; nlgs_2d visits the last row
    first)."""
    from saxum.solver.nlgs import nlgs_2d

    inv_mass = model.body_inv_mass
    mass = np.divide(1.0, inv_mass, out=np.zeros_like(inv_mass), where=inv_mass > 0.0)
    permuted = [{name: p[name][order] for name in ("cand", "ant", *_ARRAYS)}
                for order in orders]
    n = len(p["cand"])
    v, v_prev, work = p["v_free"].copy(), np.empty_like(p["v_free"]), np.empty((n, 18))
    joints = law_map = None  # dry laws only
    impulse = np.zeros((n, 2))
    for sweep in range(cap):
        k = sweep % len(orders)
        q, order = permuted[k], orders[k]
        r = impulse[order]  # this order's rows
        _, error = nlgs_2d(q["cand"], q["ant"], q["h_cand"], q["h_ant"], q["delassus"],
                           q["bias"], q["friction"], q["active"], n, inv_mass, mass,
                           p["v_free"], v, v_prev, r, work, joints, law_map, None, 0,
                           tolerance, 1, 1.0)
        impulse[order] = r
        if error <= tolerance:
            return sweep + 1
    return cap


def orders() -> list[dict]:
    out = []
    for name in ("tower", "wall512", "arch", "arch-collapse"):
        model = CASES[name][0]()
        p = _capture_first(model)
        n = len(p["cand"])
        own = np.arange(n)
        height = np.argsort(-p["point"][:, 1], kind="stable")  # last row: the lowest point
        row = {"case": name, "contacts": n}
        for label, sequence in (("sweep_order", [own]), ("forward", [own[::-1]]),
                                ("lowest_first", [height]), ("highest_first", [height[::-1]]),
                                ("symmetric", [own, own[::-1]])):
            row[label] = _cold_sweeps(model, p, sequence)
        out.append(row)
        print(f"{name}: cold start, sweeps to 1e-6: "
              + ", ".join(f"{k} {v}" for k, v in row.items() if k not in ("case", "contacts")))
    return out


def _first_problem(model):
    """(W dense [1/kg], closed contacts) of the first step's problem, every closed contact
    taken as a bilateral 2 x 2 block."""
    p = _capture_first(model)
    keep = p["active"] & (p["bias"] == 0.0)
    captured = {name: p[name][keep] for name in ("cand", "ant", "h_cand", "h_ant")}
    inv_mass = model.body_inv_mass.reshape(-1)
    n, dof = len(captured["cand"]), model.body_inv_mass.shape[1]
    rows = np.zeros((2 * n, model.body_count * dof))  # H*: local velocity from body velocity
    for a in range(n):
        for r in range(2):
            for body, h in ((captured["cand"][a], captured["h_cand"][a, r]),
                            (captured["ant"][a], captured["h_ant"][a, r])):
                rows[2 * a + r, body * dof:(body + 1) * dof] += h
    return rows @ (inv_mass[:, None] * rows.T), n


def _radius(w, omega=1.0, order=None, symmetric=False):
    """Largest |eigenvalue| other than 1 of the block Gauss-Seidel (SOR) iteration matrix."""
    m = w.shape[0]
    if order is not None:
        perm = np.concatenate([[2 * a, 2 * a + 1] for a in order])
        w = w[np.ix_(perm, perm)]
    d = np.zeros_like(w)
    for i in range(0, m, 2):
        d[i:i + 2, i:i + 2] = w[i:i + 2, i:i + 2]
    lower, upper = np.tril(w) - np.tril(d), np.triu(w) - np.triu(d)
    g = np.eye(m) - np.linalg.solve(d / omega + lower, w)
    if symmetric:
        g = (np.eye(m) - np.linalg.solve(d / omega + upper, w)) @ g
    radii = np.sort(np.abs(np.linalg.eigvals(g)))[::-1]
    return float(radii[np.abs(radii - 1.0) > 1e-9][0])


def spectral(courses_list=(10, 20, 40)) -> list[dict]:
    out = []
    for courses in courses_list:
        w, n = _first_problem(wall(courses=courses, bricks=2, bond="stack"))
        eig = np.linalg.eigvalsh(w)
        positive = eig[eig > 1e-10 * eig.max()]
        sweep = np.arange(n)[::-1]  # nlgs_2d visits the last contact first
        row = {"courses": courses, "closed_contacts": n,
               "eigenvalue_ratio": float(positive.min() / eig.max()),
               "one_minus_rho": {
                   "sweep_order": 1.0 - _radius(w, order=sweep),
                   "forward_order": 1.0 - _radius(w, order=np.arange(n)),
                   **{f"omega_{om}": 1.0 - _radius(w, omega=om, order=sweep)
                      for om in (1.5, 1.8, 1.95)},
                   "symmetric_per_sweep": 1.0 - math.sqrt(_radius(w, order=sweep,
                                                                  symmetric=True))}}
        out.append(row)
        print(f"tower {courses} x 2: {n} closed contacts, smallest/largest eigenvalue of W "
              f"{row['eigenvalue_ratio']:.3g}; 1 - rho: "
              + ", ".join(f"{k} {v:.3g}" for k, v in row["one_minus_rho"].items()))
    return out


class _Capping(sx.ContactSolver):
    """NLGS that keeps a copy of the first `keep` step problems (not projections) on which it
    hit its cap: the arrays NLGS reads, the starting impulses and velocities, v_free."""

    def __init__(self, solver: sx.NLGS, keep: int):
        self.solver, self.keep, self.captured, self.steps = solver, keep, [], 0

    def solve(self, problem, impulse, v_free, v):
        k = problem.count
        before = None
        if getattr(problem, "v_begin", None) is not None:  # not a projection's problem
            self.steps += 1
        if len(self.captured) < self.keep and getattr(problem, "v_begin", None) is not None:
            c = problem.contacts
            before = {name: getattr(problem, name)[:k].copy() for name in _ARRAYS}
            before.update(cand=c.candidate[:k].copy(), ant=c.antagonist[:k].copy(),
                          impulse=impulse[:k].copy(), v=v.copy(), v_free=v_free.copy())
        report = self.solver.solve(problem, impulse, v_free, v)
        if before is not None and not report.converged:
            before.update(sweeps=report.iterations, step=self.steps)
            self.captured.append(before)
        return report


def _states(p: dict, impulse: np.ndarray) -> np.ndarray:
    """0 open (R = 0), 1 sticking inside the cone, 2 on the cone's edge (|R_T| >= (1 - 1e-9)
    mu R_n: sliding, or sticking at the limit)."""
    rn = impulse[:, 1]
    rt = np.linalg.norm(np.delete(impulse, 1, axis=1), axis=1)
    edge = rt >= (1.0 - 1e-9) * p["friction"] * rn
    return np.where(rn > 0.0, np.where(edge, 2, 1), 0)


def _replay(model, p: dict, impulse, v, sweeps: int, tolerance: float):
    """NLGS sweeps on captured problem p from (impulse, v), in place: (sweeps done, error)."""
    from saxum.solver.nlgs import nlgs_2d, nlgs_3d

    inv_mass = model.body_inv_mass
    mass = np.divide(1.0, inv_mass, out=np.zeros_like(inv_mass), where=inv_mass > 0.0)
    n = len(p["cand"])
    sweep, width = (nlgs_3d, 38) if model.dim == 3 else (nlgs_2d, 18)
    joints = law_map = None  # dry laws only
    return sweep(p["cand"], p["ant"], p["h_cand"], p["h_ant"], p["delassus"], p["bias"],
                 p["friction"], p["active"], n, inv_mass, mass, p["v_free"], v, np.empty_like(v),
                 impulse, np.empty((n, width)), joints, law_map, None, 0, tolerance, sweeps,
                 1.0)


def diagnose(name: str, steps: int, reference_sweeps: int) -> list[dict]:
    model = CASES[name][0]()
    capping = _Capping(sx.NLGS(), steps)
    sim = sx.Simulation(model, dt=DT, solver=capping)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sx.SolverWarning)
        sim.run(sim.initial_state(), CASES[name][1])
    mass = np.divide(1.0, model.body_inv_mass, out=np.zeros_like(model.body_inv_mass),
                     where=model.body_inv_mass > 0.0)
    out = []
    for p in capping.captured:
        impulse, v = p["impulse"].copy(), p["v"].copy()
        errors = [float(_replay(model, p, impulse, v, 1000, 0.0)[1])
                  for _ in range(p["sweeps"] // 1000)]
        at_cap = _states(p, impulse)
        v_cap = v.copy()
        more, error = _replay(model, p, impulse, v, reference_sweeps, 1e-10)
        ref = _states(p, impulse)
        u = (np.einsum("ad,ad->a", p["h_cand"][:, 1], v[p["cand"]])
             + np.einsum("ad,ad->a", p["h_ant"][:, 1], v[p["ant"]]) + p["bias"])
        scale = np.sqrt(np.sum(mass * (v - p["v_free"]) ** 2))
        rt = np.linalg.norm(np.delete(impulse, 1, axis=1), axis=1)
        near_edge = (impulse[:, 1] > 0.0) & (rt >= 0.999 * p["friction"] * impulse[:, 1])
        u_scale = float(np.max(np.abs(u)))
        row = {"case": name, "step": p["step"], "contacts": len(p["cand"]),
               "errors_per_1000_sweeps": errors,
               "at_cap_open_stick_edge": np.bincount(at_cap, minlength=3).tolist(),
               "reference_sweeps": int(more), "reference_error": float(error),
               "reference_converged": bool(error <= 1e-10),
               "distance_at_cap": float(np.sqrt(np.sum(mass * (v_cap - v) ** 2)) / scale),
               "states_changed": int(np.count_nonzero(at_cap != ref)),
               "reference_open_stick_edge": np.bincount(ref, minlength=3).tolist(),
               "reference_closed_within_0.1%_of_edge": int(np.count_nonzero(near_edge)),
               "reference_grazing_open": int(np.count_nonzero(
                   (ref == 0) & p["active"] & (np.abs(u) < 1e-6 * u_scale)))}
        out.append(row)
        print(f"{name} step {row['step']} ({row['contacts']} contacts): error per 1000 sweeps "
              + ", ".join(f"{e:.2g}" for e in errors)
              + f"; at the cap open/stick/edge {row['at_cap_open_stick_edge']}; reference "
              f"after {more} more sweeps (error {error:.2g}): open/stick/edge "
              f"{row['reference_open_stick_edge']}, {row['states_changed']} contacts changed "
              f"state, the capped iterate {row['distance_at_cap']:.2g} away; "
              f"{row['reference_closed_within_0.1%_of_edge']} closed contacts within 0.1 % of "
              f"the edge, {row['reference_grazing_open']} open ones grazing")
    return out


def _print(r: dict) -> None:
    rest = (f"rest solutions {r['rest_solutions']}/{r['rest_attempts']}"
            if r["rest_attempts"] is not None else "no rest solution")
    print(f"{r['case']} [{r['solver']}: steps finished by NLGS {r['finished_nlgs']}, by the "
          f"conic solver {r['finished_conic']}, by Newton {r['finished_newton']}, by smoothing "
          f"Newton {r['finished_smoothing']}, by the proximal point {r['finished_proximal']}; "
          f"largest error "
          f"{r['error_max']:.2g}, largest natural-map error of a step not converged "
          f"{r['natural_map_max']:.2g}]: "
          f"{r['bodies']} bodies, {r['contacts_min']}..{r['contacts_max']} "
          f"contacts, {r['steps']} steps; first step {r['first_sweeps']} sweeps "
          f"({'converged' if r['first_converged'] else 'NOT converged'}, error "
          f"{r['first_error']:.2g}, {r['first_ms']:.1f} ms); after it sweeps mean "
          f"{r['sweeps_mean']:.2f}, median {r['sweeps_median']:g}, p95 {r['sweeps_p95']:g}, "
          f"max {r['sweeps_max']}; not converged {r['not_converged']} "
          f"({r['not_converged_after_first']} after the first); contact set changed on "
          f"{r['steps_contacts_changed']} steps; {rest}; {r['ms_per_step_mean']:.3f} ms/step "
          f"(median {r['ms_per_step_median']:.3f}; CPU {r['cpu_ms_per_step_mean']:.3f}); "
          + (f"not converged: {r['why']}; " if r["why"] else "") + "largest displacement "
          f"{r['largest_displacement_m']:.2g} m, interpenetration "
          f"{r['largest_interpenetration_m']:.2g} m")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default=",".join(CASES),
                        help=f"comma-separated subset of {', '.join(CASES)}")
    parser.add_argument("--rest-after", type=int, default=None,
                        help="NLGS rest_after (0: NLGS alone); default: saxum's default")
    parser.add_argument("--solvers", default="nlgs",
                        help="comma-separated solvers, each case run with each in turn (the "
                             "same process, interleaved): nlgs, hybrid (default: nlgs)")
    parser.add_argument("--duration", type=float, default=None,
                        help="simulated duration of every case [s] (default: the case's own)")
    parser.add_argument("--tolerance", type=float, default=None,
                        help="the solvers' tolerance (default: saxum's, 1e-6)")
    parser.add_argument("--spectral", action="store_true",
                        help="also the spectral radius of the linearized sweep (towers)")
    parser.add_argument("--orders", action="store_true",
                        help="also the cold start's sweeps in other orders of the contacts")
    parser.add_argument("--diagnose", action="store_true",
                        help="replay the steps that hit the cap and compare with a reference")
    parser.add_argument("--diagnose-steps", type=int, default=2,
                        help="capped steps replayed per case (default 2)")
    parser.add_argument("--reference-sweeps", type=int, default=400_000,
                        help="most sweeps for the reference solution (default 400 000)")
    parser.add_argument("--json", type=Path, default=DEFAULT_JSON)
    args = parser.parse_args(argv)
    started = time.perf_counter()
    _warm_up(args.rest_after)
    results = {"command": " ".join(sys.argv), "machine": machine_info(),
               "saxum_file": sx.__file__, "cases": []}
    for name in args.cases.split(","):
        for solver in args.solvers.split(","):
            r = run_case(name, args.rest_after, solver, args.duration, args.tolerance)
            _print(r)
            results["cases"].append(r)
    if args.diagnose:
        results["diagnosis"] = [row for name in args.cases.split(",")
                                for row in diagnose(name, args.diagnose_steps,
                                                    args.reference_sweeps)]
    if args.orders:
        results["orders"] = orders()
    if args.spectral:
        results["spectral"] = spectral()
    results["wall_s"] = time.perf_counter() - started
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(results, indent=1))
    print(f"written {args.json} ({results['wall_s']:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
