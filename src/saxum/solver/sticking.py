"""The sticking solution of a step with deformable blocks: the impulses with which every
closed contact sticks, U_n + b_n = 0 and U_t = 0, from one sparse solve of the step's linear
equations in node and body velocities (2D):

    [ A  H^T ] [ dv ]   [      0         ]      A = diag(R_s M~ R_s^T per deformable block,
    [ H   0  ] [ -R ] = [ -(H v_free + b) ]             M of the free rigid bodies),

v = v_free + dv, H the rows of the contacts in the solve (saxum.solver.problem, side by side
as in saxum.bodies.fe), b the normal shift of each law. Each contact has a status, first
that of its warm-start impulse (open for R_n = 0, sliding on the cone's edge, else
sticking), and after each solve an active set changes it: a closed contact with R_n < 0
opens (R = 0), a sticking one outside its Coulomb cone slides (R_t = +-mu R_n, U_n + b_n =
0), a sliding one whose slip goes with its friction impulse sticks, an open one with U_n +
b_n < 0 closes; up to _PASSES solves. When no status changes, this is a solution of the
step's problem (every law holds); when a few still change (at most _CHANGING of the
contacts), it is a start near one, from which NLGS sweeps on (the caller judges convergence
by the sweeps, as always); with more, it is not taken.

Why: a wall of elastic blocks has no rest solution (its nodes vibrate), and Gauss-Seidel
over node contacts converges as slowly as a Gauss-Seidel on the blocks' stiffness: hundreds
of sweeps per step for a wall at rest (benchmarks/wall_fe.py). Its contacts nearly all
stick, so one sparse LU (scipy's SuperLU) of the equations above gives what those sweeps
approach. The KKT form keeps M~ sparse; the Delassus matrix H A^-1 H^T would couple every
pair of contacts on a block (it is that system's Schur complement).
"""

import numba as nb
import numpy as np

from ..bodies.fe import side_velocity
from ..model import BodyKind

__all__ = ["sticking_solution"]

_REGULARIZATION = 1e-9
"""A compliance of this fraction of each row's Delassus diagonal [1/kg] in the equations'
lower right block: the contacts of nodes built coincident at a joint's corner have linearly
dependent rows (a node's tangent on one block is the difference of two normals on the block
below), which leave the exact equations singular; with it they share the redundant impulse
and each contact's U + b is off by 1e-9 of its W R, which NLGS's sweeps then take out."""

_PASSES = 8
"""Solves at most, each with the contacts' status (open, sticking, sliding) from the last
one's impulses and velocities (module doc)."""
_OPEN, _STICK, _SLIDE_UP, _SLIDE_DOWN = 0, 1, 2, 3
"""A contact's status in the solve: R = 0; U + b = 0; U_n + b_n = 0 and R_t = +mu R_n, or
-mu R_n."""
_CHANGING = 0.01
"""The start is taken when the last solve left at most this fraction of its contacts still
changing status (their impulses as that solve gave them: NLGS's local solves correct
them). Why not only settled statuses: on the 210-brick wall at rest (benchmarks/wall_fe.py),
a step whose last solves kept 6 to 10 of its 2940 contacts cycling between sticking and
sliding (neighbours along a joint at the edge of a sliding zone) took 385 sweeps from the
warm start and 37 from this one. With some 200 cycling (7 %), taking it helped some steps
and harmed others (three starts per step, 20 sweeps apart: 396, 286, 678 sweeps against 495,
421, 469 without) and under a pulse it was measured to harm (626 against 434 sweeps)."""
_EDGE = 1e-9
"""A warm-start impulse with |R_t| >= (1 - _EDGE) mu R_n is on its cone's edge: sliding."""
_SLACK = 1e-9
"""An open contact closes when its U_n + b_n falls below -_SLACK times the largest
|U_free + b| of the step: below the round-off of the solve, above nothing physical."""


