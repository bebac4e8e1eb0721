"""Seismic ensembles: a scenario run through a set of ground-motion records at many scales,
as tasks of a Dask cluster, into one HDF5 file that grows as the runs finish.

Each run is the scenario with its `[loads.ground_motion]` source replaced by the record,
scaled (that table's application, direction, trimming and baseline correction are kept; with
no such table the record acts as inertial forces along x), lasting the record plus
`after` seconds, and ended early once a free block has moved by `stop` x the smallest free
block's size. Its demand: the peak displacement, horizontal displacement, drift (horizontal
displacement over the height above the base of the structure, the lowest point of its free
blocks) and rotation of the chosen blocks over the output frames, the displacement at the
end, and the collapse (saxum.collapse.find_collapse: a free block moved by more than half
the smallest free block's size and did not come back) with its time and the mechanism when
the collapsing motion began.

Multiple-stripe analysis (MSA) runs every record at every scale. Incremental dynamic
analysis (IDA; Vamvatsikos & Cornell 2002, Earthquake Engng Struct. Dyn. 31(3)) runs each
record's stripes in increasing order up to its first collapse, then bisects between the
last scale at which it stood and the first at which it collapsed until their gap is below
`tolerance` times the latter (a structure that would stand again at a larger scale is not
looked for).

Only the client process writes the file, a row per finished run, flushed; rerunning the
same ensemble into the same file skips the runs it holds. A run that fails is a row with
its error; a worker that dies has its tasks run again by the Dask scheduler (a task is
retried up to distributed.scheduler.allowed-failures times), and a run's row is written
once, when its task's result reaches the client.
"""

from __future__ import annotations

import logging
import math
import os
import socket
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import h5py
import numba as nb
import numpy as np
from tqdm import tqdm

from ._version import __version__
from .errors import InputError
from .ground import G_STANDARD, GroundMotion, read_at2, read_csv
from .scenario import EnsembleSpec, GroundMotionSpec, Scenario

__all__ = ["COLUMNS", "Ensemble", "EnsembleRecord", "EnsembleSummary", "connect", "describe",
           "ensemble_records", "read_ensemble", "run_ensemble"]

KIND = "saxum ensemble"
"""The `kind` attribute of an ensemble file (saxum plot tells it from a run's results)."""
CONNECT_TIMEOUT = 5.0
"""[s]: a scheduler that does not answer within this is an error."""

COLUMNS = {"record": ("i4", ""), "scale": ("f8", ""), "factor": ("f8", ""),
           "collapsed": ("i1", ""), "collapse_time": ("f8", "s"), "onset_time": ("f8", "s"),
           "peak_displacement": ("f8", "m"), "peak_horizontal": ("f8", "m"),
           "peak_drift": ("f8", ""), "peak_rotation": ("f8", "rad"),
           "residual_displacement": ("f8", "m"), "block": ("str", ""),
           "mechanism": ("str", ""), "error": ("str", ""), "non_converged": ("i4", ""),
           "steps": ("i8", ""), "duration": ("f8", "s"), "wall_time": ("f8", "s"),
           "worker": ("str", "")}
"""The columns of an ensemble file's runs (group "runs"), dtype and unit: the record's
index, the scale (the intensity: a factor, or a PGA in g with measure "pga"), the factor on
the record, collapsed (1, 0, or -1 for a run that failed), the times of collapse and of the
start of the collapsing motion, the demand (module doc) and the block of the peak
displacement, the mechanism (text), the error of a failed run, steps that did not converge,
steps, simulated time, wall time and the worker's host."""


@dataclass(frozen=True)
class EnsembleRecord:
    """A record of an ensemble: name, where it came from (a file or a FEMA P695 component),
    the motion (None when it could not be read) and the reason."""

    name: str
    source: str
    motion: GroundMotion | None
    error: str = ""

    @property
    def pga(self) -> float:
        """Peak horizontal ground acceleration [m/s^2], of either component of a pair (nan
        for an unread record)."""
        if self.motion is None:
            return math.nan
        return float(np.abs(self.motion.acceleration[:, :-1]).max())


