"""The discrete contact problem of one step, in the local frames of the contacts.

For each contact alpha: the rows of H*_alpha on the candidate and antagonist velocities, the
Delassus block W_alpha_alpha = H*_c M_c^-1 H_c + H*_a M_a^-1 H_a, the shift b_n of the law
(see saxum.laws), the friction coefficient, and whether the contact is active this step.
With v the end-of-step velocities, U_alpha = H*_alpha v and v = v_free + M^-1 H R (NSCD.md).

The kernels are generic over the dimension (rows of H* from the rigid body kind of the model's
dimension, saxum.bodies); in 2D, assembly and the end-of-step gaps run kernels written out for
3 dof, which give the same numbers bit for bit in a fraction of the time.
"""

import numba as nb
import numpy as np

from .. import bodies
from ..bodies import rigid2d, rigid3d
from ..contacts import Contacts
from ..laws import SMOOTH_KINDS, LawKind
from ..model import Model
from .laws_local import law_map_width, law_terms, local_velocities

__all__ = ["ContactProblem"]

_RESTITUTION = int(LawKind.RESTITUTION_COULOMB)


class ContactProblem:
    """Work arrays of the local problem (first `count` rows valid), reused from step to step."""

    def __init__(self, model: Model) -> None:
        self.model = model
        self.count = 0
        self.v_begin = None
        """Velocities at the start of the step [m/s, rad/s] (bodies, dof), set by assemble."""
        self._jacobians = bodies.rigid(model.dim).contact_jacobians
        self._written_out = model.dim == 2 and model.dof == 3
        """Use the kernels written out for 2D (False: the generic ones, which tests compare)."""
        self.fe = None
        """The deformable body kind (saxum.bodies.fe.FEKind) when the model has deformable
        blocks: their contacts' rows, Delassus blocks and node velocities."""
        self.parallel = False
        """Assemble on numba's threads (and in 2D take the end gaps; the same numbers bit
        for bit): Simulation sets it where the solver's threads are set."""
        self.joint_laws = bool(np.isin(model.law_kind, SMOOTH_KINDS).any())
        """Whether some law is a joint law (saxum.solver.laws_local): then law_map is filled."""
        self._initial_gaps = bool(model.law_initial_gap.any())
        """Whether some law is a _g0 law (saxum.laws): its contacts' b_n are taken again from
        g - g0 after the assembly (a pass of their own, which costs models without them
        nothing)."""
        self._allocate(64)

    def _allocate(self, capacity: int) -> None:
        d, dof = self.model.dim, self.model.dof
        self.capacity = capacity
        self.h_cand = np.zeros((capacity, d, dof))
        """Rows of H* on the candidate's velocity [-, m], shape [capacity, dim, dof]."""
        self.h_ant = np.zeros((capacity, d, dof))
        """Rows of H* on the antagonist's velocity [-, m], shape [capacity, dim, dof]."""
        self.delassus = np.zeros((capacity, d, d))
        """Diagonal Delassus block W_alpha_alpha [1/kg], shape [capacity, dim, dim]."""
        self.bias = np.zeros(capacity)
        """Shift b_n of the normal condition U_n + b_n >= 0 [m/s], shape [capacity]."""
        self.friction = np.zeros(capacity)
        """Coulomb coefficient mu [-], shape [capacity]."""
        self.active = np.zeros(capacity, dtype=np.bool_)
        """Contact enters the solve this step (else R = 0), shape [capacity]."""
        self.gap_end = np.zeros(capacity)
        """Estimated gap at the end of the step [m] (end_gaps), shape [capacity]."""
        self.u_begin = np.zeros((capacity, d))
        """The contacts' local velocities U at the start of the step [m/s] (joint laws only),
        shape [capacity, dim]."""
        self.u_end = np.zeros((capacity, d))
        """The contacts' local velocities U at the end of the step [m/s] (joint laws only,
        local_velocities), shape [capacity, dim]."""
        self.law_map = np.zeros((capacity, law_map_width(d)))
        """The joint laws' modified local problems (saxum.solver.laws_local; column 0 is 0
        for contacts of dry laws), shape [capacity, law_map_width(dim)]."""

    def assemble(
        self, contacts: Contacts, q: np.ndarray, v_begin: np.ndarray, h: float, theta: float,
        closed_gap: float, v: np.ndarray,
    ) -> None:
        """Build the problem of `contacts` detected on configuration q [m, rad]; v_begin is the
        velocity at the start of the step (for restitution), h [s] the step, theta [-].
        closed_gap [m]: velocity-level laws treat a contact as closed (active) when its gap is
        below this round-off tolerance, so that blocks built touching are in contact at once.
        Then the warm start: v [m/s, rad/s] += M^-1 H R for the contacts' impulses R, which
        are set to zero for inactive contacts."""
        if contacts.count > self.capacity:
            self._allocate(max(contacts.count, 2 * self.capacity))
        self.count = k = contacts.count
        m = self.model
        self.contacts = contacts
        self.v_begin = v_begin
        c = contacts
        if self._written_out:
            if self.parallel:
                _assemble_2d_parallel(q, c.candidate, c.antagonist, c.point, c.frame, c.gap,
                                      c.law, k, m.body_inv_mass, v_begin, m.law_kind,
                                      m.law_friction, m.law_restitution, h, theta,
                                      closed_gap, c.impulse, v, self.h_cand, self.h_ant,
                                      self.delassus, self.bias, self.friction, self.active,
                                      nb.get_num_threads())
            else:
                _assemble_2d(0, k, q, c.candidate, c.antagonist, c.point, c.frame, c.gap,
                             c.law, m.body_inv_mass, v_begin, m.law_kind, m.law_friction,
                             m.law_restitution, h * theta, closed_gap, c.impulse,
                             self.h_cand, self.h_ant, self.delassus, self.bias,
                             self.friction, self.active, v, True)
            if self.fe is not None:
                self.fe.assemble_contacts(self, v)
        else:
            if self.parallel and m.dim == 3:
                _rows_3d_parallel(q, c.candidate, c.antagonist, c.point, c.frame, c.gap,
                                  c.law, k, self.h_cand, self.h_ant, m.body_inv_mass,
                                  v_begin, m.law_kind, m.law_friction, m.law_restitution, h,
                                  theta, closed_gap, self.delassus, self.bias, self.friction,
                                  self.active, c.impulse, v, nb.get_num_threads())
            else:
                self._jacobians(q, c.candidate, c.antagonist, c.point, c.frame, c.gap, k,
                                self.h_cand, self.h_ant)
                _assemble(c.candidate, c.antagonist, c.law, c.gap, k, self.h_cand, self.h_ant,
                          m.body_inv_mass, v_begin, m.law_kind, m.law_friction,
                          m.law_restitution, h, theta, closed_gap, self.delassus, self.bias,
                          self.friction, self.active)
                _apply(c.candidate, c.antagonist, self.h_cand, self.h_ant, self.active, k,
                       m.body_inv_mass, c.impulse, v)
            if self.fe is not None:
                self.fe.assemble_contacts(self, v)
        if self._initial_gaps:
            _initial_gap_bias(c.law, c.gap, c.initial_gap, k, m.law_kind, m.law_initial_gap,
                              closed_gap, h * theta, self.bias)
        if self.joint_laws:
            self.local_velocities(v_begin, self.u_begin, begin=True)
            law_terms(c.law, c.gap, c.area, c.slip, c.damage, c.history, c.crush, c.impulse,
                      k, self.u_begin, m.law_kind, m.law_parameter, h, theta, self.delassus,
                      self.bias, self.law_map)

    def local_velocities(self, v: np.ndarray, out: np.ndarray, *, begin: bool = False) -> None:
        """out[:count] = U = H* v [m/s] in the contacts' frames, from the bodies' velocities v
        [m/s, rad/s] and, with deformable blocks, their nodes' (at the start of the step with
        begin, else the solve's)."""
        c = self.contacts
        if self.fe is not None:
            self.fe.local_velocities(self, v, out, begin)
            return
        local_velocities(c.candidate, c.antagonist, self.h_cand, self.h_ant, self.count, v, out)

    def end_gaps(self, impulse: np.ndarray, v: np.ndarray, h: float, theta: float,
                 w: np.ndarray | None = None) -> tuple[int, float]:
        """gap_end = g + theta h U_n(v) [+ h U_n(w)]: the gap at the end of the step from the
        end-of-step velocity v [m/s, rad/s], plus the displacement h w of a position projection
        (saxum.solver.projection) when w is given. Returns (contacts with R_n > 0, largest
        interpenetration -gap_end [m], 0 if none)."""
        c = self.contacts
        if self.fe is not None:
            return self.fe.end_gaps(self, impulse, v, w, h, theta)
        h_w = 0.0 if w is None else h
        w = v if w is None else w
        kernel = _end_gaps
        if self._written_out:
            kernel = _end_gaps_2d_parallel if self.parallel else _end_gaps_2d
        return kernel(c.candidate, c.antagonist, self.h_cand, self.h_ant, c.gap, self.count,
                      impulse, v, w, h_w, h, theta, self.gap_end)


