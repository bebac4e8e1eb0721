"""NLGS sweeps for models with deformable blocks (saxum.bodies.fe), 2D and 3D: the exchange
local-global iteration of saxum.solver.nlgs.nlgs_2d and nlgs_3d, each contact side read and
updated by its kind (design-deformable-and-joints.md section 3):

    rigid side:  U += H*_side v_body,              v_body += M^-1 H_side dR
    FE side:     U += +-F sum_p w_p v_p,          v_q += +-R sum_p w_p G[q, p] R^T F^T dR
                 (p the side's nodes, q all nodes of their block; + candidate, - antagonist)

G = M~^-1 in the block's frame (saxum.fe.FEBlocks.inv). nlgs_fe_3d reads and pushes the sides
with saxum.bodies.fe's kernels, written for any dimension, and solves the single contact by
saxum.solver.local3d (Coulomb's cone). nlgs_fe_2d is the same iteration written out on
scalars for 2 x 2 blocks with local2d's solve: the same maths, kept apart for speed, since
the generic side kernels (loops of runtime length d over small work arrays) made the 2D
sweeps 2x slower (17 against 7.5 to 9.3 CPU ms of sweeps per step on benchmarks/wall_fe.py
--courses 6 --bricks 4, measured in one run). Models without deformable blocks never come
here, so their sweeps are nlgs_2d's and nlgs_3d's, bit for bit. The convergence criterion is
theirs with the nodes' lumped masses in the norm. A contact of a joint law (law_map flag
!= 0, saxum.solver.laws_local) is solved by law_solve_2d / law_solve_3d on its W', in the
same sweep as the dry ones.
"""


import numba as nb
import numpy as np

from ..bodies.fe import side_push, side_velocity
from .laws_local import law_solve_2d, law_solve_3d
from .local2d import factorize_contact_2d, solve_factored_contact_2d
from .local3d import open_or_stick_3d, solve_contact_3d
from .velocity_change import change_ratio, change_sums

__all__ = ["nlgs_fe_2d", "nlgs_fe_3d"]


@nb.njit(cache=True)
def _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free, node_mass):
    """nlgs._relative_change over bodies and nodes together (node_mass [N, d] [kg]); then
    v_prev = v, node_prev = node_v."""
    num, den, size = change_sums(v, v_prev, v_free, mass, 0.0, 0.0, 0.0)
    num, den, size = change_sums(node_v, node_prev, node_free, node_mass, num, den, size)
    return change_ratio(num, den, size)


@nb.njit(cache=True)
def nlgs_fe_3d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass,
               mass, v_free, v, v_prev, impulse, side_kind, side_node, side_weight, node_block,
               node_start, inv_start, inverse, rotation, node_mass, node_free, node_v,
               node_prev, law_map, tolerance, max_iterations, relaxation):
    """NLGS sweeps (module doc) in 3D; returns (sweeps done, final error). Updates v, node_v
    and impulse in place; v_prev and node_prev are work memory; law_map [count, width] the
    joint laws' rows (all flags 0 without them)."""
    d = delassus.shape[1]
    nactive = 0
    for a in range(count):
        nactive += active[a]
    if nactive == 0:
        return 0, 0.0
    u = np.empty(d)
    rr = np.empty(d)
    dr = np.empty(d)
    f = np.empty(d)
    pl = np.empty(d)
    dv = np.empty(d)
    wp = np.empty((d, d))
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
            if law_map[a, 0] != 0.0:  # a joint: its W', from the current impulse
                for r in range(3):
                    rr[r] = impulse[a, r]
                law_solve_3d(law_map[a], u, bias[a], friction[a], wp, rr)
            else:
                case, rr[0], rr[1], rr[2] = open_or_stick_3d(
                    w[0, 0], w[0, 1], w[0, 2], w[1, 0], w[1, 1], w[1, 2], w[2, 0], w[2, 1],
                    w[2, 2], u[0], u[1], u[2], friction[a])
                if case < 0:  # a slide: the full solve, from the current impulse
                    for r in range(3):
                        rr[r] = impulse[a, r]
                    solve_contact_3d(w, u, friction[a], rr)
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


