"""Results on disk: one HDF5 file per run, written as the run goes, readable after a crash.

Layout (every dataset carries a `units` attribute; arrays grow along their first axis):

    /                      attrs: format = "saxum-results", format_version, saxum_version, dim,
                           dof, dt [s], theta [-]
    /scenario              the scenario's TOML text ("" for a run built in Python)
    /scenario_json         the validated scenario (saxum.scenario.Scenario) as JSON, overrides
                           applied and paths resolved: what `saxum resume` rebuilds the run from
    /model/...             body_name, body_kind, body_group, group_names, body_mass [kg/m],
                           body_inertia [kg m^2/m], body_q0, body_vertex_start, vertex_local [m],
                           law_kind, law_friction, law_restitution, law_parameter (SI units,
                           columns saxum.laws.Parameter), law_initial_gap (the _g0 laws),
                           group_law, gravity [m/s^2];
                           3D also body_face_start, face_vertex_start, face_vertex (faces);
                           with discs (spheres) body_shape, body_round_radius [m];
                           with clusters contactor_vertex_start (each part's vertices)
    /frames/...            one row per output time: time [s], step, body_q, body_v,
                           contact_count; the contacts of all frames one after the other in
                           /frames/contacts/{candidate, antagonist, key, law, point, frame, gap,
                           impulse, area [m^2/m; 3D: m^2] (saxum.contacts.Contacts.area),
                           slip [m], damage [-], history [-], crush [m] (the joint laws'
                           state),
                           initial_gap [m] (the _g0 laws' g0, saxum.laws)}
    /steps/...             one row per time step: the StepReport fields (saxum.steplog)
    /histories/...         one row per time step for the chosen blocks (attrs body: their
                           indices): time [s], step, body_q, body_v (shape [steps, blocks, 3])
                           and, under a ground motion, ground_acceleration [m/s^2]
    /checkpoints/...       one row per checkpoint: everything a bit-identical restart needs
                           (state, contacts with impulses, broad-phase pair list, the
                           solver's state: its refinement flags, _SOLVER_FIELDS, and the
                           rest packed in solver_state, _SOLVER_STATE)
    /run/status            0 running, 1 finished, 2 interrupted, 3 failed; /run/message

The file is opened in HDF5's single-writer/multiple-reader (SWMR) mode: every object exists
before the first step, rows are appended and flushed, so a run killed at any moment (even by
SIGKILL) leaves a file that reads consistently up to its last flush. Rows are committed in an
order that makes the index datasets (frames/time, checkpoints/step) the last written, and the
reader trusts only rows that every dataset of a group has.

Files that must not lie (format 2):
- one writer at a time: a writer holds an exclusive lock (flock) on the hidden file
  `.NAME.lock` next to NAME while it writes; a second writer gets an InputError, and a file
  that says "running" while nobody holds its lock was left by a killed or crashed run
  ("interrupted": `saxum resume` continues it).
- every row of frames, steps, histories and checkpoints carries a CRC-32 (zlib) of its values
  (the row's contacts and pair list included) in the group's `checksum` dataset, written
  before the index dataset. The reader keeps the rows up to the first whose checksum does not
  match, and says what it dropped (Results.damage).
- a file shorter than the end-of-file address in its HDF5 superblock (a copy cut short, a full
  disk) is truncated: it is read through an image padded with zeros (HDF5 then reports lost
  metadata at once instead of retrying as an SWMR reader does), and the checksums drop the
  rows whose data were lost.
- a file damaged while its writer still runs is read as an SWMR reader that gives up after
  _SWMR_READ_ATTEMPTS reads of a metadata entry whose checksum fails (0.07 s), not
  HDF5's 100 (hours), so that no reader hangs.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import io
import os
import struct
import warnings
import zlib
from dataclasses import fields
from pathlib import Path

import h5py
import numpy as np

from .errors import InputError, ResultsDamageWarning, ResultsWriteError
from .geometry2d import polygon_properties
from .steplog import STEP_DTYPES, StepReport

try:
    import fcntl
except ImportError:  # Windows: no advisory locks; one writer per file is then up to the user
    fcntl = None

__all__ = ["Results", "ResultsWriter", "STATUS", "writer_pid"]

FORMAT = "saxum-results"
FORMAT_VERSION = 2
STATUS = {0: "running", 1: "finished", 2: "interrupted", 3: "failed"}

_CONTACT_FIELDS = {
    # name: (dtype, trailing shape as a function of dim, units)
    "candidate": (np.int32, lambda d: (), "-"),
    "antagonist": (np.int32, lambda d: (), "-"),
    "key": (np.int64, lambda d: (), "-"),
    "law": (np.int32, lambda d: (), "-"),
    "point": (np.float64, lambda d: (d,), "m"),
    "frame": (np.float64, lambda d: (d, d), "-"),
    "gap": (np.float64, lambda d: (), "m"),
    "impulse": (np.float64, lambda d: (d,), "N s/m"),
    "area": (np.float64, lambda d: (), "m^2/m"),
    "slip": (np.float64, lambda d: (d - 1,), "m"),
    "damage": (np.float64, lambda d: (), "-"),
    "history": (np.float64, lambda d: (), "-"),
    "crush": (np.float64, lambda d: (), "m"),
    "initial_gap": (np.float64, lambda d: (), "m"),
}
"""Contact fields in frames and checkpoints; files written before `area` (or the joint laws'
`slip`, `damage`, `history`, `crush`, or the _g0 laws' `initial_gap`) existed lack them, and
are read and resumed without them."""
_FE_CONTACT_FIELDS = {
    "side_kind": (np.int8, lambda d: (2,), "-"),
    "side_node": (np.int32, lambda d: (2, d), "-"),
    "side_weight": (np.float64, lambda d: (2, d), "-"),
}
"""The contact sides (saxum.contacts), written only for models with deformable blocks."""
_SOLVER_FIELDS = {"refinement": (np.int8, (3,))}
"""The solver's state in checkpoints (ContactSolver.checkpoint(), restore()) of fixed shape: the
refinement's (carrying, cheap, sliding) (saxum.solver.nlgs.Refinement.flags), -1s from a solver
without one; files written before they existed lack them, and resume with a new solver's."""
_SOLVER_STATE = {"solver_state": "solver_state_size"}
"""The rest of the solver's state in checkpoints (the entries of ContactSolver.checkpoint() that
_SOLVER_FIELDS lacks, of any shape: the rest solution's back-off, the anchors of the loads
followed): one byte string per checkpoint (_pack_state) and its length [bytes]; files written
before it existed lack both, and resume with a new solver's state but for the refinement."""
_STEP_UNITS = {"time": "s", "error": "-", "max_interpenetration": "m", "kinetic_energy": "J/m"}
_UNITS = {2: ("m, m, rad", "m/s, m/s, rad/s"),
          3: ("m, m, m, -, -, -, - (x, y, z, unit quaternion qw, qx, qy, qz)",
              "m/s, m/s, m/s, rad/s, rad/s, rad/s (vx, vy, vz world; wx, wy, wz body frame)")}
"""Units of body_q and body_v by dimension."""
_STEP_FIELDS = [f.name for f in fields(StepReport)]

_ROWS = {
    # group: (columns in checksum order, the index column last; ragged parts: (subgroup, its
    # datasets, the column counting each row's entries))
    "frames": (("step", "body_q", "body_v", "node_x", "node_v", "contact_count", "time"),
               (("contacts", (*_CONTACT_FIELDS, *_FE_CONTACT_FIELDS), "contact_count"),)),
    "steps": (tuple(_STEP_FIELDS), ()),
    "histories": (("step", "body_q", "body_v", "ground_acceleration", "time"), ()),
    "checkpoints": (("body_q", "body_v", "node_x", "node_v", "q_ref", "pair_count",
                     "since_refresh", "refresh_count", "contact_count", "steps_logged",
                     *_SOLVER_FIELDS, *_SOLVER_STATE.values(), "time", "step"),
                    (("contacts", (*_CONTACT_FIELDS, *_FE_CONTACT_FIELDS), "contact_count"),
                     ("", ("pairs",), "pair_count"),
                     *(("", (name,), size) for name, size in _SOLVER_STATE.items()))),
}
"""What a row of each appended group is, for its CRC-32 (the same order on writing and reading);
node_x, node_v and the contact sides are there only for models with deformable blocks."""


def _pack_state(state: dict[str, np.ndarray]) -> np.ndarray:
    """Named arrays (numbers) as one byte string (uint8): the names, then each array, in
    numpy's .npy format (numpy.lib.format: dtype, shape and data; the same bytes for the same
    arrays); empty for none."""
    if not state:
        return np.zeros(0, dtype=np.uint8)
    out = io.BytesIO()
    np.lib.format.write_array(out, np.array(list(state)), allow_pickle=False)
    for value in state.values():
        np.lib.format.write_array(out, np.asarray(value), allow_pickle=False)
    return np.frombuffer(out.getvalue(), dtype=np.uint8)


def _unpack_state(data: np.ndarray) -> dict[str, np.ndarray]:
    """The named arrays of _pack_state's byte string."""
    if data.size == 0:
        return {}
    stream = io.BytesIO(data.tobytes())
    names = np.lib.format.read_array(stream, allow_pickle=False)
    return {str(name): np.lib.format.read_array(stream, allow_pickle=False)
            for name in names}


def _byte_rows(column: np.ndarray) -> np.ndarray:
    """The rows of `column` as a (rows, bytes per row) uint8 array."""
    column = np.ascontiguousarray(column)
    width = column.dtype.itemsize * int(np.prod(column.shape[1:], dtype=np.int64))
    return column.view(np.uint8).reshape(column.shape[0], width)


def _checksums(columns: list[np.ndarray],
               ragged: list[tuple[list[np.ndarray], np.ndarray]] = ()) -> np.ndarray:
    """CRC-32 (zlib) of each row: its bytes in every column, then the entries of each ragged
    part (a list of arrays of entries, and the number of entries of each row) that are its."""
    table = np.concatenate([_byte_rows(c) for c in columns], axis=1)
    parts = []
    for arrays, counts in ragged:
        entries = np.concatenate([_byte_rows(a) for a in arrays], axis=1)
        start = np.concatenate([[0], np.cumsum(counts, dtype=np.int64)])
        parts.append((entries, np.minimum(start, len(entries))))
    out = np.empty(len(table), dtype=np.uint32)
    for k, row in enumerate(table):
        crc = zlib.crc32(row)
        for entries, start in parts:
            crc = zlib.crc32(entries[start[k]:start[k + 1]], crc)
        out[k] = crc
    return out


_ROW_NAMES = {"frames": "output frames", "steps": "step reports",
              "histories": "history rows", "checkpoints": "checkpoints"}


def _reason(err: Exception) -> str:
    """What an HDF5 error says, without its time stamp and buffer addresses."""
    text = str(err).strip("'\"")
    if "error message = " in text:
        return text.split("error message = ")[1].split(",")[0].strip("' ")
    if text.endswith(")") and "(" in text:  # "Unable to ... (what went wrong)"
        text = text[text.index("(") + 1:-1]
    return text.replace(" after all read attempts", "")


_SWMR_READ_ATTEMPTS = 26
"""Reads of a metadata entry whose checksum fails before an SWMR reader gives up. HDF5 sleeps
between them, 1 ns at first and twice as long each time (H5C__load_entry), so its default of
100 never ends on a damaged file; 26 wait at most 2^26 ns ~ 0.07 s in all, far longer than a
writer takes to write an entry that a reader caught half written."""


@functools.cache
def _set_read_attempts():
    """HDF5's H5Pset_metadata_read_attempts (h5py does not wrap it), found among the libraries
    that h5py's extension module is linked to; None where it cannot be found."""
    try:
        fn = ctypes.CDLL(h5py.h5p.__file__).H5Pset_metadata_read_attempts
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_int64, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


def _open_swmr_reader(path: Path) -> h5py.File:
    """`path` opened as an SWMR reader that gives up on damaged metadata within 0.07 s
    (_SWMR_READ_ATTEMPTS)."""
    fapl = h5py.h5p.create(h5py.h5p.FILE_ACCESS)
    set_attempts = _set_read_attempts()
    if set_attempts is None or set_attempts(fapl.id, _SWMR_READ_ATTEMPTS) < 0:
        return h5py.File(path, "r", swmr=True)  # HDF5's own retries, then
    flags = h5py.h5f.ACC_RDONLY | h5py.h5f.ACC_SWMR_READ
    return h5py.File(h5py.h5f.open(os.fsencode(path), flags, fapl=fapl))


def _lock_path(path: Path) -> Path:
    return path.with_name(f".{path.name}.lock")


_HELD: set[Path] = set()
"""Results files whose lock this process holds (a reader here must not take them for another
process's live run)."""


class _Lock:
    """An exclusive advisory lock (flock) on `.NAME.lock`, held while NAME is written; the lock
    file holds the writer's process id and is removed on release."""

    def __init__(self, path: Path) -> None:
        self.path = path.resolve()
        self._fd = None
        if fcntl is None:
            return
        lock = _lock_path(self.path)
        while True:
            try:
                fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as err:
                raise InputError(f"cannot write results file {path}: {err.strerror} "
                                 f"({lock.parent}); give another one (-o)") from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                pid = writer_pid(self.path)
                raise InputError(
                    f"{path} is being written by another saxum process"
                    + (f" (pid {pid})" if pid else "")
                    + ": wait for it to finish (saxum info shows how far it is), or write "
                    "to another file (-o)") from None
            try:  # the lock file may have been removed by its previous holder meanwhile
                if os.path.samestat(os.fstat(fd), os.stat(lock)):
                    break
            except FileNotFoundError:
                pass
            os.close(fd)
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        self._fd = fd
        _HELD.add(self.path)

    def release(self) -> None:
        if self._fd is not None:
            _HELD.discard(self.path)
            try:
                os.unlink(_lock_path(self.path))
            except OSError:
                pass
            os.close(self._fd)  # closing releases the flock
            self._fd = None


def writer_pid(path: str | os.PathLike) -> int | None:
    """The id of the process that is writing results file `path` now (0 if it cannot be told),
    or None when no process holds its lock (also when the writer is this process)."""
    path = Path(path).resolve()
    if fcntl is None or path in _HELD:
        return None
    try:
        fd = os.open(_lock_path(path), os.O_RDONLY)
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        text = os.pread(fd, 32, 0).decode(errors="replace").strip()
        return int(text) if text.isdigit() else 0
    finally:
        os.close(fd)
    return None


_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def _lookup3(data: bytes) -> int:
    """Bob Jenkins' lookup3 hash (hashlittle, initial value 0): the checksum of HDF5's
    version 2-3 superblock (HDF5 file format specification, "Superblock", and lookup3.c,
    public domain, 2006)."""
    m = 0xFFFFFFFF

    def rot(x, k):
        return ((x << k) | (x >> (32 - k))) & m

    a = b = c = (0xDEADBEEF + len(data)) & m
    rest = data
    while len(rest) > 12:
        a = (a + int.from_bytes(rest[0:4], "little")) & m
        b = (b + int.from_bytes(rest[4:8], "little")) & m
        c = (c + int.from_bytes(rest[8:12], "little")) & m
        a = ((a - c) & m) ^ rot(c, 4)
        c = (c + b) & m
        b = ((b - a) & m) ^ rot(a, 6)
        a = (a + c) & m
        c = ((c - b) & m) ^ rot(b, 8)
        b = (b + a) & m
        a = ((a - c) & m) ^ rot(c, 16)
        c = (c + b) & m
        b = ((b - a) & m) ^ rot(a, 19)
        a = (a + c) & m
        c = ((c - b) & m) ^ rot(b, 4)
        b = (b + a) & m
        rest = rest[12:]
    if not rest:
        return c
    rest = rest.ljust(12, b"\0")  # the tail's missing bytes count as zeros
    a = (a + int.from_bytes(rest[0:4], "little")) & m
    b = (b + int.from_bytes(rest[4:8], "little")) & m
    c = (c + int.from_bytes(rest[8:12], "little")) & m
    for x, y, k in ((2, 1, 14), (0, 2, 11), (1, 0, 25), (2, 1, 16), (0, 2, 4), (1, 0, 14),
                    (2, 1, 24)):
        v = [a, b, c]
        v[x] = ((v[x] ^ v[y]) - rot(v[y], k)) & m
        a, b, c = v
    return c


def _superblock(path: Path) -> tuple[bytes, int] | None:
    """The first 48 bytes of an HDF5 file with a version 2 or 3 superblock (as saxum writes)
    and its end-of-file address [bytes]; None for another superblock."""
    with open(path, "rb") as f:
        head = f.read(48)
    if len(head) < 48 or head[:8] != _SIGNATURE or head[8] not in (2, 3) or head[9] != 8:
        return None
    if struct.unpack("<I", head[44:48])[0] != _lookup3(head[:44]):
        return None
    return head, struct.unpack("<Q", head[28:36])[0]


class _Image(io.RawIOBase):
    """A read-only view of an HDF5 file for h5py's file-object driver: zeros past its end up to
    the end-of-file address `eof` (a truncated file), and the superblock's "open for writing"
    flags cleared (a killed or crashed run), so that HDF5 opens it without SWMR."""

    def __init__(self, path: Path, head: bytes, eof: int) -> None:
        self._f = open(path, "rb")  # noqa: SIM115 - closed with this object
        self._size = os.fstat(self._f.fileno()).st_size
        self._eof = max(eof, self._size)
        head = bytearray(head)
        head[11] = 0
        head[44:48] = struct.pack("<I", _lookup3(bytes(head[:44])))
        self._head = bytes(head)
        self._pos = 0

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def seek(self, offset: int, whence: int = 0) -> int:
        self._pos = (offset, self._pos + offset, self._eof + offset)[whence]
        return self._pos

    def tell(self) -> int:
        return self._pos

    def readinto(self, buffer) -> int:
        n = max(0, min(len(buffer), self._eof - self._pos))
        data = os.pread(self._f.fileno(), n, self._pos) if self._pos < self._size else b""
        view = memoryview(buffer).cast("B")
        view[:len(data)] = data
        view[len(data):n] = bytes(n - len(data))
        if self._pos < len(self._head):
            k = min(n, len(self._head) - self._pos)
            view[:k] = self._head[self._pos:self._pos + k]
        self._pos += n
        return n

    def close(self) -> None:
        self._f.close()
        super().close()


def _grow(group: h5py.Group, name: str, dtype, tail: tuple, units: str, chunk: int = 256):
    ds = group.create_dataset(name, shape=(0, *tail), maxshape=(None, *tail), dtype=dtype,
                              chunks=(chunk, *tail) if np.prod(tail, dtype=int) < 4096
                              else (1, *tail))
    ds.attrs["units"] = units
    return ds


def _append(ds: h5py.Dataset, rows: np.ndarray) -> None:
    """ds[n:n + len(rows)] = rows after growing ds by len(rows), flushed. Rows of ds's own
    (fixed-size) dtype go through h5py's low-level calls, which write the same as resize and
    ds[n:] = rows in ~25 instead of ~180 us (a 2D frame has ~36 datasets: this was 6 ms of
    the 6.5 a frame cost to write)."""
    shape = ds.id.shape
    n = shape[0]
    if rows.dtype != ds.dtype or rows.dtype.kind == "O":  # variable-length strings
        ds.resize(n + len(rows), axis=0)
        ds[n:] = rows
    else:
        ds.id.set_extent((n + len(rows), *shape[1:]))
        if len(rows):
            rows = np.ascontiguousarray(rows)
            space = ds.id.get_space()
            space.select_hyperslab((n,) + (0,) * (rows.ndim - 1), rows.shape)
            ds.id.write(h5py.h5s.create_simple(rows.shape), space, rows)
    ds.flush()


def _strings(values) -> np.ndarray:
    return np.array([str(v) for v in values], dtype=h5py.string_dtype())


class ResultsWriter:
    """Creates `path` for a run of `model` with time step dt [s] and theta, then appends frames,
    step reports and checkpoints. Use as a context manager or call close().

    The file is locked while it is written: another writer of the same path gets an InputError.
    An existing file is an InputError too unless `overwrite` (it may hold a run to resume).
    A failed write (a full disk) raises ResultsWriteError; the file stays readable up to its
    last complete row."""

    def __init__(self, path: str | os.PathLike, model, *, dt: float, theta: float,
                 scenario: str = "", scenario_json: str = "", version: str = "",
                 histories: tuple[int, ...] = (), ground: bool = False,
                 overwrite: bool = False) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file = None
        self._steps_buffer: list[StepReport] = []
        self._history_buffer: list[tuple] = []
        self._groups: dict[str, _Rows] = {}
        self._lock = _Lock(self.path)
        try:
            if self.path.exists() and not overwrite:
                raise InputError(f"{self.path} already exists{_describe_existing(self.path)}: "
                                 "give --overwrite to replace it (Python: overwrite=True), or "
                                 "another results file (-o)")
            self._file = _open_for_writing(self.path, "w")
            self._create(model, dt=dt, theta=theta, scenario=scenario,
                         scenario_json=scenario_json, version=version, histories=histories,
                         ground=ground)
        except BaseException:
            self.close()
            raise

    def _create(self, model, *, dt, theta, scenario, scenario_json, version, histories,
                ground) -> None:
        f = self._file
        dim, dof = model.dim, model.dof
        nq = model.body_q0.shape[1]
        q_units, v_units = _UNITS[dim]
        f.attrs.update(format=FORMAT, format_version=FORMAT_VERSION, saxum_version=version,
                       dim=dim, dof=dof, dt=dt, theta=theta)
        f.create_dataset("scenario", data=scenario, dtype=h5py.string_dtype())
        f.create_dataset("scenario_json", data=scenario_json, dtype=h5py.string_dtype())
        _write_model(f.create_group("model"), model)

        frames = f.create_group("frames")
        n = model.body_count
        _grow(frames, "step", np.int64, (), "-")
        _grow(frames, "body_q", np.float64, (n, nq), q_units)
        _grow(frames, "body_v", np.float64, (n, dof), v_units)
        _node_datasets(frames, model, 256)
        _grow(frames, "contact_count", np.int64, (), "-")
        _contact_datasets(frames.create_group("contacts"), dim, model.fe is not None)
        _grow(frames, "time", np.float64, (), "s")

        steps = f.create_group("steps")
        for name in _STEP_FIELDS:
            _grow(steps, name, STEP_DTYPES[name], (), _STEP_UNITS.get(name, "-"), chunk=1024)

        if histories:
            hist = f.create_group("histories")
            hist.attrs["body"] = np.asarray(histories, dtype=np.int64)
            k = len(histories)
            _grow(hist, "step", np.int64, (), "-", chunk=1024)
            _grow(hist, "body_q", np.float64, (k, nq), q_units, chunk=1024)
            _grow(hist, "body_v", np.float64, (k, dof), v_units, chunk=1024)
            if ground:
                _grow(hist, "ground_acceleration", np.float64, (dim,), "m/s^2", chunk=1024)
            _grow(hist, "time", np.float64, (), "s", chunk=1024)

        for g in (frames, steps, *([hist] if histories else [])):
            _grow(g, "checksum", np.uint32, (), "-", chunk=1024)
        cp = f.create_group("checkpoints")
        _grow(cp, "checksum", np.uint32, (), "-", chunk=16)
        _grow(cp, "time", np.float64, (), "s", chunk=16)
        _grow(cp, "body_q", np.float64, (n, nq), q_units, chunk=1)
        _grow(cp, "body_v", np.float64, (n, dof), v_units, chunk=1)
        _node_datasets(cp, model, 1)
        _grow(cp, "q_ref", np.float64, (n, nq), q_units, chunk=1)
        for name in ("contact_count", "pair_count", "since_refresh", "refresh_count",
                     "steps_logged"):
            _grow(cp, name, np.int64, (), "-", chunk=16)
        _solver_datasets(cp)
        _contact_datasets(cp.create_group("contacts"), dim, model.fe is not None)
        _grow(cp, "pairs", np.int32, (2,), "-", chunk=4096)
        _grow(cp, "step", np.int64, (), "-", chunk=16)

        run = f.create_group("run")
        run.create_dataset("status", data=np.array([0], dtype=np.int8))
        run.create_dataset("message", data=np.array([b" " * 512]), dtype="S512")
        f.swmr_mode = True
        self._history_bodies = np.asarray(histories, dtype=np.int64)

    @classmethod
    def resume(cls, path: str | os.PathLike, checkpoint: int = -1, *,
               frame_every: int = 1) -> tuple[ResultsWriter, int]:
        """Reopen the results of an interrupted or finished run for appending from one of its
        checkpoints (default: the last). The file is rewritten without the rows after that
        checkpoint and without frames off the regular output steps (multiples of
        frame_every, such as the frame written when a run was interrupted), so the resumed
        run continues exactly as the run made in one go. Returns (writer, checkpoint index)."""
        path = Path(path)
        lock = _Lock(path)
        try:
            return cls._resume(path, lock, checkpoint, frame_every)
        except BaseException:
            lock.release()
            raise

    @classmethod
    def _resume(cls, path: Path, lock: _Lock, checkpoint: int,
                frame_every: int) -> tuple[ResultsWriter, int]:
        with warnings.catch_warnings():  # what was lost is said below, once
            warnings.simplefilter("ignore", ResultsDamageWarning)
            src = Results(path)
        steps = src.checkpoint_steps[:src.resumable]
        if steps.size == 0:
            src.close()
            what = ("no intact checkpoint (" + "; ".join(src.damage) + ")" if src.damage
                    else "no checkpoint")
            raise InputError(f"{path}: the run left {what} to resume from: run it again "
                             "(saxum run SCENARIO -o FILE --overwrite)")
        k = int(np.arange(steps.size)[checkpoint])
        cp_step = int(steps[k])
        if src.damage:
            warnings.warn(f"{path} is damaged (" + "; ".join(src.damage) + "): resuming from "
                          f"its last intact checkpoint, step {cp_step} (t = {cp_step * src.dt:g}"
                          " s); what followed it is computed again", ResultsDamageWarning,
                          stacklevel=3)
        tmp = path.with_name(path.name + ".resume-tmp")
        try:
            with h5py.File(tmp, "w", libver="latest") as dst:
                for key, value in src.file.attrs.items():
                    dst.attrs[key] = value
                for name in ("scenario", "scenario_json", "model", "run"):
                    src.file.copy(src.file[name], dst, name)
                fsteps = src.step
                _copy_rows(src, dst, "frames", src.frame_count,
                           (fsteps <= cp_step) & (fsteps % frame_every == 0))
                n_steps = int(src.file["checkpoints/steps_logged"][k])
                _copy_rows(src, dst, "steps", n_steps, None)
                _copy_rows(src, dst, "checkpoints", k + 1, None)
                cp = dst["checkpoints"]
                if _solver_datasets(cp) and "checksum" in cp:
                    # a file from before the solver's state was stored takes it from here on
                    # (its checkpoints none): the rows read intact, with their new columns
                    cp["checksum"][:] = _stored_checksums(cp, k + 1)
                if src.histories is not None:
                    hsteps = src.histories["step"]
                    _copy_rows(src, dst, "histories", hsteps.size, hsteps <= cp_step)
                    dst["histories"].attrs["body"] = src.file["histories"].attrs["body"]
        except BaseException:  # a failed copy (a full disk, Ctrl-C) leaves no stray file
            src.close()
            tmp.unlink(missing_ok=True)
            raise
        src.close()
        os.replace(tmp, path)
        self = cls.__new__(cls)
        self.path = path
        self._lock = lock
        self._file = _open_for_writing(path, "a")
        self._file["run/status"][0] = 0
        self._file.swmr_mode = True
        self._steps_buffer = []
        self._history_buffer = []
        self._groups = {}
        self._history_bodies = (self._file["histories"].attrs["body"]
                                if "histories" in self._file else np.zeros(0, np.int64))
        return self, k

    # -- appending ----------------------------------------------------------------------------

    def log_step(self, report: StepReport) -> None:
        """Buffer one step's report; written at the next frame, checkpoint or flush."""
        self._steps_buffer.append(report)

    def log_history(self, state, ground: tuple[float, ...] | None = None) -> None:
        """Buffer the chosen blocks' coordinates and velocities after a step, and the ground
        acceleration a_g(t) [m/s^2] when the run has a ground motion."""
        if self._history_bodies.size:
            b = self._history_bodies
            self._history_buffer.append((state.step, state.time, state.body_q[b].copy(),
                                         state.body_v[b].copy(), ground))

    def _rows(self, group: str) -> _Rows:
        if group not in self._groups:
            self._groups[group] = _Rows(self._file[group])
        return self._groups[group]

    def flush_steps(self) -> None:
        """Write the buffered step reports and histories."""
        self._write(self._flush_steps)

    def _flush_steps(self) -> None:
        if self._history_buffer:
            rows = list(zip(*self._history_buffer, strict=True))
            self._rows("histories").append({
                "step": np.array(rows[0]), "time": np.array(rows[1]),
                "body_q": np.array(rows[2]), "body_v": np.array(rows[3]),
                "ground_acceleration": np.array(rows[4], dtype=np.float64)})
            self._history_buffer.clear()
        if self._steps_buffer:
            self._rows("steps").append({name: np.array([getattr(r, name)
                                                        for r in self._steps_buffer])
                                        for name in _STEP_FIELDS})
            self._steps_buffer.clear()
        self._file.flush()

    def write_frame(self, state) -> None:
        """Append the state (time, coordinates, velocities, contacts) as an output frame."""
        c = state.contacts

        def write():
            self._flush_steps()
            self._rows("frames").append({
                "step": np.array([state.step]), "time": np.array([state.time]),
                "body_q": state.body_q[None], "body_v": state.body_v[None],
                "node_x": state.node_x[None], "node_v": state.node_v[None],
                "contact_count": np.array([c.count]),
                **{name: getattr(c, name)[: c.count]
                   for name in (*_CONTACT_FIELDS, *_FE_CONTACT_FIELDS)}})
            self._file.flush()

        self._write(write)

    def write_checkpoint(self, state, detector, solver=None) -> None:
        """Append what a bit-identical restart needs: the state with its contacts, the
        broad phase's pair list (saxum.detection.Detector.checkpoint) and the solver's state
        (ContactSolver.checkpoint; -1s for what `solver` does not have, or without it)."""
        det = detector.checkpoint()
        c = state.contacts
        held = solver.checkpoint() if solver is not None else {}
        carried = {name: np.asarray(held.get(name, np.full(shape, -1)))[None]
                   for name, (_, shape) in _SOLVER_FIELDS.items()}
        packed = _pack_state({k: v for k, v in held.items() if k not in _SOLVER_FIELDS})
        for name, size in _SOLVER_STATE.items():
            carried[name], carried[size] = packed, np.array([packed.size])

        def write():
            self._flush_steps()
            self._rows("checkpoints").append({
                "step": np.array([state.step]), "time": np.array([state.time]),
                "body_q": state.body_q[None], "body_v": state.body_v[None],
                "node_x": state.node_x[None], "node_v": state.node_v[None],
                "q_ref": det["q_ref"][None], "pairs": det["pairs"],
                **{name: np.array([det[name]])
                   for name in ("pair_count", "since_refresh", "refresh_count")},
                "contact_count": np.array([c.count]),
                "steps_logged": np.array([self._file["steps/step"].shape[0]]), **carried,
                **{name: getattr(c, name)[: c.count]
                   for name in (*_CONTACT_FIELDS, *_FE_CONTACT_FIELDS)}})
            self._file.flush()

        self._write(write)

    def set_status(self, status: int, message: str = "") -> None:
        """Mark the run 0 running, 1 finished, 2 interrupted or 3 failed, with a message."""
        def write():
            self._flush_steps()
            self._file["run/message"][0] = message.encode()[:512].ljust(512)
            self._file["run/status"][0] = status
            self._file.flush()

        self._write(write)

    def _write(self, write) -> None:
        """Call write(); HDF5's errors on writing (a full disk: errno ENOSPC or EFBIG) become a
        ResultsWriteError, the file then closed, readable up to its last complete row."""
        if self._file is None:
            raise ResultsWriteError(f"{self.path}: the results file is closed")
        try:
            write()
            return
        except (OSError, RuntimeError) as err:
            reason = _reason(err)
            # HDF5 writes again when it releases the objects of the failed write and closes
            # the file; failing again, it leaves them half closed and crashes at exit. Those
            # writes go to /dev/null: the file keeps what it had when the write failed
            sink = os.open(os.devnull, os.O_RDWR)
            os.dup2(sink, self._file.id.get_vfd_handle())
            os.close(sink)
        self.close()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ResultsDamageWarning)
            try:
                with Results(self.path) as r:
                    kept = (f"it is readable up to t = {r.time[-1]:g} s (frame "
                            f"{r.frame_count - 1}, last checkpoint at step "
                            f"{r.checkpoint_steps[-1]})" if r.checkpoint_steps.size
                            else "it holds no checkpoint")
            except Exception:  # noqa: BLE001 - said in the message
                kept = "it cannot be read back"
        raise ResultsWriteError(
            f"could not write {self.path} ({reason}: a full disk or a file-size limit?): "
            f"{kept}; make room and continue with saxum resume {self.path}")

    def close(self) -> None:
        """Write what is buffered, close the file and release its lock."""
        try:
            if self._file is not None:
                with contextlib.suppress(OSError, RuntimeError):
                    self._flush_steps()
                # once only: closing again a file whose close failed (a full disk) crashes
                # HDF5 when Python exits
                f, self._file = self._file, None
                with contextlib.suppress(OSError, RuntimeError):
                    f.close()
        finally:
            self._lock.release()

    def __enter__(self) -> ResultsWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _write_model(g: h5py.Group, model) -> None:
    g.create_dataset("body_name", data=_strings(model.body_name))
    g.create_dataset("group_names", data=_strings(model.group_names))
    per_depth = "/m" if model.dim == 2 else ""
    fields = [("body_kind", "-"), ("body_group", "-"), ("body_mass", "kg" + per_depth),
              ("body_inertia", "kg m^2" + per_depth), ("body_q0", _UNITS[model.dim][0]),
              ("body_vertex_start", "-"), ("vertex_local", "m"), ("law_kind", "-"),
              ("law_friction", "-"), ("law_restitution", "-"), ("law_parameter", "SI"),
              ("law_initial_gap", "-"), ("group_law", "-"),
              ("gravity", "m/s^2")]
    if model.dim == 3:
        fields += [("body_face_start", "-"), ("face_vertex_start", "-"), ("face_vertex", "-"),
                   ("body_size", "m")]
    if model.has_round:  # and a disc's size, which its bounding square does not give
        fields += [("body_shape", "-"), ("body_round_radius", "m")]
    if model.clustered:  # which vertices make each part of a cluster (drawn_outlines)
        fields += [("contactor_vertex_start", "-")]
    if model.dim == 2 and (model.has_round or model.clustered):  # not the vertices' area
        fields += [("body_size", "m")]
    for name, units in fields:
        ds = g.create_dataset(name, data=np.asarray(getattr(model, name)))
        ds.attrs["units"] = units
    if model.fe is not None:
        fe = model.fe
        for name, data, units in (
                ("fe_body", fe.body, "-"), ("fe_node_x0", fe.node_x0, "m"),
                ("fe_node_start", np.cumsum([0] + [len(m.nodes) for m in fe.meshes]), "-"),
                ("fe_cell_node", np.concatenate([m.cells + s for m, s in zip(
                    fe.meshes, np.cumsum([0] + [len(m.nodes) for m in fe.meshes]),
                    strict=False)]), "-"),
                ("fe_cell_start", np.cumsum([0] + [len(m.cells) for m in fe.meshes]), "-"),
                ("fe_material", np.array([m.row() for m in fe.materials]),
                 "Pa, -, kg/m^3, 1/s, s, m")):
            g.create_dataset(name, data=np.asarray(data)).attrs["units"] = units


