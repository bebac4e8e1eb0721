"""The rest solution of a step's contact problem, when there is one: impulses in the Coulomb
cones that bring every free body to rest relative to its supports. 2D and 3D rigid blocks.

Rest means: every free body ends the step with the velocity V of the supports (fixed and
driven bodies) that it touches, which must share one translation (V = 0 for fixed supports;
a driven ground moving as a whole). Every contact whose law asks U_n + b_n >= 0 with b_n = 0
("closed": Signorini and gap-based laws with a gap within closed_gap, restitution on a contact
that does not approach) then has U = 0, which satisfies Signorini (U_n = 0) and Coulomb (stick)
whatever impulse R_alpha in the cone |R_T| <= mu R_n it carries; every other contact must have
U_n + b_n >= 0 at rest, and carries nothing. So the rest solution exists exactly when the
impulse balance of the free bodies
    sum_alpha H_alpha R_alpha = f = M (V - v_free)          (v = v_free + M^-1 H R = V)
has a solution with every closed contact's R_alpha in its cone: a static equilibrium (the
lower-bound problem of limit analysis, with the step's impulses for forces). When it exists it
is a solution of the step's problem (the laws are unchanged; with friction a step's solution
need not be unique, and this one is the solution at rest). It takes a handful of sparse
factorizations where Gauss-Seidel needs as many sweeps as the slowest deformation mode of the
assembly takes to relax: tens of thousands for a slender tower (saxum.solver.nlgs).

Each closed contact's impulse is R = B x, x in a cone with a logarithmic barrier phi(x):
- 2D (frame (t, n)): two nonnegative coordinates x_1 = mu R_n - R_t, x_2 = mu R_n + R_t
  (R_t = (x_2 - x_1) / 2, R_n = (x_1 + x_2) / (2 mu); for mu = 0, R_n = x_1 + x_2 and R_t = 0),
  phi = -log x_1 - log x_2 (= -log(mu^2 R_n^2 - R_t^2), the 3D barrier's 2D case, in
  coordinates where the cone is a quadrant);
- 3D (frame (t, n, s)): the second-order cone |(x_t, x_s)| <= x_n with R_t = x_t, R_s = x_s,
  R_n = x_n / mu (for mu = 0, R_n = x_n and R_t = R_s = 0), and its logarithmic barrier
  phi = -log(x_n^2 - x_t^2 - x_s^2) (S. Boyd and L. Vandenberghe, "Convex Optimization", 2004,
  sec. 11.6.1), whose Hessian has the inverse x x^T - (x_n^2 - x_t^2 - x_s^2) J / 2,
  J = diag(-1, 1, -1) (Sherman-Morrison on -2 J / Q + 4 J x x^T J / Q^2); for mu = 0 the
  barrier keeps x_t = x_s = 0 and is -2 log x_n.
Then
    minimize  (1 / 2 r0^2) sum |B x|^2 + sum phi(x)   subject to   G x = f,  G = H B
by the infeasible-start Newton method (Boyd and Vandenberghe, sec. 10.3): each step solves the
KKT system through its Schur complement G P^-1 G^T (P the Hessian, 2 x 2 or 3 x 3 per
contact), a body-space sparse matrix with a 3 x 3 (2D) or 6 x 6 (3D) block for each free body
and each pair of free bodies in closed contact (a block Cholesky factorization whose analysis
is kept per pattern: saxum.solver.block_cholesky), and moves towards G x = f as far as the
cones allow (0.99 of the way to the nearest cone's boundary). It stops at the first
x inside every cone with G x = f to round-off: any such x is a rest solution, and the barrier
keeps it strictly inside every cone, so that Gauss-Seidel keeps it as it is (every contact
sticks with a margin). Which of the many rest solutions of a statically indeterminate assembly
it returns depends on the starting point (the caller's impulses) and r0 [N s], the largest
impulse a free body needs; all give the same velocities. When there is none (a mechanism under
the loads, e.g. an arch thinner than its limit), the steps shrink to nothing within a few
iterations.

The static load path comes first where the caller asks for it (NLGS does on a step that does
not follow an earlier rest solution: a cold start). A stack carries its loads down to its
supports: visiting the bodies from the top down, each passes its loads, its own and those of
the bodies resting on it, to the contacts that hold it up (_load_path). That takes one pass
over the contacts and no factorization; where every such impulse lies strictly inside its
cone and the balance holds to round-off it is a rest solution, taken as it is (the contacts
that hold nothing up, a wall's head joints, carry R = 0, which U = 0 satisfies too), and
otherwise (an arch whose voussoirs lean on each other, friction that the path overloads, a
mechanism) the Newton method goes on as above. On the first step of a 125 000-brick wall it
replaces 11 factorizations (benchmarks/cold_start.py, BENCHMARKS.md).
"""

import math

import numba as nb
import numpy as np

from ..linalg3 import solve3
from .block_cholesky import BlockCholesky, analyse

__all__ = ["LoadResponse", "rest_hypothesis", "rest_solution"]

_RIGID_DOF = {2: 3, 3: 6}
"""Degrees of freedom of a rigid body by spatial dimension: the models this module serves."""
_ITERATIONS = 40
"""Newton iterations before the rest solution is given up (none exists, or it is not found)."""
_FEASIBLE = 1e-10
"""Relative residual |G x - f|_M^-1 / |f|_M^-1 at which x counts as a solution (round-off is
about 1e-13: a rest solution leaves velocities of 1e-10 of those of one step of the loads)."""
_FLOOR = 1e-8
"""... or at which it does, after a full Newton step that did not halve it (round-off of the
factorization)."""
_MARGIN = 0.1
"""Added to the caller's impulses moved into the cones, relative to r0 (_start): the default
of rest_solution's `margin`."""
_LIFT = 1e-3
"""Cosine of the angle between a contact's normal and the direction of the loads above which
the contact holds up the body its normal impulse pushes along them (_load_path): joints more
nearly parallel to the loads (a wall's head joints) carry nothing on the load path."""
_STALLED = 1e-3
"""Steps shorter than this, three in a row, mean no rest solution: the residual, which each
step shrinks by its length, stops shrinking (the barrier holds x off the cones' edges that
the loads would have to cross)."""


