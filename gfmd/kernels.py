"""The cohesive NCG's spectral vector algebra (`gfmd.algorithms.ncg`), numpy or fused.

Per iteration the NCG needs, over the rfft spectra of nodal fields (complex, N/2 + 1 modes):

* `products`: f·s, f_old·s and f·d_old with s = K⁻¹ f (s = g f, g = 1/K(q), 0 where the mode is
  clamped), as nodal sums Σ_j a_j b_j (Parseval: interior modes count twice, q = 0 and, for even N,
  the Nyquist mode once);
* `direction`: d ← g f + β d, in place;
* `advance`: û ← û + α d, then f ← f − K û, in place (f holds rfft(T_n) on entry).

numpy needs 10 passes over the spectra for these (a temporary per product); the numba kernels
(the ``fast`` extra) one pass each, 3 in all: 0.15 ms against 0.57 ms at N = 2^17 on this machine
(docs/design/performance.md). Both give the same sums up to round-off (the fused sums are
reassociated). ``GFMD_JIT=auto|numba|numpy`` (default auto: numba where installed) chooses.

Under the two-level preconditioner (`gfmd.cohesive_preconditioner`, profiles) s = M⁻¹ f comes from the preconditioner
and d·Kd is a sum over the modes: `preconditioned_kernels` (products with s given, the direction with d·Kd, d on the
nodes), one pass each with numba.

2+1-D surfaces: the spectra are the flat rfft2 half-spectrum (`gfmd.fft`); `direction` and `advance` are
elementwise and unchanged; `products` counts the q_y = 0 column and, for even Ny, the Nyquist column once
(`surface_products`), the other modes twice.
"""

from __future__ import annotations

import os

import numpy as np

try:  # optional, the `fast` extra
    import numba
except ImportError:  # pragma: no cover - depends on the environment
    numba = None


def choose_backend(variable, name, compiled, pure):
    """The backend named by `name`, else by $`variable` (default "auto"): of `compiled`, {backend: (its package,
    installed)} in order of preference, the one asked for, or on "auto" the first installed; else `pure`
    (numpy/scipy).

    Raises ValueError naming `variable` for an unknown name, ImportError naming the package when a compiled
    backend is asked for by name but its package (a default dependency, the ``fast`` extra) is missing.
    """
    name = (name or os.environ.get(variable, "auto")).lower()
    if name not in ("auto", pure, *compiled):
        raise ValueError(f"{variable} = {name!r}: expected auto, {', '.join((pure, *compiled))}")
    if name in compiled:
        package, present = compiled[name]
        if not present:
            raise ImportError(f"{variable} = {name} but {package} is not installed "
                              f"(pip install {package}, or 'gfmd-contact[fast]')")
        return name
    if name == "auto":
        return next((b for b, (_, present) in compiled.items() if present), pure)
    return pure


def jit_backend(name=None):
    """The kernels in use: "numba" or "numpy" (from `name`, else $GFMD_JIT, default "auto")."""
    return choose_backend("GFMD_JIT", name, {"numba": ("numba", numba is not None)}, "numpy")


def _counted_once(a, b, nodes):
    """Σ Re(conj(â_n) b̂_n) over the modes counted once (q = 0; the Nyquist mode for even N)."""
    once = a[0].real * b[0].real + a[0].imag * b[0].imag
    if nodes % 2 == 0:
        once += a[-1].real * b[-1].real + a[-1].imag * b[-1].imag
    return once


def _nodal(raw, a, b, nodes):
    """Σ_j a_j b_j from raw = Σ_n Re(conj(â_n) b̂_n) over every mode."""
    return (2.0 * raw - _counted_once(a, b, nodes)) / nodes


def _raw(a, b):
    return float(np.einsum("i,i->", a.view(np.float64), b.view(np.float64)))


def nodal_dot(a, b, nodes):
    """Σ_j a_j b_j of two profiles' nodal fields from their rfft spectra (Parseval, `_nodal`)."""
    return _nodal(_raw(a, b), a, b, nodes)


def _products_numpy(f, f_old, d, g, nodes):
    s = g * f
    return (_nodal(_raw(f, s), f, s, nodes), _nodal(_raw(f_old, s), f_old, s, nodes),
            _nodal(_raw(f, d), f, d, nodes))


def _direction_numpy(f, g, beta, d):
    if beta == 0.0:
        np.multiply(g, f, out=d)
    else:
        d *= beta
        d += g * f


def _advance_numpy(uh, d, alpha, k, f):
    uh += alpha * d
    f -= k * uh


