"""Restarted GMRES (Saad & Schultz 1986), modified Gram–Schmidt in one fused pass, a float32 basis.

The coupled law's Newton steps solve their linearised balance with it (`gfmd.coupled_krylov.spectral_step`), to
a relative tolerance ≥ 1e-3 (the inexact Newton's forcing, `gfmd.coupled_krylov.forcing`). scipy's
`scipy.sparse.linalg.gmres` (1.17) orthogonalises by modified Gram–Schmidt in a Python loop (a dot and an axpy
with a temporary per basis vector) in double precision; at N = 2^17 its basis (up to 61 vectors of 2N floats)
streams from memory twice on every iteration, 62 % of a Newton solve (measured at 2^17). Here the same modified
Gram–Schmidt runs as one numba kernel (double sums), and for rtol ≥ SINGLE_BASIS_RTOL the basis is stored in
float32: half the traffic (mixed-precision GMRES: the Arnoldi relation holds to ≈ 1e-7, far below the tolerance,
and w, the Hessenberg matrix, x and the verdict's true residual stay double). Measured on whole coupled ramps:
docs/design/performance.md. (Classical Gram–Schmidt with DGKS reorthogonalisation, two BLAS products per
pass, was tried first: the reorthogonalisation ran on 96 % of the Arnoldi steps, which made it as slow as scipy's at
2^17.) The iteration is scipy's otherwise: x0 = 0, no preconditioner (the caller's operator is preconditioned
already), the inner loop stops at the estimated residual ptol, each cycle ends with the true residual b − A x,
whose norm ≤ rtol ‖b‖ is convergence, and ptol adapts between cycles as scipy's does (gh-8400); the coupled Newton
(`gfmd.coupled_krylov.newton_direction`) trusts the estimate instead (``trust_estimate``: one product fewer per
solve) and takes its step's parts from the products (``extras``). Returns (x, info):
info 0 where it converged, else the number of cycles allowed. Without numba (the ``fast`` extra) the same
iteration projects in a numpy loop.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernels

#: the basis is stored in single precision for a solve to rtol ≥ this (the Newton steps' forcing, ≥ 1e-3): half
#: the memory traffic of its projections, which at N = 2^17 stream the whole basis from memory; its round-off
#: (≈ 1e-7 relative) is far below the tolerance, and the verdict is the double-precision true residual's
SINGLE_BASIS_RTOL = 1e-4


def gmres(matvec, b, rtol, restart, maxiter, single=None, trust_estimate=False, extras=0):
    """x with ‖b − A x‖ ≤ rtol ‖b‖ (A x = matvec(x), float64 vectors), by GMRES(restart), at most `maxiter` cycles:
    (x, 0) where it converged, else (x, maxiter). single: the basis in float32 (default: rtol ≥ SINGLE_BASIS_RTOL).
    matvec must return a new array (float64 is projected in place, without a copy) and may not keep its argument
    (one array, rewritten for every product).

    trust_estimate: a cycle whose estimated residual (the rotated Hessenberg's, exact in exact arithmetic) is ≤ rtol ‖b‖
    ends the solve without the true residual's product (scipy's verdict costs one product more; a caller that tests
    its own residual next, the inexact Newton, does not need it). extras = k > 0: matvec returns (A x, e_1(x), …,
    e_k(x)), each e_i linear in x and a new array, and the solve returns (x, info, [e_1(x), …, e_k(x)]) summed from the
    basis products' as x is from the basis (no product of x; the coupled Newton's M⁻¹ x and K M⁻¹ x, which a right
    preconditioner's products compute on the way)."""
    b = np.asarray(b, dtype=float)
    n = b.size
    b_norm = float(np.linalg.norm(b))
    if b_norm == 0.0:
        return (np.zeros(n), 0) if not extras else (np.zeros(n), 0, [0.0] * extras)
    atol = rtol * b_norm
    restart = min(restart, n)
    if single is None:
        single = rtol >= SINGLE_BASIS_RTOL
    dtype = np.float32 if single else np.float64
    eps = np.finfo(dtype).eps
    project = _project_fused if kernels.jit_backend() == "numba" else _project_numpy
    basis = np.empty((restart + 1, n), dtype=dtype)
    hess = np.zeros((restart + 1, restart))  # column j: the Arnoldi coefficients of A v_j, then rotated
    cos, sin = np.zeros(restart), np.zeros(restart)
    x = np.zeros(n)
    v_j = np.empty(n)
    r, r_norm = b.copy(), b_norm
    ptol_factor, ptol = 1.0, atol
    presid = r_norm
    x_extras = [0.0] * extras  # e_i(x), summed as x is
    for _ in range(maxiter):
        basis[0] = r * (1.0 / r_norm)
        g = np.zeros(restart + 1)  # the rotated right-hand side ‖r‖ e_1
        g[0] = r_norm
        breakdown = False
        parts = []  # e_i(v_j) of this cycle's basis vectors
        for j in range(restart):
            v_j[:] = basis[j]  # (one reused double copy of the basis vector: no fresh array per product)
            w = matvec(v_j)
            if extras:
                w, *more = w
                parts.append(more)
            w = np.asarray(w, dtype=np.float64)  # the caller's fresh product, projected in place
            w_norm = float(np.linalg.norm(w))
            h = project(basis, j, w)  # w ← w − Σ_k (v_k·w) v_k, modified Gram–Schmidt
            h_next = float(np.linalg.norm(w))
            col = hess[:, j]
            col[:j + 1] = h
            col[j + 1] = h_next
            if h_next <= eps * w_norm:  # A v_j in the span: the exact solution is in the basis
                col[j + 1] = 0.0
                breakdown = True
            else:
                np.multiply(w, 1.0 / h_next, out=basis[j + 1], casting="same_kind")
            for k in range(j):  # the rotations so far, on the new column
                a, c = col[k], col[k + 1]
                col[k], col[k + 1] = cos[k] * a + sin[k] * c, -sin[k] * a + cos[k] * c
            a, c = col[j], col[j + 1]
            mag = math.hypot(a, c)
            cos[j], sin[j] = (a / mag, c / mag) if mag > 0.0 else (1.0, 0.0)
            col[j], col[j + 1] = mag, 0.0
            g[j + 1] = -sin[j] * g[j]
            g[j] = cos[j] * g[j]
            presid = abs(g[j + 1])
            if presid <= ptol or breakdown:
                break
        y = g[:j + 1].copy()  # back substitution on the rotated Hessenberg matrix (a zero pivot: that term 0)
        for k in range(j, -1, -1):
            y[k] = y[k] / hess[k, k] if hess[k, k] != 0.0 else 0.0
            y[:k] -= y[k] * hess[:k, k]
        x += y.astype(dtype) @ basis[:j + 1]
        for i in range(extras):
            for k in range(j + 1):
                x_extras[i] = x_extras[i] + y[k] * parts[k][i]
        if trust_estimate and presid <= atol:
            r_norm = presid
            break
        r = b - np.asarray(matvec(x)[0] if extras else matvec(x), dtype=float)
        r_norm = float(np.linalg.norm(r))
        if r_norm <= atol or breakdown:
            break
        ptol_factor = max(eps, 0.25 * ptol_factor) if presid <= ptol else min(1.0, 1.5 * ptol_factor)
        ptol = presid * min(ptol_factor, atol / r_norm)
    info = 0 if r_norm <= atol else maxiter
    return (x, info) if not extras else (x, info, x_extras)


def _project_numpy(basis, j, w):
    """Modified Gram–Schmidt of w (float64, in place) against basis rows 0 … j: their coefficients."""
    h = np.empty(j + 1)
    for k in range(j + 1):
        v = basis[k]
        h[k] = float(np.dot(v, w))  # a float32 row is promoted to double
        w -= h[k] * v
    return h


if kernels.numba is not None:
    @kernels.numba.njit(cache=True, fastmath={"reassoc", "contract", "nsz", "arcp"})
    def _project_kernel(basis, j, w, h):  # per row: its dot with w (double sums), then w −= h_k v_k
        n = w.size
        for k in range(j + 1):
            t = 0.0
            for i in range(n):
                t += np.float64(basis[k, i]) * w[i]
            h[k] = t
            for i in range(n):
                w[i] -= t * np.float64(basis[k, i])

    def _project_fused(basis, j, w):
        h = np.empty(j + 1)
        _project_kernel(basis, j, w, h)
        return h
else:  # pragma: no cover - depends on the environment
    _project_fused = _project_numpy