_KEPT_SYSTEM = ("closed", "slot", "b", "x", "data")
"""The arrays of a LoadResponse that a checkpoint holds (data: None until formed)."""


class LoadResponse:
    """The last Newton system of a rest solution, kept to answer a change of the loads: for
    df [N s] per free body, the impulse change dR = B dx, dx = P^-1 G^T nu, G P^-1 G^T nu = df,
    which balances it exactly (G dx = df) and is the Newton step of the barrier problem
    without its gradient: small on the contacts near their cone's boundary, where the
    barrier's Hessian P is large (an affine-scaling direction of interior-point methods).
    A rest solution found without a factorization (the load path: rest_solution) keeps the
    system at the point where the Newton iterations would have started, factorized at the
    first change asked for. The system's values (`data`, CSC) are kept with it: a checkpoint
    holds them (checkpoint(), restored()), and the restored system is factorized from them at
    the first change asked for, bit for bit the factor it had."""

    def __init__(self) -> None:
        self.clear()

    def clear(self) -> None:
        self.lu = None
        self.closed = self.slot = self.b = self.x = self.data = None
        self.scale = 0.0

    @property
    def ready(self) -> bool:
        return self.closed is not None

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The kept system as arrays ({} where none is kept): the closed contacts, the free
        bodies' slots, B, x, r0 [N s] and, once it was formed, its values."""
        if self.closed is None:
            return {}
        kept = {name: getattr(self, name) for name in _KEPT_SYSTEM}
        return {"scale": np.float64(self.scale),
                **{name: value for name, value in kept.items() if value is not None}}

    @classmethod
    def restored(cls, saved: dict) -> "LoadResponse":
        """The system whose checkpoint() was `saved` (none kept for {})."""
        response = cls()
        if saved:
            for name in _KEPT_SYSTEM:
                setattr(response, name, saved.get(name))
            response.scale = float(saved["scale"])
        return response

    def impulse_change(self, problem, change: np.ndarray) -> np.ndarray | None:
        """dR (count, dim) [N s] for the change of loads `change` (free bodies, dof) [N s] on
        the closed contacts of the kept system; None if there is none kept (or it is
        singular)."""
        if self.closed is None:
            return None
        c = problem.contacts
        if self.lu is None:
            nfree, dof = change.shape
            indptr, indices, where, diagonal, bptr, blocks = _pattern(
                c.candidate, c.antagonist, self.closed, self.slot, nfree, dof)
            if self.data is None:  # the load path's system, formed with this step's H
                self.data = np.zeros(len(indices))
                _newton_system(c.candidate, c.antagonist, problem.h_cand, problem.h_ant,
                               self.closed, self.slot, self.b, self.x, self.scale, where,
                               diagonal, indptr, np.zeros((nfree, dof)), self.data)
            self.lu = _factorize(bptr, blocks, self.data, indices, indptr, dof)
            if self.lu is None:
                self.clear()
                return None
        nu = self.lu.solve(change.reshape(-1)).reshape(change.shape)
        dx = np.empty_like(self.x)
        _newton_step(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, self.closed,
                     self.slot, self.b, self.x, self.scale, nu, False, dx)
        out = np.empty((problem.count, problem.model.dim))
        _scatter(self.closed, self.b, dx, problem.count, out)
        return -out


def rest_solution(problem, impulse: np.ndarray, v_free: np.ndarray, v: np.ndarray,
                  response: LoadResponse | None = None, margin: float = _MARGIN,
                  load_path: bool = False) -> bool:
    """If the step's problem (saxum.solver.ContactProblem or a view with the same arrays) has a
    rest solution, write its impulses [N s] into `impulse` (R = 0 for the contacts that do not
    carry any) and v = v_free + M^-1 H R [m/s, rad/s] (V for the free bodies, to round-off;
    v_free for the others) into `v`, and return True. Otherwise (no rest solution, or none found in
    _ITERATIONS Newton steps) leave both untouched and return False. The caller's impulses are
    the starting point: among the solutions, it returns one near them. `response`, if
    given, keeps the last Newton system of a rest solution found (cleared otherwise); margin
    [-]: the Newton iterations start from the caller's impulses moved into the cones plus
    margin x r0 (module doc), less for impulses that already balance the loads. load_path:
    first try the static load path (_load_path), a rest solution without any factorization
    where the assembly is a stack that carries its loads down to its supports (a wall at
    rest): it does not depend on the caller's impulses."""
    if response is not None:
        response.clear()
    hypothesis = rest_hypothesis(problem, v_free)
    if hypothesis is None:
        return False
    closed, slot, force = hypothesis
    count = problem.count
    dof = problem.model.dof
    nfree = len(force)
    c = problem.contacts
    inv_mass = problem.model.body_inv_mass
    if load_path:
        trial = np.zeros((count, problem.model.dim))
        if _load_path(c.candidate, c.antagonist, problem.h_cand, problem.h_ant,
                      problem.friction, closed, slot, force, trial):
            x, b, scale = _start(closed, problem.friction, trial, force, 0.0)
            rhs = np.empty((nfree, dof))
            residual = _residual(c.candidate, c.antagonist, problem.h_cand, problem.h_ant,
                                 closed, slot, b, x, force, inv_mass, rhs)
            if residual <= _FEASIBLE * _norm_m(force, slot, inv_mass):
                _apply(c.candidate, c.antagonist, problem.h_cand, problem.h_ant,
                       problem.active, count, closed, b, x, inv_mass, v_free, impulse, v)
                if response is not None:  # the system of the Newton method's start
                    response.closed, response.slot, response.scale = closed, slot, scale
                    response.x, response.b = _start(closed, problem.friction, trial, force,
                                                     margin)[:2]
                return True
    indptr, indices, where, diagonal, bptr, blocks = _pattern(c.candidate, c.antagonist, closed,
                                                              slot, nfree, dof)
    x, b, scale = _start(closed, problem.friction, impulse, force, margin)
    data = np.zeros(len(indices))
    rhs = np.empty((nfree, dof))
    step = np.empty_like(x)
    residual = _residual(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, closed, slot,
                         b, x, force, inv_mass, rhs)
    size = _norm_m(force, slot, inv_mass)
    alpha = 0.0
    short = 0
    lu = None
    x_factored = x
    for _ in range(_ITERATIONS):
        if residual <= _FEASIBLE * size:
            break
        _newton_system(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, closed, slot,
                       b, x, scale, where, diagonal, indptr, rhs, data)
        lu = _factorize(bptr, blocks, data, indices, indptr, dof)
        if lu is None:  # singular: a free body's motion that no contact resists
            return False
        nu = lu.solve(rhs.reshape(-1)).reshape(nfree, dof)
        if not np.all(np.isfinite(nu)):
            return False
        _newton_step(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, closed, slot, b,
                     x, scale, nu, True, step)
        x_factored = x.copy()
        alpha = _step_length(x, step)
        short = short + 1 if alpha < _STALLED else 0
        if short == 3:
            return False
        x += alpha * step
        if not _inside(x):  # round-off at a cone's boundary
            return False
        before = residual
        residual = _residual(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, closed,
                             slot, b, x, force, inv_mass, rhs)
        if alpha == 1.0 and residual > 0.5 * before:
            break
    if not residual <= (_FLOOR if alpha == 1.0 else _FEASIBLE) * size:
        return False
    _apply(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, problem.active, count,
           closed, b, x, inv_mass, v_free, impulse, v)
    if response is not None and lu is not None:
        response.lu, response.closed, response.slot = lu, closed, slot
        response.b, response.x, response.scale = b, x_factored, scale
        response.data = data  # (lu's: formed last before it)
    return True


