"""Tests of the 2+1-D analytic references (reference.analytic: hertz_sphere, jkr_sphere,
maugis_dugdale_sphere, jgh_wavy, embedded_sinusoid; docs/analytic_2d.rst).

Each formula is checked along a path that does not re-type it: quadrature of the pressure
for the load, Fourier sums of the half-space Green's function for displacements, brute-force
extrema for pull-offs, limits with their observed orders, and lattice sums for the periodic
corrections. Tolerances come from round-off or from the orders the tests measure.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar
from scipy.special import j0

from reference.analytic import (embedded_sinusoid as emb, hertz_sphere as hs, jgh_wavy as jgh, jkr_sinusoid,
                                jkr_sphere as jkr, maugis_dugdale_sphere as mds, westergaard)

E_STAR = 1.1e9  # Pa
R = 1.5e-3  # m
W = 0.04  # J/m²
SETTINGS = settings(max_examples=40, derandomize=True, deadline=None)


def observed_order(e_coarse, e_fine, ratio):
    return math.log(abs(e_coarse) / abs(e_fine)) / math.log(ratio)


# ------------------------------------------------------------------------------------ Hertz sphere
@pytest.mark.parametrize("P", [1e-4, 0.3, 20.0])
def test_hertz_pressure_integrates_to_load(P):
    a = hs.contact_radius(P, R, E_STAR)
    # r = a sin θ removes the √ edge; quad to round-off
    total, _ = quad(lambda th: hs.pressure(a * math.sin(th), P, R, E_STAR) * 2 * math.pi * a * math.sin(th)
                    * a * math.cos(th), 0, math.pi / 2, epsabs=0, epsrel=1e-13)
    assert total == pytest.approx(P, rel=1e-12)
    assert hs.peak_pressure(P, R, E_STAR) == pytest.approx(3 * P / (2 * math.pi * a**2), rel=1e-14)


@SETTINGS
@given(st.floats(1e-8, 1e3))
def test_hertz_load_approach_inverse_and_monotone(P):
    d = hs.approach(P, R, E_STAR)
    assert hs.load_from_approach(d, R, E_STAR) == pytest.approx(P, rel=1e-13)
    a = hs.contact_radius(P, R, E_STAR)
    assert hs.load_from_contact_radius(a, R, E_STAR) == pytest.approx(P, rel=1e-13)
    assert hs.approach(P * (1 + 1e-6), R, E_STAR) > d and hs.contact_radius(P * (1 + 1e-6), R, E_STAR) > a


def _image_sum_approach(P, L, M):
    """u(0) − ū of a periodic array of Hertz pressures, summed in Fourier space (independent of the
    closed form): (1/L²) Σ_{q≠0} 2p̂(q)/(E*|q|), p̂(q) = P·3(sin x − x cos x)/x³, x = |q|a, the
    Hankel transform of p0√(1 − r²/a²); the box |m|, |n| ≤ M converges like 1/(qa)² at its edge."""
    a = hs.contact_radius(P, R, E_STAR)
    n = np.arange(-M, M + 1)
    total = 0.0
    for m in n:
        q = 2 * math.pi / L * np.hypot(m, n)
        if m == 0:
            q = q[n != 0]
        x = q * a
        total += np.sum(2 * P * 3 * (np.sin(x) - x * np.cos(x)) / x**3 / (E_STAR * q))
    return total / L**2


def test_epstein_constants():
    mp = pytest.importorskip("mpmath")
    beta = [0, 1, 0, -1]
    assert hs.EPSTEIN_SQUARE_HALF == pytest.approx(float(4 * mp.zeta(0.5) * mp.dirichlet(0.5, beta)), rel=1e-13)
    assert hs.EPSTEIN_SQUARE_THREE_HALVES == pytest.approx(float(4 * mp.zeta(1.5) * mp.dirichlet(1.5, beta)),
                                                           rel=1e-13)
    # Z(3/2) is a convergent sum: direct lattice sum + tail 2π/ρ outside the disc of radius ρ
    rho = 400
    m = np.arange(-rho, rho + 1)
    r = np.hypot(*np.meshgrid(m, m))
    inside = (r > 0) & (r <= rho)
    assert np.sum(r[inside] ** -3.0) + 2 * math.pi / rho == pytest.approx(hs.EPSTEIN_SQUARE_THREE_HALVES, rel=1e-4)


def test_periodic_approach_against_image_sum():
    """Relative residual of δ_rel against the Fourier image sum at a/L = 0.15, 0.3 (box M = 800,
    converged to 1e-8 relative): measured 6.9e-6 and 3.4e-4, order 5.6 — the O((a/L)⁵) of the
    expansion; without the (a/L)² Z(3/2)/10 term the residual is 1.7e-3 and 2.0e-2."""
    L = 1e-4
    res, res_leading = [], []
    for a_over_L in (0.15, 0.3):
        P = hs.load_from_contact_radius(a_over_L * L, R, E_STAR)
        exact = _image_sum_approach(P, L, 800)
        res.append(hs.approach_periodic(P, R, E_STAR, L) / exact - 1)
        leading = hs.approach(P, R, E_STAR) + hs.EPSTEIN_SQUARE_HALF * P / (math.pi * E_STAR * L)
        res_leading.append(leading / exact - 1)
        # the image correction is a few % of δ here: the check is not the trivial a²/R
        assert abs(exact / hs.approach(P, R, E_STAR) - 1) > 100 * abs(res[-1])
    assert 4.5 < observed_order(res[1], res[0], 2.0) < 7.0
    # the (a/L)² term carries > 99 % of what the leading image term leaves (measured 1.7e-3 → 6.9e-6)
    assert abs(res[0]) < 0.01 * abs(res_leading[0]) and abs(res[1]) < 0.02 * abs(res_leading[1])


def test_periodic_mean_pressure_and_fraction():
    P, Lx, Ly = 0.02, 2e-4, 1e-4
    assert hs.mean_pressure(P, Lx, Ly) * Lx * Ly == pytest.approx(P, rel=1e-15)
    assert hs.load_from_mean_pressure(hs.mean_pressure(P, Lx, Ly), Lx, Ly) == pytest.approx(P, rel=1e-15)
    a = hs.contact_radius(P, R, E_STAR)
    assert hs.contact_fraction(P, R, E_STAR, Lx, Ly) == pytest.approx(math.pi * a**2 / (Lx * Ly), rel=1e-15)
    with pytest.raises(ValueError, match="period"):
        hs.approach_periodic(P, R, E_STAR, 1.9 * a)


# ------------------------------------------------------------------------------------ JKR sphere
PC, DC, AC = jkr.pull_off_load_control(R, E_STAR, W)
DD, PD, AD = jkr.pull_off_displacement_control(R, E_STAR, W)


def test_jkr_is_hertz_without_adhesion():
    for P in (1e-3, 0.5, 7.0):
        a = hs.contact_radius(P, R, E_STAR)
        assert jkr.contact_radius(P, R, E_STAR, 0.0) == pytest.approx(a, rel=1e-14)
        assert jkr.load(a, R, E_STAR, 0.0) == pytest.approx(P, rel=1e-13)
        assert jkr.approach(a, R, E_STAR, 0.0) == pytest.approx(hs.approach(P, R, E_STAR), rel=1e-13)
        r = np.linspace(0, 0.999 * a, 11)
        np.testing.assert_allclose(jkr.pressure(r, a, R, E_STAR, 0.0), hs.pressure(r, P, R, E_STAR), rtol=1e-12)


def test_jkr_tends_to_hertz_as_w_vanishes():
    """At fixed load a_JKR − a_H = Δa(1 + O(√w)), Δa = √(8πwE*a³)/(dP_H/da) from P = P_H(a) − √(8πwE*a³)."""
    P = 0.05
    a_h = hs.contact_radius(P, R, E_STAR)
    errors = []
    for w in (1e-4, 1e-6, 1e-8):
        da = math.sqrt(8 * math.pi * w * E_STAR * a_h**3) / (4 * E_STAR * a_h**2 / R)
        errors.append(abs(jkr.contact_radius(P, R, E_STAR, w) - a_h - da) / da)
    # the relative error of the first-order term is itself O(√w): a factor 10 per factor 100 in w
    assert 0.4 < observed_order(errors[0], errors[1], 100) < 0.6
    assert 0.4 < observed_order(errors[1], errors[2], 100) < 0.6


def test_jkr_pull_off_load_control_is_min_of_load():
    res = minimize_scalar(lambda a: jkr.load(a, R, E_STAR, W), bounds=(1e-3 * AC, 10 * AC), method="bounded",
                          options={"xatol": 1e-12 * AC})
    assert res.fun == pytest.approx(-1.5 * math.pi * W * R, rel=1e-12)
    assert PC == pytest.approx(-1.5 * math.pi * W * R, rel=1e-15)
    assert res.x == pytest.approx(AC, rel=1e-6)  # flat minimum: a to ~√(xatol)
    assert DC == pytest.approx(jkr.approach(AC, R, E_STAR, W), rel=1e-13)
    assert jkr.contact_radius(PC, R, E_STAR, W) == pytest.approx(AC, rel=1e-14)
    with pytest.raises(ValueError, match="pull-off"):
        jkr.contact_radius(1.001 * PC, R, E_STAR, W)


def test_jkr_pull_off_displacement_control_is_min_of_approach():
    res = minimize_scalar(lambda a: jkr.approach(a, R, E_STAR, W), bounds=(1e-3 * AD, 10 * AD), method="bounded",
                          options={"xatol": 1e-12 * AD})
    assert res.fun == pytest.approx(DD, rel=1e-12)
    assert res.x == pytest.approx(AD, rel=1e-6)
    assert jkr.load(AD, R, E_STAR, W) == pytest.approx(-5 / 6 * math.pi * W * R, rel=1e-13)
    assert PD == pytest.approx(jkr.load(AD, R, E_STAR, W), rel=1e-13)
    # the displacement-control pull-off lies beyond the load-control one on the δ–P curve
    assert AD < AC and DD < DC and PC < PD < 0
    assert jkr.contact_radius_from_approach(DD, R, E_STAR, W) == pytest.approx(AD, rel=1e-12)
    with pytest.raises(ValueError, match="displacement-control pull-off"):
        jkr.contact_radius_from_approach(DD - 1e-3 * abs(DD), R, E_STAR, W)


@SETTINGS
@given(st.floats(1.0, 1e3))
def test_jkr_inverses_and_monotonicity_on_stable_branches(ratio):
    a = ratio * AC
    P = jkr.load(a, R, E_STAR, W)
    # near a_c dP/da → 0, so a is only fixed to ~√eps by P there
    assert jkr.contact_radius(P, R, E_STAR, W) == pytest.approx(a, rel=1e-7)
    assert jkr.load(a * (1 + 1e-6), R, E_STAR, W) > P
    a = ratio * AD
    d = jkr.approach(a, R, E_STAR, W)
    assert jkr.contact_radius_from_approach(d, R, E_STAR, W) == pytest.approx(a, rel=1e-7)
    assert jkr.approach(a * (1 + 1e-6), R, E_STAR, W) > d


@pytest.mark.parametrize("ulps", [-30, -3, -1, 1, 3, 30])
def test_jkr_pull_offs_accept_round_off(ulps):
    """Loads / approaches a few ulps either side of the pull-off values are the pull-off points; beyond
    PULL_OFF_ROUNDING they are refused (found by hypothesis: load(a_c) one ulp below −(3/2)πwR)."""
    P, d = PC, DD
    for _ in range(abs(ulps)):
        P, d = np.nextafter(P, math.copysign(math.inf, ulps)), np.nextafter(d, math.copysign(math.inf, ulps))
    # on the stable branch P − P_c ∝ (Δa)², so a is fixed to √(2 ε·ulps)·a_c above a_c; below, only the
    # closed form's own rounding (two cube roots, a square root: < 16 ε) separates it from a_c
    eps = np.finfo(float).eps
    a = jkr.contact_radius(P, R, E_STAR, W)
    assert AC * (1 - 16 * eps) <= a <= AC * (1 + math.sqrt(2 * jkr.PULL_OFF_ROUNDING))
    assert AD <= jkr.contact_radius_from_approach(d, R, E_STAR, W) <= AD * (1 + math.sqrt(2 * jkr.PULL_OFF_ROUNDING))
    with pytest.raises(ValueError, match="pull-off"):
        jkr.contact_radius(PC - 2 * jkr.PULL_OFF_ROUNDING * abs(PC), R, E_STAR, W)
    with pytest.raises(ValueError, match="pull-off"):
        jkr.contact_radius_from_approach(DD - 2 * jkr.PULL_OFF_ROUNDING * abs(DD), R, E_STAR, W)


@pytest.mark.parametrize("ratio", [0.5, 1.0, 3.0])
def test_jkr_pressure_integrates_to_load_and_gives_griffith(ratio):
    a = ratio * AC
    # r = a sin θ: the −1/√(1 − r²/a²) edge becomes 1/cos θ, cancelled by dr = a cos θ dθ
    total, _ = quad(lambda th: jkr.pressure(a * math.sin(th), a, R, E_STAR, W) * 2 * math.pi * a * math.sin(th)
                    * a * math.cos(th), 0, math.pi / 2, epsabs=0, epsrel=1e-13)
    assert total == pytest.approx(jkr.load(a, R, E_STAR, W), rel=1e-11)

    def k_est(s):  # −p√(2πs) = K_I + O(s); Richardson in s removes O(s)
        return -jkr.pressure(a - s, a, R, E_STAR, W) * math.sqrt(2 * math.pi * s)

    s = 1e-6 * a
    K = 2 * k_est(s) - k_est(2 * s)
    assert K == pytest.approx(math.sqrt(2 * E_STAR * W), rel=1e-6)
    assert jkr.stress_intensity_factor(a, R, E_STAR, W) == pytest.approx(math.sqrt(2 * E_STAR * W), rel=1e-13)


# ----------------------------------------------------------------------------- Maugis–Dugdale sphere
def test_md_sphere_eq_m1_as_printed():
    """(M1) in the printed m-form in 50-digit arithmetic (the module uses m = cosh t)."""
    mp = pytest.importorskip("mpmath")
    for lam in (0.05, 1.0, 30.0):
        for A in (0.01, 0.7, 3.0):
            m = mds.solve_m(A, lam)
            with mp.workdps(50):
                s = mp.sqrt(mp.mpf(m) ** 2 - 1)
                at = mp.atan(s)
                lhs = lam * A**2 / 2 * (s + (mp.mpf(m) ** 2 - 2) * at) + 4 * lam**2 * A / 3 * (s * at - m + 1)
            # m − 1 carries ε/(m − 1) relative error as a double (≥ 1e-4 here)
            assert float(lhs) == pytest.approx(1.0, rel=1e-9)


def test_md_sphere_jkr_limit():
    """λ → ∞: P̄ → Ā³ − √(6Ā³), Δ̄ → Ā² − √(8Ā/3); measured errors ∝ 1/λ² (1e-2 … 1e-8 for λ = 10 … 1e4)."""
    for A in (0.5, 1.0, 2.0):
        ep = [mds.load_dimensionless(A, lam) - (A**3 - math.sqrt(6 * A**3)) for lam in (100, 1000)]
        ed = [mds.approach_dimensionless(A, lam) - (A**2 - math.sqrt(8 * A / 3)) for lam in (100, 1000)]
        assert abs(observed_order(ep[0], ep[1], 10) - 2) < 0.05
        assert abs(observed_order(ed[0], ed[1], 10) - 2) < 0.05
    P_c, A_c = mds.pull_off(1e3)
    assert abs(P_c + 1.5) < abs(mds.pull_off(1e2)[0] + 1.5) / 50  # also ∝ 1/λ²
    assert A_c == pytest.approx(1.5 ** (1 / 3), rel=1e-3)


def test_md_sphere_dmt_limit():
    """λ → 0: P̄ → Ā³ − 2 (error ∝ λ) and Δ̄ → Ā² (error ∝ √λ), measured over λ = 1e-3 … 1e-4."""
    for A in (0.5, 1.0, 2.0):
        ep = [mds.load_dimensionless(A, lam) - (A**3 - 2) for lam in (1e-3, 1e-4)]
        ed = [mds.approach_dimensionless(A, lam) - A**2 for lam in (1e-3, 1e-4)]
        assert abs(observed_order(ep[0], ep[1], 10) - 1) < 0.05
        assert abs(observed_order(ed[0], ed[1], 10) - 0.5) < 0.05
    assert mds.pull_off(1e-4)[0] == pytest.approx(-2.0, abs=1e-5)


def test_md_sphere_pull_off_is_the_minimum_and_moves_from_dmt_to_jkr():
    lams = [0.03, 0.1, 0.3, 1.0, 3.0, 10.0]
    values = []
    for lam in lams:
        P_c, A_c = mds.pull_off(lam)
        grid = np.linspace(0.3 * max(A_c, 0.05), 3 * max(A_c, 0.05), 200)
        assert P_c <= min(mds.load_dimensionless(A, lam) for A in grid) + 1e-12
        values.append(P_c)
    assert np.all(np.diff(values) > 0) and -2 < values[0] and values[-1] < -1.5
    P = mds.pull_off_load(R, E_STAR, W, 1e8)
    assert -2 * math.pi * W * R < P < -1.5 * math.pi * W * R


@settings(max_examples=30, derandomize=True, deadline=None)
@given(st.floats(-1.0, 2.0), st.floats(1.01, 20.0))
def test_md_sphere_stable_branch_is_monotone(log_lam, ratio):
    """Beyond the load-control pull-off P̄(Ā) and Δ̄(Ā) increase (the branch that load control follows)."""
    lam = 10.0**log_lam
    A_c = max(mds.pull_off(lam)[1], 1e-3)
    A = ratio * A_c
    assert mds.load_dimensionless(A * 1.001, lam) > mds.load_dimensionless(A, lam)
    assert mds.approach_dimensionless(A * 1.001, lam) > mds.approach_dimensionless(A, lam)


def test_md_sphere_parameters():
    # λ ≈ 1.16 μ for the Lennard-Jones Dugdale stress σ0 = 16w/(9√3 z0) (Johnson & Greenwood 1997)
    z0 = 3e-10
    lam = mds.maugis_parameter(16 * W / (9 * math.sqrt(3) * z0), R, E_STAR, W)
    assert lam / jkr.tabor_parameter(R, E_STAR, W, z0) == pytest.approx(1.157, abs=1e-3)
    phi, dn = 0.03, 2e-9
    assert mds.maugis_parameter_from_cohesive_law(phi, dn, R, E_STAR) == pytest.approx(
        mds.maugis_parameter(phi / (math.e * dn), R, E_STAR, phi), rel=1e-15)
    ell, P_u, d_u = mds.units(R, E_STAR, W)
    # dimensional wrappers against the JKR sphere at large λ (error ∝ 1/λ², λ = 1e4 here)
    s0 = 1e4 / mds.maugis_parameter(1.0, R, E_STAR, W)
    assert mds.load(ell, R, E_STAR, W, s0) == pytest.approx(jkr.load(ell, R, E_STAR, W), rel=1e-6)
    assert mds.approach(ell, R, E_STAR, W, s0) == pytest.approx(jkr.approach(ell, R, E_STAR, W), rel=1e-6)


# ----------------------------------------------------------------------------------- JGH egg-box
DELTA, LAM = 2e-8, 1e-6  # m


def _full_contact_field(N):
    """Full-contact pressure fluctuation of h = Δ cos(kx)cos(ky) by FFT with the half-space stiffness E*|q|/2."""
    x = np.arange(N) * LAM / N
    X, Y = np.meshgrid(x, x, indexing="ij")
    h = DELTA * np.cos(2 * np.pi * X / LAM) * np.cos(2 * np.pi * Y / LAM)
    q1 = 2 * np.pi * np.fft.fftfreq(N, LAM / N)
    q = np.hypot(*np.meshgrid(q1, q1, indexing="ij"))
    return X, Y, np.real(np.fft.ifft2(E_STAR * q / 2 * np.fft.fft2(h)))


def test_jgh_full_contact_pressure_by_fft():
    X, Y, dp = _full_contact_field(32)
    ps = jgh.full_contact_pressure(DELTA, LAM, E_STAR)
    assert -dp.min() == pytest.approx(ps, rel=1e-13)  # tension at the valleys = p*: contact complete iff p̄ ≥ p*
    field = jgh.full_contact_pressure_field(X, Y, 2 * ps, DELTA, LAM, E_STAR)
    np.testing.assert_allclose(field, 2 * ps + dp, rtol=1e-13)
    with pytest.raises(ValueError, match="not complete"):
        jgh.full_contact_pressure_field(0.0, 0.0, 0.99 * ps, DELTA, LAM, E_STAR)


def test_jgh_small_load_is_hertz_at_each_peak():
    """Peaks counted and their curvature measured on the height map (central differences, error
    (kl)²/12 ≈ 1e-6 at N = 2048), load per peak p̄ × cell / peaks, hertz_sphere for a."""
    N = 2048
    x = np.arange(N) * LAM / N
    h = DELTA * np.cos(2 * np.pi * x[:, None] / LAM) * np.cos(2 * np.pi * x[None, :] / LAM)
    peaks = np.sum((h > np.roll(h, 1, 0)) & (h > np.roll(h, -1, 0)) & (h > np.roll(h, 1, 1)) & (h > np.roll(h, -1, 1)))
    assert peaks == 2
    l = LAM / N
    curvature = -(h[1, 0] - 2 * h[0, 0] + h[-1, 0]) / l**2
    assert 1 / curvature == pytest.approx(jgh.peak_radius(DELTA, LAM), rel=2e-6)
    ps = jgh.full_contact_pressure(DELTA, LAM, E_STAR)
    for P in (1e-4, 1e-2, 0.1):
        a = hs.contact_radius(P * ps * LAM**2 / peaks, 1 / curvature, E_STAR)
        assert jgh.contact_fraction_small_load(P * ps, DELTA, LAM, E_STAR) == pytest.approx(
            peaks * math.pi * a**2 / LAM**2, rel=4e-6)


def test_jgh_near_full_contact_slope():
    """Axisymmetrised hole problem, independent of (JGH3): the full-contact tension around a valley
    averaged over the angle, p̄ − p* J0(√2 k r), and a smooth closure of a circular hole,
    ∫₀^b (p* J0(√2kr) − p̄) r dr/√(b² − r²) = 0 (K_I = 0), solved by quadrature and brentq. The
    asymptote's slope 3/(2π) is its P → 1 limit: ratio − 1 measured −3.0e-3 and −3.0e-4 at
    P = 0.99, 0.999 (∝ 1 − P, order 1). (The root also satisfies sin z/z = P, z = √2 k b, to 1e-16.)"""
    ps = jgh.full_contact_pressure(DELTA, LAM, E_STAR)
    k = 2 * np.pi / LAM

    def k_condition(b, pbar):
        return quad(lambda r: (ps * j0(math.sqrt(2) * k * r) - pbar) * r / math.sqrt(b + r), 0, b,
                    weight="alg", wvar=(0, -0.5), epsabs=1e-13 * ps * b, epsrel=1e-13)[0]  # → 0 at the root

    ratios = []
    for P in (0.99, 0.999):
        b0 = jgh.hole_radius(P * ps, DELTA, LAM, E_STAR)
        b = brentq(k_condition, 0.5 * b0, 2 * b0, args=(P * ps,), xtol=1e-14 * b0)
        free = 2 * math.pi * b**2 / LAM**2
        ratios.append((1 - jgh.contact_fraction_near_full(P * ps, DELTA, LAM, E_STAR)) / free)
    assert abs(observed_order(ratios[0] - 1, ratios[1] - 1, 10) - 1) < 0.05
    assert abs(ratios[1] - 1) < 1e-3


def test_jgh_asymptotes_meet_the_bounds():
    ps = jgh.full_contact_pressure(DELTA, LAM, E_STAR)
    assert jgh.contact_fraction_near_full(ps, DELTA, LAM, E_STAR) == 1.0
    assert jgh.contact_fraction_near_full(2 * ps, DELTA, LAM, E_STAR) == 1.0
    assert jgh.contact_fraction_near_full(0.0, DELTA, LAM, E_STAR) == pytest.approx(1 - 3 / (2 * math.pi))
    assert jgh.contact_fraction_small_load(0.0, DELTA, LAM, E_STAR) == 0.0
    assert jgh.hole_radius(ps, DELTA, LAM, E_STAR) == 0.0


def test_jgh_interaction_lattice_sum():
    """S = Σ' |r_j|^{−3} over the egg-box peaks (points (iλ/2, jλ/2), i + j even) by direct sum in a disc
    of radius ρ plus the tail 2π n/ρ (n = 2/λ² peaks per area): the 2√2 Z(3/2)/λ³ of the module."""
    rho_cells = 200
    i = np.arange(-2 * rho_cells, 2 * rho_cells + 1)
    I, J = np.meshgrid(i, i, indexing="ij")
    keep = ((I + J) % 2 == 0) & ((I != 0) | (J != 0))
    r = np.hypot(I[keep], J[keep]) * LAM / 2
    rho = rho_cells * LAM
    S = np.sum(r[r <= rho] ** -3.0) + 2 * math.pi * (2 / LAM**2) / rho
    ps = jgh.full_contact_pressure(DELTA, LAM, E_STAR)
    P = 0.05
    a_h = jgh.contact_fraction_small_load(P * ps, DELTA, LAM, E_STAR)
    a_i = jgh.contact_fraction_small_load_interacting(P * ps, DELTA, LAM, E_STAR)
    Rp = jgh.peak_radius(DELTA, LAM)
    expected = (1 / (1 + Rp * P * ps * LAM**2 / 2 * S / (2 * math.pi * E_STAR))) ** (2 / 3)
    assert a_i / a_h == pytest.approx(expected, rel=1e-4)  # tail estimate good to ~(λ/ρ)²
    assert a_i < a_h


@SETTINGS
@given(st.floats(1e-6, 1.0), st.floats(1.0001, 2.0))
def test_jgh_asymptotes_increase_with_load(P, factor):
    ps = jgh.full_contact_pressure(DELTA, LAM, E_STAR)
    for f in (jgh.contact_fraction_small_load, jgh.contact_fraction_small_load_interacting):
        assert f(P * factor * ps, DELTA, LAM, E_STAR) > f(P * ps, DELTA, LAM, E_STAR)
    if P * factor < 1:
        assert jgh.contact_fraction_near_full(P * factor * ps, DELTA, LAM, E_STAR) > \
            jgh.contact_fraction_near_full(P * ps, DELTA, LAM, E_STAR)


# ------------------------------------------------------------------------------- embedded sinusoid
def test_embedded_sinusoid_full_contact_field_is_the_1d_one():
    """2-D FFT of h0 cos(2πx/Lx) on an Lx × Ly grid with E*|q|/2: constant along y, amplitude p* of 1+1-D."""
    h0, Lx, Ly, Nx, Ny = 1e-8, 1e-6, 0.5e-6, 32, 16
    x = np.arange(Nx) * Lx / Nx
    h = np.repeat((h0 * np.cos(2 * np.pi * x / Lx))[:, None], Ny, axis=1)
    q = np.hypot(*np.meshgrid(2 * np.pi * np.fft.fftfreq(Nx, Lx / Nx), 2 * np.pi * np.fft.fftfreq(Ny, Ly / Ny),
                              indexing="ij"))
    dp = np.real(np.fft.ifft2(E_STAR * q / 2 * np.fft.fft2(h)))
    np.testing.assert_allclose(dp, dp[:, :1] * np.ones((1, Ny)), atol=1e-13 * np.abs(dp).max())
    assert -dp.min() == pytest.approx(emb.full_contact_pressure(h0, Lx, E_STAR), rel=1e-13)


@SETTINGS
@given(st.floats(0.0, 0.999))
def test_embedded_sinusoid_equals_1d(P):
    h0, Lx, Ly = 1e-8, 1e-6, 0.5e-6
    ps = westergaard.full_contact_pressure(h0, Lx, E_STAR)
    a_rel = emb.contact_fraction(P * ps, h0, Lx, E_STAR)
    assert a_rel == 2 * westergaard.half_width(P * ps, h0, Lx, E_STAR) / Lx
    assert emb.mean_pressure(a_rel, h0, Lx, E_STAR) == pytest.approx(P * ps, rel=1e-9, abs=1e-12 * ps)
    assert emb.mean_gap(P * ps, h0, Lx, E_STAR) == westergaard.mean_gap(P * ps, h0, Lx, E_STAR)
    assert emb.total_load(P * ps, Lx, Ly) == pytest.approx(P * ps * Lx * Ly, rel=1e-15)


def test_embedded_sinusoid_adhesive_branch():
    h0, Lx, w = 1e-8, 1e-6, 2e-3
    alpha = jkr_sinusoid.johnson_alpha(w, h0, Lx, E_STAR)
    ps = westergaard.full_contact_pressure(h0, Lx, E_STAR)
    P_off, a_off = jkr_sinusoid.pull_off(alpha)
    a_rel = emb.contact_fraction(0.9 * P_off * ps + 0.1 * jkr_sinusoid.jump_to_contact(alpha)[0] * ps, h0, Lx,
                                 E_STAR, w)
    assert 2 * a_off < a_rel < 1
    assert emb.mean_pressure(2 * a_off, h0, Lx, E_STAR, w) == pytest.approx(P_off * ps, rel=1e-12)


# ------------------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("call, name", [
    (lambda: hs.contact_radius(-1.0, R, E_STAR), "load"),
    (lambda: hs.approach(1.0, 0.0, E_STAR), "radius"),
    (lambda: hs.pressure(float("nan"), 1.0, R, E_STAR), "r"),
    (lambda: hs.mean_pressure(1.0, -1.0, 1.0), "length_x"),
    (lambda: hs.approach_periodic(1.0, R, E_STAR, 0.0), "period"),
    (lambda: jkr.load(1e-6, R, E_STAR, -W), "work"),
    (lambda: jkr.contact_radius(float("inf"), R, E_STAR, W), "load"),
    (lambda: jkr.contact_radius_from_approach(-1e-9, R, E_STAR, 0.0), "approach"),
    (lambda: jkr.tabor_parameter(R, E_STAR, W, 0.0), "range_z0"),
    (lambda: jkr.pressure(0.0, 0.0, R, E_STAR, W), "contact_radius"),
    (lambda: mds.pull_off(-1.0), "lam"),
    (lambda: mds.load(1e-6, R, E_STAR, W, 0.0), "sigma0"),
    (lambda: mds.solve_m(0.0, 1.0), "a_bar"),
    (lambda: jgh.full_contact_pressure(0.0, LAM, E_STAR), "amplitude"),
    (lambda: jgh.contact_fraction_small_load(-1.0, DELTA, LAM, E_STAR), "mean_pressure"),
    (lambda: jgh.peak_radius(DELTA, "x"), "wavelength"),
    (lambda: emb.contact_fraction(1.0, 1e-8, 1e-6, E_STAR, work=-1.0), "work"),
    (lambda: emb.mean_pressure(1.5, 1e-8, 1e-6, E_STAR), "contact_fraction"),
    (lambda: emb.total_load(1.0, 1e-6, 0.0), "length_y"),
])
def test_bad_input_names_the_argument(call, name):
    with pytest.raises(ValueError, match=rf"^{name} "):
        call()
