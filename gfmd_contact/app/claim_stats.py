"""Statistics of the claims table (`gfmd_contact.app.claims`): set means, their covariance, effect sizes and verdicts.

A *sample* is one parameter set's per-realization values, {seed: value} (NaN: that realization gives
no value). Realizations with different seeds are independent; two sets' realizations with the same
seed share their rough profile (scaled), so their values are correlated.

* A set's value is its mean x̄ over the n realizations with a value, its standard error
  SE = s/√n (s: sample standard deviation, ddof = 1; 0 for n = 1).
* The covariance of two sets' means is estimated from the seeds they share (Cov(x̄_a, x̄_b) =
  s_ab n_ab/(n_a n_b): the sum over the n_ab shared seeds of Cov(x_a, x_b), divided by n_a n_b; s_ab the
  sample covariance over them, ddof = 1; 0 when fewer than two are shared).
* An effect is a function f of set means; its value is f(x̄) and its standard error the delta
  method's √(gᵀ C g), g = ∇f at x̄, C the covariance of the set means above. For a difference of
  two sets with the same seeds this is the paired SE, √(Var(a − b)/n); with no shared seed it is
  √(SE_a² + SE_b²). Should the estimated form be negative (shared seeds too few for the sample
  covariances to be consistent), the bound of perfectly correlated means, Σ|g_i| SE_i, is used.
* n of an effect: the fewest realizations of a set it depends on (g_i ≠ 0).

The verdict compares the effect with the claim's limit at two standard errors.
"""

from __future__ import annotations

import math

import numpy as np

REPRODUCED, NOT_REPRODUCED, INCONCLUSIVE = "reproduced", "not reproduced", "inconclusive (within 2 SE)"
SINGLE = "inconclusive (n < 2: no standard error)"
NOT_IN_STUDY, DEPENDS = "not in this study", "depends on δn / the contact rule"


def stats(values):
    """(mean, standard error s/√n, n) of the finite values (a dict's values or a sequence)."""
    v = np.asarray(list(values.values()) if isinstance(values, dict) else list(values), float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return math.nan, math.nan, 0
    se = float(np.std(v, ddof=1) / math.sqrt(v.size)) if v.size > 1 else 0.0
    return float(np.mean(v)), se, int(v.size)


def _finite(sample):
    return {k: float(v) for k, v in sample.items() if np.isfinite(v)}


def mean_covariance(a, b):
    """Estimated Cov(x̄_a, x̄_b) of two samples' means ({seed: value}); Var(x̄_a) = SE_a² when a is b."""
    a, b = _finite(a), _finite(b)
    shared = [k for k in a if k in b]
    if len(shared) < 2:
        return 0.0
    x = np.array([a[k] for k in shared])
    y = np.array([b[k] for k in shared])
    s_ab = float(np.sum((x - x.mean()) * (y - y.mean())) / (len(shared) - 1))
    return s_ab * len(shared) / (len(a) * len(b))


def standard_error(samples, gradient):
    """√(gᵀ C g): the delta-method SE of f(x̄_1 … x̄_k) with ∇f = gradient (C: `mean_covariance`).

    When every sample it depends on has the same seeds, the same number as sd(z)/√n with
    z(seed) = Σ g_i x_i(seed): the combination is taken per seed before squaring, so two sets that
    differ by round-off (κ at two ν on the same profiles) give the SE of their difference, not the
    round-off of C_aa + C_bb − 2 C_ab."""
    g = np.asarray(gradient, float)
    k = len(samples)
    used = [i for i in range(k) if g[i] != 0]
    finite = [_finite(s) for s in samples]
    seeds = sorted(finite[used[0]]) if used else []
    if len(seeds) >= 2 and all(sorted(finite[i]) == seeds for i in used):
        z = sum(g[i] * np.array([finite[i][s] for s in seeds]) for i in used)
        return float(np.std(z, ddof=1) / math.sqrt(len(seeds)))
    cov = np.array([[mean_covariance(samples[i], samples[j]) for j in range(k)] for i in range(k)])
    q = float(g @ cov @ g)
    if q < 0:  # inconsistent pairwise estimates: the perfectly correlated bound
        return float(np.abs(g) @ np.sqrt(np.diag(cov)))
    return math.sqrt(q)


def effect(samples, value, gradient):
    """(value, SE, n) of an effect f of the samples' means: value = f(x̄), gradient = ∇f(x̄)."""
    ns = [stats(s)[2] for s, g in zip(samples, gradient) if g != 0]
    return float(value), standard_error(samples, gradient), min(ns) if ns else 0


def linear(samples, weights, offset=0.0):
    """(Σ w_i x̄_i + offset, SE, n)."""
    means = [stats(s)[0] for s in samples]
    return effect(samples, float(np.dot(weights, means)) + offset, weights)


def difference(a, b):
    """(x̄_a − x̄_b, SE, n): paired over the seeds a and b share, independent over the rest."""
    return linear([a, b], [1.0, -1.0])


def relative_range_gradient(samples):
    """(r, ∇r, i_max, i_min) of r = (x̄_max − x̄_min)/|mean of the x̄| over the samples with a value, or None (< 2).

    i_max, i_min index `samples`; ∇r runs through the extreme sets and the mean in the denominator (every
    set with a value)."""
    means = [stats(s)[0] for s in samples]
    ok = [i for i, m in enumerate(means) if np.isfinite(m)]
    if len(ok) < 2:
        return None
    hi = max(ok, key=lambda i: means[i])
    lo = min(ok, key=lambda i: means[i])
    total = float(np.mean([means[i] for i in ok]))
    scale = abs(total)
    r = (means[hi] - means[lo]) / scale
    g = np.zeros(len(samples))
    g[ok] = -r * math.copysign(1.0, total) / (len(ok) * scale)
    g[hi] += 1 / scale
    g[lo] -= 1 / scale
    return r, g, hi, lo


def relative_range(samples):
    """(r, SE, n, i_max, i_min) of `relative_range_gradient`'s r, or None (fewer than two sets with a value)."""
    rg = relative_range_gradient(samples)
    if rg is None:
        return None
    r, g, hi, lo = rg
    return (*effect(samples, r, g), hi, lo)


def verdict_below(value, se, limit):
    """Claim 'value ≤ limit' at 2 SE."""
    if not np.isfinite(value):
        return NOT_IN_STUDY
    if value + 2 * se <= limit:
        return REPRODUCED
    if value - 2 * se > limit:
        return NOT_REPRODUCED
    return INCONCLUSIVE


def verdict_positive(value, se):
    """Claim 'value > 0' at 2 SE."""
    if not np.isfinite(value):
        return NOT_IN_STUDY
    if value - 2 * se > 0:
        return REPRODUCED
    if value + 2 * se <= 0:
        return NOT_REPRODUCED
    return INCONCLUSIVE
