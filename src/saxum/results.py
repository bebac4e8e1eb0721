"""Results on disk: one HDF5 file per run, written as the run goes, readable after a crash.

Layout (every dataset carries a `units` attribute; arrays grow along their first axis):

    /                      attrs: format = "saxum-results", format_version, saxum_version, dim,
                           dof, dt [s], theta [-]
    /scenario              the scenario's TOML text ("" for a run built in Python)
    /scenario_json         the validated scenario (saxum.scenario.Scenario) as JSON, overrides
                           applied and paths resolved: what `saxum resume` rebuilds the run from
    /model/...             body_name, body_kind, body_group, group_names, body_mass [kg/m],
                           body_inertia [kg m^2/m], body_q0, body_vertex_start, vertex_local [m],
                           law_kind, law_friction, law_restitution, group_law, gravity [m/s^2];
                           3D also body_face_start, face_vertex_start, face_vertex (faces)
    /frames/...            one row per output time: time [s], step, body_q, body_v,
                           contact_count; the contacts of all frames one after the other in
                           /frames/contacts/{candidate, antagonist, key, law, point, frame, gap,
                           impulse, area [m^2/m; 3D: m^2] (saxum.contacts.Contacts.area)}
    /steps/...             one row per time step: the StepReport fields (saxum.steplog)
    /histories/...         one row per time step for the chosen blocks (attrs body: their
                           indices): time [s], step, body_q, body_v (shape [steps, blocks, 3])
                           and, under a ground motion, ground_acceleration [m/s^2]
    /checkpoints/...       one row per checkpoint: everything a bit-identical restart needs
                           (state, contacts with impulses, broad-phase pair list)
    /run/status            0 running, 1 finished, 2 interrupted, 3 failed; /run/message

The file is opened in HDF5's single-writer/multiple-reader (SWMR) mode: every object exists
before the first step, rows are appended and flushed, so a run killed at any moment (even by
SIGKILL) leaves a file that reads consistently up to its last flush. Rows are committed in an
order that makes the index datasets (frames/time, checkpoints/step) the last written, and the
reader trusts only rows that every dataset of a group has.
"""

from __future__ import annotations

import contextlib
import functools
import os
from dataclasses import fields
from pathlib import Path

import h5py
import numpy as np

from .errors import InputError
from .geometry2d import polygon_properties
from .steplog import STEP_DTYPES, StepReport

__all__ = ["Results", "ResultsWriter", "STATUS"]

FORMAT = "saxum-results"
FORMAT_VERSION = 1
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
}
"""Contact fields in frames and checkpoints; files written before `area` existed lack it, and
are read and resumed without it."""
_STEP_UNITS = {"time": "s", "error": "-", "max_interpenetration": "m", "kinetic_energy": "J/m"}
_UNITS = {2: ("m, m, rad", "m/s, m/s, rad/s"),
          3: ("m, m, m, -, -, -, - (x, y, z, unit quaternion qw, qx, qy, qz)",
              "m/s, m/s, m/s, rad/s, rad/s, rad/s (vx, vy, vz world; wx, wy, wz body frame)")}
"""Units of body_q and body_v by dimension."""
_STEP_FIELDS = [f.name for f in fields(StepReport)]


def _grow(group: h5py.Group, name: str, dtype, tail: tuple, units: str, chunk: int = 256):
    ds = group.create_dataset(name, shape=(0, *tail), maxshape=(None, *tail), dtype=dtype,
                              chunks=(chunk, *tail) if np.prod(tail, dtype=int) < 4096
                              else (1, *tail))
    ds.attrs["units"] = units
    return ds


def _append(ds: h5py.Dataset, rows: np.ndarray) -> None:
    n = ds.shape[0]
    ds.resize(n + len(rows), axis=0)
    ds[n:] = rows
    ds.flush()


def _strings(values) -> np.ndarray:
    return np.array([str(v) for v in values], dtype=h5py.string_dtype())


