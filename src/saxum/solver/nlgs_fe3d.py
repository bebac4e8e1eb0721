"""NLGS sweeps for 3D models with deformable blocks (saxum.bodies.fe, .fe3d): saxum.solver.
nlgs_fe.nlgs_fe_2d's exchange local-global iteration with the 3D single-contact problem of
saxum.solver.local3d (Coulomb's cone, as nlgs_3d solves it), each contact side read and
updated by its kind:

    rigid side:  U += H*_side v_body,              v_body += M^-1 H_side dR
    FE side:     U += +-F sum_p w_p v_p,          v_q += +-R sum_p w_p G[q, p] R^T F^T dR

(p the side's nodes, q all nodes of their block; G = M~^-1 in the block's frame). Models
without deformable blocks never come here, so their sweeps are nlgs_3d's, bit for bit.
"""

import numba as nb
import numpy as np

from ..bodies.fe3d import side_push_nd, side_velocity_nd
from .local3d import open_or_stick_3d, solve_contact_3d
from .nlgs_fe import _relative_change

__all__ = ["nlgs_fe_3d"]


@nb.njit(cache=True)
def nlgs_fe_3d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass,
               mass, v_free, v, v_prev, impulse, side_kind, side_node, side_weight, node_block,
               node_start, inv_start, inverse, rotation, node_mass, node_free, node_v,
               node_prev, tolerance, max_iterations, relaxation):
    """NLGS sweeps (module doc), the arguments of nlgs_fe_2d; returns (sweeps done, final
    error). Updates v, node_v and impulse in place; v_prev and node_prev are work memory."""
    nactive = 0
    for a in range(count):
        nactive += active[a]
    if nactive == 0:
        return 0, 0.0
    u = np.empty(3)
    rr = np.empty(3)
    dr = np.empty(3)
    f = np.empty(3)
    pl = np.empty(3)
    dv = np.empty(3)
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
            side_velocity_nd(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0],
                             cand[a], v, node_v, u)
            side_velocity_nd(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1],
                             ant[a], v, node_v, u)
            # U without contact a's own impulse, plus the shift b_n
            for r in range(3):
                u[r] -= w[r, 0] * impulse[a, 0] + w[r, 1] * impulse[a, 1] + w[r, 2] * impulse[a, 2]
            u[1] += bias[a]
            case, rr[0], rr[1], rr[2] = open_or_stick_3d(
                w[0, 0], w[0, 1], w[0, 2], w[1, 0], w[1, 1], w[1, 2], w[2, 0], w[2, 1],
                w[2, 2], u[0], u[1], u[2], friction[a])
            if case < 0:  # a slide: the full solve, from the current impulse
                for r in range(3):
                    rr[r] = impulse[a, r]
                solve_contact_3d(w, u, friction[a], rr)
            for r in range(3):
                if relaxation != 1.0:
                    rr[r] = relaxation * rr[r] + (1.0 - relaxation) * impulse[a, r]
                dr[r] = rr[r] - impulse[a, r]
            side_push_nd(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1], ant[a],
                         dr, inv_mass, v, node_block, node_start, inv_start, inverse, rotation,
                         node_v, f, pl, dv)
            side_push_nd(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0],
                         cand[a], dr, inv_mass, v, node_block, node_start, inv_start, inverse,
                         rotation, node_v, f, pl, dv)
            for r in range(3):
                impulse[a, r] = rr[r]
        error = _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free,
                                 node_mass)
        if error <= tolerance:
            break
    return it, error
