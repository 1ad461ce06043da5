"""JKR sphere: rigid paraboloid of radius R on an elastic half-space with adhesion (2+1-D).

Johnson, Kendall & Roberts (1971), Proc. R. Soc. A 324, 301; Johnson (1985),
Contact Mechanics, §5.5, eqs. (5.59)–(5.60); Maugis (2000), Contact, Adhesion
and Rupture of Elastic Solids, ch. 5:

    P(a) = 4E*a³/(3R) − √(8πwE*a³),         δ(a) = a²/R − √(2πwa/E*),
    a³(P) = (3R/(4E*)) [P + 3πwR + √(6πwRP + (3πwR)²)]      (branch stable under load control),
    p(r) = (2E*a/(πR)) √(1 − r²/a²) − √(2wE*/(πa)) / √(1 − r²/a²)        (r < a),
    K_I = √(2E*w)  (G = K_I²/(2E*) = w at the contact edge).

Pull-off (extrema of the δ–P curve, Maugis 2000 §5.3):
  load control (min of P):          P_c = −(3/2)πwR, a_c = (9πwR²/(8E*))^{1/3}, δ_c = −a_c²/(3R);
  displacement control (min of δ):  δ_d = −3a_d²/R,  a_d = (πwR²/(8E*))^{1/3} = a_c/9^{1/3},
                                    P_d = −(5/6)πwR.
Jump-in (contact formation on approach) is NOT defined in JKR: the adhesive
forces have zero range, so nothing acts before the surfaces touch at δ = 0;
the zero-range limit then snaps from a = 0 to the stable branch at δ = 0,
a³ = 2πwR²/E*, but the real jump-in distance depends on the range of the
forces (use maugis_dugdale_sphere or the cohesive law itself).

Tabor (1977) parameter μ = (Rw²/(E*²z0³))^{1/3} (z0: equilibrium spacing /
range of the forces); JKR applies for μ ≫ 1 (λ ≈ 1.16μ of Maugis–Dugdale ≫ 1).

Units: SI. P in N, a, r, R, δ in m, E* = E/(1−ν²) and p in Pa, w in J/m².
p > 0 is compressive (adhesive tension p < 0); δ > 0 pushes the sphere into
the body (δ < 0: the body is pulled up). Validity: frictionless, a ≪ R,
half-space, isolated contact (a ≪ period), cohesive zone ≪ a. w = 0 is Hertz.
"""

import math

import numpy as np
from scipy.optimize import brentq

from ._validate import finite, nonnegative, positive, scalar

#: A load (approach) within PULL_OFF_ROUNDING·|P_c| of P_c (·|δ_d| of δ_d) is the pull-off point, not a
#: value beyond it: `load(a_c)` and −(3/2)πwR round independently. With u = ε/2 and a cube root c·u off
#: (c = 1…4 by numpy's SIMD target), P_H(a_c) = |P_c| carries (3c + 4)u, √(8πwE*a_c³) = 2|P_c| carries
#: (1.5c + 3)u, the difference one more u: (6c + 11)u ≤ 17.5 ε for c = 4; the approach at a_d
#: (a²/R = |δ_d|/3, √ term (4/3)|δ_d|) stays below that. 32 ε bounds both.
PULL_OFF_ROUNDING = 32 * np.finfo(float).eps


def load(contact_radius, radius, e_star, work):
    """Load P = 4E*a³/(3R) − √(8πwE*a³) [N] at contact radius a ≥ 0 [m] (Johnson eq. 5.59).

    `radius` R [m], `e_star` E* [Pa] > 0, `work` w [J/m²] ≥ 0.
    """
    a = nonnegative("contact_radius", contact_radius)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    w = nonnegative("work", work)
    return scalar(4.0 * E * a**3 / (3.0 * R) - np.sqrt(8.0 * np.pi * w * E * a**3))


def approach(contact_radius, radius, e_star, work):
    """Approach δ = a²/R − √(2πwa/E*) [m] at contact radius a ≥ 0 [m] (Johnson eq. 5.60)."""
    a = nonnegative("contact_radius", contact_radius)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    w = nonnegative("work", work)
    return scalar(a**2 / R - np.sqrt(2.0 * np.pi * w * a / E))


def contact_radius(load, radius, e_star, work):
    """Contact radius a [m] on the branch stable under load control, for load P ≥ −(3/2)πwR [N] (JKR 1971).

    a³ = (3R/(4E*))[P + 3πwR + √(6πwRP + (3πwR)²)]. A load below the pull-off
    load −(3/2)πwR raises ValueError (the sphere has pulled off); one within
    round-off of it (`PULL_OFF_ROUNDING`) gives a_c. With work = 0 this is
    Hertz (P ≥ 0).
    """
    P = finite("load", load)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    w = nonnegative("work", work)
    P_c = -1.5 * np.pi * w * R
    if np.any(P < P_c - PULL_OFF_ROUNDING * np.abs(P_c)):
        raise ValueError(f"load = {load!r} N is below the pull-off load {scalar(P_c)!r} N: no contact")
    s = 3.0 * np.pi * w * R
    root = np.sqrt(np.clip(6.0 * np.pi * w * R * P + s**2, 0.0, None))  # clip: round-off at P = P_c
    return scalar(np.cbrt(3.0 * R / (4.0 * E) * (P + s + root)))


