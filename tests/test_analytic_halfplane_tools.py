"""Tests of the numerical half-plane tools used to cross-check the closed forms
(reference.analytic._halfplane), against each other and the sign convention of §0/§1.1."""

import math

import numpy as np
import pytest

from reference.analytic._halfplane import fft_displacement, flamant_uz_difference, periodic_uz

E_STAR = 2.0e9
L = 1.0e-3
WIDTH = 2.0e-5  # Gaussian load width, ≫ grid spacing L/N


def gauss(s):
    return 1e6 * np.exp(-0.5 * (s / WIDTH) ** 2)


def test_fft_and_periodic_quadrature_agree_and_sign():
    n = 2**14
    x = (np.arange(n) - n // 2) * L / n
    u = fft_displacement(gauss(x), L, E_STAR)
    assert abs(u.mean()) < 1e-20  # q = 0 mode clamped
    support = (-12 * WIDTH, 12 * WIDTH)  # Gaussian tail e^{-72}: negligible
    for j in (n // 2, n // 2 + 300, n // 4):
        uq = periodic_uz(gauss, x[j], support, L, E_STAR)
        # smooth, well-resolved load: spectral accuracy; measured ~1e-12 relative
        assert u[j] == pytest.approx(uq, rel=1e-9, abs=1e-9 * abs(u[n // 2]))
    # compressive load pushes the surface down (u_z < 0) under the load: Convention A
    assert u[n // 2] < 0 and u[n // 2] == u.min()


def test_isolated_and_periodic_kernels_agree_for_large_period():
    # ln|2 sin(πs/L)| = ln(2π|s|/L) + O((s/L)²): differences of u_z agree to O((x/L)²)
    support = (-12 * WIDTH, 12 * WIDTH)
    x1, x2 = 3 * WIDTH, 0.0
    d_iso = flamant_uz_difference(gauss, x1, x2, support, E_STAR)
    d_per = periodic_uz(gauss, x1, support, L, E_STAR) - periodic_uz(gauss, x2, support, L, E_STAR)
    assert d_iso > 0  # farther from the load the surface is higher
    assert d_iso == pytest.approx(d_per, rel=10 * (12 * WIDTH / L) ** 2)


def test_line_load_log_profile():
    # §1.1: u_z(x) − ū = (2P/(πE*)) ln|2 sin(πx/L)| for a narrow load of resultant P;
    # width σ = L/1000 changes the log by ≈ −σ²/(2x²) (5e-5 at x = 0.1L): tolerance 1e-3
    sigma = L / 1000

    def narrow(s):
        return np.exp(-0.5 * (s / sigma) ** 2)

    P = sigma * math.sqrt(2 * math.pi)
    for x in (0.1 * L, 0.37 * L):
        uq = periodic_uz(narrow, x, (-12 * sigma, 12 * sigma), L, E_STAR)
        expected = 2 * P / (math.pi * E_STAR) * math.log(abs(2 * math.sin(math.pi * x / L)))
        assert uq == pytest.approx(expected, rel=1e-3)
