"""Tests of reference.analytic.westergaard (reference-formulas §3).

Independent checks: the displacement produced by the closed-form pressure
through the periodic half-plane kernel, (a) by FFT û_z = −2p̂/(E*|q|) on
N = 2¹⁶ nodes, (b) by adaptive quadrature of the periodic line-load kernel.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad

from reference.analytic import hertz, westergaard as wg
from reference.analytic._halfplane import fft_displacement, periodic_uz

E_STAR = 1.7e9  # Pa
LAM = 2.0e-4  # m
H0 = 3.0e-6  # m (amplitude)
PS = math.pi * E_STAR * H0 / LAM


def test_full_contact_pressure():
    assert wg.full_contact_pressure(H0, LAM, E_STAR) == pytest.approx(PS, rel=1e-15)


@settings(max_examples=60, derandomize=True, deadline=None)
@given(st.floats(0.0, 0.5))
def test_half_width_round_trip(a_over_lam):
    # arcsin/sin inverse: round-off, except near a = λ/2 where dp̄/da → 0 (tolerance in a ~ √eps)
    a = a_over_lam * LAM
    pbar = wg.mean_pressure(a, H0, LAM, E_STAR)
    assert wg.half_width(pbar, H0, LAM, E_STAR) == pytest.approx(a, rel=1e-7, abs=1e-8 * LAM)


def test_half_width_full_contact_branch():
    assert wg.half_width(PS, H0, LAM, E_STAR) == pytest.approx(LAM / 2, rel=1e-15)
    assert wg.half_width(3 * PS, H0, LAM, E_STAR) == LAM / 2
    assert wg.half_width(0.0, H0, LAM, E_STAR) == 0.0


@pytest.mark.parametrize("P", [0.05, 0.3, 0.7])
def test_pressure_integrates_to_mean_pressure(P):
    pbar = P * PS
    a = wg.half_width(pbar, H0, LAM, E_STAR)
    # x = a sin θ removes the square-root edge: quad converges to ~1e-14
    total, _ = quad(lambda th: wg.pressure(a * math.sin(th), pbar, H0, LAM, E_STAR) * a * math.cos(th),
                    -math.pi / 2, math.pi / 2, epsabs=0, epsrel=1e-13)
    assert total == pytest.approx(pbar * LAM, rel=1e-12)


def test_pressure_periodic_and_zero_outside():
    pbar = 0.3 * PS
    a = wg.half_width(pbar, H0, LAM, E_STAR)
    x = np.linspace(-0.49 * LAM, 0.49 * LAM, 99)
    p = wg.pressure(x, pbar, H0, LAM, E_STAR)
    np.testing.assert_allclose(wg.pressure(x + 3 * LAM, pbar, H0, LAM, E_STAR), p, rtol=1e-9, atol=1e-12 * PS)
    assert np.all(p[np.abs(x) >= a] == 0.0)
    assert np.all(p[np.abs(x) < a] > 0.0)


def test_full_contact_branch_is_continuous():
    # at p̄ = p* the partial-contact formula 2p* cos ψ √(1 − sin²ψ) equals p* + p* cos 2ψ
    x = np.linspace(-LAM / 2, LAM / 2, 201)
    below = wg.pressure(x, PS * (1 - 1e-12), H0, LAM, E_STAR)
    at = wg.pressure(x, PS, H0, LAM, E_STAR)
    np.testing.assert_allclose(below, at, rtol=0, atol=1e-5 * PS)  # √(1e-12)-sized edge effect
    above = wg.pressure(x, 1.5 * PS, H0, LAM, E_STAR)
    np.testing.assert_allclose(above, 1.5 * PS + PS * np.cos(2 * np.pi * x / LAM), rtol=1e-14, atol=1e-14 * PS)
    assert wg.mean_gap(1.5 * PS, H0, LAM, E_STAR) == 0.0
    assert np.all(wg.gap(x, 1.5 * PS, H0, LAM, E_STAR) == 0.0)


@pytest.mark.parametrize("P", [0.05, 0.3, 0.7, 1.0, 1.4])
def test_fft_displacement_conforms_and_gap_matches(P):
    """FFT of the sampled pressure (N = 2¹⁶, one period).

    Gap from FFT: g = z_ind − u_z = h0(1 − cos 2πx/λ) + u_z(0) − u_z(x)
    (d fixed by contact at x = 0). Tolerances: the sampled square-root edge
    limits FFT accuracy; measured max errors at N = 2¹⁶ are 2.2e-7 h0
    (conformity/gap), 5e-7 (mean of the sampled pressure), 4e-8 h0 (mean gap).
    """
    n = 2**16
    x = (np.arange(n) - n // 2) * LAM / n
    pbar = P * PS
    p = wg.pressure(x, pbar, H0, LAM, E_STAR)
    assert p.mean() == pytest.approx(pbar, rel=2e-6)
    u = fft_displacement(p, LAM, E_STAR)
    g_fft = H0 * (1 - np.cos(2 * np.pi * x / LAM)) + u[n // 2] - u
    g = wg.gap(x, pbar, H0, LAM, E_STAR)
    a = wg.half_width(pbar, H0, LAM, E_STAR)
    inside = np.abs(x) < a
    assert np.max(np.abs(g_fft[inside])) < 1e-6 * H0  # conformity with the sinusoid
    assert np.all(g[inside] == 0.0)
    assert np.max(np.abs(g_fft - g)) < 1e-6 * H0  # gap profile outside
    assert g_fft.min() > -1e-6 * H0
    assert np.all(g >= 0.0)
    assert wg.mean_gap(pbar, H0, LAM, E_STAR) == pytest.approx(g_fft.mean(), abs=2e-7 * H0)


@pytest.mark.parametrize("P", [0.02, 0.3, 0.8])
def test_gap_and_mean_gap_against_periodic_quadrature(P):
    """Periodic Flamant kernel by quad: ḡ = h0 + u_z(0) (ū_z = 0); measured agreement 1e-14."""
    pbar = P * PS
    a = wg.half_width(pbar, H0, LAM, E_STAR)

    def p(s):
        return wg.pressure(s, pbar, H0, LAM, E_STAR)

    u0 = periodic_uz(p, 0.0, (-a, a), LAM, E_STAR, [-a, a])
    assert H0 + u0 == pytest.approx(wg.mean_gap(pbar, H0, LAM, E_STAR), rel=1e-9)
    for x in (0.5 * a, 1.3 * a, 0.5 * LAM):
        ux = periodic_uz(p, x, (-a, a), LAM, E_STAR, [-a, a])
        g = H0 * (1 - math.cos(2 * math.pi * x / LAM)) + u0 - ux
        assert g == pytest.approx(wg.gap(x, pbar, H0, LAM, E_STAR), abs=1e-10 * H0)


@pytest.mark.parametrize("P", [0.1, 0.5, 0.9])
def test_gap_closes_continuously_and_mean_gap_is_gap_average(P):
    pbar = P * PS
    a = wg.half_width(pbar, H0, LAM, E_STAR)
    # g(x) ~ (x − a)^{3/2} at the edge: g(a + ε)/h0 → 0
    eps = 1e-9 * LAM
    assert wg.gap(a, pbar, H0, LAM, E_STAR) == 0.0
    assert 0.0 < wg.gap(a + eps, pbar, H0, LAM, E_STAR) < 1e-10 * H0
    # (1/λ)∫g dx over one period equals the closed-form mean gap (quad: ~1e-13)
    integral, _ = quad(lambda x: wg.gap(x, pbar, H0, LAM, E_STAR), a, LAM / 2, epsabs=0, epsrel=1e-12)
    assert 2 * integral / LAM == pytest.approx(wg.mean_gap(pbar, H0, LAM, E_STAR), rel=1e-10)


def test_zero_load_limits():
    x = np.linspace(-LAM / 2, LAM / 2, 11)
    np.testing.assert_allclose(wg.gap(x, 0.0, H0, LAM, E_STAR), H0 * (1 - np.cos(2 * np.pi * x / LAM)),
                               rtol=1e-13, atol=1e-16)
    assert wg.mean_gap(0.0, H0, LAM, E_STAR) == H0
    assert np.all(wg.pressure(x, 0.0, H0, LAM, E_STAR) == 0.0)
    assert wg.elastic_energy(0.0, H0, LAM, E_STAR) == 0.0


@pytest.mark.parametrize("P", [0.05, 0.4, 0.8])
def test_elastic_energy_spectral_and_work_conjugate(P):
    """U from the Fourier energy (L/2)Σ|p̂|²·2/(E*|q|) (§1.1), and p̄ = −dU/(λ dḡ).

    FFT tolerance 2e-6 (edge sampling, N = 2¹⁶); the derivative check uses
    central differences with step 1e-4 P (truncation ~1e-8).
    """
    pbar = P * PS
    n = 2**16
    x = (np.arange(n) - n // 2) * LAM / n
    p_hat = np.fft.rfft(wg.pressure(x, pbar, H0, LAM, E_STAR)) / n
    q = 2 * np.pi * np.fft.rfftfreq(n, LAM / n)
    # two-sided sum over n ≠ 0 = 2 × the positive half-spectrum
    u_spec = LAM / 2 * 2 * np.sum(np.abs(p_hat[1:]) ** 2 * 2 / (E_STAR * q[1:]))
    assert wg.elastic_energy(pbar, H0, LAM, E_STAR) == pytest.approx(u_spec, rel=2e-6)
    dP = 1e-4 * pbar
    dU = wg.elastic_energy(pbar + dP, H0, LAM, E_STAR) - wg.elastic_energy(pbar - dP, H0, LAM, E_STAR)
    dg = wg.mean_gap(pbar + dP, H0, LAM, E_STAR) - wg.mean_gap(pbar - dP, H0, LAM, E_STAR)
    assert -dU / (LAM * dg) == pytest.approx(pbar, rel=1e-7)


@pytest.mark.parametrize("a_over_lam", [0.001, 0.01, 0.05])
def test_hertz_limit(a_over_lam):
    """Same tip curvature 1/R = 4π²h0/λ²: F_W/F_Hertz = sin²(πa/λ)/(πa/λ)² exactly (§3)."""
    a = a_over_lam * LAM
    radius = LAM**2 / (4 * math.pi**2 * H0)
    psi = math.pi * a_over_lam
    F_w = wg.mean_pressure(a, H0, LAM, E_STAR) * LAM
    F_h = hertz.load(a, radius, E_STAR)
    assert F_w / F_h == pytest.approx(math.sin(psi) ** 2 / psi**2, rel=1e-13)
    # pressure profiles agree to O(ψ_a²) (same load used for both)
    xs = np.linspace(-0.95 * a, 0.95 * a, 41)
    p_w = wg.pressure(xs, F_w / LAM, H0, LAM, E_STAR)
    p_h = hertz.pressure(xs, F_w, radius, E_STAR)
    np.testing.assert_allclose(p_w, p_h, rtol=2 * psi**2)


@pytest.mark.parametrize(
    "call",
    [
        lambda: wg.full_contact_pressure(0.0, LAM, E_STAR),
        lambda: wg.full_contact_pressure(H0, -LAM, E_STAR),
        lambda: wg.mean_pressure(0.6 * LAM, H0, LAM, E_STAR),
        lambda: wg.mean_pressure(-1e-9, H0, LAM, E_STAR),
        lambda: wg.half_width(-1.0, H0, LAM, E_STAR),
        lambda: wg.pressure(0.0, -PS, H0, LAM, E_STAR),
        lambda: wg.gap(float("nan"), PS / 2, H0, LAM, E_STAR),
        lambda: wg.mean_gap(PS / 2, H0, LAM, 0.0),
        lambda: wg.elastic_energy(float("inf"), H0, LAM, E_STAR),
    ],
)
def test_bad_input_raises(call):
    with pytest.raises(ValueError):
        call()
