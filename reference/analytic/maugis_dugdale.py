"""Maugis–Dugdale line contact (rigid cylinder, half-plane): Baney & Hui (1997).

Implements shared/reference-formulas.md §4.2 (Baney & Hui 1997, J. Adhesion
Sci. Technol. 11, 393, as coded in ContactEngineering BaneyHui.py). A Dugdale
cohesive stress σ0 acts over a ≤ |x| ≤ c (c = outer edge of the cohesive
zone, gap(c) = w/σ0).

Scales:  ℓ = 2(wR²/(πE*))^{1/3},  F_u = (πE*w²R)^{1/3},  p_u = (E*²w/(πR))^{1/3};
         Ā = a/ℓ,  m = c/a ≥ 1.
Maugis parameter:  λ = 4σ0 (R/(π²E*²w))^{1/3}     (E* = E/(1−ν²), checked in §4.2)
 (i)  (λĀ²/2)[m√(m²−1) − ln(m + √(m²−1))]
        + (λ²Ā/2)[√(m²−1) ln(m + √(m²−1)) − m ln m] = 1
 (ii) F/F_u = Ā² − λĀ√(m²−1)
 pressure: |x| < a:      p = p_u{Ā√(1−X²) − (λ/2) arctan √((m²−1)/(1−X²))},  X = x/a
           a ≤ |x| ≤ c:  p = −σ0  (= −p_u πλ/4)

Units: SI per unit length (gfmd_contact.core.conventions): F in N/m, a, c, R, x in m,
E*, σ0, p in Pa, w in J/m². p > 0 is compressive (the cohesive zone pulls:
p = −σ0 < 0). Validity: frictionless, a ≪ R, half-plane. λ → ∞ gives JKR
(jkr_cylinder), λ → 0 a DMT-like limit F → F_Hertz − 2√(2σ0wR).

Internally m = cosh t, so √(m²−1) = sinh t is computed without cancellation
when m → 1 (large λ).
"""

import math

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ._validate import finite, nonnegative, positive, scalar

_T_MAX = 350.0  # sinh(2t) overflows beyond t ≈ 355 (m = cosh t ≈ 1e152)


# --------------------------------------------------------------------------- scales
def units(radius, e_star, work):
    """Baney–Hui scales (ℓ [m], F_u [N/m], p_u [Pa]) = (2(wR²/(πE*))^{1/3}, (πE*w²R)^{1/3}, (E*²w/(πR))^{1/3})."""
    R = float(positive("radius", radius))
    E = float(positive("e_star", e_star))
    w = float(positive("work", work))
    ell = 2.0 * np.cbrt(w * R**2 / (np.pi * E))
    F_u = np.cbrt(np.pi * E * w**2 * R)
    p_u = np.cbrt(E**2 * w / (np.pi * R))
    return float(ell), float(F_u), float(p_u)


def maugis_parameter(sigma0, radius, e_star, work):
    """Maugis parameter of the cylinder λ = 4σ0 (R/(π²E*²w))^{1/3} [-] (§4.2).

    `sigma0` Dugdale stress [Pa] > 0, `radius` R [m], `e_star` E* [Pa], `work` w [J/m²] > 0.
    """
    s0 = positive("sigma0", sigma0)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    w = positive("work", work)
    return scalar(4.0 * s0 * np.cbrt(R / (np.pi**2 * E**2 * w)))


def dugdale_from_cohesive_law(phi_n, delta_n):
    """Map the exponential CZ law (§4.0) to Dugdale parameters: (w, σ0) = (φn, φn/(e δn)).

    `phi_n` work of normal separation [J/m²], `delta_n` characteristic length [m].
    Returns (work [J/m²], sigma0 [Pa]); σ0 is the peak traction of the law.
    """
    phi = float(positive("phi_n", phi_n))
    dn = float(positive("delta_n", delta_n))
    return phi, phi / (math.e * dn)