def ensemble_records(source: str, *, normalized: bool = False, units: str | None = None,
                     pairs: bool = False) -> list[EnsembleRecord]:
    """The records of `source`: a FEMA P695 set ("far-field", "near-field", ...: every
    horizontal component; `normalized`: times the set's normalization factor; `pairs`:
    instead, every record's two components together, a motion of two columns (a, b)) or a
    folder whose .AT2 and .csv files are the records (`units` for CSV files that do not state
    theirs). A file that cannot be read is a record with its error (file and line), not an
    exception: the others go on."""
    from .records import SETS, fema_p695_records, read_fema_p695

    if source in SETS:
        infos = fema_p695_records(source)
        motions = [read_fema_p695(i.id, set=i.set, component=i.component,
                                  normalized=normalized) for i in infos]
        if not pairs:
            return [EnsembleRecord(i.title, f"{i.set} {i.id}{i.component}", m)
                    for i, m in zip(infos, motions, strict=True)]
        out = []
        for k in range(0, len(infos), 2):  # (by ID, then component: a, b)
            a, b = infos[k], infos[k + 1]
            t = np.union1d(motions[k].time, motions[k + 1].time)
            acc = [np.interp(t, m.time, m.acceleration[:, 0], left=0.0, right=0.0)
                   for m in motions[k:k + 2]]  # (zero where one of them has ended)
            name = (f"FEMA P695 {a.set} {a.id}: {a.earthquake} {a.year}, {a.station} "
                    f"({a.component_name} + {b.component_name})")
            out.append(EnsembleRecord(name, f"{a.set} {a.id}ab", GroundMotion(
                t, np.column_stack((*acc, np.zeros_like(t))), name)))
        return out
    if pairs:
        raise InputError(f"records {source!r}: a scenario with two horizontal components "
                         "(loads.ground_motion.second) runs the pairs of a FEMA P695 set "
                         f"({', '.join(SETS)}); a folder's records are single components")
    folder = Path(source)
    if not folder.is_dir():
        raise InputError(f"records {source!r}: neither a record set ({', '.join(SETS)}) nor "
                         "a folder")
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in (".at2", ".csv"))
    if not files:
        raise InputError(f"records {source!r}: no .AT2 or .csv file in this folder")
    out = []
    for path in files:
        try:
            motion = (read_at2(path) if path.suffix.lower() == ".at2"
                      else read_csv(path, units=units))
        except InputError as err:
            out.append(EnsembleRecord(path.stem, str(path), None, str(err)))
        else:
            out.append(EnsembleRecord(path.stem, str(path), motion))
    return out


class _Frames:
    """A run's output frames kept in memory, read as saxum.results.Results is by
    find_collapse and frame_mechanism (writing a results file costs more than the steps of a
    small model)."""

    def __init__(self, model, dt: float) -> None:
        self.model = {name: getattr(model, name) for name in (
            "body_kind", "body_q0", "body_vertex_start", "vertex_local", "law_kind")}
        self.body_size, self.body_radius = model.body_size, model.body_radius
        self.body_name, self.dim, self.dt = model.body_name, model.dim, dt
        self._q, self._v, self._t, self._step, self._contacts = [], [], [], [], []

    def add(self, state) -> None:
        c = state.contacts
        self._q.append(state.body_q.copy())
        self._v.append(state.body_v.copy())
        self._t.append(state.time)
        self._step.append(state.step)
        self._contacts.append({k: getattr(c, k)[: c.count].copy() for k in c._fields()})

    def done(self) -> None:
        """Stack the frames into arrays (body_q, body_v [frame, body, :], time, step)."""
        self.body_q, self.body_v = np.array(self._q), np.array(self._v)
        self.time, self.step = np.array(self._t), np.array(self._step)
        self.frame_count = len(self._t)

    def contacts(self, frame: int) -> dict:
        return self._contacts[frame]


