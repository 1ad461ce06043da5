"""Restarted GMRES (Saad & Schultz 1986): classical Gram–Schmidt, selective reorthogonalisation, a float32 basis.

The coupled law's Newton steps solve their linearised balance with it (`gfmd.coupled_krylov.spectral_step`), to
a relative tolerance ≥ 1e-3 (the inexact Newton's forcing, `gfmd.coupled_krylov.forcing`). scipy's
`scipy.sparse.linalg.gmres` (1.17) orthogonalises by modified Gram–Schmidt in a Python loop, one basis vector at a
time, in double precision; at N = 2^17 the basis (up to 61 vectors of 2N floats) streams from memory on every
iteration, and projecting against it costs more than the iteration's FFT pair. Here the Arnoldi step projects
against the whole basis at once, two BLAS matrix–vector products (h = Vᵀw, w ← w − V h), repeated once where the
projection cancelled more than 1 − 1/√2 of w (Daniel, Gragg, Kaufman & Stewart 1976), and, for rtol ≥
SINGLE_BASIS_RTOL, the basis is stored in float32 (half the traffic; mixed-precision GMRES: the Arnoldi relation
holds to ≈ 1e-7, far below the tolerance, and the verdict is the double-precision true residual's). Measured on
whole coupled ramps: benchmarks/results/bench_gmres.md. The iteration is scipy's otherwise: x0 = 0, no
preconditioner (the caller's operator is preconditioned already), the inner loop stops at the estimated residual
ptol, each cycle ends with the true residual b − A x, whose norm ≤ rtol ‖b‖ is convergence, and ptol adapts between
cycles as scipy's does (gh-8400). Returns (x, info): info 0 where it converged, else the number of cycles allowed.
"""

from __future__ import annotations

import math

import numpy as np

#: reorthogonalise where the projection left less than this fraction of ‖w‖ (DGKS's 1/√2)
REORTHOGONALISE = 1.0 / math.sqrt(2.0)
#: the basis is stored in single precision for a solve to rtol ≥ this (the Newton steps' forcing, ≥ 1e-3): half
#: the memory traffic of its projections, which at N = 2^17 stream the whole basis from memory; its round-off
#: (≈ 1e-7 relative) is far below the tolerance, and the verdict is the double-precision true residual's
SINGLE_BASIS_RTOL = 1e-4


def gmres(matvec, b, rtol, restart, maxiter, single=None):
    """x with ‖b − A x‖ ≤ rtol ‖b‖ (A x = matvec(x), float64 vectors), by GMRES(restart), at most `maxiter` cycles:
    (x, 0) where it converged, else (x, maxiter). single: the basis in float32 (default: rtol ≥ SINGLE_BASIS_RTOL)."""
    b = np.asarray(b, dtype=float)
    n = b.size
    b_norm = float(np.linalg.norm(b))
    if b_norm == 0.0:
        return np.zeros(n), 0
    atol = rtol * b_norm
    restart = min(restart, n)
    if single is None:
        single = rtol >= SINGLE_BASIS_RTOL
    dtype = np.float32 if single else np.float64
    eps = np.finfo(dtype).eps
    basis = np.empty((restart + 1, n), dtype=dtype)
    hess = np.zeros((restart + 1, restart))  # column j: the Arnoldi coefficients of A v_j, then rotated
    cos, sin = np.zeros(restart), np.zeros(restart)
    x = np.zeros(n)
    r, r_norm = b.copy(), b_norm
    ptol_factor, ptol = 1.0, atol
    presid = r_norm
    for _ in range(maxiter):
        basis[0] = r * (1.0 / r_norm)
        g = np.zeros(restart + 1)  # the rotated right-hand side ‖r‖ e_1
        g[0] = r_norm
        breakdown = False
        for j in range(restart):
            w = np.array(matvec(basis[j].astype(np.float64)), dtype=dtype)
            w_norm = float(np.linalg.norm(w))
            v = basis[:j + 1]
            h = v @ w
            w -= h @ v
            h_next = float(np.linalg.norm(w))
            if h_next < REORTHOGONALISE * w_norm:  # cancellation: a second pass
                h2 = v @ w
                w -= h2 @ v
                h += h2
                h_next = float(np.linalg.norm(w))
            col = hess[:, j]
            col[:j + 1] = h
            col[j + 1] = h_next
            if h_next <= eps * w_norm:  # A v_j in the span: the exact solution is in the basis
                col[j + 1] = 0.0
                breakdown = True
            else:
                basis[j + 1] = w * (1.0 / h_next)
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
        r = b - np.asarray(matvec(x), dtype=float)
        r_norm = float(np.linalg.norm(r))
        if r_norm <= atol or breakdown:
            break
        ptol_factor = max(eps, 0.25 * ptol_factor) if presid <= ptol else min(1.0, 1.5 * ptol_factor)
        ptol = presid * min(ptol_factor, atol / r_norm)
    return x, (0 if r_norm <= atol else maxiter)
