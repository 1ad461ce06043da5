"""gfmd.coupled_kernels equal to the formulas they fuse: Eq. 2's tractions (`contact.law_equations`), the 2×2
block products of K(q), the law tangent's nodal product and the weighted spectral dot, numpy and numba."""

import numpy as np
import pytest

from contact.law_equations import CompressionOverflowError, traction_coupled
from gfmd import kernels
from gfmd.coupled_kernels import coupled_kernels

BACKENDS = ["numpy"] + (["numba"] if kernels.numba is not None else [])
PARAMS = (0.3, 2e-9, 0.15, 1e-9)  # φn (J/m²), δn (m), φt (J/m²), δt (m)
N = 1001


@pytest.fixture
def fields():
    rng = np.random.default_rng(3)
    u = np.stack([rng.normal(0.0, 2e-9, N), rng.normal(0.0, 5e-9, N)])  # (x, z), m
    z_ind = rng.uniform(-5e-9, 20e-9, N)
    return u, z_ind


@pytest.mark.parametrize("backend", BACKENDS)
def test_fused_tractions_equal_the_laws_formula(backend, fields):
    u, z_ind = fields
    t = coupled_kernels(backend)[2](u, z_ind, PARAMS, np.empty_like(u))
    t_n, t_t = traction_coupled(z_ind - u[1], -u[0], *PARAMS)
    np.testing.assert_allclose(t[1], t_n, rtol=1e-14, atol=0)
    np.testing.assert_allclose(t[0], t_t, rtol=1e-14, atol=0)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("bad", [-700.0, np.nan, -np.inf])
def test_fused_tractions_raise_the_laws_overflow_error(backend, bad, fields):
    u, z_ind = fields
    z_ind = z_ind.copy()
    z_ind[N // 2] = bad * PARAMS[1] + u[1, N // 2]  # Δn = bad·δn at one node
    with pytest.raises(CompressionOverflowError):
        coupled_kernels(backend)[2](u, z_ind, PARAMS, np.empty_like(u))


@pytest.mark.parametrize("backend", BACKENDS)
def test_block_and_tangent_products_equal_the_stacked_formulas(backend):
    rng = np.random.default_rng(5)
    nq = 257
    a, d = rng.uniform(1, 2, nq) + 0j, rng.uniform(1, 2, nq).astype(complex)
    b = 1j * rng.normal(size=nq)
    x = rng.normal(size=(2, nq)) + 1j * rng.normal(size=(2, nq))
    block_times, tangent_times, _, weighted_dot = coupled_kernels(backend)
    out = block_times(a, b, d, x, np.empty_like(x))
    np.testing.assert_allclose(out, np.stack([a * x[0] + b * x[1], np.conj(b) * x[0] + d * x[1]]), rtol=1e-15)
    d_nn, d_nt, d_tn, d_tt = rng.normal(size=(4, N))
    v = rng.normal(size=(2, N))
    dv = tangent_times(d_nn, d_nt, d_tn, d_tt, v, np.empty_like(v))
    np.testing.assert_allclose(dv, np.stack([d_tt * v[0] + d_tn * v[1], d_nt * v[0] + d_nn * v[1]]), rtol=1e-15)
    w = rng.uniform(1, 2, nq)
    y = rng.normal(size=(2, nq)) + 1j * rng.normal(size=(2, nq))
    assert weighted_dot(w, x, y) == pytest.approx(float(np.sum(w * (np.conj(x) * y).real)), rel=1e-13)
