"""NLGS sweeps for 2D models with deformable blocks (saxum.bodies.fe): the same exchange
local-global iteration as saxum.solver.nlgs.nlgs_2d, each contact side read and updated by
its kind (design-deformable-and-joints.md section 3):

    rigid side:  U += H*_side v_body,              v_body += M^-1 H_side dR
    FE side:     U += +-F sum_p w_p v_p,          v_q += +-R sum_p w_p G[q, p] R^T F^T dR
                 (p the side's nodes, q all nodes of their block; + candidate, - antagonist)

G = M~^-1 in the block's frame (saxum.fe.FEBlocks.inv). Models without deformable blocks never
come here, so their sweeps are nlgs_2d's, bit for bit. The convergence criterion is nlgs_2d's
with the nodes' lumped masses in the norm. A contact of a joint law (law_map flag != 0,
saxum.solver.laws_local) is solved by law_solve_2d on its W', in the same sweep as the dry
ones.
"""


import numba as nb
import numpy as np

from ..bodies.fe import side_push, side_velocity
from .laws_local import law_solve_2d
from .local2d import factorize_contact_2d, solve_factored_contact_2d
from .velocity_change import change_ratio, change_sums

__all__ = ["nlgs_fe_2d"]


@nb.njit(cache=True)
def _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free, node_mass):
    """nlgs._relative_change over bodies and nodes together (node_mass [N, 2] [kg]); then
    v_prev = v, node_prev = node_v."""
    num, den, size = change_sums(v, v_prev, v_free, mass, 0.0, 0.0, 0.0)
    num, den, size = change_sums(node_v, node_prev, node_free, node_mass, num, den, size)
    return change_ratio(num, den, size)


@nb.njit(cache=True)
def nlgs_fe_2d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass,
               mass, v_free, v, v_prev, impulse, side_kind, side_node, side_weight, node_block,
               node_start,
               inv_start, inverse, rotation, node_mass, node_free, node_v, node_prev, law_map,
               tolerance, max_iterations, relaxation):
    """NLGS sweeps (module doc); returns (sweeps done, final error). Updates v, node_v and
    impulse in place; v_prev and node_prev are work memory; law_map [count, width] the joint
    laws' rows (all flags 0 without them)."""
    factors = np.empty((count, 5))
    nactive = 0
    for a in range(count):
        if active[a]:
            nactive += 1
            m = law_map[a]
            if m[0] != 0.0:  # a joint: the factors of its W'
                f = factorize_contact_2d(m[1], m[2], m[4], friction[a])
            else:
                f = factorize_contact_2d(delassus[a, 0, 0], delassus[a, 0, 1],
                                         delassus[a, 1, 1], friction[a])
            for i in range(5):
                factors[a, i] = f[i]
    if nactive == 0:
        return 0, 0.0
    error = np.inf
    it = 0
    _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free, node_mass)
    while it < max_iterations:
        it += 1
        for k in range(count):
            a = count - 1 - k
            if not active[a]:
                continue
            c = cand[a]
            b = ant[a]
            uc0, uc1 = side_velocity(h_cand, a, side_kind[a, 0], side_node[a, 0],
                                     side_weight[a, 0], c, v, node_v)
            ua0, ua1 = side_velocity(h_ant, a, side_kind[a, 1], side_node[a, 1],
                                     side_weight[a, 1], b, v, node_v)
            u0 = uc0 + ua0
            u1 = uc1 + ua1
            wtt = delassus[a, 0, 0]
            wtn = delassus[a, 0, 1]
            wnn = delassus[a, 1, 1]
            rt0 = impulse[a, 0]
            rn0 = impulse[a, 1]
            ut = u0 - (wtt * rt0 + wtn * rn0)
            un = u1 + (bias[a] - (wtn * rt0 + wnn * rn0))
            if law_map[a, 0] != 0.0:
                rt, rn = law_solve_2d(law_map[a], ut, un, bias[a], factors[a, 0],
                                      factors[a, 1], factors[a, 2], factors[a, 3],
                                      factors[a, 4], friction[a])
            else:
                rt, rn = solve_factored_contact_2d(wtt, wtn, wnn, factors[a, 0], factors[a, 1],
                                                   factors[a, 2], factors[a, 3], factors[a, 4],
                                                   ut, un, friction[a])
            if relaxation != 1.0:
                rt = relaxation * rt + (1.0 - relaxation) * rt0
                rn = relaxation * rn + (1.0 - relaxation) * rn0
            dt = rt - rt0
            dn = rn - rn0
            side_push(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1], b, dt,
                      dn, inv_mass, v, node_block, node_start, inv_start, inverse, rotation,
                      node_v)
            side_push(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0], c, dt,
                      dn, inv_mass, v, node_block, node_start, inv_start, inverse, rotation,
                      node_v)
            impulse[a, 0] = rt
            impulse[a, 1] = rn
        error = _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free,
                                 node_mass)
        if error <= tolerance:
            break
    return it, error