def _demand(frames: _Frames, model, blocks: np.ndarray) -> dict:
    """The demand of a run (module doc) from its frames."""
    from .collapse import find_collapse
    from .mechanism import frame_mechanism
    from .model import BodyKind

    d = model.dim
    q0 = model.body_q0
    q = frames.body_q[:, blocks]
    u = q[:, :, :d] - q0[blocks, :d]
    moved = np.linalg.norm(u, axis=-1)
    horizontal = np.linalg.norm(u[:, :, :d - 1], axis=-1)
    if d == 2:
        rotation = np.abs(q[:, :, 2] - q0[blocks, 2])
    else:  # the angle of the relative rotation of two unit quaternions
        dots = np.abs(np.einsum("fbk,bk->fb", q[:, :, 3:7], q0[blocks, 3:7]))
        rotation = 2.0 * np.arccos(np.minimum(dots, 1.0))
    free = np.flatnonzero(model.body_kind == BodyKind.FREE)
    lowest = min(float(model.vertices(b)[:, d - 1].min()) for b in free)
    height = q0[blocks, d - 1] - lowest
    drift = np.where(height > 0.0, horizontal / np.where(height > 0.0, height, 1.0), 0.0)
    peak = np.unravel_index(int(np.argmax(moved)), moved.shape)
    event = find_collapse(frames)
    row = {"peak_displacement": float(moved.max()), "peak_horizontal": float(horizontal.max()),
           "peak_drift": float(drift.max()), "peak_rotation": float(rotation.max()),
           "residual_displacement": float(moved[-1].max()),
           "block": model.body_name[int(blocks[peak[1]])],
           "collapsed": int(event is not None), "collapse_time": math.nan,
           "onset_time": math.nan, "mechanism": ""}
    if event is not None:
        row.update(collapse_time=event.time, onset_time=float(frames.time[event.onset_frame]),
                   mechanism=frame_mechanism(frames, event.onset_frame).text())
    return row


def _run_one(task: dict) -> dict:
    """One run on a worker: the scenario (JSON) with the record (time [s], horizontal
    acceleration [m/s^2]: one column, or a pair for a scenario with a second component)
    times `factor`; returns its row of COLUMNS (a failed run: its error). The record goes
    through CSV files in a temporary folder, as a user's would."""
    row = {"record": task["record"], "scale": task["scale"], "factor": task["factor"],
           "worker": socket.gethostname()}
    start = time.perf_counter()
    try:
        scenario = Scenario.model_validate_json(task["scenario"])
        dim = scenario.structure.dim
        with tempfile.TemporaryDirectory(prefix="saxum-ensemble-") as tmp:
            first = Path(tmp) / "a.csv"
            template = scenario.loads.ground_motion or GroundMotionSpec(file=first)
            acc = np.asarray(task["acceleration"]).reshape(len(task["time"]), -1)
            ground = _component(template, task["time"], acc[:, 0], first, task["factor"], dim)
            if template.second is not None:
                ground = ground.model_copy(update={"second": _component(
                    template.second, task["time"], acc[:, 1], Path(tmp) / "b.csv",
                    task["factor"] * template.second.scale, dim)})
            scenario = scenario.model_copy(update={
                "loads": scenario.loads.model_copy(update={"ground_motion": ground})})
            duration = float(ground.motion(dim).time[-1]) + task["after"]
            model = scenario.build_model()
        if scenario.solver.threads is None:
            # a worker per core: one thread each (the same results: solver.threads)
            scenario = scenario.model_copy(update={
                "solver": scenario.solver.model_copy(update={"threads": 1})})
        sim = scenario.build_simulation(model)
        row.update(_advance(sim, model, duration, scenario.output.interval, task))
    except Exception as err:  # noqa: BLE001 - a failed run is a row with its error
        row.update(collapsed=-1, error=f"{type(err).__name__}: {err}")
    row["wall_time"] = time.perf_counter() - start
    return row


def _component(template: GroundMotionSpec, time: np.ndarray, acceleration: np.ndarray,
               csv: Path, factor: float, dim: int) -> GroundMotionSpec:
    """`template` (a ground motion table) with its source replaced by the record (time [s],
    acceleration [m/s^2]) written to `csv` and its scale by `factor`; in 3D along the
    template's `direction` where it gives one (else the CSV's horizontal at its azimuth)."""
    columns = [acceleration]
    if dim == 3 and template.direction is not None:
        d = np.asarray(template.direction, dtype=float)
        columns = [acceleration * c for c in d / np.linalg.norm(d)]
    np.savetxt(csv, np.column_stack((time, *columns)), delimiter=",", fmt="%.17g",
               header="units: m/s^2")
    return template.model_copy(update={"file": csv, "fema_p695": None, "pulse": None,
                                       "units": "m/s^2", "scale": factor})


