"""The two-level preconditioner's fused nodal passes (`gfmd.coarse_kernels`).

`TwoLevel.apply` with blocks covering the nodes (`cover`, the default `COARSE_GAPS`) runs three fused passes; the
same operator through the generic path (the coarse nodes as an index array: spread by np.repeat, mean removal by a
pass, restriction by np.add.reduceat) must give the same ŝ and nodal s, with numba's kernels and numpy's, on a
half-plane (q = 0 clamped, the last block dropped) and on a layer. The coarse matrix a rebuild assembles
(`coarse_matrix`) is Zᵀ Π (K + D) Π Z as dense products give it, with either backend.
"""

import numpy as np
import pytest

from gfmd import coarse_kernels, kernels
from gfmd import cohesive_preconditioner as cp
from gfmd.fft import Fft
from tests.test_cohesive_preconditioner import stiff_patches

BACKENDS = ["numpy"] + (["numba"] if kernels.numba is not None else [])


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("clamp", [True, False])
def test_fused_apply_equals_the_generic_path(backend, clamp):
    n = 512
    k = 2.0 * np.pi * np.fft.rfftfreq(n) * 1e3  # K(q) ∝ q
    if not clamp:
        k[0] = 0.3 * k[1]  # a layer: the q = 0 mode has a stiffness
    kn = 20.0 * k[1]
    rng = np.random.default_rng(3)
    pre = cp.TwoLevel(Fft(n), k, clamp, n, kn)
    assert pre.rebuild(stiff_patches(n, kn, rng)) and isinstance(pre.index, slice)
    pre.kernels = coarse_kernels.coarse_kernels(backend)
    f_hat = np.fft.rfft(rng.standard_normal(n))
    if clamp:
        f_hat[0] = 0.0
    s_hat, s = pre.apply(f_hat.copy())
    fused = s_hat.copy(), s.copy()
    pre.index = np.arange(pre.index.stop)  # the same coarse space through the generic path
    s_hat, s = pre.apply(f_hat.copy())
    np.testing.assert_allclose(fused[0], s_hat, rtol=0, atol=1e-13 * np.max(np.abs(s_hat)))
    np.testing.assert_allclose(fused[1], s, rtol=0, atol=1e-13 * np.max(np.abs(s)))
    np.testing.assert_allclose(fused[1], np.fft.irfft(fused[0], n), rtol=0, atol=1e-12 * np.max(np.abs(s)))


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("clamp", [True, False])
def test_coarse_matrix_is_the_dense_galerkin_product(backend, clamp):
    n = 256
    k = 2.0 * np.pi * np.fft.rfftfreq(n) * 1e3
    if not clamp:
        k[0] = 0.3 * k[1]
    kn = 20.0 * k[1]
    fft = Fft(n)
    pre = cp.TwoLevel(fft, k, clamp, n, kn)
    k_loc = stiff_patches(n, kn, np.random.default_rng(4))
    assert pre.rebuild(k_loc)
    nodes, starts, p, _ = pre.coarse
    z = np.zeros((n, starts.size))
    for j, (a, w) in enumerate(zip(nodes[starts], p)):
        z[a:a + w, j] = 1.0
    proj = np.eye(n) - (1.0 / n if clamp else 0.0)
    kz = np.array([fft.irfft(k * fft.rfft(col)) for col in (proj @ z).T]).T
    dense = (proj @ z).T @ (kz + np.diag(pre.d) @ proj @ z)
    mass = np.add.reduceat(pre.d[nodes], starts)
    e = coarse_kernels.coarse_matrix(backend)(pre.cs2, n, nodes[starts], p, mass, clamp, float(np.sum(pre.d)))
    np.testing.assert_array_equal(e, e.T)
    np.testing.assert_allclose(e, dense, rtol=0, atol=1e-9 * np.max(np.abs(dense)))


def test_unknown_backend_names_the_variable():
    with pytest.raises(ValueError, match="GFMD_JIT"):
        coarse_kernels.coarse_kernels("fortran")
