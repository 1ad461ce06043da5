"""Numerical half-plane displacement tools for cross-checking the closed forms (private).

Independent of the formulas in this package: they only use the elastic
Green's functions of shared/reference-formulas.md §1.1 (Convention A,
u_z > 0 upward, p > 0 compressive), so the tests can check that a closed-form
pressure really produces the displacement of the indenter it claims to.

* FFT, periodic cell:  û_z(q) = −2 p̂(q)/(E*|q|), q ≠ 0, ū_z = 0.
* Flamant line load (isolated half-plane): u_z(x) = (2P/(πE*)) ln|x − s| + C.
* Periodic line-load array: u_z(x) − ū_z = (2P/(πE*)) ln|2 sin(π(x − s)/L)|.
"""

import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad


def fft_displacement(p, period, e_star):
    """u_z [m] on N equispaced nodes of a periodic cell from nodal pressures p [Pa] (mean u_z = 0)."""
    p = np.asarray(p, dtype=float)
    n = p.size
    q = 2.0 * np.pi * np.fft.rfftfreq(n, period / n)
    p_hat = np.fft.rfft(p)
    u_hat = np.zeros_like(p_hat)
    u_hat[1:] = -2.0 * p_hat[1:] / (e_star * q[1:])
    return np.fft.irfft(u_hat, n)


def _integrate(f, lo, hi, breakpoints):
    pts = sorted({lo, hi, *[b for b in breakpoints if lo < b < hi]})
    total = 0.0
    with warnings.catch_warnings():
        # QUADPACK warns when round-off stops it short of epsrel; the callers
        # compare the result with closed forms at a stated tolerance instead.
        warnings.simplefilter("ignore", IntegrationWarning)
        for s0, s1 in zip(pts[:-1], pts[1:]):
            val, _ = quad(f, s0, s1, limit=400, epsabs=0.0, epsrel=1e-10)
            total += val
    return total


def flamant_uz_difference(pressure, x1, x2, support, e_star, breakpoints=()):
    """u_z(x1) − u_z(x2) [m] on an isolated half-plane for pressure p(s) [Pa] on `support` (lo, hi).

    (2/(πE*)) ∫ p(s) [ln|x1 − s| − ln|x2 − s|] ds by adaptive quadrature; list
    the points where p is singular or kinked in `breakpoints`.
    """
    lo, hi = support

    def f(s):
        return pressure(s) * (np.log(abs(x1 - s)) - np.log(abs(x2 - s)))

    return 2.0 / (np.pi * e_star) * _integrate(f, lo, hi, [x1, x2, *breakpoints])


def periodic_uz(pressure, x, support, period, e_star, breakpoints=()):
    """u_z(x) − ū_z [m] of a periodic half-plane for pressure p(s) [Pa] on `support` within one period.

    (2/(πE*)) ∫ p(s) ln|2 sin(π(x − s)/L)| ds by adaptive quadrature (the
    kernel has zero mean, so the mean pressure does not shift ū_z).
    """
    lo, hi = support

    def f(s):
        return pressure(s) * np.log(abs(2.0 * np.sin(np.pi * (x - s) / period)))

    return 2.0 / (np.pi * e_star) * _integrate(f, lo, hi, [x, *breakpoints])