def _factorize(bptr, blocks, data, indices, indptr, dof):
    """A factor of the symmetric positive definite Newton system (CSC, _pattern's) with a
    solve(rhs) method, None if singular: the block Cholesky factor with the analysis of the
    pattern, kept while the closed contacts do not change (saxum.solver.block_cholesky: a
    fifth of SuperLU's time on the 512-brick wall's systems, benchmarks/rest_factorization.py),
    or SuperLU's LU as before it where that meets a pivot that is not positive (a system
    singular to round-off)."""
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu

    factor = BlockCholesky.factorize(analyse(bptr, blocks), bptr, data, indptr, dof)
    if factor is not None:
        return factor
    size = len(indptr) - 1
    try:
        # a symmetric fill-reducing order, no pivoting
        return splu(csc_matrix((data, indices, indptr), shape=(size, size)),
                    permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                    options={"SymmetricMode": True})
    except RuntimeError:
        return None


def rest_hypothesis(problem, v_free: np.ndarray):
    """(closed contacts, slot of each body among the free bodies (-1 for the others), the
    loads f = M (V - v_free) [N s] per free body (rows in slot order)) when the step's problem
    can have a rest solution and it is worth looking for (_rest_contacts); None otherwise."""
    count = problem.count
    v_begin = getattr(problem, "v_begin", None)
    if count == 0 or v_begin is None or problem.model.dof != _RIGID_DOF.get(problem.model.dim):
        return None
    c = problem.contacts
    inv_mass = problem.model.body_inv_mass
    slot = np.empty(len(inv_mass), dtype=np.int64)
    closed = np.empty(count, dtype=np.int64)
    m, _, force = _rest_contacts(c.candidate, c.antagonist, problem.h_cand, problem.h_ant,
                                 problem.bias, problem.friction, problem.active, count,
                                 inv_mass, v_begin, v_free, slot, closed)
    if m <= 0:
        return None
    return closed[:m], slot, force


@nb.njit(cache=True)
def _rest_contacts(cand, ant, h_cand, h_ant, bias, friction, active, count, inv_mass, v_begin,
                   v_free, slot, closed):
    """Check the rest hypothesis: slot[b] = index of free body b among the free bodies (-1
    for the others), closed[:m] = the closed contacts. Returns (m, free bodies, f [N s] per
    free body: M (V - v_free), V the supports' velocity (see rest_solution)), m = -1 when no
    rest solution can exist: supports in closed contact that do not share one translation,
    an open contact that would close, a restitution target, a free body that needs an
    impulse and has no closed contact, or supports whose closed contacts share one Coulomb
    cone (one frame and one mu: a flat ground) that the sum of the loads, which only they can
    carry, lies outside (a structure that slides on its ground as a whole, where NLGS would
    otherwise stop to look for the rest solution on every step); or when it is not worth
    looking for: the blocks move
    relative to the supports (|v_begin - V|_M above |v_free - v_begin|_M, the velocity that
    one step of the loads gives: a structure in motion, which the contacts would have to stop
    within one step)."""
    dim = h_cand.shape[1]
    dof = inv_mass.shape[1]
    nfree = 0
    for b in range(inv_mass.shape[0]):
        if inv_mass[b, 0] > 0.0:
            slot[b] = nfree
            nfree += 1
        else:
            slot[b] = -1
    force = np.zeros((nfree, dof))
    held = np.zeros(nfree, dtype=np.bool_)
    # one pass over the contacts: the closed ones go to the front of `closed`, the other
    # active ones (open) to its back; V, the velocity of the supports in closed contact, must
    # be one translation, the same for all
    frame = np.zeros(dof)
    framed = False
    m = 0
    opened = 0
    cone = -1  # a closed contact of a free body with a support, whose cone the others share
    for a in range(count):
        if not active[a]:
            continue
        if bias[a] != 0.0:
            opened += 1
            closed[count - opened] = a
            continue
        closed[m] = a
        m += 1
        if cone != -2 and (slot[cand[a]] < 0) != (slot[ant[a]] < 0):
            if cone == -1:
                cone = a
            elif not _same_cone(h_cand, h_ant, friction, slot, cand, ant, cone, a, dim):
                cone = -2
        for body in (cand[a], ant[a]):
            if slot[body] >= 0:
                held[slot[body]] = True  # U = 0 at rest: every body in it moves with V
            elif not framed:
                framed = True
                for d in range(dof):
                    frame[d] = v_free[body, d]
            else:
                for d in range(dof):
                    if v_free[body, d] != frame[d]:
                        return -1, nfree, force
    for d in range(dim, dof):  # the angular velocities
        if frame[d] != 0.0:
            return -1, nfree, force
    moving = 0.0
    loads = 0.0
    for b in range(inv_mass.shape[0]):
        if slot[b] >= 0:
            for d in range(dof):
                if not inv_mass[b, d] > 0.0:
                    return -1, nfree, force
                force[slot[b], d] = (frame[d] - v_free[b, d]) / inv_mass[b, d]
                moving += (v_begin[b, d] - frame[d]) ** 2 / inv_mass[b, d]
                loads += (v_free[b, d] - v_begin[b, d]) ** 2 / inv_mass[b, d]
    if moving > loads:
        return -1, nfree, force
    if cone >= 0 and not _inside_cone(h_cand, h_ant, friction, slot, cand, cone, force, dim):
        return -1, nfree, force
    for k in range(count - opened, count):
        # an open contact: U_n + b_n >= 0 at rest, free bodies moving with V
        a = closed[k]
        c = cand[a]
        b = ant[a]
        un = bias[a]
        for d in range(dof):
            vc = frame[d] if slot[c] >= 0 else v_free[c, d]
            vb = frame[d] if slot[b] >= 0 else v_free[b, d]
            un += h_cand[a, 1, d] * vc + h_ant[a, 1, d] * vb
        if un < 0.0:
            return -1, nfree, force
    for k in range(nfree):
        if not held[k]:
            for d in range(dof):
                if force[k, d] != 0.0:
                    return -1, nfree, force
    return m, nfree, force


