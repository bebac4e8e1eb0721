"""The steps a case ends above the tolerance, measured by the natural-map error, and the other
solvers tried on them (docs/method.md, "The shaken 3D L wall").

    python benchmarks/capped_steps.py                          # wall3d-shaken, 0.3 s (long)
    python benchmarks/capped_steps.py --case wall3d-shaken --solve 1
    python benchmarks/capped_steps.py --small --solve 1        # the 29-brick L wall, 0.02 s
    python benchmarks/capped_steps.py --save /tmp/capped.npz   # keep them (benchmarks/fischer.py)
    python benchmarks/capped_steps.py --load /tmp/capped.npz --existence 10
    python benchmarks/capped_steps.py --small --save-first tests/data/small_l_wall_step14.npz

Runs the case (benchmarks/convergence.py's CASES; --small: the 4-course L wall of walls 1.0
and 0.75 m under 0.7 g, tests/test_hybrid.py's) with NLGS alone and keeps the assembled
local problem (saxum.solver.assembled: W, q, mu in FCLIB order) of every step that ends above
the tolerance, with NLGS's iterate. Prints, per such step, NLGS's criterion and the natural-map
error ||F_nat(r)|| / ||q|| of NLGS's iterate (saxum.solver.residual), then their spread.
--solve K: on the first K of them, semismooth Newton (saxum.solver.newton) from NLGS's iterate
and from zero impulses (--newton iterations), and the proximal point method (outer iterations
r_k+1 solving u = (W + sigma I) r + q - sigma r_k by Newton; sigma = 1e-2, then 1e-3 times
W's largest diagonal entry, --outer each): the natural-map error each reaches and its time.
--existence K: on the first K of them, whether the step's problem has a solution: W's rank
(singular values above 1e-12 times the largest) and the strict feasibility margin
max t subject to u_N - mu (|u_T1| + |u_T2|) >= t ||q|| for every contact, u = W r + q, t <= 1
(a linear program, HiGHS). A positive margin puts u in the interior of the dual cone K* (the
l1 norm bounds the l2 one), and then the Coulomb problem has a solution whatever W's rank (V.
Acary, F. Cadoux, C. Lemarechal, J. Malick, "A formulation of the linear discrete Coulomb
friction problem via convex optimization", ZAMM 91(2), 2011, sec. 3: strict feasibility of
the associated conic problem). Also the frictionless problem (mu = 0: a monotone linear
complementarity problem, W positive semidefinite: one convex problem) by Clarabel
(saxum.solver.conic, whose fixed point is exact after one iteration there): the natural-map
error it reaches. --load: the steps of an earlier --save instead of a run.
"""

import argparse
import dataclasses
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp

import saxum as sx
from saxum.solver.assembled import assemble_local
from saxum.solver.conic import delassus_conic
from saxum.solver.newton import alart_curnier_newton
from saxum.solver.residual import natural_map_error
from saxum.structures import wall3d

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from convergence import CASES, DT  # noqa: E402  (benchmarks/ is not a package)


class _Keeping(sx.ContactSolver):
    """NLGS that keeps the assembled problem and NLGS's iterate of every step it does not
    converge on (not the projections')."""

    def __init__(self):
        self.nlgs, self.kept, self.steps = sx.NLGS(), [], 0

    def solve(self, problem, impulse, v_free, v):
        report = self.nlgs.solve(problem, impulse, v_free, v)
        if getattr(problem, "v_begin", None) is None:
            return report
        self.steps += 1
        if not report.converged:
            local = assemble_local(problem, v_free)
            self.kept.append({"step": self.steps, "w": local.w, "q": local.q, "mu": local.mu,
                              "r": local.impulses(impulse), "error": report.error,
                              "hstar": local.hstar, "inv_mass": local.inv_mass})
        return report


def _small():
    model = wall3d(courses=4, length=1.0, return_length=0.75)
    g = float(np.linalg.norm(model.gravity))
    return dataclasses.replace(model, accelerations=((lambda t: (0.7 * g, 0.0, 0.0)),))


