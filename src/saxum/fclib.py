"""FCLIB: the HDF5 format of frictional contact problems, read, written, solved and exported.

FCLIB (V. Acary, M. Bremond, T. Koziara, F. Perignon, "FCLIB: a collection of discrete 3D
frictional contact problems", 2014) stores one problem per file:
- local:  find r, u in R^m with u = W r + q, each contact on its Coulomb cone
          (group /fclib_local: spacedim, W, vectors/q, vectors/mu);
- global: find v, r, u with M v = H r + f, u = H^T v + w, same contact law
          (group /fclib_global: spacedim, M, H, vectors/f, vectors/w, vectors/mu);
both with an optional info group (title, description, math_info), /solution and /guesses.
Per contact the components are ordered [normal, tangent(s)] (saxum's frames are (t, n[, s])).
A matrix group holds CSparse arrays: nz >= 0 triplet (i rows, p columns, nz entries), nz = -1
CSC (p column pointers), nz = -2 CSR (p row pointers); integers are int32 datasets of shape (1,).
Rolling friction (/fclib_global_rolling, spacedim 5) and the mixed variants with equality
constraints (local V, R, s; global G, b) are refused: saxum does not solve them.

The solve reduces a global problem to its Delassus form W = H^T M^-1 H, q = H^T M^-1 f + w and
runs saxum.solver.delassus_nlgs on W, switching to saxum.solver.conic where NLGS stalls
(SOLVERS); the reported error is always the natural-map residual
||F_nat(r)|| / ||q|| of saxum.solver.residual (for a global problem: of its Delassus form).
"""

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import InputError
from .solver.assembled import assemble_local
from .solver.base import STALLED
from .solver.conic import delassus_conic
from .solver.delassus_nlgs import DelassusNLGS
from .solver.fischer import fischer_burmeister_newton
from .solver.residual import natural_map_error

__all__ = [
    "GlobalProblem",
    "Info",
    "LocalProblem",
    "MatrixInfo",
    "SOLVERS",
    "SolveRow",
    "Solution",
    "export_step",
    "format_table",
    "read_fclib",
    "solve_fclib_files",
    "solve_global",
    "solve_local",
    "step_problem",
    "verdict",
    "write_fclib",
]

STORAGES = {"triplet": None, "csc": -1, "csr": -2}
"""Matrix storages of write_fclib and their FCLIB nz code (triplet: nz = number of entries)."""

_PROBLEM_GROUPS = ("fclib_local", "fclib_global")


@dataclass
class Info:
    """The problem's info group; None where a field is absent. Bytes that are not UTF-8 are
    kept (surrogateescape), so that a file read and written again is unchanged."""

    title: str | None = None
    description: str | None = None
    math_info: str | None = None


@dataclass
class MatrixInfo:
    """FCLIB's optional matrix information (fclib_matrix_info); None where absent."""

    comment: str | None = None
    conditioning: float | None = None
    sparsity: float | None = None
    determinant: float | None = None
    rank: int | None = None


@dataclass
class Solution:
    """A solution or a guess: u and r [FCLIB order], v (global problems); None where absent."""

    u: np.ndarray | None = None
    r: np.ndarray | None = None
    v: np.ndarray | None = None


@dataclass(kw_only=True)
class _ProblemRecord:
    """What FCLIB stores beside a problem's data: info, guesses, solution; matrix_info: per
    matrix name ("W", "M", "H"); attributes: HDF5 attributes by object path (none are part of
    FCLIB, but codes such as LMGC90 and Siconos add some: they are kept)."""

    info: Info | None = None
    guesses: list[Solution] = field(default_factory=list)
    solution: Solution | None = None
    matrix_info: dict[str, MatrixInfo] = field(default_factory=dict)
    attributes: dict[str, dict] = field(default_factory=dict)

    @property
    def contacts(self) -> int:
        return self.mu.size


@dataclass
class LocalProblem(_ProblemRecord):
    """u = W r + q, r_alpha in K_mu_alpha; W (m, m) CSR, m = spacedim x contacts."""

    W: sp.csr_matrix
    q: np.ndarray
    mu: np.ndarray
    spacedim: int


