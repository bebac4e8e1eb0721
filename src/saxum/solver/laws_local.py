"""The joint laws (saxum.laws: ELASTIC, VISCOUS_COULOMB, COHESIVE) as modified local problems.

NLGS solves, per contact alpha, U = W R + q with Signorini-Coulomb on (U_n + b_n, R). A joint
law changes that problem, per contact and step, into the same one on other data, so the same
NLGS (saxum.solver.nlgs) solves all laws (design doc, sec. 5). With theta-weighted stresses,
x_theta = (1 - theta) x_i + theta x_i+1 over the step [t_i, t_i+1] (the trapezoid for
theta = 1/2, which keeps a spring's energy), g the gap on the predicted configuration,
U^b the local velocity at t_i and U the one at t_i+1 [m/s], A the contact's area:

- compliance (ELASTIC): R_n = h A max(0, -(k_n g_theta + c_n U_n,theta)) with
  g_theta = g - (1 - theta)^2 h U^b_n + theta^2 h U_n, which is
      R_n >= 0,  U_n + b_n + C_n R_n >= 0,  complementary,
      C_n = 1 / (h A K),  K = theta (theta h k_n + c_n),
      b_n = (k_n (g - (1 - theta)^2 h U^b_n) + c_n (1 - theta) U^b_n) / K,
  and the tangential spring s_theta = s + theta (1 - theta) h U^b_t + theta^2 h U_t in series
  with Coulomb's slider: C_t = 1 / (theta^2 h^2 A k_t), b_t = (s + theta (1 - theta) h U^b_t)
  / (theta^2 h). So W' = W + diag(C) and the shift (b_t, b_n) [V. Acary & B. Brogliato,
  Numerical Methods for Nonsmooth Dynamical Systems, Springer 2008, sec. 7].
- parallel part (VISCOUS_COULOMB, COHESIVE): R = R_d + R_l, R_l = -D U - e with D diagonal,
  R_d Signorini-Coulomb on U. Eliminating U = W R + q:
      U = W' R_d + q',  W' = (I + W D)^-1 W,  q' = (I + W D)^-1 (q - W e),
  then R = R_d - D U - e. Viscous: D_t = h A eta, R_d the gap law's (its b_n).
- COHESIVE (a bonded joint; beta = 1 - d): the normal stress is k_n (-g_theta) in compression
  and -beta k_n g_theta in tension (saxum.laws), a kink at g_theta = 0 solved as two
  branches. Compression: R_d is the compliant contact, ELASTIC's with c_n = 0 (C_n added to
  W'_nn, b_n = g_0 / (theta^2 h), g_0 = g - (1 - theta)^2 h U^b_n), with Coulomb friction,
  in parallel with the bond's shear spring D_t = beta theta^2 h^2 A k_t,
  e_t = beta h A k_t (s + theta (1 - theta) h U^b_t). If its solution has R_d,n > 0 the
  joint is closed and that is the solution; else (open) the tension branch: the bond alone,
  R = -(I + D W)^-1 (D q + e) with D_n = beta theta^2 h^2 A k_n, e_n = beta h A k_n g_0,
  linear in the kernel's u: R = T u + r. Since the law is monotone, an open compression
  branch (g_theta >= 0 with no normal force) stays open when the bond pulls (g_theta shrinks
  by a positive factor and does not change sign). A fully damaged bonded joint has only the
  compression branch (an ELASTIC contact with k_t = 0); a contact that was never bonded is
  the gap law's (flag 0), and only those are projected (saxum.solver.projection).
  With a compression cap (saxum.laws), the law is written on g + w (w the joint's plastic
  closure, Contacts.crush), and the compression branch bounds the normal impulse,
  R_d,n <= R_c = sqrt((h A sigma_c(w))^2 - C_ss R_t^2) (w from the start of the step, R_t
  the tangential impulse of the warm start, 0 if C_ss R_t^2 passes the first term: the
  ellipse of saxum.laws with the shear of the step before): where the dry solve gives
  more, R_d,n = R_c and R_d,t is the friction problem under that fixed normal impulse (2D:
  sticking, R_t = -(u'_t + W'_tn R_c) / W'_tt, clipped to mu R_c; 3D: the sticking impulse
  of the 2 x 2 tangential block, scaled down onto the disc mu R_c when outside it, exact
  when that block is isotropic).

`law_terms` writes per contact one row of `law_map` (flag 0: a dry law, nothing to do; 2: a
bonded COHESIVE joint with a tension branch; 1: the others):
[flag, W' (dim x dim), P = (I + W D)^-1 (dim x dim), shift s'' (dim), D (dim), e (dim),
T (dim x dim), r (dim), R_c (inf without a cap)];
the sweep kernels visit the flagged rows after the dry ones and call `law_solve_2d` /
`law_solve_3d`: u' = P u + s'' (u the kernel's local velocity with b_n added, so
s'' = -P W e + b - P b), the dry solve on W', then R = R_d - D U - e with
U = W' R_d + u' - b (flag 2 and R_d,n = 0: R = T u + r instead). For compliance, P = I,
D = e = 0.
`update_joints` advances the state after the solve (slip, history, damage, crush:
saxum.laws).
"""