def _solver_datasets(cp: h5py.Group) -> int:
    """The checkpoints' datasets of the solver's state (_SOLVER_FIELDS, _SOLVER_STATE) that
    `cp` lacks, each filled for the rows it has (-1s, no state: a new solver's); returns how
    many were added."""
    rows = cp["step"].shape[0] if "step" in cp else 0
    added = 0
    for name, (dtype, shape) in _SOLVER_FIELDS.items():
        if name not in cp:
            _append(_grow(cp, name, dtype, shape, "-", chunk=16),
                    np.full((rows, *shape), -1, dtype=dtype))
            added += 1
    for name, size in _SOLVER_STATE.items():
        if size not in cp:
            _append(_grow(cp, size, np.int64, (), "bytes", chunk=16),
                    np.zeros(rows, dtype=np.int64))
            _grow(cp, name, np.uint8, (), "-", chunk=65536)
            added += 1
    return added


def _node_datasets(g: h5py.Group, model, chunk: int) -> None:
    """node_x [m], node_v [m/s] of the deformable blocks' nodes, for models that have them."""
    if model.fe is not None:
        nodes = (model.fe.node_count, model.dim)
        _grow(g, "node_x", np.float64, nodes, "m", chunk=chunk)
        _grow(g, "node_v", np.float64, nodes, "m/s", chunk=chunk)


