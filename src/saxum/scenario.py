"""Scenario files: a whole run described in TOML, validated before anything runs.

A scenario names the structure (a generator with its parameters, or a file of blocks), the
contact laws per pair of body groups, the loads, the solver and detection settings, and the
duration and output intervals. Every key, its unit and its default: docs/scenario.md.
`load_scenario` reads a file, applies `--set key=value` overrides and validates; an unknown
key, a wrong type, a value out of range or a missing file raises InputError naming the key, the
line of the file and the allowed values. The same objects can be made in Python:
`Scenario(structure=ArchStructure(...), laws=[...], output=OutputSpec(duration=2.0))`.
"""

from __future__ import annotations

import json
import math
import re
import tomllib
from pathlib import Path
from typing import Annotated, ClassVar, Literal

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)

from .detection import DetectionSettings
from .errors import InputError
from .laws import ContactLaw, LawKind
from .model import BodyKind, Model, ModelBuilder
from .simulation import Simulation
from .solver import NLGS
from .structures import (
    ArchShape,
    add_blocks_from_mesh,
    add_bridge3d,
    add_ground_slab,
    add_grounded_running_bond_wall,
    add_pier3d,
    add_semicircular_arch3d,
    add_supported_semicircular_arch,
    add_wall3d,
)

__all__ = ["Arch3dStructure", "ArchStructure", "BlockSpec", "BlocksStructure",
           "Bridge3dStructure", "DetectionSpec", "GroundMotionSpec", "LawSpec", "Loads",
           "MeshStructure", "OutputSpec", "Pier3dStructure", "PointLoad", "Scenario",
           "Settlement", "SolverSpec", "Wall3dStructure", "WallStructure", "load_scenario",
           "parse_scenario"]

