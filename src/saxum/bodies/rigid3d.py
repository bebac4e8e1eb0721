"""Rigid bodies in space, compiled: the body kind (saxum.bodies) of 6-dof polyhedra, the 3D
counterpart of saxum.bodies.rigid2d.

q = (x, y, z, qw, qx, qy, qz): centre of mass [m] and unit quaternion of the body-to-world
rotation R; v = (v_G [m/s] in the world frame, omega [rad/s] in the body frame), the body frame
being the principal frame, so M = diag(m, m, m, J_1, J_2, J_3) is constant (NSCD.md).

Velocity of a material point M: v(M) = v_G + R (omega x R^T l), l = M - G in the world frame, so
a contact direction d gives the row of H* [d, R^T (l x d)] (d . (R (omega x R^T l)) =
omega . (R^T l x R^T d)).

Orientation. Over a step the body turns by the body-frame rotation vector
phi = h [(1 - theta) omega_i + theta omega_i+1], applied through the Cayley transform
    q+ = q (x) (1, phi / 2) / sqrt(1 + |phi|^2 / 4)
(the exponential map up to O(|phi|^3): rotation angle 2 atan(|phi| / 2) instead of |phi|;
F. Diele, L. Lopez, R. Peluso, "The Cayley transform in the numerical solution of unitary
differential systems", Adv. Comput. Math. 8, 1998), then renormalized. The Cayley form is the
one that makes the rotation consistent with the implicit midpoint rule on Euler's equations
(`gyroscopic_torques`): for a free body the pair conserves the kinetic energy and the angular
momentum vector in the world frame exactly (module doc of gyroscopic_torques).
"""

import math

import numba as nb
import numpy as np

from ..integrator import diagonal_free_velocity
from ..linalg3 import solve3

__all__ = [
    "angular_velocity_to_body",
    "contact_jacobians",
    "driven_velocity",
    "free_velocity",
    "gyroscopic_torques",
    "kinetic_energy",
    "predict_positions",
    "update_positions",
    "world_geometry",
    "world_geometry_range",
]

_NEWTON = 30  # cap of the midpoint solve per body (converges in 2-4 steps for h |omega| << 1)


@nb.njit(inline="always")
def _rotation(q, b):
    """Rows of the rotation matrix R (body to world) of body b's unit quaternion."""
    w = q[b, 3]
    x = q[b, 4]
    y = q[b, 5]
    z = q[b, 6]
    return (1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y),
            2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x),
            2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y))


@nb.njit(inline="always")
def _rotate(r, lx, ly, lz):
    return (r[0] * lx + r[1] * ly + r[2] * lz, r[3] * lx + r[4] * ly + r[5] * lz,
            r[6] * lx + r[7] * ly + r[8] * lz)


@nb.njit(cache=True)
def world_geometry(q, vertex_start, vertex_local, face_start, normal_local, wv, wn):
    """wv[k] = x_b + R_b vertex_local[k] [m] for every vertex k of every body b, and
    wn[f] = R_b normal_local[f] for its faces (the rotation computed once per body)."""
    world_geometry_range(0, q.shape[0], q, vertex_start, vertex_local, face_start,
                         normal_local, wv, wn)


@nb.njit(inline="always")
def world_geometry_range(lo, hi, q, vertex_start, vertex_local, face_start, normal_local, wv,
                         wn):
    """world_geometry of the bodies lo .. hi - 1 (a parallel region calls it on blocks)."""
    for b in range(lo, hi):
        r = _rotation(q, b)
        for k in range(vertex_start[b], vertex_start[b + 1]):
            x, y, z = _rotate(r, vertex_local[k, 0], vertex_local[k, 1], vertex_local[k, 2])
            wv[k, 0] = q[b, 0] + x
            wv[k, 1] = q[b, 1] + y
            wv[k, 2] = q[b, 2] + z
        for f in range(face_start[b], face_start[b + 1]):
            wn[f, 0], wn[f, 1], wn[f, 2] = _rotate(r, normal_local[f, 0], normal_local[f, 1],
                                                   normal_local[f, 2])


@nb.njit(inline="always")
def _turn(out, b, q, px, py, pz):
    """out[b, 3:7] = q[b, 3:7] (x) cay(phi), renormalized; phi: body-frame rotation vector."""
    s = 1.0 / math.sqrt(1.0 + 0.25 * (px * px + py * py + pz * pz))
    dw = s
    dx = 0.5 * s * px
    dy = 0.5 * s * py
    dz = 0.5 * s * pz
    w = q[b, 3]
    x = q[b, 4]
    y = q[b, 5]
    z = q[b, 6]
    nw = w * dw - x * dx - y * dy - z * dz
    nx = w * dx + x * dw + y * dz - z * dy
    ny = w * dy - x * dz + y * dw + z * dx
    nz = w * dz + x * dy - y * dx + z * dw
    norm = 1.0 / math.sqrt(nw * nw + nx * nx + ny * ny + nz * nz)
    out[b, 3] = nw * norm
    out[b, 4] = nx * norm
    out[b, 5] = ny * norm
    out[b, 6] = nz * norm