def _contact_datasets(g: h5py.Group, dim: int, sides: bool = False) -> None:
    fields = {**_CONTACT_FIELDS, **(_FE_CONTACT_FIELDS if sides else {})}
    for name, (dtype, tail, units) in fields.items():
        # 2D quantities are per metre of depth, 3D ones are not
        _grow(g, name, dtype, tail(dim), units if dim == 2 else units.replace("/m", ""),
              chunk=4096)


class _Rows:
    """Appends rows to one group (frames, steps, histories or checkpoints): the ragged parts,
    the columns, the rows' CRC-32 and last the index column (_ROWS), so that a reader that
    sees a row in the index sees all of it. Holds the group's datasets (looking them up at
    every row would cost more than writing it)."""

    def __init__(self, g: h5py.Group) -> None:
        columns, ragged = _ROWS[g.name.lstrip("/")]
        self.columns = [name for name in columns if name in g]
        self.ds = {name: g[name] for name in self.columns}
        # a file resumed from before a contact field existed goes on without it (format 1,
        # which has no checksums to keep consistent)
        self.ragged = [(names, {name: (g[sub] if sub else g)[name] for name in names
                                if name in (g[sub] if sub else g)}, count)
                       for sub, names, count in ragged if count in g]
        self.checksum = g["checksum"] if "checksum" in g else None  # (none in format 1)

    def append(self, values: dict[str, np.ndarray]) -> None:
        data = {name: np.asarray(values[name], dtype=ds.dtype) for name, ds in self.ds.items()}
        parts = []
        for names, datasets, count in self.ragged:
            present = [name for name in names if name in datasets]
            arrays = [np.asarray(values[name], dtype=datasets[name].dtype) for name in present]
            parts.append((arrays, data[count]))
            for name, a in zip(present, arrays, strict=True):
                _append(datasets[name], a)
        for name in self.columns[:-1]:
            _append(self.ds[name], data[name])
        if self.checksum is not None:
            _append(self.checksum, _checksums([data[name] for name in self.columns], parts))
        _append(self.ds[self.columns[-1]], data[self.columns[-1]])


