"""A warm start that follows the loads of an assembly at rest (our choice).

An assembly that stays at rest relative to its supports while its loads change from step to
step (a wall on a shaking base: weight plus the ground's inertial force -M a_g(t), or a driven
base) needs at each step impulses R_k in the Coulomb cones with H R_k = f_k, f_k = M (V - v_free)
the loads of the step (saxum.solver.equilibrium). A warm start from R_k-1 is off by the change
of the loads, which Gauss-Seidel spreads through the assembly only as fast as it relaxes the
softest mode, so every such step ended in the rest solution's Newton iterations.

Each rest solution found is kept as an anchor (R_a, f_a, its Newton system; at most _ANCHORS,
on the same contacts), and a later step starts from
    R = R_a + dR,   H dR = f_k - f_a,
which balances the step's loads exactly (H is the same: the assembly has not moved relative to
its supports); when R lies inside every cone it is the step's rest solution and NLGS's first
sweep confirms it (it changes nothing beyond round-off). dR comes from the anchor's Newton
system (equilibrium.LoadResponse: one solve with its factorization, an impulse change that
spares the contacts near their cone's boundary), and is reused: the loads of a rigid assembly
at rest change along the ground motion's components only (f is affine in a_g(t)), so a load
change that is a combination sum_j lambda_j df_j of the changes already answered from that
anchor (to _FIT x the solver's tolerance, relative to |f_k|, in the norm |.|_M^-1) takes
dR = sum_j lambda_j dR_j (least squares, the load changes kept orthonormal, at most _DEPTH of
them) without any solve; a misfit is answered by one solve, which adds its direction. Beyond
the ground motion's components, the loads also carry -M v_begin, the velocities that earlier
steps left (round-off and the tolerance: misfits of ~1e-8 relative on the 0.3 g wall): a kept
direction that the step's change uses least (the smallest |lambda_j|) makes room for a new
one, so that these never push out the ground motion's own.
The anchor of the last step is tried first, then the others, the first whose R is inside
every cone is taken: a periodic load comes back to the loads of earlier anchors, so that
after a cycle no new rest solution is needed. When none is, R of the last anchor is the start
anyway: the sweep does not confirm it, and the rest solution is looked for from it at once
(it balances the loads already), whose system becomes a new anchor. A load change below the
solver's tolerance needs nothing: the plain warm start then is already at rest; on two steps
in a row, the following stops until a step needs the rest solution again (an assembly at rest
under constant loads pays nothing for it).
"""

import math

import numba as nb
import numpy as np

from .base import prefixed, unprefixed
from .equilibrium import LoadResponse, rest_hypothesis

__all__ = ["START_MARGIN", "LoadFollowing"]

_DEPTH = 3
"""Load changes answered and kept per anchor (a ground motion has up to 3 components)."""
_ANCHORS = 8
"""Rest solutions kept as anchors."""
START_MARGIN = 0.01
"""The rest solution's starting margin (saxum.solver.equilibrium) after a start of this module
that the sweep did not confirm: that start balances the loads and leaves the cones only
slightly, so the Newton iterations start near it (0.01 r0 instead of 0.1 r0: 1.4 instead of 2
to 3 factorizations per rest solution on the 0.3 g wall of benchmarks/shaken_wall.py)."""
_FIT = 1e-2
"""Misfit of the loads, as a fraction of the solver's tolerance (relative to |f|_M^-1), below
which a combination of the kept answers is used: its impulses then balance the step's loads
more closely than the convergence criterion can tell."""


