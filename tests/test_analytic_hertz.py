"""Tests of reference.analytic.hertz (reference-formulas §2).

Independent checks use the Flamant line-load displacement (§1.1) integrated
over the closed-form pressure by adaptive quadrature (reference.analytic._halfplane).
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad

from reference.analytic import hertz
from reference.analytic._halfplane import flamant_uz_difference, periodic_uz

E_STAR = 2.5e9  # Pa
R = 3.0e-3  # m
F = 40.0  # N/m  -> a ≈ 7.8 µm ≪ R


@settings(max_examples=60, derandomize=True, deadline=None)
@given(st.floats(1e-6, 1e6), st.floats(1e-6, 1.0), st.floats(1e5, 1e12))
def test_half_width_load_round_trip(load, radius, e_star):
    # exact algebraic inverse: round-off level
    a = hertz.half_width(load, radius, e_star)
    assert hertz.load(a, radius, e_star) == pytest.approx(load, rel=1e-13)


def test_peak_pressure_three_forms():
    # p0 = 2F/(πa) = E*a/(2R) = √(FE*/(πR)): algebraic identities, round-off level
    a = hertz.half_width(F, R, E_STAR)
    p0 = hertz.peak_pressure(F, R, E_STAR)
    assert p0 == pytest.approx(2 * F / (math.pi * a), rel=1e-14)
    assert p0 == pytest.approx(E_STAR * a / (2 * R), rel=1e-14)
    assert hertz.pressure(0.0, F, R, E_STAR) == pytest.approx(p0, rel=1e-15)


def test_pressure_integrates_to_load_and_vanishes_outside():
    a = hertz.half_width(F, R, E_STAR)
    # x = a sin θ removes the square-root edge; quad converges to ~1e-14
    total, _ = quad(lambda th: hertz.pressure(a * math.sin(th), F, R, E_STAR) * a * math.cos(th),
                    -math.pi / 2, math.pi / 2, epsabs=0, epsrel=1e-13)
    assert total == pytest.approx(F, rel=1e-12)
    x = np.array([-2 * a, -a, a, 1.0001 * a, 5 * a])
    assert np.all(hertz.pressure(x, F, R, E_STAR) == 0.0)
    inside = np.linspace(-0.999 * a, 0.999 * a, 101)
    assert np.all(hertz.pressure(inside, F, R, E_STAR) > 0.0)


def test_pressure_conforms_to_cylinder_and_gap_positive_outside():
    """Flamant displacement of p(x): u_z(x) − u_z(0) = x²/(2R) inside, gap > 0 outside."""
    a = hertz.half_width(F, R, E_STAR)

    def p(s):
        return hertz.pressure(s, F, R, E_STAR)

    for x in (0.3 * a, 0.8 * a, 0.99 * a):
        du = flamant_uz_difference(p, x, 0.0, (-a, a), E_STAR, [-a, a])
        # quadrature of a log-singular integrand: measured 2e-14 relative
        assert du == pytest.approx(x**2 / (2 * R), rel=1e-9)
    # gap outside: g(x) = (x² − a²)/(2R) − [u_z(x) − u_z(a)] must be > 0 and grow
    gaps = []
    for x in (1.05 * a, 1.5 * a, 3.0 * a):
        du = flamant_uz_difference(p, x, a, (-a, a), E_STAR, [-a, a])
        gaps.append((x**2 - a**2) / (2 * R) - du)
    assert gaps[0] > 0 and np.all(np.diff(gaps) > 0)


@pytest.mark.parametrize("ratio", [20.0, 100.0])
def test_periodic_approach_matches_periodic_kernel(ratio):
    """δ_rel = −u_z(0) with ū_z = 0 for the Hertz pressure in a cell L (§2.2).

    The formula is the a/L → 0 limit; expanding ln|2 sin(πs/L)| one order
    further gives the correction (F/(πE*))(π²/12)(a/L)² (derived for this test:
    ∫p s² ds = Fa²/4). With it the agreement is limited by the O((a/L)⁴) term
    and the quadrature (1e-8 relative is > 100× the measured deviation).
    """
    a = hertz.half_width(F, R, E_STAR)
    L = ratio * a
    u0 = periodic_uz(lambda s: hertz.pressure(s, F, R, E_STAR), 0.0, (-a, a), L, E_STAR, [-a, a])
    delta = hertz.approach_periodic(F, R, E_STAR, L)
    correction = F / (math.pi * E_STAR) * math.pi**2 / 12 * (a / L) ** 2
    assert -u0 == pytest.approx(delta + correction, rel=1e-8)
    # and the uncorrected formula is within the (a/L)² error quoted in §2.2
    assert -u0 == pytest.approx(delta, rel=0.2 * (a / L) ** 2)


def test_zero_load():
    assert hertz.half_width(0.0, R, E_STAR) == 0.0
    assert np.all(hertz.pressure(np.linspace(-1, 1, 5), 0.0, R, E_STAR) == 0.0)
    assert hertz.approach_periodic(0.0, R, E_STAR, 1e-3) == 0.0


@pytest.mark.parametrize(
    "call",
    [
        lambda: hertz.half_width(-1.0, R, E_STAR),
        lambda: hertz.half_width(F, 0.0, E_STAR),
        lambda: hertz.half_width(F, R, -E_STAR),
        lambda: hertz.load(-1e-6, R, E_STAR),
        lambda: hertz.peak_pressure(float("nan"), R, E_STAR),
        lambda: hertz.pressure([0.0, float("inf")], F, R, E_STAR),
        lambda: hertz.approach_periodic(F, R, E_STAR, 0.0),
        lambda: hertz.approach_periodic(F, R, E_STAR, 1e-6),  # a > L/2
        lambda: hertz.load("abc", R, E_STAR),
    ],
)
def test_bad_input_raises(call):
    with pytest.raises(ValueError):
        call()
