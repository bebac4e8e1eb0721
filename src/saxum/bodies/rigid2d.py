"""Rigid bodies in the plane, compiled: the body kind (saxum.bodies) of 3-dof polygons, what
the time loop needs that depends on how they move. (saxum.bodies.rigid3d provides the same
functions for 6-dof bodies and quaternions.)

Velocity of a material point M of body i: v(M) = v(G_i) + omega_i e_z x l_i, l_i = M - G_i, so a
contact direction d gives the row of H* [d_x, d_y, l x d] with l x d = l_x d_y - l_y d_x.
"""

import math

import numba as nb
import numpy as np

from ..integrator import diagonal_free_velocity

__all__ = [
    "contact_jacobians",
    "contactor_coordinates",
    "driven_velocity",
    "free_velocity",
    "lever_arms",
    "kinetic_energy",
    "predict_positions",
    "update_positions",
    "world_geometry",
    "world_geometry_range",
]


@nb.njit(cache=True)
def world_geometry(q, vertex_start, vertex_local, direction_local, vertices, directions):
    """vertices[k] = x_b + Rot(theta_b) vertex_local[k] [m] and directions[k] =
    Rot(theta_b) direction_local[k] for every vertex k of every body b (one rotation per
    body for both)."""
    world_geometry_range(0, q.shape[0], q, vertex_start, vertex_local, direction_local,
                         vertices, directions)


@nb.njit(inline="always")
def world_geometry_range(lo, hi, q, vertex_start, vertex_local, direction_local, vertices,
                         directions):
    """world_geometry of the bodies lo .. hi - 1 (a parallel region calls it on blocks)."""
    for b in range(lo, hi):
        c = math.cos(q[b, 2])
        s = math.sin(q[b, 2])
        for k in range(vertex_start[b], vertex_start[b + 1]):
            lx = vertex_local[k, 0]
            ly = vertex_local[k, 1]
            vertices[k, 0] = q[b, 0] + c * lx - s * ly
            vertices[k, 1] = q[b, 1] + s * lx + c * ly
            lx = direction_local[k, 0]
            ly = direction_local[k, 1]
            directions[k, 0] = c * lx - s * ly
            directions[k, 1] = s * lx + c * ly


@nb.njit(cache=True)
def contactor_coordinates(q, contactor_body, centre_local, out):
    """out[c] = (x_b + Rot(theta_b) centre_local[c], theta_b): where contactor c of body b =
    contactor_body[c] is, its centroid [m] and its body's angle [rad] (clusters)."""
    for c in range(contactor_body.shape[0]):
        b = contactor_body[c]
        co = math.cos(q[b, 2])
        si = math.sin(q[b, 2])
        out[c, 0] = q[b, 0] + co * centre_local[c, 0] - si * centre_local[c, 1]
        out[c, 1] = q[b, 1] + si * centre_local[c, 0] + co * centre_local[c, 1]
        out[c, 2] = q[b, 2]


def free_velocity(q: np.ndarray, v: np.ndarray, inertia: np.ndarray, inv_mass: np.ndarray,
                  force: np.ndarray, h: float, out: np.ndarray) -> None:
    """out = v + h M^-1 force [m/s, rad/s]: M diagonal; force [N, N, N m] theta-weighted."""
    diagonal_free_velocity(v, inv_mass, force, h, out)


def driven_velocity(q: np.ndarray, bodies: np.ndarray, v: np.ndarray) -> None:
    """Imposed velocities are already (vx, vy, omega) in 2D: nothing to turn."""


@nb.njit(cache=True)
def predict_positions(q, v, step, out):
    """Predicted configuration for detection: out = q + step v, step = (1 - theta) h [s]."""
    for b in range(q.shape[0]):
        for d in range(3):
            out[b, d] = q[b, d] + step * v[b, d]


@nb.njit(cache=True)
def update_positions(q, v_begin, v_end, h, theta):
    """Moreau-Jean position update: q += h [(1 - theta) v_begin + theta v_end]."""
    a = h * (1.0 - theta)
    c = h * theta
    for b in range(q.shape[0]):
        for d in range(3):
            q[b, d] += a * v_begin[b, d] + c * v_end[b, d]


@nb.njit(cache=True)
def kinetic_energy(v, mass, inertia, inv_mass):
    """1/2 sum (m |v|^2 + I omega^2) over free bodies [J per metre of depth]."""
    e = 0.0
    for b in range(v.shape[0]):
        if inv_mass[b, 0] > 0.0:
            e += mass[b] * (v[b, 0] ** 2 + v[b, 1] ** 2) + inertia[b] * v[b, 2] ** 2
    return 0.5 * e


@nb.njit(inline="always")
def lever_arms(q, c, b, point, frame, gap, a):
    """(l_c, l_a) [m] of contact a, flattened: from the candidate c's centre of mass to its
    material point `point`, and from the antagonist b's to its own, the projection
    point - gap n on the antagonist's face."""
    nx = frame[a, 1, 0]
    ny = frame[a, 1, 1]
    return (point[a, 0] - q[c, 0], point[a, 1] - q[c, 1], point[a, 0] - gap[a] * nx - q[b, 0],
            point[a, 1] - gap[a] * ny - q[b, 1])


@nb.njit(cache=True)
def contact_jacobians(q, candidate, antagonist, point, frame, gap, count, h_cand, h_ant):
    """Rows of H* for each contact: U = h_cand[a] v_cand + h_ant[a] v_ant, U = (U_t, U_n),
    material points as in lever_arms."""
    for a in range(count):
        lcx, lcy, lax, lay = lever_arms(q, candidate[a], antagonist[a], point, frame, gap, a)
        for r in range(2):
            dx = frame[a, r, 0]
            dy = frame[a, r, 1]
            h_cand[a, r, 0] = dx
            h_cand[a, r, 1] = dy
            h_cand[a, r, 2] = lcx * dy - lcy * dx
            h_ant[a, r, 0] = -dx
            h_ant[a, r, 1] = -dy
            h_ant[a, r, 2] = -(lax * dy - lay * dx)
