"""The surface stiffness of a free (unbounded, non-periodic) half-plane or half-space, by Hockney padding.

Units: SI (see `gfmd_contact.core.conventions`): compliances in m/Pa, stiffness in Pa/m, tension > 0 pulls
the surface up (u_z > 0). The N-node region (Nx × Ny on a surface) is embedded in a periodic cell of 2N
nodes per axis. Its circulant compliance holds the free body's exact nodal compliance g(x_i − x_j) of a
uniform traction on one node's segment / rectangle, sampled at the wrapped distances min(j, 2N − j)·l: for
two nodes of the region |i − j| ≤ N − 1, so the wrapped distance is the true one and the padded cell
reproduces the free body exactly on the region, provided no traction acts outside it (the
method's task). The stiffness the periodic solver uses on the padded cell is K_c(q) = 1/Ĝ_c(q),
Ĝ_c = rfft(g_c) (numpy's unnormalized forward transform, as `gfmd_contact.core.kernels`: t̂ = K û);
at long wavelengths it tends to the periodic E*|q|/2. The q = 0 entry is 0 (clamped by the solver,
⟨u⟩ = 0 on the padded cell): the equilibrium is then the free solution minus a uniform shift
Ĝ_c(0)·t̄ (`far_field_shift`).

Closed forms (uniform traction t on one node, E* the plane-strain contact modulus):
    1+1-D  u(x) = −(2/(π E*)) t ∫_{−l/2}^{l/2} ln|x − x'|/l dx'  (defined up to a constant: the log)
    2+1-D  u(x, y) = (1/(π E*)) t ∫∫_{rectangle} dA'/r  (Love's rectangle; → 0 far away)
"""

from __future__ import annotations

import numpy as np


def _log_integral(s, spacing):
    """s ln|s/l| − s (m), an antiderivative of ln|s/l|, 0 at s = 0."""
    s = np.asarray(s, float)
    nz = s != 0
    return np.where(nz, s * np.log(np.where(nz, np.abs(s), spacing) / spacing), 0.0) - s


def segment_compliance(x, spacing, contact_modulus):
    """u_z (m/Pa) at x (m) of unit tension on the segment |x'| ≤ l/2 of a free half-plane (plane strain),
    the constant chosen so that the log is of |x − x'|/l."""
    a = 0.5 * spacing
    integral = _log_integral(np.asarray(x) + a, spacing) - _log_integral(np.asarray(x) - a, spacing)
    return -2.0 / (np.pi * contact_modulus) * integral


def _love(x, y):
    """x asinh(y/|x|) + y asinh(x/|y|) (m): F with ∂²F/∂x∂y = 1/r (zero terms where a coordinate is 0)."""
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    out = np.zeros(x.shape)
    nx, ny = x != 0, y != 0
    out[nx] += x[nx] * np.arcsinh(y[nx] / np.abs(x[nx]))
    out[ny] += y[ny] * np.arcsinh(x[ny] / np.abs(y[ny]))
    return out


def rectangle_compliance(x, y, spacing_x, spacing_y, contact_modulus):
    """u_z (m/Pa) at (x, y) (m) of unit tension on the rectangle |x'| ≤ lx/2, |y'| ≤ ly/2 of a free
    half-space: (1/(π E*)) ∫∫ dA'/r, Love's closed form."""
    a, b = 0.5 * spacing_x, 0.5 * spacing_y
    x, y = np.asarray(x, float), np.asarray(y, float)
    integral = _love(x + a, y + b) - _love(x - a, y + b) - _love(x + a, y - b) + _love(x - a, y - b)
    return integral / (np.pi * contact_modulus)


def wrapped_distances(nodes, spacing):
    """min(j, 2N − j)·l (m), j = 0 … 2N − 1: the distances of the padded cell's circulant."""
    j = np.arange(2 * nodes)
    return np.minimum(j, 2 * nodes - j) * spacing


def padded_compliance(grid, spacings, contact_modulus):
    """g_c (m/Pa) on the padded grid (2N,) or (2Nx, 2Ny) of the region grid (N,) or (Nx, Ny): the free body's nodal
    compliance at wrapped distances."""
    if len(grid) == 1:
        return segment_compliance(wrapped_distances(grid[0], spacings[0]), spacings[0], contact_modulus)
    dx = wrapped_distances(grid[0], spacings[0])[:, None]
    dy = wrapped_distances(grid[1], spacings[1])[None, :]
    return rectangle_compliance(dx, dy, spacings[0], spacings[1], contact_modulus)


def padded_spectrum(grid, spacings, contact_modulus):
    """Ĝ_c (m/Pa) on the padded rfft (1+1-D) / rfft2 (2+1-D) half-spectrum of the region grid: real, g_c is even."""
    g = padded_compliance(grid, spacings, contact_modulus)
    return np.real(np.fft.rfftn(g))


