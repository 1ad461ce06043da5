"""The real FFT the GFMD algorithms use, counting pairs, and the nodal dot products.

Backend: scipy.fft, or ducc0 where installed (the ``fast`` extra; 1.4–2× faster rfft/irfft pairs
measured here); ``GFMD_FFT=scipy|ducc0|auto`` (default auto) chooses (`fft_backend`). The hard-wall
CGs, the cohesive NCG, FIRE on a law with a traction function and Newton–Krylov go through `Fft`;
the projected dynamics of the hard wall and of the cohesive wall, and `gfmd.stopping.finish`, call
scipy.fft directly.
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


class Fft:
    """rfft / irfft along the last axis (length n) through the chosen backend, counting pairs."""

    def __init__(self, n, backend=None):
        self.n, self.backend, self.calls = n, fft_backend(backend), 0
        self._spectrum = None  # `apply_to`'s preallocated spectrum (ducc0)

    def rfft(self, x):
        self.calls += 1
        if self.backend == "ducc0":
            return _ducc_fft.r2c(np.ascontiguousarray(x), axes=(-1,), forward=True)
        return scipy.fft.rfft(x, axis=-1)

    def irfft(self, x_hat):
        self.calls += 1
        if self.backend == "ducc0":
            return _ducc_fft.c2r(np.ascontiguousarray(x_hat), axes=(-1,), forward=False, lastsize=self.n, inorm=2)
        return scipy.fft.irfft(x_hat, n=self.n, axis=-1)

    def apply(self, kernel, x):
        """irfft(kernel · rfft(x)): one pair."""
        x_hat = self.rfft(x)
        x_hat *= kernel
        return self.irfft(x_hat)

    def apply_to(self, kernel, x, out):
        """out ← irfft(kernel · rfft(x)) for 1-D x: one pair; with ducc0 single-threaded and without
        allocating (preallocated spectrum, c2r into `out`, overwriting the spectrum)."""
        self.calls += 2
        if self.backend == "ducc0":
            if self._spectrum is None:
                self._spectrum = np.empty(self.n // 2 + 1, complex)
            spectrum = _ducc_fft.r2c(x, axes=(-1,), forward=True, out=self._spectrum, nthreads=1)
            spectrum *= kernel
            return _ducc_fft.c2r(spectrum, axes=(-1,), forward=False, lastsize=self.n, inorm=2, out=out,
                                 nthreads=1, allow_overwriting_input=True)
        out[...] = scipy.fft.irfft(kernel * scipy.fft.rfft(x), n=self.n)
        return out

    @property
    def pairs(self):
        return self.calls / 2


def dot(a, b):
    """Σ a_j b_j without BLAS: multi-threaded BLAS dot products of 1-D arrays stalled
    the solver 4× on a loaded 2-core machine (measured: 15.2 s vs 3.6 s per step at N = 2^17)."""
    return float(np.einsum("i,i->", a, b))


def spectral_weights(nodes):
    """w_n with Σ_j a_j b_j = (1/N) Σ_n w_n Re(conj(â_n) b̂_n) for rfft spectra."""
    w = np.full(nodes // 2 + 1, 2.0)
    w[0] = 1.0
    if nodes % 2 == 0:
        w[-1] = 1.0
    return w