@nb.njit(inline="always")
def _local_velocity(h_cand, h_ant, a, r, c, b, v):
    u = 0.0
    for d in range(v.shape[1]):
        u += h_cand[a, r, d] * v[c, d] + h_ant[a, r, d] * v[b, d]
    return u


@nb.njit(inline="always")
def _law(kind, restitution, gap, un_begin, closed_gap, h_theta):
    """(active, b_n [m/s]) of a contact with gap g [m] under a law of `kind` (a _g0 law's
    g - g0: _initial_gap_bias); un_begin [m/s] is U_n at the start of the step (used by
    restitution only)."""
    if kind == _RESTITUTION:
        return gap <= closed_gap, restitution * min(un_begin, 0.0)
    # Signorini and gap-based: an open contact may close exactly by the end of the step
    # (g + theta h U_n >= 0), a closed one gets U_n >= 0; the gap-based law's
    # interpenetration is removed afterwards by saxum.solver.projection. Gaps within
    # +-closed_gap count as exactly closed: targets that differ by round-off would be
    # incompatible in a statically indeterminate assembly.
    g = gap - min(max(gap, -closed_gap), closed_gap)
    return True, max(g, 0.0) / h_theta


@nb.njit(cache=True)
def _assemble(cand, ant, law, gap, count, h_cand, h_ant, inv_mass, v_begin, law_kind,
              law_friction, law_restitution, h, theta, closed_gap, delassus, bias, friction,
              active):
    dim = h_cand.shape[1]
    h_theta = h * theta
    for a in range(count):
        c = cand[a]
        b = ant[a]
        for r in range(dim):
            for s in range(dim):
                w = 0.0
                for d in range(inv_mass.shape[1]):
                    w += (h_cand[a, r, d] * inv_mass[c, d] * h_cand[a, s, d]
                          + h_ant[a, r, d] * inv_mass[b, d] * h_ant[a, s, d])
                delassus[a, r, s] = w
        kind = law_kind[law[a]]
        friction[a] = law_friction[law[a]]
        un = _local_velocity(h_cand, h_ant, a, 1, c, b, v_begin) if kind == _RESTITUTION else 0.0
        active[a], bias[a] = _law(kind, law_restitution[law[a]], gap[a], un, closed_gap,
                                  h_theta)