@dataclass
class GlobalProblem(_ProblemRecord):
    """M v = H r + f, u = H^T v + w, r_alpha in K_mu_alpha; M (n, n), H (n, m) CSR."""

    M: sp.csr_matrix
    H: sp.csr_matrix
    f: np.ndarray
    w: np.ndarray
    mu: np.ndarray
    spacedim: int

    def delassus(self) -> tuple[sp.csr_matrix, np.ndarray]:
        """(W, q) = (H^T M^-1 H, H^T M^-1 f + w), by a sparse LU of M; M^-1 H is formed a few
        hundred columns at a time, so only W needs to fit in memory."""
        try:
            lu = spla.splu(sp.csc_matrix(self.M))
        except RuntimeError as err:
            raise InputError(f"the mass matrix M cannot be factorized ({err})") from None
        h = sp.csc_matrix(self.H)
        ht = h.T.tocsr()
        chunk = 256
        cols = [sp.csr_matrix(ht @ lu.solve(h[:, k:k + chunk].toarray()))
                for k in range(0, h.shape[1], chunk)]
        w = sp.hstack(cols, format="csr") if cols else sp.csr_matrix(ht.shape[:1] * 2)
        return w, ht @ lu.solve(self.f) + self.w


# --- reading ----------------------------------------------------------------------------------


def read_fclib(path: str | Path) -> LocalProblem | GlobalProblem:
    """Read an FCLIB local or global problem; InputError for anything else."""
    path = Path(path)
    try:
        h5 = h5py.File(path, "r")
    except OSError as err:
        raise InputError(f"{path}: not a readable HDF5 file ({err})") from None
    with h5:
        try:
            return _read(h5)
        except InputError as err:
            raise InputError(f"{path}: {err}") from None
        except (KeyError, TypeError, ValueError) as err:
            raise InputError(f"{path}: not a valid FCLIB file ({err})") from None


def _read(h5: h5py.File) -> LocalProblem | GlobalProblem:
    if "fclib_global_rolling" in h5:
        raise InputError("rolling friction (/fclib_global_rolling) is an FCLIB variant that "
                         "saxum does not solve")
    kinds = [k for k in _PROBLEM_GROUPS if k in h5]
    if len(kinds) != 1:
        raise InputError("not an FCLIB problem: expected exactly one of the groups "
                         f"/fclib_local, /fclib_global, found {sorted(h5.keys())}")
    g = h5[kinds[0]]
    spacedim = _int(g, "spacedim")
    if spacedim not in (2, 3):
        raise InputError(f"spacedim {spacedim} is not supported (2 or 3; 5 is rolling "
                         "friction, which saxum does not solve)")
    for extra in ("V", "R", "G"):
        if extra in g:
            raise InputError(f"the problem has the equality-constraint matrix {extra}: a mixed "
                             "FCLIB variant that saxum does not solve")
    info = _read_info(g["info"]) if "info" in g else None
    vec = g["vectors"]
    mu = _vector(vec, "mu")
    attributes = _read_attributes(h5)
    if kinds[0] == "fclib_local":
        w = _read_matrix(g["W"])
        q = _vector(vec, "q")
        _check_local(w, q, mu, spacedim)
        problem = LocalProblem(w, q, mu, spacedim, info=info,
                               matrix_info=_matrix_infos(g, ("W",)), attributes=attributes)
        sizes = {"u": q.size, "r": q.size}
    else:
        m, h = _read_matrix(g["M"]), _read_matrix(g["H"])
        f, w_vec = _vector(vec, "f"), _vector(vec, "w")
        _check_global(m, h, f, w_vec, mu, spacedim)
        problem = GlobalProblem(m, h, f, w_vec, mu, spacedim, info=info,
                                matrix_info=_matrix_infos(g, ("M", "H")), attributes=attributes)
        sizes = {"u": w_vec.size, "r": w_vec.size, "v": f.size}
    if "solution" in h5:
        problem.solution = _read_solution(h5["solution"], sizes)
    if "guesses" in h5:
        count = _int(h5["guesses"], "number_of_guesses")
        problem.guesses = [_read_solution(h5[f"guesses/{k}"], sizes)
                           for k in range(1, count + 1)]
    return problem


def _int(group: h5py.Group, name: str) -> int:
    return int(np.asarray(group[name][()]).ravel()[0])


def _vector(group: h5py.Group, name: str) -> np.ndarray:
    return np.asarray(group[name][()], dtype=np.float64).ravel()


