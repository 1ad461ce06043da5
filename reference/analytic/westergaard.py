"""Westergaard: rigid periodic sinusoid on an elastic half-plane, no adhesion.

Implements shared/reference-formulas.md §3 (Westergaard 1939; Johnson 1995
eq. 4). Indenter z_ind(x) = −d + h0[1 − cos(2πx/λ)], h0 = amplitude
(peak-to-valley 2h0), period λ; contact |x| < a in every period,
ψ = πx/λ, ψ_a = πa/λ, P = p̄/p*:

    p* = πE*h0/λ,   p̄ = p* sin²ψ_a,
    p(x) = 2p* cos ψ √(sin²ψ_a − sin²ψ)         (|x| < a),
    p(x) = p̄ + p* cos(2πx/λ)                     (full contact, p̄ ≥ p*),
    g(x) = 2h0[S√(S² − S_a²) − S_a² ln((S + √(S² − S_a²))/S_a)],  S = |sin ψ|,
    ḡ = h0[1 − P + P ln P],   U = λ h0 p* P²(¼ − ½ ln P).

Units: SI per unit length (gfmd_contact.core.conventions): h0, λ, a, x, gaps in m; E*,
p̄, p in Pa; U in J/m. p > 0 is compressive; p̄ = F/λ is the mean pressure.
x is measured from the centre of a contact (minimum of the profile); x may
lie in any period. Validity: frictionless hard wall, small slopes
(h0 ≪ λ), half-plane (mean displacement ū_z = 0).
"""

import numpy as np

from ._validate import finite, in_range, nonnegative, positive, scalar


def _wrap(x, wavelength):
    """Map x onto the period centred on the contact, [−λ/2, λ/2]."""
    return x - wavelength * np.round(x / wavelength)


def full_contact_pressure(h0, wavelength, e_star):
    """Mean pressure for full contact p* = πE*h0/λ [Pa] (§3); h0 = amplitude [m]."""
    h0 = positive("h0", h0)
    lam = positive("wavelength", wavelength)
    E = positive("e_star", e_star)
    return scalar(np.pi * E * h0 / lam)


def mean_pressure(half_width, h0, wavelength, e_star):
    """Mean pressure p̄ = p* sin²(πa/λ) [Pa] for contact half-width 0 ≤ a ≤ λ/2 [m] (§3)."""
    lam = positive("wavelength", wavelength)
    a = in_range("half_width", half_width, 0.0, float(lam) / 2.0)
    ps = full_contact_pressure(h0, lam, e_star)
    return scalar(ps * np.sin(np.pi * a / lam) ** 2)


def half_width(mean_pressure, h0, wavelength, e_star):
    """Contact half-width a = (λ/π) arcsin √(p̄/p*) [m] for mean pressure p̄ ≥ 0 [Pa] (§3).

    Returns λ/2 (full contact) for p̄ ≥ p*.
    """
    pbar = nonnegative("mean_pressure", mean_pressure)
    lam = positive("wavelength", wavelength)
    ps = full_contact_pressure(h0, lam, e_star)
    P = np.minimum(pbar / ps, 1.0)
    return scalar(np.where(P >= 1.0, lam / 2.0, lam / np.pi * np.arcsin(np.sqrt(P))))


def pressure(x, mean_pressure, h0, wavelength, e_star):
    """Contact pressure p(x) [Pa] at scalar mean pressure p̄ ≥ 0 [Pa] (§3), any x [m] (periodic).

    Partial contact (p̄ < p*): 2p* cos ψ √(sin²ψ_a − sin²ψ) for |x| < a, else 0.
    Full contact (p̄ ≥ p*): p̄ + p* cos(2πx/λ). p > 0 is compressive.
    """
    x = finite("x", x)
    pbar = float(nonnegative("mean_pressure", mean_pressure))
    lam = positive("wavelength", wavelength)
    ps = full_contact_pressure(h0, lam, e_star)
    psi = np.pi * _wrap(x, lam) / lam
    if pbar >= ps:
        return scalar(pbar + ps * np.cos(2.0 * psi))
    sa2 = pbar / ps  # sin²ψ_a
    root = np.sqrt(np.clip(sa2 - np.sin(psi) ** 2, 0.0, None))
    return scalar(2.0 * ps * np.cos(psi) * root)


def gap(x, mean_pressure, h0, wavelength, e_star):
    """Gap g(x) = z_ind − u_z ≥ 0 [m] at scalar mean pressure p̄ ≥ 0 [Pa] (§3), any x [m].

    Zero inside the contact (and everywhere in full contact);
    2h0[S√(S² − S_a²) − S_a² ln((S + √(S² − S_a²))/S_a)] outside, S = |sin(πx/λ)|.
    """
    x = finite("x", x)
    pbar = float(nonnegative("mean_pressure", mean_pressure))
    lam = positive("wavelength", wavelength)
    h0 = positive("h0", h0)
    ps = full_contact_pressure(h0, lam, e_star)
    S = np.abs(np.sin(np.pi * _wrap(x, lam) / lam))
    if pbar >= ps:
        return scalar(np.zeros_like(S))
    sa2 = pbar / ps
    if sa2 == 0.0:
        return scalar(2.0 * h0 * S**2)  # no load: undeformed profile
    sa = np.sqrt(sa2)
    outside = S > sa
    Sc = np.where(outside, S, sa)
    root = np.sqrt(np.clip(Sc**2 - sa2, 0.0, None))  # clip: round-off at S ≈ S_a
    g = 2.0 * h0 * (Sc * root - sa2 * np.log((Sc + root) / sa))
    return scalar(np.where(outside, g, 0.0))


def mean_gap(mean_pressure, h0, wavelength, e_star):
    """Mean gap ḡ = h0[1 − P + P ln P] [m], P = p̄/p*, for p̄ ≥ 0 [Pa] (§3); 0 for P ≥ 1."""
    pbar = nonnegative("mean_pressure", mean_pressure)
    h0 = positive("h0", h0)
    ps = full_contact_pressure(h0, wavelength, e_star)
    P = np.minimum(pbar / ps, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        plogp = np.where(P > 0.0, P * np.log(np.where(P > 0.0, P, 1.0)), 0.0)
    return scalar(h0 * (1.0 - P + plogp))


def elastic_energy(mean_pressure, h0, wavelength, e_star):
    """Elastic energy per period U = λ h0 p* P²(¼ − ½ ln P) [J/m], P = min(p̄/p*, 1) (§3).

    Energy of the non-uniform part of the deformation (half-plane, q = 0 mode
    carries no energy), so U stays at λ h0 p*/4 in full contact.
    """
    pbar = nonnegative("mean_pressure", mean_pressure)
    h0 = positive("h0", h0)
    lam = positive("wavelength", wavelength)
    ps = full_contact_pressure(h0, lam, e_star)
    P = np.minimum(pbar / ps, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        logp = np.log(np.where(P > 0.0, P, 1.0))
    return scalar(lam * h0 * ps * P**2 * (0.25 - 0.5 * logp))