import math

import numba as nb
import numpy as np

from ..laws import LawKind, Parameter
from .local2d import solve_factored_contact_2d
from .local3d import solve_contact_3d

__all__ = ["cap_stress", "law_map_width", "law_solve_2d", "law_solve_3d", "law_terms",
           "local_velocities", "update_joints"]

_ELASTIC = int(LawKind.ELASTIC)
_VISCOUS = int(LawKind.VISCOUS_COULOMB)
_COHESIVE = int(LawKind.COHESIVE)
_K_N, _K_T, _C_N, _ETA = (int(Parameter.K_N), int(Parameter.K_T), int(Parameter.C_N),
                          int(Parameter.ETA))
_F_T, _COH, _G_I, _G_II = (int(Parameter.F_T), int(Parameter.COHESION), int(Parameter.G_I),
                           int(Parameter.G_II))
_F_C, _G_FC, _C_SS = int(Parameter.F_C), int(Parameter.G_FC), int(Parameter.C_SS)


def law_map_width(dim: int) -> int:
    """Columns of a law_map row: flag, W', P, s'', D, e, T, r, R_c."""
    return 2 + 3 * dim * dim + 4 * dim


@nb.njit(inline="always")
def _local(h_cand, h_ant, a, r, c, b, v):
    u = 0.0
    for k in range(v.shape[1]):
        u += h_cand[a, r, k] * v[c, k] + h_ant[a, r, k] * v[b, k]
    return u


@nb.njit(cache=True)
def local_velocities(cand, ant, h_cand, h_ant, count, v, out):
    """out[a] = U = H*_cand v_cand + H*_ant v_ant [m/s] of the contacts of rigid bodies, in
    their frames (t, n[, s]); a model with deformable blocks has its own
    (saxum.bodies.fe.FEKind.local_velocities)."""
    for a in range(count):
        for r in range(out.shape[1]):
            out[a, r] = _local(h_cand, h_ant, a, r, cand[a], ant[a], v)


