"""Maugis–Dugdale sphere: rigid paraboloid (radius R) on an elastic half-space, Dugdale adhesion.

Maugis (1992), J. Colloid Interface Sci. 150, 243, in the notation of Johnson
& Greenwood (1997), J. Colloid Interface Sci. 192, 326. A Dugdale stress σ0
acts over a ≤ r ≤ c (gap(c) = w/σ0); m = c/a ≥ 1, K = (4/3)E*.

Scales:  ℓ = (πwR²/K)^{1/3},  P_u = πwR,  δ_u = (π²w²R/K²)^{1/3};   Ā = a/ℓ, P̄ = P/P_u, Δ̄ = δ/δ_u.
Maugis parameter:  λ = 2σ0 (R/(πwK²))^{1/3}      (≈ 1.16 μ, Tabor μ, for Lennard-Jones σ0 = 1.03 w/z0)
 (M1)  (λĀ²/2)[√(m²−1) + (m²−2) arctan√(m²−1)]
         + (4λ²Ā/3)[√(m²−1) arctan√(m²−1) − m + 1] = 1
 (M2)  P̄ = Ā³ − λĀ²[√(m²−1) + m² arctan√(m²−1)]
 (M3)  Δ̄ = Ā² − (4/3)λĀ√(m²−1)
Limits: λ → ∞ gives JKR (P̄ = Ā³ − √(6Ā³), Δ̄ = Ā² − √(8Ā/3), pull-off −3/2);
λ → 0 gives DMT (P̄ = Ā³ − 2, Δ̄ = Ā², pull-off −2, i.e. P_c = −2πwR).
Along the contact branch Ā → 0 (m → ∞, c = mĀ → c̄0):
λπc̄0²/4 + (4/3)λ²(π/2 − 1)c̄0 = 1 and P̄ → −λπc̄0²/2 (derived here from M1, M2).

Units: SI. P in N, a, c, R, δ in m, E*, σ0 in Pa, w in J/m². P > 0 compressive,
δ > 0 into the body. Internally m = cosh t, √(m²−1) = sinh t, arctan√(m²−1)
= gd t (Gudermann), which removes the cancellation at m → 1 (large λ).
Validity: frictionless, a ≪ R, half-space, isolated contact.
"""

import math

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ._validate import nonnegative, positive, scalar
from .maugis_dugdale import dugdale_from_cohesive_law

_T_MAX = 350.0  # cosh t overflows beyond t ≈ 710; the terms carry cosh² t


def units(radius, e_star, work):
    """Maugis scales (ℓ [m], P_u [N], δ_u [m]) = ((πwR²/K)^{1/3}, πwR, (π²w²R/K²)^{1/3}), K = 4E*/3.

    `radius` R [m], `e_star` E* [Pa], `work` w [J/m²], all > 0.
    """
    R = float(positive("radius", radius))
    K = 4.0 / 3.0 * float(positive("e_star", e_star))
    w = float(positive("work", work))
    return float(np.cbrt(math.pi * w * R**2 / K)), math.pi * w * R, float(np.cbrt(math.pi**2 * w**2 * R / K**2))


def maugis_parameter(sigma0, radius, e_star, work):
    """Maugis parameter of the sphere λ = 2σ0 (R/(πwK²))^{1/3}, K = 4E*/3 [-] (Maugis 1992).

    `sigma0` Dugdale stress [Pa] > 0, `radius` R [m], `e_star` E* [Pa], `work` w [J/m²] > 0.
    """
    s0 = positive("sigma0", sigma0)
    R = positive("radius", radius)
    K = 4.0 / 3.0 * positive("e_star", e_star)
    w = positive("work", work)
    return scalar(2.0 * s0 * np.cbrt(R / (math.pi * w * K**2)))


def maugis_parameter_from_cohesive_law(phi_n, delta_n, radius, e_star):
    """λ of the sphere for the exponential CZ law mapped by w = φn, σ0 = φn/(eδn) (as maugis_dugdale).

    `phi_n` [J/m²], `delta_n` [m], `radius` R [m], `e_star` E* [Pa].
    """
    w, s0 = dugdale_from_cohesive_law(phi_n, delta_n)
    return maugis_parameter(s0, radius, e_star, w)


def _gd(t):
    return 2.0 * math.atan(math.tanh(0.5 * t))


def _sinh_minus_gd(t):
    """sinh t − gd t (series for small t, where the difference cancels)."""
    if t < 1e-2:
        return t**3 / 3.0 - t**5 / 30.0 + 31.0 * t**7 / 2520.0
    return math.sinh(t) - _gd(t)


def _lhs_m1(t, A, lam):
    s, g = math.sinh(t), _gd(t)
    first = _sinh_minus_gd(t) + s * s * g  # √(m²−1) + (m²−2) arctan√(m²−1)
    second = s * g - 2.0 * math.sinh(0.5 * t) ** 2  # √(m²−1) arctan√(m²−1) − m + 1
    return 0.5 * lam * A * A * first + 4.0 / 3.0 * lam * lam * A * second


def _check(a_bar, lam):
    return float(positive("a_bar", a_bar)), float(positive("lam", lam))