def _read_matrix(g: h5py.Group) -> sp.csr_matrix:
    """CSparse arrays -> CSR (entries of a triplet that repeat a position are summed)."""
    nz, m, n = _int(g, "nz"), _int(g, "m"), _int(g, "n")
    p = np.asarray(g["p"][()], dtype=np.int64)
    i = np.asarray(g["i"][()], dtype=np.int64)
    x = np.asarray(g["x"][()], dtype=np.float64)
    if nz >= 0:
        # only the first nz entries count (nzmax may be larger)
        if min(p.size, i.size, x.size) < nz:
            raise InputError(f"{g.name}: triplet with nz = {nz} but shorter arrays")
        mat = sp.coo_matrix((x[:nz], (i[:nz], p[:nz])), shape=(m, n)).tocsr()
    elif nz in (-1, -2):
        outer = n if nz == -1 else m
        if p.size != outer + 1 or p[-1] > min(i.size, x.size):
            raise InputError(f"{g.name}: compressed storage with inconsistent p, i, x sizes")
        args = (x[: p[-1]], i[: p[-1]], p)
        mat = (sp.csc_matrix(args, shape=(m, n)) if nz == -1
               else sp.csr_matrix(args, shape=(m, n))).tocsr()
    else:
        raise InputError(f"{g.name}: unknown sparse storage nz = {nz} (triplet >= 0, CSC -1, "
                         "CSR -2)")
    mat.sum_duplicates()
    return mat


def _text(dataset: h5py.Dataset) -> str:
    raw = dataset[()]
    if isinstance(raw, np.ndarray):
        raw = raw.ravel()[0]
    if isinstance(raw, bytes):
        return raw.decode("utf-8", "surrogateescape")
    return str(raw)


def _read_info(g: h5py.Group) -> Info:
    return Info(**{k: _text(g[k]) if k in g else None
                   for k in ("title", "description", "math_info")})


def _matrix_infos(g: h5py.Group, names: tuple[str, ...]) -> dict[str, MatrixInfo]:
    out = {}
    for name in names:
        mg = g[name]
        values = {
            "comment": _text(mg["comment"]) if "comment" in mg else None,
            "rank": _int(mg, "rank") if "rank" in mg else None,
        }
        for key in ("conditioning", "sparsity", "determinant"):
            values[key] = float(_vector(mg, key)[0]) if key in mg else None
        if any(v is not None for v in values.values()):
            out[name] = MatrixInfo(**values)
    return out


def _read_solution(g: h5py.Group, sizes: dict[str, int]) -> Solution:
    out = Solution()
    for name, size in sizes.items():
        if name in g:
            value = _vector(g, name)
            if value.size != size:
                raise InputError(f"{g.name}/{name} has {value.size} values, the problem needs "
                                 f"{size}")
            setattr(out, name, value)
    return out


def _read_attributes(h5: h5py.File) -> dict[str, dict]:
    out = {}

    def visit(name, obj):
        if obj.attrs:
            out[name] = dict(obj.attrs)

    visit("/", h5)
    h5.visititems(visit)
    return out


def _check_local(w, q, mu, spacedim) -> None:
    m = q.size
    if w.shape != (m, m) or m != spacedim * mu.size:
        raise InputError(f"sizes do not match: W {w.shape}, q {m}, mu {mu.size}, "
                         f"spacedim {spacedim}")
    _check_finite(W=w.data, q=q)
    _check_mu(mu)


def _check_global(m, h, f, w, mu, spacedim) -> None:
    n = f.size
    if m.shape != (n, n) or h.shape != (n, w.size) or w.size != spacedim * mu.size:
        raise InputError(f"sizes do not match: M {m.shape}, H {h.shape}, f {n}, w {w.size}, "
                         f"mu {mu.size}, spacedim {spacedim}")
    _check_finite(M=m.data, H=h.data, f=f, w=w)
    _check_mu(mu)


def _check_finite(**arrays: np.ndarray) -> None:
    for name, values in arrays.items():
        bad = np.count_nonzero(~np.isfinite(values))
        if bad:
            raise InputError(f"{name} has {bad} value(s) that are not finite numbers (NaN or "
                             "inf): the problem cannot be solved")


def _check_mu(mu) -> None:
    if not np.all(np.isfinite(mu) & (mu >= 0.0)):
        raise InputError("friction coefficients mu must be finite and >= 0")


# --- writing ----------------------------------------------------------------------------------


