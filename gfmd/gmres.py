"""Restarted GMRES on a real operator, orthogonalised by classical Gram–Schmidt (twice where needed) through BLAS.

The same method and stopping rules as scipy.sparse.linalg.gmres(A, b, rtol=, restart=, maxiter=, M=) from x0 = 0
(scipy ≥ 1.12): Arnoldi on the left-preconditioned operator M⁻¹A, Givens rotations on the Hessenberg matrix,
the inner cycle stopped by scipy's adaptive estimate of the preconditioned residual (gh-8400), and after each cycle the
true residual ‖b − A x‖ tested against rtol‖b‖; info 0 where it was reached, `maxiter` otherwise. The same number
of products as scipy (one per Arnoldi vector plus one true residual per cycle). Only the orthogonalisation differs:
each new vector is projected out of the stored basis by two BLAS matrix–vector products (classical Gram–Schmidt),
and once more where the first pass cancelled (`REORTHOGONALIZE`), instead of scipy's Python loop of modified
Gram–Schmidt; the iterates agree with scipy's to round-off (tests/test_gmres.py).
"""

from __future__ import annotations

import math

import numpy as np

#: a second Gram–Schmidt pass where the first one left less than this fraction of the vector's norm (Daniel,
#: Gragg, Kaufman & Stewart 1976; "twice is enough": the second pass restores orthogonality to round-off)
REORTHOGONALIZE = 1.0 / np.sqrt(2.0)


def _rotation(f, g):
    """(c, s, r) with [c s; −s c]·(f, g) = (r, 0), c ≥ 0 (LAPACK's dlartg convention)."""
    if g == 0.0:
        return 1.0, 0.0, f
    if f == 0.0:
        return 0.0, math.copysign(1.0, g), abs(g)
    d = math.hypot(f, g)
    r = math.copysign(d, f)
    return abs(f) / d, g / r, r


def gmres(matvec, b, rtol, restart, maxiter, psolve=None):
    """(x, info): x ≈ A⁻¹ b by restarted GMRES (module docstring), x0 = 0.

    matvec: v ↦ A v on 1-D float arrays; psolve: v ↦ M⁻¹ v (None: no preconditioner); rtol: the relative
    tolerance of ‖b − A x‖ ≤ rtol‖b‖; restart: the Krylov dimension of one cycle; maxiter: the most cycles.
    info: 0 where the tolerance was reached, else `maxiter`.
    """
    b = np.asarray(b, dtype=float)
    if b.ndim != 1:
        raise ValueError(f"gmres: b must be 1-D, got shape {b.shape}")
    if psolve is None:
        def psolve(v):
            return v
    n = b.size
    x = np.zeros(n)
    bnrm2 = float(np.linalg.norm(b))
    if bnrm2 == 0.0:
        return x, 0
    atol = float(rtol) * bnrm2
    eps = np.finfo(float).eps
    restart = min(int(restart), n)
    mb_nrm2 = float(np.linalg.norm(psolve(b)))
    ptol_max_factor = 1.0
    ptol = mb_nrm2 * min(ptol_max_factor, atol / bnrm2)
    presid = 0.0
    basis = np.empty((restart + 1, n))  # the Arnoldi vectors, one per row
    h = np.zeros(restart + 1)  # the new Hessenberg column: projections, then the rotated column
    work = np.empty(n)
    rot_c = [0.0] * restart
    rot_s = [0.0] * restart
    r = b.copy()
    if float(np.linalg.norm(r)) < atol:
        return x, 0
    rnorm = bnrm2
    for _ in range(maxiter):
        basis[0] = psolve(r)
        beta = float(np.linalg.norm(basis[0]))
        basis[0] *= 1.0 / beta
        s_rhs = [0.0] * (restart + 1)  # Givens-rotated β e1
        s_rhs[0] = beta
        tri = np.zeros((restart, restart))  # R of the rotated Hessenberg matrix, column by column
        breakdown = False
        for col in range(restart):
            w = basis[col + 1]
            w[:] = psolve(matvec(basis[col]))
            h0 = float(np.linalg.norm(w))
            active = basis[: col + 1]
            coef = h[: col + 1]
            np.dot(active, w, out=coef)  # classical Gram–Schmidt
            np.dot(coef, active, out=work)
            w -= work
            h1 = float(np.linalg.norm(w))
            if h1 < REORTHOGONALIZE * h0:  # cancellation: once more against the round-off left over
                again = active @ w
                np.dot(again, active, out=work)
                w -= work
                coef += again
                h1 = float(np.linalg.norm(w))
            if h1 <= eps * h0:
                h1 = 0.0
                breakdown = True
            else:
                w *= 1.0 / h1
            column = coef.tolist()
            for k in range(col):  # the earlier rotations on the new column
                c, s = rot_c[k], rot_s[k]
                n0, n1 = column[k], column[k + 1]
                column[k], column[k + 1] = c * n0 + s * n1, c * n1 - s * n0
            c, s, mag = _rotation(column[col], h1)
            rot_c[col], rot_s[col] = c, s
            column[col] = mag
            tri[: col + 1, col] = column
            s_rhs[col], s_rhs[col + 1] = c * s_rhs[col], -s * s_rhs[col]
            presid = abs(s_rhs[col + 1])
            if presid <= ptol or breakdown:
                break
        # back substitution on R y = s, a zero pivot's component dropped (scipy's pseudo-solve)
        if tri[col, col] == 0.0:
            s_rhs[col] = 0.0
        y = np.array(s_rhs[: col + 1])
        for k in range(col, 0, -1):
            if y[k] != 0.0:
                y[k] /= tri[k, k]
                y[:k] -= y[k] * tri[:k, k]
        if y[0] != 0.0:
            y[0] /= tri[0, 0]
        x += y @ basis[: col + 1]
        r = b - matvec(x)
        rnorm = float(np.linalg.norm(r))
        if rnorm <= atol or breakdown:
            break
        if presid <= ptol:  # the inner estimate passed, the true residual did not: ask the next cycle for more
            ptol_max_factor = max(eps, 0.25 * ptol_max_factor)
        else:
            ptol_max_factor = min(1.0, 1.5 * ptol_max_factor)
        ptol = presid * min(ptol_max_factor, atol / rnorm)
    return x, (0 if rnorm <= atol else int(maxiter))
