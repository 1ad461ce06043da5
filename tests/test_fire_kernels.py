"""gfmd.fire_kernels: FIRE's per-iteration spectral algebra, numpy and fused, against the formulas written out here
(f̂ = t̂ − K û, P = Σ_q w_q Re(conj f̂_q · v_q), a = M⁻¹ f̂, v ← v + Δt a, f·a, v·M v, v ← keep v + β a, û ← û + Δt v;
the q = 0 mode zeroed where clamped), on random 2×2 blocks (a b; b̄ d) and a one-block (normal-only) case; the trust
region's largest nodal change, max_j |u_j − u_prev,j|."""

import numpy as np
import pytest

from gfmd.fire_kernels import fire_kernels, largest_change
from gfmd.kernels import numba

BACKENDS = ["numpy"] + (["numba"] if numba is not None else [])


def blocks(rng, nq):
    a = rng.random(nq) + 1.0 + 0j
    d = rng.random(nq) + 1.0 + 0j
    b = 0.3 * (rng.standard_normal(nq) + 1j * rng.standard_normal(nq))
    return a, b, d


def times(k, x):
    if len(k) == 1:
        return k[0] * x
    a, b, d = k
    return np.array([a * x[0] + b * x[1], np.conj(b) * x[0] + d * x[1]])


def spectrum(rng, c, nq):
    return rng.standard_normal((c, nq)) + 1j * rng.standard_normal((c, nq))


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("components", [1, 2])
@pytest.mark.parametrize("clamp", [True, False])
def test_fire_kernels_are_the_formulas(backend, components, clamp):
    rng = np.random.default_rng(components + 2 * clamp)
    nq = 33
    w = np.full(nq, 2.0)
    w[0] = w[-1] = 1.0
    if components == 2:
        k, m, inv_m = blocks(rng, nq), blocks(rng, nq), blocks(rng, nq)
    else:
        k, m, inv_m = ((rng.random(nq) + 1.0,) for _ in range(3))
    force_power, accelerate, mix_move = fire_kernels(backend, components=components)
    t_hat, u_hat, v = (spectrum(rng, components, nq) for _ in range(3))
    f = t_hat - times(k, u_hat)
    if clamp:
        f[:, 0] = 0.0
    power = force_power(t_hat, k, u_hat, v, w, clamp)
    np.testing.assert_allclose(t_hat, f, rtol=1e-13, atol=1e-13)
    assert power == pytest.approx(np.sum(w * (np.conj(f) * v).real), rel=1e-12)
    dt = 0.37
    acc_expected = times(inv_m, f)
    v_expected = v + dt * acc_expected
    acc, f_norm, v_norm = accelerate(t_hat, inv_m, m, v, dt, w, np.empty_like(v))
    np.testing.assert_allclose(acc, acc_expected, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(v, v_expected, rtol=1e-13, atol=1e-13)
    assert f_norm == pytest.approx(np.sum(w * (np.conj(f) * acc_expected).real), rel=1e-12)
    assert v_norm == pytest.approx(np.sum(w * (np.conj(v_expected) * times(m, v_expected)).real), rel=1e-12)
    keep, beta = 0.9, 0.25
    u_before = u_hat.copy()
    v_mixed = keep * v_expected + beta * acc_expected
    if clamp:
        v_mixed[:, 0] = 0.0
    mix_move(v, acc, keep, beta, u_hat, dt, clamp)
    np.testing.assert_allclose(v, v_mixed, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(u_hat, u_before + dt * v_mixed, rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("shape", [(7,), (1, 64), (2, 33)])
def test_largest_change_is_the_max_of_the_differences(backend, shape):
    rng = np.random.default_rng(sum(shape))
    u, u_prev = rng.standard_normal(shape), rng.standard_normal(shape)
    change = largest_change(backend)
    assert change(u, u_prev) == float(np.max(np.abs(u - u_prev)))  # a max is exact: the same number
    assert change(u, u) == 0.0
    u[..., -1] = np.nan  # a NaN wins, as numpy's max lets it
    assert np.isnan(change(u, u_prev))


@pytest.mark.skipif(numba is None, reason="numba not installed: the fused kernels are numba's")
@pytest.mark.parametrize("clamp", [True, False])
def test_fused_kernels_on_the_split_blocks_are_the_complex_ones_bit_for_bit(clamp):
    """force_power and accelerate on `Blocks` with a split form (a, d real, b imaginary: an isotropic body's K, M, M⁻¹)
    give the numbers of the complex blocks' fused kernels exactly (what the blocks' zero parts add is exact)."""
    from gfmd.coupled_kernels import hermitian_blocks
    rng = np.random.default_rng(7 + clamp)
    nq = 65
    w = np.full(nq, 2.0)
    w[0] = w[-1] = 1.0

    def isotropic():
        return rng.random(nq) + 1.0 + 0j, 0.3j * rng.standard_normal(nq), rng.random(nq) + 1.0 + 0j

    k, m, inv_m = isotropic(), isotropic(), isotropic()
    split = [hermitian_blocks(*x) for x in (k, m, inv_m)]
    assert all(x.split is not None for x in split)
    force_power, accelerate, _ = fire_kernels("numba", components=2)
    t_hat, u_hat, v = (spectrum(rng, 2, nq) for _ in range(3))
    results = []
    for blocks in ((k, m, inv_m), split):  # plain tuples: the complex kernels
        t, vv = t_hat.copy(), v.copy()
        power = force_power(t, blocks[0], u_hat, vv, w, clamp)
        acc, f_norm, v_norm = accelerate(t, blocks[2], blocks[1], vv, 0.37, w, np.empty_like(vv))
        results.append((t, vv, acc, power, f_norm, v_norm))
    for a, b in zip(*results):
        assert np.array_equal(a, b)