@nb.njit(cache=True)
def law_terms(law, gap, area, slip, damage, history, crush, impulse, count, u_begin, law_kind,
              law_parameter, h, theta, delassus, bias, law_map):
    """Fill law_map (module doc) for the contacts of joint laws, and b_n of ELASTIC ones and
    bonded COHESIVE ones (damage < 1, or history > 0: bonded once) in bias [m/s]; other rows
    get flag 0. u_begin [m/s]: the contacts' local velocities U^b at the start of the step
    (local_velocities); delassus [1/kg] is W, left as it is."""
    dim = delassus.shape[1]
    o_w, o_p = 1, 1 + dim * dim
    o_s, o_d, o_e = 1 + 2 * dim * dim, 1 + 2 * dim * dim + dim, 1 + 2 * dim * dim + 2 * dim
    o_x, o_r = 1 + 2 * dim * dim + 3 * dim, 1 + 3 * dim * dim + 3 * dim
    o_c = 1 + 3 * dim * dim + 4 * dim
    dd = np.empty(dim)
    ee = np.empty(dim)
    bb = np.empty(dim)
    m = np.empty((dim, dim))
    for a in range(count):
        row = law_map[a]
        row[0] = 0.0
        kind = law_kind[law[a]]
        area_a = area[a]
        if kind < _ELASTIC or area_a <= 0.0:  # dry, or no area: Signorini-Coulomb
            continue
        p = law_parameter[law[a]]
        beta = 1.0 - damage[a]
        if kind == _COHESIVE and beta <= 0.0 and history[a] <= 0.0:
            continue  # never bonded (saxum.contacts): a gap-law Coulomb contact
        ub = u_begin[a]
        row[0] = 2.0 if kind == _COHESIVE and beta > 0.0 else 1.0
        row[o_c] = np.inf
        for r in range(dim * dim):
            row[o_p + r] = 0.0
        for r in range(dim):
            row[o_p + r * dim + r] = 1.0
            row[o_s + r] = 0.0
            row[o_d + r] = 0.0
            row[o_e + r] = 0.0
            for s in range(dim):
                row[o_w + r * dim + s] = delassus[a, r, s]
        if kind == _ELASTIC:
            kn, kt, cn = p[_K_N], p[_K_T], p[_C_N]
            stiff = theta * (theta * h * kn + cn)
            row[o_w + dim + 1] += 1.0 / (h * area_a * stiff)
            bias[a] = (kn * (gap[a] - (1.0 - theta) ** 2 * h * ub[1])
                       + cn * (1.0 - theta) * ub[1]) / stiff
            if kt > 0.0:
                for j in range(dim - 1):
                    r = 0 if j == 0 else 2
                    row[o_w + r * dim + r] += 1.0 / (theta * theta * h * h * area_a * kt)
                    row[o_s + r] = (slip[a, j] + theta * (1.0 - theta) * h * ub[r]) / (
                        theta * theta * h)
            continue
        for r in range(dim):
            dd[r] = 0.0
            ee[r] = 0.0
            bb[r] = 0.0
        if kind == _VISCOUS:
            bb[1] = bias[a]
            for r in range(0, dim, 2):
                dd[r] = h * area_a * p[_ETA]
            _parallel(delassus[a], dd, ee, bb, m, row, o_w, o_p, o_s, o_d, o_e)
            continue
        # COHESIVE's compression branch: the contact part is compliant, k_n (ELASTIC's with
        # c_n = 0), in parallel with the bond's shear spring; the law on the elastic part of
        # the closure, the plastic one crush[a] taken off, and the cap's impulse
        g0 = gap[a] + crush[a] - (1.0 - theta) ** 2 * h * ub[1]
        if p[_F_C] > 0.0:
            # the cap's ellipse sigma^2 + C_ss tau^2 <= sigma_c^2 with tau the shear stress of
            # the warm start (the step before's): explicit, as the damage is
            rt2 = 0.0
            for r in range(0, dim, 2):
                rt2 += impulse[a, r] * impulse[a, r]
            sc = cap_stress(p, crush[a])
            row[o_c] = math.sqrt(max(0.0, (h * area_a * sc) ** 2 - p[_C_SS] * rt2))
        bb[1] = bias[a] = g0 / (theta * theta * h)
        scale = beta * h * area_a
        for j in range(dim - 1):
            r = 0 if j == 0 else 2
            dd[r] = scale * theta * theta * h * p[_K_T]
            ee[r] = scale * p[_K_T] * (slip[a, j] + theta * (1.0 - theta) * h * ub[r])
        _parallel(delassus[a], dd, ee, bb, m, row, o_w, o_p, o_s, o_d, o_e)
        row[o_w + dim + 1] += 1.0 / (theta * theta * h * h * area_a * p[_K_N])
        if beta <= 0.0:
            continue
        # tension branch: the bond alone, R = -(I + D W)^-1 (D q + e) with q = u - b
        dd[1] = scale * theta * theta * h * p[_K_N]
        ee[1] = scale * p[_K_N] * g0
        for r in range(dim):
            for s in range(dim):
                m[r, s] = (1.0 if r == s else 0.0) + dd[r] * delassus[a, r, s]
        mi = np.linalg.inv(m)
        for r in range(dim):
            lin = 0.0
            for s in range(dim):
                row[o_x + r * dim + s] = -mi[r, s] * dd[s]
                lin += mi[r, s] * (dd[s] * bb[s] - ee[s])
            row[o_r + r] = lin