def write_fclib(path: str | Path, problem: LocalProblem | GlobalProblem,
                storage: str = "csr") -> None:
    """Write `problem` to a new FCLIB file (overwritten if it exists); storage of the
    matrices: "csr", "csc" or "triplet"."""
    if storage not in STORAGES:
        raise InputError(f"storage must be one of {sorted(STORAGES)}, got {storage!r}")
    if problem.spacedim not in (2, 3):
        raise InputError(f"spacedim must be 2 or 3, got {problem.spacedim}")
    if isinstance(problem, LocalProblem):
        _check_local(problem.W, problem.q, problem.mu, problem.spacedim)
        name, matrices = "fclib_local", {"W": problem.W}
        vectors = {"q": problem.q, "mu": problem.mu}
        sizes = {"u": problem.q.size, "r": problem.q.size}
    else:
        _check_global(problem.M, problem.H, problem.f, problem.w, problem.mu, problem.spacedim)
        name, matrices = "fclib_global", {"M": problem.M, "H": problem.H}
        vectors = {"f": problem.f, "w": problem.w, "mu": problem.mu}
        sizes = {"u": problem.w.size, "r": problem.w.size, "v": problem.f.size}
    for sol in [problem.solution, *problem.guesses]:
        for key, size in sizes.items():
            if sol is not None and getattr(sol, key) is not None and getattr(sol, key).size != size:
                raise InputError(f"a solution or guess has {getattr(sol, key).size} values of "
                                 f"{key}, the problem needs {size}")
    with h5py.File(path, "w") as h5:
        g = h5.create_group(name)
        _int_dataset(g, "spacedim", problem.spacedim)
        for key, mat in matrices.items():
            mg = g.create_group(key)
            _write_matrix(mg, mat, storage)
            if key in problem.matrix_info:
                _write_matrix_info(mg, problem.matrix_info[key])
        vg = g.create_group("vectors")
        for key, value in vectors.items():
            vg.create_dataset(key, data=np.asarray(value, dtype=np.float64))
        if problem.info is not None:
            ig = g.create_group("info")
            for key in ("title", "description", "math_info"):
                if getattr(problem.info, key) is not None:
                    _string_dataset(ig, key, getattr(problem.info, key))
        if problem.solution is not None:
            _write_solution(h5.create_group("solution"), problem.solution)
        if problem.guesses:
            gg = h5.create_group("guesses")
            _int_dataset(gg, "number_of_guesses", len(problem.guesses))
            for k, guess in enumerate(problem.guesses, start=1):
                _write_solution(gg.create_group(str(k)), guess)
        for obj_path, attrs in problem.attributes.items():
            if obj_path in h5:
                h5[obj_path].attrs.update(attrs)


def _int_dataset(g: h5py.Group, name: str, value: int) -> None:
    g.create_dataset(name, data=np.array([value], dtype=np.int32))


def _string_dataset(g: h5py.Group, name: str, text: str) -> None:
    raw = text.encode("utf-8", "surrogateescape")
    # fixed-length and NUL-terminated, as FCLIB's H5LTmake_dataset_string writes it
    g.create_dataset(name, data=np.array(raw, dtype=f"S{len(raw) + 1}"))


def _write_matrix(g: h5py.Group, mat: sp.spmatrix, storage: str) -> None:
    m, n = mat.shape
    if storage == "triplet":
        coo = sp.coo_matrix(mat)
        nz = coo.nnz
        p, i, x = coo.col, coo.row, coo.data
    else:
        comp = sp.csc_matrix(mat) if storage == "csc" else sp.csr_matrix(mat)
        nz = STORAGES[storage]
        p, i, x = comp.indptr, comp.indices, comp.data
    for key, value in (("nzmax", x.size), ("m", m), ("n", n), ("nz", nz)):
        _int_dataset(g, key, value)
    g.create_dataset("p", data=np.asarray(p, dtype=np.int32))
    g.create_dataset("i", data=np.asarray(i, dtype=np.int32))
    g.create_dataset("x", data=np.asarray(x, dtype=np.float64))


def _write_matrix_info(g: h5py.Group, info: MatrixInfo) -> None:
    if info.comment is not None:
        _string_dataset(g, "comment", info.comment)
    for key in ("conditioning", "sparsity", "determinant"):
        if getattr(info, key) is not None:
            g.create_dataset(key, data=np.array([getattr(info, key)], dtype=np.float64))
    if info.rank is not None:
        _int_dataset(g, "rank", info.rank)


def _write_solution(g: h5py.Group, sol: Solution) -> None:
    for key in ("v", "u", "r"):
        if getattr(sol, key) is not None:
            g.create_dataset(key, data=np.asarray(getattr(sol, key), dtype=np.float64))


# --- solving ----------------------------------------------------------------------------------


