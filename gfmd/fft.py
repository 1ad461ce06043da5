"""The real FFT the GFMD algorithms use, counting pairs, and the nodal dot products.

Backend: scipy.fft, or ducc0 where installed (the ``fast`` extra; 1.4–2× faster rfft/irfft pairs
measured here); ``GFMD_FFT=scipy|ducc0|auto`` (default auto) chooses (`fft_backend`). The hard-wall
CGs, the cohesive NCG, FIRE on a law with a traction function and Newton–Krylov go through `Fft`;
the projected dynamics of the hard wall and of the cohesive wall, and `gfmd.stopping.finish`, call
scipy.fft directly (through `rfft_nodes` / `irfft_nodes`, which are exactly those calls in 1+1-D).

2+1-D surfaces (a `contact.model.Model` with shape (Nx, Ny)): the algorithms see nodal fields as flat
vectors of the N = Nx·Ny nodes (row-major, x first) and spectra as flat vectors of the Nx·(Ny//2 + 1)
modes of the rfft2 half-spectrum (`gfmd.problem.flat_problem`); `Fft` and the helpers here reshape
to the grid, transform over its axes (rfftn / irfftn over (-2, -1)) and flatten again (views, no
copies). One rfft2/irfft2 pair counts as one pair, as in 1+1-D.
"""

from __future__ import annotations

import numpy as np
import scipy.fft

try:  # optional, the `fast` extra: a faster real FFT (measured 1.4–2× per rfft/irfft pair here)
    import ducc0.fft as _ducc_fft
except ImportError:  # pragma: no cover - depends on the environment
    _ducc_fft = None

from . import kernels


def fft_backend(name=None):
    """The FFT backend in use: "ducc0" or "scipy" (from `name`, else $GFMD_FFT, default "auto")."""
    return kernels.choose_backend("GFMD_FFT", name, "ducc0", "scipy", _ducc_fft is not None)


def _grid(grid):
    """(N,) for a node count or a 1-tuple, (Nx, Ny) for a 2-D grid."""
    return (int(grid),) if np.ndim(grid) == 0 else tuple(int(g) for g in grid)