@nb.njit(parallel=True, cache=True)
def _rows_3d_parallel(q, cand, ant, point, frame, gap, law, count, h_cand, h_ant, inv_mass,
                      v_begin, law_kind, law_friction, law_restitution, h, theta, closed_gap,
                      delassus, bias, friction, active, impulse, v, runs):
    """rigid3d.contact_jacobians and _assemble by blocks of _BLOCK contacts on numba's
    threads, then the warm start (_apply) by `runs` runs of bodies (the threads) in parallel,
    each run's pushes in the contacts' order: the same numbers bit for bit (each contact's
    rows are its own, each body's sum in _apply's order)."""
    for k in nb.prange(-(-count // _BLOCK)):
        lo = k * _BLOCK
        hi = min(count, lo + _BLOCK)
        rigid3d.contact_jacobians(q, cand[lo:hi], ant[lo:hi], point[lo:hi], frame[lo:hi],
                                  gap[lo:hi], hi - lo, h_cand[lo:hi], h_ant[lo:hi])
        _assemble(cand[lo:hi], ant[lo:hi], law[lo:hi], gap[lo:hi], hi - lo, h_cand[lo:hi],
                  h_ant[lo:hi], inv_mass, v_begin, law_kind, law_friction, law_restitution, h,
                  theta, closed_gap, delassus[lo:hi], bias[lo:hi], friction[lo:hi],
                  active[lo:hi])
        for a in range(lo, hi):
            if not active[a]:
                impulse[a, :] = 0.0
    for k in nb.prange(runs):
        _apply_bodies(k * v.shape[0] // runs, (k + 1) * v.shape[0] // runs, cand, ant, h_cand,
                      h_ant, active, count, inv_mass, impulse, v)


@nb.njit(cache=True)
def _apply_bodies(lo, hi, cand, ant, h_cand, h_ant, active, count, inv_mass, impulse, v):
    """_apply's pushes of the active contacts, in their order, into the velocities of the
    bodies lo .. hi - 1 only (each body's terms as _apply's)."""
    for a in range(count):
        if not active[a]:
            continue
        c = cand[a]
        b = ant[a]
        into_c = lo <= c < hi
        into_b = lo <= b < hi
        if not (into_c or into_b):
            continue
        for d in range(v.shape[1]):
            fc = 0.0
            fa = 0.0
            for r in range(impulse.shape[1]):
                fc += h_cand[a, r, d] * impulse[a, r]
                fa += h_ant[a, r, d] * impulse[a, r]
            if into_c:
                v[c, d] += inv_mass[c, d] * fc
            if into_b:
                v[b, d] += inv_mass[b, d] * fa


@nb.njit(cache=True)
def _initial_gap_bias(law, gap, initial_gap, count, law_kind, law_initial_gap, closed_gap,
                      h_theta, bias):
    """b_n [m/s] of the _g0 laws' contacts: _law on g - g0 [m] (the Signorini laws, always
    active, so the assembly's active flags and warm start stand)."""
    for a in range(count):
        if law_initial_gap[law[a]]:
            bias[a] = _law(law_kind[law[a]], 0.0, gap[a] - initial_gap[a], 0.0, closed_gap,
                           h_theta)[1]


@nb.njit(cache=True)
def _apply(cand, ant, h_cand, h_ant, active, count, inv_mass, impulse, v):
    """v += M^-1 H R (the warm start); inactive contacts' R = 0."""
    for a in range(count):
        if not active[a]:
            impulse[a, :] = 0.0
    _apply_bodies(0, v.shape[0], cand, ant, h_cand, h_ant, active, count, inv_mass, impulse, v)


_BLOCK = 4096
"""Contacts per block of the parallel kernels (_assemble_2d_parallel, _end_gaps_2d_parallel,
_rows_3d_parallel)."""


@nb.njit(parallel=True, cache=True)
def _assemble_2d_parallel(q, cand, ant, point, frame, gap, law, count, inv_mass, v_begin,
                          law_kind, law_friction, law_restitution, h, theta, closed_gap,
                          impulse, v, h_cand, h_ant, delassus, bias, friction, active, runs):
    """_assemble_2d on numba's threads, the same numbers bit for bit: the contacts' rows by
    blocks in parallel (each contact's own), then the warm start by `runs` runs of bodies
    (the threads) in parallel, each run's pushes in the contacts' order (so each body's sum
    in the serial order, whatever the runs)."""
    for k in nb.prange(-(-count // _BLOCK)):
        _assemble_2d(k * _BLOCK, min(count, (k + 1) * _BLOCK), q, cand, ant, point, frame, gap,
                     law, inv_mass, v_begin, law_kind, law_friction, law_restitution,
                     h * theta, closed_gap, impulse, h_cand, h_ant, delassus, bias, friction,
                     active, v, False)
    for k in nb.prange(runs):
        _warm_start_bodies_2d(k * v.shape[0] // runs, (k + 1) * v.shape[0] // runs, count,
                              cand, ant, active, inv_mass, impulse, v, h_cand, h_ant)


@nb.njit(cache=True)
def _warm_start_bodies_2d(lo, hi, count, cand, ant, active, inv_mass, impulse, v, h_cand,
                          h_ant):
    """The warm start v += M^-1 H_a R_a of the active contacts, in their order, into the
    velocities of the bodies lo .. hi - 1 only (each body's terms as _assemble_2d's with
    warm)."""
    for a in range(count):
        if not active[a]:
            continue
        rt = impulse[a, 0]
        rn = impulse[a, 1]
        c = cand[a]
        if lo <= c < hi:
            for d in range(3):
                v[c, d] += inv_mass[c, d] * (h_cand[a, 0, d] * rt + h_cand[a, 1, d] * rn)
        b = ant[a]
        if lo <= b < hi:
            for d in range(3):
                v[b, d] += inv_mass[b, d] * (h_ant[a, 0, d] * rt + h_ant[a, 1, d] * rn)


@nb.njit(cache=True)
def _assemble_2d(lo, hi, q, cand, ant, point, frame, gap, law, inv_mass, v_begin, law_kind,
                 law_friction, law_restitution, h_theta, closed_gap, impulse, h_cand, h_ant,
                 delassus, bias, friction, active, v, warm):
    """rigid2d.contact_jacobians and _assemble written out for 3 dof, for the contacts
    lo .. hi - 1: their rows of H*, W, mu, b_n and active flags (an inactive one's impulse set
    to 0); with warm, in the same pass, _apply's warm start v += M^-1 H_a R_a of each active
    one in the contacts' order (the same numbers bit for bit). One loop body, no per-contact
    function: an inlined one taking the arrays made numba count references per contact (3x
    the assembly's time at rest, 2cb2a1a)."""
    for a in range(lo, hi):
        c = cand[a]
        b = ant[a]
        tx = frame[a, 0, 0]
        ty = frame[a, 0, 1]
        nx = frame[a, 1, 0]
        ny = frame[a, 1, 1]
        lcx, lcy, lax, lay = rigid2d.lever_arms(q, c, b, point, frame, gap, a)
        ct = lcx * ty - lcy * tx
        cn = lcx * ny - lcy * nx
        at = -(lax * ty - lay * tx)
        an = -(lax * ny - lay * nx)
        h_cand[a, 0, 0] = tx
        h_cand[a, 0, 1] = ty
        h_cand[a, 0, 2] = ct
        h_cand[a, 1, 0] = nx
        h_cand[a, 1, 1] = ny
        h_cand[a, 1, 2] = cn
        h_ant[a, 0, 0] = -tx
        h_ant[a, 0, 1] = -ty
        h_ant[a, 0, 2] = at
        h_ant[a, 1, 0] = -nx
        h_ant[a, 1, 1] = -ny
        h_ant[a, 1, 2] = an
        mc0, mc1, mc2 = inv_mass[c, 0], inv_mass[c, 1], inv_mass[c, 2]
        mb0, mb1, mb2 = inv_mass[b, 0], inv_mass[b, 1], inv_mass[b, 2]
        # (-x) m (-y) == x m y exactly, so the antagonist's rows enter with either sign
        wtt = 0.0 + (tx * mc0 * tx + tx * mb0 * tx)
        wtt += ty * mc1 * ty + ty * mb1 * ty
        wtt += ct * mc2 * ct + at * mb2 * at
        wtn = 0.0 + (tx * mc0 * nx + tx * mb0 * nx)
        wtn += ty * mc1 * ny + ty * mb1 * ny
        wtn += ct * mc2 * cn + at * mb2 * an
        wnt = 0.0 + (nx * mc0 * tx + nx * mb0 * tx)
        wnt += ny * mc1 * ty + ny * mb1 * ty
        wnt += cn * mc2 * ct + an * mb2 * at
        wnn = 0.0 + (nx * mc0 * nx + nx * mb0 * nx)
        wnn += ny * mc1 * ny + ny * mb1 * ny
        wnn += cn * mc2 * cn + an * mb2 * an
        delassus[a, 0, 0] = wtt
        delassus[a, 0, 1] = wtn
        delassus[a, 1, 0] = wnt
        delassus[a, 1, 1] = wnn
        kind = law_kind[law[a]]
        friction[a] = law_friction[law[a]]
        un = 0.0
        if kind == _RESTITUTION:
            un = 0.0 + (nx * v_begin[c, 0] + -nx * v_begin[b, 0])
            un += ny * v_begin[c, 1] + -ny * v_begin[b, 1]
            un += cn * v_begin[c, 2] + an * v_begin[b, 2]
        on, bias[a] = _law(kind, law_restitution[law[a]], gap[a], un, closed_gap, h_theta)
        active[a] = on
        if not on:
            impulse[a, 0] = 0.0
            impulse[a, 1] = 0.0
            continue
        if warm:
            rt = impulse[a, 0]
            rn = impulse[a, 1]
            v[c, 0] += mc0 * (tx * rt + nx * rn)
            v[b, 0] += mb0 * (-tx * rt + -nx * rn)
            v[c, 1] += mc1 * (ty * rt + ny * rn)
            v[b, 1] += mb1 * (-ty * rt + -ny * rn)
            v[c, 2] += mc2 * (ct * rt + cn * rn)
            v[b, 2] += mb2 * (at * rt + an * rn)


@nb.njit(cache=True)
def _end_gaps(cand, ant, h_cand, h_ant, gap, count, impulse, v, w, h_w, h, theta, gap_end):
    loaded = 0
    worst = 0.0
    for a in range(count):
        g = gap[a] + theta * h * _local_velocity(h_cand, h_ant, a, 1, cand[a], ant[a], v)
        if h_w != 0.0:
            g += h_w * _local_velocity(h_cand, h_ant, a, 1, cand[a], ant[a], w)
        gap_end[a] = g
        loaded += impulse[a, 1] > 0.0
        worst = max(worst, -g)
    return loaded, worst


@nb.njit(inline="always")
def _normal_velocity_2d(h_cand, h_ant, a, c, b, v):
    """_local_velocity(h_cand, h_ant, a, 1, c, b, v) written out for 3 dof."""
    u = 0.0 + (h_cand[a, 1, 0] * v[c, 0] + h_ant[a, 1, 0] * v[b, 0])
    u += h_cand[a, 1, 1] * v[c, 1] + h_ant[a, 1, 1] * v[b, 1]
    u += h_cand[a, 1, 2] * v[c, 2] + h_ant[a, 1, 2] * v[b, 2]
    return u


@nb.njit(cache=True)
def _end_gaps_2d(cand, ant, h_cand, h_ant, gap, count, impulse, v, w, h_w, h, theta, gap_end):
    """_end_gaps written out for 3 dof (the same numbers bit for bit)."""
    return _end_gaps_range_2d(0, count, cand, ant, h_cand, h_ant, gap, impulse, v, w, h_w, h,
                              theta, gap_end)


@nb.njit(parallel=True, cache=True)
def _end_gaps_2d_parallel(cand, ant, h_cand, h_ant, gap, count, impulse, v, w, h_w, h, theta,
                          gap_end):
    """_end_gaps_2d by blocks of contacts on numba's threads: the same numbers bit for bit
    (each contact's gap is its own; a count and a largest value do not depend on the
    order)."""
    loaded = np.zeros(-(-count // _BLOCK), dtype=np.int64)
    worst = np.zeros(loaded.shape[0])
    for k in nb.prange(loaded.shape[0]):
        loaded[k], worst[k] = _end_gaps_range_2d(k * _BLOCK, min(count, (k + 1) * _BLOCK),
                                                 cand, ant, h_cand, h_ant, gap, impulse, v, w,
                                                 h_w, h, theta, gap_end)
    return loaded.sum(), worst.max() if count > 0 else 0.0


@nb.njit(inline="always")
def _end_gaps_range_2d(lo, hi, cand, ant, h_cand, h_ant, gap, impulse, v, w, h_w, h, theta,
                       gap_end):
    """_end_gaps_2d of the contacts lo .. hi - 1 (inline: the serial kernel stays one
    compiled function, tests/test_precompile.py)."""
    loaded = 0
    worst = 0.0
    for a in range(lo, hi):
        c = cand[a]
        b = ant[a]
        g = gap[a] + theta * h * _normal_velocity_2d(h_cand, h_ant, a, c, b, v)
        if h_w != 0.0:
            g += h_w * _normal_velocity_2d(h_cand, h_ant, a, c, b, w)
        gap_end[a] = g
        loaded += impulse[a, 1] > 0.0
        worst = max(worst, -g)
    return loaded, worst