def _proximal(w, q, mu, r, outer: int, newton: int):
    """The proximal point method from r: (natural-map error, seconds) after each sigma."""
    identity = sp.identity(q.size, format="csr")
    scale = float(w.diagonal().max())
    out = []
    start = time.perf_counter()
    for relative in (1e-2, 1e-3):
        sigma = relative * scale
        for _ in range(outer):
            r = alart_curnier_newton(w + sigma * identity, q - sigma * r, mu, 3, r, 1e-12,
                                     newton).r
        out.append((relative, natural_map_error(w, q, mu, r, 3),
                    time.perf_counter() - start))
    return out


def _existence(w, q, mu) -> tuple[int, int, float, float]:
    """(rank of W, its size, the strict feasibility margin t of the module doc, the natural-map
    error of the frictionless problem's solution by Clarabel)."""
    from scipy.optimize import linprog

    singular = np.linalg.svd(w.toarray(), compute_uv=False)
    rank = int(np.count_nonzero(singular > 1e-12 * singular[0]))
    m = mu.size
    w = sp.csr_matrix(w)
    rows_n, rows_t1, rows_t2 = w[0::3], w[1::3], w[2::3]
    eye, zero = sp.identity(m, format="csr"), sp.csr_matrix((m, m))
    scale = float(np.linalg.norm(q))
    col = sp.csr_matrix(np.full((m, 1), scale))
    # unknowns (r, s1, s2, t): -u_N + mu (s1 + s2) + t ||q|| <= 0, +-u_Tk - s_k <= 0
    mu_diag = sp.diags(mu)
    a = sp.vstack([
        sp.hstack([-rows_n, mu_diag, mu_diag, col]),
        sp.hstack([rows_t1, -eye, zero, sp.csr_matrix((m, 1))]),
        sp.hstack([-rows_t1, -eye, zero, sp.csr_matrix((m, 1))]),
        sp.hstack([rows_t2, zero, -eye, sp.csr_matrix((m, 1))]),
        sp.hstack([-rows_t2, zero, -eye, sp.csr_matrix((m, 1))]),
    ]).tocsr()
    b = np.concatenate([q[0::3], -q[1::3], q[1::3], -q[2::3], q[2::3]])
    cost = np.zeros(q.size + 2 * m + 1)
    cost[-1] = -1.0
    bounds = [(None, None)] * q.size + [(0.0, None)] * (2 * m) + [(None, 1.0)]
    result = linprog(cost, A_ub=a, b_ub=b, bounds=bounds, method="highs")
    margin = float(result.x[-1]) if result.success else math.nan
    frictionless = delassus_conic(w, q, np.zeros_like(mu), 3, None, 1e-10, 3)
    return rank, q.size, margin, frictionless.error


def _save(path: Path, kept: list[dict]) -> None:
    """The kept problems in one .npz (W as CSR arrays), read back by load_kept."""
    arrays = {}
    for i, k in enumerate(kept):
        w = sp.csr_matrix(k["w"])
        arrays.update({f"{i}_data": w.data, f"{i}_indices": w.indices, f"{i}_indptr": w.indptr,
                       f"{i}_q": k["q"], f"{i}_mu": k["mu"], f"{i}_r": k["r"],
                       f"{i}_meta": np.array([k["step"], k["error"]])})
    np.savez_compressed(path, count=len(kept), **arrays)


def _save_first(path: Path, kept: list[dict]) -> None:
    """The first kept problem by its factors W = H* M^-1 H*^T (CSR H*, M^-1), q, mu and NLGS's
    iterate r: ten times smaller than W (tests/data/small_l_wall_step14.npz)."""
    k = kept[0]
    h = sp.csr_matrix(k["hstar"])
    np.savez_compressed(path, h_data=h.data, h_indices=h.indices, h_indptr=h.indptr,
                        h_shape=np.array(h.shape), inv_mass=k["inv_mass"], q=k["q"],
                        mu=k["mu"], r=k["r"], step=k["step"])


