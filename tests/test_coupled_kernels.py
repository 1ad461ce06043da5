"""gfmd.coupled_kernels equal to the formulas they fuse: Eq. 2's tractions (`gfmd_contact.core.law_equations`), the 2×2
block products of K(q), the law tangent's nodal product, the weighted spectral dot and the two-level
preconditioner's nodal passes (against a dense block matrix Z built here), numpy and numba."""

import numpy as np
import pytest

from gfmd_contact.core.law_equations import CompressionOverflowError, traction_coupled
from gfmd import kernels
from gfmd.coupled_kernels import coarse_passes, coupled_kernels

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


@pytest.mark.filterwarnings("ignore:invalid value encountered")
@pytest.mark.parametrize("backend", BACKENDS)
def test_fused_tractions_of_an_infinite_gap_are_the_laws(backend, fields):
    """A node at Δn = +inf (no error in the law, its T = NaN there): the law's values, not a silent 0."""
    u, z_ind = fields
    z_ind = z_ind.copy()
    z_ind[7] = np.inf
    t = coupled_kernels(backend)[2](u, z_ind, PARAMS, np.empty_like(u))
    t_n, t_t = traction_coupled(z_ind - u[1], -u[0], *PARAMS)
    np.testing.assert_array_equal(np.isnan(t[1]), np.isnan(t_n))
    np.testing.assert_allclose(t[1], t_n, rtol=1e-14, atol=0)
    np.testing.assert_allclose(t[0], t_t, rtol=1e-14, atol=0)


@pytest.mark.skipif(kernels.numba is None, reason="numba not installed")
def test_fused_tractions_call_no_libm_exp():
    """The tractions loop inlines `gfmd.vector_exp.exp` (LLVM vectorizes it; libm's exp is a scalar call): its source
    compiled afresh with the kernel's flags (numba does not show a cached kernel's assembly)."""
    from gfmd.coupled_kernels import _tractions_kernel
    from gfmd.vector_exp import STRICT_FLAGS

    kernel = kernels.numba.njit(fastmath=STRICT_FLAGS)(_tractions_kernel.py_func)
    u, z_ind = np.zeros((2, 8)), np.ones(8) * 1e-9
    kernel(u, z_ind, *PARAMS, -1.0, np.empty_like(u))
    asm = kernel.inspect_asm(kernel.signatures[0])
    assert "pd" in asm
    assert not [line for line in asm.splitlines() if "$exp" in line or "exp@" in line]


def _blocks(n, rng):
    """Random consecutive blocks from node 0 (int64 starts, widths) ending before or at n, and Z (n × m)."""
    widths = rng.integers(1, 40, size=60)
    widths = widths[np.cumsum(widths) <= n - 5]
    starts = np.r_[0, np.cumsum(widths)[:-1]].astype(np.int64)
    z = np.zeros((n, widths.size))
    for j, (a, p) in enumerate(zip(starts, widths)):
        z[a:a + p, j] = 1.0
    return starts, widths.astype(np.int64), z


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("clamp", [True, False])
def test_coarse_passes_equal_the_dense_formulas(backend, clamp):
    rng = np.random.default_rng(11)
    starts, widths, z = _blocks(N, rng)
    pi = np.eye(N) - 1.0 / N if clamp else np.eye(N)
    d_nn, d_nt, d_tn, d_tt = rng.normal(size=(4, N))
    y, s = rng.normal(size=(2, N)), rng.normal(size=(2, N))
    c = rng.normal(size=(2, widths.size))
    row_block_sums, coarse_residual, tangent_plus = coarse_passes(backend)
    np.testing.assert_allclose(row_block_sums(y, starts, widths), y @ z, rtol=1e-12, atol=1e-12)
    w = (pi @ z @ c.T).T  # Π Z c per component
    dw = np.stack([d_tt * w[0] + d_tn * w[1], d_nt * w[0] + d_nn * w[1]])
    g = coarse_residual(d_nn, d_nt, d_tn, d_tt, y, c, starts, widths, clamp, np.empty((2, N)))
    np.testing.assert_allclose(g, y - dw, rtol=1e-12, atol=1e-12)
    out = tangent_plus(d_nn, d_nt, d_tn, d_tt, s, g, clamp, np.empty((2, N)))
    ds = np.stack([d_tt * s[0] + d_tn * s[1], d_nt * s[0] + d_nn * s[1]])
    np.testing.assert_allclose(out, (pi @ (ds + g).T).T, rtol=1e-12, atol=1e-12)