@nb.njit(inline="always")
def _parallel(w, dd, ee, bb, m, row, o_w, o_p, o_s, o_d, o_e):
    """law_map's W', P, s'', D, e of a parallel part D, e and shift bb (module doc)."""
    dim = w.shape[0]
    for r in range(dim):
        for s in range(dim):
            m[r, s] = (1.0 if r == s else 0.0) + w[r, s] * dd[s]
    pm = np.linalg.inv(m)
    wp = pm @ w
    we = w @ ee
    for r in range(dim):
        row[o_d + r] = dd[r]
        row[o_e + r] = ee[r]
        shift = bb[r]
        for s in range(dim):
            row[o_p + r * dim + s] = pm[r, s]
            # W' is symmetric, (W^-1 + D)^-1: keep it so against round-off
            row[o_w + r * dim + s] = 0.5 * (wp[r, s] + wp[s, r])
            shift -= pm[r, s] * (we[s] + bb[s])
        row[o_s + r] = shift


@nb.njit(inline="always")
def law_solve_2d(m, ut, un, bn, inv_nn, inv_tn, inv_tt, slide_plus, slide_minus, mu):
    """Total impulse (R_t, R_n) [N s] of a contact with a joint law in 2D: law_map row m, the
    kernel's local velocity (u_t, u_n + b_n) [m/s], b_n, and the factors of W'
    (saxum.solver.local2d.factorize_contact_2d)."""
    qt = m[5] * ut + m[6] * un + m[9]
    qn = m[7] * ut + m[8] * un + m[10]
    rdt, rdn = solve_factored_contact_2d(m[1], m[2], m[4], inv_nn, inv_tn, inv_tt, slide_plus,
                                         slide_minus, qt, qn, mu)
    if m[0] > 1.5 and rdn <= 0.0:  # an open bonded joint: the tension branch
        return m[15] * ut + m[16] * un + m[19], m[17] * ut + m[18] * un + m[20]
    if rdn > m[21]:  # crushing: the normal impulse at the cap, friction under it
        rdn = m[21]
        limit = mu * rdn
        rdt = min(max(-(qt + m[2] * rdn) / m[1], -limit), limit)
    vt = m[1] * rdt + m[2] * rdn + qt
    vn = m[3] * rdt + m[4] * rdn + qn - bn
    return rdt - m[11] * vt - m[13], rdn - m[12] * vn - m[14]


@nb.njit(inline="always")
def law_solve_3d(m, u, bn, mu, wp, rr):
    """law_solve_2d in 3D: u [m/s] (t, n + b_n, s) in, rr [N s] the impulse (in: the dry
    part's starting guess; out: the total); wp: 3 x 3 work memory for W'."""
    u0, u1, u2 = u[0], u[1], u[2]
    u[0] = m[10] * u0 + m[11] * u1 + m[12] * u2 + m[19]
    u[1] = m[13] * u0 + m[14] * u1 + m[15] * u2 + m[20]
    u[2] = m[16] * u0 + m[17] * u1 + m[18] * u2 + m[21]
    for r in range(3):
        for s in range(3):
            wp[r, s] = m[1 + 3 * r + s]
    solve_contact_3d(wp, u, mu, rr)
    if m[0] > 1.5 and rr[1] <= 0.0:  # an open bonded joint: the tension branch
        for r in range(3):
            rr[r] = m[28 + 3 * r] * u0 + m[29 + 3 * r] * u1 + m[30 + 3 * r] * u2 + m[37 + r]
        return
    if rr[1] > m[40]:  # crushing: the normal impulse at the cap, friction under it
        rn = m[40]
        bt, bs = -(u[0] + wp[0, 1] * rn), -(u[2] + wp[2, 1] * rn)
        det = wp[0, 0] * wp[2, 2] - wp[0, 2] * wp[2, 0]
        rt, rs = (wp[2, 2] * bt - wp[0, 2] * bs) / det, (wp[0, 0] * bs - wp[2, 0] * bt) / det
        norm = math.sqrt(rt * rt + rs * rs)
        scale = mu * rn / norm if norm > mu * rn else 1.0
        rr[0], rr[1], rr[2] = scale * rt, rn, scale * rs
    for r in range(3):
        vel = u[r] - (bn if r == 1 else 0.0)
        for s in range(3):
            vel += wp[r, s] * rr[s]
        u[r] = vel
    for r in range(3):
        rr[r] = rr[r] - m[22 + r] * u[r] - m[25 + r]