@nb.njit(cache=True)
def predict_positions(q, v, step, out):
    """Predicted configuration for detection: x + step v_G, orientation turned by step omega,
    step = (1 - theta) h [s]."""
    for b in range(q.shape[0]):
        for d in range(3):
            out[b, d] = q[b, d] + step * v[b, d]
        _turn(out, b, q, step * v[b, 3], step * v[b, 4], step * v[b, 5])


@nb.njit(cache=True)
def update_positions(q, v_begin, v_end, h, theta):
    """Moreau-Jean position update: x += h [(1 - theta) v_begin + theta v_end], orientation
    turned by phi = h [(1 - theta) omega_begin + theta omega_end] (module doc)."""
    a = h * (1.0 - theta)
    c = h * theta
    for b in range(q.shape[0]):
        for d in range(3):
            q[b, d] += a * v_begin[b, d] + c * v_end[b, d]
        _turn(q, b, q, a * v_begin[b, 3] + c * v_end[b, 3], a * v_begin[b, 4] + c * v_end[b, 4],
              a * v_begin[b, 5] + c * v_end[b, 5])


@nb.njit(cache=True)
def kinetic_energy(v, mass, inertia, inv_mass):
    """1/2 sum (m |v_G|^2 + J_1 w_1^2 + J_2 w_2^2 + J_3 w_3^2) over free bodies [J]."""
    e = 0.0
    for b in range(v.shape[0]):
        if inv_mass[b, 0] > 0.0:
            e += (mass[b] * (v[b, 0] ** 2 + v[b, 1] ** 2 + v[b, 2] ** 2)
                  + inertia[b, 0] * v[b, 3] ** 2 + inertia[b, 1] * v[b, 4] ** 2
                  + inertia[b, 2] * v[b, 5] ** 2)
    return 0.5 * e


@nb.njit(cache=True)
def gyroscopic_torques(q, v, inertia, inv_mass, h, force):
    """Turn the applied moments force[:, 3:6] [N m] from the world frame into the body frame
    and add the gyroscopic moment -omega_m x (J omega_m) of Euler's equations, for free bodies.

    omega_m = (omega_i + omega_free) / 2 is the midpoint of the step's free rotation, which
    solves the implicit midpoint rule  J (omega_free - omega_i) = h (M - omega_m x J omega_m)
    (Newton's method per body, 3 x 3). It conserves J omega . omega and |J omega| (quadratic
    invariants) exactly, and with the Cayley update of the orientation (module doc) the world
    angular momentum R J omega as well: J omega_free = cay(-h omega_m / 2 ^) J omega_i.
    Within a step with contacts the moment is kept as computed here (explicit in the impulses,
    as NSCD.md has the gyroscopic term)."""
    for b in range(q.shape[0]):
        if inv_mass[b, 3] == 0.0:
            continue
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = _rotation(q, b)
        mx = force[b, 3]
        my = force[b, 4]
        mz = force[b, 5]
        m0 = r00 * mx + r10 * my + r20 * mz
        m1 = r01 * mx + r11 * my + r21 * mz
        m2 = r02 * mx + r12 * my + r22 * mz
        j0 = inertia[b, 0]
        j1 = inertia[b, 1]
        j2 = inertia[b, 2]
        w0 = v[b, 3]
        w1 = v[b, 4]
        w2 = v[b, 5]
        x0 = w0 + h * m0 / j0
        x1 = w1 + h * m1 / j1
        x2 = w2 + h * m2 / j2
        scale = j0 * abs(w0) + j1 * abs(w1) + j2 * abs(w2) + h * (abs(m0) + abs(m1) + abs(m2))
        g0 = g1 = g2 = 0.0
        for _ in range(_NEWTON):
            a0 = 0.5 * (w0 + x0)
            a1 = 0.5 * (w1 + x1)
            a2 = 0.5 * (w2 + x2)
            l0 = j0 * a0
            l1 = j1 * a1
            l2 = j2 * a2
            g0 = -(a1 * l2 - a2 * l1)
            g1 = -(a2 * l0 - a0 * l2)
            g2 = -(a0 * l1 - a1 * l0)
            f0 = j0 * (x0 - w0) - h * (m0 + g0)
            f1 = j1 * (x1 - w1) - h * (m1 + g1)
            f2 = j2 * (x2 - w2) - h * (m2 + g2)
            if abs(f0) + abs(f1) + abs(f2) <= 1e-15 * scale:
                break
            # J_F = diag(J) + h/2 (skew(a) diag(J) - skew(J a))
            k = 0.5 * h
            s0, s1, s2 = solve3(j0, k * (-a2 * j1 + l2), k * (a1 * j2 - l1),
                                k * (a2 * j0 - l2), j1, k * (-a0 * j2 + l0),
                                k * (-a1 * j0 + l1), k * (a0 * j1 - l0), j2, f0, f1, f2)
            x0 -= s0
            x1 -= s1
            x2 -= s2
        force[b, 3] = m0 + g0
        force[b, 4] = m1 + g1
        force[b, 5] = m2 + g2


