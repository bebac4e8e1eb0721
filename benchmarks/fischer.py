"""Semismooth Newton on the Fischer-Burmeister function (saxum.solver.fischer) alone: on the
shared FCLIB 3D problems from zero impulses, and on the captured steps of a run that ended
above the tolerance (benchmarks/capped_steps.py --save) from NLGS's iterate.

    python benchmarks/fischer.py                                   # FCLIB, 1e-8, 100 iterations
    python benchmarks/capped_steps.py --save /tmp/capped.npz       # the shaken 3D L wall
    python benchmarks/fischer.py --steps /tmp/capped.npz --tolerance 1e-6 --iterations 20
    python benchmarks/fischer.py --steps /tmp/capped.npz --diagnose 0 --sigma 1e-2 --iterations 60
    python benchmarks/fischer.py --steps /tmp/capped.npz --smoothing --tolerance 1e-6 \
        --iterations 150

Prints per problem the natural-map error ||F_nat(r)|| / ||q|| reached (Acary, Bremond & Huber
2018), the iterations and the wall-clock time (time.perf_counter, one solve). With --steps,
the steps whose NLGS iterate is already within --tolerance are skipped, the others are solved
from the largest error down. --smoothing: smoothing Newton (saxum.solver.fischer.smoothing_newton,
--iterations LU factorizations at most) instead, CPU time (time.process_time) instead of wall
clock. --proximal: the hybrid's proximal stage instead (saxum.solver.newton.proximal_point,
--iterations outer iterations at most, then 10 Fischer-Burmeister Newton iterations from its
iterate where it is not within --tolerance), CPU time.

    python benchmarks/fischer.py --steps /tmp/capped.npz --proximal --tolerance 1e-6 \
        --iterations 20

--diagnose K: where the time of an iteration goes and where Newton stops, on the K-th captured
step from NLGS's iterate. First the CPU time of one iteration's parts (assembling J = A + B W,
the sparse LU of J, the Levenberg-Marquardt normal equations (J^T J + lambda I) d = -J^T phi
that saxum.solver.fischer solves). Then the proximally regularized Newton iteration
r += d, (J + sigma B) d = -phi (the first Newton step on the proximal subproblem u = (W + sigma
I) r + q - sigma r_k at r = r_k; sigma = --sigma times W's largest diagonal entry), without a
line search: the natural-map error, the cosine between successive directions, |W d| / (W_max
|d|) (d's part outside W's null space) and |r - r0|, every 5 iterations.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from capped_steps import load_kept

from saxum.fclib import LocalProblem, read_fclib
from saxum.solver.fischer import fischer_burmeister, fischer_burmeister_newton, smoothing_newton
from saxum.solver.newton import _block_diagonal, proximal_point
from saxum.solver.residual import natural_map_error

DEFAULT_FOLDER = Path(__file__).resolve().parents[1].parent / "shared" / "fclib"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--folder", type=Path, default=DEFAULT_FOLDER)
    parser.add_argument("--steps", type=Path, default=None,
                        help="captured steps (.npz of capped_steps.py --save) instead of FCLIB")
    parser.add_argument("--tolerance", type=float, default=1e-8)
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--smoothing", action="store_true",
                        help="smoothing Newton instead (--iterations: its factorizations)")
    parser.add_argument("--proximal", action="store_true",
                        help="the proximal point, then FB Newton (--iterations: outer ones)")
    parser.add_argument("--diagnose", type=int, default=None,
                        help="the captured step (index in --steps) to diagnose")
    parser.add_argument("--sigma", type=float, default=1e-2,
                        help="--diagnose's proximal regularization, relative to W's diagonal")
    args = parser.parse_args(argv)
    if args.diagnose is not None:
        _diagnose(load_kept(args.steps)[args.diagnose], args.sigma, args.iterations)
        return 0
    if args.steps is not None:
        kept = [(natural_map_error(k["w"], k["q"], k["mu"], k["r"], 3), k)
                for k in load_kept(args.steps)]
        solved = tried = 0
        for before, k in sorted(kept, key=lambda item: -item[0]):
            if before <= args.tolerance:
                continue
            cpu = args.smoothing or args.proximal
            clock = time.process_time if cpu else time.perf_counter
            start = clock()
            solver = (smoothing_newton if args.smoothing else proximal_point if args.proximal
                      else fischer_burmeister_newton)
            result = solver(k["w"], k["q"], k["mu"], k["r"], args.tolerance, args.iterations)
            if args.proximal:
                print(f"  proximal point: {result.error:.2e} after {result.iterations} outer "
                      f"iterations ({result.interior_iterations} Newton ones), "
                      f"{clock() - start:.1f} s")
                if result.error > args.tolerance:
                    result = fischer_burmeister_newton(k["w"], k["q"], k["mu"], result.r,
                                                       1e-2 * args.tolerance, 10)
            tried += 1
            solved += result.error <= args.tolerance
            print(f"step {k['step']}: {k['q'].size // 3} contacts, {before:.2e} -> "
                  f"{result.error:.2e} after {result.iterations} iterations "
                  f"({result.interior_iterations} linear solves), {clock() - start:.1f} s",
                  flush=True)
        print(f"{solved} of {tried} steps above {args.tolerance:g} brought under it "
              f"({len(kept) - tried} already were)")
        return 0
    for path in sorted(args.folder.glob("*.hdf5")):
        problem = read_fclib(path)
        if isinstance(problem, LocalProblem):
            w, q = problem.W, problem.q
        else:
            w, q = problem.delassus()
        if problem.spacedim != 3:
            print(f"{path.name}: 2D, not for this solver")
            continue
        start = time.perf_counter()
        result = fischer_burmeister_newton(w, q, problem.mu, None, args.tolerance,
                                           args.iterations)
        print(f"{path.name}: {problem.mu.size} contacts, {result.error:.2e} after "
              f"{result.iterations} iterations, {time.perf_counter() - start:.2f} s", flush=True)
    return 0


def _diagnose(k: dict, sigma_relative: float, iterations: int) -> None:
    """--diagnose on the captured step k (module doc)."""
    w, q, mu, r = k["w"], k["q"], k["mu"], k["r"].copy()
    rho = 1.0 / w.diagonal().reshape(-1, 3).max(axis=1)  # as fischer_burmeister_newton's
    scale = float(w.diagonal().max())
    phi, a_blocks, b_blocks = fischer_burmeister(r, w, q, mu, rho)
    print(f"step {k['step']}: {mu.size} contacts, W {w.nnz} nonzeros, natural-map error "
          f"{natural_map_error(w, q, mu, r, 3):.2e}")
    start = time.process_time()
    jacobian = (_block_diagonal(a_blocks) + _block_diagonal(b_blocks) @ w).tocsc()
    assembled = time.process_time()
    spla.splu(jacobian).solve(-phi)
    factored = time.process_time()
    lam = 1e-2 * float(np.linalg.norm(phi))  # fischer.py's first multiplier
    normal = (jacobian.T @ jacobian + lam * sp.identity(q.size)).tocsc()
    spla.spsolve(normal, -(jacobian.T @ phi))
    print(f"CPU per iteration: J {assembled - start:.3f} s, LU of J {factored - assembled:.3f} "
          f"s, Levenberg-Marquardt normal equations {time.process_time() - factored:.3f} s "
          f"(J^T J: {normal.nnz} nonzeros)")
    r0, previous = r.copy(), None
    for it in range(1, iterations + 1):
        b_matrix = _block_diagonal(b_blocks)
        jacobian = (_block_diagonal(a_blocks) + b_matrix @ w).tocsc()
        d = spla.splu((jacobian + sigma_relative * scale * b_matrix).tocsc()).solve(-phi)
        r = r + d
        phi, a_blocks, b_blocks = fischer_burmeister(r, w, q, mu, rho)
        if it % 5 == 0:
            cosine = float(d @ previous) / float(np.linalg.norm(d) * np.linalg.norm(previous))
            print(f"{it}: error {natural_map_error(w, q, mu, r, 3):.2e}, |phi| "
                  f"{np.linalg.norm(phi):.2e}, cos(d, d_prev) {cosine:.3f}, |W d| / (W_max |d|) "
                  f"{np.linalg.norm(w @ d) / (scale * np.linalg.norm(d)):.2e}, |d| "
                  f"{np.linalg.norm(d):.2e}, |r - r0| {np.linalg.norm(r - r0):.2e}", flush=True)
        previous = d


if __name__ == "__main__":
    sys.exit(main())