SOLVERS = ("hybrid", "nlgs", "conic", "newton")
"""Solvers of solve_local / solve_global: hybrid (the default: NLGS, then the conic fixed
point when NLGS stalls or is too slow, then NLGS again), nlgs (NLGS alone), conic (the De
Saxce fixed point with Clarabel alone: saxum.solver.conic), newton (semismooth Newton on the
Fischer-Burmeister function, saxum.solver.fischer, then NLGS from its iterate where it stops
at a stationary point of its merit that is not a solution)."""

_WINDOW = 200
"""NLGS sweeps between two measurements of the natural-map error (one product W r each)."""
_STALLED = STALLED
"""An error that falls by less than this fraction per sweep over a window (0.2 % over 200
sweeps) stalls; above it the error is still falling (the time stepper's threshold)."""
_RELAXED = 0.7
"""Relaxation the hybrid tries when NLGS stalls without relaxation (a cycling iterate)."""
_FIXED_POINTS = 40
"""Fixed-point iterations of the conic solver at most (each one interior-point solve)."""
_NEWTON_ITERATIONS = 100
"""Fischer-Burmeister Newton iterations at most (each one sparse LU; it stops earlier where
its merit stalls: saxum.solver.fischer)."""


@dataclass(frozen=True)
class SolveRow:
    """One solved problem: name, kind ("local"/"global"), contacts, spacedim, NLGS sweeps,
    wall time [s] (Delassus reduction, sweeps, error), natural-map error, solved
    (error <= tolerance), relaxation (the last NLGS ran with), r, u (and v for a global
    problem); solver: what ran, in order ("nlgs", "conic", "nlgs+conic+nlgs", ...);
    rate: the error's factor per sweep over NLGS's last window (nan if not measured);
    stalled: the error stopped falling (rate above 1 - 1e-5) rather than the sweeps running
    out; conic_iterations: fixed-point iterations of the conic solver (0 if it did not run);
    newton_iterations: Fischer-Burmeister Newton's iterations (0 if it did not run)."""

    name: str
    kind: str
    contacts: int
    spacedim: int
    iterations: int
    time: float
    error: float
    solved: bool
    tolerance: float
    relaxation: float
    r: np.ndarray
    u: np.ndarray
    v: np.ndarray | None = None
    solver: str = "nlgs"
    rate: float = math.nan
    stalled: bool = False
    conic_iterations: int = 0
    newton_iterations: int = 0


@dataclass
class _Run:
    """State of one solve: the iterate, its error, what ran, the last window's rate."""

    w: sp.csr_matrix
    q: np.ndarray
    mu: np.ndarray
    spacedim: int
    r: np.ndarray
    error: float
    sweeps: int = 0
    rate: float = math.nan
    steps: list = field(default_factory=list)
    conic_iterations: int = 0
    newton_iterations: int = 0

    def measure(self, r: np.ndarray) -> float:
        return natural_map_error(self.w, self.q, self.mu, r, self.spacedim)


def _sweep(run: _Run, tolerance: float, budget: int, relaxation: float,
           give_up: bool) -> bool:
    """NLGS from run.r in windows of _WINDOW sweeps until the natural-map error is <=
    tolerance, `budget` sweeps are done, or (give_up) the error stalls or falls too slowly to
    reach the tolerance within the budget at the last window's rate. Each window stops early
    on NLGS's own test (relative change of r per sweep), tightened 100-fold whenever it
    stopped a window above the tolerance. With give_up the iterate of least error is kept,
    else the last (NLGS alone follows its iterates, as the time stepper does). Returns True
    if it gave up (stalled or too slow), False if done or out of budget."""
    if not run.steps or run.steps[-1] != "nlgs":
        run.steps.append("nlgs")
    change_tolerance = tolerance
    used = 0
    best = run.error
    while run.error > tolerance and used < budget:
        window = min(_WINDOW, budget - used)
        report = DelassusNLGS(change_tolerance, window, relaxation).solve(
            run.w, run.q, run.mu, run.spacedim, run.r)
        used += report.iterations
        run.sweeps += report.iterations
        if report.error < run.error or not give_up:
            run.r, run.error = report.r, report.error
        if report.iterations < window:  # NLGS's own test stopped it
            if report.change == 0.0 or change_tolerance < 1e-16:
                return False
            change_tolerance *= 1e-2
            continue
        # the window ran in full: the error's factor per sweep over it
        run.rate = (min(report.error, best) / best) ** (1.0 / window) if best > 0.0 else 0.0
        best = min(best, report.error)
        if not give_up or run.error <= tolerance:
            continue
        if run.rate > 1.0 - _STALLED:
            return True
        if math.log(tolerance / run.error) / math.log(run.rate) > budget - used:
            return True
    return False


