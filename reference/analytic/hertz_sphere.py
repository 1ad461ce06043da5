"""Hertz sphere: rigid paraboloid of radius R on an elastic half-space (2+1-D, no adhesion).

Johnson (1985), Contact Mechanics, §4.2, eqs. (4.22)–(4.23) (Hertz 1882):

    a³ = 3PR/(4E*),   δ = a²/R = (9P²/(16RE*²))^{1/3},   P = (4/3)E* R^{1/2} δ^{3/2},
    p(r) = p0 √(1 − r²/a²),   p0 = 3P/(2πa²) = (6PE*²/(π³R²))^{1/3} = 2E*a/(πR).

Periodic square array of spheres (period L, one sphere per L × L cell, the
setting of a 2+1-D GFMD/FE cell with the "sphere" scene), derived here:

    p̄ = P/(Lx Ly)                                              (mean pressure)
    δ_rel = a²/R + (P/(πE*L)) [Z(½) + (a/L)² Z(3/2)/10] + O((a²/R)(a/L)⁵),
    Z(s) = Σ'_{(m,n)≠0} (m² + n²)^{−s} = 4ζ(s)β(s):  Z(½) = −3.9002649…, Z(3/2) = 9.0336217…

δ_rel is the tip penetration relative to the mean surface displacement of the
half-space (the q = 0 mode carries no stiffness, as in 1+1-D §2.2). By Poisson
summation it is δ plus the isolated contact's surface displacement
u(r) = P/(πE*r)[1 + a²/(10r²) + O(a⁴/r⁴)] (Johnson eq. 3.42b expanded) summed
over the image contacts r = L(m, n) ≠ 0; Z is the Epstein zeta function of the
square lattice (ζ: Riemann, β: Dirichlet beta), Z(½) its analytic continuation
(the image sum of 1/r less the mean). a(P) and p(r) carry relative errors
O((a/L)³): only the curvature of the images' field at the contact acts on them.

Units: SI. P in N, a, r, R, δ, L in m, E* = E/(1−ν²) and p in Pa. p > 0 is
compressive; δ > 0 pushes the sphere into the body; r is measured from the
contact centre. Validity: frictionless, small slopes (a ≪ R), half-space,
isolated contact (a ≪ L).
"""

import numpy as np

from ._validate import finite, nonnegative, positive, scalar

#: Z(½) = 4ζ(½)β(½), Epstein zeta of the unit square lattice at s = ½ (analytic continuation);
#: ζ(½) = −1.4603545088095868, β(½) = 0.6676914571896092 (checked with mpmath in the tests)
EPSTEIN_SQUARE_HALF = -3.90026492000196
#: Z(3/2) = 4ζ(3/2)β(3/2) = Σ'(m² + n²)^{−3/2} (convergent; checked with mpmath in the tests)
EPSTEIN_SQUARE_THREE_HALVES = 9.03362168310095


def contact_radius(load, radius, e_star):
    """Contact radius a = (3PR/(4E*))^{1/3} [m] for load `load` P ≥ 0 [N] (Johnson eq. 4.22).

    `radius` R [m] > 0, `e_star` E* [Pa] > 0.
    """
    P = nonnegative("load", load)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    return scalar(np.cbrt(3.0 * P * R / (4.0 * E)))


def load_from_contact_radius(contact_radius, radius, e_star):
    """Load P = 4E*a³/(3R) [N] for contact radius a ≥ 0 [m] (Johnson eq. 4.22)."""
    a = nonnegative("contact_radius", contact_radius)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    return scalar(4.0 * E * a**3 / (3.0 * R))


def approach(load, radius, e_star):
    """Approach (indentation) δ = a²/R = (9P²/(16RE*²))^{1/3} [m] of an isolated contact (Johnson eq. 4.23).

    `load` P ≥ 0 [N]; δ is measured against the undeformed surface far away.
    """
    a = contact_radius(load, radius, e_star)
    R = positive("radius", radius)
    return scalar(np.asarray(a) ** 2 / R)