class _Anchor:
    """A rest solution (impulses [N s], loads M^-1/2 f [N s]) with its Newton system and the
    load changes answered from it."""

    def __init__(self, response: LoadResponse, impulse: np.ndarray, loads: np.ndarray) -> None:
        self.response = response
        self.impulse = impulse
        self.loads = loads
        # one more row than kept: a new direction joins the start before the oldest is dropped
        self.q = np.empty((_DEPTH + 1, *loads.shape))
        """Orthonormal load changes M^-1/2 df_j (first `answers` rows) ..."""
        self.dr = np.empty((_DEPTH + 1, *impulse.shape))
        """... and the impulse changes dR_j [N s] (count, dim) that balance them."""
        self.lam = np.empty(_DEPTH + 1)
        self.change = np.empty_like(loads)
        self.answers = 0

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The anchor as arrays (restored() puts it back): its system's
        (LoadResponse.checkpoint, "response." before each name), impulses, loads and the
        answers kept."""
        n = self.answers
        return {**prefixed("response", self.response.checkpoint()), "impulse": self.impulse,
                "loads": self.loads, "q": self.q[:n], "dr": self.dr[:n]}

    @classmethod
    def restored(cls, saved: dict) -> "_Anchor":
        """The anchor whose checkpoint() was `saved`."""
        response = LoadResponse.restored(unprefixed(saved, "response"))
        anchor = cls(response, saved["impulse"], saved["loads"])
        anchor.answers = n = len(saved["q"])
        anchor.q[:n], anchor.dr[:n] = saved["q"], saved["dr"]
        return anchor

    def start(self, problem, loads: np.ndarray, weight: np.ndarray, tolerance: float,
              impulse: np.ndarray, v_free: np.ndarray, v: np.ndarray) -> bool:
        """impulse = R_a + dR for the loads M^-1/2 f (module doc; one solve if the kept
        answers do not span their change), v = v_free + M^-1 H impulse [m/s, rad/s]; returns
        whether every contact's impulse is in its Coulomb cone."""
        misfit, size = _combine(loads, self.loads, self.q, self.answers, self.change, self.lam)
        if misfit > _FIT * tolerance * size:  # a new direction of the loads: one solve
            dr = self.response.impulse_change(problem, self.change / weight)
            if dr is None:  # a system kept unfactorized (a load path) found singular
                return False
            n = self.answers
            self.q[n] = self.change / misfit
            self.dr[n] = dr / misfit
            self.lam[n] = misfit
            self.answers += 1
        c = problem.contacts
        inside = _start(c.candidate, c.antagonist, problem.h_cand, problem.h_ant,
                        problem.active, problem.friction, problem.model.body_inv_mass,
                        self.impulse, self.dr, self.lam, self.answers, v_free, impulse, v)
        if self.answers > _DEPTH:
            # drop the old answer least used now (the smallest |lam_j|): the loads of a
            # ground motion keep changing along its components, the rest of the change comes
            # and goes with the velocities left by earlier steps
            drop = int(np.argmin(np.abs(self.lam[:_DEPTH])))
            for kept in (self.q, self.dr):
                kept[drop:-1] = kept[drop + 1:].copy()
            self.answers -= 1
        return inside


