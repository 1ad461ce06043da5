"""Adhesive periodic sinusoid, JKR type: Johnson (1995), Int. J. Solids Struct. 32, 423.

Implements shared/reference-formulas.md §4.3. Indenter as in westergaard:
z_ind(x) = −d + h0[1 − cos(2πx/λ)] (h0 = amplitude), contact |x| < a per
period, ψ = πx/λ, ψ_a = πa/λ, p* = πE*h0/λ (westergaard.full_contact_pressure):

    α = √(2wλ/(π²h0²E*))                                   (Johnson parameter)
    p̄/p* = sin²ψ_a − α√(tan ψ_a)
    p(x) = 2p* cos ψ √(sin²ψ_a − sin²ψ) − p*α√(tan ψ_a) cos ψ/√(sin²ψ_a − sin²ψ)
    ḡ = h0[cos²ψ_a + 2(p̄/p*) ln sin ψ_a]
    K_I = p*α√λ = √(2E*w)   (so G = K_I²/(2E*) = w)

Load control: dp̄/dψ_a = 0 ⇔ 4 sin^{3/2}ψ_a cos^{5/2}ψ_a = α. For
α < α_max = 4(3/8)^{3/4}(5/8)^{5/4} ≈ 1.065 this has two roots: the minimum
of p̄ (pull-off, smaller a) and the maximum (jump to full contact). The jump
load is zero at ψ_a = π/3, i.e. α_c = 3^{3/4}/4 ≈ 0.5699 (derived here from the
two conditions; Johnson 1995 quotes 0.57): for α ≥ α_c full contact is reached
spontaneously at zero load.

Units: SI per unit length (gfmd_contact.core.conventions): h0, λ, a, x, gaps in m; E*,
p̄, p in Pa; w in J/m². p > 0 is compressive; x is measured from the centre
of a contact (any period). Validity: frictionless, h0 ≪ λ, half-plane,
cohesive-zone length πE*w/(4σ0²) ≪ a (JKR limit). Full contact (a = λ/2) is
not described by these formulas: use westergaard.pressure(p̄ ≥ p*) — adhesion
does not change the full-contact field.
"""

import math

import numpy as np
from scipy.optimize import brentq

from ._validate import finite, in_range, nonnegative, positive, scalar
from .westergaard import full_contact_pressure

#: largest α for which p̄(a) has a minimum and a maximum (partial contact can be stable)
ALPHA_MAX = 4.0 * (3.0 / 8.0) ** 0.75 * (5.0 / 8.0) ** 1.25
_PSI_M = math.atan(math.sqrt(3.0 / 5.0))  # maximum of 4 sin^{3/2} cos^{5/2}


def johnson_alpha(work, h0, wavelength, e_star):
    """Johnson parameter α = √(2wλ/(π²h0²E*)) [-] (§4.3); w [J/m²] ≥ 0, h0 (amplitude) and λ [m]."""
    w = nonnegative("work", work)
    h0 = positive("h0", h0)
    lam = positive("wavelength", wavelength)
    E = positive("e_star", e_star)
    return scalar(np.sqrt(2.0 * w * lam / (np.pi**2 * h0**2 * E)))


def _ratio(psi_a, alpha):
    """p̄/p* = sin²ψ_a − α√(tan ψ_a)."""
    return np.sin(psi_a) ** 2 - alpha * np.sqrt(np.tan(psi_a))


def mean_pressure(half_width, h0, wavelength, e_star, work):
    """Mean pressure p̄ = p*[sin²ψ_a − α√(tan ψ_a)] [Pa] for 0 ≤ a < λ/2 [m] (§4.3)."""
    lam = float(positive("wavelength", wavelength))
    a = in_range("half_width", half_width, 0.0, lam / 2.0, upper_open=True)
    ps = full_contact_pressure(h0, lam, e_star)
    alpha = johnson_alpha(work, h0, lam, e_star)
    return scalar(ps * _ratio(np.pi * a / lam, alpha))


def pressure(x, half_width, h0, wavelength, e_star, work):
    """Contact pressure p(x) [Pa] at half-width 0 < a < λ/2 [m] (§4.3); x [m] (array, periodic).

    Westergaard term minus Koiter's periodic flat-punch term (inverse-square-root
    edges); 0 outside the contact. The value at |x| = a exactly is not evaluated
    (0 is returned there).
    """
    x = finite("x", x)
    lam = float(positive("wavelength", wavelength))
    a = float(in_range("half_width", half_width, 0.0, lam / 2.0, lower_open=True, upper_open=True))
    ps = full_contact_pressure(h0, lam, e_star)
    alpha = johnson_alpha(work, h0, lam, e_star)
    psi = np.pi * (x - lam * np.round(x / lam)) / lam
    psi_a = np.pi * a / lam
    inside = np.abs(psi) < psi_a
    c = np.cos(psi[inside])
    root = np.sqrt(np.sin(psi_a) ** 2 - np.sin(psi[inside]) ** 2)
    p = np.zeros_like(psi)
    p[inside] = 2.0 * ps * c * root - ps * alpha * np.sqrt(np.tan(psi_a)) * c / root
    return scalar(p)