def _solve(w, q, mu, spacedim, r0, tolerance, max_iterations, relaxation, solver):
    """Solve u = W r + q to the natural-map error `tolerance` with `solver` (SOLVERS).

    nlgs: NLGS sweeps (_sweep, never giving up) with the given relaxation (None: 1).
    conic: saxum.solver.conic alone (at most _FIXED_POINTS fixed-point iterations).
    newton: Fischer-Burmeister Newton (at most _NEWTON_ITERATIONS iterations), then NLGS sweeps
    (never giving up) from its iterate where it ends above the tolerance: its merit has
    stationary points that are not solutions (the two Capsules problems stop there at 3.5e-7
    and 4.7e-7), from which NLGS converges in a few hundred sweeps.
    hybrid: NLGS with relaxation 1 (or the one given); when its error stalls, with relaxation
    _RELAXED (when none was given); when it stalls again or falls too slowly to reach the
    tolerance within max_iterations sweeps, the conic fixed point from NLGS's iterate, and
    NLGS again from its solution (the interior point ends near 1e-7 on degenerate problems).
    Returns (run, relaxation)."""
    r = np.zeros(q.size) if r0 is None else np.array(r0, dtype=np.float64)
    w = sp.csr_matrix(w, dtype=np.float64)
    run = _Run(w, np.asarray(q, dtype=np.float64), np.asarray(mu, dtype=np.float64), spacedim,
               r, 0.0)
    run.error = run.measure(r)
    omega = 1.0 if relaxation is None else relaxation
    if solver == "conic":
        _conic(run, tolerance)
        return run, omega
    if solver == "nlgs":
        _sweep(run, tolerance, max_iterations, omega, give_up=False)
        return run, omega
    if solver == "newton":
        run.steps.append("newton")
        result = fischer_burmeister_newton(run.w, run.q, run.mu, run.r, tolerance,
                                           _NEWTON_ITERATIONS, spacedim)
        run.newton_iterations = result.iterations
        if result.error < run.error:
            run.r, run.error = result.r, result.error
        if run.error > tolerance:
            _sweep(run, tolerance, max_iterations, omega, give_up=False)
        return run, omega
    gave_up = _sweep(run, tolerance, max_iterations, omega, give_up=True)
    if gave_up and relaxation is None and run.rate > 1.0 - _STALLED:
        omega = _RELAXED
        gave_up = _sweep(run, tolerance, max_iterations - run.sweeps, omega, give_up=True)
    if gave_up:
        _conic(run, tolerance)
        _sweep(run, tolerance, max_iterations - run.sweeps, omega, give_up=False)
    return run, omega


def _conic(run: _Run, tolerance: float) -> None:
    """The conic fixed point from run.r; keeps its result if its error is lower."""
    run.steps.append("conic")
    result = delassus_conic(run.w, run.q, run.mu, run.spacedim, run.r, tolerance,
                            _FIXED_POINTS)
    run.conic_iterations += result.iterations
    if result.error < run.error:
        run.r, run.error = result.r, result.error


def _row(run: _Run, problem, kind, name, start, tolerance, omega, v=None) -> SolveRow:
    stalled = bool(run.error > tolerance and run.rate > 1.0 - _STALLED)
    return SolveRow(name, kind, problem.contacts, problem.spacedim, run.sweeps,
                    time.perf_counter() - start, run.error, run.error <= tolerance, tolerance,
                    omega, run.r, run.w @ run.r + run.q, v, "+".join(run.steps), run.rate,
                    stalled, run.conic_iterations, run.newton_iterations)


def _check_solve_options(tolerance, max_iterations, solver="hybrid") -> None:
    if not (math.isfinite(tolerance) and tolerance > 0.0):
        raise InputError(f"tolerance must be > 0, got {tolerance}")
    if max_iterations < 1:
        raise InputError(f"max_iterations must be >= 1, got {max_iterations}")
    if solver not in SOLVERS:
        raise InputError(f"solver must be one of {', '.join(SOLVERS)}, got {solver!r}")


