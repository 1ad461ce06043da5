"""Tests of reference.analytic.maugis_dugdale (Baney & Hui 1997, reference-formulas §4.2).

The decisive independent check is the Dugdale condition: the Flamant
displacement of the closed-form pressure field must open the gap at the
outer edge c of the cohesive zone to exactly w/σ0 — this tests Eq. (i)
without re-typing it.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from reference.analytic import jkr_cylinder as jkr, maugis_dugdale as md
from reference.analytic._halfplane import flamant_uz_difference

E_STAR = 1.5e9  # Pa
R = 1.0e-3  # m
W = 0.05  # J/m²
ELL, F_U, P_U = md.units(R, E_STAR, W)


def sigma0_for(lam):
    """Inverse of λ = 4σ0 (R/(π²E*²w))^{1/3}."""
    return lam / 4.0 * np.cbrt(math.pi**2 * E_STAR**2 * W / R)


def test_scales_and_maugis_parameter():
    # identities of §4.2: p_u/ℓ = E*/(2R) (Hertz term), p_u πλ/4 = σ0, F_u = p_u ℓ · π/2
    assert P_U / ELL == pytest.approx(E_STAR / (2 * R), rel=1e-14)
    assert md.maugis_parameter(sigma0_for(0.7), R, E_STAR, W) == pytest.approx(0.7, rel=1e-14)
    assert P_U * math.pi * 0.7 / 4 == pytest.approx(sigma0_for(0.7), rel=1e-14)
    assert F_U == pytest.approx(P_U * ELL * math.pi / 2, rel=1e-14)


def test_cohesive_law_mapping():
    """σ0 = max of T_n(Δ) = (φn/δn)(Δ/δn)e^{−Δ/δn}; w = ∫₀^∞ T_n dΔ (§4.0), checked by quadrature."""
    phi, dn = 0.03, 2e-9

    def t_n(d):
        return phi / dn * (d / dn) * math.exp(-d / dn)

    w, s0 = md.dugdale_from_cohesive_law(phi, dn)
    res = minimize_scalar(lambda d: -t_n(d), bounds=(0, 10 * dn), method="bounded", options={"xatol": 1e-15})
    assert s0 == pytest.approx(-res.fun, rel=1e-10)  # flat maximum: value to ~xatol²
    assert w == pytest.approx(quad(t_n, 0, 200 * dn, epsabs=0, epsrel=1e-12)[0], rel=1e-10)
    lam = md.maugis_parameter_from_cohesive_law(phi, dn, R, E_STAR)
    assert lam == pytest.approx(md.maugis_parameter(s0, R, E_STAR, w), rel=1e-15)
    assert lam == pytest.approx(4 / math.e * phi / dn * np.cbrt(R / (math.pi**2 * E_STAR**2 * phi)), rel=1e-14)


@pytest.mark.parametrize("lam", [0.05, 0.5, 3.0, 300.0])
@pytest.mark.parametrize("a_bar", [1e-4, 0.3, 1.0, 5.0])
def test_solve_m_satisfies_eq_i(lam, a_bar):
    """Eq. (i) as printed (m-form), evaluated in 50-digit arithmetic (the module uses m = cosh t).

    m is returned as a double, so m − 1 carries a relative error ~1e-16/(m − 1)
    (≤ 1e-10 here, m − 1 ≥ 1e-6); the tolerance 1e-8 covers that.
    """
    mp = pytest.importorskip("mpmath")
    m = md.solve_m(a_bar, lam)
    assert m > 1.0
    with mp.workdps(50):
        mm = mp.mpf(m)
        s = mp.sqrt(mm * mm - 1)
        L = mp.log(mm + s)
        lhs = lam * a_bar**2 / 2 * (mm * s - L) + lam**2 * a_bar / 2 * (s * L - mm * mp.log(mm))
    assert float(lhs) == pytest.approx(1.0, rel=1e-8)


def test_m_decreases_with_lambda_and_with_a():
    ms = [md.solve_m(0.5, lam) for lam in (0.1, 1.0, 10.0, 100.0)]
    assert np.all(np.diff(ms) < 0) and ms[-1] - 1 < 1e-3
    ms = [md.solve_m(a, 1.0) for a in (0.1, 0.5, 2.0)]
    assert np.all(np.diff(ms) < 0)


CASES = [(0.16, 1.0), (0.93, 0.4), (3.7, 1.5)]  # (λ, Ā) spanning DMT-like … JKR-like


@pytest.mark.parametrize("lam, a_bar", CASES)
def test_pressure_integrates_to_load(lam, a_bar):
    s0 = sigma0_for(lam)
    a = a_bar * ELL
    c = md.cohesive_zone_edge(a, R, E_STAR, W, s0)
    # inside: x = a sin θ (smooth integrand, quad ~1e-14); cohesive zone: −σ0·2(c − a) exactly
    inner, _ = quad(lambda th: md.pressure(a * math.sin(th), a, R, E_STAR, W, s0) * a * math.cos(th),
                    -math.pi / 2, math.pi / 2, epsabs=0, epsrel=1e-12)
    assert inner - 2 * s0 * (c - a) == pytest.approx(md.load(a, R, E_STAR, W, s0), rel=1e-10)
    # the field: continuous at |x| = a, −σ0 on the cohesive zone, 0 beyond c
    p = md.pressure(np.array([a * (1 - 1e-12), a, 0.5 * (a + c), c, c * (1 + 1e-9)]), a, R, E_STAR, W, s0)
    np.testing.assert_allclose(p[:4], -s0, rtol=0, atol=1e-5 * P_U)  # p(a⁻) + σ0 = O(√(2e-12)) p_u
    assert p[4] == 0.0


@pytest.mark.parametrize("lam, a_bar", CASES)
def test_conformity_and_dugdale_opening(lam, a_bar):
    """Flamant displacement of p(x): conformity inside (u_z(x) − u_z(0) = x²/(2R)),
    gap(c) = (c² − a²)/(2R) − [u_z(c) − u_z(a)] = w/σ0. Adaptive quadrature
    of log-singular integrands: measured ≤ 3e-13 relative."""
    s0 = sigma0_for(lam)
    a = a_bar * ELL
    c = md.cohesive_zone_edge(a, R, E_STAR, W, s0)

    def p(s):
        return md.pressure(s, a, R, E_STAR, W, s0)

    x = 0.7 * a
    du = flamant_uz_difference(p, x, 0.0, (-c, c), E_STAR, [-a, a])
    assert du == pytest.approx(x**2 / (2 * R), rel=1e-9)
    du = flamant_uz_difference(p, c, a, (-c, c), E_STAR, [-a, a])
    assert (c**2 - a**2) / (2 * R) - du == pytest.approx(W / s0, rel=1e-9)


# pull-off table of reference-formulas §4.2, tolerance = half a unit of the last quoted digit
PULL_OFF_TABLE = [(0.1, -0.444, 5e-4), (0.3, -0.744, 5e-4), (1.0, -1.113, 5e-4), (3.0, -1.188, 5e-4),
                  (10.0, -1.1905, 5e-5), (100.0, -1.19055, 5e-6), (1000.0, -1.19055, 5e-6)]


@pytest.mark.parametrize("lam, expected, tol", PULL_OFF_TABLE)
def test_pull_off_table(lam, expected, tol):
    f_min, a_bar = md.pull_off(lam)
    assert f_min == pytest.approx(expected, abs=tol)
    if lam <= 0.3:
        assert a_bar == 0.0  # branch ends at a → 0 (§4.2 footnote)
    else:
        assert a_bar > 0.0
        # it is a local minimum of F(Ā): neighbours are higher (F smooth, quadratic minimum)
        for s in (0.99, 1.01):
            assert md.load_dimensionless(s * a_bar, lam) > f_min


def test_pull_off_tends_to_jkr():
    jkr_value = -3 / 2 ** (4 / 3)
    errs = [abs(md.pull_off(lam)[0] - jkr_value) for lam in (3.0, 10.0, 100.0, 1000.0)]
    assert np.all(np.diff(errs) < 0) and errs[-1] < 1e-8  # (measured 1e-11 at λ = 1000)
    assert md.pull_off(1000.0)[1] == pytest.approx(2 ** (-2 / 3), rel=1e-3)  # JKR Ā_c = 2^{-2/3}
    # dimensional: large σ0 reproduces jkr_cylinder
    s0 = sigma0_for(1000.0)
    assert md.pull_off_load(R, E_STAR, W, s0) == pytest.approx(jkr.pull_off_load(R, E_STAR, W), rel=1e-8)
    assert md.pull_off_half_width(R, E_STAR, W, s0) == pytest.approx(
        jkr.pull_off_half_width(R, E_STAR, W), rel=1e-3)


def test_pull_off_against_independent_minimisation():
    for lam in (1.0, 3.0):
        res = minimize_scalar(lambda A: md.load_dimensionless(A, lam), bounds=(0.02, 2.0), method="bounded",
                              options={"xatol": 1e-10})
        assert md.pull_off(lam)[0] == pytest.approx(res.fun, rel=1e-10)


def test_small_lambda_end_point():
    # for λ ≲ 0.4 F(Ā) increases from its Ā → 0 end value −λs0 ≈ −√(2λ)
    for lam in (0.01, 0.1, 0.3):
        f_end, a_bar = md.pull_off(lam)
        grid = np.logspace(-5, 0.3, 60)
        assert np.min([md.load_dimensionless(A, lam) for A in grid]) >= f_end - 1e-12
        assert md.load_dimensionless(1e-8, lam) == pytest.approx(f_end, abs=1e-9)


def test_jkr_limit_of_load():
    # F/F_u → Ā² − 2√Ā as λ → ∞; deviation measured ∝ 1/λ² (4.4/λ² at Ā = 2)
    for lam in (100.0, 1000.0):
        for A in (0.2, 0.63, 2.0):
            assert md.load_dimensionless(A, lam) == pytest.approx(A * A - 2 * math.sqrt(A), abs=10 / lam**2)
    # dimensional equivalence with jkr_cylinder
    a = np.array([0.5, 1.0, 3.0]) * ELL
    np.testing.assert_allclose(md.load(a, R, E_STAR, W, sigma0_for(1e4)), jkr.load(a, R, E_STAR, W),
                               rtol=0, atol=1e-6 * F_U)


def test_dmt_like_limit_of_load():
    # F/F_u → Ā² − √(2λ) as λ → 0; measured relative deviation 3e-3, 1e-4, 4e-4·(λ/1e-4)… → decreasing
    rel = []
    for lam in (1e-2, 1e-3, 1e-4):
        dev = max(abs(md.load_dimensionless(A, lam) - (A * A - math.sqrt(2 * lam))) for A in (0.2, 0.63, 2.0))
        rel.append(dev / math.sqrt(2 * lam))
    assert np.all(np.diff(rel) < 0) and rel[-1] < 1e-3


@pytest.mark.parametrize(
    "call",
    [
        lambda: md.solve_m(0.0, 1.0),
        lambda: md.solve_m(1.0, -1.0),
        lambda: md.solve_m(1e-320, 1.0),  # no representable root (cohesive zone ~1e300 a)
        lambda: md.load_dimensionless(float("nan"), 1.0),
        lambda: md.pull_off(0.0),
        lambda: md.units(R, E_STAR, 0.0),
        lambda: md.maugis_parameter(-1.0, R, E_STAR, W),
        lambda: md.dugdale_from_cohesive_law(W, 0.0),
        lambda: md.load(-ELL, R, E_STAR, W, 1e6),
        lambda: md.pressure(0.0, ELL, R, E_STAR, W, 0.0),
        lambda: md.cohesive_zone_edge(ELL, -R, E_STAR, W, 1e6),
    ],
)
def test_bad_input_raises(call):
    with pytest.raises(ValueError):
        call()
