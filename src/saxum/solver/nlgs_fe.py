"""NLGS sweeps for models with deformable blocks (saxum.bodies.fe), 2D and 3D: the exchange
local-global iteration of saxum.solver.nlgs.nlgs_2d and nlgs_3d, each contact side read and
updated by its kind (design-deformable-and-joints.md section 3):

    rigid side:  U += H*_side v_body,              v_body += M^-1 H_side dR
    FE side:     U += +-F sum_p w_p v_p,          v_q += +-R sum_p w_p G[q, p] R^T F^T dR
                 (p the side's nodes, q all nodes of their block; + candidate, - antagonist)

G = M~^-1 in the block's frame (saxum.fe.FEBlocks.inv). The single-contact problem is the
rigid sweeps': in 2D saxum.solver.local2d's (its divisions once per contact and step), in 3D
saxum.solver.local3d's (Coulomb's cone). Models without deformable blocks never come here, so
their sweeps are nlgs_2d's and nlgs_3d's, bit for bit. The convergence criterion is theirs
with the nodes' lumped masses in the norm.
"""


import numba as nb
import numpy as np

from ..bodies.fe import side_push, side_velocity
from .local2d import factorize_contact_2d, solve_factored_contact_2d
from .local3d import open_or_stick_3d, solve_contact_3d
from .velocity_change import change_ratio, change_sums

__all__ = ["nlgs_fe"]


@nb.njit(cache=True)
def _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free, node_mass):
    """nlgs._relative_change over bodies and nodes together (node_mass [N, d] [kg]); then
    v_prev = v, node_prev = node_v."""
    num, den, size = change_sums(v, v_prev, v_free, mass, 0.0, 0.0, 0.0)
    num, den, size = change_sums(node_v, node_prev, node_free, node_mass, num, den, size)
    return change_ratio(num, den, size)


@nb.njit(inline="always")
def _local_solve(a, w, u, friction, factors, impulse, rr):
    """rr = contact a's impulse [N s] for the local velocity u [m/s] (the other impulses' and
    the shift b_n), W = w [1/kg]: 2D by the factors of local2d.factorize_contact_2d, 3D by
    local3d's open or stick cases, else its full solve from the current impulse."""
    if u.shape[0] == 2:
        rr[0], rr[1] = solve_factored_contact_2d(w[0, 0], w[0, 1], w[1, 1], factors[a, 0],
                                                 factors[a, 1], factors[a, 2], factors[a, 3],
                                                 factors[a, 4], u[0], u[1], friction[a])
        return
    case, rr[0], rr[1], rr[2] = open_or_stick_3d(
        w[0, 0], w[0, 1], w[0, 2], w[1, 0], w[1, 1], w[1, 2], w[2, 0], w[2, 1], w[2, 2],
        u[0], u[1], u[2], friction[a])
    if case < 0:  # a slide: the full solve, from the current impulse
        for r in range(3):
            rr[r] = impulse[a, r]
        solve_contact_3d(w, u, friction[a], rr)


@nb.njit(cache=True)
def nlgs_fe(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass, mass,
            v_free, v, v_prev, impulse, side_kind, side_node, side_weight, node_block,
            node_start, inv_start, inverse, rotation, node_mass, node_free, node_v, node_prev,
            tolerance, max_iterations, relaxation):
    """NLGS sweeps (module doc), d = delassus.shape[1] (2 or 3); returns (sweeps done, final
    error). Updates v, node_v and impulse in place; v_prev and node_prev are work memory."""
    d = delassus.shape[1]
    factors = np.empty((count if d == 2 else 0, 5))
    nactive = 0
    for a in range(count):
        if active[a]:
            nactive += 1
            if d == 2:
                f = factorize_contact_2d(delassus[a, 0, 0], delassus[a, 0, 1],
                                         delassus[a, 1, 1], friction[a])
                for i in range(5):
                    factors[a, i] = f[i]
    if nactive == 0:
        return 0, 0.0
    u = np.empty(d)
    rr = np.empty(d)
    dr = np.empty(d)
    f = np.empty(d)
    pl = np.empty(d)
    dv = np.empty(d)
    error = np.inf
    it = 0
    _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free, node_mass)
    while it < max_iterations:
        it += 1
        for k in range(count):
            a = count - 1 - k
            if not active[a]:
                continue
            w = delassus[a]
            u[:] = 0.0
            side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0],
                          cand[a], v, node_v, u)
            side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1],
                          ant[a], v, node_v, u)
            # U without contact a's own impulse, plus the shift b_n
            for r in range(d):
                s = 0.0
                for c in range(d):
                    s += w[r, c] * impulse[a, c]
                u[r] -= s
            u[1] += bias[a]
            _local_solve(a, w, u, friction, factors, impulse, rr)
            for r in range(d):
                if relaxation != 1.0:
                    rr[r] = relaxation * rr[r] + (1.0 - relaxation) * impulse[a, r]
                dr[r] = rr[r] - impulse[a, r]
            side_push(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1], ant[a], dr,
                      inv_mass, v, node_block, node_start, inv_start, inverse, rotation,
                      node_v, f, pl, dv)
            side_push(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0], cand[a],
                      dr, inv_mass, v, node_block, node_start, inv_start, inverse, rotation,
                      node_v, f, pl, dv)
            for r in range(d):
                impulse[a, r] = rr[r]
        error = _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free,
                                 node_mass)
        if error <= tolerance:
            break
    return it, error