def load_from_approach(approach, radius, e_star):
    """Load P = (4/3)E* R^{1/2} δ^{3/2} [N] for approach δ ≥ 0 [m] (Johnson eq. 4.23)."""
    d = nonnegative("approach", approach)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    return scalar(4.0 / 3.0 * E * np.sqrt(R) * d**1.5)


def peak_pressure(load, radius, e_star):
    """Centre pressure p0 = 3P/(2πa²) = (6PE*²/(π³R²))^{1/3} [Pa] for load P ≥ 0 [N] (Johnson eq. 4.22)."""
    P = nonnegative("load", load)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    return scalar(np.cbrt(6.0 * P * E**2 / (np.pi**3 * R**2)))


def pressure(r, load, radius, e_star):
    """Contact pressure p(r) = p0 √(1 − r²/a²) [Pa] for r < a, zero outside (Johnson eq. 4.22).

    `r` [m] (array) distance from the contact centre (a negative r is taken as |r|);
    `load` P ≥ 0 [N] (scalar). p > 0 is compressive.
    """
    r = np.abs(finite("r", r))
    a = float(np.asarray(contact_radius(load, radius, e_star)))
    p0 = float(np.asarray(peak_pressure(load, radius, e_star)))
    p = np.zeros_like(r)
    if a == 0.0:
        return scalar(p)
    inside = r < a
    p[inside] = p0 * np.sqrt(1.0 - (r[inside] / a) ** 2)
    return scalar(p)


def mean_pressure(load, length_x, length_y):
    """Mean pressure p̄ = P/(Lx Ly) [Pa] of a periodic array, one sphere of load P ≥ 0 [N] per cell.

    `length_x` Lx, `length_y` Ly [m] > 0: the periodic cell.
    """
    P = nonnegative("load", load)
    Lx = positive("length_x", length_x)
    Ly = positive("length_y", length_y)
    return scalar(P / (Lx * Ly))


def load_from_mean_pressure(mean_pressure, length_x, length_y):
    """Load per sphere P = p̄ Lx Ly [N] for mean pressure p̄ ≥ 0 [Pa] on an Lx × Ly cell [m]."""
    p = nonnegative("mean_pressure", mean_pressure)
    Lx = positive("length_x", length_x)
    Ly = positive("length_y", length_y)
    return scalar(p * Lx * Ly)


def approach_periodic(load, radius, e_star, period):
    """Tip penetration relative to the mean surface, square cell (module doc) [m]:

    δ_rel = a²/R + (P/(πE*L))[Z(½) + (a/L)² Z(3/2)/10]. `load` P ≥ 0 [N] per
    sphere, `period` L [m] of the square L × L cell. Requires 2a < L; the
    remainder is O((a²/R)(a/L)⁵) (tests: against the image sum in Fourier
    space). A rectangular cell needs the Epstein zeta of the rectangular
    lattice: not implemented.
    """
    L = positive("period", period)
    a = contact_radius(load, radius, e_star)
    if np.any(2.0 * np.asarray(a) >= L):
        raise ValueError(f"contact radius a = {a!r} m must be < period/2 = {float(L) / 2!r} m")
    P = nonnegative("load", load)
    R = positive("radius", radius)
    E = positive("e_star", e_star)
    images = EPSTEIN_SQUARE_HALF + (np.asarray(a) / L) ** 2 * EPSTEIN_SQUARE_THREE_HALVES / 10.0
    return scalar(np.asarray(a) ** 2 / R + images * P / (np.pi * E * L))


def contact_fraction(load, radius, e_star, length_x, length_y):
    """Contact area fraction a_rel = πa²/(Lx Ly) [-] of the periodic array for load P ≥ 0 [N] per sphere."""
    a = contact_radius(load, radius, e_star)
    Lx = positive("length_x", length_x)
    Ly = positive("length_y", length_y)
    return scalar(np.pi * np.asarray(a) ** 2 / (Lx * Ly))
