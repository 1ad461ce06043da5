"""The nodal passes of the two-level cohesive preconditioner's application (`gfmd.cohesive_preconditioner`), fused.

The coarse space Z holds piecewise constants on consecutive blocks of nodes, block b = [a_b, a_b + p_b),
covering the nodes 0 … m − 1 in order (`cover`); Π removes the mean on a half-plane (`clamp`). Per
application `TwoLevel.apply` needs three nodal passes besides its FFTs and two small coarse solves:

* `spread_scaled`: w = Π Z c and D w (D = diag(k_loc), `gfmd.cohesive_preconditioner.SIGNED_CURVATURE`), into two
  arrays;
* `stiff_sums`: Zᵀ Π D (x − w) (the coarse residual of y = x − w);
* `spread_subtract`: z = Π Z c and x ← x − z, in place.

`split_kernels`: the passes of `TwoLevel.apply_split` (the force given as T_n and û, the NCG's path), one each.

numpy needs 4–6 passes and a temporary for each of these; the numba kernels one pass each, with the mean of
Π Z c from the block sums (Σ_b p_b c_b / N) instead of a pass. Both give the same values up to round-off
(the fused sums are reassociated). A rebuild assembles the coarse matrix E = Zᵀ Π (K + D) Π Z (`coarse_matrix`:
numpy's four m × m gathers and three outer products, 28 ms at m = 800, or one numba pass over its upper triangle,
4 ms). The backend is `gfmd.kernels.jit_backend`'s (``GFMD_JIT``).
"""

from __future__ import annotations

import numpy as np

from .kernels import jit_backend, numba


def _coarse_mean(c, widths, n, clamp):
    return float(np.dot(c, widths)) / n if clamp else 0.0


def _spread_numpy(c, starts, widths, n, clamp, out):
    m = int(starts[-1] + widths[-1])
    out[:m] = np.repeat(c, widths)
    out[m:] = 0.0
    if clamp:
        out -= _coarse_mean(c, widths, n, clamp)
    return out


def spread(c, starts, widths, n, clamp, out):
    """Π Z c on every node, into out (N,): blocks of `widths` nodes from `starts`, consecutive from node 0."""
    return _spread_numpy(c, starts, widths, n, clamp, out)


def _spread_scaled_numpy(c, starts, widths, n, clamp, d, w, work):
    _spread_numpy(c, starts, widths, n, clamp, w)
    np.multiply(d, w, out=work)


def _stiff_sums_numpy(d, x, w, starts, widths, n, clamp):
    m = int(starts[-1] + widths[-1])
    dy = d * (x - w)
    r = np.add.reduceat(dy[:m], starts)
    if clamp:
        r -= widths * (float(np.sum(dy)) / n)
    return r


def _spread_subtract_numpy(c, starts, widths, n, clamp, z, x):
    _spread_numpy(c, starts, widths, n, clamp, z)
    np.subtract(x, z, out=x)