def maugis_parameter_from_cohesive_law(phi_n, delta_n, radius, e_star):
    """λ = (4/e)(φn/δn)(R/(π²E*²φn))^{1/3} for the exponential CZ law mapped by w = φn, σ0 = φn/(eδn) (§4.2)."""
    w, s0 = dugdale_from_cohesive_law(phi_n, delta_n)
    return maugis_parameter(s0, radius, e_star, w)


# ------------------------------------------------------------ dimensionless solution
def _check_a_lam(a_bar, lam):
    A = float(positive("a_bar", a_bar))
    lm = float(positive("lam", lam))
    return A, lm


def _f1(t):
    """m√(m²−1) − ln(m + √(m²−1)) = sinh(2t)/2 − t (series for small t)."""
    if t < 1e-2:
        return 2.0 * t**3 / 3.0 + 2.0 * t**5 / 15.0 + 4.0 * t**7 / 315.0
    return 0.5 * math.sinh(2.0 * t) - t


def _f2(t):
    """√(m²−1) ln(m + √(m²−1)) − m ln m = t sinh t − cosh t ln cosh t."""
    log_cosh = t + math.log1p(math.exp(-2.0 * t)) - math.log(2.0)
    return t * math.sinh(t) - math.cosh(t) * log_cosh


def _lhs_i(t, A, lam):
    return 0.5 * lam * A**2 * _f1(t) + 0.5 * lam**2 * A * _f2(t)


def _solve_t(A, lam):
    """Root t > 0 of Eq. (i) with m = cosh t; the left side increases monotonically from 0."""
    hi = 1.0
    while _lhs_i(hi, A, lam) < 1.0:
        if hi >= _T_MAX:
            raise ValueError(
                f"Eq. (i) has no representable root for a_bar = {A!r}, lam = {lam!r} "
                "(cohesive zone too long relative to the contact; increase a_bar)"
            )
        hi = min(2.0 * hi, _T_MAX)
    return brentq(lambda t: _lhs_i(t, A, lam) - 1.0, 0.0, hi, xtol=1e-300, rtol=1e-15, maxiter=500)


def solve_m(a_bar, lam):
    """Solve Baney–Hui Eq. (i) for m = c/a ≥ 1 given Ā = a/ℓ > 0 and λ > 0 (scalars, §4.2).

    The left side of (i) is 0 at m = 1 and increases strictly with m, so the
    root is unique; it is bracketed and found with brentq.
    """
    A, lm = _check_a_lam(a_bar, lam)
    return math.cosh(_solve_t(A, lm))


def load_dimensionless(a_bar, lam):
    """F/F_u = Ā² − λĀ√(m²−1) (Eq. ii, §4.2) for Ā > 0, λ > 0 (scalars)."""
    A, lm = _check_a_lam(a_bar, lam)
    return A**2 - lm * A * math.sinh(_solve_t(A, lm))


def _limit_small_a(lam):
    """lim_{Ā→0} F/F_u = −λs0 with λs0²/2 + λ²s0 ln2/2 = 1 (s0 = c/ℓ at Ā → 0)."""
    b = 0.5 * lam**2 * math.log(2.0)
    s0 = (-b + math.sqrt(b * b + 2.0 * lam)) / lam
    return -lam * s0


