"""Tests of reference.analytic.jkr_cylinder (reference-formulas §4.1)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from reference.analytic import hertz, jkr_cylinder as jkr
from reference.analytic._halfplane import flamant_uz_difference

E_STAR = 1.2e9  # Pa
R = 2.0e-3  # m
W = 0.06  # J/m²
A_C = jkr.pull_off_half_width(R, E_STAR, W)


def test_pull_off_against_brute_force_minimum():
    # bounded Brent on F(a): converges to ~1e-10 in a (flat minimum), F to round-off
    res = minimize_scalar(lambda a: jkr.load(a, R, E_STAR, W), bounds=(1e-3 * A_C, 10 * A_C),
                          method="bounded", options={"xatol": 1e-12 * A_C})
    assert res.x == pytest.approx(A_C, rel=1e-6)
    assert res.fun == pytest.approx(jkr.pull_off_load(R, E_STAR, W), rel=1e-12)
    # the two closed forms of F_c agree (algebraic identity)
    assert jkr.pull_off_load(R, E_STAR, W) == pytest.approx(-0.75 * math.pi * E_STAR * A_C**2 / R, rel=1e-14)
    assert jkr.load(A_C, R, E_STAR, W) == pytest.approx(jkr.pull_off_load(R, E_STAR, W), rel=1e-14)


@settings(max_examples=60, derandomize=True, deadline=None)
@given(st.floats(1.0, 1e3))
def test_half_width_round_trip_on_stable_branch(a_over_ac):
    a = a_over_ac * A_C
    F = jkr.load(a, R, E_STAR, W)
    # brentq to rtol 1e-15; near a_c dF/da → 0 so a is only determined to ~√eps there
    assert jkr.half_width(F, R, E_STAR, W) == pytest.approx(a, rel=1e-7)
    assert jkr.half_width(F, R, E_STAR, W) >= A_C


def test_half_width_at_pull_off_and_below():
    F_c = jkr.pull_off_load(R, E_STAR, W)
    assert jkr.half_width(F_c, R, E_STAR, W) == A_C
    with pytest.raises(ValueError, match="pull-off"):
        jkr.half_width(1.001 * F_c, R, E_STAR, W)


@pytest.mark.parametrize("a_over_ac", [0.5, 1.0, 3.0])
def test_pressure_integrates_to_load(a_over_ac):
    a = a_over_ac * A_C
    # x = a sin θ turns the −1/√(a² − x²) edge into a constant; quad to ~1e-14
    total, _ = quad(lambda th: jkr.pressure(a * math.sin(th), a, R, E_STAR, W) * a * math.cos(th),
                    -math.pi / 2, math.pi / 2, epsabs=0, epsrel=1e-13)
    assert total == pytest.approx(jkr.load(a, R, E_STAR, W), rel=1e-11)


@pytest.mark.parametrize("a_over_ac", [0.5, 2.0])
def test_pressure_conforms_to_cylinder(a_over_ac):
    """Flamant displacement of the singular JKR pressure: u_z(x) − u_z(0) = x²/(2R) inside.

    Adaptive quadrature with log and inverse-square-root endpoint
    singularities: measured 1e-11 relative.
    """
    a = a_over_ac * A_C

    def p(s):
        return jkr.pressure(s, a, R, E_STAR, W)

    for x in (0.3 * a, 0.9 * a):
        du = flamant_uz_difference(p, x, 0.0, (-a, a), E_STAR, [-a, a])
        assert du == pytest.approx(x**2 / (2 * R), rel=1e-8)


@pytest.mark.parametrize("a_over_ac", [0.5, 1.0, 4.0])
def test_edge_singularity_gives_griffith_balance(a_over_ac):
    """K_I from the pressure field near the edge, G = K_I²/(2E*) = w.

    −p√(2πr) = K_I + O(r); Richardson extrapolation in r = 1e-6 a, 2e-6 a
    removes the O(r) term, leaving ~1e-11 relative.
    """
    a = a_over_ac * A_C

    def k_est(r):
        return -jkr.pressure(a - r, a, R, E_STAR, W) * math.sqrt(2 * math.pi * r)

    r = 1e-6 * a
    K = 2 * k_est(r) - k_est(2 * r)
    assert K == pytest.approx(jkr.stress_intensity_factor(a, R, E_STAR, W), rel=1e-6)
    assert K**2 / (2 * E_STAR) == pytest.approx(W, rel=1e-6)


def test_hertz_limit():
    # w = 0 is Hertz exactly
    a = 3 * A_C
    F_h = hertz.load(a, R, E_STAR)
    assert jkr.load(a, R, E_STAR, 0.0) == pytest.approx(F_h, rel=1e-15)
    xs = np.linspace(-1.2 * a, 1.2 * a, 37)
    np.testing.assert_allclose(jkr.pressure(xs, a, R, E_STAR, 0.0), hertz.pressure(xs, F_h, R, E_STAR),
                               rtol=1e-13, atol=1e-9 * hertz.peak_pressure(F_h, R, E_STAR))  # √ edge amplifies round-off
    assert jkr.half_width(F_h, R, E_STAR, 0.0) == pytest.approx(a, rel=1e-14)
    # w → 0 at fixed load: a_JKR/a_Hertz − 1 = O(√w) (leading term √(2πE*w a)·dA/dF)
    F = 50.0
    a_h = hertz.half_width(F, R, E_STAR)
    errors = []
    for w in (1e-4, 1e-6, 1e-8):
        a_j = jkr.half_width(F, R, E_STAR, w)
        # first-order perturbation: F = F_H(a) − √(2πE*wa) ⇒ Δa ≈ √(2πE*wa)/(πE*a/(2R))
        da = math.sqrt(2 * math.pi * E_STAR * w * a_h) / (math.pi * E_STAR * a_h / (2 * R))
        errors.append(abs(a_j - a_h - da) / da)
    assert errors[-1] < 1e-3 and errors[0] > errors[1] > errors[2]


@pytest.mark.parametrize(
    "call",
    [
        lambda: jkr.load(-1.0, R, E_STAR, W),
        lambda: jkr.load(A_C, R, E_STAR, -W),
        lambda: jkr.pull_off_load(0.0, E_STAR, W),
        lambda: jkr.pull_off_half_width(R, float("nan"), W),
        lambda: jkr.half_width(-1.0, R, E_STAR, 0.0),
        lambda: jkr.half_width(float("-inf"), R, E_STAR, W),
        lambda: jkr.pressure(0.0, 0.0, R, E_STAR, W),
        lambda: jkr.stress_intensity_factor(0.0, R, E_STAR, W),
    ],
)
def test_bad_input_raises(call):
    with pytest.raises(ValueError):
        call()


@pytest.mark.parametrize("ulps", [-12, -3, -1, 1, 3, 12])
def test_half_width_accepts_pull_off_load_within_round_off(ulps):
    """On an AVX2 machine numpy's cbrt put load(a_c) one ulp below pull_off_load, and
    half_width raised "below the pull-off load". A load a few ulps either side of F_c is F_c."""
    F_c = jkr.pull_off_load(R, E_STAR, W)
    F = F_c
    for _ in range(abs(ulps)):
        F = np.nextafter(F, math.copysign(math.inf, ulps))
    a = jkr.half_width(F, R, E_STAR, W)
    # F − F_c = ½|F_c|(Δa/a_c)² on the stable branch: |F − F_c| ≤ 16 ε|F_c| gives Δa ≤ √(32 ε) a_c
    assert A_C <= a <= A_C * (1 + math.sqrt(2 * jkr.PULL_OFF_ROUNDING))
    assert jkr.half_width(jkr.load(A_C, R, E_STAR, W), R, E_STAR, W) == pytest.approx(A_C, rel=1e-7)


def test_half_width_refuses_beyond_round_off():
    F_c = jkr.pull_off_load(R, E_STAR, W)
    with pytest.raises(ValueError, match="pull-off"):
        jkr.half_width(F_c - 2 * jkr.PULL_OFF_ROUNDING * abs(F_c), R, E_STAR, W)
