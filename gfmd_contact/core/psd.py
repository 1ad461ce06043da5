"""The periodic grid and the seed's Eq. 4 PSD shape, shared by profiles (gfmd_contact.core.surfaces) and
surfaces (gfmd_contact.core.surfaces_2d). Units: SI (see `gfmd_contact.core.conventions`)."""

from __future__ import annotations

import numpy as np


def grid(nodes, length):
    """Node positions x_j = (j − N/2)·L/N (m); x = 0 is node N/2."""
    return (np.arange(nodes) - nodes // 2) * (length / nodes)


def psd_self_affine(q, hurst, rolloff_wavelength, rollon_wavelength, length):
    """Unnormalised two-sided PSD shape C(q)/C(q_r) of seed Eq. 4 (dimensionless).

    1 for λr < 2π/q ≤ L, (q/q_r)^{−(1+2H)} for λs,H < 2π/q ≤ λr, 0 for
    2π/q < λs,H and at q = 0 (zero mean). Wavelengths in m, q in 1/m.
    """
    q = np.abs(np.asarray(q, dtype=float))
    q_r = 2 * np.pi / rolloff_wavelength
    q_s = 2 * np.pi / rollon_wavelength
    q_l = 2 * np.pi / length
    c = np.zeros_like(q)
    plateau = (q >= q_l * (1 - 1e-12)) & (q < q_r)
    power = (q >= q_r) & (q <= q_s * (1 + 1e-12))
    c[plateau] = 1.0
    c[power] = (q[power] / q_r) ** (-(1 + 2 * hurst))
    return c
