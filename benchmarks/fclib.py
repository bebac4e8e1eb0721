"""Benchmark: saxum's solvers on the shared FCLIB frictional contact problems.

Every problem in the folder (default ../shared/fclib next to the repository) is solved from zero
impulses with saxum.fclib (global problems through their Delassus form W = H^T M^-1 H), to the
natural-map error ||F_nat(r)|| / ||q|| <= --tolerance (Acary, Bremond & Huber 2018) or
--max-iterations NLGS sweeps, by each solver of --solvers (one table each): hybrid (the
default of `saxum fclib solve`), nlgs (NLGS alone, relaxation 1; a problem it does not solve is
solved again with --relaxation, and both rows are shown), conic (the conic fixed point alone),
newton (Fischer-Burmeister Newton, then NLGS from its iterate where it stops short).
Times are wall-clock (time.perf_counter) on one thread, the median of --repeats solves,
kernels compiled beforehand; they cover the Delassus reduction, the solve and the error.

The table is printed and written into the "## FCLIB" section of BENCHMARKS.md (appended at the
end, or replaced there if it exists), with the command and the machine.

    python benchmarks/fclib.py
    python benchmarks/fclib.py --tolerance 1e-10 --no-write
"""

import argparse
import dataclasses
import datetime
import statistics
import sys
from pathlib import Path

from wall import machine_info

from saxum.fclib import (
    LocalProblem,
    format_table,
    read_fclib,
    solve_global,
    solve_local,
    verdict,
)

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
DEFAULT_FOLDER = REPO.parent / "shared" / "fclib"
SECTION = "## FCLIB"


def solve_timed(path: Path, tolerance: float, max_iterations: int, relaxation: float | None,
                repeats: int, solver: str):
    """The row of one solve, with the median time of `repeats` identical solves (after one
    untimed solve, which loads or compiles the kernels)."""
    problem = read_fclib(path)
    solve = solve_local if isinstance(problem, LocalProblem) else solve_global
    rows = [solve(problem, tolerance=tolerance, max_iterations=max_iterations,
                  relaxation=relaxation, name=path.name, solver=solver)
            for _ in range(repeats + 1)]
    return dataclasses.replace(rows[1], time=statistics.median(r.time for r in rows[1:]))


def _verdict(solver: str, rows) -> str:
    failed = [r for r in rows if not r.solved]
    if not failed:
        return f"{solver}: every problem solved."
    return f"{solver}: not solved: " + "; ".join(
        f"{r.name} with relaxation {r.relaxation:g} ({verdict(r)})" for r in failed) + "."


def section(tables, command: str, machine: dict, tolerance: float, max_iterations: int) -> str:
    date = datetime.date.today().isoformat()
    commit = (machine["git_commit"] or "unknown")[:10]
    dirty = ", src modified since" if machine["src_modified_since_commit"] else ""
    verdicts = " ".join(_verdict(solver, rows) for solver, rows in tables.items())
    body = "\n\n".join(f"Solver **{solver}**:\n\n{format_table(rows)}"
                        for solver, rows in tables.items())
    return f"""{SECTION}

- Command: `{command}` ({date}, commit {commit}{dirty}).
- Machine: {machine['cpu_model']}, {machine['cpu_count']} CPUs, {machine['platform']};
  Python {machine['python']}, numpy {machine['numpy']}, numba {machine['numba']}.

The shared FCLIB problems (`../shared/fclib`, see its README), solved by `saxum.fclib` from
zero impulses (global problems through W = H^T M^-1 H, q = H^T M^-1 f + w) by each solver:
**nlgs** the Delassus NLGS (`saxum.solver.delassus_nlgs`: the time stepper's single-contact
solvers over W in CSR); **conic** De Saxce's fixed point on the friction threshold with each
convex subproblem solved by Clarabel (`saxum.solver.conic`, at most 40 fixed-point
iterations); **newton** semismooth Newton on the Fischer-Burmeister function with a line search
and Levenberg-Marquardt regularization (`saxum.solver.fischer`, at most 100 iterations, fewer
where its merit stalls), then NLGS from its iterate where it ends above the target;
**hybrid** (the default of `saxum fclib solve`) NLGS, relaxed to 0.7 where its
error stalls, then the conic fixed point where it stalls again or falls too slowly to reach the
target within the sweeps, then NLGS from there (docs/method.md). **error** is the natural-map
residual with De Saxce's modified velocity, ||F_nat(r)|| / ||q|| (Acary, Bremond & Huber 2018),
recomputed from r alone; target {tolerance:g}, at most {max_iterations} sweeps. "fixed points":
the conic solver's iterations (one interior-point solve each); "Newton iterations": the
Fischer-Burmeister Newton's (one sparse LU each, more where the line search raises the
regularization). Time: median of the timed solves,
compiled kernels, one thread, including the Delassus reduction of global problems. {verdicts}

{body}
"""


def write_section(path: Path, text: str) -> None:
    """Replace the FCLIB section of `path` (up to the next '## ' or '### ' heading: other
    benchmarks' subsections may follow it) or append it."""
    old = path.read_text() if path.exists() else ""
    start = old.find(f"\n{SECTION}\n")
    if start < 0:
        new = old.rstrip("\n") + "\n\n" + text
    else:
        ends = [e for e in (old.find("\n## ", start + 1), old.find("\n### ", start + 1))
                if e >= 0]
        end = min(ends) if ends else -1
        new = old[: start + 1] + text + ("" if end < 0 else old[end:])
    path.write_text(new)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--folder", type=Path, default=DEFAULT_FOLDER,
                        help="folder of FCLIB .hdf5 files (default: %(default)s)")
    parser.add_argument("--tolerance", type=float, default=1e-8,
                        help="natural-map error to reach (default: %(default)g)")
    parser.add_argument("--max-iterations", type=int, default=100_000,
                        help="NLGS sweeps at most (default: %(default)d)")
    parser.add_argument("--relaxation", type=float, default=0.7,
                        help="relaxation of the second try (default: %(default)g)")
    parser.add_argument("--repeats", type=int, default=3, help="solves per problem, timed")
    parser.add_argument("--solvers", default="hybrid,nlgs,conic,newton",
                        help="comma-separated solvers, one table each (default: %(default)s)")
    parser.add_argument("--markdown", type=Path, default=REPO / "BENCHMARKS.md",
                        help="file whose FCLIB section is written (default: %(default)s)")
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args(argv)
    paths = sorted(args.folder.glob("*.hdf5"))
    if not paths:
        print(f"no .hdf5 files in {args.folder}", file=sys.stderr)
        return 1
    tables = {}
    for solver in args.solvers.split(","):
        rows = tables[solver] = []
        for path in paths:
            row = solve_timed(path, args.tolerance, args.max_iterations,
                              None if solver == "hybrid" else 1.0, args.repeats, solver)
            rows.append(row)
            if not row.solved and solver == "nlgs":
                rows.append(solve_timed(path, args.tolerance, args.max_iterations,
                                        args.relaxation, args.repeats, solver))
        print(f"{solver}:\n{format_table(rows)}")
    if not args.no_write:
        command = "python benchmarks/fclib.py" + "".join(f" {a}" for a in (argv or sys.argv[1:]))
        write_section(args.markdown, section(tables, command, machine_info(), args.tolerance,
                                             args.max_iterations))
        print(f"written to {args.markdown}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
