"""The rest solution of a step's contact problem, when there is one: impulses in the Coulomb
cones that bring every free body to rest relative to its supports.

Rest means: every free body ends the step with the velocity V of the supports (fixed and
driven bodies) that it touches, which must share one translation (V = 0 for fixed supports;
a driven ground moving as a whole). Every contact whose law asks U_n + b_n >= 0 with b_n = 0
("closed": Signorini and gap-based laws with a gap within closed_gap, restitution on a contact
that does not approach) then has U = 0, which satisfies Signorini (U_n = 0) and Coulomb (stick)
whatever impulse R_alpha in the cone |R_t| <= mu R_n it carries; every other contact must have
U_n + b_n >= 0 at rest, and carries nothing. So the rest solution exists exactly when the
impulse balance of the free bodies
    sum_alpha H_alpha R_alpha = f = M (V - v_free)          (v = v_free + M^-1 H R = V)
has a solution with every closed contact's R_alpha in its cone: a static equilibrium (the
lower-bound problem of limit analysis, with the step's impulses for forces). When it exists it
is a solution of the step's problem (the laws are unchanged; with friction a step's solution
need not be unique, and this one is the solution at rest). It takes a handful of sparse
factorizations where Gauss-Seidel needs as many sweeps as the slowest deformation mode of the
assembly takes to relax: tens of thousands for a slender tower (saxum.solver.nlgs).

Each cone is written with two nonnegative coordinates, s_1 = mu R_n - R_t, s_2 = mu R_n + R_t
(R = B s: R_t = (s_2 - s_1) / 2, R_n = (s_1 + s_2) / (2 mu); for mu = 0, R_n = s_1 + s_2 and
R_t = 0), and
    minimize  (1 / 2 r0^2) sum |B s|^2 - sum log s   subject to   G s = f,  G = H B
by the infeasible-start Newton method (S. Boyd and L. Vandenberghe, "Convex Optimization",
2004, sec. 10.3): each step solves the KKT system through its Schur complement G P^-1 G^T
(P the Hessian, 2 x 2 per contact), a body-space sparse matrix with a 3 x 3 block for each
free body and each pair of free bodies in closed contact (scipy's SuperLU), and moves towards
G s = f as far as s > 0 allows (0.99 of the way to the nearest s_i = 0). It stops at the
first s > 0 with G s = f to round-off: any such s is a rest solution, and the barrier keeps it
strictly inside every cone, so that Gauss-Seidel keeps it as it is (every contact sticks with a
margin). Which of the many rest solutions of a statically indeterminate assembly it returns
depends on the starting point (the caller's impulses) and r0 [N s], the largest impulse a free
body needs; all give the same velocities. When there is none (a mechanism under the loads,
e.g. an arch thinner than its limit), the steps shrink to nothing within a few iterations.
"""

import math

import numba as nb
import numpy as np

__all__ = ["rest_solution"]

_ITERATIONS = 40
"""Newton iterations before the rest solution is given up (none exists, or it is not found)."""
_FEASIBLE = 1e-10
"""Relative residual |G s - f|_M^-1 / |f|_M^-1 at which s counts as a solution (round-off is
about 1e-13: a rest solution leaves velocities of 1e-10 of those of one step of the loads)."""
_FLOOR = 1e-8
"""... or at which it does, after a full Newton step that did not halve it (round-off of the
factorization)."""
_STALLED = 1e-3
"""Steps shorter than this, three in a row, mean no rest solution: the residual, which each
step shrinks by its length, stops shrinking (the barrier holds s off the cones' edges that
the loads would have to cross)."""


