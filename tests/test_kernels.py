"""Tests of gfmd_contact.core.kernels: plane-strain surface stiffness K(q) (reference-formulas §1).

Convention A (gfmd_contact/core/conventions.py): u_z up, t = traction applied on the body, t_z = −p,
t̂ = K û on the rfft half-spectrum (q ≥ 0, s = +1), K_zx = conj(K_xz) = −K_xz.
The compliances of §1.2/§1.3 are implemented here, independently of the code, and the
sign of the coupling is pinned by the convention-independent Flamant/Cerruti line-load
solutions (Johnson 1985, ch. 2), computed by FFT on a periodic grid.
"""

import math

import numpy as np
import pytest
import scipy.fft
from hypothesis import given, settings, strategies as st

from gfmd_contact.core import kernels
from gfmd_contact.core.surfaces import grid

EPS = np.finfo(float).eps
E = 70e9  # Pa


def _moduli(e, nu):
    e_star = e / (1 - nu**2)
    mu = e / (2 * (1 + nu))
    m = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) if nu < 0.5 else math.inf
    return e_star, mu, m


def _layer_compliance(q, e, nu, depth):
    """G(q) of a layer bonded to a rigid base, §1.3 (independent transcription), q > 0."""
    e_star, _, _ = _moduli(e, nu)
    h = np.abs(q) * depth
    k3 = 3 - 4 * nu
    c = 2 / (e_star * np.abs(q))
    s = np.sign(q)
    den = k3 * np.cosh(2 * h) + 2 * h**2 + (1 - 2 * nu) ** 2 + 4 * (1 - nu) ** 2
    g_xx = c * (k3 * np.sinh(2 * h) + 2 * h) / den
    g_zz = c * (k3 * np.sinh(2 * h) - 2 * h) / den
    x = ((1 - 2 * nu) * k3 * (np.cosh(2 * h) - 1) - 2 * h**2) / (2 * (1 - nu))
    g_xz = -1j * s * c * x / den
    return g_xx, g_xz, g_zz


def _product_minus_identity(k, g):
    """max |K·G − I| per mode, with K_zx = −K_xz and G_zx = −G_xz."""
    k_xx, k_xz, k_zz = k
    g_xx, g_xz, g_zz = g
    k_zx, g_zx = -k_xz, -g_xz
    entries = [k_xx * g_xx + k_xz * g_zx - 1, k_xx * g_xz + k_xz * g_zz,
               k_zx * g_xx + k_zz * g_zx, k_zx * g_xz + k_zz * g_zz - 1]
    return np.max([np.abs(p) for p in entries], axis=0)


def _assert_hermitian_pd(k_xx, k_xz, k_zz):
    # K_xx, K_zz real (> 0); K_xz purely imaginary ⇒ K_zx = conj(K_xz) = −K_xz; det = K_xx K_zz − |K_xz|²
    assert np.all(k_xx.imag == 0) and np.all(k_zz.imag == 0) and np.all(k_xz.real == 0)
    assert np.all(k_xx.real > 0) and np.all(k_zz.real > 0)
    det = k_xx.real * k_zz.real - np.abs(k_xz) ** 2
    assert np.all(det > 0)


def _solve(kernel, t_x, t_z):
    """û = K⁻¹ t̂ on the rfft spectrum (q = 0 clamped to û = 0); returns (u_x, u_z)."""
    k_xx, k_xz, k_zz = kernel
    n = t_x.size
    tx, tz = scipy.fft.rfft(t_x), scipy.fft.rfft(t_z)
    ux, uz = np.zeros_like(tx), np.zeros_like(tz)
    m = slice(1, None)
    det = k_xx[m] * k_zz[m] + k_xz[m] ** 2  # K_xx K_zz − K_xz K_zx
    ux[m] = (k_zz[m] * tx[m] - k_xz[m] * tz[m]) / det
    uz[m] = (k_xz[m] * tx[m] + k_xx[m] * tz[m]) / det  # row z of K⁻¹: (−K_zx, K_xx)/det
    return scipy.fft.irfft(ux, n=n), scipy.fft.irfft(uz, n=n)


