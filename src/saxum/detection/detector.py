"""Detection stage of the time step: world geometry, broad phase (refreshed), narrow phase.

Broad and narrow phases run over contactors, the convex parts of the bodies (Model.contactor_*):
one per body, or several for a cluster (a non-convex block). Pairs of contactors of one body are
dropped; the contacts found are then written with their bodies as candidate and antagonist
(keys stay those of the contactor pair), so the solver sees bodies only."""

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from ..bodies import rigid3d
from ..bodies.fe3d import principal_axes
from ..bodies.rigid2d import contactor_coordinates, world_geometry, world_geometry_range
from ..contacts import Contacts
from ..errors import InputError, OverlapError
from ..model import BodyKind, Model, Shape
from .broadphase import bounding_boxes, grid_pairs, grid_pairs_parallel, sort_pairs
from .fe_nodes import flat_sides, node_contacts
from .fe_nodes3d import node_contacts_3d
from .polygons import PAIR_BLOCK, polygon_contacts, polygon_contacts_parallel
from .polyhedra import (
    MAX_POINTS,
    PAIR_BLOCK_3D,
    SLOTS,
    polyhedron_contacts,
    polyhedron_contacts_parallel,
)
from .round import round_contacts

__all__ = ["DetectionSettings", "Detector", "PolyhedronDetector", "detector_for"]


@dataclass(frozen=True)
class DetectionSettings:
    """alert [m]: pairs closer than this become contacts (default: 2 % of the smallest free
    block's size, sqrt(area)). margin [m]: extra padding of the bounding boxes so that the
    broad phase need only run every `refresh_every` steps (default: equal to alert); it also runs
    as soon as a body has moved by more than margin/2 since the last time.
    interpenetration [m]: the largest interpenetration that the gap-based law leaves at the end
    of a step before it projects the positions (default: 0.1 % of alert).
    per_pair: the laws without their own alert (ContactLaw.alert) take, instead of alert, 2 %
    of the size of the smaller block of each pair (as LMGC90's users set an alert per
    see-table from the blocks it names); alert then still sets the margin, the closed gap and
    the interpenetration.
    initial_overlap [m]: the deepest interpenetration accepted at the start (default: 1e-6
    of the largest block's size, round-off of generated geometry); e.g. the micrometre
    interpenetrations of a state imported from LMGC90 (saxum.lmgc90)."""

    alert: float | None = None
    margin: float | None = None
    refresh_every: int = 10
    interpenetration: float | None = None
    per_pair: bool = False
    initial_overlap: float | None = None

    def __post_init__(self) -> None:
        for name in ("alert", "margin", "interpenetration", "initial_overlap"):
            value = getattr(self, name)
            if value is not None and not (np.isfinite(value) and value > 0.0):
                raise InputError(f"detection.{name} must be a finite length > 0 [m], got {value}")
        if self.refresh_every < 1:
            raise InputError(f"detection.refresh_every must be >= 1, got {self.refresh_every}")


@nb.njit(cache=True)
def _motion_since(q, q_ref, radius, motion, turn):
    """motion[b] [m]: upper bound of the displacement of any point of body b since q_ref,
    turn[b] [rad]: its rotation; returns the largest motion."""
    return _motion_range(0, q.shape[0], q, q_ref, radius, motion, turn)


_BODY_BLOCK = 4096
"""Bodies per block of _geometry_parallel."""