def rest_solution(problem, impulse: np.ndarray, v_free: np.ndarray, v: np.ndarray) -> bool:
    """If the step's problem (saxum.solver.ContactProblem or a view with the same arrays) has a
    rest solution, write its impulses [N s] into `impulse` (R = 0 for the contacts that do not
    carry any) and v = v_free + M^-1 H R [m/s, rad/s] (V for the free bodies, to round-off;
    v_free for the others) into `v`, and return True. Otherwise (no rest solution, or none found in
    _ITERATIONS Newton steps) leave both untouched and return False. The caller's impulses are
    the starting point: among the solutions, it returns one near them."""
    count = problem.count
    v_begin = getattr(problem, "v_begin", None)
    if count == 0 or v_begin is None or problem.model.dof != 3:  # written for 2D rigid bodies
        return False
    c = problem.contacts
    inv_mass = problem.model.body_inv_mass
    slot = np.empty(len(inv_mass), dtype=np.int64)
    closed = np.empty(count, dtype=np.int64)
    m, nfree, force = _rest_contacts(c.candidate, c.antagonist, problem.h_cand, problem.h_ant,
                                     problem.bias, problem.active, count, inv_mass, v_begin,
                                     v_free, slot, closed)
    if m <= 0:
        return False
    closed = closed[:m]
    indptr, indices, where, diagonal = _pattern(c.candidate, c.antagonist, closed, slot, nfree)
    s, b, scale = _start(closed, problem.friction, impulse, force)
    data = np.zeros(len(indices))
    rhs = np.empty((nfree, 3))
    step = np.empty_like(s)
    residual = _residual(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, closed, slot,
                         b, s, force, inv_mass, rhs)
    size = _norm_m(force, slot, inv_mass)
    alpha = 0.0
    short = 0
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu

    for _ in range(_ITERATIONS):
        if residual <= _FEASIBLE * size:
            break
        _newton_system(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, closed, slot,
                       b, s, scale, where, diagonal, indptr, rhs, data)
        try:
            # symmetric positive definite: a symmetric fill-reducing order, no pivoting
            lu = splu(csc_matrix((data, indices, indptr), shape=(3 * nfree, 3 * nfree)),
                      permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                      options={"SymmetricMode": True})
        except RuntimeError:  # singular: a free body's motion that no contact resists
            return False
        nu = lu.solve(rhs.reshape(-1)).reshape(nfree, 3)
        if not np.all(np.isfinite(nu)):
            return False
        _newton_step(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, closed, slot, b,
                     s, scale, nu, step)
        alpha = _step_length(s, step)
        short = short + 1 if alpha < _STALLED else 0
        if short == 3:
            return False
        s += alpha * step
        before = residual
        residual = _residual(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, closed,
                             slot, b, s, force, inv_mass, rhs)
        if alpha == 1.0 and residual > 0.5 * before:
            break
    if not residual <= (_FLOOR if alpha == 1.0 else _FEASIBLE) * size:
        return False
    _apply(c.candidate, c.antagonist, problem.h_cand, problem.h_ant, problem.active, count,
           closed, b, s, inv_mass, v_free, impulse, v)
    return True