def _open_for_writing(path: Path, mode: str) -> h5py.File:
    try:
        return h5py.File(path, mode, libver="latest")
    except OSError as err:
        raise InputError(f"cannot write {path}: {err} (is it open in another program, such "
                         "as an HDF5 viewer?)") from None


def _describe_existing(path: Path) -> str:
    """What the file at `path` holds, for the message refusing to overwrite it."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ResultsDamageWarning)
            with Results(path) as r:
                if r.status == "interrupted":
                    at = f" (t = {r.time[-1]:g} s)" if r.frame_count else ""
                    return (f" and holds an interrupted run{at} that saxum resume {path} "
                            "continues")
                return f" and holds a {r.status} run"
    except Exception:  # noqa: BLE001 - only a description
        return ""


def _stored_checksums(g: h5py.Group, m: int) -> np.ndarray:
    """The CRC-32 of the first m rows of the appended group `g` as it stores them: the
    columns and ragged parts it has (as written: see _Rows; older files lack some)."""
    columns, ragged = _ROWS[g.name.lstrip("/")]
    columns = [name for name in columns if name in g]
    data = [g[name][:m] for name in columns]
    parts = []
    for sub, names, count in ragged:
        if count not in g:
            continue
        h = g[sub] if sub else g
        counts = data[columns.index(count)]
        total = max(0, int(counts.sum()))
        parts.append(([h[name][:total] for name in names if name in h], counts))
    return _checksums(data, parts)


def _copy_rows(src: Results, dst: h5py.File, group: str, rows: int, mask) -> None:
    """Copy the first `rows` rows (or the rows where mask is true) of every dataset of a
    group, contacts and pairs cut to match."""
    s = src.file[group]
    d = dst.create_group(group)
    if mask is None:
        keep = np.arange(rows)
    else:
        keep = np.flatnonzero(mask[:rows])
    ragged = {name: count for sub, names, count in _ROWS[group][1] if not sub
              for name in names}  # (pairs, the solver's state)
    for name, ds in s.items():
        if isinstance(ds, h5py.Group):
            continue
        if name in ragged:
            counts = s[ragged[name]][:rows]
            data = _ragged_rows(ds[: int(counts.sum())], counts, keep)
        else:
            data = ds[:rows][keep]
        out = _grow(d, name, ds.dtype, ds.shape[1:], ds.attrs.get("units", "-"),
                    chunk=ds.chunks[0])
        _append(out, data)
    if isinstance(s.get("contacts"), h5py.Group):
        counts = s["contact_count"][:rows]
        dc = d.create_group("contacts")
        for name, ds in s["contacts"].items():
            data = _ragged_rows(ds[: int(counts.sum())], counts, keep)
            out = _grow(dc, name, ds.dtype, ds.shape[1:], ds.attrs.get("units", "-"),
                        chunk=ds.chunks[0])
            _append(out, data)


def _ragged_rows(data: np.ndarray, counts: np.ndarray, keep: np.ndarray) -> np.ndarray:
    start = np.concatenate([[0], np.cumsum(counts)])
    parts = [data[start[k]:start[k + 1]] for k in keep]
    return np.concatenate(parts) if parts else data[:0]


class Results:
    """Reads a results file (also one still being written, or left by a killed run).

    Arrays are numpy; `units` maps each name to its unit. Frames are the output times;
    `steps` holds the solver's per-step figures.

        with Results("arch.h5") as r:
            r.time, r.body_q[-1]          # frame times [s]; coordinates at the last frame
            r.body_name.index("voussoir 8")
            r.contacts(-1)["force"]       # (tangential, normal) contact forces [N/m; 3D: N]
            r.steps["converged"]          # per step: iterations, error, interpenetration...
            r.status, r.message           # finished, interrupted or failed, and why
            r.damage                      # what a truncated or damaged file has lost

    Only intact rows are read: a frame, step, history row or checkpoint whose CRC-32 does not
    match, and every one after it, is left out and said in `damage` (and a
    ResultsDamageWarning). A run that stopped without closing its file (killed, crashed) and
    that no process is writing any more has status "interrupted".
    """

    def __init__(self, path: str | os.PathLike) -> None:
        self.path = Path(path)
        if not self.path.is_file():
            raise InputError(f"no results file at {self.path}")
        self.damage: list[str] = []
        self._image = None
        live = writer_pid(self.path) is not None
        self.file = self._open(live)
        try:
            try:
                if self.file.attrs.get("format") != FORMAT:
                    raise InputError(f"{self.path} is not a saxum results file")
                self._read(live)
            except (OSError, RuntimeError, KeyError, ValueError) as err:
                if live:  # (a run that is creating its file)
                    raise InputError(f"{self.path} is being written and cannot be read yet "
                                     f"({_reason(err)}): try again") from None
                raise InputError(f"{self.path} is damaged beyond reading ({_reason(err)})"
                                 + "".join(f"; {d}" for d in self.damage)) from None
        except BaseException:
            self.close()
            raise
        if self.damage:
            last = f"t = {self.time[-1]:g} s" if self.frame_count else "no frame"
            warnings.warn(f"{self.path} is damaged: " + "; ".join(self.damage)
                          + f"; what is intact is read (frames up to {last})",
                          ResultsDamageWarning, stacklevel=2)

    def _open(self, live: bool) -> h5py.File:
        """The file opened for reading: as an SWMR reader while its writer runs, else without
        SWMR (an SWMR reader retries damaged metadata for minutes) and, for a file left open
        by a killed run or cut short, through _Image."""
        try:
            head = None if live else _superblock(self.path)
            if live:
                return _open_swmr_reader(self.path)
            if head is not None:
                sb, eof = head
                size = self.path.stat().st_size
                if size < eof:
                    self.damage.append(f"the file is truncated ({size} of its {eof} bytes: a "
                                       "copy cut short, or a full disk)")
                if size < eof or sb[11]:  # byte 11: the file consistency flags
                    self._image = _Image(self.path, sb, eof)
                    return h5py.File(self._image, "r")
            return h5py.File(self.path, "r")
        except OSError as err:
            if self._image is not None:
                self._image.close()
            hint = ("; it looks like a scenario: run it first (saxum run "
                    f"{self.path}) and give the results file" if self.path.suffix == ".toml"
                    else "")
            raise InputError(f"{self.path} is not a readable HDF5 file: {_reason(err)}{hint}"
                             + "".join(f"; {d}" for d in self.damage)) from None

    def _read(self, live: bool) -> None:
        a = self.file.attrs
        self.dim = int(a["dim"])
        self.dof = int(a["dof"])
        self.dt = float(a["dt"])
        self.theta = float(a["theta"])
        self.version = str(a["saxum_version"])
        self.scenario = self.file["scenario"][()].decode()
        self.scenario_json = self.file["scenario_json"][()].decode()
        m = self.file["model"]
        self.body_name = [s.decode() for s in m["body_name"][:]]
        self.group_names = [s.decode() for s in m["group_names"][:]]
        self.model = {k: m[k][()] for k in m if k not in ("body_name", "group_names")}
        fr = self.file["frames"]
        self.frame_count = self._intact_rows("frames")
        self.time = fr["time"][: self.frame_count]
        self.step = fr["step"][: self.frame_count]
        self.body_q = fr["body_q"][: self.frame_count]
        self._body_v = fr["body_v"][: self.frame_count]
        self.node_x = fr["node_x"][: self.frame_count] if "node_x" in fr else None
        """Deformable blocks' node positions [m] per frame [frames, nodes, dim] (or None)."""
        self.node_v = fr["node_v"][: self.frame_count] if "node_v" in fr else None
        """... and velocities [m/s]."""
        self._body_v_filled = self.node_v is None or not self.frame_count
        counts = fr["contact_count"][: self.frame_count]
        self._contact_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        st = self.file["steps"]
        present = [k for k in _STEP_FIELDS if k in st]  # files before a field was added
        n = self._intact_rows("steps")
        self.steps = {k: st[k][:n] for k in present}
        cp = self.file["checkpoints"]
        n_cp = self._intact_rows("checkpoints")
        self.checkpoint_steps = cp["step"][:n_cp]
        self.histories = self._read_histories()
        self.resumable = self._resumable(cp["steps_logged"][:n_cp])
        self.status = STATUS[int(self.file["run/status"][0])]
        self.message = self.file["run/message"][0].decode().strip()
        if self.status == "running" and not live:
            at = f"t = {self.time[-1]:g} s" if self.frame_count else "its start"
            self.status = "interrupted"
            self.message = (f"interrupted (resume with saxum resume {self.path}): the run "
                            f"stopped after {at} without closing its file (killed, crashed, "
                            "or out of disk space)")
        per_depth = "/m" if self.dim == 2 else ""
        self.units = {"time": "s", "body_q": _UNITS[self.dim][0],
                      "body_v": _UNITS[self.dim][1], "point": "m", "gap": "m",
                      "impulse": "N s" + per_depth, "force": "N" + per_depth,
                      "area": "m^2" + per_depth,
                      **_STEP_UNITS}
        if self.dim == 3:
            self.units["kinetic_energy"] = "J"

    def _intact_rows(self, group: str) -> int:
        """Rows of `group` that every dataset has and whose CRC-32 matches, up to the first
        that does not; the rows dropped are said in self.damage."""
        g = self.file[group]
        columns = [name for name in _ROWS[group][0] if name in g]
        checked = "checksum" in g  # (not in files of format version 1)
        n = min(g[name].shape[0] for name in columns + ["checksum"] * checked)
        if not checked or n == 0:
            return n

        def intact(m: int) -> np.ndarray:
            """Whether each of the first m rows is intact (raises if they cannot be read)."""
            return _stored_checksums(g, m) == g["checksum"][:m]

        try:
            ok = intact(n)
        except (OSError, RuntimeError, ValueError) as err:
            # the index of the last rows is lost: the most rows, from the first, that read
            reason, good, bad = _reason(err), 0, n
            while bad - good > 1:
                m = (good + bad) // 2
                try:
                    intact(m)
                    good = m
                except (OSError, RuntimeError, ValueError):
                    bad = m
            ok = np.zeros(n, dtype=bool)
            ok[:good] = intact(good) if good else ok[:0]
        else:
            reason = "checksums do not match"
        if ok.all():
            return n
        k = int(np.argmin(ok))
        self.damage.append(f"{_ROW_NAMES[group]}: {n - k} of {n} lost, from row {k} ({reason})")
        return k

    def _resumable(self, steps_logged: np.ndarray) -> int:
        """How many checkpoints, from the first, a resumed run can start from: those that the
        intact step reports, frames and histories reach (a resumed run computes only what
        follows its checkpoint)."""
        ok = steps_logged <= self.steps["step"].size
        lost = " ".join(self.damage)
        if _ROW_NAMES["frames"] in lost:
            ok &= self.checkpoint_steps <= (self.step[-1] if self.frame_count else -1)
        if self.histories is not None and _ROW_NAMES["histories"] in lost:
            h = self.histories["step"]
            ok &= self.checkpoint_steps <= (h[-1] if h.size else 0)
        return int(ok.size if ok.all() else np.argmin(ok))

    @functools.cached_property
    def body_size(self) -> np.ndarray:
        """Square root of each body's area (3D: cube root of its volume, stored in the file)
        [m] (as saxum.model.Model.body_size)."""
        if "body_size" in self.model:
            return self.model["body_size"]
        return np.array([np.sqrt(polygon_properties(p).area) for p in self._polygons()])

    @functools.cached_property
    def body_radius(self) -> np.ndarray:
        """Largest distance from each body's centre of mass to its vertices [m]."""
        return np.array([np.linalg.norm(p, axis=1).max() for p in self._polygons()])

    def _polygons(self) -> list[np.ndarray]:
        return np.split(self.model["vertex_local"], self.model["body_vertex_start"][1:-1])

    def _read_histories(self) -> dict[str, np.ndarray] | None:
        """{"body": indices, "name": names, "time", "step", "body_q", "body_v" and, under a
        ground motion, "ground_acceleration"}, rows that every dataset has; None when the run
        kept no histories."""
        h = self.file.get("histories")
        if h is None:
            return None
        n = self._intact_rows("histories")
        out = {name: ds[:n] for name, ds in h.items() if name != "checksum"}
        out["body"] = np.asarray(h.attrs["body"])
        out["name"] = [self.body_name[b] for b in out["body"]]
        return out

    def contacts(self, frame: int) -> dict[str, np.ndarray]:
        """The contacts of output frame `frame`: the stored fields (`area` [m; 3D: m^2], the
        share of the joint each point stands for, absent from files of saxum before it) and
        `force` = impulse / dt [N/m; 3D: N], the mean contact force over the step, in the
        contact frame (t, n) (3D: (t, n, s))."""
        k = range(self.frame_count)[frame]
        lo, hi = self._contact_start[k], self._contact_start[k + 1]
        g = self.file["frames/contacts"]
        out = {name: g[name][lo:hi] for name in (*_CONTACT_FIELDS, *_FE_CONTACT_FIELDS)
               if name in g}
        out["force"] = out["impulse"] / self.dt
        return out

    @property
    def contact_counts(self) -> np.ndarray:
        """The number of contacts stored at each output frame [frames]."""
        return np.diff(self._contact_start)

    def view(self, *, every: int = 1, blocks: str | None = None):
        """An interactive 3D view of the run (saxum.view: the page of `saxum view`), shown
        inline in a Jupyter notebook; every `every`-th output frame and the last, the blocks
        whose name or group matches the glob `blocks` (and the supports) or all."""
        from .view import View, view_html

        return View(view_html(self, every=every, blocks=blocks))

    @property
    def body_v(self) -> np.ndarray:
        """Body velocities per frame [frames, bodies, dof] [m/s, rad/s]. The rows of deformable
        blocks, which the run leaves empty (their body rows hold only their frames), are their
        nodes' nearest rigid motion (FEBlocks.rigid_velocities, as saxum.mechanism does for a
        run's state), computed for all frames at the first read: collapse detection and the
        mechanism read the blocks' speeds there."""
        if not self._body_v_filled:
            body, d = self.model["fe_body"], self.dim
            velocity, spin = self._blocks().rigid_velocities(self.node_x, self.node_v)
            self._body_v[:, body, :d] = velocity
            self._body_v[:, body, d:] = spin
            self._body_v_filled = True
        return self._body_v

    def _blocks(self):
        """The deformable blocks' geometry (saxum.bodies.fe.stored_blocks), built once."""
        if getattr(self, "_fe_blocks", None) is None:
            from .bodies.fe import stored_blocks

            self._fe_blocks = stored_blocks(self.model)
        return self._fe_blocks

    def stresses(self, frame: int) -> dict[str, np.ndarray]:
        """Cell stresses of the deformable blocks at output frame `frame` [Pa], world axes,
        from the stored node positions (saxum.fe.FEBlocks.stresses): "stress" (sxx, syy, sxy)
        [cells, 3] (3D: sxx, syy, szz, syz, sxz, sxy [cells, 6]), "principal" ascending
        [cells, d], "compression" and "tension" (the largest of each, >= 0) [cells]; {}
        without deformable blocks."""
        if self.node_x is None:
            return {}
        blocks = self._blocks()
        x = self.node_x[range(self.frame_count)[frame]]
        stress, principal, compression, tension = blocks.stresses(x, *blocks.frames(x))
        return {"stress": stress, "principal": principal, "compression": compression,
                "tension": tension}

    def vertices(self, body: int, frame: int) -> np.ndarray:
        """World vertices [m] of `body` at output frame `frame`, shape (n, dim)."""
        from .model import body_vertices

        vs = self.model["body_vertex_start"]
        return body_vertices(self.body_q[frame, body],
                             self.model["vertex_local"][vs[body]:vs[body + 1]])

    def checkpoint(self, index: int = -1) -> dict:
        """The arrays of one checkpoint (for restart)."""
        cp = self.file["checkpoints"]
        n = self.checkpoint_steps.size
        k = range(n)[index]
        counts = cp["contact_count"][:n]
        start = np.concatenate([[0], np.cumsum(counts)])
        pcounts = cp["pair_count"][:n]
        pstart = np.concatenate([[0], np.cumsum(pcounts)])
        out = {name: cp[name][k] for name in ("time", "step", "body_q", "body_v", "node_x",
                                               "node_v", "q_ref", "pair_count",
                                               "since_refresh", "refresh_count",
                                               "steps_logged", *_SOLVER_FIELDS) if name in cp}
        out["contacts"] = {name: cp["contacts"][name][start[k]:start[k + 1]]
                           for name in (*_CONTACT_FIELDS, *_FE_CONTACT_FIELDS)
                           if name in cp["contacts"]}
        out["pairs"] = cp["pairs"][pstart[k]:pstart[k + 1]]
        for name, size in _SOLVER_STATE.items():
            if size in cp:
                sstart = np.concatenate([[0], np.cumsum(cp[size][:n])])
                out.update(_unpack_state(cp[name][sstart[k]:sstart[k + 1]]))
        return out

    def to_xarray(self):
        """The frames as an xarray.Dataset with dimensions (time, body, dof) and units
        (requires xarray)."""
        import xarray as xr

        if self.dim == 3:
            coords = {"time": ("time", self.time, {"units": "s"}), "body": self.body_name,
                      "coordinate": ["x", "y", "z", "qw", "qx", "qy", "qz"],
                      "dof": ["x", "y", "z", "wx", "wy", "wz"]}
            q_dims = ("time", "body", "coordinate")
        else:
            coords = {"time": ("time", self.time, {"units": "s"}), "body": self.body_name,
                      "dof": ["x", "y", "theta"][: self.dof]}
            q_dims = ("time", "body", "dof")
        return xr.Dataset({
            "body_q": (q_dims, self.body_q, {"units": self.units["body_q"]}),
            "body_v": (("time", "body", "dof"), self.body_v, {"units": self.units["body_v"]}),
        }, coords=coords)

    def close(self) -> None:
        if getattr(self, "file", None) is not None:
            self.file.close()
        if self._image is not None:
            self._image.close()

    def __enter__(self) -> Results:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