# ---------------------------------------------------------------- helpers and half-plane

def test_wavenumbers_and_moduli():
    q = kernels.wavenumbers(8, 2.0)
    assert np.allclose(q, 2 * np.pi * np.arange(5) / 2.0, rtol=0, atol=1e-15)
    assert kernels.wavenumbers(9, 2.0).size == 5
    e_star, mu, m = _moduli(E, 0.3)
    assert kernels.contact_modulus(E, 0.3) == pytest.approx(e_star, rel=4 * EPS)
    assert kernels.shear_modulus(E, 0.3) == pytest.approx(mu, rel=4 * EPS)
    assert kernels.constrained_modulus(E, 0.3) == pytest.approx(m, rel=4 * EPS)
    assert kernels.constrained_modulus(E, 0.5) == math.inf
    # §0 identity E*/2 = μ/(1 − ν)
    assert e_star / 2 == pytest.approx(mu / (1 - 0.3), rel=4 * EPS)


@settings(max_examples=30, derandomize=True, deadline=None)
@given(st.floats(1e3, 1e12), st.floats(-0.99, 0.5))
def test_halfplane_normal(e, nu):
    q = kernels.wavenumbers(64, 1e-6)
    k = kernels.halfplane_normal(q, e, nu)
    assert k[0] == 0.0
    assert np.allclose(k, e / (1 - nu**2) * q / 2, rtol=4 * EPS, atol=0)  # round-off level


@settings(max_examples=40, derandomize=True, deadline=None)
@given(st.floats(-0.99, 0.5), st.sampled_from([64, 65]))
def test_halfplane_coupled_is_inverse_of_compliance(nu, nodes):
    # §1.2 μ-form: K_xx = K_zz = 4μ(1−ν)|q|/(3−4ν), K_xz = 2iμ(1−2ν)|q|/(3−4ν) (s = +1), and
    # K·G = I with G = (2/(E*|q|))[[1, −iβ], [iβ, 1]]: algebraic identities, round-off (16 eps)
    q = kernels.wavenumbers(nodes, 3e-6)
    k_xx, k_xz, k_zz = kernels.halfplane_coupled(q, E, nu, nodes=nodes)
    _assert_hermitian_pd(k_xx[1:], k_xz[1:], k_zz[1:])
    e_star, mu, _ = _moduli(E, nu)
    diag = 4 * mu * (1 - nu) * q / (3 - 4 * nu)
    off = 2j * mu * (1 - 2 * nu) * q / (3 - 4 * nu)
    assert np.allclose(k_xx, diag, rtol=16 * EPS, atol=0) and np.allclose(k_zz, diag, rtol=16 * EPS, atol=0)
    assert np.allclose(k_xz[:-1], off[:-1], rtol=16 * EPS, atol=0)
    beta = (1 - 2 * nu) / (2 * (1 - nu))
    g = (2 / (e_star * q[1:-1]), -1j * beta * 2 / (e_star * q[1:-1]), 2 / (e_star * q[1:-1]))
    err = _product_minus_identity((k_xx[1:-1], k_xz[1:-1], k_zz[1:-1]), g)
    assert np.all(err < 16 * EPS)
    # q = 0: zero stiffness (mean clamped by the solver)
    assert k_xx[0] == 0 and k_xz[0] == 0 and k_zz[0] == 0
    # Nyquist mode (even N only): coupling zeroed so real fields stay real (§1.6)
    if nodes % 2 == 0:
        assert k_xz[-1] == 0
    else:
        assert k_xz[-1] == pytest.approx(off[-1], rel=16 * EPS)


def test_halfplane_coupled_without_nodes_keeps_last_mode():
    q = kernels.wavenumbers(64, 1.0)
    assert kernels.halfplane_coupled(q, E, 0.3)[1][-1] != 0