@nb.njit(cache=True)
def _rows(side_kind, side_node, side_weight, cand, ant, h_cand, h_ant, bias, v_free,
          node_free, count, take, body_column, node_columns, rows, cols, vals, rhs):
    """Triplets of H over the contacts `take` (row 2 k: t, 2 k + 1: n of contact take[k]):
    an FE side's rows on its nodes' dofs (2 p, 2 p + 1), weighted; a rigid side's on the
    body's columns (body_column, -1 for bodies without unknowns); rhs = -(H v_free + b).
    Returns the number of triplets."""
    e = 0
    u = np.empty(2)
    for k in range(take.shape[0]):
        a = take[k]
        for side in range(2):
            rws = h_cand if side == 0 else h_ant
            body = cand[a] if side == 0 else ant[a]
            if side_kind[a, side] == 1:
                for i in range(side_node.shape[2]):
                    w = side_weight[a, side, i]
                    if w == 0.0:
                        continue
                    p = side_node[a, side, i]
                    for r in range(2):
                        for d in range(2):
                            rows[e] = 2 * k + r
                            cols[e] = 2 * p + d
                            vals[e] = w * rws[a, r, d]
                            e += 1
            elif body_column[body] >= 0:
                for r in range(2):
                    for d in range(3):
                        rows[e] = 2 * k + r
                        cols[e] = node_columns + body_column[body] + d
                        vals[e] = rws[a, r, d]
                        e += 1
        u[:] = 0.0
        side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0], cand[a],
                      v_free, node_free, u)
        side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1], ant[a],
                      v_free, node_free, u)
        rhs[2 * k] = -u[0]
        rhs[2 * k + 1] = -(u[1] + bias[a])
    return e


def _world_iteration_matrix(kind):
    """A of the deformable blocks: R_s M~ R_s^T node by node [kg], world axes, for the
    step's frames (FEKind.rotation)."""
    import scipy.sparse as sp

    b = kind.blocks
    n = b.n_nodes
    rot = kind.rotation[b.node_block]  # [N, 2, 2]
    rows = np.repeat(np.arange(2 * n), 2)
    cols = (2 * np.arange(n)[:, None, None] + np.array([0, 1])[None, None, :]
            + np.zeros((1, 2, 1), dtype=np.int64)).ravel()
    q = sp.csr_matrix((rot.ravel(), (rows, cols)), shape=(2 * n, 2 * n))
    return (q @ kind.iteration_matrix @ q.T).tocsr()


def _solve_status(a_matrix, h, rhs, status, mu, diagonal):
    """(x = (dv, -R) [m/s, N s], R [m, 2] [N s]) of the equations with each contact's rows by
    its status: sticking U + b = 0 (with _REGULARIZATION), sliding U_n + b_n = 0 and R_t =
    +-mu R_n, open R = 0."""
    import scipy.sparse as sp
    import scipy.sparse.linalg

    n = a_matrix.shape[0]
    m = len(status)
    open_ = status == _OPEN
    sliding = (status == _SLIDE_UP) | (status == _SLIDE_DOWN)
    keep = np.ones((m, 2))
    keep[open_] = 0.0
    keep[sliding, 0] = 0.0
    lower = _REGULARIZATION * diagonal
    lower[open_] = 1.0
    lower[sliding, 0] = 1.0
    k = np.flatnonzero(sliding)
    sign = np.where(status[k] == _SLIDE_UP, 1.0, -1.0)
    coupling = sp.csr_matrix((-sign * mu[k], (2 * k, 2 * k + 1)), shape=(2 * m, 2 * m))
    kkt = sp.bmat([[a_matrix, h.T], [sp.diags(keep.ravel()) @ h,
                                     -sp.diags(lower.ravel()) - coupling]], format="csc")
    x = scipy.sparse.linalg.splu(kkt, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                 options={"SymmetricMode": True}).solve(np.concatenate((np.zeros(n),
                                                             keep.ravel() * rhs)))
    return x, -x[n:].reshape(m, 2)