@nb.njit(cache=True)
def _rest_contacts(cand, ant, h_cand, h_ant, bias, active, count, inv_mass, v_begin, v_free,
                   slot, closed):
    """Check the rest hypothesis: slot[b] = index of free body b among the free bodies (-1
    for the others), closed[:m] = the closed contacts. Returns (m, free bodies, f [N s] per
    free body: M (V - v_free), V the supports' velocity (see rest_solution)), m = -1 when no
    rest solution can exist: supports in closed contact that do not share one translation,
    an open contact that would close, a restitution target, or a free body that needs an
    impulse and has no closed contact; or when it is not worth looking for: the blocks move
    relative to the supports (|v_begin - V|_M above |v_free - v_begin|_M, the velocity that
    one step of the loads gives: a structure in motion, which the contacts would have to stop
    within one step)."""
    nfree = 0
    for b in range(inv_mass.shape[0]):
        if inv_mass[b, 0] > 0.0:
            slot[b] = nfree
            nfree += 1
        else:
            slot[b] = -1
    force = np.zeros((nfree, 3))
    # V: the velocity of the supports in closed contact (a translation, the same for all)
    frame = np.zeros(3)
    framed = False
    for k in range(2 * count):
        a = k // 2
        body = cand[a] if k % 2 == 0 else ant[a]
        if active[a] and bias[a] == 0.0 and slot[body] < 0:
            if not framed:
                framed = True
                for d in range(3):
                    frame[d] = v_free[body, d]
            elif (v_free[body, 0] != frame[0] or v_free[body, 1] != frame[1]
                  or v_free[body, 2] != frame[2]):
                return -1, nfree, force
    if frame[2] != 0.0:
        return -1, nfree, force
    moving = 0.0
    loads = 0.0
    for b in range(inv_mass.shape[0]):
        if slot[b] >= 0:
            for d in range(3):
                if not inv_mass[b, d] > 0.0:
                    return -1, nfree, force
                force[slot[b], d] = (frame[d] - v_free[b, d]) / inv_mass[b, d]
                moving += (v_begin[b, d] - frame[d]) ** 2 / inv_mass[b, d]
                loads += (v_free[b, d] - v_begin[b, d]) ** 2 / inv_mass[b, d]
    if moving > loads:
        return -1, nfree, force
    held = np.zeros(nfree, dtype=np.bool_)
    m = 0
    for a in range(count):
        if not active[a]:
            continue
        c = cand[a]
        b = ant[a]
        if bias[a] == 0.0:  # U = 0 at rest: every body in it moves with V (checked above)
            closed[m] = a
            m += 1
            if slot[c] >= 0:
                held[slot[c]] = True
            if slot[b] >= 0:
                held[slot[b]] = True
            continue
        # an open contact: U_n + b_n >= 0 at rest, free bodies moving with V
        un = bias[a]
        for d in range(3):
            vc = frame[d] if slot[c] >= 0 else v_free[c, d]
            vb = frame[d] if slot[b] >= 0 else v_free[b, d]
            un += h_cand[a, 1, d] * vc + h_ant[a, 1, d] * vb
        if un < 0.0:
            return -1, nfree, force
    for k in range(nfree):
        if not held[k] and (force[k, 0] != 0.0 or force[k, 1] != 0.0 or force[k, 2] != 0.0):
            return -1, nfree, force
    return m, nfree, force


@nb.njit(cache=True)
def _pattern(cand, ant, closed, slot, nfree):
    """The body-space matrix in CSC form, a 3 x 3 block for each free body and each pair of
    free bodies in closed contact: (indptr, row indices (int32), position in the data array of
    each closed contact's blocks (cand, cand), (ant, cand), (cand, ant), (ant, ant) (-1 where a
    body is not free; entry (dr, dc) of a block at position + dc * 3 (blocks in its column) +
    dr), position of each free body's diagonal block)."""
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
    indptr = np.zeros(3 * nfree + 1, dtype=np.int64)
    for col in range(nfree):
        per = 3 * (bptr[col + 1] - bptr[col])
        for dc in range(3):
            indptr[3 * col + dc + 1] = indptr[3 * col + dc] + per
    indices = np.empty(indptr[-1], dtype=np.int32)
    for col in range(nfree):
        for dc in range(3):
            at = indptr[3 * col + dc]
            for blk in range(bptr[col], bptr[col + 1]):
                for dr in range(3):
                    indices[at] = 3 * blocks[blk] + dr
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
                    where[k, 2 * q + r] = indptr[3 * col] + 3 * (blk - bptr[col])
    diagonal = np.empty(nfree, dtype=np.int64)
    for col in range(nfree):
        blk = bptr[col]
        while blocks[blk] != col:
            blk += 1
        diagonal[col] = indptr[3 * col] + 3 * (blk - bptr[col])
    return indptr, indices, where, diagonal


@nb.njit(cache=True)
def _start(closed, friction, impulse, force):
    """(s [N s] (m, 2) from the caller's impulses moved into the cones' interiors, B (m, 2, 2),
    r0 [N s]: the largest impulse a free body needs)."""
    m = closed.shape[0]
    scale = 0.0
    for k in range(force.shape[0]):
        scale = max(scale, math.hypot(force[k, 0], force[k, 1]))
    if scale == 0.0:
        scale = 1.0
    s = np.empty((m, 2))
    b = np.zeros((m, 2, 2))
    for k in range(m):
        a = closed[k]
        mu = friction[a]
        rt = impulse[a, 0]
        rn = max(impulse[a, 1], 0.0)
        if mu > 0.0:
            b[k, 0, 0] = -0.5
            b[k, 0, 1] = 0.5
            b[k, 1, 0] = 0.5 / mu
            b[k, 1, 1] = 0.5 / mu
            s[k, 0] = max(mu * rn - rt, 0.0) + 0.1 * scale
            s[k, 1] = max(mu * rn + rt, 0.0) + 0.1 * scale
        else:
            b[k, 1, 0] = 1.0
            b[k, 1, 1] = 1.0
            s[k, 0] = 0.5 * rn + 0.1 * scale
            s[k, 1] = 0.5 * rn + 0.1 * scale
    return s, b, scale