@pytest.mark.parametrize("nu", [0.5 - 1e-3, 0.5 - 1e-6, 0.5])
def test_incompressible_limit_decouples(nu):
    # β = (1 − 2ν)/(2(1 − ν)) → 0: K_xz/K_xx = β (linear in 1 − 2ν); exactly 0 at ν = 1/2, where K = (E*|q|/2) I
    q = kernels.wavenumbers(32, 1.0)
    k_xx, k_xz, k_zz = kernels.halfplane_coupled(q, E, nu)
    beta = (1 - 2 * nu) / (2 * (1 - nu))
    assert np.allclose(np.abs(k_xz[1:]) / k_xx[1:].real, beta, rtol=1e-12, atol=0)
    if nu == 0.5:
        assert np.all(k_xz == 0)
        assert np.allclose(k_zz.real, kernels.halfplane_normal(q, E, nu), rtol=4 * EPS, atol=0)


# ---------------------------------------------------------------- layer on a bonded base

@pytest.mark.parametrize("qd, ratio, digits", [(1, 2.405, 3), (2, 1.314, 3), (3, 1.073, 3), (5, 1.0031, 4)])
def test_layer_normal_tabulated(qd, ratio, digits):
    # §1.3 table (ν = 0.3), given to `digits` decimals: agreement to half a unit of the last digit
    depth = 2e-6
    q = np.array([qd / depth])
    got = kernels.layer_normal(q, E, 0.3, depth)[0] / kernels.halfplane_normal(q, E, 0.3)[0]
    assert abs(got - ratio) <= 0.5 * 10.0**-digits


NUS = np.concatenate([np.linspace(-0.9, 0.4999, 57), [0.25, 0.45, 0.49999]])
QD = np.geomspace(1e-4, 40, 600)


@pytest.mark.parametrize("nu", NUS)
def test_layer_coupled_hermitian_pd_and_inverse_of_compliance(nu):
    depth = 1.5e-6
    q = QD / depth
    k = kernels.layer_coupled(q, E, nu, depth)
    _assert_hermitian_pd(*k)
    # K·G = I with G from §1.3. Round-off: the closed forms lose ~eps/H digits to cancellation at
    # small H = qD (e.g. cosh 2H − 1) and ~eps/(1 − 2ν) near incompressibility. Measured over
    # ν ∈ [−0.9, 0.499999], qD ∈ [1e-4, 40]: max |K·G − I| / (eps(1 + 1/H + 1/(1−2ν))) = 6.7 → factor 32.
    err = _product_minus_identity(k, _layer_compliance(q, E, nu, depth))
    assert np.all(err <= 32 * EPS * (1 + 1 / QD + 1 / (1 - 2 * nu)))
    # frictionless-top normal stiffness = 1/G_zz (§1.3), same round-off budget
    k_eff = kernels.layer_normal(q, E, nu, depth)
    g_zz = _layer_compliance(q, E, nu, depth)[2]
    assert np.all(np.abs(k_eff * g_zz - 1) <= 32 * EPS * (1 + 1 / QD + 1 / (1 - 2 * nu)))


@pytest.mark.parametrize("nu", [-0.9, 0.0, 0.3, 0.45, 0.49, 0.4999])
def test_layer_deep_limit_is_halfplane(nu):
    # H = qD → ∞: the layer deviates from the half-plane by ~C(ν) H² e^{−2H}; measured at
    # H = 5…20: C ≈ 0.7 (ν = −0.9) … 2.01e4 (ν = 0.4999, the small coupling entry) ≤ 4.02/(1 − 2ν);
    # bound 8/(1 − 2ν) plus 16 eps of round-off.
    depth = 1e-6
    qd = np.array([5.0, 10.0, 15.0, 20.0, 30.0, 39.9, 40.0, 41.0, 1e3])
    q = qd / depth
    bound = 8 / (1 - 2 * nu) * qd**2 * np.exp(-2 * qd) + 16 * EPS
    hp = kernels.halfplane_coupled(q, E, nu)
    for a, b in zip(kernels.layer_coupled(q, E, nu, depth), hp):
        assert np.all(np.abs(a / b - 1) <= bound)
    k_n = kernels.layer_normal(q, E, nu, depth)
    assert np.all(np.abs(k_n / kernels.halfplane_normal(q, E, nu) - 1) <= bound)