@nb.njit(cache=True)
def _load_path(cand, ant, h_cand, h_ant, friction, closed, slot, force, impulse):
    """The static load path of a stack: impulse [N s] (count, dim) on the closed contacts
    that balances the loads f [N s] of every free body, the loads passed from body to body
    down to the supports. A closed contact whose normal impulse pushes one body along u, the
    direction of the sum of the loads (n . u > _LIFT), holds that body up; the other closed
    contacts carry nothing. The bodies are visited from the top down (each after every body
    that rests on it: a topological order of the "rests on" graph, whose cycles, if odd
    shapes make any, leave their bodies unvisited); each body's loads, its own f less
    the impulses of the bodies resting on it, are carried by the contacts that hold it up
    with the least weighted norm sum R_n^2 + |R_T|^2 / mu^2 (R = W H_b lambda, (H_b^T W H_b)
    lambda = f_b - ..., W = diag(mu^2, 1(, mu^2)): the lever rule, R_T = 0 for mu = 0), so
    that every body's balance G x = f holds to round-off. Returns whether every body was
    visited, had a nonsingular system (or nothing to carry), and every contact holding it up
    carries an impulse strictly inside its Coulomb cone (|R_T| < mu R_n, R_n > 0); otherwise
    the caller falls back on the Newton method (a mechanism, an arch whose voussoirs lean on
    each other sideways, a load path outside the cones)."""
    m = closed.shape[0]
    nfree, dof = force.shape
    dim = h_cand.shape[1]
    up = np.zeros(dim)
    for k in range(nfree):
        for d in range(dim):
            up[d] += force[k, d]
    size = 0.0
    for d in range(dim):
        size += up[d] * up[d]
    if size == 0.0:
        return False
    up /= math.sqrt(size)
    # per closed contact: the side it holds up (0: candidate, 1: antagonist, -1: none); per
    # free body: the contacts that hold it up (CSR) and how many contacts it holds up with
    # free bodies on them (those must be visited before it)
    side = np.full(m, -1, dtype=np.int64)
    held = np.zeros(nfree + 1, dtype=np.int64)
    waiting = np.zeros(nfree, dtype=np.int64)
    for k in range(m):
        a = closed[k]
        for s in range(2):
            body = slot[cand[a]] if s == 0 else slot[ant[a]]
            if body < 0:
                continue
            h = h_cand if s == 0 else h_ant
            lift = 0.0
            for d in range(dim):
                lift += h[a, 1, d] * up[d]
            if lift > _LIFT:
                side[k] = s
                held[body + 1] += 1
                other = slot[ant[a]] if s == 0 else slot[cand[a]]
                if other >= 0:
                    waiting[other] += 1
    for b in range(nfree):
        held[b + 1] += held[b]
    holds = np.empty(held[nfree], dtype=np.int64)
    fill = held[:nfree].copy()
    for k in range(m):
        if side[k] >= 0:
            a = closed[k]
            body = slot[cand[a]] if side[k] == 0 else slot[ant[a]]
            holds[fill[body]] = k
            fill[body] += 1
    carried = force.copy()  # f_b less the impulses of the bodies resting on b
    queue = np.empty(nfree, dtype=np.int64)
    tail = 0
    for b in range(nfree):
        if waiting[b] == 0:
            queue[tail] = b
            tail += 1
    weight = np.empty(dim)
    s_mat = np.empty((dof, dof))
    lam = np.empty(dof)
    head = 0
    while head < tail:
        body = queue[head]
        head += 1
        if held[body] == held[body + 1]:  # nothing holds it up: it must carry nothing
            for p in range(dof):
                if carried[body, p] != 0.0:
                    return False
            continue
        s_mat[:, :] = 0.0
        for j in range(held[body], held[body + 1]):
            k = holds[j]
            a = closed[k]
            h = h_cand if side[k] == 0 else h_ant
            mu2 = friction[a] * friction[a]
            for r in range(dim):
                w = 1.0 if r == 1 else mu2
                for p in range(dof):
                    for q in range(dof):
                        s_mat[p, q] += w * h[a, r, p] * h[a, r, q]
        for p in range(dof):
            lam[p] = carried[body, p]
        if not _cholesky_solve(s_mat, lam):
            return False
        for j in range(held[body], held[body + 1]):
            k = holds[j]
            a = closed[k]
            h = h_cand if side[k] == 0 else h_ant
            mu = friction[a]
            for r in range(dim):
                acc = 0.0
                for p in range(dof):
                    acc += h[a, r, p] * lam[p]
                weight[r] = acc * (1.0 if r == 1 else mu * mu)
            tangent = abs(weight[0]) if dim == 2 else math.hypot(weight[0], weight[2])
            if not (weight[1] > 0.0 and (tangent < mu * weight[1] or tangent == 0.0)):
                return False
            for r in range(dim):
                impulse[a, r] = weight[r]
            other = slot[ant[a]] if side[k] == 0 else slot[cand[a]]
            if other < 0:
                continue
            ho = h_ant if side[k] == 0 else h_cand
            for p in range(dof):
                acc = 0.0
                for r in range(dim):
                    acc += ho[a, r, p] * weight[r]
                carried[other, p] -= acc
            waiting[other] -= 1
            if waiting[other] == 0:
                queue[tail] = other
                tail += 1
    return tail == nfree


