"""The sticking solution of a step with deformable blocks: the impulses with which every
closed contact sticks, U_n + b_n = 0 and U_t = 0, from one sparse solve of the step's linear
equations in node and body velocities (2D and 3D):

    [ A  H^T ] [ dv ]   [      0         ]      A = diag(R_s M~ R_s^T per deformable block,
    [ H   0  ] [ -R ] = [ -(H v_free + b) ]             M of the free rigid bodies),

v = v_free + dv, H the rows of the contacts in the solve (saxum.solver.problem, side by side
as in saxum.bodies.fe), b the normal shift of each law. Each contact has a status, first
that of its warm-start impulse (open for R_n = 0, sliding on the cone's edge, else
sticking), and after each solve an active set changes it: a closed contact with R_n < 0
opens (R = 0), a sticking one outside its Coulomb cone slides (R_t = mu R_n d, U_n + b_n =
0, d the unit direction of its friction impulse: +-1 in 2D, a unit vector of the tangent
plane in 3D, the friction cone's generatrix), a sliding one whose slip goes with its
friction impulse sticks, one whose slip turned (3D: by more than _TURN) slides on along
-U_t / |U_t| (not counted as a change of status: the directions of a few sliding contacts
settle over more solves than the statuses, and NLGS's local solves finish them), an open
one with U_n + b_n < 0 closes; up to _PASSES solves. When no status changes, this is a
solution of the step's problem (every law holds; in 3D, up to the sliding directions); when
a few still change (at most _CHANGING of the contacts), it is a start near one, from which
NLGS sweeps on (the caller judges convergence by the sweeps, as always); with more, it is
not taken.

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
_OPEN, _STICK, _SLIDE = 0, 1, 2
"""A contact's status in the solve: R = 0; U + b = 0; U_n + b_n = 0 and R_t = mu R_n d."""
_TURN = 1e-3
"""A 3D sliding contact whose slip direction -U_t / |U_t| differs from its d by more than
this [rad] (|d - (-U_t / |U_t|)|) slides along the slip's direction in the next solve."""
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
    """Triplets of H over the contacts `take` (rows d k + r of contact take[k], r in the
    contact's frame (t, n) or (t, n, s)): an FE side's rows on its nodes' dofs (d p + i),
    weighted; a rigid side's on the body's columns (body_column, -1 for bodies without
    unknowns); rhs = -(H v_free + b). Returns the number of triplets."""
    dim = h_cand.shape[1]
    dof = h_cand.shape[2]
    e = 0
    u = np.empty(dim)
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
                    for r in range(dim):
                        for d in range(dim):
                            rows[e] = dim * k + r
                            cols[e] = dim * p + d
                            vals[e] = w * rws[a, r, d]
                            e += 1
            elif body_column[body] >= 0:
                for r in range(dim):
                    for d in range(dof):
                        rows[e] = dim * k + r
                        cols[e] = node_columns + body_column[body] + d
                        vals[e] = rws[a, r, d]
                        e += 1
        u[:] = 0.0
        side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0], cand[a],
                      v_free, node_free, u)
        side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1], ant[a],
                      v_free, node_free, u)
        for r in range(dim):
            rhs[dim * k + r] = -u[r]
        rhs[dim * k + 1] -= bias[a]
    return e


def _world_iteration_matrix(kind):
    """A of the deformable blocks: R_s M~ R_s^T node by node [kg], world axes, for the
    step's frames (FEKind.rotation)."""
    import scipy.sparse as sp

    b = kind.blocks
    n, d = b.n_nodes, b.dim
    rot = kind.rotation[b.node_block]  # [N, d, d]
    rows = np.repeat(np.arange(d * n), d)
    cols = (d * np.arange(n)[:, None, None] + np.arange(d)[None, None, :]
            + np.zeros((1, d, 1), dtype=np.int64)).ravel()
    q = sp.csr_matrix((rot.ravel(), (rows, cols)), shape=(d * n, d * n))
    return (q @ kind.iteration_matrix @ q.T).tocsr()


def _solve_status(a_matrix, h, rhs, status, direction, mu, diagonal):
    """(x = (dv, -R) [m/s, N s], R [m, d] [N s]) of the equations with each contact's rows by
    its status: sticking U + b = 0 (with _REGULARIZATION), sliding U_n + b_n = 0 and R_t =
    mu R_n d (d = direction [m, d - 1]: the tangent axes t, and s in 3D), open R = 0."""
    import scipy.sparse as sp
    import scipy.sparse.linalg

    n = a_matrix.shape[0]
    m, dim = diagonal.shape
    tangent = [0] if dim == 2 else [0, 2]
    open_ = status == _OPEN
    sliding = status == _SLIDE
    keep = np.ones((m, dim))
    keep[open_] = 0.0
    lower = _REGULARIZATION * diagonal
    lower[open_] = 1.0
    k = np.flatnonzero(sliding)
    for j in tangent:
        keep[sliding, j] = 0.0
        lower[sliding, j] = 1.0
    rows = (dim * k[:, None] + np.array(tangent)[None, :]).ravel()
    coupling = sp.csr_matrix(((-mu[k, None] * direction[k]).ravel(),
                              (rows, np.repeat(dim * k + 1, len(tangent)))),
                             shape=(dim * m, dim * m))
    kkt = sp.bmat([[a_matrix, h.T], [sp.diags(keep.ravel()) @ h,
                                     -sp.diags(lower.ravel()) - coupling]], format="csc")
    x = scipy.sparse.linalg.splu(kkt, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                 options={"SymmetricMode": True}).solve(np.concatenate((np.zeros(n),
                                                             keep.ravel() * rhs)))
    return x, -x[n:].reshape(m, dim)