class ResultsWriter:
    """Creates `path` for a run of `model` with time step dt [s] and theta, then appends frames,
    step reports and checkpoints. Use as a context manager or call close()."""

    def __init__(self, path: str | os.PathLike, model, *, dt: float, theta: float,
                 scenario: str = "", scenario_json: str = "", version: str = "",
                 histories: tuple[int, ...] = (), ground: bool = False) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file = f = h5py.File(self.path, "w", libver="latest")
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
        _grow(frames, "contact_count", np.int64, (), "-")
        _contact_datasets(frames.create_group("contacts"), dim)
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

        cp = f.create_group("checkpoints")
        _grow(cp, "time", np.float64, (), "s", chunk=16)
        _grow(cp, "body_q", np.float64, (n, nq), q_units, chunk=1)
        _grow(cp, "body_v", np.float64, (n, dof), v_units, chunk=1)
        _grow(cp, "q_ref", np.float64, (n, nq), q_units, chunk=1)
        for name in ("contact_count", "pair_count", "since_refresh", "refresh_count",
                     "steps_logged"):
            _grow(cp, name, np.int64, (), "-", chunk=16)
        _contact_datasets(cp.create_group("contacts"), dim)
        _grow(cp, "pairs", np.int32, (2,), "-", chunk=4096)
        _grow(cp, "step", np.int64, (), "-", chunk=16)

        run = f.create_group("run")
        run.create_dataset("status", data=np.array([0], dtype=np.int8))
        run.create_dataset("message", data=np.array([b" " * 512]), dtype="S512")
        f.swmr_mode = True
        self._steps_buffer: list[StepReport] = []
        self._history_buffer: list[tuple] = []
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
        src = Results(path)
        steps = src.checkpoint_steps
        if steps.size == 0:
            raise InputError(f"{path}: the run left no checkpoint to resume from")
        k = int(np.arange(steps.size)[checkpoint])
        cp_step = int(steps[k])
        tmp = path.with_name(path.name + ".resume-tmp")
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
            if "histories" in src.file:
                hsteps = src.file["histories/step"]
                _copy_rows(src, dst, "histories", hsteps.shape[0],
                           hsteps[: hsteps.shape[0]] <= cp_step)
                dst["histories"].attrs["body"] = src.file["histories"].attrs["body"]
        src.close()
        os.replace(tmp, path)
        self = cls.__new__(cls)
        self.path = path
        self._file = h5py.File(path, "a", libver="latest")
        self._file["run/status"][0] = 0
        self._file.swmr_mode = True
        self._steps_buffer = []
        self._history_buffer = []
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

    def flush_steps(self) -> None:
        """Write the buffered step reports and histories."""
        if self._history_buffer:
            hist = self._file["histories"]
            rows = list(zip(*self._history_buffer, strict=True))
            _append(hist["step"], np.array(rows[0]))
            _append(hist["body_q"], np.array(rows[2]))
            _append(hist["body_v"], np.array(rows[3]))
            if "ground_acceleration" in hist:
                _append(hist["ground_acceleration"], np.array(rows[4], dtype=np.float64))
            _append(hist["time"], np.array(rows[1]))
            self._history_buffer.clear()
        if not self._steps_buffer:
            self._file.flush()
            return
        steps = self._file["steps"]
        for name in _STEP_FIELDS:
            _append(steps[name], np.array([getattr(r, name) for r in self._steps_buffer],
                                          dtype=steps[name].dtype))
        self._steps_buffer.clear()
        self._file.flush()

    def write_frame(self, state) -> None:
        """Append the state (time, coordinates, velocities, contacts) as an output frame."""
        self.flush_steps()
        fr = self._file["frames"]
        c = state.contacts
        _append_contacts(fr["contacts"], c)
        _append(fr["contact_count"], np.array([c.count]))
        _append(fr["body_q"], state.body_q[None])
        _append(fr["body_v"], state.body_v[None])
        _append(fr["step"], np.array([state.step]))
        _append(fr["time"], np.array([state.time]))
        self._file.flush()

    def write_checkpoint(self, state, detector) -> None:
        """Append what a bit-identical restart needs: the state with its contacts and the
        broad phase's pair list (saxum.detection.Detector.checkpoint)."""
        self.flush_steps()
        cp = self._file["checkpoints"]
        det = detector.checkpoint()
        c = state.contacts
        _append_contacts(cp["contacts"], c)
        _append(cp["pairs"], det["pairs"])
        _append(cp["q_ref"], det["q_ref"][None])
        for name in ("pair_count", "since_refresh", "refresh_count"):
            _append(cp[name], np.array([det[name]]))
        _append(cp["contact_count"], np.array([c.count]))
        _append(cp["steps_logged"], np.array([self._file["steps/step"].shape[0]]))
        _append(cp["body_q"], state.body_q[None])
        _append(cp["body_v"], state.body_v[None])
        _append(cp["time"], np.array([state.time]))
        _append(cp["step"], np.array([state.step]))
        self._file.flush()

    def set_status(self, status: int, message: str = "") -> None:
        self.flush_steps()
        self._file["run/message"][0] = message.encode()[:512].ljust(512)
        self._file["run/status"][0] = status
        self._file.flush()

    def close(self) -> None:
        if self._file:
            with contextlib.suppress(Exception):
                self.flush_steps()
            self._file.close()
            self._file = None

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
              ("law_friction", "-"), ("law_restitution", "-"), ("group_law", "-"),
              ("gravity", "m/s^2")]
    if model.dim == 3:
        fields += [("body_face_start", "-"), ("face_vertex_start", "-"), ("face_vertex", "-"),
                   ("body_size", "m")]
    for name, units in fields:
        ds = g.create_dataset(name, data=np.asarray(getattr(model, name)))
        ds.attrs["units"] = units