def _half_spectrum(grid):
    return grid[:-1] + (grid[-1] // 2 + 1,)


def rfft_nodes(x, grid):
    """The rfft of nodal fields x (..., N) by scipy.fft: scipy.fft.rfft(x) on a profile; on a grid (Nx, Ny)
    rfftn over the grid's axes, flattened to (..., Nx·(Ny//2 + 1))."""
    grid = _grid(grid)
    if len(grid) == 1:
        return scipy.fft.rfft(x, axis=-1)
    x = np.asarray(x)
    lead = x.shape[:-1]
    return scipy.fft.rfftn(x.reshape(lead + grid), axes=(-2, -1)).reshape(lead + (-1,))


def irfft_nodes(x_hat, grid):
    """The inverse of `rfft_nodes` (flat nodal fields (..., N)) by scipy.fft."""
    grid = _grid(grid)
    if len(grid) == 1:
        return scipy.fft.irfft(x_hat, n=grid[0], axis=-1)
    x_hat = np.asarray(x_hat)
    lead = x_hat.shape[:-1]
    return scipy.fft.irfftn(x_hat.reshape(lead + _half_spectrum(grid)), s=grid, axes=(-2, -1)).reshape(lead + (-1,))


class Fft:
    """rfft / irfft along the last axis (length n) through the chosen backend, counting pairs.

    grid = (Nx, Ny): a 2+1-D surface; nodal fields (..., n = Nx·Ny) and spectra (..., Nx·(Ny//2 + 1))
    are flat and transformed over the grid's two axes (module docstring). grid None or (n,): 1+1-D.
    """

    def __init__(self, n, backend=None, grid=None):
        self.n, self.backend, self.calls = n, fft_backend(backend), 0
        self._spectrum = None  # `apply_to`'s preallocated spectrum (ducc0)
        self.grid = _grid(grid) if grid is not None and len(_grid(grid)) > 1 else None
        if self.grid is not None:
            if int(np.prod(self.grid)) != n:
                raise ValueError(f"Fft: grid {self.grid} does not hold n = {n} nodes")
            self.axes = (-2, -1)
            self.spectrum_grid = _half_spectrum(self.grid)

    def rfft(self, x):
        self.calls += 1
        if self.grid is not None:
            return self._rfft2(x)
        if self.backend == "ducc0":
            return _ducc_fft.r2c(np.ascontiguousarray(x), axes=(-1,), forward=True)
        return scipy.fft.rfft(x, axis=-1)

    def irfft(self, x_hat):
        self.calls += 1
        if self.grid is not None:
            return self._irfft2(x_hat)
        if self.backend == "ducc0":
            return _ducc_fft.c2r(np.ascontiguousarray(x_hat), axes=(-1,), forward=False, lastsize=self.n, inorm=2)
        return scipy.fft.irfft(x_hat, n=self.n, axis=-1)

    def _rfft2(self, x):
        x = np.ascontiguousarray(x)
        lead = x.shape[:-1]
        x = x.reshape(lead + self.grid)
        if self.backend == "ducc0":
            out = _ducc_fft.r2c(x, axes=self.axes, forward=True)
        else:
            out = scipy.fft.rfftn(x, axes=self.axes)
        return out.reshape(lead + (-1,))

    def _irfft2(self, x_hat):
        x_hat = np.ascontiguousarray(x_hat)
        lead = x_hat.shape[:-1]
        x_hat = x_hat.reshape(lead + self.spectrum_grid)
        if self.backend == "ducc0":
            out = _ducc_fft.c2r(x_hat, axes=self.axes, forward=False, lastsize=self.grid[-1], inorm=2)
        else:
            out = scipy.fft.irfftn(x_hat, s=self.grid, axes=self.axes)
        return out.reshape(lead + (-1,))

    def apply(self, kernel, x):
        """irfft(kernel · rfft(x)): one pair."""
        x_hat = self.rfft(x)
        x_hat *= kernel
        return self.irfft(x_hat)

    def apply_to(self, kernel, x, out):
        """out ← irfft(kernel · rfft(x)) for 1-D x: one pair; with ducc0 single-threaded and without
        allocating (preallocated spectrum, c2r into `out`, overwriting the spectrum)."""
        self.calls += 2
        if self.grid is not None:
            return self._apply_to2(kernel, x, out)
        if self.backend == "ducc0":
            if self._spectrum is None:
                self._spectrum = np.empty(self.n // 2 + 1, complex)
            spectrum = _ducc_fft.r2c(x, axes=(-1,), forward=True, out=self._spectrum, nthreads=1)
            spectrum *= kernel
            return _ducc_fft.c2r(spectrum, axes=(-1,), forward=False, lastsize=self.n, inorm=2, out=out,
                                 nthreads=1, allow_overwriting_input=True)
        out[...] = scipy.fft.irfft(kernel * scipy.fft.rfft(x), n=self.n)
        return out

    def _apply_to2(self, kernel, x, out):
        """`apply_to` on a 2-D grid (flat x, out of n nodes; kernel flat over the half-spectrum)."""
        if self.backend == "ducc0":
            if self._spectrum is None:
                self._spectrum = np.empty(self.spectrum_grid, complex)
            spectrum = _ducc_fft.r2c(np.ascontiguousarray(x).reshape(self.grid), axes=self.axes, forward=True,
                                     out=self._spectrum, nthreads=1)
            spectrum.reshape(-1)[...] *= kernel
            _ducc_fft.c2r(spectrum, axes=self.axes, forward=False, lastsize=self.grid[-1], inorm=2,
                          out=out.reshape(self.grid), nthreads=1, allow_overwriting_input=True)
            return out
        spectrum = scipy.fft.rfftn(np.reshape(x, self.grid), axes=self.axes)
        spectrum *= np.reshape(kernel, self.spectrum_grid)
        out[...] = scipy.fft.irfftn(spectrum, s=self.grid, axes=self.axes).reshape(-1)
        return out

    @property
    def pairs(self):
        return self.calls / 2


def dot(a, b):
    """Σ a_j b_j without BLAS: multi-threaded BLAS dot products of 1-D arrays stalled
    the solver 4× on a loaded 2-core machine (measured: 15.2 s vs 3.6 s per step at N = 2^17)."""
    if a.ndim != 1:  # 2+1-D fields on their grid: the same sum over the flattened nodes
        return float(np.einsum("i,i->", a.ravel(), b.ravel()))
    return float(np.einsum("i,i->", a, b))


def spectral_weights(nodes):
    """w_n with Σ_j a_j b_j = (1/N) Σ_n w_n Re(conj(â_n) b̂_n) for rfft spectra.

    `nodes`: N (or (N,)) for a profile; a grid (Nx, Ny) for the rfft2 half-spectrum of a surface, flat
    (Nx·(Ny//2 + 1),): every mode with 0 < q_y-index < Ny/2 stands for itself and its conjugate (w = 2),
    the q_y = 0 column and, for even Ny, the Nyquist column hold their own conjugates (w = 1).
    """
    grid = _grid(nodes)
    if len(grid) > 1:
        w = np.full(_half_spectrum(grid), 2.0)
        w[..., 0] = 1.0
        if grid[-1] % 2 == 0:
            w[..., -1] = 1.0
        return w.reshape(-1)
    nodes = grid[0]
    w = np.full(nodes // 2 + 1, 2.0)
    w[0] = 1.0
    if nodes % 2 == 0:
        w[-1] = 1.0
    return w