if numba is not None:
    @numba.njit(cache=True, fastmath=True)
    def _products_raw(f, f_old, d, g):  # float views: mode i is (2i, 2i + 1)
        rz = fos = fd = 0.0
        for i in range(g.size):
            fr, fi = f[2 * i], f[2 * i + 1]
            sr, si = g[i] * fr, g[i] * fi
            rz += fr * sr + fi * si
            fos += f_old[2 * i] * sr + f_old[2 * i + 1] * si
            fd += fr * d[2 * i] + fi * d[2 * i + 1]
        return rz, fos, fd

    @numba.njit(cache=True, fastmath=True)
    def _direction_fused(f, g, beta, d):
        for i in range(g.size):
            d[2 * i] = g[i] * f[2 * i] + beta * d[2 * i]
            d[2 * i + 1] = g[i] * f[2 * i + 1] + beta * d[2 * i + 1]

    @numba.njit(cache=True, fastmath=True)
    def _advance_fused(uh, d, alpha, k, f):
        for i in range(k.size):
            a = uh[2 * i] + alpha * d[2 * i]
            b = uh[2 * i + 1] + alpha * d[2 * i + 1]
            uh[2 * i], uh[2 * i + 1] = a, b
            f[2 * i] -= k[i] * a
            f[2 * i + 1] -= k[i] * b


def _products_numba(f, f_old, d, g, nodes):
    rz, fos, fd = _products_raw(f.view(np.float64), f_old.view(np.float64), d.view(np.float64), g)
    s0, s_end = g[0] * f[0], g[-1] * f[-1]  # the once-counted modes of s, for the corrections
    s_ends = np.array([s0, s_end])
    return (_nodal(rz, f[[0, -1]], s_ends, nodes), _nodal(fos, f_old[[0, -1]], s_ends, nodes),
            _nodal(fd, f[[0, -1]], d[[0, -1]], nodes))


def _direction_numba(f, g, beta, d):
    _direction_fused(f.view(np.float64), g, float(beta), d.view(np.float64))


def _advance_numba(uh, d, alpha, k, f):
    _advance_fused(uh.view(np.float64), d.view(np.float64), float(alpha), k, f.view(np.float64))


def _preconditioned_products_numpy(f, f_old, d, s, nodes):
    return nodal_dot(f, s, nodes), nodal_dot(f_old, s, nodes), nodal_dot(f, d, nodes)


def _direction_energy_numpy(s, beta, d, k, nodes):
    if beta == 0.0:
        d[...] = s
    else:
        d *= beta
        d += s
    return nodal_dot(d, k * d, nodes)


def _stiffness_products_numpy(x, x_old, d, k, nodes):
    kx = k * x
    return nodal_dot(x, kx, nodes), nodal_dot(x_old, kx, nodes), nodal_dot(d, kx, nodes)


def _combine_numpy(s, beta, d):
    np.multiply(d, beta, out=d)
    return np.add(s, d, out=s)


if numba is not None:
    @numba.njit(cache=True, fastmath=True)
    def _preconditioned_raw(f, f_old, d, s):  # float views: Σ Re(conj(a) b) is the sum over the floats
        rz = fos = fd = 0.0
        for i in range(s.size):
            rz += f[i] * s[i]
            fos += f_old[i] * s[i]
            fd += f[i] * d[i]
        return rz, fos, fd

    @numba.njit(cache=True, fastmath=True)
    def _direction_energy_raw(s, beta, d, k):  # d ← s + β d; Σ_n k_n |d_n|²
        energy = 0.0
        for i in range(k.size):
            dr = s[2 * i] + beta * d[2 * i]
            di = s[2 * i + 1] + beta * d[2 * i + 1]
            d[2 * i], d[2 * i + 1] = dr, di
            energy += k[i] * (dr * dr + di * di)
        return energy

    @numba.njit(cache=True, fastmath=True)
    def _stiffness_raw(x, x_old, d, k):  # Σ_n k_n Re(conj(a_n) x_n) for a = x, x_old, d
        xx = ox = dx = 0.0
        for i in range(k.size):
            kr, ki = k[i] * x[2 * i], k[i] * x[2 * i + 1]
            xx += x[2 * i] * kr + x[2 * i + 1] * ki
            ox += x_old[2 * i] * kr + x_old[2 * i + 1] * ki
            dx += d[2 * i] * kr + d[2 * i + 1] * ki
        return xx, ox, dx

    @numba.njit(cache=True, fastmath=True)
    def _combine_fused(s, beta, d):  # s ← s + β d
        for i in range(s.size):
            s[i] += beta * d[i]


def _preconditioned_products_numba(f, f_old, d, s, nodes):
    rz, fos, fd = _preconditioned_raw(f.view(np.float64), f_old.view(np.float64), d.view(np.float64),
                                      s.view(np.float64))
    ends = [0, -1]
    return (_nodal(rz, f[ends], s[ends], nodes), _nodal(fos, f_old[ends], s[ends], nodes),
            _nodal(fd, f[ends], d[ends], nodes))


