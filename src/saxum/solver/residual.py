"""The error measure of frictional contact problems: the natural-map residual.

For the local problem u = W r + q with, per contact alpha, the components in FCLIB's order
[normal, tangent(s)] (spacedim 2 or 3) and K_alpha = {r : |r_T| <= mu_alpha r_N} the Coulomb
cone, the De Saxce modified velocity
    u_hat_alpha = u_alpha + mu_alpha |u_T,alpha| e_N
turns the law into the complementarity K* ∋ u_hat ⊥ r ∈ K, which holds iff the natural map
    F_nat(r)_alpha = r_alpha - proj_K_alpha(r_alpha - u_hat_alpha)
vanishes. The projection of z = (z_N, z_T) on K (|z_T| the absolute value in 2D):
    z_N >= 0, |z_T| <= mu z_N  ->  z                               (inside the cone)
    mu |z_T| <= -z_N           ->  0                               (inside the polar cone)
    otherwise                  ->  a (1, mu z_T / |z_T|),  a = (mu |z_T| + z_N) / (1 + mu^2)
(for mu = 0 the cone is the half-line r_T = 0, r_N >= 0 and the same formulas hold; the test
z_N >= 0 matters there only, where |z_T| = 0 <= mu z_N would hold for z_N < 0 too).
The relative error is ||F_nat(r)||_2 / ||q||_2 (V. Acary, M. Bremond, O. Huber, "On solving
contact problems with Coulomb friction: formulations and numerical comparisons", 2018, sec.
"Measuring errors"), ||F_nat|| itself when q = 0. It is computed here from r alone, with u
recomputed from W and q, so that it does not depend on what a solver reports.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = ["natural_map", "natural_map_error", "project_on_cone"]


def project_on_cone(z: np.ndarray, mu: np.ndarray) -> np.ndarray:
    """Projection of z (contacts, spacedim), order [N, T...], on the cones |z_T| <= mu z_N."""
    zn = z[:, 0]
    zt = z[:, 1:]
    norm_t = np.sqrt(np.einsum("ij,ij->i", zt, zt))
    inside = (zn >= 0.0) & (norm_t <= mu * zn)
    polar = ~inside & (mu * norm_t <= -zn)
    a = (mu * norm_t + zn) / (1.0 + mu * mu)
    # on the boundary branch norm_t > 0 (else one of the two tests above holds)
    scale = np.divide(mu * a, norm_t, out=np.zeros_like(a), where=norm_t > 0.0)
    out = np.empty_like(z)
    out[:, 0] = a
    out[:, 1:] = scale[:, None] * zt
    out[inside] = z[inside]
    out[polar] = 0.0
    return out


def natural_map(r: np.ndarray, u: np.ndarray, mu: np.ndarray, spacedim: int) -> np.ndarray:
    """F_nat(r) (flat, like r) for impulses r and velocities u = W r + q in FCLIB order."""
    r2 = r.reshape(-1, spacedim)
    u2 = u.reshape(-1, spacedim)
    ut = u2[:, 1:]
    u_hat = u2.copy()
    u_hat[:, 0] += mu * np.sqrt(np.einsum("ij,ij->i", ut, ut))
    return (r2 - project_on_cone(r2 - u_hat, mu)).ravel()


def natural_map_error(w: sp.spmatrix | np.ndarray, q: np.ndarray, mu: np.ndarray, r: np.ndarray,
                      spacedim: int) -> float:
    """||F_nat(r)|| / ||q|| with u = W r + q (||F_nat(r)|| if q = 0)."""
    f = natural_map(r, w @ r + q, mu, spacedim)
    norm_q = float(np.linalg.norm(q))
    norm_f = float(np.linalg.norm(f))
    return norm_f / norm_q if norm_q > 0.0 else norm_f
