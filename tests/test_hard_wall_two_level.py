"""The two-level dual hard-wall CG (`gfmd.algorithms.hard_wall_two_level_cg`).

* its coarse blocks never span a gap of the contact set and hold ≤ the block size;
* G_AA Z from G's real-space kernel sums (no FFT) equals the dense product, and the two-level
  preconditioner is symmetric positive definite;
* on a warm-started ramp it reaches the band-only dual CG's equilibrium (same contact set, within the
  tolerance) and passes the independent KKT check of tests/test_gfmd_fast.py; its pairs per 0.1 nm step are
  fewer than the band-only dual CG's on the same steps (a count, not a time);
* it must fall back: past `dual_contact_limit` it hands the step over to the primal CG ("cg-dual2→cg"),
  which ends at the KKT point; where one coarse block per patch would cost more than the FFT pairs it saves
  (the cost gate) the band preconditions alone; a bad `dual_coarse_block` is refused, naming the key.
"""

import numpy as np
import pytest
import scipy.fft
from hypothesis import given, settings as hyp_settings, strategies as st

from gfmd_contact.core.loading import indenter_surface
from gfmd.algorithms import hard_wall_two_level_cg as two
from gfmd.fft import Fft
from gfmd.problem import Elastic, Problem, band_stiffness, stiffness_operator
from gfmd.solver import Settings, relax
from gfmd.stopping import finish
from test_gfmd_fast import TOL, assert_same_kkt_equilibria, case, kkt_violation, ramp, two_ramps


@hyp_settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(0, 299), min_size=1, max_size=120, unique=True), st.integers(1, 20))
def test_coarse_blocks_stay_within_runs(picks, block):
    act = np.unique(picks)
    starts = two.coarse_blocks(act, block)
    ends = np.r_[starts[1:], act.size]
    assert starts[0] == 0 and np.all(ends - starts <= block) and np.all(ends > starts)
    for a, b in zip(starts, ends):
        assert np.all(np.diff(act[a:b]) == 1)  # consecutive nodes: one contiguous stretch of the line
    gaps = np.flatnonzero(np.diff(act) > 1) + 1
    assert set(gaps) <= set(starts)  # every run starts a block


def _kernels(n):
    sc, h, model, law, wall_tol = case(nodes=n)
    g = np.real(Elastic(model, 0.0, 0.0).inv_mass[0])
    k = np.real(model.k_zz)
    return scipy.fft.irfft(g.astype(complex), n=n), scipy.fft.irfft(k.astype(complex), n=n)


@hyp_settings(max_examples=20, deadline=None)
@given(st.lists(st.integers(0, 511), min_size=2, max_size=45, unique=True), st.integers(1, 12))  # 45² < 4 · 512
def test_coarse_space_is_the_dense_product_and_spd(picks, block):
    n = 512
    g_kernel, k_kernel = _kernels(n)
    act = np.unique(picks)
    assert (1 + np.count_nonzero(np.diff(act) > 1)) * act.size <= two.COARSE_ENTRIES_PER_NODE * n  # not gated
    coarse = two.coarse_space(np.cumsum(g_kernel[np.arange(-n, n) % n]), act, n, block)
    assert coarse is not None
    starts, gz, factor = coarse
    z = np.zeros((act.size, starts.size))
    z[np.arange(act.size), np.searchsorted(starts, np.arange(act.size), side="right") - 1] = 1.0
    g_aa = g_kernel[(act[:, None] - act[None, :]) % n]
    # the cumulative sums lose ~log10(n) digits to cancellation against the direct sum
    np.testing.assert_allclose(gz, g_aa @ z, rtol=0, atol=1e-12 * n * np.max(np.abs(g_kernel)))
    band = band_stiffness(k_kernel, act, n, two.BAND_HALF_WIDTH)
    prec = np.stack([two.two_level(e, lambda r: band @ r, coarse) for e in np.eye(act.size)], axis=1)
    np.testing.assert_allclose(prec, prec.T, rtol=1e-9, atol=1e-9 * np.max(np.abs(prec)))
    assert np.min(np.linalg.eigvalsh(0.5 * (prec + prec.T))) > 0


@pytest.mark.parametrize("thickness", [None, 0.5e-6])
def test_two_level_equals_the_band_dual_and_is_kkt(thickness):
    model, z_of, deltas, h, now, before = two_ramps(Settings(tolerance=TOL, dual_contact_limit=1.0),
                                                    Settings(tolerance=TOL, dual_contact_limit=1.0, dual_coarse_block=0),
                                                    thickness)
    assert {r.method for r in now} == {"cg-dual2"} and {r.method for r in before} == {"cg-dual"}
    assert_same_kkt_equilibria(model, z_of, deltas, h, now, before)


def test_fewer_fft_pairs_than_the_band_dual_on_the_fig3_step():
    """0.1 nm steps after a 1.5 nm approach at N = 2^14 (the bench's Fig. 3 step, on the bench_gfmd scene)."""
    sc, h, model, law, wall_tol = case(nodes=2**14)
    d0 = sc.loading.initial_separation
    deltas = np.r_[1.5e-9 * np.arange(1, 6), 7.5e-9 + 0.1e-9 * np.arange(1, 7)]

    def z_of(d):
        return indenter_surface(h, d0, d0 + d)

    now = ramp(model, law, z_of, deltas, Settings(tolerance=1e-8), wall_tol)[-4:]
    before = ramp(model, law, z_of, deltas, Settings(tolerance=1e-8, dual_coarse_block=0), wall_tol)[-4:]
    assert {r.method for r in now} == {"cg-dual2"}
    assert sum(r.fft_pairs for r in now) < sum(r.fft_pairs for r in before)


