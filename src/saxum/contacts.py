"""Contacts: the candidate/antagonist pairs found by detection, as structure-of-arrays.

A contact alpha joins a candidate body (which carries the contact point) and an antagonist body
(which carries the frame). In 2D the frame is (t, n), n the antagonist's outward face normal and
t = (n_y, -n_x), so that (t, n) is right-handed; local vectors are stored as (t, n) components.
Each point carries the `area` of the contact face it stands for, which laws in stresses need.
A side is a rigid body or nodes of a deformable block (`side_kind`, design-deformable-and-
joints.md section 3).
`key` identifies a contact from one step to the next (same bodies, same pair of edges, same end
of the common segment), so that the solver can start from the previous impulses and the joint
laws keep their state (slip, damage, history, crush: saxum.laws) and the _g0 laws their initial gap.
Detection writes contacts in increasing key order, which makes matching a linear merge.
"""

import numba as nb
import numpy as np

from .laws import LawKind

__all__ = ["Contacts"]


class Contacts:
    """Preallocated contact arrays; the first `count` rows are valid."""

    def __init__(self, dim: int = 2, capacity: int = 64) -> None:
        self.dim = dim
        self.count = 0
        self._allocate(max(capacity, 1))

    def _allocate(self, capacity: int) -> None:
        d = self.dim
        self.capacity = capacity
        self.candidate = np.zeros(capacity, dtype=np.int32)
        """Candidate body index, shape [capacity], int32."""
        self.antagonist = np.zeros(capacity, dtype=np.int32)
        """Antagonist body index, shape [capacity], int32."""
        self.key = np.zeros(capacity, dtype=np.int64)
        """Identity of the contact across steps, shape [capacity], int64."""
        self.law = np.zeros(capacity, dtype=np.int32)
        """Index into Model.laws, shape [capacity], int32."""
        self.point = np.zeros((capacity, d))
        """Contact point on the candidate [m], shape [capacity, dim], float64."""
        self.frame = np.zeros((capacity, d, d))
        """Rows: t, n (2D) or t, n, s (3D) in world coordinates, shape [capacity, dim, dim]."""
        self.gap = np.zeros(capacity)
        """Gap on the predicted configuration [m] (negative: interpenetration), shape [capacity]."""
        self.impulse = np.zeros((capacity, d))
        """Contact impulse R over the step in the local frame [N s], shape [capacity, dim]."""
        self.area = np.zeros(capacity)
        """Share of the contact face the point stands for [m^2; 2D: m^2/m, a length along the
        face], shape [capacity]: the contact's stress is its force / area. The points of a face
        contact share its overlap (the part within the alert distance), so a joint's areas sum
        to its overlap length (2D) or polygon area (3D); a vertex against a face gets a small
        area, an edge against an edge (3D) none (saxum.detection.polygons, .polyhedra)."""
        self.side_kind = np.zeros((capacity, 2), dtype=np.int8)
        """Kind of the (candidate, antagonist) sides: 0 a rigid body, 1 nodes of a deformable
        block (saxum.bodies.fe), shape [capacity, 2], int8."""
        self.side_node = np.zeros((capacity, 2, d), dtype=np.int32)
        """FE sides: the nodes whose velocities make the side's material point (a candidate:
        one boundary node), shape [capacity, 2, dim], int32."""
        self.side_weight = np.zeros((capacity, 2, d))
        """FE sides: the shape-function weights of side_node at the point [-] (a candidate
        node: 1), shape [capacity, 2, dim]."""
        self.slip = np.zeros((capacity, d - 1))
        """Tangential jump s of a joint law [m], shape [capacity, dim - 1]: the spring's
        elongation (ELASTIC) or the jump since bonding (COHESIVE); 0 for other laws."""
        self.damage = np.zeros(capacity)
        """Damage d in [0, 1] of a COHESIVE joint [-] (1: a Coulomb contact), shape
        [capacity]; 0 for other laws. It never decreases."""
        self.history = np.zeros(capacity)
        """Largest scaled opening kappa reached by a COHESIVE joint [-] (saxum.laws), shape
        [capacity]; 0 for other laws."""
        self.crush = np.zeros(capacity)
        """Plastic closure w of a COHESIVE joint's compression cap [m] (saxum.laws), shape
        [capacity]; 0 for other laws and joints that have not crushed. It never decreases."""
        self.initial_gap = np.zeros(capacity)
        """g0 of a _g0 law [m] (ContactLaw.initial_gap): its gap at the first step of the run
        (Simulation.step), shape [capacity]; 0 for other laws and for contacts that appeared
        later."""

    def reserve(self, capacity: int) -> None:
        """Make room for `capacity` contacts; existing rows are kept."""
        if capacity <= self.capacity:
            return
        old = {k: getattr(self, k)[: self.count].copy() for k in self._fields()}
        self._allocate(max(capacity, 2 * self.capacity))
        for k, a in old.items():
            getattr(self, k)[: self.count] = a

    @staticmethod
    def _fields() -> tuple[str, ...]:
        return ("candidate", "antagonist", "key", "law", "point", "frame", "gap", "impulse",
                "area", "side_kind", "side_node", "side_weight", "slip", "damage", "history",
                "crush", "initial_gap")

    def copy(self) -> "Contacts":
        """A deep copy of the valid rows."""
        c = Contacts(self.dim, max(self.count, 1))
        c.count = self.count
        for k in self._fields():
            getattr(c, k)[: self.count] = getattr(self, k)[: self.count]
        return c

    def warm_start_from(self, previous: "Contacts", law_kind: np.ndarray | None = None, *,
                        parallel: bool = False) -> int:
        """Copy the impulses, the joint state (slip, damage, history, crush) and the initial gap
        of persisting contacts (same key) from `previous`; returns how many. A new contact starts
        with zero impulse, slip and initial gap, and, under a COHESIVE law (law_kind:
        Model.law_kind), fully damaged: a joint that was not bonded at the start does not bond
        later. parallel: by blocks of contacts on numba's threads (_carry_parallel, the same
        rows)."""
        # whole arrays and the counts: fifteen slices cost more than the merge on a small model
        return (_carry_parallel if parallel else _carry)(
            self.count, previous.count, self.key, previous.key, self.impulse, previous.impulse,
            self.slip, previous.slip, self.damage, previous.damage, self.history,
            previous.history, self.crush, previous.crush, self.initial_gap,
            previous.initial_gap, self.law, _NO_LAWS if law_kind is None else law_kind,
        )


