"""Egg-box wavy surface on an elastic half-space, no adhesion: Johnson, Greenwood & Higginson (1985).

Johnson, Greenwood & Higginson (1985), "The contact of elastic regular wavy
surfaces", Int. J. Mech. Sci. 27, 383 (JGH). JGH write the surface as
z = Δ[1 − cos(2πx/λ) cos(2πy/λ)]; implemented here is the same surface in the
form of the project's "egg-box" scene (SPEC2D), h(x, y) = Δ cos(2πx/λ) cos(2πy/λ)
on a square λ × λ cell (Δ = `amplitude`, peak-to-valley 2Δ): the heights differ
by a constant and a sign flip that only chooses which side the indenter is on.
Per cell there are two peaks, (0, 0) and (λ/2, λ/2), and two valleys,
(λ/2, 0) and (0, λ/2); the peaks form a square lattice of spacing λ/√2.

Complete contact (JGH): the full-contact pressure is p̄ + p* cos(2πx/λ)cos(2πy/λ)
(the two plane waves of |q| = 2√2π/λ, pressure E*|q|Δ/2 each), so contact is
complete for p̄ ≥
    p* = √2 π E* Δ/λ.                                                    (JGH1)
Small loads (JGH: Hertz at each peak): peak radius R = λ²/(4π²Δ), load per peak
P = p̄λ²/2, contact radius a³ = 3PR/(4E*), two contacts per cell:
    a_rel = 2πa²/λ² = π (3/(8π))^{2/3} (p̄/p*)^{2/3}.                       (JGH2)
Near complete contact (JGH: the non-contact holes at the valleys as
penny-shaped cracks under the full-contact tension p̄ − p* + p*k²r²/2, k = 2π/λ,
that close smoothly, K_I = 0 ⇒ ∫₀^b (p* − p̄ − p*k²r²/2) r dr/√(b² − r²) = 0):
    b² = 3(p* − p̄)/(p*k²),   1 − a_rel = 2πb²/λ² = (3/(2π))(1 − p̄/p*).  (JGH3)
Both asymptotes are re-derived here (the JGH paper text was not available to
this implementation; the constants agree with those usually quoted from it).
The curve between (JGH: numerical) is NOT implemented.

Interaction correction of the small-load asymptote (derived here, not JGH):
the other contacts' displacement adds curvature at a peak, 1/R_eff = 1/R +
P S/(2πE*), S = Σ'|r_j|^{−3} over the peak lattice = 2√2 Z(3/2)/λ³ (Z(3/2) as
in hertz_sphere); a_eff = a (R_eff/R)^{1/3}. It is O((a/λ)³) relative.

Units: SI. Δ, λ, a, b in m; E*, p̄, p* in Pa. p̄ > 0 is compressive.
Validity: frictionless, small slopes (Δ ≪ λ), half-space; (JGH2) for
a ≪ λ/(2√2) (half the peak spacing), (JGH3) for 1 − p̄/p* ≪ 1.
"""

import math

import numpy as np

from ._validate import finite, nonnegative, positive, scalar
from .hertz_sphere import EPSTEIN_SQUARE_THREE_HALVES

#: a_rel = SMALL_LOAD_PREFACTOR (p̄/p*)^{2/3} (JGH2)
SMALL_LOAD_PREFACTOR = math.pi * (3.0 / (8.0 * math.pi)) ** (2.0 / 3.0)
#: 1 − a_rel = NEAR_FULL_SLOPE (1 − p̄/p*) (JGH3)
NEAR_FULL_SLOPE = 3.0 / (2.0 * math.pi)


def full_contact_pressure(amplitude, wavelength, e_star):
    """p* = √2 π E* Δ/λ [Pa] (JGH1): smallest mean pressure of complete contact.

    `amplitude` Δ [m] > 0, `wavelength` λ [m] > 0 (square cell), `e_star` E* [Pa] > 0.
    """
    D = positive("amplitude", amplitude)
    lam = positive("wavelength", wavelength)
    E = positive("e_star", e_star)
    return scalar(math.sqrt(2.0) * np.pi * E * D / lam)