def load_kept(path: Path) -> list[dict]:
    """The problems _save wrote: dicts with step, w, q, mu, r, error."""
    data = np.load(path)
    kept = []
    for i in range(int(data["count"])):
        q = data[f"{i}_q"]
        w = sp.csr_matrix((data[f"{i}_data"], data[f"{i}_indices"], data[f"{i}_indptr"]),
                          shape=(q.size, q.size))
        step, error = data[f"{i}_meta"]
        kept.append({"step": int(step), "w": w, "q": q, "mu": data[f"{i}_mu"],
                     "r": data[f"{i}_r"], "error": float(error)})
    return kept


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--case", default="wall3d-shaken", choices=sorted(CASES))
    parser.add_argument("--small", action="store_true",
                        help="the 29-brick L wall under 0.7 g instead of --case")
    parser.add_argument("--duration", type=float, default=None,
                        help="simulated time [s] (default: the case's; 0.02 with --small)")
    parser.add_argument("--solve", type=int, default=0,
                        help="run the other solvers on the first SOLVE steps kept")
    parser.add_argument("--newton", type=int, default=100, help="Newton iterations at most")
    parser.add_argument("--outer", type=int, default=15,
                        help="proximal outer iterations per sigma")
    parser.add_argument("--existence", type=int, default=0,
                        help="W's rank and the strict feasibility margin of the first K steps")
    parser.add_argument("--load", type=Path, default=None,
                        help="the steps of an earlier --save (3D) instead of a run")
    parser.add_argument("--save", type=Path, default=None,
                        help="write the kept problems (W, q, mu, NLGS's iterate) to this .npz")
    parser.add_argument("--save-first", type=Path, default=None,
                        help="write the first kept problem as H*, M^-1, q, mu, r to this .npz")
    args = parser.parse_args(argv)
    if args.small:
        model, duration = _small(), 0.02
    else:
        model, duration = CASES[args.case][0](), CASES[args.case][1]
    duration = duration if args.duration is None else args.duration
    keeping = _Keeping()
    if args.load is not None:
        keeping.kept = load_kept(args.load)
        keeping.steps = max(k["step"] for k in keeping.kept)  # at least: the run's is not kept
    else:
        sim = sx.Simulation(model, dt=DT, solver=keeping)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sx.SolverWarning)
            sim.run(sim.initial_state(), duration)
    if args.save is not None:
        _save(args.save, keeping.kept)
    if args.save_first is not None and keeping.kept:
        _save_first(args.save_first, keeping.kept)
    natural = np.array([natural_map_error(k["w"], k["q"], k["mu"], k["r"], 3)
                        for k in keeping.kept])
    criterion = np.array([k["error"] for k in keeping.kept])
    for k, e in zip(keeping.kept, natural, strict=True):
        print(f"step {k['step']}: {k['q'].size // 3} contacts, NLGS's criterion "
              f"{k['error']:.3g}, natural-map error of its iterate {e:.3g}")
    if natural.size:
        print(f"{natural.size} of {keeping.steps} steps above the tolerance; natural-map error "
              f"min / median / max {natural.min():.2g} / {np.median(natural):.2g} / "
              f"{natural.max():.2g} ({np.count_nonzero(natural <= 1e-6)} at most 1e-6, "
              f"{np.count_nonzero(natural <= 1e-5)} at most 1e-5); NLGS's criterion "
              f"{criterion.min():.2g} / {np.median(criterion):.2g} / {criterion.max():.2g}; "
              f"ratio {np.min(natural / criterion):.2g} to {np.max(natural / criterion):.2g}")
    for k in keeping.kept[: args.existence]:
        rank, size, margin, frictionless = _existence(k["w"], k["q"], k["mu"])
        print(f"step {k['step']}: W of rank {rank} of {size}, strict feasibility margin "
              f"{margin:.3g}" + (" (a solution exists)" if margin > 0.0 else "")
              + f"; frictionless problem solved to {frictionless:.2g}", flush=True)
    for k in keeping.kept[: args.solve]:
        w, q, mu = k["w"], k["q"], k["mu"]
        for name, r0 in (("NLGS's iterate", k["r"]), ("zero", None)):
            start = time.perf_counter()
            result = alart_curnier_newton(w, q, mu, 3, r0, 1e-10, args.newton)
            print(f"step {k['step']}: Newton from {name}: {result.error:.3g} after "
                  f"{result.iterations} iterations, {time.perf_counter() - start:.1f} s")
        for relative, error, seconds in _proximal(w, q, mu, k["r"], args.outer, args.newton):
            print(f"step {k['step']}: proximal point from NLGS's iterate, sigma {relative:g} "
                  f"x max diag W, {args.outer} outer iterations: {error:.3g} ({seconds:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