def _advance(sim, model, duration: float, interval: float, task: dict) -> dict:
    """Step `sim` from rest for `duration` [s] (or until a free block has moved by
    task["stop"] x the smallest free block's size), keeping a frame every `interval` [s];
    the run's demand and solver figures."""
    dim = model.dim
    dt = sim.integrator.dt
    free = np.flatnonzero(model.body_kind == 0)
    reach = task["stop"] * float(model.body_size[free].min())
    every = max(1, round(interval / dt))
    total = round(duration / dt)
    state = sim.initial_state()
    frames = _Frames(model, dt)
    frames.add(state)
    while state.step < total:
        sim.step(state)
        far = _moved_beyond(state.body_q, model.body_q0, free, dim, reach)
        if state.step % every == 0 or far or state.step == total:
            frames.add(state)
        if far:
            break
    frames.done()
    row = _demand(frames, model, np.asarray(task["blocks"], dtype=np.int64))
    row.update(non_converged=int(np.count_nonzero(~sim.log.converged)), steps=state.step,
               duration=state.time)
    return row


@nb.njit(cache=True)
def _moved_beyond(q, q0, bodies, dim, reach):
    """Whether one of `bodies` has moved by more than `reach` [m]: |x - x0| > reach, x its
    first `dim` coordinates (one compiled call per step: numpy's norm of a few rows costs
    more than the step of a small model)."""
    for b in bodies:
        s = 0.0
        for d in range(dim):
            e = q[b, d] - q0[b, d]
            s += e * e
        if np.sqrt(s) > reach:
            return True
    return False


def _defaults(row: dict) -> dict:
    """The row with every column, missing ones nan, 0 or ""."""
    blank = {"f8": math.nan, "str": ""}
    return {name: row.get(name, blank.get(dtype, 0)) for name, (dtype, _) in COLUMNS.items()}


class _Store:
    """The ensemble file, written by the client only: attributes that say which ensemble it
    is, the records, and the runs' rows, each flushed once appended."""

    def __init__(self, path: Path, meta: dict, records: list[EnsembleRecord],
                 overwrite: bool) -> None:
        self.path = path
        if path.exists() and not overwrite:
            self.file = _open_ensemble(path, "r+")
            held = {k: self.file.attrs[k] for k in meta if k in self.file.attrs}
            names = [n.decode() if isinstance(n, bytes) else n
                     for n in self.file["records/name"][()]]
            if held != meta or names != [r.name for r in records]:
                differ = sorted(k for k in meta if held.get(k) != meta[k])
                self.file.close()
                raise InputError(f"{path} holds another ensemble (its "
                                 f"{', '.join(differ) or 'records'} differ); give another "
                                 "-o, or --overwrite to replace it")
        else:
            self.file = h5py.File(path, "w")
            self.file.attrs.update(meta)
            self.file.attrs["kind"] = KIND
            self.file.attrs["version"] = __version__
            g = self.file.create_group("records")
            text = h5py.string_dtype()
            g["name"] = np.array([r.name for r in records], dtype=object).astype(text)
            g["source"] = np.array([r.source for r in records], dtype=object).astype(text)
            g["error"] = np.array([r.error for r in records], dtype=object).astype(text)
            g["pga"] = np.array([r.pga for r in records])
            g["pga"].attrs["units"] = "m/s^2"
            runs = self.file.create_group("runs")
            for name, (dtype, units) in COLUMNS.items():
                ds = runs.create_dataset(name, shape=(0,), maxshape=(None,), chunks=(256,),
                                         dtype=text if dtype == "str" else dtype)
                ds.attrs["units"] = units
            self.file.flush()
        runs = self.file["runs"]
        # (a client killed while writing a row leaves some columns one longer: cut them)
        rows = min(runs[name].shape[0] for name in COLUMNS)
        for name in COLUMNS:
            runs[name].resize((rows,))
        self.done = {(int(r), float(s)): int(c) for r, s, c in zip(
            runs["record"][()], runs["scale"][()], runs["collapsed"][()], strict=True)}

    def append(self, row: dict) -> bool:
        """Write the run's row (unless the file holds it already); False if it did."""
        key = (int(row["record"]), float(row["scale"]))
        if key in self.done:
            return False
        runs = self.file["runs"]
        n = runs["record"].shape[0]
        for name, value in _defaults(row).items():
            runs[name].resize((n + 1,))
            runs[name][n] = value
        self.file.flush()
        self.done[key] = int(row["collapsed"])
        return True

    def close(self) -> None:
        self.file.close()