@nb.njit(inline="always")
def _push_node_2d(inverse, inv_start, node_start, block, p, c, s, fx, fy, v):
    """v_q += R G[q, p] R^T (fx, fy) for every node q of the block of node p: the change of
    the block's velocities from an impulse (fx, fy) [N s] on node p (global numbers)."""
    n0 = node_start[block]
    n2 = 2 * (node_start[block + 1] - n0)
    base = inv_start[block]
    lx = c * fx + s * fy
    ly = -s * fx + c * fy
    pl = p - n0
    for q in range(n2 // 2):
        r0 = base + 2 * q * n2 + 2 * pl
        r1 = r0 + n2
        gx = inverse[r0] * lx + inverse[r0 + 1] * ly
        gy = inverse[r1] * lx + inverse[r1 + 1] * ly
        v[n0 + q, 0] += c * gx - s * gy
        v[n0 + q, 1] += s * gx + c * gy


@nb.njit(inline="always")
def _side_velocity_2d(rows, a, kind, nodes, weights, body, v, node_v):
    """(U_t, U_n) [m/s] of one side of contact a: rows . v_body for a rigid side (kind 0), sum
    w_i rows . v_node_i for an FE side (rows [t; n] on the node, signed by side)."""
    u0 = 0.0
    u1 = 0.0
    if kind == 1:
        for i in range(nodes.shape[0]):
            w = weights[i]
            if w != 0.0:
                p = nodes[i]
                u0 += w * (rows[a, 0, 0] * node_v[p, 0] + rows[a, 0, 1] * node_v[p, 1])
                u1 += w * (rows[a, 1, 0] * node_v[p, 0] + rows[a, 1, 1] * node_v[p, 1])
    else:
        for d in range(v.shape[1]):
            u0 += rows[a, 0, d] * v[body, d]
            u1 += rows[a, 1, d] * v[body, d]
    return u0, u1


@nb.njit(inline="always")
def _side_push_2d(rows, a, kind, nodes, weights, body, dt, dn, inv_mass, v, node_block,
              node_start, inv_start, inverse, rotation, node_v):
    """v += M^-1 H_side (dt, dn) on one side: the body's diagonal M^-1 for a rigid side, R M~^-1
    R^T of the nodes' block for an FE side (each node w_i of the impulse)."""
    if kind == 1:
        fx = rows[a, 0, 0] * dt + rows[a, 1, 0] * dn
        fy = rows[a, 0, 1] * dt + rows[a, 1, 1] * dn
        for i in range(nodes.shape[0]):
            w = weights[i]
            if w != 0.0:
                p = nodes[i]
                f = node_block[p]
                _push_node_2d(inverse, inv_start, node_start, f, p, rotation[f, 0, 0],
                                  rotation[f, 1, 0], w * fx, w * fy, node_v)
    else:
        for d in range(v.shape[1]):
            v[body, d] += inv_mass[body, d] * (rows[a, 0, d] * dt + rows[a, 1, d] * dn)


@nb.njit(cache=True)
def nlgs_fe_2d(cand, ant, h_cand, h_ant, delassus, bias, friction, active, count, inv_mass,
               mass, v_free, v, v_prev, impulse, side_kind, side_node, side_weight, node_block,
               node_start,
               inv_start, inverse, rotation, node_mass, node_free, node_v, node_prev, law_map,
               tolerance, max_iterations, relaxation):
    """nlgs_fe's sweeps in 2D, written out on scalars (module doc); returns (sweeps done,
    final error). Updates v, node_v and impulse in place; v_prev and node_prev are work
    memory; law_map [count, width] the joint laws' rows (all flags 0 without them)."""
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
            uc0, uc1 = _side_velocity_2d(h_cand, a, side_kind[a, 0], side_node[a, 0],
                                     side_weight[a, 0], c, v, node_v)
            ua0, ua1 = _side_velocity_2d(h_ant, a, side_kind[a, 1], side_node[a, 1],
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
            _side_push_2d(h_ant, a, side_kind[a, 1], side_node[a, 1], side_weight[a, 1], b, dt,
                      dn, inv_mass, v, node_block, node_start, inv_start, inverse, rotation,
                      node_v)
            _side_push_2d(h_cand, a, side_kind[a, 0], side_node[a, 0], side_weight[a, 0], c, dt,
                      dn, inv_mass, v, node_block, node_start, inv_start, inverse, rotation,
                      node_v)
            impulse[a, 0] = rt
            impulse[a, 1] = rn
        error = _relative_change(v, v_prev, v_free, mass, node_v, node_prev, node_free,
                                 node_mass)
        if error <= tolerance:
            break
    return it, error
