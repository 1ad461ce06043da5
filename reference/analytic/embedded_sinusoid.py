"""The 1-D sinusoid embedded in 2+1-D: the 1+1-D results as 2-D mean quantities.

The 2+1-D "sinusoid" scene (SPEC2D) is h(x, y) = h0 cos(2πx/Lx), constant
along y, on an Lx × Ly cell. Every field is independent of y and the
plane-strain problem of westergaard (no adhesion, Westergaard 1939) and
jkr_sinusoid (adhesive, Johnson 1995) holds on every line y = const, so the
2-D means equal the 1-D ones (reference-formulas §3, §4.3):

    p̄_2D = p̄_1D,   a_rel = 2a/Lx,   ḡ_2D = ḡ_1D,   total load F_2D = p̄ Lx Ly.

These functions only rename and re-scale the 1+1-D ones so that verification
can ask for "the 2+1-D sinusoid" by name; they add no physics.

Units: SI. h0, Lx, Ly, gaps in m; E*, p̄ in Pa; w in J/m²; F in N.
Validity: as westergaard / jkr_sinusoid (frictionless, h0 ≪ Lx, half-space).
"""

import numpy as np

from . import jkr_sinusoid, westergaard
from ._validate import in_range, nonnegative, positive, scalar


def contact_fraction(mean_pressure, h0, length_x, e_star, work=0.0):
    """Contact area fraction a_rel = 2a/Lx [-] at mean pressure p̄ [Pa] (scalar).

    `h0` amplitude [m], `length_x` Lx = wavelength [m], `e_star` E* [Pa], `work`
    w [J/m²] ≥ 0. w = 0: Westergaard (1 for p̄ ≥ p*); w > 0: the load-control
    stable branch of jkr_sinusoid.half_width (ValueError outside it).
    """
    if float(nonnegative("work", work)) == 0.0:
        a = westergaard.half_width(mean_pressure, h0, length_x, e_star)
    else:
        a = jkr_sinusoid.half_width(mean_pressure, h0, length_x, e_star, work)
    return scalar(2.0 * np.asarray(a) / float(positive("length_x", length_x)))


def mean_pressure(contact_fraction, h0, length_x, e_star, work=0.0):
    """Mean pressure p̄ [Pa] at contact fraction 0 ≤ a_rel < 1 [-] (a_rel ≤ 1 for work = 0).

    Westergaard p* sin²(πa_rel/2) for w = 0, Johnson (1995) for `work` w > 0 [J/m²].
    `h0` [m], `length_x` Lx [m], `e_star` E* [Pa].
    """
    Lx = float(positive("length_x", length_x))
    w = float(nonnegative("work", work))
    a = in_range("contact_fraction", contact_fraction, 0.0, 1.0, upper_open=w > 0.0) * Lx / 2.0
    if w == 0.0:
        return westergaard.mean_pressure(a, h0, Lx, e_star)
    return jkr_sinusoid.mean_pressure(a, h0, Lx, e_star, w)


def mean_gap(mean_pressure, h0, length_x, e_star):
    """Mean gap ḡ = h0[1 − P + P ln P] [m], P = p̄/p*, without adhesion (Westergaard, §3).

    `mean_pressure` p̄ ≥ 0 [Pa], `h0` [m], `length_x` Lx [m], `e_star` E* [Pa].
    """
    return westergaard.mean_gap(mean_pressure, h0, length_x, e_star)


def full_contact_pressure(h0, length_x, e_star):
    """p* = πE*h0/Lx [Pa]: complete contact of the embedded sinusoid (as in 1+1-D, §3)."""
    return westergaard.full_contact_pressure(h0, length_x, e_star)


def total_load(mean_pressure, length_x, length_y):
    """Total normal load on the cell F = p̄ Lx Ly [N]; `mean_pressure` [Pa], `length_x`, `length_y` [m]."""
    return scalar(np.asarray(mean_pressure, dtype=float) * float(positive("length_x", length_x))
                  * float(positive("length_y", length_y)))