def sticking_solution(problem, impulse: np.ndarray, v_free: np.ndarray,
                      v: np.ndarray) -> bool:
    """Write the sticking solution (module doc) of the step's problem with deformable blocks
    (problem.fe) into `impulse` [N s] (0 for inactive and open contacts), v [m/s, rad/s]
    (the rigid bodies) and problem.fe.v (the nodes), and return True, when at most
    _CHANGING of its contacts still change status after the last of up to _PASSES solves;
    otherwise leave them untouched and return False."""
    import scipy.sparse as sp  # ~0.3 s with its linalg: imported by the runs with FE blocks

    kind = problem.fe
    c = problem.contacts
    model = problem.model
    count = problem.count
    take = np.flatnonzero(problem.active[:count]).astype(np.int64)
    free = np.flatnonzero(model.body_kind == BodyKind.FREE)
    body_column = np.full(model.body_count, -1, dtype=np.int64)
    body_column[free] = 3 * np.arange(len(free))
    node_columns = 2 * kind.blocks.n_nodes
    n = node_columns + 3 * len(free)
    mass = np.divide(1.0, model.body_inv_mass[free], out=np.zeros((len(free), 3)),
                     where=model.body_inv_mass[free] > 0.0).ravel()
    a_matrix = sp.block_diag((_world_iteration_matrix(kind), sp.diags(mass)), format="csr")
    m = len(take)
    rows = np.empty(16 * m, dtype=np.int64)
    cols = np.empty(16 * m, dtype=np.int64)
    vals = np.empty(16 * m)
    rhs = np.empty(2 * m)
    e = _rows(c.side_kind, c.side_node, c.side_weight, c.candidate, c.antagonist,
              problem.h_cand, problem.h_ant, problem.bias, v_free, kind.v_free, count, take,
              body_column, node_columns, rows, cols, vals, rhs)
    h = sp.csr_matrix((vals[:e], (rows[:e], cols[:e])), shape=(2 * m, n))
    mu = problem.friction[take]
    diagonal = problem.delassus[take][:, [0, 1], [0, 1]]
    # tolerance on U_n + b_n [m/s] of an open contact: round-off of the velocities
    slack = _SLACK * max(float(np.abs(rhs).max(initial=0.0)), 1e-300)
    # the status of the warm start's impulses (those of the last step, by contact): the
    # same joints open and slide from step to step, so that most steps need one solve
    warm = impulse[take]
    status = np.full(m, _STICK)
    status[warm[:, 1] <= 0.0] = _OPEN
    edge = (warm[:, 1] > 0.0) & (np.abs(warm[:, 0]) >= (1.0 - _EDGE) * mu * warm[:, 1])
    status[edge] = np.where(warm[edge, 0] > 0.0, _SLIDE_UP, _SLIDE_DOWN)
    changing = m
    for _ in range(_PASSES):
        x, r = _solve_status(a_matrix, h, rhs, status, mu, diagonal)
        u = h @ x[:n] - rhs  # U + b of every contact in the solve [m/s]
        new = status.copy()
        new[(status == _OPEN) & (u[1::2] < -slack)] = _STICK
        closed = status != _OPEN
        new[closed & (r[:, 1] < 0.0)] = _OPEN
        stick = new == _STICK
        outside = stick & (status == _STICK) & (np.abs(r[:, 0]) > mu * r[:, 1])
        new[outside] = np.where(r[outside, 0] > 0.0, _SLIDE_UP, _SLIDE_DOWN)
        # a slip against its friction impulse: it sticks
        sliding = (new == _SLIDE_UP) | (new == _SLIDE_DOWN)
        wrong = sliding & (status == new) & (u[0::2] * r[:, 0] > 0.0)
        new[wrong] = _STICK
        changing = int((new != status).sum())
        if changing == 0:
            break
        status = new
    if changing > _CHANGING * m:
        return False
    impulse[:count] = 0.0
    impulse[take] = r
    dv = x[:n]
    kind.v[:] = kind.v_free + dv[:node_columns].reshape(-1, 2)
    v[:] = v_free
    v[free] += dv[node_columns:].reshape(-1, 3)
    return True
