"""The indenter on the FE surface: the profile between the nodes and z_ind at every surface point.

Units: SI (see `gfmd_contact.core.conventions`). P2 has surface points at the facet
midpoints; h there is the band-limited (Fourier) interpolant of the nodal heights.
"""

from __future__ import annotations

import numpy as np
import scipy.fft


def fourier_interpolate(h, factor):
    """Band-limited interpolant of periodic nodal values h on a grid `factor` times finer."""
    n = h.size
    if factor == 1:
        return h.copy()
    spec = scipy.fft.rfft(h)
    if n % 2 == 0:
        spec[-1] *= 0.5  # split the Nyquist mode between ±q
    return scipy.fft.irfft(spec, n * factor) * factor


def surface_indenter(h_surface, h_min, initial_separation, displacement):
    """z_ind = h − min h + δ0 − U (m, gfmd_contact.core.conventions) at every FE surface point.

    h_surface: the profile at the surface points (Fourier interpolant of the nodal h);
    h_min: the *nodal* minimum of h (m), so that z_ind at the vertices is exactly GFMD's.
    Written here from the convention, not taken from `gfmd_contact.core.loading` (the FE is an
    independent check).
    """
    return np.asarray(h_surface, dtype=float) - h_min + initial_separation - displacement
