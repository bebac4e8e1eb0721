"""Lognormal fragility functions fitted to the runs of an ensemble.

A fragility function is the probability that a structure fails (collapses, or its demand
exceeds a threshold) under a ground motion of intensity x:

    P(x) = Phi(ln(x / theta) / beta),

theta the median capacity, beta its logarithmic standard deviation. Both fits follow J.W.
Baker (2015), "Efficient analytical fragility function fitting using dynamic structural
analysis", Earthquake Spectra 31(1), 579-599:

- multiple-stripe analysis (`fit_stripes`): z_j failures of n_j runs at intensity x_j; theta
  and beta maximize the binomial likelihood prod_j C(n_j, z_j) p_j^z_j (1 - p_j)^(n_j - z_j),
  p_j = P(x_j) (Baker's Eq. 11);
- incremental dynamic analysis (`fit_capacities`): the records' capacities x_i (the
  intensity at which each failed) are lognormal: ln theta = mean of ln x_i, beta = their
  standard deviation (1/(n-1); Baker's Eqs. 2-3). Records that never failed up to the largest
  intensity run are censored there: then theta and beta maximize the likelihood
  prod_failed phi(u_i) / (beta x_i) prod_censored (1 - Phi(u_i)), u_i = ln(x_i/theta)/beta.

Confidence bands: from the curvature of the log-likelihood, the observed Fisher information
I at the fit in (mu = ln theta, ln beta), by central differences of the exact
log-likelihood; the covariance C = I^-1 gives the standard errors of mu and ln beta and,
by the delta method, of u(x) = (ln x - mu) / beta, so that the band at level `level` is
Phi(u -/+ z s_u), z the normal quantile (Wald intervals; for the closed-form IDA fit the
same information of the lognormal likelihood at its estimates).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special, stats

from .errors import InputError

__all__ = ["Fragility", "fit_capacities", "fit_stripes"]


@dataclass(frozen=True)
class Fragility:
    """A fitted lognormal fragility: median theta (in the intensity's unit), beta [-], the
    covariance of (ln theta, ln beta) [-], the method ("stripes" or "capacities") and the
    number of observations (runs, or records)."""

    theta: float
    beta: float
    covariance: np.ndarray
    method: str
    observations: int

    def probability(self, x) -> np.ndarray:
        """P(x) = Phi(ln(x / theta) / beta)."""
        return special.ndtr(np.log(np.asarray(x, dtype=float) / self.theta) / self.beta)

    def band(self, x, level: float = 0.95) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper confidence bounds of P(x) at `level` (module doc)."""
        u = np.log(np.asarray(x, dtype=float) / self.theta) / self.beta
        # u = (ln x - mu) / exp(lb): du/dmu = -1/beta, du/dlb = -u
        grad = np.stack((np.full_like(u, -1.0 / self.beta), -u))
        s = np.sqrt(np.einsum("i...,ij,j...->...", grad, self.covariance, grad))
        z = stats.norm.ppf(0.5 + 0.5 * level)
        return special.ndtr(u - z * s), special.ndtr(u + z * s)

    def interval(self, level: float = 0.95) -> dict[str, tuple[float, float]]:
        """Confidence intervals of theta and beta at `level` (Wald, on their logarithms)."""
        z = stats.norm.ppf(0.5 + 0.5 * level)
        s_mu, s_lb = np.sqrt(np.diag(self.covariance))
        return {"theta": (self.theta * math.exp(-z * s_mu), self.theta * math.exp(z * s_mu)),
                "beta": (self.beta * math.exp(-z * s_lb), self.beta * math.exp(z * s_lb))}


def _covariance(nll, mu: float, lb: float) -> np.ndarray:
    """Inverse of the Hessian of the negative log-likelihood nll(mu, ln beta) at its
    minimum, by central differences (steps 1e-4: the likelihood is smooth, and the error
    O(h^2) is far below the sampling error that the band shows)."""
    h = 1e-4
    p = np.array([mu, lb])
    hess = np.empty((2, 2))
    for i in range(2):
        for j in range(2):
            e_i, e_j = np.eye(2)[i] * h, np.eye(2)[j] * h
            hess[i, j] = (nll(*(p + e_i + e_j)) - nll(*(p + e_i - e_j))
                          - nll(*(p - e_i + e_j)) + nll(*(p - e_i - e_j))) / (4 * h * h)
    try:
        return np.linalg.inv(hess)
    except np.linalg.LinAlgError:
        raise InputError("the fragility fit has no curvature: the data do not fix theta "
                         "and beta") from None


def fit_stripes(intensity, runs, failures) -> Fragility:
    """Fit theta and beta to stripes: at intensity x_j > 0, `failures` z_j of `runs` n_j
    (Baker 2015, maximum likelihood; module doc)."""
    x = np.asarray(intensity, dtype=float)
    n = np.asarray(runs, dtype=float)
    z = np.asarray(failures, dtype=float)
    if not (x.shape == n.shape == z.shape and x.ndim == 1 and x.size >= 2):
        raise InputError("fragility: give at least two stripes, as many runs and failures "
                         "as intensities")
    if np.any(x <= 0.0) or np.any(n < 1) or np.any((z < 0) | (z > n)):
        raise InputError("fragility: intensities must be > 0 and 0 <= failures <= runs")
    if not z.any() or np.all(z == n):
        raise InputError(f"fragility: {'no' if not z.any() else 'every'} run failed; the "
                         "stripes must reach from where the structure stands to where it "
                         "fails")
    ln_x = np.log(x)
    partial = (z > 0) & (z < n)
    if not partial.any() and ln_x[z > 0].min() > ln_x[z < n].max():
        raise InputError("fragility: every stripe below some intensity stands and every one "
                         "above fails: the data fix no beta; add stripes between "
                         f"{x[z < n].max():g} and {x[z > 0].min():g} or more records")

    def nll(mu: float, lb: float) -> float:
        u = (ln_x - mu) / math.exp(lb)
        return -float(np.sum(z * special.log_ndtr(u) + (n - z) * special.log_ndtr(-u)))

    start = (float(np.average(ln_x, weights=n)), math.log(0.5))
    fit = optimize.minimize(lambda p: nll(*p), start, method="Nelder-Mead",
                            options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000})
    mu, lb = fit.x
    return Fragility(math.exp(mu), math.exp(lb), _covariance(nll, mu, lb), "stripes",
                     int(n.sum()))