if numba is not None:
    @numba.njit(cache=True, fastmath=True)
    def _mean(c, widths, n, clamp):
        total = 0.0
        if clamp:
            for b in range(c.size):
                total += c[b] * widths[b]
        return total / n

    @numba.njit(cache=True, fastmath=True)
    def _spread_scaled_fused(c, starts, widths, n, clamp, d, w, work):
        mean = _mean(c, widths, n, clamp)
        m = 0
        for b in range(c.size):
            v = c[b] - mean
            for i in range(starts[b], starts[b] + widths[b]):
                w[i] = v
                work[i] = d[i] * v
            m = starts[b] + widths[b]
        for i in range(m, n):
            w[i] = -mean
            work[i] = -d[i] * mean

    @numba.njit(cache=True, fastmath=True)
    def _stiff_sums_fused(d, x, w, starts, widths, n, clamp, r):
        total = 0.0
        m = 0
        for b in range(starts.size):
            acc = 0.0
            for i in range(starts[b], starts[b] + widths[b]):
                acc += d[i] * (x[i] - w[i])
            r[b] = acc
            total += acc
            m = starts[b] + widths[b]
        for i in range(m, n):
            total += d[i] * (x[i] - w[i])
        if clamp:
            mean = total / n
            for b in range(starts.size):
                r[b] -= widths[b] * mean

    @numba.njit(cache=True, fastmath=True)
    def _spread_subtract_fused(c, starts, widths, n, clamp, z, x):
        mean = _mean(c, widths, n, clamp)
        m = 0
        for b in range(c.size):
            v = c[b] - mean
            for i in range(starts[b], starts[b] + widths[b]):
                z[i] = v
                x[i] -= v
            m = starts[b] + widths[b]
        for i in range(m, n):
            z[i] = -mean
            x[i] += mean


    @numba.njit(cache=True)
    def _coarse_matrix_fused(cs2, n, a, p, mass, clamp, dsum, e):
        inv = 1.0 / n
        shift = dsum * inv * inv
        for i in range(a.size):
            ai, pi = a[i], p[i]
            for j in range(i, a.size):
                b, r = a[j], p[j]
                v = ((cs2[ai + pi - b + n + 1] - cs2[ai - b + n + 1])
                     - (cs2[ai + pi - b - r + n + 1] - cs2[ai - b - r + n + 1]))
                if i == j:
                    v += mass[i]
                if clamp:
                    v += shift * pi * r - (pi * mass[j] + mass[i] * r) * inv
                e[i, j] = v
                e[j, i] = v


def block_sums(cs2, n, a, p):
    """Zᵀ K Z of one kernel: Σ_{i∈I} Σ_{j∈J} kr(i − j) for the blocks [a_I, a_I + p_I) (cs2: the kernel's double
    cumulative sums, `gfmd.cohesive_preconditioner.kernel_sums`)."""
    ai, pi = a[:, None], p[:, None]
    b, r = a[None, :], p[None, :]
    return ((cs2[ai + pi - b + n + 1] - cs2[ai - b + n + 1])
            - (cs2[ai + pi - b - r + n + 1] - cs2[ai - b - r + n + 1]))


def _coarse_matrix_numpy(cs2, n, a, p, mass, clamp, dsum):
    e = block_sums(cs2, n, a, p)
    e[np.diag_indices_from(e)] += mass
    if clamp:
        w = p.astype(float)
        e -= (np.outer(w, mass) + np.outer(mass, w)) / n
        e += dsum / n**2 * np.outer(w, w)
    return 0.5 * (e + e.T)


def _coarse_matrix_numba(cs2, n, a, p, mass, clamp, dsum):
    e = np.empty((a.size, a.size))
    _coarse_matrix_fused(cs2, n, np.ascontiguousarray(a, dtype=np.int64), np.ascontiguousarray(p, dtype=np.int64),
                         np.ascontiguousarray(mass, dtype=float), bool(clamp), float(dsum), e)
    return e


def coarse_matrix(name=None):
    """E = Zᵀ Π (K + D) Π Z of blocks [a_b, a_b + p_b) (symmetric, (m, m)) from K's kernel sums `cs2`
    (`gfmd.cohesive_preconditioner.kernel_sums`), the blocks' D sums `mass` = Zᵀ D 1 and dsum = Σ D, Π the mean
    removal where `clamp`; of the backend `gfmd.kernels.jit_backend(name)` (numba: one pass over the upper triangle,
    mirrored)."""
    return _coarse_matrix_numba if jit_backend(name) == "numba" else _coarse_matrix_numpy


def _spread_scaled_numba(c, starts, widths, n, clamp, d, w, work):
    _spread_scaled_fused(np.ascontiguousarray(c, dtype=float), starts, widths, n, bool(clamp), d, w, work)


def _stiff_sums_numba(d, x, w, starts, widths, n, clamp):
    r = np.empty(starts.size)
    _stiff_sums_fused(d, x, w, starts, widths, n, bool(clamp), r)
    return r