def _solve_t(A, lam):
    """Root t > 0 of (M1) with m = cosh t; its left side rises monotonically from 0 at t = 0."""
    hi = 1.0
    while _lhs_m1(hi, A, lam) < 1.0:
        if hi >= _T_MAX:
            raise ValueError(f"(M1) has no representable root for a_bar = {A!r}, lam = {lam!r}")
        hi = min(2.0 * hi, _T_MAX)
    return brentq(lambda t: _lhs_m1(t, A, lam) - 1.0, 0.0, hi, xtol=1e-300, rtol=1e-15, maxiter=500)


def solve_m(a_bar, lam):
    """m = c/a ≥ 1 solving (M1) for Ā = a/ℓ > 0 and λ > 0 (scalars); unique root, brentq."""
    A, lm = _check(a_bar, lam)
    return math.cosh(_solve_t(A, lm))


def load_dimensionless(a_bar, lam):
    """P̄ = P/(πwR) = Ā³ − λĀ²[√(m²−1) + m² arctan√(m²−1)] (M2) for Ā > 0, λ > 0 (scalars)."""
    A, lm = _check(a_bar, lam)
    t = _solve_t(A, lm)
    return A**3 - lm * A * A * (math.sinh(t) + math.cosh(t) ** 2 * _gd(t))


def approach_dimensionless(a_bar, lam):
    """Δ̄ = δ/δ_u = Ā² − (4/3)λĀ√(m²−1) (M3) for Ā > 0, λ > 0 (scalars)."""
    A, lm = _check(a_bar, lam)
    return A * A - 4.0 / 3.0 * lm * A * math.sinh(_solve_t(A, lm))


def _limit_small_a(lam):
    """lim_{Ā→0} P̄ = −λπc̄0²/2, λπc̄0²/4 + (4/3)λ²(π/2 − 1)c̄0 = 1 (module doc)."""
    qa, qb = lam * math.pi / 4.0, 4.0 / 3.0 * lam**2 * (math.pi / 2.0 - 1.0)
    c0 = 2.0 / (qb + math.sqrt(qb * qb + 4.0 * qa))  # positive root of qa c² + qb c − 1 = 0
    return -lam * math.pi * c0**2 / 2.0


def pull_off(lam, a_bar_min=1e-6, depth_tol=1e-9):
    """Pull-off under load control for λ > 0: (P̄_c = P_c/(πwR), Ā at pull-off) (Maugis 1992).

    The first local minimum of P̄(Ā) met coming from large Ā (log grid on
    [a_bar_min, 3], refined with Brent). If there is none, or it lies less
    than `depth_tol`·|P̄0| below the branch end value P̄0 = lim_{Ā→0} P̄, the
    pull-off is the end point (P̄0, 0.0) (DMT-like: the contact shrinks to a
    point). λ → ∞: (−3/2, (3/2)^{1/3}); λ → 0: (−2, 0).
    """
    lm = float(positive("lam", lam))
    a_bar_min = float(positive("a_bar_min", a_bar_min))
    depth_tol = float(nonnegative("depth_tol", depth_tol))
    if a_bar_min >= 0.1:
        raise ValueError(f"a_bar_min = {a_bar_min!r} must be < 0.1 (start of the search grid)")
    p_end = _limit_small_a(lm)
    grid = np.logspace(math.log10(a_bar_min), math.log10(3.0), 141)
    P = np.array([load_dimensionless(A, lm) for A in grid])
    minima = [j for j in range(1, len(grid) - 1) if P[j] < P[j - 1] and P[j] < P[j + 1]]
    if not minima:
        return p_end, 0.0
    j = minima[-1]
    res = minimize_scalar(lambda s: load_dimensionless(math.exp(s), lm),
                          bracket=(math.log(grid[j - 1]), math.log(grid[j]), math.log(grid[j + 1])),
                          method="brent", options={"xtol": 1e-10})
    if res.fun > p_end - depth_tol * abs(p_end):
        return p_end, 0.0
    return float(res.fun), float(math.exp(res.x))


def load(contact_radius, radius, e_star, work, sigma0):
    """Load P [N] at contact radius a > 0 [m] (M2); a may be an array. σ0 = `sigma0` [Pa]."""
    a = positive("contact_radius", contact_radius)
    ell, P_u, _ = units(radius, e_star, work)
    lam = float(maugis_parameter(sigma0, radius, e_star, work))
    return scalar(P_u * np.vectorize(lambda x: load_dimensionless(x / ell, lam), otypes=[float])(a))


def approach(contact_radius, radius, e_star, work, sigma0):
    """Approach δ [m] at contact radius a > 0 [m] (M3); a may be an array. σ0 = `sigma0` [Pa]."""
    a = positive("contact_radius", contact_radius)
    ell, _, d_u = units(radius, e_star, work)
    lam = float(maugis_parameter(sigma0, radius, e_star, work))
    return scalar(d_u * np.vectorize(lambda x: approach_dimensionless(x / ell, lam), otypes=[float])(a))


def pull_off_load(radius, e_star, work, sigma0):
    """Pull-off load under load control P_c [N] (< 0), between −2πwR (DMT) and −(3/2)πwR (JKR)."""
    _, P_u, _ = units(radius, e_star, work)
    return P_u * pull_off(float(maugis_parameter(sigma0, radius, e_star, work)))[0]
