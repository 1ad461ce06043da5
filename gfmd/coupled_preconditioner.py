"""The coupled Newton's two-level right preconditioner: K⁻¹ with a coarse space of block constants.

The Newton step solves A δu = f, A = K + D on the nodes (`gfmd.coupled_krylov.newton_step`): K the half-plane's
(or layer's) 2×2 stiffness on the modes, D the nodal 2×2 tangent of seed Eq. 2 (x, z rows and columns). Under K⁻¹
alone the spectrum of A K⁻¹ = I + D K⁻¹ spreads wherever the interface is stiff: the modes longer than the crossover
wavelength (K(q) = φn/δn²) on an adhered patch are held by D, not K, and GMRES spends a product on each such
outlier, more as the contact grows. Here, as for the NCG (`gfmd.cohesive_preconditioner`, its coarse space:
blocks of consecutive stiff nodes, here BLOCK_WAVELENGTHS crossover wavelengths wide, and one block per gap between
them, `cover`), Z holds those blocks' indicator functions for each component (2m columns), E = Zᵀ A Z (non-symmetric:
D is; an LU factor), Q = Z E⁻¹ Zᵀ, and the right preconditioner is

    M⁻¹ = Q + K⁻¹ (I − A Q),

so that A M⁻¹ Z = A Z: the coarse modes are solved exactly. Since K K⁻¹ = Π (the mean removal of a clamped
half-plane; I on a layer), M⁻¹ y = K⁻¹ (y − D w) with w = Π Z E⁻¹ Zᵀ y, and A M⁻¹ y = Π (g + D s) with
g = y − D w, s = K⁻¹ g: one FFT pair per product, as K⁻¹ alone. E from K's real-space kernels by double cumulative
sums (no FFT, `gfmd.coarse_kernels.block_sums`, as the NCG's). Measured on the Fig. 8 class at 2^13 (Newton
systems sampled along a whole ramp, GMRES products to 0.1 / 1e-2 / 1e-3): 18.9 / 27.2 / 36.0 with K⁻¹, 5.9 / 8.3 / 10.7 with the coarse space (half-wavelength
blocks), flat as the contact grows where K⁻¹'s grow 2 → 40; whole ramps: docs/design/performance.md.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from .coarse_kernels import block_sums
from .cohesive_preconditioner import cover, kernel_sums
from .coupled_kernels import coarse_passes

#: which right preconditioner the coupled Newton's GMRES runs (`gfmd.coupled_krylov.newton_step`): "two-level"
#: (this module) or "stiffness" (K⁻¹ on the spectrum, the earlier preconditioner)
CHOICE = "two-level"
#: a node is in the coarse space's stiff blocks where D_nn ≥ STIFF_FRACTION φn/δn² or D_tt ≥ STIFF_FRACTION 2φt/δt²
#: (the cohesive NCG's measured choice, `gfmd.cohesive_preconditioner.STIFF_FRACTION`)
STIFF_FRACTION = 0.01
#: a stiff run is cut into blocks of BLOCK_WAVELENGTHS crossover wavelengths (the NCG's: half of one). Measured on
#: whole Fig. 8 ramps (seed 2): at 2^13 16 500 FFT pairs, 12.4 CPU s with half a wavelength; 17 369 and 10.8 s with
#: one; 18 766 and 9.7 s with two; at 2^15 34.5 against 30.9 CPU s (half, one): E's LU (2m × 2m, m blocks) and the
#: coarse correction per product cost more than the FFT pairs narrower blocks save
BLOCK_WAVELENGTHS = 1.0


def stiffness_kernel_sums(stiff, fft):
    """The double cumulative sums of the real-space kernels of `stiff`'s operator blocks (a b; b̄ d) (its `mass`: K
    for the Newton's `Elastic(model, 0, 0)`, whose `inv_mass` is its inverse, as `operators` needs), the q = 0 mode
    dropped where clamped, one per (row, column) of components; cached on `stiff` (`gfmd.problem.stiffness_operator`:
    one per model, so once per task)."""
    cached = getattr(stiff, "_coarse_kernel_sums", None)
    if cached is not None:
        return cached
    a, b, d = stiff.mass
    n = fft.n
    sums = {}
    for key, block in (("xx", a), ("xz", b), ("zz", d)):
        kq = np.array(block, complex)
        if stiff.clamp:
            kq[0] = 0.0
        sums[key] = kernel_sums(fft.irfft(kq[None])[0], n)  # (K_key u)_i = Σ_j kr(i − j) u_j
    stiff._coarse_kernel_sums = sums
    return sums


class CoarseSpace:
    """Z (blocks over the first `size` nodes: `starts`, `widths`), the LU factor of E = Zᵀ A Z (A = K + D on
    zero-mean fields where clamped) and the coarse solve."""

    def __init__(self, size, starts, widths, factor, clamp, n):
        self.size, self.starts, self.widths, self.factor, self.clamp, self.n = size, starts, widths, factor, clamp, n
        self.m = starts.size

    def coefficients(self, sums):
        """c = E⁻¹ Zᵀ y (2, m) from the block sums Zᵀ y (2, m) of a nodal y (zero-mean rows where clamped, so
        Zᵀ Π y = Zᵀ y); w = Π Z c is the coarse correction."""
        return scipy.linalg.lu_solve(self.factor, sums.ravel(), check_finite=False).reshape(2, self.m)


def coarse_space(stiff, fft, tangent, scales):
    """The `CoarseSpace` of the stiff nodes at this tangent, or None (no stiff node, or E singular).

    tangent: (d_nn, d_nt, d_tn, d_tt) per node (Pa/m); scales: the law's (k_t, k_n) = (2φt/δt², φn/δn²), the
    stiff threshold's units and k_n the crossover K(q) = k_n that sets the block width."""
    d_nn, d_nt, d_tn, d_tt = (np.broadcast_to(np.asarray(x, float), (fft.n,)) for x in tangent)
    n, clamp = fft.n, stiff.clamp
    k_t, k_n = scales
    stiff_nodes = np.flatnonzero((d_nn >= STIFF_FRACTION * k_n) | (d_tt >= STIFF_FRACTION * k_t if k_t > 0 else False))
    if stiff_nodes.size == 0:
        return None
    k = np.abs(np.asarray(stiff.mass[2]))
    above = np.flatnonzero(k >= k_n)  # the crossover mode
    crossover = int(above[0]) if above.size else k.size
    nodes, starts = cover(stiff_nodes, n, max(1, int(round(BLOCK_WAVELENGTHS * n / max(crossover, 1)))))
    if clamp:  # Σ of all blocks = 1, which Π removes: the last block is the others' negative, dropped
        if starts.size < 2:
            return None
        nodes, starts = nodes[:starts[-1]], starts[:-1]
    ends = np.r_[starts[1:], nodes.size]
    a, p = nodes[starts], ends - starts  # nodes is 0 … size − 1 (`cover`)
    m = a.size
    k_part = _stiffness_part(stiff, fft, a, p)
    d_blocks = ((d_tt, d_tn), (d_nt, d_nn))  # rows and columns (x, z), as `coupled_kernels.tangent_times`
    e = np.empty((2 * m, 2 * m))
    width = p.astype(float)
    for row in range(2):
        for col in range(2):
            block = k_part[row * m:(row + 1) * m, col * m:(col + 1) * m].copy()
            mass = np.add.reduceat(d_blocks[row][col][nodes], starts)  # Zᵀ D Z: diagonal, D is nodal
            block[np.diag_indices_from(block)] += mass
            if clamp:  # Zᵀ Π D Π Z
                block -= (np.outer(width, mass) + np.outer(mass, width)) / n
                block += float(np.sum(d_blocks[row][col])) / n**2 * np.outer(width, width)
            e[row * m:(row + 1) * m, col * m:(col + 1) * m] = block
    if not np.all(np.isfinite(e)):
        return None
    factor = scipy.linalg.lu_factor(e, check_finite=False)
    if not np.all(np.isfinite(factor[0])) or np.min(np.abs(np.diag(factor[0]))) == 0.0:
        return None
    return CoarseSpace(nodes.size, starts, p, factor, clamp, n)