_COHESIVE = int(LawKind.COHESIVE)
_NO_LAWS = np.zeros(0, dtype=np.int8)


@nb.njit(cache=True)
def _carry(count, old_count, key, old_key, impulse, old_impulse, slip, old_slip, damage,
           old_damage, history, old_history, crush, old_crush, initial_gap, old_initial_gap,
           law, law_kind):
    """Merge of two key lists (the first count and old_count rows) that detection writes in
    increasing order: O(count), no sort; rows of a key found in old_key are copied, the
    others reset (module doc)."""
    return _carry_range(0, count, 0, old_count, key, old_key, impulse, old_impulse, slip,
                        old_slip, damage, old_damage, history, old_history, crush, old_crush,
                        initial_gap, old_initial_gap, law, law_kind)


_CARRY_BLOCK = 4096
"""Contacts per block of _carry_parallel."""


@nb.njit(parallel=True, cache=True)
def _carry_parallel(count, old_count, key, old_key, impulse, old_impulse, slip, old_slip,
                    damage, old_damage, history, old_history, crush, old_crush, initial_gap,
                    old_initial_gap, law, law_kind):
    """_carry by blocks of contacts on numba's threads, the same rows: each block's merge
    starts at the first old key not below its first key (a bisection)."""
    hits = np.zeros(-(-count // _CARRY_BLOCK), dtype=np.int64)
    for b in nb.prange(hits.shape[0]):
        lo = b * _CARRY_BLOCK
        hi = min(count, lo + _CARRY_BLOCK)
        first = np.searchsorted(old_key[:old_count], key[lo])
        hits[b] = _carry_range(lo, hi, first, old_count, key, old_key, impulse, old_impulse, slip,
                               old_slip, damage, old_damage, history, old_history, crush,
                               old_crush, initial_gap, old_initial_gap, law, law_kind)
    return hits.sum()


@nb.njit(inline="always")
def _carry_range(lo, hi, first, old_count, key, old_key, impulse, old_impulse, slip, old_slip,
                 damage, old_damage, history, old_history, crush, old_crush, initial_gap,
                 old_initial_gap, law, law_kind):
    """_carry's merge for the rows lo .. hi - 1, from old_key[first] to old_key[old_count - 1]
    (no old key before it is at least key[lo]); returns the rows found."""
    hits = 0
    k = first
    for a in range(lo, hi):
        while k < old_count and old_key[k] < key[a]:
            k += 1
        # element by element: a slice assignment per contact costs more than the merge itself
        if k < old_count and old_key[k] == key[a]:
            for r in range(impulse.shape[1]):
                impulse[a, r] = old_impulse[k, r]
            for r in range(slip.shape[1]):
                slip[a, r] = old_slip[k, r]
            damage[a] = old_damage[k]
            history[a] = old_history[k]
            crush[a] = old_crush[k]
            initial_gap[a] = old_initial_gap[k]
            hits += 1
        else:
            for r in range(impulse.shape[1]):
                impulse[a, r] = 0.0
            for r in range(slip.shape[1]):
                slip[a, r] = 0.0
            cracked = law_kind.shape[0] > 0 and law_kind[law[a]] == _COHESIVE
            damage[a] = 1.0 if cracked else 0.0
            history[a] = 0.0
            crush[a] = 0.0
            initial_gap[a] = 0.0
    return hits
