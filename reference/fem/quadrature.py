"""Gauss–Legendre quadrature of the cohesive boundary term on the periodic top surface.

Units: SI (see `gfmd_contact.core.conventions`). The default FE boundary term uses nodal
(lumped) quadrature: the nodal force is f_i = W_i T(Δ_i) with W the FacetBasis
load-vector weights (`Cell.weights`: P1 l per node, P2 Simpson l/3 at
vertices, 2l/3 at facet midpoints), the same structure as GFMD's nodal forces.
This module provides the consistent alternative

    f = Bᵀ (w_g ∘ T(Δ_g)),   Δ_g = z_ind(x_g) − (B u_z)_g,

where B (n_g × n_s, sparse) evaluates the FE trace (P1: linear, P2: quadratic
Lagrange on vertex–midpoint–vertex facets) at the Gauss–Legendre points x_g of
every top facet and w_g (m) are the Gauss weights times the facet length. The
indenter z_ind(x_g) comes from the band-limited (Fourier) interpolant of the
nodal heights h (`fourier_evaluate`), the interpolant the solver already uses
for P2 midpoints (`solver.fourier_interpolate`).

Points per facet (`default_points_per_facet`): order + 2, i.e. 3 (P1) and 4 (P2).
Gauss with n points integrates polynomials of degree ≤ 2n − 1 exactly; a
linear law (T = k Δ) needs the mass-matrix integrand φ_i φ_j (degree 2·order),
so n ≥ order + 1 suffices for it; the extra point covers the nonlinearity of
T(Δ) and the non-polynomial (Fourier) z_ind. (The verification study
verification/test_fe_quadrature.py measures the effect of n.)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft
import scipy.sparse as sp


def default_points_per_facet(order):
    """Gauss points per top facet for element order 1 (P1) or 2 (P2): order + 2 (module docstring)."""
    return order + 2


def shape_functions(order, xi):
    """1-D Lagrange shape functions on a facet, local coordinate ξ ∈ [0, 1] (dimensionless).

    Returns an array (len(ξ), order + 1) whose columns belong to the facet's
    surface points in x order: P1 (left vertex, right vertex); P2 (left vertex,
    midpoint, right vertex).
    """
    xi = np.asarray(xi, dtype=float)
    if order == 1:
        return np.stack([1.0 - xi, xi], axis=-1)
    if order == 2:
        return np.stack([(1.0 - xi) * (1.0 - 2.0 * xi), 4.0 * xi * (1.0 - xi), xi * (2.0 * xi - 1.0)], axis=-1)
    raise ValueError(f"order = {order!r}: 1 (P1) or 2 (P2)")


@dataclass
class SurfaceQuadrature:
    """Gauss–Legendre rule on the periodic top surface.

    x: Gauss points (m), ascending in [−L/2, L/2); weights: w_g (m), sum = L;
    interpolation: B (scipy.sparse CSR, n_g × n_s), (B u)_g = FE trace of the
    surface-point values u at x_g (dimensionless entries).
    """

    x: np.ndarray
    weights: np.ndarray
    interpolation: sp.csr_matrix

    def integrate(self, values_at_points):
        """Σ_g w_g v_g for values at the Gauss points (units of v times m)."""
        return float(self.weights @ values_at_points)


def gauss_surface_quadrature(surface_x, length, order, points_per_facet=None):
    """Gauss rule on the top surface of an FE cell (see `SurfaceQuadrature`).

    surface_x: the surface points of the cell (m), ascending from −L/2, right
    edge excluded (`Cell.surface_x`): P1 the vertices, P2 vertices at even and
    facet midpoints at odd indices; length: period L (m); order: 1 or 2;
    points_per_facet: Gauss points per facet (default `default_points_per_facet`).
    Facets join consecutive vertices, the last one wraps to x_0 + L.
    """
    surface_x = np.asarray(surface_x, dtype=float)
    n_s = surface_x.size
    if order not in (1, 2):
        raise ValueError(f"order = {order!r}: 1 (P1) or 2 (P2)")
    if n_s % order:
        raise ValueError(f"{n_s} surface points cannot form P{order} facets (need a multiple of {order})")
    n = default_points_per_facet(order) if points_per_facet is None else int(points_per_facet)
    if n < 1:
        raise ValueError(f"points_per_facet = {points_per_facet!r}: at least 1")
    facets = n_s // order
    left = surface_x[::order]
    right = np.append(left[1:], left[0] + length)
    facet_length = right - left
    if np.any(facet_length <= 0):
        raise ValueError("surface_x must be ascending within one period")
    if order == 2:
        mid = surface_x[1::2]
        if not np.allclose(mid, 0.5 * (left + right), rtol=0, atol=1e-9 * length):
            raise ValueError("P2 surface points: odd points must be the facet midpoints")
    nodes, unit_weights = np.polynomial.legendre.leggauss(n)
    xi = 0.5 * (nodes + 1.0)  # [−1, 1] → [0, 1]
    phi = shape_functions(order, xi)  # (n, order + 1)
    x = (left[:, None] + xi[None, :] * facet_length[:, None]).ravel()
    weights = (0.5 * unit_weights[None, :] * facet_length[:, None]).ravel()
    rows = np.repeat(np.arange(facets * n), order + 1)
    local = np.arange(order + 1)
    cols = ((np.arange(facets)[:, None, None] * order + local[None, None, :]) % n_s)
    cols = np.broadcast_to(cols, (facets, n, order + 1)).ravel()
    values = np.broadcast_to(phi[None, :, :], (facets, n, order + 1)).ravel()
    matrix = sp.csr_matrix((values, (rows, cols)), shape=(facets * n, n_s))
    return SurfaceQuadrature(x=x, weights=weights, interpolation=matrix)


def fourier_evaluate(h, length, x, x0=None):
    """Band-limited (trigonometric) interpolant of periodic nodal values h (m) at arbitrary x (m).

    h: values at x_j = x0 + j L/N (default x0 = −L/2, the GFMD grid
    `gfmd_contact.core.surfaces.grid`); length: period L (m). The Nyquist mode (even N) is
    split evenly between ±q, i.e. it enters as a cosine: the same interpolant
    as `solver.fourier_interpolate`, which samples it on a finer grid.
    """
    h = np.asarray(h, dtype=float)
    n = h.size
    x0 = -0.5 * length if x0 is None else x0
    spec = scipy.fft.rfft(h) / n
    factor = np.full(spec.size, 2.0)
    factor[0] = 1.0
    if n % 2 == 0:
        factor[-1] = 1.0
    coeff = spec * factor
    q = 2.0 * np.pi * np.arange(spec.size) / length
    x = np.asarray(x, dtype=float)
    out = np.empty(x.shape)
    flat_x, flat_out = x.ravel(), out.reshape(-1)
    for start in range(0, flat_x.size, 4096):  # chunked: n_x × N/2 complex phases at a time
        phase = np.exp(1j * np.outer(flat_x[start:start + 4096] - x0, q))
        flat_out[start:start + 4096] = (phase @ coeff).real
    return out