@pytest.mark.parametrize("nu", [-0.9, 0.0, 0.3, 0.4999])
def test_layer_continuous_across_internal_switch(nu):
    # the code switches to the half-plane formula for qD > 40: K/(E*q/2) must not jump there
    # (difference of the two formulas ~4/(1−2ν)·1600 e^{−80} < 1e-27; round-off level, 16 eps)
    depth = 1e-6
    qd = 40.0 * np.array([1 - 1e-12, 1.0, 1 + 1e-12])
    q = qd / depth
    f = kernels.halfplane_normal(q, E, nu)
    for comp in kernels.layer_coupled(q, E, nu, depth):
        scaled = comp / f
        assert np.all(np.abs(scaled - scaled[1]) <= 16 * EPS * np.abs(scaled[1]))
    scaled = kernels.layer_normal(q, E, nu, depth) / f
    assert np.all(np.abs(scaled - scaled[1]) <= 16 * EPS * scaled[1])


@pytest.mark.parametrize("nu", [-0.9, 0.0, 0.25, 0.3, 0.45, 0.4999])
def test_layer_thin_limit(nu):
    # H = qD → 0 (§1.3/§1.5): k_zz^eff → M/D, K_xx → μ/D, K_zz → M/D, coupling → 0.
    # The deviations are O(H²) for the diagonals and O(H) for the coupling; measured coefficients
    # ≤ 0.26, 1.0, 0.42, 1665 … (largest at ν → 1/2) are all below 1 + 1/(1 − 2ν), used as bound.
    depth = 2e-6
    _, mu, m = _moduli(E, nu)
    c = 1 + 1 / (1 - 2 * nu)
    for h in (1e-2, 1e-3, 1e-4):
        q = np.array([h / depth])
        k_xx, k_xz, k_zz = kernels.layer_coupled(q, E, nu, depth)
        assert abs(kernels.layer_normal(q, E, nu, depth)[0] / (m / depth) - 1) <= c * h**2
        assert abs(k_xx[0].real / (mu / depth) - 1) <= c * h**2
        assert abs(k_zz[0].real / (m / depth) - 1) <= c * h**2
        assert abs(k_xz[0]) <= c * h * math.sqrt(k_xx[0].real * k_zz[0].real)
    # q = 0 exactly: the uniform-strain values of §1.5, no coupling
    q0 = np.array([0.0, 1.0 / depth])
    k_xx, k_xz, k_zz = kernels.layer_coupled(q0, E, nu, depth)
    assert k_xx[0] == pytest.approx(mu / depth, rel=4 * EPS)
    assert k_zz[0] == pytest.approx(m / depth, rel=4 * EPS)
    assert k_xz[0] == 0
    assert kernels.layer_normal(q0, E, nu, depth)[0] == pytest.approx(m / depth, rel=4 * EPS)


def test_layer_nyquist_coupling_zeroed():
    depth, length = 1e-7, 1e-6
    for nodes in (64, 65):
        q = kernels.wavenumbers(nodes, length)
        k_xz = kernels.layer_coupled(q, E, 0.3, depth, nodes=nodes)[1]
        assert (k_xz[-1] == 0) == (nodes % 2 == 0)
        assert np.all(k_xz[1:-1] != 0)


# ---------------------------------------------------------------- line loads by FFT (signs and factors)

N, L = 4096, 1e-5  # m
SIGMA = 8 * L / N  # Gaussian width ≫ Δx: its spectrum at Nyquist is e^{−π²·64/2} ≈ 1e-137 (no aliasing)


def _gaussian(x):
    return np.exp(-0.5 * (x / SIGMA) ** 2) / (SIGMA * math.sqrt(2 * math.pi))  # unit integral


