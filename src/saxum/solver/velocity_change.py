"""NLGS's convergence criterion: the relative change of the velocities between two sweeps,
sqrt(sum m |v - v_prev|^2 / sum m |v - v_free|^2) (saxum.solver.nlgs._relative_change), as
inline pieces that rigid bodies and finite-element nodes share."""

import math

import numba as nb
import numpy as np

__all__ = ["change_ratio", "change_sums"]


@nb.njit(inline="always")
def change_sums(v, v_prev, v_free, mass, num, den, size):
    """Adds to (num, den, size) the mass-weighted squares of v's change since v_prev, of its
    reaction v - v_free and of v itself (mass [n, dof]); then v_prev = v."""
    for b in range(v.shape[0]):
        for d in range(v.shape[1]):
            m = mass[b, d]
            change = v[b, d] - v_prev[b, d]
            v_prev[b, d] = v[b, d]
            reaction = v[b, d] - v_free[b, d]
            num += m * change * change
            den += m * reaction * reaction
            size += m * v[b, d] * v[b, d]
    return num, den, size


@nb.njit(inline="always")
def change_ratio(num, den, size):
    """sqrt(num / (den + 1e-28 size)) of change_sums' squares (module doc)."""
    if num == 0.0:
        return 0.0
    den += 1e-28 * size
    if den == 0.0:
        return np.inf
    return math.sqrt(num / den)