def mean_gap(half_width, h0, wavelength, e_star, work):
    """Mean gap ḡ = h0[cos²ψ_a + 2(p̄/p*) ln sin ψ_a] [m] for 0 < a < λ/2 [m] (§4.3)."""
    lam = float(positive("wavelength", wavelength))
    a = in_range("half_width", half_width, 0.0, lam / 2.0, lower_open=True, upper_open=True)
    h0 = positive("h0", h0)
    alpha = johnson_alpha(work, h0, lam, e_star)
    psi_a = np.pi * a / lam
    return scalar(h0 * (np.cos(psi_a) ** 2 + 2.0 * _ratio(psi_a, alpha) * np.log(np.sin(psi_a))))


def _extremum_psi(alpha, which):
    a = float(positive("alpha", alpha))
    if a >= ALPHA_MAX:
        raise ValueError(
            f"alpha = {a!r} >= {ALPHA_MAX:.6f}: p̄(a) decreases monotonically, "
            "no stable partial contact (no pull-off / jump point)"
        )

    def g(psi):
        return 4.0 * math.sin(psi) ** 1.5 * math.cos(psi) ** 2.5 - a

    lo, hi = (0.0, _PSI_M) if which == "min" else (_PSI_M, math.pi / 2.0)
    return brentq(g, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)


def pull_off(alpha):
    """Pull-off under load control: (p̄/p*, a/λ) at the minimum of p̄(a) (§4.3); 0 < α < ALPHA_MAX.

    Table of §4.3, e.g. α = 0.3 → (−0.0959, 0.059).
    """
    psi = _extremum_psi(alpha, "min")
    return float(_ratio(psi, float(alpha))), psi / math.pi


def jump_to_contact(alpha):
    """Jump to full contact under load control: (p̄/p*, a/λ) at the maximum of p̄(a) (§4.3).

    0 < α < ALPHA_MAX; e.g. α = 0.3 → (+0.388, 0.379). The jump load is < 0 for
    α > critical_alpha().
    """
    psi = _extremum_psi(alpha, "max")
    return float(_ratio(psi, float(alpha))), psi / math.pi


def critical_alpha():
    """α_c = 3^{3/4}/4 ≈ 0.5699: smallest α with spontaneous full contact at p̄ = 0 (§4.3).

    From p̄ = 0 and dp̄/dψ_a = 0: sin²ψ_a = 4 sin²ψ_a cos²ψ_a ⇒ ψ_a = π/3.
    """
    return 3.0**0.75 / 4.0


def half_width(mean_pressure, h0, wavelength, e_star, work):
    """Contact half-width a [m] on the branch stable under load control for scalar mean pressure p̄ [Pa] (§4.3).

    The stable branch is dp̄/da > 0, between pull-off and jump to full contact;
    p̄ outside [p̄_pull-off, p̄_jump] raises ValueError (no stable partial contact).
    With work = 0 this is the Westergaard inverse (0 ≤ p̄ < p*).
    """
    pbar = float(finite("mean_pressure", mean_pressure))
    lam = float(positive("wavelength", wavelength))
    ps = float(full_contact_pressure(h0, lam, e_star))
    alpha = float(johnson_alpha(work, h0, lam, e_star))
    P = pbar / ps
    if alpha == 0.0:
        if not 0.0 <= P < 1.0:
            raise ValueError(f"mean_pressure/p* = {P!r} outside [0, 1) for partial contact without adhesion")
        return lam / math.pi * math.asin(math.sqrt(P))
    psi_lo = _extremum_psi(alpha, "min")
    psi_hi = _extremum_psi(alpha, "max")
    P_lo, P_hi = _ratio(psi_lo, alpha), _ratio(psi_hi, alpha)
    tol = 1e-12  # round-off of p̄/p* at the end points is accepted as the end point
    if not P_lo - tol <= P <= P_hi + tol:
        raise ValueError(
            f"mean_pressure/p* = {P!r} outside the stable range [{P_lo:.6g}, {P_hi:.6g}] "
            f"for alpha = {alpha:.6g} (below: pull-off; above: full contact)"
        )
    if P <= P_lo:
        return lam * psi_lo / math.pi
    if P >= P_hi:
        return lam * psi_hi / math.pi
    psi = brentq(lambda s: _ratio(s, alpha) - P, psi_lo, psi_hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    return lam * psi / math.pi