def free_velocity(q: np.ndarray, v: np.ndarray, inertia: np.ndarray, inv_mass: np.ndarray,
                  force: np.ndarray, h: float, out: np.ndarray) -> None:
    """out = v + h M^-1 force [m/s, rad/s], M diagonal in the principal frame; force [N, N m]
    theta-weighted, moments in the world frame: turned into the body frame with the
    gyroscopic moment added first (gyroscopic_torques, which overwrites force[:, 3:6])."""
    gyroscopic_torques(q, v, inertia, inv_mass, h, force)
    diagonal_free_velocity(v, inv_mass, force, h, out)


def driven_velocity(q: np.ndarray, bodies: np.ndarray, v: np.ndarray) -> None:
    """Imposed angular velocities of the listed bodies from the world into the body frame."""
    angular_velocity_to_body(q, bodies, v)


@nb.njit(cache=True)
def angular_velocity_to_body(q, bodies, v):
    """v[b, 3:6] <- R_b^T v[b, 3:6] for the listed bodies (imposed world-frame angular
    velocities of driven bodies into the body frame)."""
    for b in bodies:
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = _rotation(q, b)
        wx = v[b, 3]
        wy = v[b, 4]
        wz = v[b, 5]
        v[b, 3] = r00 * wx + r10 * wy + r20 * wz
        v[b, 4] = r01 * wx + r11 * wy + r21 * wz
        v[b, 5] = r02 * wx + r12 * wy + r22 * wz


@nb.njit(cache=True)
def contact_jacobians(q, candidate, antagonist, point, frame, gap, count, h_cand, h_ant):
    """Rows of H* for each contact: U = h_cand[a] v_cand + h_ant[a] v_ant, U = (U_t, U_n, U_s).

    The candidate's material point is `point`; the antagonist's is its projection
    point - gap n on the antagonist's face.
    """
    for a in range(count):
        c = candidate[a]
        b = antagonist[a]
        c00, c01, c02, c10, c11, c12, c20, c21, c22 = _rotation(q, c)
        b00, b01, b02, b10, b11, b12, b20, b21, b22 = _rotation(q, b)
        g = gap[a]
        lcx = point[a, 0] - q[c, 0]
        lcy = point[a, 1] - q[c, 1]
        lcz = point[a, 2] - q[c, 2]
        lax = point[a, 0] - g * frame[a, 1, 0] - q[b, 0]
        lay = point[a, 1] - g * frame[a, 1, 1] - q[b, 1]
        laz = point[a, 2] - g * frame[a, 1, 2] - q[b, 2]
        for r in range(3):
            dx = frame[a, r, 0]
            dy = frame[a, r, 1]
            dz = frame[a, r, 2]
            h_cand[a, r, 0] = dx
            h_cand[a, r, 1] = dy
            h_cand[a, r, 2] = dz
            h_ant[a, r, 0] = -dx
            h_ant[a, r, 1] = -dy
            h_ant[a, r, 2] = -dz
            # l x d in the world frame, then R^T
            ex = lcy * dz - lcz * dy
            ey = lcz * dx - lcx * dz
            ez = lcx * dy - lcy * dx
            h_cand[a, r, 3] = c00 * ex + c10 * ey + c20 * ez
            h_cand[a, r, 4] = c01 * ex + c11 * ey + c21 * ez
            h_cand[a, r, 5] = c02 * ex + c12 * ey + c22 * ez
            ex = lay * dz - laz * dy
            ey = laz * dx - lax * dz
            ez = lax * dy - lay * dx
            h_ant[a, r, 3] = -(b00 * ex + b10 * ey + b20 * ez)
            h_ant[a, r, 4] = -(b01 * ex + b11 * ey + b21 * ez)
            h_ant[a, r, 5] = -(b02 * ex + b12 * ey + b22 * ez)