class LoadFollowing:
    """The anchors (rest solutions on the current contacts), the loads of the last step at
    rest and which anchor it followed."""

    def __init__(self) -> None:
        self.response = LoadResponse()
        """Filled by saxum.solver.equilibrium.rest_solution when it finds a rest solution."""
        self._anchors: list[_Anchor] = []  # the last one followed at the end
        self._keys = None  # the contacts' keys and closed contacts of the anchors
        self._closed = None
        self._last_loads = None  # M^-1/2 f of the last step at rest
        self._pending = None  # (this step's M^-1/2 f, the anchor tried), from start to record
        self._weight = (None, None)  # (inv_mass, M^-1/2 of the free bodies, as f is laid out)
        self._quiet = 0  # steps in a row whose loads did not change

    def checkpoint(self) -> dict[str, np.ndarray]:
        """What is kept between steps, as arrays (restored() puts it back; {} where nothing
        is): the anchors' (_Anchor.checkpoint, "anchor<k>." before each name, oldest first),
        their contacts' keys and closed contacts, the last step's loads and the steps whose
        loads did not change. (Between steps nothing else is: `response` is filled and moved
        into a new anchor within a step, `_pending` kept from start to record.)"""
        if self._last_loads is None:
            return {}
        out = {"keys": self._keys, "closed": self._closed, "last_loads": self._last_loads,
               "quiet": np.int64(self._quiet), "anchors": np.int64(len(self._anchors))}
        for k, anchor in enumerate(self._anchors):
            out.update(prefixed(f"anchor{k}", anchor.checkpoint()))
        return out

    @classmethod
    def restored(cls, saved: dict) -> "LoadFollowing":
        """The following whose checkpoint() was `saved` (a new one's for {})."""
        following = cls()
        if saved:
            following._keys, following._closed = saved["keys"], saved["closed"]
            following._last_loads, following._quiet = saved["last_loads"], int(saved["quiet"])
            following._anchors = [_Anchor.restored(unprefixed(saved, f"anchor{k}"))
                                  for k in range(int(saved["anchors"]))]
        return following

    def clear(self) -> None:
        self.response.clear()
        self._anchors.clear()
        self._keys = self._closed = self._last_loads = self._pending = None
        self._quiet = 0

    def _loads(self, problem, v_free: np.ndarray):
        """(closed contacts, M^-1/2 f) of the step, None if it cannot end at rest
        (saxum.solver.equilibrium.rest_hypothesis)."""
        hypothesis = rest_hypothesis(problem, v_free)
        if hypothesis is None:
            return None
        closed, slot, force = hypothesis
        inv_mass = problem.model.body_inv_mass
        if self._weight[0] is not inv_mass:
            self._weight = inv_mass, np.sqrt(inv_mass[slot >= 0])
        return closed, force * self._weight[1]

    def start(self, problem, impulse: np.ndarray, v_free: np.ndarray, v: np.ndarray,
              tolerance: float) -> bool:
        """After a step at rest on the same contacts: impulse = R_a + dR from the first anchor
        whose start is inside every cone, else from the last one (module doc), and
        v = v_free + M^-1 H impulse [m/s, rad/s]; returns True. Otherwise (no anchor, other
        contacts, a step that cannot end at rest, loads that did not change) leaves both as they
        are and returns False; loads that did not change for the first time still let `record`
        keep the step."""
        self._pending = None
        if self._last_loads is None:
            return False
        count = problem.count
        step_loads = self._loads(problem, v_free)
        if (step_loads is None or len(self._keys) != count
                or not _equal(self._keys, problem.contacts.key[:count])
                or not _equal(step_loads[0], self._closed)):
            self.clear()
            return False
        loads = step_loads[1]
        self._pending = loads, None
        change, size = _distance(loads, self._last_loads)
        if change <= tolerance * size:
            # the warm start is at rest already; twice in a row: loads that do not change,
            # which need no following
            self._quiet += 1
            if self._quiet > 1:
                self.clear()
            return False
        self._quiet = 0
        for k in range(len(self._anchors) - 1, -1, -1):
            if self._anchors[k].start(problem, loads, self._weight[1], tolerance, impulse,
                                      v_free, v):
                break
        else:
            k = len(self._anchors) - 1
            self._anchors[k].start(problem, loads, self._weight[1], tolerance, impulse, v_free,
                                   v)
        self._pending = loads, k
        return True

    def record(self, problem, impulse: np.ndarray, v_free: np.ndarray, confirmed: bool,
               found: bool) -> None:
        """After the solve: keep the step if it ended at rest from the start that `start` saw
        and the first sweep confirmed (`confirmed`), or from a rest solution (`found`, which
        filled `response`: a new anchor); otherwise forget everything."""
        count = problem.count
        if found:
            step_loads = self._loads(problem, v_free)
            keys = problem.contacts.key[:count]
            if step_loads is None or not self.response.ready:
                self.clear()
                return
            if (self._keys is None or len(self._keys) != count
                    or not np.array_equal(self._keys, keys)
                    or not np.array_equal(step_loads[0], self._closed)):
                self._anchors.clear()
                self._keys, self._closed = keys.copy(), step_loads[0]
            self._anchors.append(_Anchor(self.response, impulse[:count].copy(), step_loads[1]))
            del self._anchors[:-_ANCHORS]
            self.response = LoadResponse()
            self._last_loads = step_loads[1]
        elif confirmed and self._pending is not None:
            loads, k = self._pending
            if k is not None:  # the anchor followed goes last
                self._anchors.append(self._anchors.pop(k))
            self._last_loads = loads
        else:
            self.clear()
        self._pending = None