@pytest.mark.parametrize("nu", [-0.5, 0.0, 0.3, 0.45])
def test_flamant_compressive_line_load_pulls_surface_toward_it(nu):
    # compressive line load P at x = 0: t_z = −P δ(x). Flamant: u_x = −A sgn(x), A = (1−2ν)(1+ν)P/(2E);
    # periodic, zero-mean version: −A sgn(x)(1 − 2|x|/L). A symmetric Gaussian leaves the linear
    # parts unchanged, so away from the load (|x| > 10σ, erfc(10/√2) ~ 1e-23) the FFT result must
    # match to round-off; 1e-9 A covers the FFT round-off (measured ~1e-12 A).
    x = grid(N, L)
    p_line = 2.5e4  # N/m
    t_z = -p_line * _gaussian(x)
    kernel = kernels.halfplane_coupled(kernels.wavenumbers(N, L), E, nu, nodes=N)
    u_x, u_z = _solve(kernel, np.zeros(N), t_z)
    amp = (1 - 2 * nu) * (1 + nu) * p_line / (2 * E)
    far = np.abs(x) > 10 * SIGMA
    expected = -amp * np.sign(x) * (1 - 2 * np.abs(x) / L)
    assert np.max(np.abs(u_x - expected)[far]) <= 1e-9 * amp
    # the sign itself, plainly: right of the load the surface moves in −x (toward the load)
    assert np.all(u_x[(x > 10 * SIGMA) & (x < 0.4 * L)] < 0)
    assert np.all(u_x[(x < -10 * SIGMA) & (x > -0.4 * L)] > 0)
    assert u_z[N // 2] < 0  # and it is pushed down under the load


@pytest.mark.parametrize("nu", [-0.5, 0.0, 0.3, 0.45])
def test_cerruti_tangential_line_load_surface_ahead_moves_down(nu):
    # tangential line load Q in +x: t_x = +Q δ(x); the surface ahead (x > 0) moves down:
    # u_z = −A sgn(x)(1 − 2|x|/L), A = (1−2ν)(1+ν)Q/(2E) (same round-off argument as above)
    x = grid(N, L)
    q_line = 1.5e4  # N/m
    kernel = kernels.halfplane_coupled(kernels.wavenumbers(N, L), E, nu, nodes=N)
    u_x, u_z = _solve(kernel, q_line * _gaussian(x), np.zeros(N))
    amp = (1 - 2 * nu) * (1 + nu) * q_line / (2 * E)
    far = np.abs(x) > 10 * SIGMA
    expected = -amp * np.sign(x) * (1 - 2 * np.abs(x) / L)
    assert np.max(np.abs(u_z - expected)[far]) <= 1e-9 * amp
    assert np.all(u_z[(x > 10 * SIGMA) & (x < 0.4 * L)] < 0)
    # the loaded point is dragged along +x; its tangential profile is the log profile (G_xx = G_zz)
    e_star = E / (1 - nu**2)
    ln_profile = _smoothed_log(x)
    assert np.max(np.abs(u_x + 2 * q_line / (math.pi * e_star) * ln_profile)[np.abs(x) > 30 * SIGMA]) <= (
        1e-8 * 2 * q_line / (math.pi * e_star))
    assert u_x[N // 2] > 0


def _smoothed_log(x):
    """ln|2 sin(πx/L)| convolved with the Gaussian: f + σ²f''/2 + σ⁴f''''/8 (+ O(σ⁶/x⁶))."""
    k = math.pi / L
    s = np.sin(k * x)
    with np.errstate(divide="ignore", invalid="ignore"):  # x = 0 (the load point) is never compared
        f = np.log(np.abs(2 * s))
        csc2 = 1 / s**2
        f2 = -k**2 * csc2
        f4 = -2 * k**4 * (3 * csc2**2 - 2 * csc2)
    return f + SIGMA**2 / 2 * f2 + SIGMA**4 / 8 * f4


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
@pytest.mark.parametrize("coupled", [False, True])
def test_line_load_log_profile(nu, coupled):
    # §1.1: compressive line load P: u_z(x) − ū = (2P/(πE*)) ln|2 sin(πx/L)| (the factor 2 of E*|q|/2).
    # With the Gaussian load the profile is the convolution; its Taylor series to σ⁴ leaves an error
    # ~2.5 (σ/x)⁶ ≤ 4e-9 for |x| > 30σ, so 1e-8 of 2P/(πE*) (a factor-2 or sign error is O(1)).
    x = grid(N, L)
    p_line = 2.5e4
    t_z = -p_line * _gaussian(x)
    q = kernels.wavenumbers(N, L)
    if coupled:
        _, u_z = _solve(kernels.halfplane_coupled(q, E, nu, nodes=N), np.zeros(N), t_z)
    else:
        k = kernels.halfplane_normal(q, E, nu)
        u_hat = np.zeros(q.size, complex)
        u_hat[1:] = scipy.fft.rfft(t_z)[1:] / k[1:]
        u_z = scipy.fft.irfft(u_hat, n=N)
    e_star = E / (1 - nu**2)
    scale = 2 * p_line / (math.pi * e_star)
    far = np.abs(x) > 30 * SIGMA
    assert abs(np.mean(u_z)) <= 1e-12 * scale  # mean clamped
    assert np.max(np.abs(u_z - scale * _smoothed_log(x))[far]) <= 1e-8 * scale


def test_layer_stiffer_than_halfplane_and_uniform_settlement():
    # a layer bonded to a rigid base is stiffer than the half-plane (strictly while qD ≤ 20, equal to
    # round-off beyond), and a uniform pressure p settles it by u_z = −p D/M (q = 0 mode, §1.5)
    depth, nu = 2e-7, 0.3
    q = kernels.wavenumbers(N, L)
    k_layer, k_hp = kernels.layer_normal(q, E, nu, depth)[1:], kernels.halfplane_normal(q, E, nu)[1:]
    assert np.all(k_layer >= k_hp * (1 - 4 * EPS))
    assert np.all((k_layer > k_hp)[q[1:] * depth <= 20])
    p = 3e6
    k0 = kernels.layer_normal(q, E, nu, depth)[0]
    _, _, m = _moduli(E, nu)
    assert -p / k0 == pytest.approx(-p * depth / m, rel=4 * EPS)


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.45, 0.49])
@pytest.mark.parametrize("thickness", [None, 2e-8, 1e-7, 1e-6, 1e-5])
def test_normal_kernel_is_the_frictionless_reduction_of_the_coupled_one(nu, thickness):
    """The normal-only model (gfmd_contact.core.model, c = 0) solves u_z alone with t_x = 0: exact only if its kernel
    equals the Schur complement K_zz − |K_xz|²/K_xx of the coupled kernel. The two come from independent
    formulas (§1.1/§1.3 closed forms vs §1.2/§1.4), so this fails if either is wrong."""
    n, length = 256, 1e-6
    q = kernels.wavenumbers(n, length)
    if thickness is None:
        k_n = kernels.halfplane_normal(q, 70e9, nu)
        k_xx, k_xz, k_zz = kernels.halfplane_coupled(q, 70e9, nu)
    else:
        k_n = kernels.layer_normal(q, 70e9, nu, thickness)
        k_xx, k_xz, k_zz = kernels.layer_coupled(q, 70e9, nu, thickness)
    inner = slice(1, -1)  # q = 0 (clamped or M/D, tested elsewhere) and Nyquist (coupling zeroed) excluded
    schur = k_zz.real[inner] - np.abs(k_xz[inner]) ** 2 / k_xx.real[inner]
    # measured ≤ 8e-16 (round-off); 1e-12 leaves room for the cancellation in the thin-layer sinh/cosh terms
    assert np.max(np.abs(schur - k_n[inner]) / k_n[inner]) < 1e-12
