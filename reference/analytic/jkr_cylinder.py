"""JKR line contact: rigid cylinder on an elastic half-plane with adhesion.

Implements shared/reference-formulas.md §4.1 (Barquins 1988; Chaudhury et
al. 1996; λ → ∞ limit of Baney & Hui 1997):

    F = F_H − √(2πE*wa),          F_H = πE*a²/(4R)  (Hertz load at the same a),
    p(x) = (E*/(2R)) √(a² − x²) − (F_H − F)/(π √(a² − x²))      (|x| < a),
    K_I = (F_H − F)/√(πa),        G = K_I²/(2E*) = w,
    pull-off (load control): a_c = (2wR²/(πE*))^{1/3},
                             F_c = −3(πE*w²R/16)^{1/3} = −(3/4)πE*a_c²/R.

Units: SI per unit length (gfmd_contact.core.conventions): F in N/m, a, R, x in m,
E* = E/(1−ν²) and p in Pa, work of adhesion w in J/m². p > 0 is compressive
(adhesive tension is p < 0); x is measured from the contact centre.
Validity: frictionless, a ≪ R, half-plane, cohesive-zone length
d ≈ πE*w/(4σ0²) ≪ a (otherwise use maugis_dugdale). w = 0 gives Hertz.
"""

import numpy as np
from scipy.optimize import brentq

from ._validate import finite, nonnegative, positive, scalar


#: |F − F_c| ≤ PULL_OFF_ROUNDING·|F_c| is round-off, not a load below pull-off: `load(a_c)` and
#: `pull_off_load` round independently (two cube roots, each 1–4 ulp by numpy's SIMD target, a square
#: root and ~15 products). To first order, with u = ε/2 and a cube root c·u off,
#: |load(a_c) − F_c|/|F_c| ≤ (1/3)·err(F_H) + (4/3)·err(√) + u + err(F_c) ≈ (13 + 2.4 c)·u, as F_H = |F_c|/3
#: and √(2πE*wa_c) = (4/3)|F_c| at a_c: 8 ε for c = 1, 10 ε for c = 4; 16 ε bounds both. The half-width
#: a load F_c(1 − 16 ε) would imply lies within √(32 ε) a_c ≈ 8e-8 a_c of a_c (F − F_c = ½|F_c|(Δa/a_c)²).
PULL_OFF_ROUNDING = 16 * np.finfo(float).eps


def load(half_width, radius, e_star, work):
    """Line load F = πE*a²/(4R) − √(2πE*wa) [N/m] at contact half-width a ≥ 0 [m] (§4.1)."""
    a = nonnegative("half_width", half_width)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    w = nonnegative("work", work)
    return scalar(_load(a, R, E, w))


def _load(a, R, E, w):
    return np.pi * E * a**2 / (4.0 * R) - np.sqrt(2.0 * np.pi * E * w * a)


def pull_off_half_width(radius, e_star, work):
    """Half-width at pull-off under load control a_c = (2wR²/(πE*))^{1/3} [m] (§4.1)."""
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    w = nonnegative("work", work)
    return scalar(np.cbrt(2.0 * w * R**2 / (np.pi * E)))


def pull_off_load(radius, e_star, work):
    """Pull-off load under load control F_c = −3(πE*w²R/16)^{1/3} [N/m] (< 0, tensile) (§4.1)."""
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    w = nonnegative("work", work)
    return scalar(-3.0 * np.cbrt(np.pi * E * w**2 * R / 16.0))


def half_width(load, radius, e_star, work):
    """Contact half-width a [m] on the stable branch (a ≥ a_c) for scalar line load F [N/m] (§4.1).

    Inverse of `load` restricted to the branch that is stable under load
    control. Raises ValueError for F < F_c (the cylinder has pulled off); a load within round-off of
    F_c (`PULL_OFF_ROUNDING`) is F_c, and gives a_c.
    """
    F = float(finite("load", load))
    R = float(positive("radius", radius))
    E = float(positive("e_star", e_star))
    w = float(nonnegative("work", work))
    if w == 0.0:
        if F < 0.0:
            raise ValueError(f"load = {F!r} N/m < 0 has no contact without adhesion (work = 0)")
        return float(np.sqrt(4.0 * F * R / (np.pi * E)))
    a_c = pull_off_half_width(R, E, w)
    F_c = pull_off_load(R, E, w)
    if F < F_c - PULL_OFF_ROUNDING * abs(F_c):
        raise ValueError(f"load = {F!r} N/m is below the pull-off load {F_c!r} N/m: no contact")

    def residual(a):
        return _load(a, R, E, w) - F

    if F <= F_c or residual(a_c) >= 0.0:  # F at or within round-off of F_c = F(a_c): the pull-off point itself
        return a_c

    hi = 2.0 * a_c
    while residual(hi) < 0.0:
        hi *= 2.0
    return brentq(residual, a_c, hi, xtol=1e-15 * hi, rtol=4 * np.finfo(float).eps)


def stress_intensity_factor(half_width, radius, e_star, work):
    """Mode-I stress-intensity factor at the contact edge K_I = (F_H − F)/√(πa) [Pa·√m] (§4.1).

    Equals √(2E*w) for every a > 0, i.e. G = K_I²/(2E*) = w. The pressure
    near the edge behaves as p ≈ −K_I/√(2π(a − |x|)).
    """
    a = positive("half_width", half_width)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    F_H = np.pi * E * a**2 / (4.0 * R)
    F = _load(a, R, E, nonnegative("work", work))
    return scalar((F_H - F) / np.sqrt(np.pi * a))


def pressure(x, half_width, radius, e_star, work):
    """Contact pressure p(x) [Pa] at contact half-width a > 0 [m] (§4.1); x [m] (array).

    p = (E*/(2R))√(a² − x²) − (F_H − F)/(π√(a² − x²)) for |x| < a, 0 for |x| ≥ a.
    The adhesive term is an integrable −1/√ singularity at |x| → a (the value
    at |x| = a exactly is not evaluated; 0 is returned there).
    """
    x = finite("x", x)
    a = float(positive("half_width", half_width))
    R = float(positive("radius", radius))
    E = float(positive("e_star", e_star))
    F_H = np.pi * E * a**2 / (4.0 * R)
    F = _load(a, R, E, nonnegative("work", work))
    inside = np.abs(x) < a
    root = np.sqrt(a**2 - x[inside] ** 2)
    p = np.zeros_like(x)
    p[inside] = E / (2.0 * R) * root - (F_H - F) / (np.pi * root)
    return scalar(p)
