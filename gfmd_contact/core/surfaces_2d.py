"""Rigid indenter surfaces h(x, y) on the periodic Nx × Ny grid (m), 2+1-D.

Units: SI (see `gfmd_contact.core.conventions`). Axis 0 is x, axis 1 is y. Node (i, j) sits at (i lx, j ly),
lx = Lx/Nx, ly = Ly/Ny (the 2+1-D contract); the positions written with a result (`positions`, Result.x
and Result.y) are those of a profile, `gfmd_contact.core.surfaces.grid` along each axis, ((i − Nx/2) lx, (j − Ny/2) ly),
the same nodes shifted by half a cell, so the centre (Lx/2, Ly/2) is (0, 0) as x = 0 is node N/2 of a
profile. Heights follow the
sign convention of 1+1-D (reference-formulas §0): the same `indenter_surface`, first contact at the
minimum of h.

Random surfaces are isotropic and self-affine with the seed's Eq. 4 bands (plateau from the longest wave of
the cell to λr, power law to λs,H, nothing above): the areal PSD shape C^iso(|q|)/C(q_r) of
`gfmd_contact.core.psd.psd_self_affine` (dimension 2) at |q| = (q_x² + q_y²)^½, ∝ |q|^−2(1+H) in the
self-affine band, so that a line scan has the seed's profile exponent −(1+2H) and H is the Hurst
exponent of the heights (Jacobs, Junge & Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017)); the
1-D exponent read radially would give line scans of Hurst exponent H − ½. Deterministic amplitudes √C, random
phases from the explicit seed that are Hermitian-symmetric by construction (the phases of the rfft2 of
white noise drawn with numpy's default_rng(seed)), zero mean (q = 0 empty), the Nyquist lines empty
(as the 1-D Nyquist mode), and h_rms exact over the surface after a final rescaling.
"""

from __future__ import annotations

import numpy as np
import scipy.fft

from .psd import grid, psd_self_affine


def positions(nodes_x, length_x, nodes_y, length_y):
    """(x, y): node coordinates (m) along each axis, shapes (Nx,), (Ny,); node (i, j) at (x_i, y_j)."""
    return grid(nodes_x, length_x), grid(nodes_y, length_y)


def self_affine(nodes_x, length_x, nodes_y, length_y, hurst, h_rms, rolloff_wavelength, rollon_wavelength, seed):
    """Random isotropic self-affine surface (m), shape (Nx, Ny): C^iso(|q|) ∝ |q|^−2(1+H) in seed Eq. 4's
    bands, exact h_rms (module docstring).

    The plateau starts at the longest wave of the cell, 2π/max(Lx, Ly). Equal arguments give identical
    surfaces.
    """
    qx = 2 * np.pi * np.fft.fftfreq(nodes_x, d=length_x / nodes_x)
    qy = 2 * np.pi * np.fft.rfftfreq(nodes_y, d=length_y / nodes_y)
    q = np.hypot(qx[:, None], qy[None, :])
    amplitude = np.sqrt(psd_self_affine(q, hurst, rolloff_wavelength, rollon_wavelength, max(length_x, length_y),
                                        dimension=2))
    if nodes_x % 2 == 0:
        amplitude[nodes_x // 2, :] = 0.0
    if nodes_y % 2 == 0:
        amplitude[:, -1] = 0.0
    noise = scipy.fft.rfftn(np.random.default_rng(seed).standard_normal((nodes_x, nodes_y)), axes=(0, 1))
    magnitude = np.abs(noise)
    phase = np.divide(noise, magnitude, out=np.ones_like(noise), where=magnitude > 0)
    h = scipy.fft.irfftn(amplitude * phase, s=(nodes_x, nodes_y), axes=(0, 1))
    rms = np.sqrt(np.mean(h**2))
    if rms == 0.0:
        raise ValueError("self-affine spectrum has no modes on this grid: check the wavelengths against L and N")
    return h * (h_rms / rms)


def embedded_sinusoid(nodes_x, length_x, nodes_y, amplitude):
    """The 1-D sinusoid h = −a cos(2πx/Lx) (the operations of `gfmd_contact.core.surfaces.sinusoid`, so bit-equal),
    constant along y: shape (Nx, Ny)."""
    line = -amplitude * np.cos(2 * np.pi * grid(nodes_x, length_x) / length_x)
    return np.repeat(line[:, None], nodes_y, axis=1)


def egg_box(nodes_x, length_x, nodes_y, length_y, amplitude):
    """h_ij = a cos(2πi/Nx) cos(2πj/Ny) (m): the contract's a cos(2πx/Lx) cos(2πy/Ly) with node (i, j) at
    (i lx, j ly); one period per cell each way, crests at nodes (0, 0) and (Nx/2, Ny/2), troughs (first
    contact) at (Nx/2, 0) and (0, Ny/2). (Even Nx, Ny: the same as a cos(2πx/Lx) cos(2πy/Ly) on the
    centred positions of `positions`.) `length_x`, `length_y` set only the period, the cell itself."""
    i, j = np.arange(nodes_x), np.arange(nodes_y)
    return amplitude * np.outer(np.cos(2 * np.pi * i / nodes_x), np.cos(2 * np.pi * j / nodes_y))


def sphere(nodes_x, length_x, nodes_y, length_y, radius):
    """Paraboloid h = (x² + y²)/(2R) (m) centred at (0, 0), node (Nx/2, Ny/2); the 2+1-D kin of the cylinder."""
    x, y = positions(nodes_x, length_x, nodes_y, length_y)
    return (x[:, None] ** 2 + y[None, :] ** 2) / (2 * radius)


def profile_2d(surface, realization=0):
    """Heights h (m) of shape (Nx, Ny) for a 2+1-D `gfmd_contact.core.scene.Surface`; realization i uses seed + i."""
    nx, lx, ny, ly = surface.nodes, surface.length, surface.nodes_y, surface.length_y
    kind = surface.kind
    if kind == "self-affine":
        return self_affine(nx, lx, ny, ly, surface.hurst, surface.h_rms, surface.rolloff_wavelength,
                           surface.rollon_wavelength, surface.seed + realization)
    if kind == "sinusoid":
        return embedded_sinusoid(nx, lx, ny, surface.amplitude)
    if kind == "egg-box":
        return egg_box(nx, lx, ny, ly, surface.amplitude)
    if kind == "sphere":
        return sphere(nx, lx, ny, ly, surface.radius)
    if kind == "flat":
        return np.zeros((nx, ny))
    if kind == "file":  # read, prepared and turned to face the body (gfmd_contact.core.topography_prep)
        from .topography_prep import indenter_heights
        return indenter_heights(surface)
    raise ValueError(f"surface.kind = {kind!r} is not a 2+1-D surface kind")
