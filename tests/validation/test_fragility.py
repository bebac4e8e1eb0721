"""Lognormal fragility fits (saxum.fragility; J.W. Baker 2015, Earthquake Spectra 31(1))
recover the parameters of synthetic data drawn from a known lognormal fragility.

Multiple stripes: at 10 intensities 0.2 .. 2.0, n = 20 runs each, the failures drawn from
Binomial(n, Phi(ln(x / 0.8) / 0.4)); IDA: 30 capacities drawn from LN(ln 0.8, 0.4), and the
same with those above 1.5 censored (records that never collapsed up to 1.5). Over 150 data
sets (seeded), the 95 % confidence intervals of theta and beta hold the true values in at
least 90 % of the sets and at most 99 % (a 95 % interval that is right covers 95 %; the
binomial scatter of 150 sets is 1.8 %, so 90 % is 2.8 sigma below: the Wald intervals of
the Fisher information are asymptotic, and 30 records are few), and the band of the curve
holds the true curve at the median in as many. One large data set (400 runs per stripe)
gives theta within 4 % and beta within 9 %: 3 standard errors (1.3 % and 2.8 % there).
"""

import math

import numpy as np
import pytest
from scipy import special

import saxum as sx
from saxum.fragility import fit_capacities, fit_stripes

THETA, BETA = 0.8, 0.4
X = np.round(np.arange(0.2, 2.01, 0.2), 12)
SETS = 150


def _covers(fit, level=0.95):
    band = fit.interval(level)
    lo, hi = fit.band(np.array([THETA]), level)
    return (band["theta"][0] <= THETA <= band["theta"][1],
            band["beta"][0] <= BETA <= band["beta"][1], lo[0] <= 0.5 <= hi[0])


@pytest.mark.parametrize("kind", ["stripes", "capacities", "censored"])
def test_confidence_intervals_cover_the_true_parameters(kind):
    rng = np.random.default_rng(2015)
    hits = np.zeros(3)
    for _ in range(SETS):
        if kind == "stripes":
            n = np.full(X.size, 20)
            fit = fit_stripes(X, n, rng.binomial(n, special.ndtr(np.log(X / THETA) / BETA)))
        else:
            c = np.exp(rng.normal(math.log(THETA), BETA, 30))
            if kind == "censored":
                c[c > 1.5] = np.nan
            fit = fit_capacities(c, 1.5)
        hits += _covers(fit)
    share = hits / SETS
    assert np.all((share >= 0.90) & (share <= 0.99)), share


def test_large_sample_recovers_the_parameters():
    rng = np.random.default_rng(7)
    n = np.full(X.size, 400)
    fit = fit_stripes(X, n, rng.binomial(n, special.ndtr(np.log(X / THETA) / BETA)))
    se_mu, se_ln_beta = np.sqrt(np.diag(fit.covariance))
    assert se_mu < 0.014 and se_ln_beta < 0.03  # (the sizes the tolerances are made of)
    assert fit.theta == pytest.approx(THETA, rel=0.04)
    assert fit.beta == pytest.approx(BETA, rel=0.09)
    assert fit.probability(THETA) == pytest.approx(0.5, abs=0.05)


def test_data_that_fix_no_fragility_are_refused():
    with pytest.raises(sx.InputError, match="no run failed"):
        fit_stripes([0.5, 1.0], [10, 10], [0, 0])
    with pytest.raises(sx.InputError, match="fix no beta"):
        fit_stripes([0.5, 1.0, 1.5], [10, 10, 10], [0, 10, 10])
    with pytest.raises(sx.InputError, match="1 record"):
        fit_capacities([0.5, np.nan, np.nan], 2.0)