def _stiffness_part(stiff, fft, a, p):
    """Zᵀ K Z (2m × 2m) for blocks [a_I, a_I + p_I), cached on `stiff` for the last block layout (a Newton solve's
    iterations mostly keep their stiff set)."""
    cached = getattr(stiff, "_coarse_stiffness_part", None)
    if cached is not None and np.array_equal(cached[0], a) and np.array_equal(cached[1], p):
        return cached[2]
    n, m = fft.n, a.size
    sums = stiffness_kernel_sums(stiff, fft)
    xz = block_sums(sums["xz"], n, a, p)
    part = np.empty((2 * m, 2 * m))
    part[:m, :m] = block_sums(sums["xx"], n, a, p)
    part[:m, m:] = xz
    part[m:, :m] = xz.T
    part[m:, m:] = block_sums(sums["zz"], n, a, p)
    stiff._coarse_stiffness_part = (a, p, part)
    return part


def operators(coarse, stiff, fft, tangent, backend=None, parts=False):
    """(inverse, product) of the nodal right-preconditioned system (module docstring), for y (2, N) nodal:
    inverse(y) = ŝ, the spectrum of M⁻¹ y = K⁻¹ (y − D w) (the q = 0 mode 0 where clamped), w = Π Z c,
    c = `coarse.coefficients`(Zᵀ y); product(y) = A M⁻¹ y = Π (g + D s), g = y − D w, s = irfft ŝ: one FFT pair, a new
    array; with `parts`, (A M⁻¹ y, s, g), s = M⁻¹ y and g, whose Π g = K s, new arrays too (the Newton's step and its
    K δu without a transform, `gfmd.gmres.gmres`'s extras). ŝ lives in one array that each call rewrites; K⁻¹ is
    `stiff.inv_mass`, so A = (its inverse) + D. The nodal passes are `gfmd.coupled_kernels.coarse_passes`'
    (`backend`: `gfmd.kernels.jit_backend`'s name)."""
    n, clamp = fft.n, coarse.clamp
    d = tuple(np.ascontiguousarray(np.broadcast_to(np.asarray(x, float), (n,))) for x in tangent)
    row_block_sums, coarse_residual, tangent_plus = coarse_passes(backend)
    starts, widths = coarse.starts.astype(np.int64), coarse.widths.astype(np.int64)
    g, s_hat = np.empty((2, n)), np.empty((2, n // 2 + 1), complex)

    def inverse(y):
        c = coarse.coefficients(row_block_sums(y, starts, widths))
        coarse_residual(*d, y, c, starts, widths, clamp, g)  # g = y − D Π Z c
        stiff._apply(stiff.inv_mass, fft.rfft(g), s_hat)
        if clamp:
            s_hat[:, 0] = 0.0
        return s_hat

    def product(y):
        s = fft.irfft(inverse(y))
        out = tangent_plus(*d, s, g, clamp, np.empty((2, n)))
        return (out, s, g.copy()) if parts else out

    return inverse, product