def _open_ensemble(path: Path, mode: str = "r") -> h5py.File:
    try:
        f = h5py.File(path, mode)
    except OSError as err:
        raise InputError(f"{path}: not an ensemble file that can be opened ({err})") from None
    if f.attrs.get("kind") != KIND:
        f.close()
        raise InputError(f"{path} is not an ensemble file of saxum ensemble (a run's results "
                         "file? saxum info)")
    return f


class _Ida:
    """A record's incremental dynamic analysis (module doc): which scale to run next."""

    def __init__(self, stripes: list[float], tolerance: float) -> None:
        self.stripes, self.tolerance = stripes, tolerance
        self.k = 0
        self.stands = 0.0
        self.collapses: float | None = None
        self.failed = False

    def next(self) -> float | None:
        """The next scale to run, or None when done."""
        if self.failed:
            return None
        if self.collapses is None:
            return self.stripes[self.k] if self.k < len(self.stripes) else None
        if self.collapses - self.stands <= self.tolerance * self.collapses:
            return None
        return 0.5 * (self.stands + self.collapses)

    def tell(self, scale: float, collapsed: int) -> None:
        """The verdict at `scale` (1 collapsed, 0 stood, -1 failed: the record stops)."""
        if collapsed < 0:
            self.failed = True
        elif self.collapses is None:
            if collapsed:
                self.collapses = scale
            else:
                self.stands = scale
                self.k += 1
        elif collapsed:
            self.collapses = scale
        else:
            self.stands = scale


@dataclass(frozen=True)
class EnsembleSummary:
    """What an ensemble did: its file, the runs it holds, the runs this call made, those
    that failed, the records left out (name and why), and whether it was interrupted."""

    path: Path
    runs: int
    new_runs: int
    failed: int
    bad_records: tuple[tuple[str, str], ...]
    interrupted: bool = False
    wall_time: float = 0.0