@nb.njit(cache=True)
def _cholesky_solve(s, rhs):
    """rhs = S^-1 rhs for a small symmetric positive semi-definite S (overwritten by its
    Cholesky factor); False where S is singular (a pivot below 1e-12 of its diagonal entry:
    loads on a motion that the contacts holding the body up do not resist)."""
    n = s.shape[0]
    for j in range(n):
        diag = s[j, j]
        for p in range(j):
            diag -= s[j, p] * s[j, p]
        if not diag > 1e-12 * s[j, j]:
            return False
        s[j, j] = math.sqrt(diag)
        for i in range(j + 1, n):
            acc = s[i, j]
            for p in range(j):
                acc -= s[i, p] * s[j, p]
            s[i, j] = acc / s[j, j]
    for i in range(n):
        acc = rhs[i]
        for p in range(i):
            acc -= s[i, p] * rhs[p]
        rhs[i] = acc / s[i, i]
    for i in range(n - 1, -1, -1):
        acc = rhs[i]
        for p in range(i + 1, n):
            acc -= s[p, i] * rhs[p]
        rhs[i] = acc / s[i, i]
    return True


@nb.njit(inline="always")
def _free_rows(h_cand, h_ant, slot, cand, a):
    """The rows of H* on the free body of contact a with a support (frame rows t, n (, s)
    seen from the free body: its impulse is their combination with R)."""
    return h_cand[a] if slot[cand[a]] >= 0 else h_ant[a]


@nb.njit(cache=True)
def _same_cone(h_cand, h_ant, friction, slot, cand, ant, a, b, dim):
    """Whether the support contacts a and b give their free bodies the same Coulomb cone:
    the same frame (translational rows of H*) and the same mu, exactly."""
    if friction[a] != friction[b]:
        return False
    rows_a = _free_rows(h_cand, h_ant, slot, cand, a)
    rows_b = _free_rows(h_cand, h_ant, slot, cand, b)
    for r in range(dim):
        for d in range(dim):
            if rows_a[r, d] != rows_b[r, d]:
                return False
    return True


@nb.njit(cache=True)
def _inside_cone(h_cand, h_ant, friction, slot, cand, a, force, dim):
    """Whether the sum of the loads `force` [N s] of the free bodies lies in the Coulomb cone
    of support contact a (the sum of such cones is the cone: what the supports can carry)."""
    rows = _free_rows(h_cand, h_ant, slot, cand, a)
    local = np.zeros(dim)
    for k in range(force.shape[0]):
        for r in range(dim):
            for d in range(dim):
                local[r] += rows[r, d] * force[k, d]
    tangent = abs(local[0]) if dim == 2 else math.hypot(local[0], local[2])
    return local[1] >= 0.0 and tangent <= friction[a] * local[1]


