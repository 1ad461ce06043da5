"""Tests of reference.analytic.jkr_sinusoid (Johnson 1995, reference-formulas §4.3).

Independent checks use the periodic line-load kernel (§1.1) integrated over
the closed-form (singular) pressure by adaptive quadrature.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq

from reference.analytic import jkr_cylinder, jkr_sinusoid as js, westergaard as wg
from reference.analytic._halfplane import periodic_uz

E_STAR = 1.1e9  # Pa
LAM = 5.0e-5  # m
H0 = 1.0e-6  # m (amplitude)
PS = math.pi * E_STAR * H0 / LAM


def work_for(alpha):
    """Inverse of α = √(2wλ/(π²h0²E*))."""
    return alpha**2 * math.pi**2 * H0**2 * E_STAR / (2 * LAM)


W = work_for(0.3)


def test_johnson_alpha():
    assert js.johnson_alpha(W, H0, LAM, E_STAR) == pytest.approx(0.3, rel=1e-14)
    # α² = (2/π) w/(h0 p*)  (second form in §4.3)
    assert js.johnson_alpha(W, H0, LAM, E_STAR) ** 2 == pytest.approx(2 / math.pi * W / (H0 * PS), rel=1e-14)


# table of §4.3: α, pull-off p̄/p* (a/λ), jump p̄/p* (a/λ); tolerance half a unit of the last digit
TABLE = [
    (0.1, -0.0220, 0.027, 0.741, 0.425),
    (0.2, -0.0556, 0.044, 0.554, 0.399),
    (0.3, -0.0959, 0.059, 0.388, 0.379),
    (0.4, -0.1416, 0.072, 0.236, 0.361),
    (0.5, -0.1919, 0.086, 0.094, 0.345),
]


@pytest.mark.parametrize("alpha, p_off, a_off, p_jump, a_jump", TABLE)
def test_pull_off_and_jump_table(alpha, p_off, a_off, p_jump, a_jump):
    po, ao = js.pull_off(alpha)
    pj, aj = js.jump_to_contact(alpha)
    assert po == pytest.approx(p_off, abs=5e-5)
    assert ao == pytest.approx(a_off, abs=5e-4)
    assert pj == pytest.approx(p_jump, abs=5e-4)
    assert aj == pytest.approx(a_jump, abs=5e-4)


@pytest.mark.parametrize("alpha", [0.05, 0.3, 0.57, 0.9])
def test_extrema_are_extrema_of_mean_pressure(alpha):
    """Independent of the derivative condition: dense scan of p̄(a) and central differences."""
    w = work_for(alpha)
    po, ao = js.pull_off(alpha)
    pj, aj = js.jump_to_contact(alpha)
    a = np.linspace(1e-6, 0.4999, 20001) * LAM
    P = js.mean_pressure(a, H0, LAM, E_STAR, w) / PS
    # on 0 < a < a_jump, p̄ is smallest at pull-off; beyond the jump point p̄ falls to −∞
    assert po <= P[a < aj * LAM].min() + 1e-15
    assert pj >= P[a > ao * LAM].max() - 1e-15  # (for α > α_c, p̄(0) = 0 exceeds the jump load)
    assert np.any(np.abs(a / LAM - ao) < 1e-4) and np.any(np.abs(a / LAM - aj) < 1e-4)
    for a_ext in (ao, aj):
        h = 1e-5 * a_ext * LAM
        d = (js.mean_pressure(a_ext * LAM + h, H0, LAM, E_STAR, w)
             - js.mean_pressure(a_ext * LAM - h, H0, LAM, E_STAR, w)) / (2 * h)
        assert abs(d) * LAM / PS < 1e-6  # central difference, truncation O(h²)


def test_critical_alpha():
    """α_c: jump load = 0; numerical root of the jump load vs the closed form 3^{3/4}/4 (brentq, 1e-13)."""
    root = brentq(lambda a: js.jump_to_contact(a)[0], 0.3, 0.9, xtol=1e-14)
    assert root == pytest.approx(js.critical_alpha(), rel=1e-12)
    assert js.critical_alpha() == pytest.approx(0.570, abs=5e-4)
    assert js.jump_to_contact(js.critical_alpha())[1] == pytest.approx(1 / 3, rel=1e-9)  # ψ_a = π/3
    assert js.jump_to_contact(0.6)[0] < 0.0 < js.jump_to_contact(0.55)[0]


def test_no_extrema_beyond_alpha_max():
    with pytest.raises(ValueError):
        js.pull_off(js.ALPHA_MAX)
    with pytest.raises(ValueError):
        js.jump_to_contact(1.2)
    # just below, the two extrema merge at tan²ψ = 3/5
    po, ao = js.pull_off(js.ALPHA_MAX * (1 - 1e-10))
    pj, aj = js.jump_to_contact(js.ALPHA_MAX * (1 - 1e-10))
    assert ao == pytest.approx(aj, abs=1e-4)
    assert ao == pytest.approx(math.atan(math.sqrt(0.6)) / math.pi, abs=1e-4)


@settings(max_examples=50, derandomize=True, deadline=None)
@given(st.floats(0.0, 1.0))
def test_half_width_round_trip(s):
    ao = js.pull_off(0.3)[1]
    aj = js.jump_to_contact(0.3)[1]
    a = (ao + s * (aj - ao)) * LAM
    pbar = js.mean_pressure(a, H0, LAM, E_STAR, W)
    # brentq to 1e-15; near the extrema dp̄/da → 0 and a is only fixed to ~√eps
    assert js.half_width(pbar, H0, LAM, E_STAR, W) == pytest.approx(a, rel=1e-7)


def test_half_width_outside_stable_range_raises():
    po = js.pull_off(0.3)[0] * PS
    pj = js.jump_to_contact(0.3)[0] * PS
    with pytest.raises(ValueError, match="stable range"):
        js.half_width(po * 1.001, H0, LAM, E_STAR, W)
    with pytest.raises(ValueError, match="stable range"):
        js.half_width(pj * 1.001, H0, LAM, E_STAR, W)


@pytest.mark.parametrize("a_over_lam", [0.1, 0.25, 0.35])
def test_pressure_integrates_to_mean_pressure(a_over_lam):
    a = a_over_lam * LAM

    def p(x):
        return js.pressure(x, a, H0, LAM, E_STAR, W)

    # x = a sin θ turns the inverse-square-root edges into a bounded integrand; quad ~1e-14
    total, _ = quad(lambda th: p(a * math.sin(th)) * a * math.cos(th), -math.pi / 2, math.pi / 2,
                    epsabs=0, epsrel=1e-13)
    assert total / LAM == pytest.approx(js.mean_pressure(a, H0, LAM, E_STAR, W), rel=1e-11)
    # zero outside the contact, periodic in x
    xs = np.array([1.01 * a, 0.5 * LAM, -0.7 * a])
    assert np.all(js.pressure(xs[:2], a, H0, LAM, E_STAR, W) == 0.0)
    assert js.pressure(xs[2] + 2 * LAM, a, H0, LAM, E_STAR, W) == pytest.approx(p(xs[2]), rel=1e-9)


@pytest.mark.parametrize("a_over_lam", [0.1, 0.25, 0.35])
def test_conformity_and_mean_gap_by_periodic_kernel(a_over_lam):
    """u_z(x) − u_z(0) = h0(1 − cos 2πx/λ) inside; ḡ = h0 + u_z(0) (ū_z = 0).

    Adaptive quadrature of log × inverse-square-root integrands: measured
    ≤ 2e-12 relative; tolerance 1e-9.
    """
    a = a_over_lam * LAM

    def p(x):
        return js.pressure(x, a, H0, LAM, E_STAR, W)

    u0 = periodic_uz(p, 0.0, (-a, a), LAM, E_STAR, [-a, a])
    assert H0 + u0 == pytest.approx(js.mean_gap(a, H0, LAM, E_STAR, W), rel=1e-9)
    for x in (0.5 * a, 0.95 * a):
        ux = periodic_uz(p, x, (-a, a), LAM, E_STAR, [-a, a])
        assert ux - u0 == pytest.approx(H0 * (1 - math.cos(2 * math.pi * x / LAM)), rel=1e-9)


@pytest.mark.parametrize("a_over_lam", [0.1, 0.3])
def test_edge_stress_intensity_gives_griffith_balance(a_over_lam):
    """−p√(2πr) → K_I = p*α√λ, and K_I²/(2E*) = w. Richardson in r (1e-7 a, 2e-7 a) removes O(r)."""
    a = a_over_lam * LAM

    def k_est(r):
        return -js.pressure(a - r, a, H0, LAM, E_STAR, W) * math.sqrt(2 * math.pi * r)

    r = 1e-7 * a
    K = 2 * k_est(r) - k_est(2 * r)
    assert K == pytest.approx(PS * 0.3 * math.sqrt(LAM), rel=1e-6)
    assert K**2 / (2 * E_STAR) == pytest.approx(W, rel=1e-6)


def test_westergaard_limit():
    # w = 0: identical to Westergaard (same expressions, round-off)
    a = 0.2 * LAM
    pbar = wg.mean_pressure(a, H0, LAM, E_STAR)
    assert js.mean_pressure(a, H0, LAM, E_STAR, 0.0) == pytest.approx(pbar, rel=1e-15)
    xs = np.linspace(-0.5 * LAM, 0.5 * LAM, 41)
    np.testing.assert_allclose(js.pressure(xs, a, H0, LAM, E_STAR, 0.0), wg.pressure(xs, pbar, H0, LAM, E_STAR),
                               rtol=1e-12, atol=1e-12 * PS)
    assert js.mean_gap(a, H0, LAM, E_STAR, 0.0) == pytest.approx(wg.mean_gap(pbar, H0, LAM, E_STAR), rel=1e-12)
    assert js.half_width(pbar, H0, LAM, E_STAR, 0.0) == pytest.approx(a, rel=1e-13)


@pytest.mark.parametrize("a_over_lam", [1e-3, 1e-2])
def test_jkr_cylinder_limit(a_over_lam):
    """a ≪ λ with 1/R = 4π²h0/λ²: p̄λ → F_JKR(a); the adhesive terms agree exactly to first
    order, the ratio of the full loads differs by O((πa/λ)²) (tan/sin² expansions)."""
    a = a_over_lam * LAM
    radius = LAM**2 / (4 * math.pi**2 * H0)
    F_s = js.mean_pressure(a, H0, LAM, E_STAR, W) * LAM
    F_c = jkr_cylinder.load(a, radius, E_STAR, W)
    scale = abs(jkr_cylinder.pull_off_load(radius, E_STAR, W)) + abs(F_c)
    assert abs(F_s - F_c) / scale < 2 * (math.pi * a_over_lam) ** 2


@pytest.mark.parametrize(
    "call",
    [
        lambda: js.johnson_alpha(-W, H0, LAM, E_STAR),
        lambda: js.mean_pressure(0.5 * LAM, H0, LAM, E_STAR, W),  # full contact: p̄ → −∞
        lambda: js.mean_pressure(-1e-9, H0, LAM, E_STAR, W),
        lambda: js.pressure(0.0, 0.0, H0, LAM, E_STAR, W),
        lambda: js.pressure(0.0, 0.1 * LAM, -H0, LAM, E_STAR, W),
        lambda: js.mean_gap(0.7 * LAM, H0, LAM, E_STAR, W),
        lambda: js.pull_off(0.0),
        lambda: js.jump_to_contact(float("nan")),
        lambda: js.half_width(float("inf"), H0, LAM, E_STAR, W),
        lambda: js.half_width(1.2 * PS, H0, LAM, E_STAR, 0.0),
    ],
)
def test_bad_input_raises(call):
    with pytest.raises(ValueError):
        call()