@nb.njit(cache=True)
def update_joints(law, gap, area, impulse, active, slip, damage, history, crush, count, u_begin,
                  u, law_kind, law_friction, law_parameter, h, theta, law_map):
    """After the solve, from the contacts' local velocities at the start and the end of the
    step, u_begin and u [m/s] (local_velocities): ELASTIC slip s [m]
    (the spring's elongation: the jump while sticking, the slider's limit while sliding, 0
    when the contact is open); COHESIVE slip (the jump since bonding), history kappa, damage
    d and, with a cap, the plastic closure w [m] (saxum.laws; they never decrease): w grows
    by what the elastic closure at theta, -(g_theta + w), passes R_c / (h A k_n), R_c the
    step's cap (law_map's last column): the closure the capped impulse did not take up
    elastically. Returns how many COHESIVE points became fully
    damaged (d reached 1: bonds lost) and how many are partly damaged (0 < d < 1) after it."""
    dim = u.shape[1]
    lost = 0
    damaged = 0
    for a in range(count):
        kind = law_kind[law[a]]
        if kind != _ELASTIC and kind != _COHESIVE:
            continue
        p = law_parameter[law[a]]
        area_a = area[a]
        if kind == _ELASTIC:
            rn = impulse[a, 1]
            if area_a <= 0.0 or p[_K_T] == 0.0 or not active[a] or rn <= 0.0:
                for j in range(dim - 1):
                    slip[a, j] = 0.0
                continue
            rt2 = 0.0
            for r in range(0, dim, 2):
                rt2 += impulse[a, r] * impulse[a, r]
            sticks = math.sqrt(rt2) < law_friction[law[a]] * rn * (1.0 - 1e-9)
            for j in range(dim - 1):
                r = 0 if j == 0 else 2
                if sticks:
                    slip[a, j] += h * ((1.0 - theta) * u_begin[a, r] + theta * u[a, r])
                else:
                    slip[a, j] = -impulse[a, r] / (h * area_a * p[_K_T])
            continue
        if area_a <= 0.0 or (damage[a] >= 1.0 and history[a] <= 0.0):
            continue  # never bonded: a gap-law contact (law_terms)
        g_el = gap[a] + crush[a] + h * (theta * theta * u[a, 1]
                                        - (1.0 - theta) ** 2 * u_begin[a, 1])
        opening = max(gap[a] + crush[a] + theta * h * u[a, 1], 0.0)
        if p[_F_C] > 0.0:
            cap = law_map[a, law_map.shape[1] - 1] / (h * area_a)  # the step's, law_terms
            crush[a] += max(0.0, -g_el - cap / p[_K_N])
        if damage[a] >= 1.0:
            continue
        s2 = 0.0
        for j in range(dim - 1):
            r = 0 if j == 0 else 2
            slip[a, j] += h * ((1.0 - theta) * u_begin[a, r] + theta * u[a, r])
            s2 += slip[a, j] * slip[a, j]
        _damage(p, opening, math.sqrt(s2), damage, history, a)
        if damage[a] >= 1.0:
            lost += 1
        elif damage[a] > 0.0:
            damaged += 1
    return lost, damaged


@nb.njit(inline="always")
def cap_stress(p, w):
    """The cap's compressive strength sigma_c(w) = f_c exp(-f_c w / G_fc) [Pa] at plastic
    closure w [m] (saxum.laws), p a row of Model.law_parameter."""
    return p[_F_C] * math.exp(-p[_F_C] * w / p[_G_FC])


@nb.njit(inline="always")
def _damage(p, opening, jump, damage, history, a):
    """Camanho-Davila's bilinear mixed-mode damage (saxum.laws) from the opening <g>+ [m]
    and the tangential jump |s| [m]."""
    xn = opening * p[_K_N] / p[_F_T]
    xt = jump * p[_K_T] / p[_COH]
    lam = math.sqrt(xn * xn + xt * xt)
    kappa = max(history[a], lam)
    history[a] = kappa
    if kappa <= 1.0:
        return
    lam_i = 2.0 * p[_G_I] * p[_K_N] / (p[_F_T] * p[_F_T])
    lam_ii = 2.0 * p[_G_II] * p[_K_T] / (p[_COH] * p[_COH])
    cos2 = xn * xn / (lam * lam) if lam > 0.0 else 1.0
    lam_f = 1.0 / (cos2 / lam_i + (1.0 - cos2) / lam_ii)
    d = 1.0 if kappa >= lam_f else lam_f * (kappa - 1.0) / (kappa * (lam_f - 1.0))
    if d > damage[a]:
        damage[a] = min(d, 1.0)