def test_falls_back_to_the_primal_past_the_contact_limit():
    sc, h, model, law, wall_tol = case()
    d0 = sc.loading.initial_separation

    def z_of(d):
        return indenter_surface(h, d0, d0 + d)

    deltas = 1.5e-9 * np.arange(1, 6)
    out = ramp(model, law, z_of, deltas, Settings(tolerance=TOL, dual_contact_limit=2e-3), wall_tol)
    assert "cg-dual2→cg" in {r.method for r in out}
    for d, r in zip(deltas, out):
        assert kkt_violation(model, z_of(d), r.u_z) < TOL * (1 + 1e-3)


@pytest.mark.parametrize("block", [-1, 2.5, "16"])
def test_bad_coarse_block_is_refused(block):
    sc, h, model, law, wall_tol = case()
    d0 = sc.loading.initial_separation
    with pytest.raises(ValueError, match="Settings.dual_coarse_block"):
        relax(model, law, indenter_surface(h, d0, d0 + 5e-9), np.zeros((1, model.nodes // 2 + 1), complex),
              Settings(dual_coarse_block=block), wall_tol)


def test_too_many_patches_leave_the_band_alone():
    """The cost gate: one block per patch would exceed COARSE_ENTRIES_PER_NODE · N entries of G_AA Z."""
    n = 512
    g_kernel, _ = _kernels(n)
    g_sum = np.cumsum(g_kernel[np.arange(-n, n) % n])
    many = np.arange(0, n, 4)  # 128 one-node patches: 128 · 128 > 4 · 512
    few = np.arange(0, 40)  # one patch of 40 nodes
    assert two.coarse_space(g_sum, many, n, 16) is None
    assert two.coarse_space(g_sum, few, n, 16) is not None
    assert two.two_level(np.ones(many.size), lambda r: 2 * r, None).tolist() == [2.0] * many.size


def test_a_converged_guess_keeps_the_arrays_its_residual_was_taken_on():
    """The dual CG returns a guess that already passes the test with the fields of that test's arrays (u, K u):
    the same fields finish recomputes from the spectra (round-off), at the FFT pairs actually spent (two irfft, one
    rfft)."""
    sc, h, model, law, wall_tol = case()
    d0 = sc.loading.initial_separation
    for d in (-2e-9, 3e-9):  # out of contact, and in contact from its own converged state
        z = indenter_surface(h, d0, d0 + d)
        first = relax(model, law, z, np.zeros((1, model.nodes // 2 + 1), complex), Settings(tolerance=TOL), wall_tol)
        again = relax(model, law, z, first.u_hat, Settings(tolerance=TOL), wall_tol)
        assert first.converged and again.converged and again.iterations == 0 and again.fft_pairs == 1.5
        ref = finish(Problem(model, law, z, wall_tol), again.u_hat, 0, again.residual, True, "")
        scale = float(np.max(np.abs(ref.t_z))) or model.reference_traction
        # round-off: observed 7e-18 of the profile span and 9e-16 of max |t_z| (2048 nodes); bounds 100× that
        np.testing.assert_allclose(again.u_z, ref.u_z, rtol=0, atol=1e-15 * float(np.ptp(h)))
        np.testing.assert_allclose(again.gap, ref.gap, rtol=0, atol=1e-15 * float(np.ptp(h)))
        np.testing.assert_allclose(again.t_z, ref.t_z, rtol=0, atol=1e-13 * scale)
        assert (d < 0) == (not np.any(again.t_z))


def test_the_real_space_kernels_are_made_once_per_model_as_made_in_the_step():
    """The dual CGs' K and G kernels (the band's, `coarse_space`'s sums) depend on K(q) alone: made in a task's first
    step and kept on the model's operator, read-only, holding what the step made before (the same FFT backend); a
    step from the same guess on the same model then gives the same state bit for bit with 1 FFT pair fewer."""
    sc, h, model, law, wall_tol = case()
    d0 = sc.loading.initial_separation
    z = indenter_surface(h, d0, d0 + 4.5e-9)
    guess = np.zeros((1, model.nodes // 2 + 1), complex)
    first, again = (relax(model, law, z, guess, Settings(tolerance=TOL), wall_tol) for _ in range(2))
    assert first.method == again.method == "cg-dual2" and first.converged
    np.testing.assert_array_equal(again.u_hat, first.u_hat)
    assert again.fft_pairs == first.fft_pairs - 1.0
    op = stiffness_operator(model)
    fft = Fft(model.nodes)
    n = model.nodes
    kept = op.__dict__["_kept"]
    k_kernel, g_sum = kept[("stiffness kernel", fft.backend)], kept[("compliance sums", fft.backend)]
    np.testing.assert_array_equal(k_kernel, fft.irfft(np.real(model.k_zz).astype(complex)))
    g = np.real(op.inv_mass[0]).astype(complex)
    np.testing.assert_array_equal(g_sum, np.cumsum(fft.irfft(g)[np.arange(-n, n) % n]))
    assert not k_kernel.flags.writeable and not g_sum.flags.writeable
    assert op.kept(("stiffness kernel", fft.backend), lambda: 1 / 0) is k_kernel
