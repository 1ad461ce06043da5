"""FIRE's per-iteration spectral algebra (`gfmd.algorithms.dynamics`) in three passes, numpy or fused (numba).

On mass-weighted modes (M_q, 2×2 blocks (a b; b̄ d) of `gfmd.problem.Elastic` for the coupled law's (x, z)
unknowns, one block (m,) for a normal-only law), w_q the rfft weights (Σ_j a_j b_j = (1/N) Σ_q w_q Re(conj â_q b̂_q)):

* `force_power`: f̂ = t̂ − K û (the q = 0 mode 0 where clamped) into t̂'s array, and FIRE's power P = f·v;
* `accelerate`: a = M⁻¹ f̂, v ← v + Δt a, and the norms f·a and v·(M v) of FIRE's mixing;
* `mix_move`: v ← keep·v + β a (the q = 0 mode 0 where clamped), û ← û + Δt v.

numpy does each as before (a temporary per operation: ≈ 15 passes over the spectra an iteration); the fused kernels
(1+1-D coupled profiles, c = 2: the coupled event steps' FIRE) one loop each, on the blocks' real split form
(`gfmd.coupled_kernels.Blocks.split`: a, d real, b imaginary, as an isotropic body's) where they have one: the same
numbers bit for bit. ``GFMD_JIT`` chooses (`gfmd.kernels.jit_backend`). Measured: docs/design/performance.md.
"""

from __future__ import annotations

import numpy as np

from .coupled_kernels import float_views
from .kernels import jit_backend, numba

#: the fused kernels where they apply (False: numpy's passes everywhere, the earlier FIRE; for benchmarks)
FUSED = True


def _weighted(w, a, b):
    return float(np.sum(w * (np.conj(a) * b).real))


def _force_power_numpy(t_hat, k, u_hat, v, w, clamp, apply):
    t_hat -= apply(k, u_hat)
    if clamp:
        t_hat[:, 0] = 0.0
    return _weighted(w, t_hat, v)


def _accelerate_numpy(f_hat, inv_m, m, v, dt, w, apply):
    acc = apply(inv_m, f_hat)
    v += dt * acc
    return acc, _weighted(w, f_hat, acc), _weighted(w, v, apply(m, v))


def _mix_move_numpy(v, acc, keep, beta, u_hat, dt, clamp):
    if beta != 0.0 or keep != 1.0:
        v *= keep
        v += beta * acc
    if clamp:
        v[:, 0] = 0.0
    u_hat += dt * v


if numba is not None:
    @numba.njit(cache=True)
    def _force_power_kernel(t_hat, a, b, d, u_hat, v, w, clamp):
        power = 0.0
        for i in range(w.size):
            u0, u1 = u_hat[0, i], u_hat[1, i]
            f0 = t_hat[0, i] - (a[i] * u0 + b[i] * u1)
            f1 = t_hat[1, i] - (b[i].conjugate() * u0 + d[i] * u1)
            if clamp and i == 0:
                f0 = 0.0j
                f1 = 0.0j
            t_hat[0, i] = f0
            t_hat[1, i] = f1
            power += w[i] * (f0.real * v[0, i].real + f0.imag * v[0, i].imag
                             + f1.real * v[1, i].real + f1.imag * v[1, i].imag)
        return power

    @numba.njit(cache=True)
    def _accelerate_kernel(f_hat, ia, ib, id_, a, b, d, v, dt, w, acc):
        f_norm = 0.0
        v_norm = 0.0
        for i in range(w.size):
            f0, f1 = f_hat[0, i], f_hat[1, i]
            g0 = ia[i] * f0 + ib[i] * f1
            g1 = ib[i].conjugate() * f0 + id_[i] * f1
            acc[0, i] = g0
            acc[1, i] = g1
            v0 = v[0, i] + dt * g0
            v1 = v[1, i] + dt * g1
            v[0, i] = v0
            v[1, i] = v1
            m0 = a[i] * v0 + b[i] * v1
            m1 = b[i].conjugate() * v0 + d[i] * v1
            f_norm += w[i] * (f0.real * g0.real + f0.imag * g0.imag + f1.real * g1.real + f1.imag * g1.imag)
            v_norm += w[i] * (v0.real * m0.real + v0.imag * m0.imag + v1.real * m1.real + v1.imag * m1.imag)
        return f_norm, v_norm

    # the same two passes on `Blocks.split` (Re a, Im b, Re d) and float views of the spectra (mode i: 2i, 2i + 1):
    # every product and sum of the complex ones above but those with the blocks' zero parts, in the same order
    @numba.njit(cache=True)
    def _force_power_split_kernel(t, a, b, d, u, v, w, clamp):
        power = 0.0
        for i in range(w.size):
            j = 2 * i
            u0r, u0i, u1r, u1i = u[0, j], u[0, j + 1], u[1, j], u[1, j + 1]
            f0r = t[0, j] - (a[i] * u0r + (-(b[i] * u1i)))
            f0i = t[0, j + 1] - (a[i] * u0i + b[i] * u1r)
            f1r = t[1, j] - (b[i] * u0i + d[i] * u1r)
            f1i = t[1, j + 1] - (-(b[i] * u0r) + d[i] * u1i)
            if clamp and i == 0:
                f0r = f0i = f1r = f1i = 0.0
            t[0, j], t[0, j + 1], t[1, j], t[1, j + 1] = f0r, f0i, f1r, f1i
            power += w[i] * (f0r * v[0, j] + f0i * v[0, j + 1] + f1r * v[1, j] + f1i * v[1, j + 1])
        return power

    @numba.njit(cache=True)
    def _accelerate_split_kernel(f, ia, ib, id_, a, b, d, v, dt, w, acc):
        f_norm = 0.0
        v_norm = 0.0
        for i in range(w.size):
            j = 2 * i
            f0r, f0i, f1r, f1i = f[0, j], f[0, j + 1], f[1, j], f[1, j + 1]
            g0r = ia[i] * f0r + (-(ib[i] * f1i))
            g0i = ia[i] * f0i + ib[i] * f1r
            g1r = ib[i] * f0i + id_[i] * f1r
            g1i = -(ib[i] * f0r) + id_[i] * f1i
            acc[0, j], acc[0, j + 1], acc[1, j], acc[1, j + 1] = g0r, g0i, g1r, g1i
            v0r, v0i = v[0, j] + dt * g0r, v[0, j + 1] + dt * g0i
            v1r, v1i = v[1, j] + dt * g1r, v[1, j + 1] + dt * g1i
            v[0, j], v[0, j + 1], v[1, j], v[1, j + 1] = v0r, v0i, v1r, v1i
            m0r, m0i = a[i] * v0r + (-(b[i] * v1i)), a[i] * v0i + b[i] * v1r
            m1r, m1i = b[i] * v0i + d[i] * v1r, -(b[i] * v0r) + d[i] * v1i
            f_norm += w[i] * (f0r * g0r + f0i * g0i + f1r * g1r + f1i * g1i)
            v_norm += w[i] * (v0r * m0r + v0i * m0i + v1r * m1r + v1i * m1i)
        return f_norm, v_norm

    @numba.njit(cache=True)
    def _mix_move_kernel(v, acc, keep, beta, u_hat, dt, clamp):
        for c in range(v.shape[0]):
            for i in range(v.shape[1]):
                x = keep * v[c, i] + beta * acc[c, i]
                if clamp and i == 0:
                    x = 0.0j
                v[c, i] = x
                u_hat[c, i] += dt * x


