"""Benchmark: the hybrid solver against NLGS alone on the documented applications where the
first hybrid lost (docs/method.md): the Burnum ramp (examples/burnum_harmonic.toml, 16 s,
8000 steps) and the Burnum arch under the Friuli record (examples/burnum_record.toml, 14 s,
7000 steps; needs `pip install 'saxum[records]'`).

Each scenario runs with solver.kind = "nlgs" and "hybrid" in turn in this one process and
prints, per run: steps whose error ended above the tolerance, the largest error at the end of
a step, the steps the conic solver finished, the largest displacement of a free block over the
frames (and when), the one at the end, and the wall time (a ratio only within one run of this
script: the machine is shared).

    python benchmarks/hybrid_apps.py                       # both scenarios, in full
    python benchmarks/hybrid_apps.py --cases burnum_record --duration 8
    python benchmarks/hybrid_apps.py --cases burnum_record --set solver.tolerance=1e-8
"""

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from saxum.cli import main as saxum
from saxum.results import Results

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
CASES = ("burnum_harmonic", "burnum_record")
KINDS = ("nlgs", "hybrid")


def run(case: str, kind: str, folder: Path, duration: float | None, sets: list[str]) -> dict:
    """Run the example with solver `kind` (and the overrides `sets`); what the module doc
    lists."""
    out = folder / f"{case}-{kind}.h5"
    options = ["--set", f"solver.kind={kind}"] + [x for key in sets for x in ("--set", key)]
    if duration is not None:
        options += ["--set", f"output.duration={duration}"]
    start = time.perf_counter()
    assert saxum(["run", str(EXAMPLES / f"{case}.toml"), "--quiet", "-o", str(out),
                  *options]) == 0
    wall = time.perf_counter() - start
    with Results(out) as r:
        s = r.steps
        free = r.model["body_kind"] == 0
        moved = np.linalg.norm(r.body_q[:, free, :2] - r.model["body_q0"][free, :2],
                               axis=-1).max(axis=1)
        peak = int(np.argmax(moved))
        return {"steps": int(s["step"].size), "above": int(np.count_nonzero(~s["converged"])),
                "worst": float(s["error"].max()), "conic": int(np.count_nonzero(s["solver"])),
                "sweeps": float(s["iterations"].mean()), "peak": float(moved[peak]),
                "at": float(r.time[peak]), "end": float(moved[-1]), "wall": wall}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES))
    parser.add_argument("--duration", type=float, default=None,
                        help="output.duration [s] (default: the example's)")
    parser.add_argument("--kinds", nargs="+", choices=KINDS, default=list(KINDS))
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a scenario override for every run (solver.tolerance=1e-8)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        for case in args.cases:
            for kind in args.kinds:
                m = run(case, kind, Path(folder), args.duration, args.set)
                print(f"{case:16s} {kind:6s} steps {m['steps']}, above tolerance {m['above']}, "
                      f"largest error {m['worst']:.3g}, finished by conic {m['conic']}, "
                      f"sweeps/step {m['sweeps']:.1f}, largest displacement {m['peak']:.4f} m "
                      f"at t = {m['at']:.2f} s, at the end {m['end']:.4f} m, "
                      f"wall {m['wall']:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