def solve_local(problem: LocalProblem, *, tolerance: float = 1e-8,
                max_iterations: int = 100_000, relaxation: float | None = None,
                r0: np.ndarray | None = None, name: str = "",
                solver: str = "hybrid") -> SolveRow:
    """Solve a local problem from r0 (zero if None) with `solver` (SOLVERS; see _solve) to
    the natural-map error `tolerance`, with at most max_iterations NLGS sweeps; relaxation:
    NLGS's omega (None: 1, and the hybrid's own choice when NLGS stalls)."""
    _check_solve_options(tolerance, max_iterations, solver)
    start = time.perf_counter()
    run, omega = _solve(problem.W, problem.q, problem.mu, problem.spacedim, r0, tolerance,
                        max_iterations, relaxation, solver)
    return _row(run, problem, "local", name, start, tolerance, omega)


def solve_global(problem: GlobalProblem, *, tolerance: float = 1e-8,
                 max_iterations: int = 100_000, relaxation: float | None = None,
                 r0: np.ndarray | None = None, name: str = "",
                 solver: str = "hybrid") -> SolveRow:
    """Solve a global problem through its Delassus form (GlobalProblem.delassus), as
    solve_local; the error is that of the Delassus form, v = M^-1 (H r + f)."""
    _check_solve_options(tolerance, max_iterations, solver)
    start = time.perf_counter()
    w, q = problem.delassus()
    run, omega = _solve(w, q, problem.mu, problem.spacedim, r0, tolerance, max_iterations,
                        relaxation, solver)
    v = spla.spsolve(sp.csc_matrix(problem.M), problem.H @ run.r + problem.f)
    return _row(run, problem, "global", name, start, tolerance, omega, np.atleast_1d(v))


def _warm_up() -> None:
    """Load (or compile) the NLGS kernels for spacedim 2 and 3 before anything is timed."""
    for dim in (2, 3):
        q = np.zeros(dim)
        q[0] = -1.0
        DelassusNLGS(max_iterations=2).solve(sp.identity(dim, format="csr"), q, np.ones(1),
                                             dim)


def solve_fclib_files(paths, *, tolerance: float = 1e-8, max_iterations: int = 100_000,
                      relaxation: float | None = None, solver: str = "hybrid",
                      on_error: Callable[[Path, InputError], None] | None = None
                      ) -> list[SolveRow]:
    """Read and solve each FCLIB file from zero impulses (what `saxum fclib solve` runs) with
    `solver` (SOLVERS). All files are read first. A bad file (an InputError naming it:
    unreadable, or a global problem whose M cannot be factorized) stops the call, or, given
    `on_error`, is passed to on_error(path, error) and left out while the others are solved."""
    _check_solve_options(tolerance, max_iterations, solver)
    if relaxation is not None and not 0.0 < relaxation <= 1.0:
        raise InputError(f"relaxation must be in (0, 1], got {relaxation}")
    problems, good = [], []
    for p in paths:
        try:
            problems.append((Path(p).name, read_fclib(p)))
            good.append(Path(p))
        except InputError as err:
            if on_error is None:
                raise
            on_error(Path(p), err)
    _warm_up()
    rows = []
    for (name, problem), path in zip(problems, good, strict=True):
        solve = solve_local if isinstance(problem, LocalProblem) else solve_global
        try:
            rows.append(solve(problem, tolerance=tolerance, max_iterations=max_iterations,
                              relaxation=relaxation, name=name, solver=solver))
        except InputError as err:  # a global problem whose M cannot be factorized
            if on_error is None:
                raise InputError(f"{path}: {err}") from None
            on_error(path, InputError(f"{path}: {err}"))
    return rows


def _ms(seconds: float) -> str:
    ms = seconds * 1e3
    return f"{ms:.3g}" if ms < 100.0 else f"{ms:.0f}"


def verdict(row: SolveRow) -> str:
    """yes (<= tolerance), or why not: the error stalls (stopped falling), ran out of sweeps
    while still falling (with its rate per sweep), or the conic solver's best."""
    if row.solved:
        return f"yes (<= {row.tolerance:.0e})"
    if row.stalled:
        return f"no: stalls at {row.error:.1e}"
    if math.isnan(row.rate):
        return f"no: {row.solver} ends at {row.error:.1e}"
    return (f"no: ran out of sweeps at {row.error:.1e} (error still falling, rate "
            f"{row.rate:.6f} per sweep)")


def format_table(rows: list[SolveRow]) -> str:
    """A Markdown table of solve results, one line per problem."""
    lines = ["| problem | kind | contacts | spacedim | solver | relaxation | sweeps | "
             "fixed points | Newton iterations | time [ms] | error | solved |",
             "|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---|"]
    for row in rows:
        lines.append(f"| {row.name} | {row.kind} | {row.contacts} | {row.spacedim} | "
                     f"{row.solver} | {row.relaxation:g} | {row.iterations} | "
                     f"{row.conic_iterations} | {row.newton_iterations} | {_ms(row.time)} | "
                     f"{row.error:.2e} | "
                     f"{verdict(row)} |")
    return "\n".join(lines)