def padded_stiffness(grid, spacings, contact_modulus):
    """K_c(q) = 1/Ĝ_c(q) (Pa/m) on the padded half-spectrum of the region grid, 0 at q = 0 (the clamped mean).

    ValueError if a mode q ≠ 0 has Ĝ_c ≤ 0: the circulant would not be a compliance.
    """
    g_hat = padded_spectrum(grid, spacings, contact_modulus)
    rest = g_hat.ravel()[1:]
    if not np.all(rest > 0):
        raise ValueError(f"padded free-boundary compliance: {np.sum(rest <= 0)} modes q ≠ 0 with Ĝ_c ≤ 0 "
                         f"(min {rest.min():.3g} m/Pa) on the grid {tuple(grid)}")
    k = np.zeros_like(g_hat)
    k.ravel()[1:] = 1.0 / rest
    return k


def far_field_shift(grid, spacings, contact_modulus, mean_traction):
    """s = Ĝ_c(0)·t̄ (m): the uniform shift of the clamped padded solution from the free one, u_free = u + s on
    the region; t̄ (Pa) is the mean traction over the padded cell. 2+1-D: the free u is the displacement relative
    to the far field; 1+1-D: relative to the constant of `segment_compliance` (the free half-plane's u is defined
    up to a constant)."""
    g = padded_compliance(grid, spacings, contact_modulus)
    return float(np.sum(g)) * mean_traction


def padded_grid(region):
    """The padded grid (2N,) or (2Nx, 2Ny) of a region grid."""
    return tuple(2 * n for n in region)


def segment_cross_compliance(x, spacing, contact_modulus, coupling):
    """u_x (m/Pa) at x (m) of unit normal tension on the segment |x'| ≤ l/2 of a free half-plane, = u_z of unit
    tangential traction there with the opposite sign: (β/E*) ∫ sgn(x − x') dx', β = (1 − 2ν)/(2(1 − ν)) (Johnson
    §2.2: a compressive line load P moves the surface towards it, u_x = −(β/E*) P sgn(x))."""
    x = np.asarray(x, float)
    return coupling / contact_modulus * np.clip(x, -0.5 * spacing, 0.5 * spacing) * 2.0


def padded_coupled_stiffness(nodes, spacing, contact_modulus, coupling):
    """(K_xx, K_xz, K_zz) (Pa/m) on the padded rfft half-spectrum of a 1+1-D region of N nodes: the inverse of the
    free half-plane's 2×2 circulant compliance, G_xx = G_zz = `segment_compliance`, G_xz = −G_zx = the odd
    `segment_cross_compliance` at the signed wrapped distance (0 at the distance N l, which no two nodes of the region
    are apart). K_xz is imaginary (K_zx = conj K_xz), zero at the Nyquist mode; q = 0 entries 0 (clamped).
    ValueError where the compliance is not positive definite at a mode q ≠ 0."""
    j = np.arange(2 * nodes)
    signed = np.where(j < nodes, j, j - 2 * nodes) * spacing
    g_zz = np.real(np.fft.rfft(segment_compliance(np.abs(signed), spacing, contact_modulus)))
    odd = segment_cross_compliance(signed, spacing, contact_modulus, coupling)
    odd[nodes] = 0.0  # the distance N l: either sign; 0 keeps the sequence odd
    g_xz = np.fft.rfft(odd)
    g_xz = 1j * np.imag(g_xz)  # an odd real sequence: imaginary up to round-off
    g_xz[-1] = 0.0  # Nyquist: real fields stay real
    det = g_zz**2 - np.abs(g_xz) ** 2
    if not np.all(det[1:] > 0) or not np.all(g_zz[1:] > 0):
        raise ValueError(f"padded free-boundary coupled compliance not positive definite on {nodes} nodes")
    k_xx, k_xz, k_zz = (np.zeros(g_zz.shape, complex) for _ in range(3))
    k_xx[1:] = g_zz[1:] / det[1:]
    k_zz[1:] = k_xx[1:]
    k_xz[1:] = -g_xz[1:] / det[1:]
    return k_xx, k_xz, k_zz


def padded_wavenumbers(grid, spacings):
    """q (1/m) of the padded half-spectrum: |q| of `gfmd_contact.core.kernels` on the padded grid and length."""
    from .kernels import wavenumbers, wavevector_magnitudes

    if len(grid) == 1:
        return wavenumbers(grid[0], grid[0] * spacings[0])
    return wavevector_magnitudes(grid[0], grid[0] * spacings[0], grid[1], grid[1] * spacings[1])
