"""Benchmark: the rest solution's Newton systems (saxum.solver.equilibrium) factorized by
SuperLU's LU, as saxum did before, and by the block Cholesky factorization with the analysis
kept per pattern (saxum.solver.block_cholesky); and the conjugate gradients that an earlier
system's factor would need as a preconditioner instead.

    python benchmarks/rest_factorization.py
    python benchmarks/rest_factorization.py --steps 340 --repeats 5

Systems: those of the 512-brick wall of benchmarks/shaken_wall.py on a base shaken at 0.7 g
(2 Hz, NLGS refine 10), every factorization of its first --steps steps (its first phase at
rest and, from 212 steps on, the one after the first slide); and those of the first-step rest
solution of the 480-brick 3D L wall of benchmarks/convergence.py (wall3d, 6 x 6 blocks; the
Newton iterations, not the load path). Per system the least of --repeats CPU times of: SuperLU
(MMD_AT_PLUS_A, no pivoting: equilibrium's call before), the block Cholesky (its analysis
kept; and the analysis itself, mean over the systems whose pattern is new, timed once), a
solve of each; the relative residuals of both solutions (median and largest over the
systems); and the preconditioned conjugate gradient iterations, with the previous system's
SuperLU factor, to 1e-13 relative (more than 100: not converged).
"""

import argparse
import dataclasses
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from shaken_wall import _motion  # noqa: E402  (benchmarks/ is not a package)
from wall import BRICK_HEIGHT, BRICK_LENGTH, DENSITY, FRICTION, SMALL  # noqa: E402

import saxum as sx  # noqa: E402
from saxum.solver import SolverReport, block_cholesky, equilibrium  # noqa: E402


def _capture(run) -> list[tuple]:
    """The arguments of every equilibrium._factorize call while run() runs."""
    systems = []
    factorize = equilibrium._factorize

    def kept(*args):
        systems.append(tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args))
        return factorize(*args)

    equilibrium._factorize = kept
    try:
        run()
    finally:
        equilibrium._factorize = factorize
    return systems


def _shaken_wall(steps: int) -> list[tuple]:
    from saxum.structures import running_bond_wall

    model = running_bond_wall(courses=SMALL[0], bricks=SMALL[1], brick_length=BRICK_LENGTH,
                              brick_height=BRICK_HEIGHT, density=DENSITY, friction=FRICTION)
    model = dataclasses.replace(model, accelerations=(_motion(0.7, 0.5).inertial_load(),))
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(refine=10))
    state = sim.initial_state()

    def run():
        for _ in range(steps):
            sim.step(state)

    return _capture(run)


class _NewtonRest(sx.ContactSolver):
    """The first step's rest solution by the Newton iterations (no load path), then nothing."""

    def solve(self, problem, impulse, v_free, v):
        equilibrium.rest_solution(problem, impulse, v_free, v)
        return SolverReport(iterations=0, error=0.0, converged=True)


def _wall3d() -> list[tuple]:
    from saxum.structures import wall3d

    sim = sx.Simulation(wall3d(courses=20, length=3.0, return_length=3.0), dt=1e-3,
                        solver=_NewtonRest())
    return _capture(lambda: sim.step(sim.initial_state()))


def _least(repeats: int, f, *args):
    """(the least CPU time of `repeats` calls f(*args) [s], what the last returned)."""
    best, out = np.inf, None
    for _ in range(repeats):
        start = time.thread_time()
        out = f(*args)
        best = min(best, time.thread_time() - start)
    return best, out


def _pcg(a, preconditioner, b, tolerance=1e-13, most=100) -> int:
    """Preconditioned conjugate gradient iterations to |b - A x| <= tolerance |b|."""
    x = preconditioner.solve(b)
    r = b - a @ x
    size = np.linalg.norm(b)
    z = preconditioner.solve(r)
    p = z.copy()
    rz = r @ z
    for k in range(most + 1):
        if np.linalg.norm(r) <= tolerance * size:
            return k
        ap = a @ p
        step = rz / (p @ ap)
        x += step * p
        r -= step * ap
        z = preconditioner.solve(r)
        rz, before = r @ z, rz
        p = z + (rz / before) * p
    return most + 1


def measure(systems: list[tuple], repeats: int) -> dict:
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu

    rows = []
    previous = None
    seen = set()
    block_cholesky._analyses.clear()
    rng = np.random.default_rng(0)
    for bptr, blocks, data, indices, indptr, dof in systems:
        n = len(indptr) - 1
        a = csc_matrix((data, indices, indptr), shape=(n, n))
        start = time.thread_time()
        analysis = block_cholesky.analyse(bptr, blocks)
        analysed = time.thread_time() - start
        new = id(analysis) not in seen
        seen.add(id(analysis))
        t_lu, lu = _least(repeats, splu, a, "MMD_AT_PLUS_A", 0.0, None, None,
                          {"SymmetricMode": True})
        t_ll, ll = _least(repeats, block_cholesky.BlockCholesky.factorize, analysis, bptr, data,
                          indptr, dof)
        b = rng.standard_normal(n)
        s_lu, x_lu = _least(repeats, lu.solve, b)
        s_ll, x_ll = _least(repeats, ll.solve, b)
        same = previous is not None and previous[0].shape == a.shape and np.array_equal(
            previous[0].indices, a.indices) and np.array_equal(previous[0].indptr, a.indptr)
        rows.append({"n": n, "lu_ms": t_lu * 1e3, "cholesky_ms": t_ll * 1e3,
                     "analysis_ms": analysed * 1e3 if new else None,
                     "lu_solve_ms": s_lu * 1e3,
                     "cholesky_solve_ms": s_ll * 1e3,
                     "lu_residual": float(np.linalg.norm(a @ x_lu - b) / np.linalg.norm(b)),
                     "cholesky_residual": float(np.linalg.norm(a @ x_ll - b)
                                                / np.linalg.norm(b)),
                     "pcg": _pcg(a, previous[1], b) if same else None})
        previous = a, lu
    return {"rows": rows}


def _spread(values: list[float]) -> str:
    return f"{statistics.median(values):.0e} ({max(values):.0e})"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=340,
                        help="steps of the shaken 512-brick wall (default 340)")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    cases = {"512-brick wall, 0.7 g": _shaken_wall(args.steps), "480-brick 3D L wall": _wall3d()}
    print(f"{'case':>22} {'systems':>7} {'n':>5} {'SuperLU ms':>10} {'LL^T ms':>8} "
          f"{'analyses':>8} {'analysis ms':>11} {'solve ms LU, LL^T':>18} "
          f"{'residual median (max) LU, LL^T':>31} {'PCG iterations: median (range)':>30}")
    for name, systems in cases.items():
        rows = measure(systems, args.repeats)["rows"]
        analysed = [r["analysis_ms"] for r in rows if r["analysis_ms"] is not None]
        pcg = [r["pcg"] for r in rows if r["pcg"] is not None]

        def mean(key, rows=rows):
            return statistics.fmean(r[key] for r in rows)

        print(f"{name:>22} {len(rows):>7} {rows[0]['n']:>5} {mean('lu_ms'):>10.2f} "
              f"{mean('cholesky_ms'):>8.2f} {len(analysed):>8} "
              f"{statistics.fmean(analysed):>11.2f} "
              f"{mean('lu_solve_ms'):>8.3f}, {mean('cholesky_solve_ms'):>7.3f} "
              f"{_spread([r['lu_residual'] for r in rows])}, "
              f"{_spread([r['cholesky_residual'] for r in rows])} "
              + (f"{statistics.median(pcg):>12g} ({min(pcg)}-{max(pcg)})" if pcg else "-"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