def fit_capacities(capacities, censored_at: float | None = None) -> Fragility:
    """Fit theta and beta to the records' capacities (nan: a record that never failed up to
    `censored_at`, the largest intensity run; Baker 2015, module doc)."""
    c = np.asarray(capacities, dtype=float)
    failed = np.isfinite(c)
    if failed.sum() < 2:
        raise InputError(f"fragility: {int(failed.sum())} record(s) failed; a fit needs two")
    if np.any(c[failed] <= 0.0):
        raise InputError("fragility: capacities must be > 0")
    ln_c = np.log(c[failed])
    censored = int((~failed).sum())
    if censored and censored_at is None:
        raise InputError("fragility: records that never failed need the largest intensity "
                         "run (censored_at)")
    ln_top = math.log(censored_at) if censored else 0.0

    def nll(mu: float, lb: float) -> float:
        beta = math.exp(lb)
        u = (ln_c - mu) / beta
        value = float(np.sum(0.5 * u * u + lb)) + 0.5 * ln_c.size * math.log(2.0 * math.pi)
        return value - censored * float(special.log_ndtr(-(ln_top - mu) / beta))

    if censored:
        fit = optimize.minimize(lambda p: nll(*p), (ln_c.mean(), math.log(ln_c.std(ddof=1))),
                                method="Nelder-Mead",
                                options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000})
        mu, lb = fit.x
    else:
        mu, lb = float(ln_c.mean()), math.log(float(ln_c.std(ddof=1)))
    return Fragility(math.exp(mu), math.exp(lb), _covariance(nll, mu, lb), "capacities",
                     int(c.size))