@nb.njit(parallel=True, cache=True)
def _geometry_parallel(q, q_ref, radius, motion, turn, vertex_start, vertex_local,
                       direction_local, vertices, directions):
    """world_geometry and _motion_since by blocks of bodies on numba's threads (the same
    numbers: each body's own, and a largest value does not depend on the order); returns
    the largest motion [m]."""
    worst = np.zeros(-(-q.shape[0] // _BODY_BLOCK))
    for k in nb.prange(worst.shape[0]):
        lo = k * _BODY_BLOCK
        hi = min(q.shape[0], lo + _BODY_BLOCK)
        world_geometry_range(lo, hi, q, vertex_start, vertex_local, direction_local, vertices,
                             directions)
        worst[k] = _motion_range(lo, hi, q, q_ref, radius, motion, turn)
    return worst.max()


@nb.njit(inline="always")
def _motion_range(lo, hi, q, q_ref, radius, motion, turn):
    """_motion_since of the bodies lo .. hi - 1."""
    worst = 0.0
    for b in range(lo, hi):
        turn[b] = abs(q[b, 2] - q_ref[b, 2])
        motion[b] = np.hypot(q[b, 0] - q_ref[b, 0], q[b, 1] - q_ref[b, 1]) + turn[b] * radius[b]
        worst = max(worst, motion[b])
    return worst


def _contactor_radius(model: Model) -> np.ndarray:
    """Largest distance from each contactor's centroid to its vertices [m]."""
    start = model.contactor_vertex_start
    owner = np.repeat(np.arange(len(start) - 1), np.diff(start))
    reach = np.linalg.norm(model.vertex_local - model.contactor_centre_local[owner], axis=1)
    return np.maximum.reduceat(reach, start[:-1])


class Detector:
    """Finds the contacts of a configuration q. Owns its work arrays; no allocation per step
    except when the contact or pair count grows."""

    def __init__(self, model: Model, settings: DetectionSettings | None = None) -> None:
        settings = settings or DetectionSettings()
        free = np.isin(model.body_kind, (BodyKind.FREE, BodyKind.DEFORMABLE))
        scale = float(model.body_size[free].min()) if free.any() else float(model.body_size.min())
        self.model = model
        self.alert = settings.alert if settings.alert is not None else 0.02 * scale
        unset = np.nan if settings.per_pair else self.alert
        self.law_alert = np.array([unset if law.alert is None else law.alert
                                   for law in model.laws], dtype=np.float64)
        """Alert distance per law [m]: ContactLaw.alert, or where it has none alert, or NaN
        with per_pair (the pair's: polygons.alert_of_pair)."""
        owner = model.contactor_body
        self._body_alert = 0.02 * model.body_size[owner]
        """[m] per contactor (its body's), of which a pair takes the smaller where its law's
        alert is NaN."""
        self.widest_alert = float(max(np.nanmax(self.law_alert, initial=self.alert),
                                      self._body_alert[free[owner]].max(initial=0.0)
                                      if np.isnan(self.law_alert).any() else 0.0))
        """The largest alert distance of any law [m], which the broad phase pads for."""
        self.margin = settings.margin if settings.margin is not None else self.alert
        self.refresh_every = settings.refresh_every
        self.initial_overlap = settings.initial_overlap
        self.reference_bias = 0.1 * self.alert
        self.closed_gap = 1e-6 * self.alert
        """Gaps below this [m] count as closed: the round-off of geometry built touching."""
        self.interpenetration = (settings.interpenetration if settings.interpenetration
                                 is not None else 1e-3 * self.alert)
        """Largest interpenetration [m] the gap-based law leaves without projecting."""
        n = model.body_count
        self._clustered = model.clustered
        self._cq = np.empty((len(owner), model.body_q0.shape[1])) if model.clustered else None
        """Coordinates of the contactors of a clustered model (contactor_coordinates)."""
        self._group = model.body_group[owner]
        self._radius = _contactor_radius(model) if model.clustered else model.body_radius
        """Per contactor, its body's group and its radius about its centroid [m]."""
        self._shape = model.body_shape[owner]
        self._round_radius = model.body_round_radius[owner]
        self._mobile = free[owner]
        nc = len(owner)
        self._wv = np.empty_like(model.vertex_local)
        self._wn = np.empty_like(model.vertex_local)
        self._lo = np.empty((nc, model.dim))
        self._hi = np.empty((nc, model.dim))
        self._pairs = np.empty((4 * nc + 16, 2), dtype=np.int32)
        # A body's padded box, however it turns, fits in a square (a cube in 3D) of side
        # 2 (radius + pad):
        # bodies far larger than the median go through the broad phase's direct test, and
        # the grid's cell fits every other body's box.
        extent = 2.0 * (self._radius + 0.5 * (self.widest_alert + self.margin))
        self._large = extent > 4.0 * np.median(extent)
        self._cell = float(extent[~self._large].max() if (~self._large).any() else extent.max())
        self.pair_count = 0
        self._q_ref = np.zeros_like(model.body_q0)
        self._motion = np.zeros(n)
        self._turn = np.zeros(n)
        self._faces = np.zeros((len(self._pairs), 3), dtype=np.int32)
        """The narrow phase's choice of faces per pair on q_ref (polygon_contacts)."""
        self._slack = np.zeros((len(self._pairs), 2))
        self._since_refresh = self.refresh_every  # the first detection runs the broad phase
        self.refresh_count = 0
        self.kept_faces = 0
        """Pairs of the last detection whose choice of faces was kept (polygon_contacts)."""
        self._fe_pairs = np.empty((0, 2), dtype=np.int32)
        """Pairs with a deformable block (saxum.detection.fe_nodes), split off the broad
        phase's list, which keeps the rigid pairs."""
        self._flat_side = None if model.fe is None else flat_sides(
            model.fe.node_x0, model.fe.facet_node, model.fe.facet_start)
        """Deformable blocks: each boundary facet's straight side (fe_nodes.flat_sides), by
        which the node contacts on it are keyed."""
        self._round_pairs = np.empty((0, 2), dtype=np.int32)
        """Pairs with a disc or sphere (saxum.detection.round), split off likewise."""
        if model.clustered and model.fe is not None:
            raise InputError("clusters (non-convex blocks) and deformable blocks in one model "
                             "are not supported yet; split the clusters into blocks or make "
                             "the deformable blocks rigid")
        if model.has_round and model.fe is not None:
            raise InputError("discs (spheres) and deformable blocks in one model are not "
                             "supported yet; make the deformable blocks rigid or leave out "
                             "the discs")
        mobile_groups = np.zeros(len(model.group_names), dtype=bool)
        mobile_groups[model.body_group[free]] = True
        self._no_contact = bool((model.group_law[mobile_groups] < 0).any())
        """Some group of free blocks has a NO_CONTACT pair: the broad phase drops its pairs."""
        self.parallel = False
        """Run the world geometry, the broad phase (2D) and the narrow phase on numba's threads
        (_geometry_parallel, grid_pairs_parallel, polygon_contacts_parallel; in 3D
        _geometry_parallel_3d, polyhedron_contacts_parallel: the same contacts bit for bit):
        Simulation sets it where the solver's threads are set."""
        self._scratch = Contacts(model.dim)
        """The parallel narrow phase's rows per block of pairs."""
        self._pair_scratch = np.empty((0, 2), dtype=np.int32)
        """The parallel broad phase's pairs per block of bodies (grid_pairs_parallel)."""
        self._block_start = np.zeros(1, dtype=np.int64)
        """Where the parallel narrow phase's blocks of pairs began their contacts last time."""
        self._in_place = False
        """Whether the last parallel narrow phase found as many contacts per block as the one
        before it: the next tries writing its blocks in place (polygon_contacts_parallel)."""
        self.in_place_count = 0
        """Parallel narrow phases that wrote their blocks in place (no copy)."""
        self.slots = max(2, int(model.law_points.max(initial=2)))
        """Keys per pair of faces: the most points a face contact of the model's laws has."""
        self._round_room = (2 + model.max_vertices if (model.body_shape == Shape.CAPSULE).any()
                            else 1)
        """The most contacts of a pair with a round body: a disc's 1, a capsule's two ends
        and the other body's vertices (3D: and edges) against its side."""

    def detect(self, q: np.ndarray, contacts: Contacts, node_x: np.ndarray | None = None) -> None:
        """Fill `contacts` (impulses untouched) with the contacts of configuration q and, for
        deformable blocks, node positions node_x [m] (default: the reference ones)."""
        self._node_x = node_x
        moved = self._geometry(q)
        refresh = self._since_refresh >= self.refresh_every or moved > 0.5 * self.margin
        if refresh:
            self._refresh(q)
        self._since_refresh += 1
        self._narrow_phase(self._contactor_q(q), contacts, refresh)
        if self._clustered:
            owner = self.model.contactor_body
            n = contacts.count
            contacts.candidate[:n] = owner[contacts.candidate[:n]]
            contacts.antagonist[:n] = owner[contacts.antagonist[:n]]

    def _contactor_q(self, q: np.ndarray) -> np.ndarray:
        """Coordinates per contactor, which the broad and narrow phases read: q itself unless
        some body is a cluster."""
        if not self._clustered:
            return q
        m = self.model
        contactor_coordinates(q, m.contactor_body, m.contactor_centre_local, self._cq)
        return self._cq

    def _geometry(self, q: np.ndarray) -> float:
        """World coordinates of what the narrow phase needs, for configuration q (on numba's
        threads where parallel); returns an upper bound of the displacement of any point
        since the last broad phase [m]."""
        m = self.model
        if self.parallel:
            return _geometry_parallel(q, self._q_ref, m.body_radius, self._motion, self._turn,
                                      m.body_vertex_start, m.vertex_local,
                                      m.edge_normal_local, self._wv, self._wn)
        world_geometry(q, m.body_vertex_start, m.vertex_local, m.edge_normal_local, self._wv,
                       self._wn)
        return _motion_since(q, self._q_ref, self.model.body_radius, self._motion, self._turn)

    def _narrow_phase(self, q: np.ndarray, contacts: Contacts, refresh: bool) -> None:
        """Contacts of the broad phase's pairs; refresh: the broad phase has just run."""
        m = self.model
        contacts.reserve(self.slots * self.pair_count
                         + self._round_room * len(self._round_pairs))
        out = (contacts.candidate, contacts.antagonist, contacts.key, contacts.law,
               contacts.point, contacts.frame, contacts.gap, contacts.area)
        args = (self._pairs, self.pair_count, self._wv, self._wn, m.edge_length,
                m.contactor_vertex_start, self._group, m.group_law,
                m.law_points if self.slots > 2 else None, self.slots, self.alert,
                self.law_alert, self._body_alert, self.reference_bias, m.max_vertices, q,
                self._radius, *self._contactor_motion(), refresh, self._faces, self._slack)
        if self.parallel:
            self._scratch.reserve(self.slots * self.pair_count)
            s = self._scratch
            tried = self._blocks_in_place(PAIR_BLOCK)
            contacts.count, self.kept_faces, self._in_place = polygon_contacts_parallel(
                *args, self._block_start, tried, *out,
                s.candidate, s.antagonist, s.key, s.law, s.point, s.frame, s.gap, s.area)
            self.in_place_count += tried and self._in_place
        else:
            contacts.count, self.kept_faces = polygon_contacts(*args, *out)
        if m.has_round:
            self._round_contacts(q, contacts)
        if m.fe is not None:  # side_kind is read and written for deformable blocks only
            contacts.side_kind[: contacts.count] = 0
            self._node_contacts(q, contacts)

    def _blocks_in_place(self, block: int) -> bool:
        """Whether the parallel narrow phase, by blocks of `block` pairs, tries writing its
        blocks in place: the last one found as many contacts per block as the one before it,
        and the blocks are as many (else _block_start is reset)."""
        blocks = -(-self.pair_count // block)
        if len(self._block_start) != blocks + 1:
            self._block_start = np.zeros(blocks + 1, dtype=np.int64)
            self._in_place = False
        return self._in_place

    def _contactor_motion(self) -> tuple[np.ndarray, np.ndarray]:
        """(motion [m], turn [rad]) since the last broad phase per contactor, its body's."""
        if not self._clustered:
            return self._motion, self._turn
        owner = self.model.contactor_body
        return self._motion[owner], self._turn[owner]

    def _node_contacts(self, q: np.ndarray, contacts: Contacts) -> None:
        """Append the contacts of deformable blocks' boundary nodes, in increasing key order."""
        m = self.model
        fe = m.fe
        node_x = fe.node_x0 if self._node_x is None else self._node_x
        first = contacts.count
        room = int(np.diff(fe.boundary_start).max()) + m.max_vertices
        contacts.reserve(first + len(self._fe_pairs) * room)
        count = self._node_kernel(q, node_x, first, contacts)
        while count < 0:  # (3D: edges crossing edges filled the arrays)
            contacts.reserve(2 * contacts.capacity)
            count = self._node_kernel(q, node_x, first, contacts)
        order = first + np.argsort(contacts.key[first:count], kind="stable")
        for name in contacts._fields():
            array = getattr(contacts, name)
            array[first:count] = array[order]
        contacts.count = count

    def _round_contacts(self, q: np.ndarray, contacts: Contacts) -> None:
        """Append the contacts of the pairs with a disc or sphere (saxum.detection.round),
        keyed above the polygons' (polyhedra's) and in increasing key order."""
        m = self.model
        # the features a round body can touch on the other body of a pair; a capsule: its
        # two ends each a disc's, and the polygon's vertices against its side
        faces, edges = (self._max_faces, self._max_edges) if m.dim == 3 else (
            m.max_vertices, 3 * m.max_vertices if self._round_room > 1 else 0)
        features = faces + edges + m.max_vertices
        if m.dim == 3 and self._round_room > 1:  # a 3D capsule: its two ends each a
            features *= 3  # sphere's, the polyhedron's edges and vertices against its side
        contacts.count = round_contacts(
            self._round_pairs, len(self._round_pairs), q, self._wv, self._wn, m.edge_length,
            m.contactor_vertex_start, m.contactor_face_start, m.face_vertex_start,
            m.face_vertex, m.contactor_edge_start, m.edge_vertex, self._shape,
            self._round_radius, self._group,
            m.group_law, self.alert, self.law_alert, self._body_alert, faces, edges,
            self._round_key_base(), features, contacts.count,
            contacts.candidate, contacts.antagonist, contacts.key, contacts.law,
            contacts.point, contacts.frame, contacts.gap, contacts.area)

    def _round_key_base(self) -> int:
        """The first key above those of polygon (polyhedron) pairs, where the keys of
        deformable (round) pairs start."""
        m = self.model
        return 2 * self.slots * len(m.contactor_body) ** 2 * m.max_vertices ** 2

    def _node_kernel(self, q: np.ndarray, node_x: np.ndarray, first: int,
                     contacts: Contacts) -> int:
        """Write the node contacts of the deformable pairs from row `first` on
        (saxum.detection.fe_nodes); returns the new count."""
        m = self.model
        fe = m.fe
        key_base = self._round_key_base()
        return node_contacts(
            self._fe_pairs, len(self._fe_pairs), fe.fe_index, q, node_x, fe.boundary_start,
            fe.boundary_node, fe.node_side, fe.facet_start, fe.facet_node, self._flat_side,
            self._wv, self._wn, m.edge_length, m.body_vertex_start, m.body_group, m.group_law,
            self.alert, self.law_alert, self._body_alert, key_base, first, contacts.candidate,
            contacts.antagonist, contacts.key, contacts.law, contacts.point, contacts.frame,
            contacts.gap, contacts.area, contacts.side_kind, contacts.side_node,
            contacts.side_weight)

    def _refresh(self, q: np.ndarray) -> None:
        m = self.model
        bounding_boxes(self._wv, m.contactor_vertex_start,
                       0.5 * (self.widest_alert + self.margin), self._lo, self._hi)
        while True:
            if self.parallel:
                if len(self._pair_scratch) != len(self._pairs):
                    self._pair_scratch = np.empty_like(self._pairs)
                count = grid_pairs_parallel(self._lo, self._hi, self._mobile, self._large,
                                            self._cell, self._pairs, self._pair_scratch)
            else:
                count = grid_pairs(self._lo, self._hi, self._mobile, self._large, self._cell,
                                   self._pairs)
            if count <= len(self._pairs):
                break
            self._pairs = np.empty((2 * count, 2), dtype=np.int32)
        if len(self._faces) < len(self._pairs):
            self._faces = np.zeros((len(self._pairs), 3), dtype=np.int32)
            self._slack = np.zeros((len(self._pairs), 2))
        sort_pairs(self._pairs, count, len(m.contactor_body))
        if self._no_contact or self._clustered:
            count = self._drop_no_contact(count)
        count = self._split_off(count)
        self.pair_count = count
        self._q_ref[:] = q
        self._since_refresh = 0
        self.refresh_count += 1

    def _drop_no_contact(self, count: int) -> int:
        """Drop the pairs whose groups have no law (NO_CONTACT) and those of two contactors of
        one body from the first `count` pairs, keeping the order; returns how many are left."""
        pairs = self._pairs[:count]
        g = self._group[pairs]
        keep = self.model.group_law[g[:, 0], g[:, 1]] >= 0
        if self._clustered:
            owner = self.model.contactor_body[pairs]
            keep &= owner[:, 0] != owner[:, 1]
        kept = pairs[keep]
        self._pairs[: len(kept)] = kept
        return len(kept)

    def _split_off(self, count: int) -> int:
        """Move the pairs with a deformable block into _fe_pairs and those with a round body
        into _round_pairs, out of the first `count` pairs, keeping the order of each list;
        returns how many are left (polygon pairs)."""
        m = self.model
        if m.fe is not None:
            deformable = (m.fe.fe_index[self._pairs[:count]] >= 0).any(axis=1)
            self._fe_pairs = self._pairs[:count][deformable].copy()
            kept = self._pairs[:count][~deformable]
            self._pairs[: len(kept)] = kept
            count = len(kept)
        if m.has_round:
            rounded = (self._shape[self._pairs[:count]] != 0).any(axis=1)
            self._round_pairs = self._pairs[:count][rounded].copy()
            kept = self._pairs[:count][~rounded]
            self._pairs[: len(kept)] = kept
            count = len(kept)
        return count

    def checkpoint(self) -> dict:
        """The detector's own state, which a bit-identical restart needs: the broad phase's
        pair list (with the pairs of deformable blocks after the others), the configuration it
        was built on and the steps since."""
        pairs = np.concatenate((self._pairs[: self.pair_count], self._fe_pairs,
                                self._round_pairs))
        return {"pairs": pairs, "pair_count": len(pairs),
                "q_ref": self._q_ref.copy(), "since_refresh": self._since_refresh,
                "refresh_count": self.refresh_count}

    def restore(self, saved: dict) -> None:
        """Return to a state taken by checkpoint()."""
        count = int(saved["pair_count"])
        if len(self._pairs) < count:
            self._pairs = np.empty((2 * count, 2), dtype=np.int32)
        self._pairs[:count] = saved["pairs"]
        count = self._split_off(count)
        if len(self._faces) < len(self._pairs):
            self._faces = np.zeros((len(self._pairs), 3), dtype=np.int32)
            self._slack = np.zeros((len(self._pairs), 2))
        self._faces[:, 0] = 0  # no kept choice: the full test until the next broad phase
        self._in_place = False
        self.pair_count = count
        self._q_ref[:] = saved["q_ref"]
        self._since_refresh = int(saved["since_refresh"])
        self.refresh_count = int(saved["refresh_count"])

    def contacts_at(self, q: np.ndarray, node_x: np.ndarray | None = None) -> Contacts:
        """The contacts at configuration q [m, rad] (and deformable blocks' node positions
        node_x [m], default the reference ones), found with a fresh broad phase."""
        probe = Contacts(self.model.dim)
        self._since_refresh = self.refresh_every
        self.detect(q, probe, node_x)
        return probe

    def check_overlaps(self, q: np.ndarray, *, tolerance: float | None = None) -> None:
        """Raise OverlapError naming the deepest interpenetrating pair at configuration q.

        tolerance [m]: overlaps up to this depth are accepted (default: the settings'
        initial_overlap, else 1e-6 of the largest block size, i.e. round-off of generated
        geometry).
        """
        tol = next((t for t in (tolerance, self.initial_overlap) if t is not None),
                   1e-6 * float(self.model.body_size.max()))
        probe = self.contacts_at(q)
        gaps = probe.gap[: probe.count]
        bad = np.flatnonzero(gaps < -tol)
        if bad.size == 0:
            return
        worst = bad[np.argmin(gaps[bad])]
        names = self.model.body_name
        a, b = probe.candidate[worst], probe.antagonist[worst]
        pairs = {(min(x, y), max(x, y)) for x, y in zip(probe.candidate[bad], probe.antagonist[bad],
                                                        strict=True)}
        raise OverlapError(
            f"blocks {names[a]!r} and {names[b]!r} overlap by {-gaps[worst]:.6g} m at the start "
            f"({len(pairs)} overlapping pair(s) in all, tolerance {tol:.3g} m); "
            "move them apart or shrink them so that they only touch"
        )


@nb.njit(cache=True)
def _largest_motion_3d(q, q_ref, radius):
    """Upper bound of the displacement of any point of any body since q_ref [m]: the centre's
    displacement plus the rotation angle 2 acos |q . q_ref| times the body's radius."""
    return _motion_range_3d(0, q.shape[0], q, q_ref, radius)


@nb.njit(parallel=True, cache=True)
def _geometry_parallel_3d(q, vertex_start, vertex_local, face_start, normal_local, wv, wn,
                          q_ref, radius):
    """rigid3d.world_geometry and _largest_motion_3d by blocks of bodies on numba's threads,
    as _geometry_parallel (the same numbers); returns the largest motion [m]."""
    worst = np.zeros(-(-q.shape[0] // _BODY_BLOCK))
    for k in nb.prange(worst.shape[0]):
        lo = k * _BODY_BLOCK
        hi = min(q.shape[0], lo + _BODY_BLOCK)
        rigid3d.world_geometry_range(lo, hi, q, vertex_start, vertex_local, face_start,
                                     normal_local, wv, wn)
        worst[k] = _motion_range_3d(lo, hi, q, q_ref, radius)
    return worst.max()


@nb.njit(inline="always")
def _motion_range_3d(lo, hi, q, q_ref, radius):
    """_largest_motion_3d of the bodies lo .. hi - 1."""
    worst = 0.0
    for b in range(lo, hi):
        d = math.sqrt((q[b, 0] - q_ref[b, 0]) ** 2 + (q[b, 1] - q_ref[b, 1]) ** 2
                      + (q[b, 2] - q_ref[b, 2]) ** 2)
        dot = abs(q[b, 3] * q_ref[b, 3] + q[b, 4] * q_ref[b, 4] + q[b, 5] * q_ref[b, 5]
                  + q[b, 6] * q_ref[b, 6])
        d += 2.0 * math.acos(min(dot, 1.0)) * radius[b]
        worst = max(worst, d)
    return worst


class PolyhedronDetector(Detector):
    """The detection stage of 3D models: convex polyhedra (saxum.detection.polyhedra), same
    broad phase, settings and checkpoints as in 2D."""

    def __init__(self, model: Model, settings: DetectionSettings | None = None) -> None:
        super().__init__(model, settings)
        self._wn = np.empty_like(model.face_normal_local)
        self._max_faces = int(np.diff(model.contactor_face_start).max())
        self._max_edges = int(np.diff(model.contactor_edge_start).max())
        self._max_face_vertices = int(np.diff(model.face_vertex_start).max())
        self._axes0 = None
        """Deformable blocks: the principal axes of their body rows at the start [n_fe, 3,
        3], which their body rows' quaternions turn (saxum.bodies.fe3d.principal_axes)."""
        if self._round_room > 1:  # a capsule's two ends, a polyhedron's edges and vertices
            self._round_room = 2 + self._max_edges + model.max_vertices
        features = self._max_faces + self._max_edges
        self.slots = SLOTS if model.law_points.max(initial=2) == 2 else 2 * SLOTS + 1
        if float(len(model.contactor_body)) ** 2 * 2 * features**2 * self.slots >= 2.0**62:
            raise InputError(
                f"{len(model.contactor_body)} blocks (cluster parts) with up to "
                f"{self._max_faces} faces and {self._max_edges} edges are too many to number "
                "their contacts in 64 bits; use blocks with fewer faces"
            )

    def _geometry(self, q: np.ndarray) -> float:
        m = self.model
        args = (q, m.body_vertex_start, m.vertex_local, m.body_face_start, m.face_normal_local,
                self._wv, self._wn)
        if self.parallel:
            return _geometry_parallel_3d(*args, self._q_ref, m.body_radius)
        rigid3d.world_geometry(*args)
        return _largest_motion_3d(q, self._q_ref, m.body_radius)

    def _round_key_base(self) -> int:
        m = self.model
        features = self._max_faces + self._max_edges
        return 2 * self.slots * len(m.contactor_body) ** 2 * features ** 2  # above polyhedra

    def _narrow_phase(self, q: np.ndarray, contacts: Contacts, refresh: bool) -> None:
        m = self.model
        points = MAX_POINTS if self.slots == SLOTS else 2 * MAX_POINTS + 1
        contacts.reserve(points * self.pair_count
                         + self._round_room * len(self._round_pairs))
        args = (self._pairs, self.pair_count, q, self._wv, self._wn, m.contactor_vertex_start,
                m.contactor_face_start, m.face_vertex_start, m.face_vertex,
                m.contactor_edge_start, m.edge_vertex, m.edge_face, self._group, m.group_law,
                m.law_points,
                self.slots, self.alert, self.law_alert, self._body_alert, self.reference_bias,
                self._max_faces, self._max_edges, self._max_face_vertices)
        out = (contacts.candidate, contacts.antagonist, contacts.key, contacts.law,
               contacts.point, contacts.frame, contacts.gap, contacts.area)
        if self.parallel:
            self._scratch.reserve(points * self.pair_count)
            s = self._scratch
            tried = self._blocks_in_place(PAIR_BLOCK_3D)
            contacts.count, self._in_place = polyhedron_contacts_parallel(
                *args, points, self._block_start, tried, *out, s.candidate, s.antagonist,
                s.key, s.law, s.point, s.frame, s.gap, s.area)
            self.in_place_count += tried and self._in_place
        else:
            contacts.count = polyhedron_contacts(*args, *out)
        if m.has_round:
            self._round_contacts(q, contacts)
        if m.fe is not None:
            contacts.side_kind[: contacts.count] = 0
            self._node_contacts(q, contacts)

    def _node_kernel(self, q: np.ndarray, node_x: np.ndarray, first: int,
                     contacts: Contacts) -> int:
        """Write the node contacts of the deformable pairs from row `first` on
        (saxum.detection.fe_nodes3d); returns the new count."""
        m = self.model
        fe = m.fe
        if self._axes0 is None:
            self._axes0 = principal_axes(m.body_q0[fe.body])
        key_base = self._round_key_base()
        if float(key_base) + float(len(node_x) + m.vertex_local.shape[0]) * float(
                len(self._wn) + len(fe.facet_node)) + float(len(m.edge_vertex)) * float(
                len(fe.edge_node)) >= 2.0 ** 62:
            raise InputError(f"{m.body_count} blocks with {len(node_x)} mesh nodes are too many "
                             "to number their contacts in 64 bits; use coarser meshes")
        return node_contacts_3d(
            self._fe_pairs, len(self._fe_pairs), fe.fe_index, q, self._axes0, node_x,
            fe.boundary_start, fe.boundary_node, fe.node_side, fe.facet_start, fe.facet_node,
            self._flat_side, self._wv, self._wn, m.body_face_start, m.face_vertex_start,
            m.face_vertex,
            m.body_vertex_start, m.body_edge_start, m.edge_vertex, m.edge_face,
            fe.edge_start, fe.edge_node, fe.edge_facet, m.body_group, m.group_law, self.alert,
            self.law_alert, self._body_alert, key_base, first,
            contacts.candidate, contacts.antagonist, contacts.key, contacts.law,
            contacts.point, contacts.frame, contacts.gap, contacts.area, contacts.side_kind,
            contacts.side_node, contacts.side_weight)


def detector_for(model: Model, settings: DetectionSettings | None = None) -> Detector:
    """The detector of the model's dimension."""
    return PolyhedronDetector(model, settings) if model.dim == 3 else Detector(model, settings)