def _spread_subtract_numba(c, starts, widths, n, clamp, z, x):
    _spread_subtract_fused(np.ascontiguousarray(c, dtype=float), starts, widths, n, bool(clamp), z, x)


def _block_load_numpy(t, starts, widths, n, out):
    m = int(starts[-1] + widths[-1])
    out[:] = np.add.reduceat(t[:m], starts)
    return float(np.sum(t))


def _spread_scaled_minus_numpy(c, starts, widths, n, clamp, d, t, dw, y):
    _spread_scaled_numpy(c, starts, widths, n, clamp, d, y, dw)
    np.subtract(t, dw, out=y)


def _stiff_sums_of_numpy(d, x, c, starts, widths, n, clamp, w):
    _spread_numpy(c, starts, widths, n, clamp, w)
    return _stiff_sums_numpy(d, x, w, starts, widths, n, clamp)


def _split_spectrum_numpy(y_hat, g, u_hat, x_hat):
    np.multiply(g, y_hat, out=x_hat)
    x_hat -= u_hat


def _spread_subtract_dots_numpy(c, starts, widths, n, clamp, z, x, dw, dw_old, d_old):
    _spread_subtract_numpy(c, starts, widths, n, clamp, z, x)
    return (float(np.dot(dw, x)), float(np.dot(dw_old, x)) if dw_old is not None else 0.0,
            float(np.dot(dw, d_old)) if d_old is not None else 0.0)


def _move_numpy(u_hat, d_hat, alpha):
    u_hat += alpha * d_hat


if numba is not None:
    @numba.njit(cache=True, fastmath=True)
    def _block_load_fused(t, starts, widths, n, out):
        total = 0.0
        m = 0
        for b in range(starts.size):
            acc = 0.0
            for i in range(starts[b], starts[b] + widths[b]):
                acc += t[i]
            out[b] = acc
            total += acc
            m = starts[b] + widths[b]
        for i in range(m, n):
            total += t[i]
        return total

    @numba.njit(cache=True, fastmath=True)
    def _spread_scaled_minus_fused(c, starts, widths, n, clamp, d, t, dw, y):
        mean = _mean(c, widths, n, clamp)
        m = 0
        for b in range(c.size):
            v = c[b] - mean
            for i in range(starts[b], starts[b] + widths[b]):
                x = d[i] * v
                dw[i] = x
                y[i] = t[i] - x
            m = starts[b] + widths[b]
        for i in range(m, n):
            x = -d[i] * mean
            dw[i] = x
            y[i] = t[i] - x

    @numba.njit(cache=True, fastmath=True)
    def _stiff_sums_of_fused(d, x, c, starts, widths, n, clamp, r):
        mean = _mean(c, widths, n, clamp)
        total = 0.0
        m = 0
        for b in range(starts.size):
            v = c[b] - mean
            acc = 0.0
            for i in range(starts[b], starts[b] + widths[b]):
                acc += d[i] * (x[i] - v)
            r[b] = acc
            total += acc
            m = starts[b] + widths[b]
        for i in range(m, n):
            total += d[i] * (x[i] + mean)
        if clamp:
            mean_dy = total / n
            for b in range(starts.size):
                r[b] -= widths[b] * mean_dy

    @numba.njit(cache=True, fastmath=True)
    def _split_spectrum_fused(y, g, u, x):  # float views: mode i is (2i, 2i + 1)
        for i in range(g.size):
            x[2 * i] = g[i] * y[2 * i] - u[2 * i]
            x[2 * i + 1] = g[i] * y[2 * i + 1] - u[2 * i + 1]

    @numba.njit(cache=True, fastmath=True)
    def _spread_subtract_dots_fused(c, starts, widths, n, clamp, z, x, dw, dw_old, d_old, has_old, has_d):
        mean = _mean(c, widths, n, clamp)
        s_dw = s_old = d_dw = 0.0
        m = 0
        for b in range(c.size + 1):
            if b < c.size:
                v, lo, hi = c[b] - mean, starts[b], starts[b] + widths[b]
                m = hi
            else:  # the nodes past the last block
                v, lo, hi = -mean, m, n
            for i in range(lo, hi):
                z[i] = v
                xi = x[i] - v
                x[i] = xi
                s_dw += dw[i] * xi
                if has_old:
                    s_old += dw_old[i] * xi
                if has_d:
                    d_dw += dw[i] * d_old[i]
        return s_dw, s_old, d_dw

    @numba.njit(cache=True, fastmath=True)
    def _move_fused(u, d, alpha):
        for i in range(u.size):
            u[i] += alpha * d[i]


