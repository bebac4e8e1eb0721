"""Semismooth Newton on the Fischer-Burmeister function (saxum.solver.fischer) alone: on the
shared FCLIB 3D problems from zero impulses, and on the captured steps of a run that ended
above the tolerance (benchmarks/capped_steps.py --save) from NLGS's iterate.

    python benchmarks/fischer.py                                   # FCLIB, 1e-8, 100 iterations
    python benchmarks/capped_steps.py --save /tmp/capped.npz       # the shaken 3D L wall
    python benchmarks/fischer.py --steps /tmp/capped.npz --tolerance 1e-6 --iterations 20

Prints per problem the natural-map error ||F_nat(r)|| / ||q|| reached (Acary, Bremond & Huber
2018), the iterations and the wall-clock time (time.perf_counter, one solve). With --steps,
the steps whose NLGS iterate is already within --tolerance are skipped, the others are solved
from the largest error down.
"""

import argparse
import sys
import time
from pathlib import Path

from capped_steps import load_kept

from saxum.fclib import LocalProblem, read_fclib
from saxum.solver.fischer import fischer_burmeister_newton
from saxum.solver.residual import natural_map_error

DEFAULT_FOLDER = Path(__file__).resolve().parents[1].parent / "shared" / "fclib"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--folder", type=Path, default=DEFAULT_FOLDER)
    parser.add_argument("--steps", type=Path, default=None,
                        help="captured steps (.npz of capped_steps.py --save) instead of FCLIB")
    parser.add_argument("--tolerance", type=float, default=1e-8)
    parser.add_argument("--iterations", type=int, default=100)
    args = parser.parse_args(argv)
    if args.steps is not None:
        kept = [(natural_map_error(k["w"], k["q"], k["mu"], k["r"], 3), k)
                for k in load_kept(args.steps)]
        solved = tried = 0
        for before, k in sorted(kept, key=lambda item: -item[0]):
            if before <= args.tolerance:
                continue
            start = time.perf_counter()
            result = fischer_burmeister_newton(k["w"], k["q"], k["mu"], k["r"], args.tolerance,
                                               args.iterations)
            tried += 1
            solved += result.error <= args.tolerance
            print(f"step {k['step']}: {k['q'].size // 3} contacts, {before:.2e} -> "
                  f"{result.error:.2e} after {result.iterations} iterations, "
                  f"{time.perf_counter() - start:.1f} s", flush=True)
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


if __name__ == "__main__":
    sys.exit(main())