@nb.njit(cache=True)
def _equal(a, b):
    """Whether the integer arrays a and b (1D) are equal (np.array_equal without its temporary
    arrays, on every step)."""
    if a.shape[0] != b.shape[0]:
        return False
    for i in range(a.shape[0]):
        if a[i] != b[i]:
            return False
    return True


@nb.njit(cache=True)
def _distance(a, b):
    """(|a - b|, |a|) for arrays of the same shape (2D)."""
    change = 0.0
    size = 0.0
    for i in range(a.shape[0]):
        for d in range(a.shape[1]):
            change += (a[i, d] - b[i, d]) ** 2
            size += a[i, d] * a[i, d]
    return math.sqrt(change), math.sqrt(size)


@nb.njit(cache=True)
def _start(cand, ant, h_cand, h_ant, active, friction, inv_mass, impulse_a, dr, lam, answers,
           v_free, impulse, v):
    """impulse = impulse_a + sum_j lam_j dr_j on the anchor's contacts (0 on inactive ones),
    v = v_free + M^-1 H impulse, in one pass; returns whether every impulse is in its Coulomb
    cone, R_n >= 0, |R_T| <= mu R_n (those of the contacts that are not closed are 0:
    rest_solution)."""
    dim = impulse_a.shape[1]
    for b in range(v.shape[0]):
        for d in range(v.shape[1]):
            v[b, d] = v_free[b, d]
    inside = True
    for a in range(impulse_a.shape[0]):
        if not active[a]:
            impulse[a, :] = 0.0
            continue
        for r in range(dim):
            x = impulse_a[a, r]
            for j in range(answers):
                x += lam[j] * dr[j, a, r]
            impulse[a, r] = x
        tangent = abs(impulse[a, 0])
        if dim == 3:
            tangent = math.hypot(tangent, impulse[a, 2])
        if not (impulse[a, 1] >= 0.0 and tangent <= friction[a] * impulse[a, 1]):
            inside = False
        c = cand[a]
        b = ant[a]
        for d in range(v.shape[1]):
            fc = 0.0
            fa = 0.0
            for r in range(dim):
                fc += h_cand[a, r, d] * impulse[a, r]
                fa += h_ant[a, r, d] * impulse[a, r]
            v[c, d] += inv_mass[c, d] * fc
            v[b, d] += inv_mass[b, d] * fa
    return inside


@nb.njit(cache=True)
def _combine(loads, last_loads, q, answers, change, lam):
    """change = loads - last_loads minus its projections lam_j = q_j . change on the first
    `answers` kept load changes (orthonormal); returns (|change| (the misfit), |loads|)."""
    size = 0.0
    for i in range(loads.shape[0]):
        for d in range(loads.shape[1]):
            change[i, d] = loads[i, d] - last_loads[i, d]
            size += loads[i, d] * loads[i, d]
    for j in range(answers):
        x = 0.0
        for i in range(loads.shape[0]):
            for d in range(loads.shape[1]):
                x += q[j, i, d] * change[i, d]
        for i in range(loads.shape[0]):
            for d in range(loads.shape[1]):
                change[i, d] -= x * q[j, i, d]
        lam[j] = x
    misfit = 0.0
    for i in range(loads.shape[0]):
        for d in range(loads.shape[1]):
            misfit += change[i, d] * change[i, d]
    return math.sqrt(misfit), math.sqrt(size)