@nb.njit(cache=True)
def _pattern(cand, ant, closed, slot, nfree, size):
    """The body-space matrix in CSC form, a size x size block (size: a body's dof) for each
    free body and each pair of free bodies in closed contact: (indptr, row indices (int32),
    position in the data array of each closed contact's blocks (cand, cand), (ant, cand),
    (cand, ant), (ant, ant) (-1 where a body is not free; entry (dr, dc) of a block at
    position + dc * size * (blocks in its column) + dr), position of each free body's diagonal
    block, and the pattern of blocks: block column c's rows blocks[bptr[c]:bptr[c + 1]],
    sorted)."""
    m = closed.shape[0]
    # block rows of each block column: the body itself and the bodies it touches (in contact
    # order, repeated for each contact)
    count = np.ones(nfree, dtype=np.int64)
    for k in range(m):
        i = slot[cand[closed[k]]]
        j = slot[ant[closed[k]]]
        if i >= 0 and j >= 0:
            count[i] += 1
            count[j] += 1
    first = np.zeros(nfree + 1, dtype=np.int64)
    for col in range(nfree):
        first[col + 1] = first[col] + count[col]
    rows = np.empty(first[nfree], dtype=np.int64)
    fill = first[:nfree].copy()
    for col in range(nfree):
        rows[fill[col]] = col
        fill[col] += 1
    for k in range(m):
        i = slot[cand[closed[k]]]
        j = slot[ant[closed[k]]]
        if i >= 0 and j >= 0:
            rows[fill[j]] = i
            fill[j] += 1
            rows[fill[i]] = j
            fill[i] += 1
    # the same, sorted and without repeats: row r joins the columns of its neighbours, r in
    # increasing order (the pattern is symmetric)
    last = np.full(nfree, -1, dtype=np.int64)
    bptr = np.zeros(nfree + 1, dtype=np.int64)
    for r in range(nfree):
        for x in range(first[r], first[r + 1]):
            if last[rows[x]] != r:
                last[rows[x]] = r
                bptr[rows[x] + 1] += 1
    for col in range(nfree):
        bptr[col + 1] += bptr[col]
    blocks = np.empty(bptr[nfree], dtype=np.int64)
    fill = bptr[:nfree].copy()
    for col in range(nfree):
        last[col] = -1
    for r in range(nfree):
        for x in range(first[r], first[r + 1]):
            col = rows[x]
            if last[col] != r:
                last[col] = r
                blocks[fill[col]] = r
                fill[col] += 1
    indptr = np.zeros(size * nfree + 1, dtype=np.int64)
    for col in range(nfree):
        per = size * (bptr[col + 1] - bptr[col])
        for dc in range(size):
            indptr[size * col + dc + 1] = indptr[size * col + dc] + per
    indices = np.empty(indptr[-1], dtype=np.int32)
    for col in range(nfree):
        for dc in range(size):
            at = indptr[size * col + dc]
            for blk in range(bptr[col], bptr[col + 1]):
                for dr in range(size):
                    indices[at] = size * blocks[blk] + dr
                    at += 1
    where = np.full((m, 4), -1, dtype=np.int64)
    for k in range(m):
        i = slot[cand[closed[k]]]
        j = slot[ant[closed[k]]]
        for q in range(2):
            col = i if q == 0 else j
            for r in range(2):
                row = i if r == 0 else j
                if row >= 0 and col >= 0:
                    blk = bptr[col]
                    while blocks[blk] != row:
                        blk += 1
                    where[k, 2 * q + r] = indptr[size * col] + size * (blk - bptr[col])
    diagonal = np.empty(nfree, dtype=np.int64)
    for col in range(nfree):
        blk = bptr[col]
        while blocks[blk] != col:
            blk += 1
        diagonal[col] = indptr[size * col] + size * (blk - bptr[col])
    return indptr, indices, where, diagonal, bptr, blocks


@nb.njit(cache=True)
def _start(closed, friction, impulse, force, margin):
    """(x (m, k) from the caller's impulses moved into the cones' interiors (k = 2 in 2D, 3 in
    3D: module doc), B (m, dim, k), r0 [N s]: the largest impulse a free body needs)."""
    m = closed.shape[0]
    dim = impulse.shape[1]
    scale = 0.0
    for k in range(force.shape[0]):
        size = abs(force[k, 0])
        for d in range(1, dim):
            size = math.hypot(size, force[k, d])
        scale = max(scale, size)
    if scale == 0.0:
        scale = 1.0
    x = np.empty((m, dim))
    b = np.zeros((m, dim, dim))
    for k in range(m):
        a = closed[k]
        if dim == 2:
            _orthant_start(friction[a], impulse[a], margin * scale, x[k], b[k])
        else:
            _lorentz_start(friction[a], impulse[a], margin * scale, x[k], b[k])
    return x, b, scale


@nb.njit(inline="always")
def _orthant_start(mu, r, margin, x, b):
    """2D: x = (mu R_n - R_t, mu R_n + R_t) clipped at 0, plus margin [N s]; B."""
    rt = r[0]
    rn = max(r[1], 0.0)
    if mu > 0.0:
        b[0, 0] = -0.5
        b[0, 1] = 0.5
        b[1, 0] = 0.5 / mu
        b[1, 1] = 0.5 / mu
        x[0] = max(mu * rn - rt, 0.0) + margin
        x[1] = max(mu * rn + rt, 0.0) + margin
    else:
        b[1, 0] = 1.0
        b[1, 1] = 1.0
        x[0] = 0.5 * rn + margin
        x[1] = 0.5 * rn + margin


@nb.njit(inline="always")
def _lorentz_start(mu, r, margin, x, b):
    """3D: x = (R_t, mu R_n, R_s) projected onto the cone |(x_t, x_s)| <= x_n (R_n clipped at
    0), x_n + margin [N s]; B = diag(1, 1 / mu, 1) (diag(0, 1, 0) for mu = 0)."""
    rn = max(r[1], 0.0)
    if mu > 0.0:
        b[0, 0] = 1.0
        b[1, 1] = 1.0 / mu
        b[2, 2] = 1.0
        xt = r[0]
        xn = mu * rn
        xs = r[2]
        tangent = math.hypot(xt, xs)
        if tangent > xn:  # the projection onto the cone's boundary
            xn = 0.5 * (xn + tangent)
            xt *= xn / tangent
            xs *= xn / tangent
        x[0] = xt
        x[1] = xn + margin
        x[2] = xs
    else:
        b[1, 1] = 1.0
        x[0] = 0.0
        x[1] = rn + margin
        x[2] = 0.0


@nb.njit(inline="always")
def _columns(h, a, bk, g):
    """g = G rows of one body: (H_body^T B)[d, i], dof x k."""
    dim = bk.shape[0]
    for d in range(h.shape[2]):
        for i in range(bk.shape[1]):
            acc = h[a, 0, d] * bk[0, i]
            for r in range(1, dim):
                acc += h[a, r, d] * bk[r, i]
            g[d, i] = acc


@nb.njit(inline="always")
def _hessian_inverse(bk, xk, scale, inv, grad):
    """inv = P^-1 (k x k), grad (k): of (1/2 r0^2) |B x|^2 + phi(x) at x."""
    if xk.shape[0] == 2:
        _orthant_hessian_inverse(bk, xk, scale, inv, grad)
    else:
        _lorentz_hessian_inverse(bk, xk, scale, inv, grad)