def _contact_datasets(g: h5py.Group, dim: int) -> None:
    for name, (dtype, tail, units) in _CONTACT_FIELDS.items():
        # 2D quantities are per metre of depth, 3D ones are not
        _grow(g, name, dtype, tail(dim), units if dim == 2 else units.replace("/m", ""),
              chunk=4096)


def _append_contacts(g: h5py.Group, c) -> None:
    for name in _CONTACT_FIELDS:
        if name in g:  # a resumed file from before a field existed goes on without it
            _append(g[name], getattr(c, name)[: c.count])


def _copy_rows(src: Results, dst: h5py.File, group: str, rows: int, mask) -> None:
    """Copy the first `rows` rows (or the rows where mask is true) of every dataset of a
    group, contacts and pairs cut to match."""
    s = src.file[group]
    d = dst.create_group(group)
    if mask is None:
        keep = np.arange(rows)
    else:
        keep = np.flatnonzero(mask[:rows])
    for name, ds in s.items():
        if isinstance(ds, h5py.Group):
            continue
        data = ds[: ds.shape[0]]
        if name == "pairs":
            data = _ragged_rows(data, s["pair_count"][:rows], keep)
        else:
            data = data[keep]
        out = _grow(d, name, ds.dtype, ds.shape[1:], ds.attrs.get("units", "-"),
                    chunk=ds.chunks[0])
        _append(out, data)
    if isinstance(s.get("contacts"), h5py.Group):
        counts = s["contact_count"][:rows]
        dc = d.create_group("contacts")
        for name, ds in s["contacts"].items():
            data = _ragged_rows(ds[: ds.shape[0]], counts, keep)
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
    """

    def __init__(self, path: str | os.PathLike) -> None:
        self.path = Path(path)
        if not self.path.is_file():
            raise InputError(f"no results file at {self.path}")
        try:
            self.file = h5py.File(self.path, "r", swmr=True)
        except OSError as err:
            hint = ("; it looks like a scenario: run it first (saxum run "
                    f"{self.path}) and give the results file" if self.path.suffix == ".toml"
                    else "")
            raise InputError(f"{self.path} is not a readable HDF5 file: {err}{hint}") from None
        if self.file.attrs.get("format") != FORMAT:
            self.file.close()
            raise InputError(f"{self.path} is not a saxum results file")
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
        self.frame_count = min(fr[k].shape[0] for k in ("time", "step", "body_q", "body_v",
                                                         "contact_count"))
        self.time = fr["time"][: self.frame_count]
        self.step = fr["step"][: self.frame_count]
        self.body_q = fr["body_q"][: self.frame_count]
        self.body_v = fr["body_v"][: self.frame_count]
        counts = fr["contact_count"][: self.frame_count]
        self._contact_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        st = self.file["steps"]
        n = min(st[k].shape[0] for k in _STEP_FIELDS)
        self.steps = {k: st[k][:n] for k in _STEP_FIELDS}
        cp = self.file["checkpoints"]
        self.checkpoint_steps = cp["step"][: min(cp[k].shape[0] for k in cp
                                                  if isinstance(cp[k], h5py.Dataset)
                                                  and k != "pairs")]
        self.histories = self._read_histories()
        self.status = STATUS[int(self.file["run/status"][0])]
        self.message = self.file["run/message"][0].decode().strip()
        per_depth = "/m" if self.dim == 2 else ""
        self.units = {"time": "s", "body_q": _UNITS[self.dim][0],
                      "body_v": _UNITS[self.dim][1], "point": "m", "gap": "m",
                      "impulse": "N s" + per_depth, "force": "N" + per_depth,
                      "area": "m^2" + per_depth,
                      **_STEP_UNITS}
        if self.dim == 3:
            self.units["kinetic_energy"] = "J"

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
        n = min(ds.shape[0] for ds in h.values())
        out = {name: ds[:n] for name, ds in h.items()}
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
        out = {name: g[name][lo:hi] for name in _CONTACT_FIELDS if name in g}
        out["force"] = out["impulse"] / self.dt
        return out

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
        out = {name: cp[name][k] for name in ("time", "step", "body_q", "body_v", "q_ref",
                                               "pair_count", "since_refresh", "refresh_count",
                                               "steps_logged")}
        out["contacts"] = {name: cp["contacts"][name][start[k]:start[k + 1]]
                           for name in _CONTACT_FIELDS if name in cp["contacts"]}
        out["pairs"] = cp["pairs"][pstart[k]:pstart[k + 1]]
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
        self.file.close()

    def __enter__(self) -> Results:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