def connect(scheduler: str | None = None, workers: int | None = None, *,
            processes: bool = True):
    """A dask.distributed Client: of the scheduler at `scheduler` ("tcp://host:8786"; one
    that does not answer within CONNECT_TIMEOUT is an InputError), or of a new local cluster
    of `workers` (default: one per core) single-threaded worker processes (`processes`
    False: threads of this process)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise InputError("ensembles run on Dask: pip install 'saxum[ensemble]' (or "
                         "pip install 'dask[distributed]')") from None
    if scheduler is not None:
        try:
            return Client(scheduler, timeout=f"{CONNECT_TIMEOUT}s")
        except (OSError, TimeoutError, ValueError) as err:
            raise InputError(f"scheduler {scheduler}: no Dask scheduler answers there within "
                             f"{CONNECT_TIMEOUT:g} s ({type(err).__name__}: {err}); start one "
                             "(dask scheduler, then dask worker ADDRESS on each machine) or "
                             "leave out --scheduler for a local cluster") from None
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                           processes=processes, dashboard_address=None,
                           silence_logs=logging.ERROR)
    return Client(cluster)


def run_ensemble(scenario: Scenario, output: str | Path, *,
                 records: list[EnsembleRecord] | None = None, client=None,
                 scheduler: str | None = None, workers: int | None = None,
                 processes: bool = True, quiet: bool = False, overwrite: bool = False,
                 scenario_text: str = "",
                 on_row: Callable[[dict], None] | None = None) -> EnsembleSummary:
    """Run the ensemble of `scenario.ensemble` (saxum.scenario.EnsembleSpec) into the file
    `output` (module doc), on `client` (a dask.distributed Client), else on one made by
    connect(scheduler, workers, processes=processes) and closed at the end. `records`:
    instead of the spec's source. `on_row(row)`: called with each run's row once written.
    An existing `output` of the same ensemble is resumed; of another, an InputError unless
    `overwrite`."""
    spec: EnsembleSpec | None = scenario.ensemble
    if spec is None:
        raise InputError("the scenario has no [ensemble] table (docs/ensemble.md): give "
                         "records and scales")
    if records is None:
        pairs = (scenario.loads.ground_motion is not None
                 and scenario.loads.ground_motion.second is not None)
        records = ensemble_records(spec.records, normalized=spec.normalized, units=spec.units,
                                   pairs=pairs)
    if not records:
        raise InputError("the ensemble has no records")
    model = scenario.model_copy(update={"ensemble": None}).build_model()
    blocks = _blocks(model, spec.blocks)
    bare = scenario.model_copy(update={"ensemble": None}).model_dump_json()
    meta = {"scenario_json": bare, "spec_json": spec.model_dump_json()}
    started = time.perf_counter()
    own = client is None
    if own:  # (before the file: a scheduler that does not answer leaves none behind)
        client = connect(scheduler, workers, processes=processes)
    store = None
    good = [k for k, r in enumerate(records) if r.motion is not None]
    new = failed = 0
    interrupted = False
    try:
        store = _Store(Path(output), meta, records, overwrite)
        if scenario_text:
            store.file.attrs["scenario"] = scenario_text

        def task(k: int, scale: float) -> dict:
            motion = records[k].motion
            factor = (scale * G_STANDARD / records[k].pga if spec.measure == "pga"
                      else scale)
            return {"scenario": bare, "record": k, "scale": scale, "factor": factor,
                    "time": motion.time, "acceleration": motion.acceleration[:, :-1],
                    "after": spec.after, "stop": spec.stop, "blocks": blocks}

        new, failed, interrupted = _schedule(client, store, spec, good, task, quiet, on_row)
    finally:
        if own:
            cluster = client.cluster
            client.close()
            if cluster is not None:
                cluster.close()
        if store is not None:
            runs = len(store.done)
            store.close()
    return EnsembleSummary(Path(output), runs, new, failed,
                           tuple((r.name, r.error) for r in records if r.motion is None),
                           interrupted, time.perf_counter() - started)


def _blocks(model, names: list[str]) -> list[int]:
    """Indices of the blocks `names` (default: every free block); an unknown one is an
    InputError listing the free blocks."""
    free = [b for b in range(model.body_count) if model.body_kind[b] == 0]
    if not names:
        return free
    out = []
    for name in names:
        if name not in model.body_name or model.body_name.index(name) not in free:
            listing = ", ".join(repr(model.body_name[b]) for b in free)
            raise InputError(f"ensemble.blocks: no free block {name!r}; the free blocks: "
                             f"{listing}")
        out.append(model.body_name.index(name))
    return out


def _schedule(client, store: _Store, spec: EnsembleSpec, good: list[int], task, quiet: bool,
              on_row) -> tuple[int, int, bool]:
    """Submit the runs not in `store`, write their rows as they finish; (runs made, failed,
    interrupted by Ctrl-C)."""
    from distributed import as_completed

    scales = list(spec.scales)
    pending = {}
    iterator = as_completed()
    bar = tqdm(total=0, disable=quiet, unit="run", desc="ensemble", dynamic_ncols=True)
    new = failed = 0

    def submit(k: int, scale: float) -> None:
        future = client.submit(_run_one, task(k, scale), pure=False)
        pending[future] = (k, scale)
        iterator.add(future)
        bar.total += 1
        bar.refresh()

    if spec.ida:
        idas = {k: _Ida(scales, spec.tolerance) for k in good}

        def advance(k: int) -> None:
            ida = idas[k]
            while (scale := ida.next()) is not None and (k, scale) in store.done:
                ida.tell(scale, store.done[(k, scale)])
            if scale is not None:
                submit(k, scale)

        for k in good:
            advance(k)
    else:
        for k in good:
            for scale in scales:
                if (k, scale) not in store.done:
                    submit(k, scale)
    try:
        for future in iterator:
            k, scale = pending.pop(future)
            try:
                row = future.result()
            except Exception as err:  # noqa: BLE001 - a task lost for good (KilledWorker)
                row = {"record": k, "scale": scale, "collapsed": -1,
                       "error": f"{type(err).__name__}: {err}"}
            if store.append(row):
                new += 1
                failed += row["collapsed"] < 0
                if on_row is not None:
                    on_row(row)
            bar.update(1)
            if spec.ida:
                idas[k].tell(scale, int(row["collapsed"]))
                advance(k)
    except KeyboardInterrupt:
        for future in pending:
            future.cancel()
        return new, failed, True
    finally:
        bar.close()
    return new, failed, False


@dataclass(frozen=True)
class Ensemble:
    """An ensemble file read back: the records' names, sources, PGA [m/s^2] and errors; the
    runs (COLUMNS -> array); the settings (saxum.scenario.EnsembleSpec) and the scenario
    (JSON)."""

    path: Path
    record_names: list[str]
    record_sources: list[str]
    record_pga: np.ndarray
    record_errors: list[str]
    runs: dict[str, np.ndarray]
    spec: EnsembleSpec
    scenario_json: str

    def failed(self, edp: str | None = None, threshold: float | None = None) -> np.ndarray:
        """Per run: collapsed, or (with `edp`, a demand column, and `threshold` in its unit)
        its demand above the threshold or collapsed; a run that failed to run is neither."""
        col = self.runs["collapsed"]
        if edp is None:
            return col == 1
        if edp not in COLUMNS or COLUMNS[edp][0] != "f8" or not edp.startswith(("peak",
                                                                                "residual")):
            names = ", ".join(k for k in COLUMNS if k.startswith(("peak", "residual")))
            raise InputError(f"no demand {edp!r}; the demands: {names}")
        return (col == 1) | ((col == 0) & (self.runs[edp] > threshold))

    def capacities(self, failed: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Per record, the smallest scale at which it failed (`failed`: per run, default
        collapsed) and the largest scale below it at which it did not (0 if none): its IDA
        bracket (nan, and the largest scale run, where it never failed)."""
        failed = self.failed() if failed is None else failed
        n = len(self.record_names)
        stands, fails = np.zeros(n), np.full(n, math.nan)
        rec, scale = self.runs["record"], self.runs["scale"]
        ran = self.runs["collapsed"] >= 0
        for k in range(n):
            down = scale[(rec == k) & failed]
            if down.size:
                fails[k] = down.min()
            up = scale[(rec == k) & ran & ~failed & (scale < (fails[k] if down.size
                                                               else math.inf))]
            stands[k] = up.max() if up.size else 0.0
        return stands, fails

    def fragility(self, edp: str | None = None, threshold: float | None = None):
        """The lognormal fragility (saxum.fragility) of collapse, or of `edp` above
        `threshold`: from the capacities (IDA: the midpoints of their brackets) or from the
        stripes (MSA: failures of the runs at each scale)."""
        from .fragility import fit_capacities, fit_stripes

        failed = self.failed(edp, threshold)
        if self.spec.ida:
            stands, fails = self.capacities(failed)
            read = [k for k, e in enumerate(self.record_errors) if not e]
            return fit_capacities(0.5 * (stands + fails)[read], max(self.spec.scales))
        ran = self.runs["collapsed"] >= 0
        scales = np.unique(self.runs["scale"][ran])
        runs = [int(np.count_nonzero(ran & (self.runs["scale"] == s))) for s in scales]
        fails = [int(np.count_nonzero(failed & (self.runs["scale"] == s))) for s in scales]
        return fit_stripes(scales, runs, fails)