@nb.njit(inline="always")
def _columns(h, a, bk):
    """G rows of one body: (H_body^T B)[d, i], 3 x 2."""
    g = np.empty((3, 2))
    for d in range(3):
        for i in range(2):
            g[d, i] = h[a, 0, d] * bk[0, i] + h[a, 1, d] * bk[1, i]
    return g


@nb.njit(inline="always")
def _hessian_inverse(bk, sk, scale):
    """(P^-1 (2 x 2), gradient (2)) of (1/2 r0^2) |B s|^2 - log s_1 - log s_2 at s."""
    t = 1.0 / (scale * scale)
    q00 = bk[0, 0] * bk[0, 0] + bk[1, 0] * bk[1, 0]
    q01 = bk[0, 0] * bk[0, 1] + bk[1, 0] * bk[1, 1]
    q11 = bk[0, 1] * bk[0, 1] + bk[1, 1] * bk[1, 1]
    p00 = t * q00 + 1.0 / (sk[0] * sk[0])
    p01 = t * q01
    p11 = t * q11 + 1.0 / (sk[1] * sk[1])
    det = p00 * p11 - p01 * p01
    inv = np.empty((2, 2))
    inv[0, 0] = p11 / det
    inv[0, 1] = -p01 / det
    inv[1, 0] = -p01 / det
    inv[1, 1] = p00 / det
    grad = np.empty(2)
    grad[0] = t * (q00 * sk[0] + q01 * sk[1]) - 1.0 / sk[0]
    grad[1] = t * (q01 * sk[0] + q11 * sk[1]) - 1.0 / sk[1]
    return inv, grad


@nb.njit(cache=True)
def _newton_system(cand, ant, h_cand, h_ant, closed, slot, b, s, scale, where, diagonal, indptr,
                   rhs, data):
    """data = G P^-1 G^T in the CSC pattern of _pattern (1 on the diagonal of a free body in
    no closed contact, which has f = 0 there: _rest_contacts), and rhs -= G P^-1 grad
    (rhs holds the residual G s - f on entry): the Schur complement of one Newton step."""
    data[:] = 0.0
    for k in range(closed.shape[0]):
        a = closed[k]
        inv, grad = _hessian_inverse(b[k], s[k], scale)
        gs = (_columns(h_cand, a, b[k]), _columns(h_ant, a, b[k]))
        bodies = (slot[cand[a]], slot[ant[a]])
        pg0 = inv[0, 0] * grad[0] + inv[0, 1] * grad[1]
        pg1 = inv[1, 0] * grad[0] + inv[1, 1] * grad[1]
        for r in range(2):
            row = bodies[r]
            if row < 0:
                continue
            gr = gs[r]
            for d in range(3):
                rhs[row, d] -= gr[d, 0] * pg0 + gr[d, 1] * pg1
            gp = np.empty((3, 2))  # G_r P^-1
            for d in range(3):
                gp[d, 0] = gr[d, 0] * inv[0, 0] + gr[d, 1] * inv[1, 0]
                gp[d, 1] = gr[d, 0] * inv[0, 1] + gr[d, 1] * inv[1, 1]
            for q in range(2):
                at = where[k, 2 * q + r]
                if at < 0:
                    continue
                col = bodies[q]
                per = indptr[3 * col + 1] - indptr[3 * col]
                gq = gs[q]
                for dc in range(3):
                    for dr in range(3):
                        data[at + dc * per + dr] += gp[dr, 0] * gq[dc, 0] + gp[dr, 1] * gq[dc, 1]
    for col in range(diagonal.shape[0]):
        per = indptr[3 * col + 1] - indptr[3 * col]
        for d in range(3):
            at = diagonal[col] + d * per + d
            if data[at] == 0.0:
                data[at] = 1.0