Positive = Annotated[float, Field(gt=0.0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    dim: ClassVar[int] = 2
    """Spatial dimension of a structure's model."""


class ArchStructure(_Strict):
    """A semicircular arch of equal voussoirs with radial joints on a fixed support
    (groups "voussoir" and "support")."""

    type: Literal["semicircular_arch"] = "semicircular_arch"
    radius: Positive = Field(description="mean radius R [m]")
    thickness: Positive = Field(description="ring thickness t [m], < 2 R")
    voussoirs: int = Field(ge=1, description="number of equal voussoirs")
    density: Positive = Field(2000.0, description="density [kg/m^3]")

    def add_to(self, builder: ModelBuilder) -> None:
        add_supported_semicircular_arch(builder, radius=self.radius, thickness=self.thickness,
                                        voussoirs=self.voussoirs, density=self.density)


class WallStructure(_Strict):
    """A running-bond brick wall on a fixed ground (groups "brick" and "ground")."""

    type: Literal["running_bond_wall"] = "running_bond_wall"
    courses: int = Field(ge=1, description="number of courses")
    bricks: int = Field(ge=1, description="bricks per course")
    brick_length: Positive = Field(0.25, description="[m]")
    brick_height: Positive = Field(0.065, description="[m]")
    density: Positive = Field(1800.0, description="[kg/m^3]")

    def add_to(self, builder: ModelBuilder) -> None:
        add_grounded_running_bond_wall(builder, courses=self.courses, bricks=self.bricks,
                                       brick_length=self.brick_length,
                                       brick_height=self.brick_height, density=self.density)


class BlockSpec(_Strict):
    """One block of a blocks file: a convex polygon [m] in either orientation."""

    vertices: list[tuple[Finite, Finite]] = Field(min_length=3)
    density: Annotated[float, Field(ge=0.0, allow_inf_nan=False)] = 0.0
    group: str = "block"
    kind: Literal["free", "fixed"] = "free"
    name: str | None = None


class BlocksStructure(_Strict):
    """Blocks listed in a JSON file: {"blocks": [{"vertices": [[x, y], ...], "density": ...,
    "group": ..., "kind": "free" | "fixed", "name": ...}, ...]}; a relative path is taken from
    the scenario file's folder."""

    type: Literal["blocks"] = "blocks"
    file: Path

    def add_to(self, builder: ModelBuilder) -> None:
        if not self.file.is_file():
            raise InputError(f"structure.file: no blocks file at {self.file}")
        try:
            data = json.loads(self.file.read_text())
        except json.JSONDecodeError as err:
            raise InputError(f"{self.file}: not valid JSON: {err}") from None
        if not isinstance(data, dict) or not isinstance(data.get("blocks"), list):
            raise InputError(f'{self.file}: expected {{"blocks": [...]}} at the top level')
        for k, raw in enumerate(data["blocks"]):
            try:
                block = BlockSpec.model_validate(raw)
            except ValidationError as err:
                raise InputError(f"{self.file}: block {k} ({_first_error(err)})") from None
            kind = BodyKind.FREE if block.kind == "free" else BodyKind.FIXED
            builder.add_block(block.vertices, density=block.density, group=block.group,
                              kind=kind, name=block.name or f"block {k}")


class Arch3dStructure(_Strict):
    """The semicircular arch of "semicircular_arch" given a depth (3D): its voussoirs and its
    support block are prisms through the depth (groups "voussoir" and "support")."""

    dim: ClassVar[int] = 3
    type: Literal["semicircular_arch_3d"] = "semicircular_arch_3d"
    radius: Positive = Field(description="mean radius R [m]")
    thickness: Positive = Field(description="ring thickness t [m], < 2 R")
    voussoirs: int = Field(ge=1, description="number of equal voussoirs")
    depth: Positive = Field(description="depth of the barrel [m]")
    pieces: int = Field(1, ge=1, description="pieces of each voussoir along the depth")
    stagger: bool = Field(False, description="shift every other voussoir's joints by half")
    density: Positive = Field(2000.0, description="density [kg/m^3]")

    def add_to(self, builder: ModelBuilder) -> None:
        add_semicircular_arch3d(builder, radius=self.radius, thickness=self.thickness,
                                voussoirs=self.voussoirs, depth=self.depth, pieces=self.pieces,
                                stagger=self.stagger, density=self.density)


class Wall3dStructure(_Strict):
    """A 3D wall one brick thick in running bond on a fixed ground slab, with an optional
    return wall at an interlocking L corner (groups "brick" and "ground")."""

    dim: ClassVar[int] = 3
    type: Literal["wall_3d"] = "wall_3d"
    courses: int = Field(ge=1, description="number of courses")
    length: Positive = Field(description="length of the wall along x [m]")
    return_length: Positive | None = Field(None, description="length of the return wall [m]")
    thickness: Positive = Field(0.12, description="[m]")
    brick_length: Positive = Field(0.25, description="[m]")
    brick_height: Positive = Field(0.065, description="[m]")
    density: Positive = Field(1800.0, description="[kg/m^3]")

    def add_to(self, builder: ModelBuilder) -> None:
        add_ground_slab(builder, (0.0, 0.0), (self.length, self.return_length or
                                              self.thickness), 0.0)
        add_wall3d(builder, courses=self.courses, length=self.length,
                   return_length=self.return_length, thickness=self.thickness,
                   brick_length=self.brick_length, brick_height=self.brick_height,
                   density=self.density)


class Pier3dStructure(_Strict):
    """A 3D pier of courses of two crossed blocks on a fixed ground slab (groups "pier" and
    "ground")."""

    dim: ClassVar[int] = 3
    type: Literal["pier_3d"] = "pier_3d"
    width: Positive = Field(description="along x [m]")
    depth: Positive = Field(description="along y [m]")
    courses: int = Field(ge=1, description="number of courses")
    course_height: Positive = Field(description="[m]")
    density: Positive = Field(2200.0, description="[kg/m^3]")

    def add_to(self, builder: ModelBuilder) -> None:
        add_ground_slab(builder, (0.0, 0.0), (self.width, self.depth), 0.0)
        add_pier3d(builder, width=self.width, depth=self.depth, courses=self.courses,
                   course_height=self.course_height, density=self.density)


class Bridge3dStructure(_Strict):
    """A single-span stone bridge with spandrel walls (3D): a segmental barrel on two
    abutments, spandrel walls at both faces, fill blocks between them or none (groups
    "ground", "pier", "voussoir", "spandrel", "fill")."""

    dim: ClassVar[int] = 3
    type: Literal["bridge_3d"] = "bridge_3d"
    span: Positive = Field(description="clear span [m]")
    rise: Positive = Field(description="rise of the intrados [m]")
    thickness: Positive = Field(description="ring thickness [m]")
    voussoirs: int = Field(ge=1, description="number of voussoirs")
    width: Positive = Field(description="width of the bridge along y [m]")
    spandrel_thickness: Positive = Field(description="thickness of each spandrel wall [m]")
    abutment_width: Positive = Field(description="[m]")
    abutment_height: Positive = Field(description="[m], from the ground to the springing")
    fill: Literal["blocks", "none"] = "blocks"
    course_height: Positive = Field(0.5, description="spandrel courses [m]")
    block_length: Positive = Field(1.0, description="spandrel blocks [m]")
    pieces: int = Field(1, ge=1, description="pieces of each voussoir along the width")
    stagger: bool = Field(False, description="shift every other voussoir's joints by half")
    density: Positive = Field(2200.0, description="[kg/m^3]")

    def add_to(self, builder: ModelBuilder) -> None:
        shape = ArchShape.segmental(span=self.span, rise=self.rise, thickness=self.thickness)
        add_bridge3d(builder, shape, voussoirs=self.voussoirs, width=self.width,
                     spandrel_thickness=self.spandrel_thickness,
                     abutment_width=self.abutment_width, pier_height=self.abutment_height,
                     fill=self.fill, pieces=self.pieces, stagger=self.stagger,
                     course_height=self.course_height, block_length=self.block_length,
                     density=self.density)


class MeshStructure(_Strict):
    """3D blocks from a mesh file (OBJ, STL, PLY, OFF, VTU...; saxum.structures.meshfile):
    each closed convex part is a block of group `group`; with `ground`, a fixed slab (group
    "ground") under them, its top at their lowest point. A relative path is taken from the
    scenario file's folder."""

    dim: ClassVar[int] = 3
    type: Literal["mesh"] = "mesh"
    file: Path
    density: Positive = Field(description="[kg/m^3]")
    group: str = "block"
    ground: bool = True

    def add_to(self, builder: ModelBuilder) -> None:
        asm = add_blocks_from_mesh(builder, self.file, density=self.density, group=self.group)
        if self.ground:
            pts = np.concatenate(list(asm.outlines.values()))
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            add_ground_slab(builder, lo[:2], hi[:2], float(lo[2]))


Structure = Annotated[ArchStructure | WallStructure | BlocksStructure | Arch3dStructure
                      | Wall3dStructure | Pier3dStructure | Bridge3dStructure | MeshStructure,
                      Field(discriminator="type")]


class LawSpec(_Strict):
    """The contact law between two groups of bodies."""

    groups: tuple[str, str]
    friction: Annotated[float, Field(ge=0.0, allow_inf_nan=False)]
    kind: Literal["signorini_coulomb", "restitution_coulomb", "gap_signorini_coulomb"] = (
        "gap_signorini_coulomb")
    restitution: Annotated[float, Field(ge=0.0, le=1.0)] = 0.0

    def law(self) -> ContactLaw:
        return ContactLaw(friction=self.friction, kind=LawKind[self.kind.upper()],
                          restitution=self.restitution)


Vector = tuple[Finite, Finite] | tuple[Finite, Finite, Finite]
"""A direction or vector: 2 components in 2D, 3 in 3D (z vertical)."""


class PointLoad(_Strict):
    """A constant force of `magnitude` [N/m; 3D: N] along `direction` (normalized; default
    downward) at the centre of mass of the block called `block`."""

    block: str
    magnitude: Finite
    direction: Vector | None = None


class Settlement(_Strict):
    """The fixed block called `block` (a support) moves by `magnitude` [m] along `direction`
    (normalized; default downward) and turns by `rotation` [rad] about its centre of mass (3D:
    a rotation vector, world axes), at a constant rate over `time` [s] from the start, then
    stays."""

    block: str
    magnitude: Finite
    direction: Vector | None = None
    rotation: Finite | tuple[Finite, Finite, Finite] = 0.0
    time: Positive = 1.0


class GroundMotionSpec(_Strict):
    """Base motion: a recorded accelerogram (`file`, PEER .AT2 or two/three-column CSV) or an
    analytic `pulse`, scaled, trimmed, applied as inertial forces in the ground frame or by
    driving the named fixed `supports` (saxum.ground, docs/ground-motion.md)."""

    file: Path | None = None
    units: str | None = None
    pulse: Literal["one_sine", "one_sine_symmetric", "ricker", "mavroeidis_papageorgiou",
                   "rectangular"] | None = None
    amplitude: Finite = 0.0
    velocity: Finite = 0.0
    period: Positive = 1.0
    gamma: Annotated[float, Field(gt=1.0)] = 2.0
    nu: Finite = 0.0
    direction: Vector | None = None
    azimuth: Finite = 0.0
    scale: Finite = 1.0
    start: Annotated[float, Field(ge=0.0)] = 0.0
    end: Positive | None = None
    baseline_correction: bool = False
    apply: Literal["inertial", "driven"] = "inertial"
    supports: list[str] = []

    @model_validator(mode="after")
    def _one_source(self) -> GroundMotionSpec:
        if (self.file is None) == (self.pulse is None):
            raise ValueError("give either file (a record) or pulse, not both or neither")
        if self.apply == "driven" and not self.supports:
            raise ValueError('apply = "driven" needs the names of the supports to drive')
        return self

    def motion(self, dim: int = 2):
        """The saxum.ground.GroundMotion described, with the components of a dim-D model: a
        pulse along `direction` (default x), a record of (horizontal, vertical) components in
        3D with its horizontal one at `azimuth` [deg] from x towards y."""
        from . import ground

        default = (1.0, 0.0) if dim == 2 else (1.0, 0.0, 0.0)
        d = _unit(self.direction or default, "ground_motion.direction", dim)
        if self.file is not None:
            if self.file.suffix.lower() == ".at2":
                record = ground.read_at2(self.file)
            else:
                record = ground.read_csv(self.file, units=self.units)
        elif self.pulse == "mavroeidis_papageorgiou":
            record = ground.mavroeidis_papageorgiou(self.velocity, self.period, self.gamma,
                                                    self.nu, direction=d)
        elif self.pulse == "ricker":
            record = ground.ricker(self.amplitude, self.period, direction=d)
        elif self.pulse == "rectangular":
            record = ground.rectangular(self.amplitude, self.period, direction=d)
        else:
            record = ground.one_sine(self.amplitude, self.period, direction=d,
                                     symmetric=self.pulse == "one_sine_symmetric")
        if self.start > 0.0 or self.end is not None:
            record = record.trimmed(self.start, self.end if self.end is not None
                                    else float(record.time[-1]))
        record = record.scaled(self.scale)
        if dim == 3 and record.components == 2:
            record = record.in_3d(math.radians(self.azimuth))
        return record.baseline_corrected() if self.baseline_correction else record


class Loads(_Strict):
    """Gravity [m/s^2] (default downward: (0, -9.81), 3D (0, 0, -9.81)); a horizontal
    inertial load a(t) = (horizontal_acceleration + load_factor_rate * g * t) on every free
    block [m/s^2], g = |gravity| (a tilting table), along x, in 3D along the horizontal
    direction at horizontal_azimuth [deg] from x towards y; point loads; settlements of
    supports; ground motion."""

    gravity: Vector | None = None
    horizontal_acceleration: Finite = 0.0
    horizontal_azimuth: Finite = 0.0
    load_factor_rate: Finite = 0.0
    point_loads: list[PointLoad] = []
    settlements: list[Settlement] = []
    ground_motion: GroundMotionSpec | None = None

    def gravity_for(self, dim: int) -> tuple[float, ...]:
        """The gravity vector of a dim-D model [m/s^2]."""
        if self.gravity is None:
            return (0.0, -9.81) if dim == 2 else (0.0, 0.0, -9.81)
        if len(self.gravity) != dim:
            raise InputError(f"loads.gravity has {len(self.gravity)} components, the model is "
                             f"{dim}D: give {dim}")
        return tuple(self.gravity)

    def add_to(self, builder: ModelBuilder) -> None:
        """Apply these loads to the blocks in `builder`."""
        dim = builder.dim
        down = np.eye(dim)[-1] * -1.0
        ax0, rate = self.horizontal_acceleration, self.load_factor_rate
        if dim == 2 and self.horizontal_azimuth != 0.0:
            raise InputError("loads.horizontal_azimuth is for 3D models; in 2D the horizontal "
                             "load is along x (use a negative horizontal_acceleration for -x)")
        if ax0 != 0.0 or rate != 0.0:
            g = float(np.linalg.norm(self.gravity_for(dim)))
            phi = math.radians(self.horizontal_azimuth)
            h = (1.0, 0.0) if dim == 2 else (math.cos(phi), math.sin(phi), 0.0)
            builder.add_acceleration(lambda t: tuple((ax0 + rate * g * t) * c for c in h))
        turning = 3 * (dim - 1) - dim  # rotational dof: 1 in 2D, 3 in 3D
        for k, load in enumerate(self.point_loads):
            f = load.magnitude * _unit(load.direction or down, f"point_loads[{k}].direction",
                                       dim)
            builder.add_force([builder.index(load.block)],
                              lambda t, f=tuple(f): (*f, *(0.0,) * turning))
        for k, s in enumerate(self.settlements):
            v = s.magnitude / s.time * _unit(s.direction or down,
                                             f"settlements[{k}].direction", dim)
            rotation = np.atleast_1d(np.asarray(s.rotation, dtype=np.float64))
            if rotation.size == 1 and dim == 3 and rotation[0] == 0.0:
                rotation = np.zeros(3)
            if rotation.size != turning:
                raise InputError(f"loads.settlements[{k}].rotation: a {dim}D model turns "
                                 + ("by an angle [rad]" if dim == 2 else
                                    "by a rotation vector [rad] of 3 components"))
            moving = (*v, *(rotation / s.time))
            builder.drive(s.block, lambda t, m=moving, end=s.time:
                          m if t < end else (0.0,) * len(m))
        if self.ground_motion is not None:
            motion = self.ground_motion.motion(dim)
            if self.ground_motion.apply == "inertial":
                motion.apply_as_inertial_forces(builder)
            else:
                motion.apply_as_driven_supports(builder, self.ground_motion.supports)


def _unit(direction, key: str, dim: int | None = None):
    d = np.asarray(direction, dtype=np.float64)
    if dim is not None and d.size != dim:
        raise InputError(f"loads.{key} has {d.size} components, the model is {dim}D: give "
                         f"{dim}")
    norm = float(np.linalg.norm(d))
    if norm == 0.0:
        raise InputError(f"loads.{key} must not be zero")
    return d / norm


class SolverSpec(_Strict):
    """Moreau-Jean step dt [s] and theta [-]; NLGS tolerance [-], sweep cap, relaxation."""

    dt: Positive = 1e-3
    theta: Annotated[float, Field(ge=0.5, le=1.0)] = 0.5
    tolerance: Positive = 1e-6
    max_iterations: int = Field(5000, ge=1)
    relaxation: Annotated[float, Field(gt=0.0, le=1.0)] = 1.0


class DetectionSpec(_Strict):
    """Alert distance, margin and tolerated interpenetration [m] (default: from the blocks'
    size, see saxum.detection.DetectionSettings) and the broad-phase refresh period [steps]."""

    alert: Positive | None = None
    margin: Positive | None = None
    interpenetration: Positive | None = None
    refresh_every: int = Field(10, ge=1)


class OutputSpec(_Strict):
    """Simulated duration [s], interval between output frames [s] and between checkpoints
    [s] (both rounded to whole steps)."""

    duration: Annotated[float, Field(ge=0.0, allow_inf_nan=False)]
    interval: Positive = 0.01
    checkpoint_interval: Positive = 1.0


class Scenario(_Strict):
    """A whole run. Build it with load_scenario(path) or directly in Python."""

    title: str = ""
    structure: Structure
    laws: list[LawSpec] = Field(min_length=1)
    loads: Loads = Loads()
    solver: SolverSpec = SolverSpec()
    detection: DetectionSpec = DetectionSpec()
    output: OutputSpec

    @field_validator("laws")
    @classmethod
    def _one_law_per_pair(cls, laws: list[LawSpec]) -> list[LawSpec]:
        seen = set()
        for law in laws:
            pair = frozenset(law.groups)
            if pair in seen:
                raise ValueError(f"two laws for the groups {sorted(pair)}; keep one")
            seen.add(pair)
        return laws

    def build_model(self) -> Model:
        """The Model this scenario describes."""
        dim = self.structure.dim
        builder = ModelBuilder(dim=dim, gravity=self.loads.gravity_for(dim))
        self.structure.add_to(builder)
        for spec in self.laws:
            builder.set_law(*spec.groups, spec.law())
        self.loads.add_to(builder)
        return builder.finalize()

    def build_simulation(self, model: Model | None = None) -> Simulation:
        """A Simulation of this scenario's model with its solver and detection settings."""
        s, d = self.solver, self.detection
        return Simulation(
            model if model is not None else self.build_model(), dt=s.dt, theta=s.theta,
            solver=NLGS(tolerance=s.tolerance, max_iterations=s.max_iterations,
                        relaxation=s.relaxation),
            detection=DetectionSettings(alert=d.alert, margin=d.margin,
                                        refresh_every=d.refresh_every,
                                        interpenetration=d.interpenetration),
        )


def load_scenario(path: str | Path, overrides: list[str] | tuple[str, ...] = ()) -> Scenario:
    """Read and validate a TOML scenario file; overrides are "dotted.key=value" (TOML value)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no scenario file at {path}")
    return parse_scenario(path.read_text(), base_dir=path.parent, overrides=overrides,
                          source=str(path))


def parse_scenario(text: str, *, base_dir: str | Path = ".",
                   overrides: list[str] | tuple[str, ...] = (),
                   source: str = "scenario") -> Scenario:
    """Validate scenario TOML text (see load_scenario); relative files are taken from
    base_dir."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"{source}: not valid TOML: {err}") from None
    for item in overrides:
        _apply_override(data, item)
    ground = data.get("loads", {}).get("ground_motion") if isinstance(data.get("loads"),
                                                                         dict) else None
    for table in (data.get("structure"), ground):
        if isinstance(table, dict) and isinstance(table.get("file"), str):
            file = Path(table["file"])
            table["file"] = str(file if file.is_absolute() else Path(base_dir) / file)
    try:
        return Scenario.model_validate(data)
    except ValidationError as err:
        overridden = {item.partition("=")[0].strip() for item in overrides}
        lines = [_describe(e, text, source, overridden) for e in err.errors()]
        raise InputError(f"{source}: {len(lines)} problem(s):\n" + "\n".join(lines)) from None


def _apply_override(data: dict, item: str) -> None:
    """Set data[key] from "dotted.key[index].key=value" (value in TOML syntax, else a string)."""
    key, sep, raw = item.partition("=")
    if not sep or not key.strip():
        raise InputError(f"--set {item!r}: expected KEY=VALUE, e.g. solver.dt=5e-4")
    try:
        value = tomllib.loads(f"v = {raw.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw.strip()  # a bare word: take it as a string
    path: list[str | int] = []
    for part in key.strip().split("."):
        name, _, rest = part.partition("[")
        path.append(name)
        path.extend(int(i) for i in re.findall(r"(\d+)\]", "[" + rest) if rest)
    node = data
    for here, nxt in zip(path[:-1], path[1:], strict=True):
        try:
            if isinstance(here, int):
                node = node[here]
            else:
                node = node.setdefault(here, [] if isinstance(nxt, int) else {})
        except (IndexError, TypeError, AttributeError):
            raise InputError(f"--set {item!r}: no {here!r} in the scenario") from None
    try:
        node[path[-1]] = value
    except (IndexError, TypeError):
        raise InputError(f"--set {item!r}: no {path[-1]!r} in the scenario") from None


def _describe(error: dict, text: str, source: str, overridden: set[str]) -> str:
    loc = [p for p in error["loc"] if not (isinstance(p, str) and p in _TAGS)]
    key = ".".join(str(p) if isinstance(p, str) else f"[{p}]" for p in loc).replace(".[", "[")
    line = None if key in overridden else _line_of(text, loc)
    where = "--set " if key in overridden else (f"line {line}: " if line else "")
    msg = error["msg"]
    if error["type"] == "extra_forbidden":
        tag = next((p for p in error["loc"] if isinstance(p, str) and p in _TAGS), None)
        allowed = list(_TAGS[tag].model_fields) if tag else _allowed(loc[:-1])
        msg = f"unknown key; allowed keys here: {', '.join(allowed)}"
    elif error["type"] == "missing":
        msg = "missing (required)"
    elif "input" in error and not isinstance(error["input"], dict | list):
        msg += f" (got {error['input']!r})"
    return f"  {where}{key}: {msg}"


_TAGS = {"semicircular_arch": ArchStructure, "running_bond_wall": WallStructure,
         "blocks": BlocksStructure, "semicircular_arch_3d": Arch3dStructure,
         "wall_3d": Wall3dStructure, "pier_3d": Pier3dStructure, "bridge_3d": Bridge3dStructure,
         "mesh": MeshStructure}
_TABLES = {"structure": Structure, "laws": LawSpec, "loads": Loads, "solver": SolverSpec,
           "detection": DetectionSpec, "output": OutputSpec}


def _allowed(loc: list) -> list[str]:
    names = [p for p in loc if isinstance(p, str)]
    if not names:
        return list(Scenario.model_fields)
    nested = {("loads", "point_loads"): PointLoad, ("loads", "settlements"): Settlement,
              ("loads", "ground_motion"): GroundMotionSpec}
    if tuple(names[:2]) in nested:
        return list(nested[tuple(names[:2])].model_fields)
    if names[0] == "structure":
        return sorted({k for m in _TAGS.values() for k in m.model_fields})
    model = _TABLES.get(names[0])
    return list(model.model_fields) if model is not None else []


def _line_of(text: str, loc: list) -> int | None:
    """1-based line of key loc[-1] inside the table loc[:-1] (array tables by index)."""
    names = [p for p in loc if isinstance(p, str)]
    if not names:
        return None
    table, key = names[:-1], names[-1]
    index = next((p for p in loc if isinstance(p, int)), None)
    current: list[str] = []
    seen: dict[str, int] = {}
    for n, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if line.startswith("[["):
            current = line.strip("[] ").split(".")
            name = ".".join(current)
            seen[name] = seen.get(name, -1) + 1
            current = current + [f"#{seen[name]}"]
        elif line.startswith("["):
            current = line.strip("[] ").split(".")
        elif "=" in line and line.split("=", 1)[0].strip() == key:
            here = [p for p in current if not p.startswith("#")]
            idx = next((int(p[1:]) for p in current if p.startswith("#")), None)
            if here == table and (index is None or idx == index):
                return n
    for n, raw in enumerate(text.splitlines(), start=1):
        if raw.strip().strip("[]") == ".".join(names):
            return n
    return None


def _first_error(err: ValidationError) -> str:
    e = err.errors()[0]
    return f"{'.'.join(str(p) for p in e['loc'])}: {e['msg']}"