def read_ensemble(path: str | Path) -> Ensemble:
    """Read an ensemble file (also one that is being written, up to its last row)."""
    path = Path(path)
    with _open_ensemble(path) as f:
        def strings(ds) -> list[str]:
            return [x.decode() if isinstance(x, bytes) else str(x) for x in ds[()]]

        runs = {name: (strings(f["runs"][name]) if dtype == "str" else f["runs"][name][()])
                for name, (dtype, _) in COLUMNS.items()}
        n = min(len(v) for v in runs.values())  # (a row being written: not all columns yet)
        runs = {k: (v[:n] if isinstance(v, np.ndarray) else np.array(v[:n], dtype=object))
                for k, v in runs.items()}
        spec = EnsembleSpec.model_validate_json(f.attrs["spec_json"])
        return Ensemble(path, strings(f["records/name"]), strings(f["records/source"]),
                        f["records/pga"][()], strings(f["records/error"]), runs, spec,
                        str(f.attrs["scenario_json"]))


def describe(summary: EnsembleSummary) -> str:
    """A line for the user: what the ensemble did and where its file is."""
    text = (f"{'interrupted' if summary.interrupted else 'finished'}: {summary.runs} runs in "
            f"{summary.path} ({summary.new_runs} made now in {summary.wall_time:.1f} s"
            + (f", {summary.failed} failed: their errors are in the file" if summary.failed
               else "") + ")")
    if summary.interrupted:
        text += "\nresume: run the same command again (finished runs are not redone)"
    return text
