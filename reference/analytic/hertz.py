"""Hertz line contact: rigid cylinder on an elastic half-plane (plane strain).

Implements shared/reference-formulas.md §2 (Johnson 1985, ch. 4):

    a² = 4FR/(πE*),   F = πE*a²/(4R),   p(x) = p0 √(1 − x²/a²),
    p0 = 2F/(πa) = E*a/(2R) = √(FE*/(πR)),
    δ_rel = (F/(πE*)) [2 ln(L/(πa)) + 1]      (periodic cell, §2.2).

Units: SI, per unit length out of plane (see gfmd_contact.core.conventions): F in N/m,
a, R, x, L in m, E* = E/(1−ν²) in Pa, pressures in Pa. Sign: p > 0 is
compressive. x is measured from the contact centre.
Validity: frictionless, small slopes (a ≪ R), half-plane, isolated contact
(a ≪ L for the periodic approach formula; its error scales like (a/L)²).
"""

import numpy as np

from ._validate import nonnegative, positive, finite, scalar


def half_width(load, radius, e_star):
    """Contact half-width a = √(4FR/(πE*)) [m] for line load `load` F ≥ 0 [N/m].

    §2.1. `radius` R [m], `e_star` E* [Pa] > 0.
    """
    F = nonnegative("load", load)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    return scalar(np.sqrt(4.0 * F * R / (np.pi * E)))


def load(half_width, radius, e_star):
    """Line load F = πE*a²/(4R) [N/m] for contact half-width a ≥ 0 [m] (§2.1)."""
    a = nonnegative("half_width", half_width)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    return scalar(np.pi * E * a**2 / (4.0 * R))


def peak_pressure(load, radius, e_star):
    """Peak (centre) pressure p0 = √(FE*/(πR)) [Pa] for line load F ≥ 0 [N/m] (§2.1)."""
    F = nonnegative("load", load)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    return scalar(np.sqrt(F * E / (np.pi * R)))


def pressure(x, load, radius, e_star):
    """Contact pressure p(x) = p0 √(1 − x²/a²) [Pa] for |x| < a, zero outside (§2.1).

    `x` [m] (array), measured from the contact centre; `load` F ≥ 0 [N/m].
    p > 0 is compressive.
    """
    x = finite("x", x)
    a = half_width(load, radius, e_star)
    p0 = peak_pressure(load, radius, e_star)
    if a == 0.0:
        return scalar(np.zeros_like(x))
    inside = np.abs(x) < a
    p = np.zeros_like(x)
    p[inside] = p0 * np.sqrt(1.0 - (x[inside] / a) ** 2)
    return scalar(p)


def approach_periodic(load, radius, e_star, period):
    """Tip penetration relative to the mean surface, δ_rel = ū_z − u_z(0) [m] (§2.2).

    δ_rel = (F/(πE*)) [2 ln(L/(πa)) + 1] for one Hertz contact per periodic cell
    of length `period` L [m] on a half-plane (mean displacement ū_z = 0 as in
    gfmd_contact.core.conventions). δ_rel > 0: the tip is pushed into the body. Requires
    a < L/2; accurate to O((a/L)²) (1e-5 relative at L = 100a).
    """
    L = positive("period", period)
    a = half_width(load, radius, e_star)
    if np.any(2.0 * np.asarray(a) >= L):
        raise ValueError(f"contact half-width a = {a!r} m must be < period/2 = {L / 2!r} m")
    F = nonnegative("load", load)
    E = positive("e_star", e_star)
    with np.errstate(divide="ignore", invalid="ignore"):
        d = F / (np.pi * E) * (2.0 * np.log(L / (np.pi * np.asarray(a))) + 1.0)
    d = np.where(F == 0.0, 0.0, d)  # F ln(1/a) -> 0 as F -> 0
    return scalar(d)