# The Hessian inverses are compiled once each and called (LLVM may still inline them);
# inline="always" typed them again at each call site: ~1.2 s more of a first run.
@nb.njit
def _orthant_hessian_inverse(bk, sk, scale, inv, grad):
    """2D, phi = -log x_1 - log x_2."""
    t = 1.0 / (scale * scale)
    q00 = bk[0, 0] * bk[0, 0] + bk[1, 0] * bk[1, 0]
    q01 = bk[0, 0] * bk[0, 1] + bk[1, 0] * bk[1, 1]
    q11 = bk[0, 1] * bk[0, 1] + bk[1, 1] * bk[1, 1]
    p00 = t * q00 + 1.0 / (sk[0] * sk[0])
    p01 = t * q01
    p11 = t * q11 + 1.0 / (sk[1] * sk[1])
    det = p00 * p11 - p01 * p01
    inv[0, 0] = p11 / det
    inv[0, 1] = -p01 / det
    inv[1, 0] = -p01 / det
    inv[1, 1] = p00 / det
    grad[0] = t * (q00 * sk[0] + q01 * sk[1]) - 1.0 / sk[0]
    grad[1] = t * (q01 * sk[0] + q11 * sk[1]) - 1.0 / sk[1]


@nb.njit
def _lorentz_hessian_inverse(bk, xk, scale, inv, grad):
    """3D, phi = -log Q, Q = x_n^2 - x_t^2 - x_s^2 (module doc): P = t D + grad^2 phi with
    t = 1 / r0^2, D = B^T B; P^-1 = Y (I + t D Y)^-1 from the barrier's closed-form inverse
    Hessian Y, which stays accurate near the cone's boundary where grad^2 phi itself is
    ill-conditioned (I + t D Y is similar to an SPD matrix with eigenvalues >= 1)."""
    t = 1.0 / (scale * scale)
    x0, x1, x2 = xk[0], xk[1], xk[2]
    tangent = math.hypot(x0, x2)
    q = (x1 - tangent) * (x1 + tangent)
    y = np.empty((3, 3))  # x x^T - (Q / 2) J
    for i in range(3):
        for j in range(3):
            y[i, j] = xk[i] * xk[j]
    y[0, 0] += 0.5 * q
    y[1, 1] = 0.5 * (x1 * x1 + tangent * tangent)
    y[2, 2] += 0.5 * q
    dd = np.empty((3, 3))  # D = B^T B
    for i in range(3):
        for j in range(3):
            dd[i, j] = bk[0, i] * bk[0, j] + bk[1, i] * bk[1, j] + bk[2, i] * bk[2, j]
    a = np.empty((3, 3))  # I + t D Y
    for i in range(3):
        for j in range(3):
            a[i, j] = t * (dd[i, 0] * y[0, j] + dd[i, 1] * y[1, j] + dd[i, 2] * y[2, j])
        a[i, i] += 1.0
    for j in range(3):  # row j of Y A^-1 solves A^T z = (row j of Y)
        inv[j, 0], inv[j, 1], inv[j, 2] = solve3(a[0, 0], a[1, 0], a[2, 0], a[0, 1], a[1, 1],
                                                 a[2, 1], a[0, 2], a[1, 2], a[2, 2], y[j, 0],
                                                 y[j, 1], y[j, 2])
    for i in range(3):  # symmetric in exact arithmetic
        for j in range(i + 1, 3):
            mean = 0.5 * (inv[i, j] + inv[j, i])
            inv[i, j] = mean
            inv[j, i] = mean
    for i in range(3):
        grad[i] = t * (dd[i, 0] * x0 + dd[i, 1] * x1 + dd[i, 2] * x2)
    grad[0] += 2.0 * x0 / q
    grad[1] -= 2.0 * x1 / q
    grad[2] += 2.0 * x2 / q


@nb.njit(cache=True)
def _newton_system(cand, ant, h_cand, h_ant, closed, slot, b, x, scale, where, diagonal, indptr,
                   rhs, data):
    """data = G P^-1 G^T in the CSC pattern of _pattern (1 on the diagonal of a free body in
    no closed contact, which has f = 0 there: _rest_contacts), and rhs -= G P^-1 grad
    (rhs holds the residual G x - f on entry): the Schur complement of one Newton step."""
    size = rhs.shape[1]
    nk = x.shape[1]
    data[:] = 0.0
    pg = np.empty(nk)
    gp = np.empty((size, nk))  # G_r P^-1
    inv = np.empty((nk, nk))
    grad = np.empty(nk)
    gs = (np.empty((size, nk)), np.empty((size, nk)))
    for k in range(closed.shape[0]):
        a = closed[k]
        _hessian_inverse(b[k], x[k], scale, inv, grad)
        _columns(h_cand, a, b[k], gs[0])
        _columns(h_ant, a, b[k], gs[1])
        bodies = (slot[cand[a]], slot[ant[a]])
        for i in range(nk):
            acc = inv[i, 0] * grad[0]
            for j in range(1, nk):
                acc += inv[i, j] * grad[j]
            pg[i] = acc
        for r in range(2):
            row = bodies[r]
            if row < 0:
                continue
            gr = gs[r]
            for d in range(size):
                acc = gr[d, 0] * pg[0]
                for i in range(1, nk):
                    acc += gr[d, i] * pg[i]
                rhs[row, d] -= acc
            for d in range(size):
                for i in range(nk):
                    acc = gr[d, 0] * inv[0, i]
                    for j in range(1, nk):
                        acc += gr[d, j] * inv[j, i]
                    gp[d, i] = acc
            for q in range(2):
                at = where[k, 2 * q + r]
                if at < 0:
                    continue
                col = bodies[q]
                per = indptr[size * col + 1] - indptr[size * col]
                gq = gs[q]
                for dc in range(size):
                    for dr in range(size):
                        acc = gp[dr, 0] * gq[dc, 0]
                        for i in range(1, nk):
                            acc += gp[dr, i] * gq[dc, i]
                        data[at + dc * per + dr] += acc
    for col in range(diagonal.shape[0]):
        per = indptr[size * col + 1] - indptr[size * col]
        for d in range(size):
            at = diagonal[col] + d * per + d
            if data[at] == 0.0:
                data[at] = 1.0


