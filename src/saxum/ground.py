"""Ground motion: recorded accelerograms (PEER NGA .AT2, two-column CSV), analytic pulses, and
the two ways of applying them to a structure.

Units: time [s], acceleration [m/s^2] (records in g are converted with g = 9.80665 m/s^2).

Application (documented in docs/ground-motion.md):
- **inertial forces** (`apply_as_inertial_forces`): the structure is described in the frame
  of the ground, which does not move; every free block gets the force -m a_g(t). Positions are
  relative to the ground.
- **driven supports** (`apply_as_driven_supports`): the supports move with the ground velocity
  v_g(t) = int a_g dt (trapezoidal), held at its last value after the record. Positions are
  absolute. A recorded accelerogram integrates to a velocity that does not end at zero
  (baseline error), so the ground would drift away: `baseline_corrected()` removes the
  constant acceleration v_g(end)/duration, after which the ground ends at rest.
The two give the same motion of the blocks relative to the ground for the same GroundMotion
(a uniform translation of the frame adds no force; tests/test_ground.py).

Components: a 2D model takes (horizontal, vertical), a 3D model (x, y, z) with z vertical; a
record with one horizontal component is put along any horizontal direction of a 3D model by
`in_3d(azimuth)`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numba as nb
import numpy as np

from .errors import InputError

__all__ = ["G_STANDARD", "GroundMotion", "harmonic", "mavroeidis_papageorgiou", "one_sine",
           "read_at2", "read_csv", "rectangular", "ricker"]

G_STANDARD = 9.80665  # [m/s^2]
_UNITS = {"g": G_STANDARD, "m/s^2": 1.0, "m/s2": 1.0, "cm/s^2": 0.01, "cm/s2": 0.01,
          "gal": 0.01}


@dataclass(frozen=True)
class GroundMotion:
    """A ground acceleration history: times [s] (increasing) and acceleration [m/s^2], shape
    (n, 2) (horizontal, vertical; one column: horizontal only) or (n, 3) (x, y, z, z
    vertical: for 3D models); between samples it is linear, outside it is zero."""

    time: np.ndarray
    acceleration: np.ndarray
    name: str = ""

    def __post_init__(self) -> None:
        t = np.asarray(self.time, dtype=float)
        a = np.asarray(self.acceleration, dtype=float)
        if a.ndim == 2 and a.shape[1] == 1:
            a = a[:, 0]
        if a.ndim == 1:  # horizontal only
            a = np.column_stack((a, np.zeros_like(a)))
        if t.ndim != 1 or len(t) < 2 or a.ndim != 2 or a.shape[0] != len(t) or a.shape[
                1] not in (2, 3):
            raise InputError(f"ground motion {self.name!r}: need >= 2 samples of time and of "
                             f"2 or 3 acceleration components, got {t.shape} and {a.shape}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(a))):
            raise InputError(f"ground motion {self.name!r}: NaN or infinite values")
        if np.any(np.diff(t) <= 0.0):
            k = int(np.flatnonzero(np.diff(t) <= 0.0)[0])
            raise InputError(f"ground motion {self.name!r}: time must increase (sample {k + 1}"
                             f" at {t[k + 1]:g} s follows {t[k]:g} s)")
        object.__setattr__(self, "time", t)
        object.__setattr__(self, "acceleration", a)

    @property
    def duration(self) -> float:
        return float(self.time[-1] - self.time[0])

    @property
    def components(self) -> int:
        """2: (horizontal, vertical), for 2D models; 3: (x, y, z), for 3D models."""
        return int(self.acceleration.shape[1])

    def in_3d(self, azimuth: float = 0.0) -> GroundMotion:
        """A (horizontal, vertical) record as (x, y, z): the horizontal component along the
        direction at `azimuth` [rad] from the x axis towards y, the vertical one along z."""
        if self.components != 2:
            raise InputError(f"ground motion {self.name!r} already has 3 components")
        h, v = self.acceleration[:, 0], self.acceleration[:, 1]
        return GroundMotion(self.time, np.column_stack((math.cos(azimuth) * h,
                                                        math.sin(azimuth) * h, v)), self.name)

    def plus(self, other: GroundMotion) -> GroundMotion:
        """The sum of two motions with the same components (two horizontal components of a
        record, each along its own direction), sampled at the times of both: between two
        samples of one the sum is linear, so where the other starts later or ends earlier
        it ramps from or to zero over one sample interval (two components of one record
        share their times, and their sum is exact)."""
        if other.components != self.components:
            raise InputError(f"ground motions {self.name!r} and {other.name!r} have "
                             f"{self.components} and {other.components} components; add "
                             "motions of one kind (GroundMotion.in_3d turns a 2D record "
                             "into a 3D one)")
        t = np.union1d(self.time, other.time)
        a = sum(np.column_stack([np.interp(t, m.time, c, left=0.0, right=0.0)
                                 for c in m.acceleration.T]) for m in (self, other))
        return GroundMotion(t, a, f"{self.name} + {other.name}")

    def scaled(self, factor: float) -> GroundMotion:
        """The record times `factor` (both components)."""
        return GroundMotion(self.time, factor * self.acceleration, self.name)

    def trimmed(self, start: float, end: float) -> GroundMotion:
        """The part between start and end [s], shifted to begin at t = 0."""
        keep = (self.time >= start) & (self.time <= end)
        if keep.sum() < 2:
            raise InputError(f"ground motion {self.name!r}: nothing between {start:g} and "
                             f"{end:g} s (record spans {self.time[0]:g} .. {self.time[-1]:g} s)")
        return GroundMotion(self.time[keep] - start, self.acceleration[keep], self.name)

    def acceleration_at(self, t: float) -> tuple[float, ...]:
        """a_g(t) [m/s^2], linear between samples, 0 outside the record."""
        if t < self.time[0] or t > self.time[-1]:
            return (0.0,) * self.components
        return tuple(float(np.interp(t, self.time, a)) for a in self.acceleration.T)

    def velocity(self) -> np.ndarray:
        """Ground velocity [m/s] at the samples: trapezoidal integral of the acceleration."""
        return self._velocity.copy()

    @functools.cached_property
    def _velocity(self) -> np.ndarray:
        # computed once: velocity_at is called twice per time step
        dt = np.diff(self.time)[:, None]
        return np.vstack((np.zeros((1, self.components)),
                          np.cumsum(0.5 * dt * (self.acceleration[1:] + self.acceleration[:-1]),
                                    axis=0)))

    def baseline_corrected(self) -> GroundMotion:
        """The record minus the constant acceleration v_g(end)/duration [m/s^2], so that the
        ground velocity ends at zero (the trapezoidal integral of a constant is exact)."""
        drift = self.velocity()[-1] / self.duration
        return GroundMotion(self.time, self.acceleration - drift[None, :], self.name)

    def velocity_at(self, t: float) -> np.ndarray:
        """Ground velocity [m/s] at any time: the exact integral of the piecewise-linear
        acceleration (0 before the record, its final value after)."""
        out = np.empty(self.components)
        _velocities(self.time, self.acceleration, self._velocity, t, t, out, out)
        return out

    def inertial_load(self):
        """The uniform acceleration -a_g(t) [m/s^2] that the ground frame adds to every free
        block (for ModelBuilder.add_acceleration or Model.accelerations). Over a time step
        it acts with its exact mean over the step, (v_g(t1) - v_g(t0)) / h, so that pulses
        with jumps are applied with their exact impulse."""
        return _InertialLoad(self)

    def _check_dim(self, builder) -> None:
        if self.components != builder.dim:
            raise InputError(
                f"ground motion {self.name!r} has {self.components} components, the model is "
                f"{builder.dim}D: a 2D model takes (horizontal, vertical), a 3D model (x, y, z)"
                + ("; GroundMotion.in_3d(azimuth) turns a 2D record into one"
                   if builder.dim == 3 else ""))

    def apply_as_inertial_forces(self, builder) -> None:
        """Add -m a_g(t) to every free block of a saxum.ModelBuilder (ground frame)."""
        self._check_dim(builder)
        builder.add_acceleration(self.inertial_load())

    def apply_as_driven_supports(self, builder, names: Sequence[str]) -> None:
        """Drive the fixed blocks `names` with the ground velocity (absolute frame)."""
        self._check_dim(builder)
        velocity = self.velocity()
        turning = (0.0,) * (3 * (builder.dim - 1) - builder.dim)  # no rotation

        def motion(t: float):
            # np.interp holds the end values outside the record: 0 before, v_g(end) after
            return tuple(float(np.interp(t, self.time, v)) for v in velocity.T) + turning

        for name in names:
            builder.drive(name, motion)


class _InertialLoad:
    """-a_g(t) [m/s^2], with its exact mean over a step (saxum.simulation uses `mean_over`)."""

    def __init__(self, motion: GroundMotion) -> None:
        self.motion = motion

    def __call__(self, t: float) -> tuple[float, ...]:
        return tuple(-a for a in self.motion.acceleration_at(t))

    def mean_over(self, t0: float, t1: float) -> np.ndarray:
        """-(v_g(t1) - v_g(t0)) / (t1 - t0) [m/s^2]."""
        m = self.motion
        v0, v1 = np.empty(m.components), np.empty(m.components)
        _velocities(m.time, m.acceleration, m._velocity, t0, t1, v0, v1)
        return -(v1 - v0) / (t1 - t0)


@nb.njit(cache=True)
def _velocities(time, acceleration, velocity, t0, t1, v0, v1):
    """v0, v1 = v_g(t0), v_g(t1) [m/s]: the exact integrals of the piecewise-linear
    acceleration [m/s^2] sampled at `time` [s], whose integrals at the samples are `velocity`
    (0 before the record, its final value after). Compiled: called on every time step, where
    Python's or numpy's per-call cost on two or three components is most of its cost."""
    for t, out in ((t0, v0), (t1, v1)):
        n = time.shape[0]
        if t <= time[0]:
            out[:] = 0.0
        elif t >= time[n - 1]:
            out[:] = velocity[n - 1]
        else:
            k = np.searchsorted(time, t, side="right") - 1
            tau = t - time[k]
            span = time[k + 1] - time[k]
            for d in range(out.shape[0]):
                a0, a1 = acceleration[k, d], acceleration[k + 1, d]
                out[d] = velocity[k, d] + a0 * tau + 0.5 * ((a1 - a0) / span) * tau * tau


def _pulse(name: str, duration: float, shape: Callable[[np.ndarray], np.ndarray],
           samples: int, direction: tuple[float, float]) -> GroundMotion:
    if not (math.isfinite(duration) and duration > 0.0):
        raise InputError(f"{name}: duration must be > 0 [s], got {duration}")
    t = np.linspace(0.0, duration, samples)
    d = np.asarray(direction, dtype=float)
    return GroundMotion(t, shape(t)[:, None] * d[None, :] / np.linalg.norm(d), name)


def one_sine(amplitude: float, period: float, *, symmetric: bool = False,
             direction=(1.0, 0.0), samples: int = 2001) -> GroundMotion:
    """One-sine acceleration pulse of peak `amplitude` [m/s^2] and period T_p [s]:
    antisymmetric a(t) = A sin(2 pi t/T_p) on [0, T_p] (a full cycle, zero net velocity;
    the "type-B" pulse of Zhang & Makris 2001), symmetric a(t) = A sin(pi t/T_p) on [0, T_p]
    (a half cycle)."""
    w = (1.0 if symmetric else 2.0) * math.pi / period
    return _pulse("one-sine pulse", period, lambda t: amplitude * np.sin(w * t), samples,
                  direction)


def ricker(amplitude: float, period: float, *, direction=(1.0, 0.0),
           samples: int = 2001) -> GroundMotion:
    """Ricker wavelet of peak `amplitude` [m/s^2] and period T_p = 1/f_p [s], centred at
    t0 = 1.5 T_p: a(t) = A (1 - 2 pi^2 f_p^2 (t - t0)^2) exp(-pi^2 f_p^2 (t - t0)^2)."""
    f = 1.0 / period
    t0 = 1.5 * period

    def shape(t):
        x = (math.pi * f * (t - t0)) ** 2
        return amplitude * (1.0 - 2.0 * x) * np.exp(-x)

    return _pulse("Ricker pulse", 3.0 * period, shape, samples, direction)


def mavroeidis_papageorgiou(velocity: float, period: float, gamma: float = 2.0,
                            nu: float = 0.0, *, direction=(1.0, 0.0),
                            samples: int = 4001) -> GroundMotion:
    """Mavroeidis & Papageorgiou (BSSA 93, 2003) near-fault pulse: ground velocity
    v(t) = (V/2) [1 + cos(2 pi f_p (t - t0)/gamma)] cos(2 pi f_p (t - t0) + nu) for
    |t - t0| <= gamma/(2 f_p), f_p = 1/T_p, t0 = gamma/(2 f_p); the acceleration returned is
    its exact derivative [m/s^2]. V [m/s], gamma > 1 [-] (oscillation), nu [rad] (phase)."""
    if not gamma > 1.0:
        raise InputError(f"Mavroeidis-Papageorgiou gamma must be > 1, got {gamma}")
    f = 1.0 / period
    t0 = gamma / (2.0 * f)

    def shape(t):
        x = 2.0 * math.pi * f * (t - t0)
        envelope, carrier = 0.5 * (1.0 + np.cos(x / gamma)), np.cos(x + nu)
        d_envelope = -0.5 * np.sin(x / gamma) / gamma
        return velocity * 2.0 * math.pi * f * (d_envelope * carrier - envelope * np.sin(x + nu))

    return _pulse("Mavroeidis-Papageorgiou pulse", 2.0 * t0, shape, samples, direction)


def rectangular(amplitude: float, duration: float, *, direction=(1.0, 0.0)) -> GroundMotion:
    """A rectangular acceleration pulse: A [m/s^2] for `duration` [s] (Newmark 1965)."""
    eps = 1e-9 * duration
    t = np.array([0.0, eps, duration - eps, duration])
    d = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    return GroundMotion(t, np.outer([0.0, amplitude, amplitude, 0.0], d), "rectangular pulse")


def harmonic(amplitude: float, period: float, cycles: float, *, ramp: float = 0.0,
             direction=(1.0, 0.0), samples_per_cycle: int = 200) -> GroundMotion:
    """Harmonic base motion of `cycles` periods T [s] (frequency 1/T), its amplitude growing
    linearly over the first `ramp` seconds: a(t) = A min(1, t/t_r) sin(2 pi t/T) on
    [0, cycles T], A [m/s^2] (t_r = 0: full amplitude at once). With ramp = cycles T the
    amplitude grows through the whole motion, reaching A at the end: the amplitude at time t
    is A t/t_r, so the time at which a structure fails gives the amplitude that failed it."""
    if not (math.isfinite(period) and period > 0.0):
        raise InputError(f"harmonic motion: period must be > 0 [s], got {period}")
    if not (math.isfinite(cycles) and cycles > 0.0):
        raise InputError(f"harmonic motion: cycles must be > 0, got {cycles}")
    if not (math.isfinite(ramp) and ramp >= 0.0):
        raise InputError(f"harmonic motion: ramp must be >= 0 [s], got {ramp}")
    w = 2.0 * math.pi / period

    def shape(t):
        envelope = np.minimum(1.0, t / ramp) if ramp > 0.0 else 1.0
        return amplitude * envelope * np.sin(w * t)

    return _pulse("harmonic motion", cycles * period, shape,
                  max(2, math.ceil(cycles * samples_per_cycle)) + 1, direction)


def read_at2(path: str | Path) -> GroundMotion:
    """A PEER NGA record (.AT2): four header lines (the third names the units, the fourth
    NPTS and DT), then the accelerations, several per line."""
    path = Path(path)
    lines = _read_lines(path)
    while lines and not lines[-1].strip():
        lines.pop()
    if len(lines) < 5:
        raise InputError(f"{path}: an .AT2 file has 4 header lines and data; this has "
                         f"{len(lines)} lines")
    units = lines[2].upper()
    factor = G_STANDARD if " G" in f" {units}" and "CM" not in units else (
        0.01 if "CM/S" in units else None)
    if factor is None:
        raise InputError(f"{path} line 3: units not recognized in {lines[2]!r} "
                         "(expected '... UNITS OF G' or 'CM/S/S')")
    header = lines[3].upper().replace(",", " ").replace("=", " ")
    words = header.split()
    try:
        npts = int(float(words[words.index("NPTS") + 1]))
        dt = float(words[words.index("DT") + 1])
    except (ValueError, IndexError):
        raise InputError(f"{path} line 4: expected 'NPTS= n, DT= dt SEC', got "
                         f"{lines[3]!r}") from None
    if not (math.isfinite(dt) and dt > 0.0):
        raise InputError(f"{path} line 4: the time step DT must be > 0 [s], got {dt:g}")
    values: list[float] = []
    for n, line in enumerate(lines[4:], start=5):
        values.extend(_numbers(path, n, line.split(), line))
    if len(values) != npts:
        raise InputError(f"{path} line 4: the header says NPTS = {npts} but lines 5-"
                         f"{len(lines)} hold {len(values)} values")
    acc = factor * np.array(values)
    return GroundMotion(dt * np.arange(npts), acc, path.stem)


def read_csv(path: str | Path, *, units: str | None = None) -> GroundMotion:
    """Two columns, time [s] and acceleration (three with a vertical component; four: x, y, z
    for a 3D model), comma or whitespace separated; lines starting with # are comments. A
    comment "# units: g" (or m/s^2, cm/s^2, gal) gives the units unless `units` does; a
    comment "# dt: 0.01" states the time step [s], which the time column must then follow
    (to 1e-6 relative). Every error names the line."""
    path = Path(path)
    rows, lines = [], []
    stated: dict[str, tuple[str, int]] = {}  # "units"/"dt" -> (value, line)
    for n, line in enumerate(_read_lines(path), start=1):
        text = line.strip()
        if not text:
            continue
        if text.startswith("#"):
            key, _, value = text.lstrip("#").partition(":")
            if key.strip().lower() in ("units", "dt"):
                stated[key.strip().lower()] = (value.strip(), n)
            continue
        fields = [f.strip() for f in text.split(",")] if "," in text else text.split()
        if not rows and not any(_is_number(f) for f in fields):
            continue  # a header line of column names
        row = _numbers(path, n, fields, line)
        if len(row) not in (2, 3, 4) or (rows and len(row) != len(rows[0])):
            expected = len(rows[0]) if rows else "2, 3 or 4"
            raise InputError(f"{path} line {n}: expected {expected} columns (time [s], "
                             f"acceleration[s]), got {len(row)}: {line!r}")
        if rows and not row[0] > rows[-1][0]:
            raise InputError(f"{path} line {n}: time must increase: {row[0]:g} s follows "
                             f"{rows[-1][0]:g} s (line {lines[-1]})")
        rows.append(row)
        lines.append(n)
    if units is not None:
        chosen, where = units, "units="
    elif "units" in stated:
        chosen, where = stated["units"][0], f"line {stated['units'][1]}"
    else:
        raise InputError(f"{path}: units unknown; add a line '# units: g' (or m/s^2) or pass "
                         "units=")
    if chosen.lower() not in _UNITS:
        raise InputError(f"{path} {where}: units {chosen!r} not one of {', '.join(_UNITS)}")
    if len(rows) < 2:
        raise InputError(f"{path}: fewer than 2 data lines")
    data = np.array(rows)
    if "dt" in stated:
        _check_step(path, stated["dt"], data[:, 0], lines)
    return GroundMotion(data[:, 0], _UNITS[chosen.lower()] * data[:, 1:], path.stem)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _numbers(path: Path, n: int, fields: list[str], line: str) -> list[float]:
    """The numbers in the fields of line n of a record file; an empty field (a missing
    value) or one that is not a finite number is an error naming the line."""
    if "" in fields:
        raise InputError(f"{path} line {n}: a value is missing (empty field): {line!r}")
    try:
        values = [float(x) for x in fields]
    except ValueError:
        raise InputError(f"{path} line {n}: not numbers: {line!r}") from None
    if not all(math.isfinite(v) for v in values):
        raise InputError(f"{path} line {n}: NaN or infinite value: {line!r}")
    return values


def _check_step(path: Path, stated: tuple[str, int], time: np.ndarray, lines: list[int]):
    value, where = stated
    try:
        dt = float(value)
    except ValueError:
        dt = math.nan
    if not (math.isfinite(dt) and dt > 0.0):
        raise InputError(f"{path} line {where}: the time step must be a number > 0 [s], got "
                         f"{value!r}")
    off = np.flatnonzero(np.abs(np.diff(time) - dt) > 1e-6 * dt)
    if off.size:
        k = int(off[0]) + 1
        raise InputError(f"{path} line {lines[k]}: the time step {time[k] - time[k - 1]:g} s "
                         f"does not match dt = {dt:g} s stated on line {where}")


def _read_lines(path: Path) -> list[str]:
    """All lines of the file (blank ones too, so that line numbers in messages are right)."""
    if not path.is_file():
        raise InputError(f"no ground-motion file at {path}")
    return path.read_text(errors="replace").splitlines()