def _direction_energy_numba(s, beta, d, k, nodes):
    energy = _direction_energy_raw(s.view(np.float64), float(beta), d.view(np.float64), k)
    return _nodal(energy, d[[0, -1]], k[[0, -1]] * d[[0, -1]], nodes)


def _stiffness_products_numba(x, x_old, d, k, nodes):
    xx, ox, dx = _stiffness_raw(x.view(np.float64), x_old.view(np.float64), d.view(np.float64), k)
    ends = [0, -1]
    kx = k[ends] * x[ends]
    return _nodal(xx, x[ends], kx, nodes), _nodal(ox, x_old[ends], kx, nodes), _nodal(dx, d[ends], kx, nodes)


def _combine_numba(s, beta, d):
    _combine_fused(s, float(beta), d)
    return s


def preconditioned_kernels(name=None):
    """The NCG's algebra under a preconditioner other than K⁻¹ (`gfmd.cohesive_preconditioner`; profiles), of the
    backend `jit_backend(name)`: (products(f, f_old, d, s, nodes): f·s, f_old·s, f·d as nodal sums (s = M⁻¹ f given);
    direction_energy(s, β, d, k, nodes): d ← s + β d in place, returning d·Kd; combine(s, β, d): s ← s + β d on the
    nodes, returning s (d's values may be overwritten); stiffness_products(x, x_old, d, k, nodes): x·Kx, x_old·Kx,
    d·Kx as nodal sums, the spectral parts of the split products, `gfmd.cohesive_preconditioner.split_products`).
    numba: one pass each, as `ncg_kernels` (in place of three
    nodal_dot passes, a direction pass, K d and its dot, and s + β d into a new array: a whole 201-step ramp at 2^17,
    φn* = 0.15, CPU × 0.969 ± 0.019, the same iterations; docs/design/performance.md)."""
    if jit_backend(name) == "numba":
        return (_preconditioned_products_numba, _direction_energy_numba, _combine_numba,
                _stiffness_products_numba)
    return _preconditioned_products_numpy, _direction_energy_numpy, _combine_numpy, _stiffness_products_numpy


def once_counted_modes(grid):
    """Flat indices of the rfft2 half-spectrum modes (grid (Nx, Ny)) that hold their own conjugate:
    the q_y = 0 column and, for even Ny, the Nyquist column."""
    nx, ny = grid
    half = ny // 2 + 1
    cols = [0] + ([half - 1] if ny % 2 == 0 else [])
    return (np.arange(nx)[:, None] * half + np.array(cols)[None, :]).ravel()


def surface_products(raw_products, once):
    """`products` on flat 2+1-D spectra: the raw sums Σ Re(conj(â) b̂) over every mode of `raw_products`,
    corrected to nodal sums Σ_j a_j b_j = (2 raw − Σ_once Re(conj(â) b̂))/N (Parseval on the half-spectrum)."""

    def once_sum(a, b):
        a, b = a[once], b[once]
        return float(np.sum(a.real * b.real + a.imag * b.imag))

    def products(f, f_old, d, g, nodes):
        rz, fos, fd = raw_products(f, f_old, d, g)
        s = g[once] * f[once]
        f_once, fo_once = f[once], f_old[once]
        return ((2.0 * rz - float(np.sum(f_once.real * s.real + f_once.imag * s.imag))) / nodes,
                (2.0 * fos - float(np.sum(fo_once.real * s.real + fo_once.imag * s.imag))) / nodes,
                (2.0 * fd - once_sum(f, d)) / nodes)

    return products


def _raw_numpy(f, f_old, d, g):
    s = g * f
    return _raw(f, s), _raw(f_old, s), _raw(f, d)


def _raw_numba(f, f_old, d, g):
    return _products_raw(f.view(np.float64), f_old.view(np.float64), d.view(np.float64), g)


def ncg_kernels(name=None, grid=None):
    """(products, direction, advance) of the backend `jit_backend(name)` (module docstring); grid (Nx, Ny):
    those of a 2+1-D surface's flat half-spectrum."""
    numba_backend = jit_backend(name) == "numba"
    if grid is not None and len(grid) > 1:
        raw = _raw_numba if numba_backend else _raw_numpy
        return ((surface_products(raw, once_counted_modes(grid)),)
                + ((_direction_numba, _advance_numba) if numba_backend else (_direction_numpy, _advance_numpy)))
    if numba_backend:
        return _products_numba, _direction_numba, _advance_numba
    return _products_numpy, _direction_numpy, _advance_numpy