def contact_radius_from_approach(approach, radius, e_star, work):
    """Contact radius a [m] on the branch stable under displacement control (a ≥ a_d), for scalar δ [m].

    Inverse of `approach` for δ ≥ δ_d (the displacement-control pull-off);
    a smaller δ raises ValueError, one within round-off of δ_d (`PULL_OFF_ROUNDING`)
    gives a_d. Solved with brentq on [a_d, ∞).
    """
    d = float(finite("approach", approach))
    R = float(positive("radius", radius))
    E = float(positive("e_star", e_star))
    w = float(nonnegative("work", work))
    if w == 0.0:
        if d < 0.0:
            raise ValueError(f"approach = {d!r} m < 0 has no contact without adhesion (work = 0)")
        return math.sqrt(R * d)
    d_d, _, a_d = pull_off_displacement_control(R, E, w)
    if d < d_d - PULL_OFF_ROUNDING * abs(d_d):
        raise ValueError(f"approach = {d!r} m is below the displacement-control pull-off {d_d!r} m: no contact")

    def residual(a):
        return a * a / R - math.sqrt(2.0 * math.pi * w * a / E) - d

    if d <= d_d or residual(a_d) >= 0.0:  # δ within round-off of δ_d
        return a_d
    hi = 2.0 * a_d
    while residual(hi) < 0.0:
        hi *= 2.0
    return brentq(residual, a_d, hi, xtol=1e-15 * hi, rtol=4 * np.finfo(float).eps)


def pressure(r, contact_radius, radius, e_star, work):
    """Contact pressure p(r) [Pa] at contact radius a > 0 [m] (Johnson eq. 5.56 with 5.59); r [m] (array).

    p = (2E*a/(πR))√(1 − r²/a²) − √(2wE*/(πa))/√(1 − r²/a²) for r < a, 0 for
    r ≥ a (the −1/√ edge singularity is integrable; the value at r = a is not
    evaluated). p > 0 is compressive.
    """
    r = np.abs(finite("r", r))
    a = float(positive("contact_radius", contact_radius))
    R = float(positive("radius", radius))
    E = float(positive("e_star", e_star))
    w = float(nonnegative("work", work))
    p = np.zeros_like(r)
    inside = r < a
    s = np.sqrt(1.0 - (r[inside] / a) ** 2)
    p[inside] = 2.0 * E * a / (np.pi * R) * s - math.sqrt(2.0 * w * E / (np.pi * a)) / s
    return scalar(p)


def stress_intensity_factor(contact_radius, radius, e_star, work):
    """Mode-I stress-intensity factor at the contact edge K_I = (P_H − P)/(2a√(πa)) [Pa·√m].

    P_H = 4E*a³/(3R) is the Hertz load at the same a. Equals √(2E*w) for every
    a > 0 (Griffith balance G = w). `contact_radius` a > 0 [m].
    """
    a = positive("contact_radius", contact_radius)
    P_H = 4.0 * positive("e_star", e_star) * a**3 / (3.0 * positive("radius", radius))
    return scalar((P_H - load(a, radius, e_star, work)) / (2.0 * a * np.sqrt(np.pi * a)))


def pull_off_load_control(radius, e_star, work):
    """Pull-off under load control (min of P(a)): (P_c [N], δ_c [m], a_c [m]) (Maugis 2000 §5.3).

    P_c = −(3/2)πwR, a_c = (9πwR²/(8E*))^{1/3}, δ_c = −a_c²/(3R).
    """
    R = float(positive("radius", radius))
    E = float(positive("e_star", e_star))
    w = float(nonnegative("work", work))
    a_c = float(np.cbrt(9.0 * math.pi * w * R**2 / (8.0 * E)))
    return -1.5 * math.pi * w * R, -(a_c**2) / (3.0 * R), a_c


def pull_off_displacement_control(radius, e_star, work):
    """Pull-off under displacement control (min of δ(a)): (δ_d [m], P_d [N], a_d [m]) (Maugis 2000 §5.3).

    a_d = (πwR²/(8E*))^{1/3}, δ_d = −3a_d²/R, P_d = −(5/6)πwR: the other
    extremum of the JKR δ–P curve (where dδ/da = 0; beyond it the contact is
    unstable even at fixed grips).
    """
    R = float(positive("radius", radius))
    E = float(positive("e_star", e_star))
    w = float(nonnegative("work", work))
    a_d = float(np.cbrt(math.pi * w * R**2 / (8.0 * E)))
    return -3.0 * a_d**2 / R, -5.0 / 6.0 * math.pi * w * R, a_d


def tabor_parameter(radius, e_star, work, range_z0):
    """Tabor parameter μ = (Rw²/(E*²z0³))^{1/3} [-] (Tabor 1977); JKR for μ ≫ 1, DMT for μ ≪ 1.

    `range_z0` z0 [m] > 0: the range of the surface forces (equilibrium spacing).
    """
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    w = nonnegative("work", work)
    z0 = positive("range_z0", range_z0)
    return scalar(np.cbrt(R * w**2 / (E**2 * z0**3)))