def pull_off(lam, a_bar_min=1e-7, depth_tol=1e-9):
    """Pull-off under load control for Maugis parameter λ > 0: (F_min/F_u, Ā at pull-off) (§4.2).

    Following the contact branch from large Ā towards smaller loads, the
    contact jumps off at the first local minimum of F(Ā) (the one with the
    largest Ā), located on a log grid Ā ∈ [a_bar_min, 2] and refined with
    Brent's method. The branch ends at Ā → 0 with
    F/F_u → −λs0, λs0²/2 + λ²s0 ln 2/2 = 1. For small λ the interior minimum
    is vanishingly shallow (λ = 0.3: depth ~1e-15 F_u at Ā ~ 1e-7; λ = 0.4:
    ~2e-11 F_u at Ā ~ 1e-5): if it lies less than `depth_tol`·|F0| below that
    end value F0, or no minimum is found, the pull-off is reported as the end
    point (F0, 0.0) — "the minimum lies at a → 0" of §4.2.
    """
    lm = float(positive("lam", lam))
    a_bar_min = float(positive("a_bar_min", a_bar_min))
    depth_tol = float(nonnegative("depth_tol", depth_tol))
    if a_bar_min >= 0.1:
        raise ValueError(f"a_bar_min = {a_bar_min!r} must be < 0.1 (start of the search grid)")
    f_end = _limit_small_a(lm)
    grid = np.logspace(math.log10(a_bar_min), math.log10(2.0), 141)
    F = np.array([load_dimensionless(A, lm) for A in grid])
    minima = [j for j in range(1, len(grid) - 1) if F[j] < F[j - 1] and F[j] < F[j + 1]]
    if not minima:
        return f_end, 0.0
    j = minima[-1]
    res = minimize_scalar(
        lambda s: load_dimensionless(math.exp(s), lm),
        bracket=(math.log(grid[j - 1]), math.log(grid[j]), math.log(grid[j + 1])),
        method="brent",
        options={"xtol": 1e-10},
    )
    if res.fun > f_end - depth_tol * abs(f_end):
        return f_end, 0.0
    return float(res.fun), float(math.exp(res.x))


# -------------------------------------------------------------- dimensional wrappers
def load(half_width, radius, e_star, work, sigma0):
    """Line load F [N/m] at contact half-width a > 0 [m] (Eq. ii, §4.2); a may be an array."""
    a = positive("half_width", half_width)
    ell, F_u, _ = units(radius, e_star, work)
    lam = float(maugis_parameter(sigma0, radius, e_star, work))
    F = np.vectorize(lambda ai: load_dimensionless(ai / ell, lam), otypes=[float])(a)
    return scalar(F_u * F)


def cohesive_zone_edge(half_width, radius, e_star, work, sigma0):
    """Outer edge of the cohesive zone c = m a [m] for contact half-width a > 0 [m] (Eq. i, §4.2)."""
    a = positive("half_width", half_width)
    ell, _, _ = units(radius, e_star, work)
    lam = float(maugis_parameter(sigma0, radius, e_star, work))
    m = np.vectorize(lambda ai: solve_m(ai / ell, lam), otypes=[float])(a)
    return scalar(m * a)


def pressure(x, half_width, radius, e_star, work, sigma0):
    """Pressure p(x) [Pa] at contact half-width a > 0 [m] (§4.2); x [m] (array).

    p_u{Ā√(1−X²) − (λ/2) arctan √((m²−1)/(1−X²))} for |x| < a, −σ0 for
    a ≤ |x| ≤ c, 0 for |x| > c. p is continuous at |x| = a.
    """
    x = finite("x", x)
    a = float(positive("half_width", half_width))
    ell, _, p_u = units(radius, e_star, work)
    lam = float(maugis_parameter(sigma0, radius, e_star, work))
    A = a / ell
    t = _solve_t(A, lam)
    X = np.abs(x) / a
    p = np.zeros_like(X)
    inside = X < 1.0
    cohesive = (X >= 1.0) & (X <= math.cosh(t))
    root = np.sqrt(1.0 - X[inside] ** 2)
    p[inside] = p_u * (A * root - 0.5 * lam * np.arctan2(math.sinh(t), root))
    p[cohesive] = -float(sigma0)
    return scalar(p)


def pull_off_load(radius, e_star, work, sigma0):
    """Pull-off line load under load control F_min [N/m] (< 0) (§4.2); see `pull_off`."""
    _, F_u, _ = units(radius, e_star, work)
    lam = float(maugis_parameter(sigma0, radius, e_star, work))
    return F_u * pull_off(lam)[0]


def pull_off_half_width(radius, e_star, work, sigma0):
    """Contact half-width at pull-off under load control [m] (0.0 when the branch ends at a → 0) (§4.2)."""
    ell, _, _ = units(radius, e_star, work)
    lam = float(maugis_parameter(sigma0, radius, e_star, work))
    return ell * pull_off(lam)[1]
