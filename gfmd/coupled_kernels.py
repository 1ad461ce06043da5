"""The coupled law's per-product vector algebra in GFMD, numpy or fused (numba), like `gfmd.kernels`.

* `block_times`: the 2×2 spectral block product (a b; b̄ d)·x of K(q), M_q or their inverses (`gfmd.problem.Elastic`)
  into a given output, no stacked temporaries;
* `tangent_times`: the nodal 2×2 law tangent D·v (rows and columns (x, z)) of `gfmd.coupled_krylov`'s products;
* `coupled_tractions`: Eq. 2's tractions on the body, t_x = T_t(Δt), t_z = T_n(Δn), Δn = z_ind − u_z, Δt = −u_x,
  one exponential per node; the law's formula is `contact.law_equations.traction_coupled` (the same to round-off,
  tests/test_coupled_kernels.py), which also raises its CompressionOverflowError (the fused pass only finds
  the smallest gap);
* `weighted_dot`: Σ_q w_q Re(conj(a_q) b_q) over spectra (FIRE's mass-weighted products).

``GFMD_JIT=auto|numba|numpy`` chooses (`gfmd.kernels.jit_backend`); numpy where numba is not installed.
"""

from __future__ import annotations

import numpy as np

from contact.law_equations import MAX_COMPRESSION, traction_coupled

from .kernels import jit_backend, numba


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


if numba is not None:
    @numba.njit(cache=True)
    def _block_kernel(a, b, d, x, out):
        for i in range(a.size):
            x0, x1, bi = x[0, i], x[1, i], b[i]
            out[0, i] = a[i] * x0 + bi * x1
            out[1, i] = bi.conjugate() * x0 + d[i] * x1

    @numba.njit(cache=True)
    def _tangent_kernel(d_nn, d_nt, d_tn, d_tt, v, out):
        for i in range(v.shape[1]):
            v0, v1 = v[0, i], v[1, i]
            out[0, i] = d_tt[i] * v0 + d_tn[i] * v1
            out[1, i] = d_nt[i] * v0 + d_nn[i] * v1

    @numba.njit(cache=True)
    def _tractions_kernel(u, z_ind, work_normal, length_normal, work_tangential, length_tangential, out):
        """Eq. 2 as `traction_coupled` evaluates it (same operations); returns the smallest Δn."""
        smallest = np.inf
        c_n = work_normal / length_normal
        c_t = 2.0 * (work_tangential / length_tangential)
        for i in range(z_ind.size):
            gap = z_ind[i] - u[1, i]
            if gap < smallest or gap != gap:  # a NaN stays: the check below sees it
                smallest = gap
            sn = gap / length_normal
            st = -u[0, i] / length_tangential
            common = np.exp(-sn - st * st)
            out[1, i] = c_n * sn * common
            out[0, i] = c_t * st * common
        return smallest

    @numba.njit(cache=True)
    def _weighted_dot_kernel(w, a, b):
        total = 0.0
        for k in range(a.shape[0]):
            for i in range(w.size):
                total += w[i] * (a[k, i].real * b[k, i].real + a[k, i].imag * b[k, i].imag)
        return total


def _block_times_numba(a, b, d, x, out):  # 1+1-D only: 2+1-D surfaces have no tangential unknowns
    _block_kernel(a, b, d, x, out)
    return out


def _tangent_times_numba(d_nn, d_nt, d_tn, d_tt, v, out):
    _tangent_kernel(d_nn, d_nt, d_tn, d_tt, v, out)
    return out


def _tractions_numba(u, z_ind, params, out):
    work_normal, length_normal, work_tangential, length_tangential = params
    smallest = _tractions_kernel(u, z_ind, float(work_normal), float(length_normal), float(work_tangential),
                                 float(length_tangential), out)
    worst = smallest / length_normal
    if not (np.isfinite(worst) and worst >= -MAX_COMPRESSION):  # the law's own check raises its error
        traction_coupled(z_ind - u[1], -u[0], *params)
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