# --- export of a saxum step -------------------------------------------------------------------


def step_problem(sim, state, kind: str = "local") -> LocalProblem | GlobalProblem:
    """The contact problem of the last step of `sim` (which advanced `state`), in FCLIB form.

    Active contacts only, in saxum's order; per contact a the rows of H* (sim.problem.h_cand,
    h_ant) in FCLIB order [n, t]. With M^-1 = diag(model.body_inv_mass), v_free the step's
    free velocity and b the law's shift of the normal velocity (problem.bias):
      local:  W = H* M^-1 H*^T,  q = H* v_free + b e_n;
      global: over the dofs with finite mass (the others, fixed or driven, have a known
              velocity v_free, which goes into w): M = diag(mass), H = H*_free^T,
              f = M v_free, w = H*_fixed v_fixed + b e_n.
    /solution holds the time stepper's impulses R (and the u, v they give); guesses[0] the
    impulses NLGS started from (warm start from the previous step's persisting contacts).
    """
    if kind not in ("local", "global"):
        raise InputError(f"kind must be 'local' or 'global', got {kind!r}")
    problem = sim.problem
    contacts = getattr(problem, "contacts", None)
    if contacts is None or state.contacts is not contacts:
        raise InputError("state is not the one that sim stepped last: export right after "
                         "sim.step(state)")
    if problem.joint_laws:
        raise InputError("the model has joint laws (elastic, viscous, cohesive), whose local "
                         "problems FCLIB's Signorini-Coulomb form does not hold; export a model "
                         "with dry laws only")
    model = sim.model
    dim = model.dim
    v_free = sim.free_velocity.ravel()  # the last step's free velocity
    local = assemble_local(problem, sim.free_velocity)
    active = local.active
    if active.size == 0:
        raise InputError(f"step {state.step} has no active contact: nothing to export")
    nc = active.size
    hstar = local.hstar
    inv_mass = model.body_inv_mass.ravel()
    shift = np.zeros((nc, dim))
    shift[:, 0] = problem.bias[active]
    shift = shift.ravel()
    mu = local.mu
    r = local.impulses(contacts.impulse)
    warm = contacts.copy()
    warm.warm_start_from(sim.previous_contacts)  # the warm start the step's solve began from
    r_start = local.impulses(warm.impulse)
    log = sim.log
    info = Info(
        title=f"saxum step {state.step}",
        description=(f"saxum {model.dim}D rigid blocks, Moreau-Jean dt = "
                     f"{sim.integrator.dt:g} s, theta = {sim.integrator.theta:g}; "
                     f"{model.body_count} bodies, {nc} active contacts at t = "
                     f"{state.time:g} s; solution: the time stepper's impulses (NLGS "
                     f"{log.iterations[-1]} sweeps, error {log.error[-1]:.3g}, converged "
                     f"{bool(log.converged[-1])}); guess 1: its warm start"),
        math_info=("SI units: impulses [N s], velocities [m/s, rad/s]; per contact [n, t"
                   + (", s" if dim == 3 else "") + "]; u_n includes the law's shift b_n"),
    )
    if kind == "local":
        w, q = local.w, local.q
        return LocalProblem(w, q, mu, dim, info=info,
                            guesses=[Solution(u=w @ r_start + q, r=r_start)],
                            solution=Solution(u=w @ r + q, r=r))
    free = inv_mass > 0.0
    h = hstar[:, free].T.tocsr()
    m = sp.diags(1.0 / inv_mass[free]).tocsr()
    f = m @ v_free[free]
    w_vec = hstar[:, ~free] @ v_free[~free] + shift

    def solution(rr):
        v = v_free[free] + inv_mass[free] * (h @ rr)
        return Solution(u=h.T @ v + w_vec, r=rr, v=v)

    return GlobalProblem(m, h, f, w_vec, mu, dim, info=info, guesses=[solution(r_start)],
                         solution=solution(r))


def export_step(sim, state, path: str | Path, *, kind: str = "local",
                storage: str = "csr") -> LocalProblem | GlobalProblem:
    """Write the last step's contact problem (step_problem) to an FCLIB file; returns it."""
    problem = step_problem(sim, state, kind)
    write_fclib(path, problem, storage)
    return problem