def _block_load_numba(t, starts, widths, n, out):
    return float(_block_load_fused(t, starts, widths, n, out))


def _spread_scaled_minus_numba(c, starts, widths, n, clamp, d, t, dw, y):
    _spread_scaled_minus_fused(np.ascontiguousarray(c, dtype=float), starts, widths, n, bool(clamp), d, t, dw, y)


def _stiff_sums_of_numba(d, x, c, starts, widths, n, clamp, w):
    r = np.empty(starts.size)
    _stiff_sums_of_fused(d, x, np.ascontiguousarray(c, dtype=float), starts, widths, n, bool(clamp), r)
    return r


def _split_spectrum_numba(y_hat, g, u_hat, x_hat):
    _split_spectrum_fused(y_hat.view(np.float64), g, u_hat.view(np.float64), x_hat.view(np.float64))


def _spread_subtract_dots_numba(c, starts, widths, n, clamp, z, x, dw, dw_old, d_old):
    return _spread_subtract_dots_fused(np.ascontiguousarray(c, dtype=float), starts, widths, n, bool(clamp), z, x, dw,
                                       dw if dw_old is None else dw_old, dw if d_old is None else d_old,
                                       dw_old is not None, d_old is not None)


def _move_numba(u_hat, d_hat, alpha):
    _move_fused(u_hat.view(np.float64), d_hat.view(np.float64), float(alpha))


def split_kernels(name=None):
    """`gfmd.cohesive_preconditioner.TwoLevel.apply_split`'s passes, of the backend `gfmd.kernels.jit_backend(name)`:
    (block_load(t, starts, widths, n, out) → Σ t, out = Zᵀ t; spread_scaled_minus(c, starts, widths, n, clamp, d, t,
    dw, y): dw = D Π Z c, y = t − dw; stiff_sums_of(d, x, c, starts, widths, n, clamp, w) → Zᵀ Π D (x − Π Z c) (w: a
    scratch array numpy needs); split_spectrum(ŷ, g, û_s, x̂): x̂ = g ŷ − û_s;
    spread_subtract_dots(c, starts, widths, n, clamp, z, x, dw, dw_old, d_old) → (Σ dw s, Σ dw_old s, Σ dw d_old)
    with z = Π Z c, s = x ← x − z (None: a sum 0); move(û, d̂, α): û ← û + α d̂). One pass each with numba."""
    if jit_backend(name) == "numba":
        return (_block_load_numba, _spread_scaled_minus_numba, _stiff_sums_of_numba, _split_spectrum_numba,
                _spread_subtract_dots_numba, _move_numba)
    return (_block_load_numpy, _spread_scaled_minus_numpy, _stiff_sums_of_numpy, _split_spectrum_numpy,
            _spread_subtract_dots_numpy, _move_numpy)


def coarse_kernels(name=None):
    """(spread_scaled, stiff_sums, spread_subtract) of the backend `gfmd.kernels.jit_backend(name)`.

    Blocks: `starts` (int64, ascending) and `widths` (int64) of consecutive blocks from node 0; fields (N,) float.
    """
    if jit_backend(name) == "numba":
        return _spread_scaled_numba, _stiff_sums_numba, _spread_subtract_numba
    return _spread_scaled_numpy, _stiff_sums_numpy, _spread_subtract_numpy
