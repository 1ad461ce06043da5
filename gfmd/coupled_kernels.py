"""The coupled law's per-product vector algebra in GFMD, numpy or fused (numba), like `gfmd.kernels`.

* `block_times`: the 2×2 spectral block product (a b; b̄ d)·x of K(q), M_q or their inverses (`gfmd.problem.Elastic`)
  into a given output, no stacked temporaries; `split_block_times` the same on `Blocks.split`, the blocks of an
  isotropic body (a, d real, b imaginary: K_xz(q) is odd in q) as three real arrays, the same numbers bit for bit
  (what the zero parts add is exact) from half the coefficient bytes and a third of the multiplications;
* `tangent_times`: the nodal 2×2 law tangent D·v (rows and columns (x, z)) of `gfmd.coupled_krylov`'s products;
* `coupled_tractions`: Eq. 2's tractions on the body, t_x = T_t(Δt), t_z = T_n(Δn), Δn = z_ind − u_z, Δt = −u_x,
  one exponential per node; the law's formula is `gfmd_contact.core.law_equations.traction_coupled` (the same to round-off,
  tests/test_coupled_kernels.py; e^x by `gfmd.vector_exp`, within 1 ulp of libm's), which also raises its
  CompressionOverflowError (the fused pass only counts the nodes out of the law's range);
* `weighted_dot`: Σ_q w_q Re(conj(a_q) b_q) over spectra (FIRE's mass-weighted products);
* `coarse_passes`: the nodal passes of the coupled Newton's two-level preconditioner (`gfmd.coupled_preconditioner`),
  one pass each where numpy takes 4–7 and a temporary per pass (the mean of Π Z c from the block sums, as
  `gfmd.coarse_kernels` does for the cohesive NCG's).

``GFMD_JIT=auto|numba|numpy`` chooses (`gfmd.kernels.jit_backend`); numpy where numba is not installed.
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.core.law_equations import MAX_COMPRESSION, traction_coupled

from . import vector_exp
from .kernels import jit_backend, numba


class Blocks(tuple):
    """The 2×2 Hermitian spectral blocks (a, b, d), (a b; b̄ d) on every mode, of K(q), M_q or their inverses, a
    tuple; `split` (Re a, Im b, Re d) where a and d are real and b imaginary, else None (`hermitian_blocks`)."""

    split = None


def hermitian_blocks(a, b, d):
    """`Blocks` (a, b, d) with its split form (Re a, Im b, Re d) where Im a = Im d = Re b = 0 exactly, else None."""
    out = Blocks((a, b, d))
    if not (np.any(np.imag(a)) or np.any(np.imag(d)) or np.any(np.real(b))):
        out.split = tuple(np.ascontiguousarray(x, dtype=float) for x in (np.real(a), np.imag(b), np.real(d)))
    return out


def divided_blocks(blocks, divisor):
    """`blocks` ((m,) or `Blocks`) divided by a real number or an array over the modes; a `Blocks`' split form taken
    from the complex quotients (numpy's complex division by a real multiplies by its reciprocal: not Re a / divisor)."""
    quotients = tuple(x / divisor for x in blocks)
    return hermitian_blocks(*quotients) if isinstance(blocks, Blocks) else quotients


def float_views(*spectra):
    """Whether every spectrum is complex128 and C-contiguous: seen as floats (mode i: 2i, 2i + 1) by the split kernels."""
    return all(x.dtype == complex and x.flags.c_contiguous for x in spectra)


def _block_times_numpy(a, b, d, x, out):
    np.multiply(a, x[0], out=out[0])
    out[0] += b * x[1]
    np.multiply(d, x[1], out=out[1])
    out[1] += np.conj(b) * x[0]
    return out


def _tangent_times_numpy(d_nn, d_nt, d_tn, d_tt, v, out):
    np.multiply(d_tt, v[0], out=out[0])
    out[0] += d_tn * v[1]
    np.multiply(d_nt, v[0], out=out[1])
    out[1] += d_nn * v[1]
    return out


def _tractions_numpy(u, z_ind, params, out):
    work_normal, length_normal, work_tangential, length_tangential = params
    out[1], out[0] = traction_coupled(z_ind - u[1], -u[0], work_normal, length_normal, work_tangential,
                                      length_tangential)
    return out


def _weighted_dot_numpy(w, a, b):
    return float(np.sum(w * (np.conj(a) * b).real))


def _row_block_sums_numpy(y, starts, widths):
    return np.add.reduceat(y[:, :int(starts[-1] + widths[-1])], starts, axis=1)


def _coarse_residual_numpy(d_nn, d_nt, d_tn, d_tt, y, c, starts, widths, clamp, g):
    w = np.zeros(y.shape)
    w[:, :int(starts[-1] + widths[-1])] = np.repeat(c, widths, axis=1)
    if clamp:
        w -= w.mean(axis=1, keepdims=True)
    _tangent_times_numpy(d_nn, d_nt, d_tn, d_tt, w, g)
    np.subtract(y, g, out=g)
    return g


def _tangent_plus_numpy(d_nn, d_nt, d_tn, d_tt, s, g, clamp, out):
    _tangent_times_numpy(d_nn, d_nt, d_tn, d_tt, s, out)
    out += g
    if clamp:
        out -= out.mean(axis=1, keepdims=True)
    return out


if numba is not None:
    @numba.njit(cache=True)
    def _block_kernel(a, b, d, x, out):
        for i in range(a.size):
            x0, x1, bi = x[0, i], x[1, i], b[i]
            out[0, i] = a[i] * x0 + bi * x1
            out[1, i] = bi.conjugate() * x0 + d[i] * x1

    @numba.njit(cache=True)
    def _block_split_kernel(a, b, d, x, out):  # float views of x, out: mode i is (2i, 2i + 1); b the Im of (a b; b̄ d)
        for i in range(a.size):  # (a + 0i)(x0) + (0 + ib)(x1), term by term as the complex product's, the zeros left out
            j = 2 * i
            x0r, x0i, x1r, x1i = x[0, j], x[0, j + 1], x[1, j], x[1, j + 1]
            out[0, j] = a[i] * x0r + (-(b[i] * x1i))
            out[0, j + 1] = a[i] * x0i + b[i] * x1r
            out[1, j] = b[i] * x0i + d[i] * x1r
            out[1, j + 1] = -(b[i] * x0r) + d[i] * x1i

    @numba.njit(cache=True)
    def _tangent_kernel(d_nn, d_nt, d_tn, d_tt, v, out):
        for i in range(v.shape[1]):
            v0, v1 = v[0, i], v[1, i]
            out[0, i] = d_tt[i] * v0 + d_tn[i] * v1
            out[1, i] = d_nt[i] * v0 + d_nn[i] * v1

    @numba.njit(cache=True, fastmath=vector_exp.STRICT_FLAGS)
    def _tractions_kernel(u, z_ind, work_normal, length_normal, work_tangential, length_tangential, lowest, out):
        """Eq. 2 as `traction_coupled` evaluates it, e^x by `gfmd.vector_exp` (a vectorized loop); returns the
        number of nodes whose Δn is not a finite number ≥ `lowest` (the law's overflow range, NaN, ±inf)."""
        bad = 0
        c_n = work_normal / length_normal
        c_t = 2.0 * (work_tangential / length_tangential)
        for i in range(z_ind.size):
            gap = z_ind[i] - u[1, i]
            bad += 0 if (gap >= lowest and gap < np.inf) else 1
            sn = gap / length_normal
            st = -u[0, i] / length_tangential
            common = vector_exp.exp(-sn - st * st)
            out[1, i] = c_n * sn * common
            out[0, i] = c_t * st * common
        return bad

    @numba.njit(cache=True)
    def _weighted_dot_kernel(w, a, b):
        total = 0.0
        for k in range(a.shape[0]):
            for i in range(w.size):
                total += w[i] * (a[k, i].real * b[k, i].real + a[k, i].imag * b[k, i].imag)
        return total

    # the sums reassociated (vectorized); no finite-math assumptions
    _SUM_FLAGS = {"reassoc", "contract", "nsz"}

    @numba.njit(cache=True, fastmath=_SUM_FLAGS)
    def _row_block_sums_kernel(y, starts, widths, out):
        for b in range(starts.size):
            s0 = s1 = 0.0
            for i in range(starts[b], starts[b] + widths[b]):
                s0 += y[0, i]
                s1 += y[1, i]
            out[0, b], out[1, b] = s0, s1

    @numba.njit(cache=True, fastmath=_SUM_FLAGS)
    def _coarse_residual_kernel(d_nn, d_nt, d_tn, d_tt, y, c, starts, widths, clamp, g):
        n = y.shape[1]
        mean0 = mean1 = 0.0
        if clamp:  # the mean of Z c from the block sums, not a pass
            for b in range(starts.size):
                mean0 += c[0, b] * widths[b]
                mean1 += c[1, b] * widths[b]
            mean0, mean1 = mean0 / n, mean1 / n
        end = 0
        for b in range(starts.size + 1):  # the blocks, then the nodes after them (w = −mean there)
            if b < starts.size:
                w0, w1, first, end = c[0, b] - mean0, c[1, b] - mean1, starts[b], starts[b] + widths[b]
            else:
                w0, w1, first, end = -mean0, -mean1, end, n
            for i in range(first, end):
                g[0, i] = y[0, i] - (d_tt[i] * w0 + d_tn[i] * w1)
                g[1, i] = y[1, i] - (d_nt[i] * w0 + d_nn[i] * w1)

    @numba.njit(cache=True, fastmath=_SUM_FLAGS)
    def _tangent_plus_kernel(d_nn, d_nt, d_tn, d_tt, s, g, out):
        total0 = total1 = 0.0
        for i in range(g.shape[1]):
            v0, v1 = s[0, i], s[1, i]
            o0 = d_tt[i] * v0 + d_tn[i] * v1 + g[0, i]
            o1 = d_nt[i] * v0 + d_nn[i] * v1 + g[1, i]
            out[0, i], out[1, i] = o0, o1
            total0 += o0
            total1 += o1
        return total0, total1


def _row_block_sums_numba(y, starts, widths):
    out = np.empty((2, starts.size))
    _row_block_sums_kernel(y, starts, widths, out)
    return out


def _coarse_residual_numba(d_nn, d_nt, d_tn, d_tt, y, c, starts, widths, clamp, g):
    _coarse_residual_kernel(d_nn, d_nt, d_tn, d_tt, y, np.ascontiguousarray(c, dtype=float), starts, widths,
                            bool(clamp), g)
    return g


def _tangent_plus_numba(d_nn, d_nt, d_tn, d_tt, s, g, clamp, out):
    total0, total1 = _tangent_plus_kernel(d_nn, d_nt, d_tn, d_tt, s, g, out)
    if clamp:
        n = g.shape[1]
        out[0] -= total0 / n
        out[1] -= total1 / n
    return out


def _block_times_numba(a, b, d, x, out):  # 1+1-D only: 2+1-D surfaces have no tangential unknowns
    _block_kernel(a, b, d, x, out)
    return out


def _block_split_numba(a, b, d, x, out):
    _block_split_kernel(a, b, d, x.view(np.float64), out.view(np.float64))
    return out


def split_block_times(name=None):
    """block_times(Re a, Im b, Re d, x, out) on `Blocks.split` with x, out (2, …) complex, C-contiguous (numba), or None
    (numpy: `coupled_kernels`' block_times on the complex blocks)."""
    return _block_split_numba if jit_backend(name) == "numba" else None


def _tangent_times_numba(d_nn, d_nt, d_tn, d_tt, v, out):
    _tangent_kernel(d_nn, d_nt, d_tn, d_tt, v, out)
    return out


def _tractions_numba(u, z_ind, params, out):
    work_normal, length_normal, work_tangential, length_tangential = params
    lowest = -MAX_COMPRESSION * float(length_normal)
    if _tractions_kernel(u, z_ind, float(work_normal), float(length_normal), float(work_tangential),
                         float(length_tangential), lowest, out):
        out[1], out[0] = traction_coupled(z_ind - u[1], -u[0], *params)  # the law's own check raises its error
    return out


def _weighted_dot_numba(w, a, b):
    return float(_weighted_dot_kernel(w, a.reshape(-1, w.size), b.reshape(-1, w.size)))


def coupled_kernels(name=None):
    """(block_times, tangent_times, coupled_tractions, weighted_dot) of `jit_backend(name)`; signatures:
    block_times(a, b, d, x, out) with x, out (2, …) complex; tangent_times(d_nn, d_nt, d_tn, d_tt, v, out) with
    v, out (2, N); coupled_tractions(u, z_ind, (φn, δn, φt, δt), out) with u, out (2, N) (x, z);
    weighted_dot(w, a, b) with a, b (c, nq), w (nq,). Each returns out (the float for weighted_dot)."""
    if jit_backend(name) == "numba":
        return _block_times_numba, _tangent_times_numba, _tractions_numba, _weighted_dot_numba
    return _block_times_numpy, _tangent_times_numpy, _tractions_numpy, _weighted_dot_numpy


def coarse_passes(name=None):
    """(row_block_sums, coarse_residual, tangent_plus) of `jit_backend(name)`, the two-level preconditioner's nodal
    passes (`gfmd.coupled_preconditioner.operators`) on blocks [starts_b, starts_b + widths_b) covering the nodes
    0 … m − 1 in order (int64), D = (d_nn, d_nt, d_tn, d_tt) per node (rows and columns (x, z)), Π the mean removal
    where `clamp`: row_block_sums(y, starts, widths) = Zᵀ y (2, blocks); coarse_residual(*D, y, c, starts, widths,
    clamp, g): g = y − D Π Z c; tangent_plus(*D, s, g, clamp, out): out = Π (D s + g). Each returns its result."""
    if jit_backend(name) == "numba":
        return _row_block_sums_numba, _coarse_residual_numba, _tangent_plus_numba
    return _row_block_sums_numpy, _coarse_residual_numpy, _tangent_plus_numpy
