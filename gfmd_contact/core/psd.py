"""The periodic grid and the seed's Eq. 4 PSD shape, shared by profiles (gfmd_contact.core.surfaces) and
surfaces (gfmd_contact.core.surfaces_2d). Units: SI (see `gfmd_contact.core.conventions`).

Convention: a self-affine topography of Hurst exponent H has the profile PSD C¹ᴰ(q) ∝ q^{−(1+2H)} (seed
Eq. 4) and the isotropic areal PSD C^iso(|q|) ∝ |q|^{−2(1+H)}; a line scan of such a surface has the 1-D
exponent again (reference-formulas §6; Jacobs, Junge & Pastewka 2017, cited at `psd_self_affine`)."""

from __future__ import annotations

import numpy as np


def grid(nodes, length):
    """Node positions x_j = (j − N/2)·L/N (m); x = 0 is node N/2."""
    return (np.arange(nodes) - nodes // 2) * (length / nodes)


def psd_self_affine(q, hurst, rolloff_wavelength, rollon_wavelength, length, dimension=1):
    """Unnormalised two-sided PSD shape C(q)/C(q_r) of seed Eq. 4 (dimensionless), of a profile
    (`dimension` 1) or, at q = |q|, of an isotropic surface (`dimension` 2).

    1 for λr < 2π/q ≤ L, (q/q_r)^{−(d+2H)} for λs,H < 2π/q ≤ λr, 0 for
    2π/q < λs,H and at q = 0 (zero mean). Wavelengths in m, q in 1/m. The exponent is the seed's
    −(1+2H) for d = 1 and −2(1+H) for d = 2: a surface of Hurst exponent H whose line scans have the
    profile's spectrum q^{−(1+2H)} (Jacobs, Junge & Pastewka, "Quantitative characterization of surface
    topography using spectral analysis", Surf. Topogr.: Metrol. Prop. 5, 013001 (2017); Persson et al.,
    J. Phys.: Condens. Matter 17, R1 (2005)).
    """
    if dimension not in (1, 2):
        raise ValueError(f"dimension = {dimension!r}: a PSD shape is defined for profiles (1) and surfaces (2)")
    q = np.abs(np.asarray(q, dtype=float))
    q_r = 2 * np.pi / rolloff_wavelength
    q_s = 2 * np.pi / rollon_wavelength
    q_l = 2 * np.pi / length
    c = np.zeros_like(q)
    plateau = (q >= q_l * (1 - 1e-12)) & (q < q_r)
    power = (q >= q_r) & (q <= q_s * (1 + 1e-12))
    c[plateau] = 1.0
    c[power] = (q[power] / q_r) ** (-(dimension + 2 * hurst))
    return c