@pytest.mark.skipif(kernels.numba is None, reason="numba not installed: the numpy backend has no split form (None)")
def test_split_block_product_is_the_complex_one_bit_for_bit():
    """`split_block_times` on `Blocks.split` (Re a, Im b, Re d) gives the complex block product's numbers exactly;
    `hermitian_blocks` finds that form only where a, d are real and b imaginary; `divided_blocks` keeps it."""
    from gfmd.coupled_kernels import divided_blocks, hermitian_blocks, split_block_times
    rng = np.random.default_rng(11)
    nq = 257
    a, d = rng.uniform(1, 2, nq) + 0j, rng.uniform(1, 2, nq).astype(complex)
    b = 1j * rng.normal(size=nq)
    x = rng.normal(size=(2, nq)) + 1j * rng.normal(size=(2, nq))
    blocks = hermitian_blocks(a, b, d)
    assert blocks.split is not None and all(s.dtype == float for s in blocks.split)
    complex_times = coupled_kernels("numba")[0]
    expected = complex_times(a, b, d, x, np.empty_like(x))
    assert np.array_equal(split_block_times("numba")(*blocks.split, x, np.empty_like(x)), expected)
    scale = rng.uniform(0.5, 2.0, nq)
    quotient = divided_blocks(blocks, scale)
    assert quotient.split is not None
    assert np.array_equal(split_block_times("numba")(*quotient.split, x, np.empty_like(x)),
                          complex_times(a / scale, b / scale, d / scale, x, np.empty_like(x)))
    assert hermitian_blocks(a + 1e-3j, b, d).split is None  # Im a ≠ 0
    assert hermitian_blocks(a, b + 1e-3, d).split is None  # Re b ≠ 0
    assert split_block_times("numpy") is None
    assert divided_blocks((a,), 2.0)[0] is not a


@pytest.mark.parametrize("thickness", ["inf", 2e-7])
def test_an_isotropic_bodys_blocks_have_the_split_form(thickness):
    """K(q), M_q and M_q⁻¹ of a coupled half-plane and layer (`gfmd.problem.Elastic`) are real on the diagonal and
    imaginary off it, so the fused products run on the split form; the products are the complex ones either way."""
    from pathlib import Path

    from gfmd_contact.core import surfaces
    from gfmd_contact.core.scene import load_scene
    from gfmd.loading import prepare
    from gfmd.problem import Elastic
    base = Path(__file__).resolve().parents[1] / "studies" / "seed" / "seed_base.toml"
    scene = load_scene(base).replace(**{"surface.nodes": 128, "surface.length": 128 * 2.5e-9,
                                        "surface.rollon_wavelength": 2e-8, "surface.rolloff_wavelength": 8e-8,
                                        "material.poisson_ratio": 0.1, "material.thickness": thickness,
                                        "interface.tangential_ratio": 0.5, "surface.realizations": 1})
    model = prepare(scene, surfaces.profile(scene.surface, 0), 0).physics
    elastic = Elastic(model, 1e16, 2e16)
    for blocks in (elastic.stiffness_blocks, elastic.mass, elastic.inv_mass):
        assert blocks.split is not None
    rng = np.random.default_rng(3)
    x = rng.normal(size=(2, 65)) + 1j * rng.normal(size=(2, 65))
    for blocks in (elastic.mass, elastic.inv_mass):
        np.testing.assert_array_equal(elastic._apply(blocks, x),
                                      coupled_kernels("numpy")[0](*blocks, x, np.empty_like(x)))