@nb.njit(cache=True)
def _newton_step(cand, ant, h_cand, h_ant, closed, slot, b, s, scale, nu, step):
    """step = -P^-1 (grad + G^T nu)."""
    for k in range(closed.shape[0]):
        a = closed[k]
        inv, grad = _hessian_inverse(b[k], s[k], scale)
        w0 = grad[0]
        w1 = grad[1]
        for h, body in ((h_cand, slot[cand[a]]), (h_ant, slot[ant[a]])):
            if body < 0:
                continue
            g = _columns(h, a, b[k])
            for d in range(3):
                w0 += g[d, 0] * nu[body, d]
                w1 += g[d, 1] * nu[body, d]
        step[k, 0] = -(inv[0, 0] * w0 + inv[0, 1] * w1)
        step[k, 1] = -(inv[1, 0] * w0 + inv[1, 1] * w1)


@nb.njit(cache=True)
def _step_length(s, step):
    """1, or 0.99 of the step to the nearest s_i = 0 if that is shorter."""
    alpha = 1.0
    for k in range(s.shape[0]):
        for i in range(2):
            if step[k, i] < 0.0:
                alpha = min(alpha, -0.99 * s[k, i] / step[k, i])
    return alpha


@nb.njit(cache=True)
def _residual(cand, ant, h_cand, h_ant, closed, slot, b, s, force, inv_mass, out):
    """out = G s - f [N s] per free body; returns its norm |.|_M^-1."""
    out[:, :] = 0.0
    for k in range(closed.shape[0]):
        a = closed[k]
        rt = b[k, 0, 0] * s[k, 0] + b[k, 0, 1] * s[k, 1]
        rn = b[k, 1, 0] * s[k, 0] + b[k, 1, 1] * s[k, 1]
        c = slot[cand[a]]
        if c >= 0:
            for d in range(3):
                out[c, d] += h_cand[a, 0, d] * rt + h_cand[a, 1, d] * rn
        o = slot[ant[a]]
        if o >= 0:
            for d in range(3):
                out[o, d] += h_ant[a, 0, d] * rt + h_ant[a, 1, d] * rn
    out -= force
    return _norm_m(out, slot, inv_mass)


@nb.njit(cache=True)
def _norm_m(x, slot, inv_mass):
    """|x|_M^-1 [N s] of body-space x (one row per free body)."""
    total = 0.0
    for body in range(slot.shape[0]):
        k = slot[body]
        if k >= 0:
            for d in range(3):
                total += inv_mass[body, d] * x[k, d] * x[k, d]
    return math.sqrt(total)


@nb.njit(cache=True)
def _apply(cand, ant, h_cand, h_ant, active, count, closed, b, s, inv_mass, v_free, impulse,
           v):
    """impulse = B s on the closed contacts, 0 on the others; v = v_free + M^-1 H R."""
    for a in range(count):
        impulse[a, 0] = 0.0
        impulse[a, 1] = 0.0
    for k in range(closed.shape[0]):
        a = closed[k]
        impulse[a, 0] = b[k, 0, 0] * s[k, 0] + b[k, 0, 1] * s[k, 1]
        impulse[a, 1] = b[k, 1, 0] * s[k, 0] + b[k, 1, 1] * s[k, 1]
    for body in range(v.shape[0]):
        for d in range(3):
            v[body, d] = v_free[body, d]
    for a in range(count):
        if not active[a]:
            continue
        c = cand[a]
        o = ant[a]
        rt = impulse[a, 0]
        rn = impulse[a, 1]
        for d in range(3):
            v[c, d] += inv_mass[c, d] * (h_cand[a, 0, d] * rt + h_cand[a, 1, d] * rn)
            v[o, d] += inv_mass[o, d] * (h_ant[a, 0, d] * rt + h_ant[a, 1, d] * rn)