def full_contact_pressure_field(x, y, mean_pressure, amplitude, wavelength, e_star):
    """Pressure in complete contact p = p̄ + p* cos(2πx/λ)cos(2πy/λ) [Pa] for p̄ ≥ p* (JGH1).

    `x`, `y` [m] (arrays, broadcast); `mean_pressure` p̄ [Pa] ≥ p*, else ValueError.
    """
    x, y = finite("x", x), finite("y", y)
    pbar = float(nonnegative("mean_pressure", mean_pressure))
    lam = float(positive("wavelength", wavelength))
    ps = float(full_contact_pressure(amplitude, lam, e_star))
    if pbar < ps:
        raise ValueError(f"mean_pressure = {pbar!r} Pa < p* = {ps!r} Pa: contact is not complete")
    k = 2.0 * np.pi / lam
    return scalar(pbar + ps * np.cos(k * x) * np.cos(k * y))


def peak_radius(amplitude, wavelength):
    """Radius of curvature of a peak R = λ²/(4π²Δ) [m]; `amplitude` Δ, `wavelength` λ [m] > 0."""
    D = positive("amplitude", amplitude)
    lam = positive("wavelength", wavelength)
    return scalar(lam**2 / (4.0 * np.pi**2 * D))


def contact_fraction_small_load(mean_pressure, amplitude, wavelength, e_star):
    """Hertz asymptote a_rel = π(3/(8π))^{2/3}(p̄/p*)^{2/3} [-] (JGH2); `mean_pressure` p̄ ≥ 0 [Pa]."""
    pbar = nonnegative("mean_pressure", mean_pressure)
    ps = full_contact_pressure(amplitude, wavelength, e_star)
    return scalar(SMALL_LOAD_PREFACTOR * (pbar / ps) ** (2.0 / 3.0))


def contact_fraction_small_load_interacting(mean_pressure, amplitude, wavelength, e_star):
    """Hertz asymptote with the neighbours' curvature (module doc, derived here) a_rel [-].

    a_rel = (JGH2)·(R_eff/R)^{2/3}, 1/R_eff = 1/R + P S/(2πE*), P = p̄λ²/2,
    S = 2√2 Z(3/2)/λ³. `mean_pressure` p̄ ≥ 0 [Pa].
    """
    pbar = nonnegative("mean_pressure", mean_pressure)
    lam = positive("wavelength", wavelength)
    E = positive("e_star", e_star)
    R = peak_radius(amplitude, lam)
    S = 2.0 * math.sqrt(2.0) * EPSTEIN_SQUARE_THREE_HALVES / lam**3
    ratio = 1.0 / (1.0 + R * pbar * lam**2 / 2.0 * S / (2.0 * np.pi * E))  # R_eff/R
    return scalar(contact_fraction_small_load(pbar, amplitude, lam, E) * ratio ** (2.0 / 3.0))


def contact_fraction_near_full(mean_pressure, amplitude, wavelength, e_star):
    """Near-complete-contact asymptote a_rel = 1 − (3/(2π))(1 − p̄/p*) [-] (JGH3); 1 for p̄ ≥ p*.

    `mean_pressure` p̄ ≥ 0 [Pa].
    """
    pbar = nonnegative("mean_pressure", mean_pressure)
    ps = full_contact_pressure(amplitude, wavelength, e_star)
    return scalar(1.0 - NEAR_FULL_SLOPE * (1.0 - np.minimum(pbar / ps, 1.0)))


def hole_radius(mean_pressure, amplitude, wavelength, e_star):
    """Radius of each non-contact hole b = √(3(p* − p̄)/(p*k²)) [m], k = 2π/λ (JGH3); 0 for p̄ ≥ p*."""
    pbar = nonnegative("mean_pressure", mean_pressure)
    lam = positive("wavelength", wavelength)
    ps = full_contact_pressure(amplitude, lam, e_star)
    k = 2.0 * np.pi / lam
    return scalar(np.sqrt(3.0 * np.clip(ps - pbar, 0.0, None) / (ps * k**2)))