def _tangent(values: np.ndarray) -> np.ndarray:
    """The tangent components [m, d - 1] of contact vectors [m, d] (frame (t, n) or (t, n,
    s))."""
    return values[:, [0]] if values.shape[1] == 2 else values[:, [0, 2]]


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
    dim, dof = model.dim, model.dof
    count = problem.count
    take = np.flatnonzero(problem.active[:count]).astype(np.int64)
    free = np.flatnonzero(model.body_kind == BodyKind.FREE)
    body_column = np.full(model.body_count, -1, dtype=np.int64)
    body_column[free] = dof * np.arange(len(free))
    node_columns = dim * kind.blocks.n_nodes
    n = node_columns + dof * len(free)
    mass = np.divide(1.0, model.body_inv_mass[free], out=np.zeros((len(free), dof)),
                     where=model.body_inv_mass[free] > 0.0).ravel()
    a_matrix = sp.block_diag((_world_iteration_matrix(kind), sp.diags(mass)), format="csr")
    m = len(take)
    # per contact at most d rows on 3 nodes a side (3D) or on a rigid body's dof columns
    per = 2 * dim * max(3 * dim, dof)
    rows = np.empty(per * m, dtype=np.int64)
    cols = np.empty(per * m, dtype=np.int64)
    vals = np.empty(per * m)
    rhs = np.empty(dim * m)
    e = _rows(c.side_kind, c.side_node, c.side_weight, c.candidate, c.antagonist,
              problem.h_cand, problem.h_ant, problem.bias, v_free, kind.v_free, count, take,
              body_column, node_columns, rows, cols, vals, rhs)
    h = sp.csr_matrix((vals[:e], (rows[:e], cols[:e])), shape=(dim * m, n))
    mu = problem.friction[take]
    diagonal = problem.delassus[take][:, np.arange(dim), np.arange(dim)]
    # tolerance on U_n + b_n [m/s] of an open contact: round-off of the velocities
    slack = _SLACK * max(float(np.abs(rhs).max(initial=0.0)), 1e-300)
    # the status of the warm start's impulses (those of the last step, by contact): the
    # same joints open and slide from step to step, so that most steps need one solve
    warm = impulse[take]
    status = np.full(m, _STICK)
    status[warm[:, 1] <= 0.0] = _OPEN
    direction = _unit(_tangent(warm))
    edge = (warm[:, 1] > 0.0) & (_norm(_tangent(warm)) >= (1.0 - _EDGE) * mu * warm[:, 1])
    status[edge] = _SLIDE
    changing = m
    for _ in range(_PASSES):
        x, r = _solve_status(a_matrix, h, rhs, status, direction, mu, diagonal)
        u = (h @ x[:n] - rhs).reshape(m, dim)  # U + b of every contact in the solve [m/s]
        new = status.copy()
        new_direction = direction.copy()
        new[(status == _OPEN) & (u[:, 1] < -slack)] = _STICK
        closed = status != _OPEN
        new[closed & (r[:, 1] < 0.0)] = _OPEN
        r_t, u_t = _tangent(r), _tangent(u)
        outside = (new == _STICK) & (status == _STICK) & (_norm(r_t) > mu * r[:, 1])
        new[outside] = _SLIDE
        new_direction[outside] = _unit(r_t[outside])
        # a slip against its friction impulse: it sticks
        sliding = (new == _SLIDE) & (status == _SLIDE)
        new[sliding & ((u_t * r_t).sum(axis=1) > 0.0)] = _STICK
        # (3D) a slip that turned: its friction impulse turns with it
        turned = (new == _SLIDE) & (status == _SLIDE) & (_norm(u_t) > 0.0) & (
            _norm(direction + _unit(u_t)) > _TURN)
        new_direction[turned] = -_unit(u_t[turned])
        changing = int((new != status).sum())
        if changing == 0:
            break
        status, direction = new, new_direction
    if changing > _CHANGING * m:
        return False
    impulse[:count] = 0.0
    impulse[take] = r
    dv = x[:n]
    kind.v[:] = kind.v_free + dv[:node_columns].reshape(-1, dim)
    v[:] = v_free
    v[free] += dv[node_columns:].reshape(-1, dof)
    return True


def _norm(vectors: np.ndarray) -> np.ndarray:
    """|t| of tangent vectors [m, d - 1] (d = 2: |t_0|, exactly)."""
    return np.abs(vectors[:, 0]) if vectors.shape[1] == 1 else np.linalg.norm(vectors, axis=1)


def _unit(vectors: np.ndarray) -> np.ndarray:
    """t / |t| of tangent vectors [m, d - 1] (d = 2: the sign, +-1; 3D: 0 for t = 0)."""
    size = _norm(vectors)[:, None]
    return np.divide(vectors, size, out=np.zeros_like(vectors), where=size > 0.0)
