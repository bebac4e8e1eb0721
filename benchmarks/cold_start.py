"""Benchmark: the first step of a running-bond wall at rest (issue 16), a cold start of the
solver, and where its time goes: the rest solution's sparse factorizations
(saxum.solver.equilibrium._factorize, SuperLU, one per Newton iteration; none where the static
load path, tried first on a cold start, is the rest solution).

Per wall (dt 1e-3 s, 0.25 x 0.065 m bricks, 1800 kg/m^3, mu 0.6, on a fixed ground, saxum.NLGS
with its defaults): the first step's wall and CPU time (time.process_time), the CPU time and
number of the factorizations inside it, the NLGS sweeps, whether it converged, and the peak
resident memory. The kernels are compiled before, on a 20 x 20 wall. With --orderings, the
first Newton matrix of the largest wall is factorized again with each of SuperLU's column
orderings (permc_spec), with the CPU time and the fill (nonzeros of L + U).

On a shared machine only CPU times and ratios from one run mean anything.

    python benchmarks/cold_start.py                        # 160 x 100 (16 080 bricks)
    python benchmarks/cold_start.py --sizes 160x100 400x312 --orderings

Main against a branch, in one run (the same script with each tree's sources):
    for t in /work/main /work/wt-cold16; do PYTHONPATH=$t/src python benchmarks/cold_start.py \
        --sizes 100x80 200x160 400x312; done
"""

import argparse
import resource
import time

import numpy as np

import saxum as sx
import saxum.solver.equilibrium as equilibrium
from saxum.structures import running_bond_wall

ORDERINGS = ("MMD_AT_PLUS_A", "COLAMD", "MMD_ATA", "NATURAL")


def _wall(courses: int, bricks: int):
    return running_bond_wall(courses=courses, bricks=bricks, brick_length=0.25,
                             brick_height=0.065, density=1800.0, friction=0.6)


def _first_step(courses: int, bricks: int) -> dict:
    """The first step of one wall, with its factorizations counted and timed."""
    factorize = equilibrium._factorize
    spent = {"calls": 0, "cpu": 0.0, "matrix": None}

    def timed(data, indices, indptr, size):
        if spent["matrix"] is None:
            spent["matrix"] = (data.copy(), indices.copy(), indptr.copy(), size)
        start = time.process_time()
        out = factorize(data, indices, indptr, size)
        spent["cpu"] += time.process_time() - start
        spent["calls"] += 1
        return out

    model = _wall(courses, bricks)
    sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS())
    state = sim.initial_state()
    equilibrium._factorize = timed
    try:
        wall, cpu = time.perf_counter(), time.process_time()
        sim.step(state)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    finally:
        equilibrium._factorize = factorize
    free = int(np.count_nonzero(model.body_inv_mass[:, 0] > 0.0))
    return {"blocks": free, "wall_s": wall, "cpu_s": cpu,
            "factorizations": spent["calls"], "factorize_cpu_s": spent["cpu"],
            "sweeps": int(sim.log.iterations[-1]), "converged": bool(sim.log.converged[-1]),
            "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            "matrix": spent["matrix"]}


def _orderings(matrix) -> None:
    """Factorize one Newton matrix with each SuperLU column ordering."""
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu

    data, indices, indptr, size = matrix
    a = csc_matrix((data, indices, indptr), shape=(size, size))
    rhs = np.random.default_rng(0).standard_normal(size)
    print(f"  Newton matrix: {size} unknowns, {a.nnz} nonzeros")
    for spec in ORDERINGS:
        start = time.process_time()
        lu = splu(a, permc_spec=spec, diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        cpu = time.process_time() - start
        start = time.process_time()
        solution = lu.solve(rhs)
        solve = time.process_time() - start
        error = np.linalg.norm(a @ solution - rhs) / np.linalg.norm(rhs)
        print(f"  {spec:14s} factorize {cpu:7.3f} s CPU, solve {solve:6.3f} s, "
              f"fill {lu.L.nnz + lu.U.nnz:>10d}, relative residual {error:.1e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", default=["160x100"],
                        help="walls as COURSESxBRICKS (160x100: 16 080 bricks)")
    parser.add_argument("--orderings", action="store_true",
                        help="also factorize the largest wall's first Newton matrix with each "
                             "SuperLU ordering")
    args = parser.parse_args()
    _first_step(20, 20)  # compile, the rest solution included (51 sweeps on 410 bricks)
    last = None
    for text in args.sizes:
        courses, bricks = (int(n) for n in text.lower().split("x"))
        r = _first_step(courses, bricks)
        print(f"{courses} x {bricks} wall, {r['blocks']} bricks: first step {r['wall_s']:.2f} s "
              f"wall, {r['cpu_s']:.2f} s CPU; {r['factorizations']} factorizations "
              f"{r['factorize_cpu_s']:.2f} s CPU; {r['sweeps']} sweeps, converged "
              f"{r['converged']}; peak RSS {r['peak_rss_mib']:.0f} MiB")
        last = r["matrix"] or last
    if args.orderings and last is not None:
        _orderings(last)


if __name__ == "__main__":
    main()