def _largest_change_numpy(u, u_prev):
    return float(np.max(np.abs(u - u_prev)))


if numba is not None:
    @numba.njit(cache=True)
    def _largest_change_kernel(u, u_prev):
        largest = 0.0
        for i in range(u.size):
            d = abs(u[i] - u_prev[i])
            if d > largest or d != d:  # a NaN wins, as in numpy's max
                largest = d
                if d != d:
                    break
        return largest


def largest_change(name=None):
    """max_j |u_j − u_prev,j| of two nodal arrays (FIRE's trust region): numpy's passes or one fused loop
    (`jit_backend(name)`); the same number either way (a max is exact), NaN where a difference is NaN."""
    if FUSED and jit_backend(name) == "numba":
        return lambda u, u_prev: float(_largest_change_kernel(u.reshape(-1), u_prev.reshape(-1)))
    return _largest_change_numpy


def fire_kernels(name=None, components=2):
    """(force_power, accelerate, mix_move) of `jit_backend(name)`; the fused ones for the coupled law's two components
    (profiles only: 2+1-D surfaces are normal-only), numpy otherwise. Signatures: force_power(t_hat, k_blocks, u_hat, v, w, clamp)
    → P (f̂ into t_hat); accelerate(f_hat, inv_blocks, mass_blocks, v, dt, w, acc) → (acc, f·a, v·M v);
    mix_move(v, acc, keep, beta, u_hat, dt, clamp). Blocks: `gfmd.problem.Elastic`'s tuples (`Blocks`); acc: an array
    of û's shape the fused accelerate fills (numpy returns its own)."""
    if FUSED and jit_backend(name) == "numba" and components == 2:
        def force_power(t_hat, k, u_hat, v, w, clamp):
            split = getattr(k, "split", None)
            if split is not None and float_views(t_hat, u_hat, v):
                return _force_power_split_kernel(t_hat.view(np.float64), *split, u_hat.view(np.float64),
                                                 v.view(np.float64), w, clamp)
            return _force_power_kernel(t_hat, *k, u_hat, v, w, clamp)

        def accelerate(f_hat, inv_m, m, v, dt, w, acc):
            split, split_m = getattr(inv_m, "split", None), getattr(m, "split", None)
            if split is not None and split_m is not None and float_views(f_hat, v, acc):
                f_norm, v_norm = _accelerate_split_kernel(f_hat.view(np.float64), *split, *split_m, v.view(np.float64),
                                                          dt, w, acc.view(np.float64))
            else:
                f_norm, v_norm = _accelerate_kernel(f_hat, *inv_m, *m, v, dt, w, acc)
            return acc, f_norm, v_norm

        return force_power, accelerate, _mix_move_kernel
    from .coupled_kernels import coupled_kernels
    block_times = coupled_kernels("numpy")[0]

    def apply(blocks, x):
        if len(blocks) == 1:
            return blocks[0] * x
        return block_times(*blocks, x, np.empty(x.shape, np.result_type(x, *blocks)))

    def force_power(t_hat, k, u_hat, v, w, clamp):
        return _force_power_numpy(t_hat, k, u_hat, v, w, clamp, apply)

    def accelerate(f_hat, inv_m, m, v, dt, w, acc):
        return _accelerate_numpy(f_hat, inv_m, m, v, dt, w, apply)

    return force_power, accelerate, _mix_move_numpy