@nb.njit(cache=True)
def _newton_step(cand, ant, h_cand, h_ant, closed, slot, b, x, scale, nu, gradient, step):
    """step = -P^-1 (grad + G^T nu) (without grad if not `gradient`)."""
    nk = x.shape[1]
    w = np.empty(nk)
    inv = np.empty((nk, nk))
    grad = np.empty(nk)
    g = np.empty((nu.shape[1], nk))
    for k in range(closed.shape[0]):
        a = closed[k]
        _hessian_inverse(b[k], x[k], scale, inv, grad)
        for i in range(nk):
            w[i] = grad[i] if gradient else 0.0
        for h, body in ((h_cand, slot[cand[a]]), (h_ant, slot[ant[a]])):
            if body < 0:
                continue
            _columns(h, a, b[k], g)
            for d in range(nu.shape[1]):
                for i in range(nk):
                    w[i] += g[d, i] * nu[body, d]
        for i in range(nk):
            acc = inv[i, 0] * w[0]
            for j in range(1, nk):
                acc += inv[i, j] * w[j]
            step[k, i] = -acc


@nb.njit(cache=True)
def _step_length(x, step):
    """1, or 0.99 of the step to the nearest cone's boundary if that is shorter."""
    alpha = 1.0
    for k in range(x.shape[0]):
        if x.shape[1] == 2:
            for i in range(2):
                if step[k, i] < 0.0:
                    alpha = min(alpha, -0.99 * x[k, i] / step[k, i])
        else:
            alpha = min(alpha, 0.99 * _lorentz_exit(x[k], step[k]))
    return alpha


@nb.njit(inline="always")
def _lorentz_exit(x, dx):
    """The least a > 0 with x + a dx on the boundary of the cone |(x_t, x_s)| <= x_n (inf if
    none; x inside): the first positive root of Q(x + a dx) = A a^2 + 2 B a + C, C = Q(x) > 0,
    from the numerically stable pair of roots q / A, C / q, q = -(B + sign(B) sqrt(B^2 - AC)).
    A > 0 is dx inside the cone (the half-line stays inside) or inside its opposite (it leaves,
    with real roots: B^2 - AC >= 0 but for round-off where the line passes through the apex);
    A <= 0 gives B^2 - AC >= 0 anyway."""
    tangent = math.hypot(x[0], x[2])
    c = (x[1] - tangent) * (x[1] + tangent)
    aa = dx[1] * dx[1] - dx[0] * dx[0] - dx[2] * dx[2]
    if aa > 0.0 and dx[1] > 0.0:
        return math.inf
    bb = x[1] * dx[1] - x[0] * dx[0] - x[2] * dx[2]
    disc = max(bb * bb - aa * c, 0.0)
    q = -(bb + math.copysign(math.sqrt(disc), bb))
    exit_ = math.inf
    if q != 0.0:
        if c / q > 0.0:
            exit_ = c / q
        if aa != 0.0 and q / aa > 0.0:
            exit_ = min(exit_, q / aa)
    return exit_


@nb.njit(cache=True)
def _inside(x):
    """Every contact's x strictly inside its cone."""
    for k in range(x.shape[0]):
        if x.shape[1] == 2:
            if not (x[k, 0] > 0.0 and x[k, 1] > 0.0):
                return False
        elif not x[k, 1] > math.hypot(x[k, 0], x[k, 2]):
            return False
    return True


@nb.njit(inline="always")
def _impulse(bk, xk, out):
    """out = B x [N s] of one contact."""
    for i in range(bk.shape[0]):
        acc = bk[i, 0] * xk[0]
        for j in range(1, xk.shape[0]):
            acc += bk[i, j] * xk[j]
        out[i] = acc


@nb.njit(cache=True)
def _residual(cand, ant, h_cand, h_ant, closed, slot, b, x, force, inv_mass, out):
    """out = G x - f [N s] per free body; returns its norm |.|_M^-1."""
    dim = b.shape[1]
    r = np.empty(dim)
    out[:, :] = 0.0
    for k in range(closed.shape[0]):
        a = closed[k]
        _impulse(b[k], x[k], r)
        for h, body in ((h_cand, slot[cand[a]]), (h_ant, slot[ant[a]])):
            if body < 0:
                continue
            for d in range(out.shape[1]):
                acc = h[a, 0, d] * r[0]
                for i in range(1, dim):
                    acc += h[a, i, d] * r[i]
                out[body, d] += acc
    out -= force
    return _norm_m(out, slot, inv_mass)


@nb.njit(cache=True)
def _norm_m(x, slot, inv_mass):
    """|x|_M^-1 [N s] of body-space x (one row per free body)."""
    total = 0.0
    for body in range(slot.shape[0]):
        k = slot[body]
        if k >= 0:
            for d in range(x.shape[1]):
                total += inv_mass[body, d] * x[k, d] * x[k, d]
    return math.sqrt(total)


@nb.njit(cache=True)
def _scatter(closed, b, x, count, impulse):
    """impulse = B x [N s] on the closed contacts, 0 on the others."""
    impulse[:count] = 0.0
    for k in range(closed.shape[0]):
        _impulse(b[k], x[k], impulse[closed[k]])


@nb.njit(cache=True)
def _apply(cand, ant, h_cand, h_ant, active, count, closed, b, x, inv_mass, v_free, impulse,
           v):
    """impulse = B x on the closed contacts, 0 on the others; v = v_free + M^-1 H R."""
    dim = b.shape[1]
    _scatter(closed, b, x, count, impulse)
    for body in range(v.shape[0]):
        for d in range(v.shape[1]):
            v[body, d] = v_free[body, d]
    for a in range(count):
        if not active[a]:
            continue
        c = cand[a]
        o = ant[a]
        for d in range(v.shape[1]):
            fc = h_cand[a, 0, d] * impulse[a, 0]
            fo = h_ant[a, 0, d] * impulse[a, 0]
            for i in range(1, dim):
                fc += h_cand[a, i, d] * impulse[a, i]
                fo += h_ant[a, i, d] * impulse[a, i]
            v[c, d] += inv_mass[c, d] * fc
            v[o, d] += inv_mass[o, d] * fo
