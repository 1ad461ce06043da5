"""The cohesive NCG's preconditioners (`gfmd.cohesive_preconditioner`).

* "two-level": its coarse matrix is Zᵀ(K + D)Z computed by FFT (the double cumulative sums of K's kernel);
  the balancing operator is symmetric positive definite and exact on the coarse space (M A z = z for z in
  range(ΠZ)), its nodal s the irfft of its ŝ, on a half-plane (q = 0 clamped) and on a layer;
* a ramp into strong adhesion with the coarse level engaged from the first iteration reaches the states of
  the default K⁻¹ (within the tolerance bound of tests/test_solver_ncg.py) in fewer iterations;
* it is built only by the steps that reach its engagement point, once each;
* a slow step engages it early (`slow_step`): the same states, fewer iterations on a strong-adhesion ramp;
* D is k_loc with its sign (`SIGNED_CURVATURE`): a softening tail over the gaps lifts the smallest eigenvalue of the
  preconditioned operator above the one max(k_loc, 0) leaves; where the signed E is not definite, max(k_loc, 0);
* `TwoLevel.apply_split` (the force as tractions and the state's spectral part and coarse tail, two FFTs) gives
  `apply`'s s in its spectral part and tail, the force in its two parts, and the parts from which the NCG's products
  are the direct ones; Zᵀ K s keeps the coarse Zᵀ K u equal to its direct value along the NCG's steps; `fold` makes
  the spectral part the state's spectrum; FFT.rfft_scratch is rfft;
* a bad Settings value is refused naming the key.
"""

import numpy as np
import pytest

from gfmd import cohesive_preconditioner as cp
from gfmd.coarse_kernels import block_sums
from gfmd.fft import Fft
from gfmd.solver import Settings, relax
from tests.test_solver_ncg import case, ramp, tolerance_bound

TOL = 1e-10


def stiff_patches(n, kn, rng):
    """k_loc with a few stiff patches (≈ kn), soft negative tails and zeros elsewhere."""
    k_loc = np.zeros(n)
    for start, width in ((10, 40), (90, 7), (150, 60), (250, 3)):
        k_loc[start:start + width] = kn * (0.5 + rng.random(width))
        k_loc[start + width:start + width + 3] = -0.1 * kn  # beyond the law's peak (in D with its sign)
    return k_loc


def dense(apply, n, fft):
    """The matrix of a spectral operator f̂ ↦ ŝ acting on nodal vectors (columns: unit vectors)."""
    cols = [fft.irfft(apply(fft.rfft(e))) for e in np.eye(n)]
    return np.array(cols).T


@pytest.mark.parametrize("thickness", [None, 0.5e-6])
def test_two_level_is_spd_and_exact_on_its_coarse_space(thickness):
    sc, h, model, law, z_of = case(nodes=256, thickness=thickness)
    n, clamp = model.nodes, model.half_plane
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)
    kn = 20.0 * float(k[1])  # crossover near mode 20: blocks of about 256 / 40 nodes
    fft = Fft(n)
    pre = cp.TwoLevel(fft, k, clamp, n, kn)
    assert 4 <= pre.block <= 7
    k_loc = stiff_patches(n, kn, np.random.default_rng(1))
    assert pre.rebuild(k_loc) and not pre.rebuild(k_loc)  # unchanged stiff set: kept
    stiff, starts, p, _ = pre.coarse
    assert starts.size > 4  # several blocks per wide patch
    # Zᵀ K Z by FFT against the double cumulative sums
    z = np.zeros((n, starts.size))
    for j, (a, w) in enumerate(zip(stiff[starts], p)):
        z[a:a + w, j] = 1.0
    kz = np.array([fft.irfft(k * fft.rfft(col)) for col in z.T]).T
    np.testing.assert_allclose(block_sums(pre.cs2, n, stiff[starts], p), z.T @ kz, rtol=1e-9,
                               atol=1e-9 * np.max(np.abs(kz)))
    # the balancing operator on the (mean-free where clamped) nodal space
    proj = np.eye(n) - (1.0 / n if clamp else 0.0)
    # D with its sign (the softening tails too) where E is definite with it (`SIGNED_CURVATURE`)
    np.testing.assert_array_equal(pre.d, k_loc if cp.SIGNED_CURVATURE else np.maximum(k_loc, 0))
    a_mat = proj @ (np.array([fft.irfft(k * fft.rfft(e)) for e in np.eye(n)]).T + np.diag(pre.d)) @ proj
    m = proj @ dense(lambda f: pre.apply(f)[0], n, fft) @ proj  # the NCG's forces are mean-free where clamped
    f = proj @ np.random.default_rng(2).standard_normal(n)
    s_hat, s_nodes = pre.apply(fft.rfft(f))
    np.testing.assert_allclose(s_nodes, fft.irfft(s_hat), atol=1e-12 * np.max(np.abs(s_nodes)))  # nodal s as given
    np.testing.assert_allclose(m, m.T, atol=1e-10 * np.max(np.abs(m)))
    eig = np.linalg.eigvalsh(proj @ (0.5 * (m + m.T)) @ proj)
    assert np.sum(eig > 1e-10 * eig.max()) == n - (1 if clamp else 0)  # positive definite on the space
    zp = proj @ z
    np.testing.assert_allclose(m @ a_mat @ zp, zp, atol=1e-8 * np.max(np.abs(zp)))
    # the preconditioned spectrum is tighter than K⁻¹'s on the stiff patches
    g = proj @ dense(lambda f: pre.g * f, n, fft) @ proj
    def top(mat):
        return np.max(np.real(np.linalg.eigvals(mat @ a_mat)))

    assert top(m) < 0.5 * top(g)


@pytest.mark.parametrize("jit", ["numpy", "numba"])
@pytest.mark.parametrize("thickness", [None, 0.5e-6])
def test_apply_split_is_apply_on_the_state_and_the_force_in_two_parts(thickness, jit, monkeypatch):
    """`TwoLevel.apply_split` from (T_n, û_s, the tail e_u), û = û_s + rfft(Π Z e_u), gives `apply`'s s on the force
    f = T_n − K u (− ⟨T_n⟩ where clamped): on the nodes, and on the modes as x̂' and its tail e_s; f = irfft(ŷ − K û) +
    D w; its nodal sums; Zᵀ K s and the parts, from which `split_products` and `split_energy` give the direct
    products; `fold` makes û_s the state's spectrum, and `move` keeps Zᵀ K u equal to its direct value along steps
    with tails."""
    from gfmd import coarse_kernels, kernels
    if jit == "numba" and kernels.numba is None:
        pytest.skip("numba not installed (a default dependency; without it GFMD_JIT runs the numpy kernels, the "
                    "other case of this test)")
    monkeypatch.setenv("GFMD_JIT", jit)
    sc, h, model, law, z_of = case(nodes=256, thickness=thickness)
    n, clamp = model.nodes, model.half_plane
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)
    kn = 20.0 * float(k[1])
    fft = Fft(n)
    pre = cp.TwoLevel(fft, k, clamp, n, kn)
    assert pre.split[0] is coarse_kernels.split_kernels(jit)[0]
    rng = np.random.default_rng(3)
    pre.rebuild(stiff_patches(n, kn, rng))
    _, starts, p, _ = pre.coarse
    m = starts[-1] + p[-1]

    def spread(e):  # Π Z e on the nodes
        return coarse_kernels.spread(e, starts, p, n, clamp, np.empty(n))

    def z_k(x_hat):  # Zᵀ K x, directly
        return np.add.reduceat(fft.irfft(k * x_hat)[:m], starts)

    def k_dot(a_hat, b_hat):  # a·K b on the nodes, directly
        return float(fft.irfft(a_hat) @ fft.irfft(k * b_hat))

    t, u_hat = rng.standard_normal(n), fft.rfft(rng.standard_normal(n))
    if clamp:
        u_hat[0] = 0.0
    e_u = 0.1 * rng.standard_normal(starts.size)
    u_s = u_hat - fft.rfft(spread(e_u))  # the same state with a tail
    if clamp:
        u_s[0] = 0.0
    pre.tail[:], pre.k_tail[:] = e_u, z_k(fft.rfft(spread(e_u)))
    f_hat = fft.rfft(t) - k * u_hat
    if clamp:
        f_hat[0] = 0.0
    s_hat, s_nodes = pre.apply(f_hat.copy())
    # an older force's x and nodal part, and a direction, each with a tail
    x_old_hat, e_xo = fft.rfft(rng.standard_normal(n)), 0.1 * rng.standard_normal(starts.size)
    d_s, e_d = fft.rfft(rng.standard_normal(n)), 0.1 * rng.standard_normal(starts.size)
    if clamp:
        x_old_hat[0] = d_s[0] = 0.0
    x_o, d_full = x_old_hat + fft.rfft(spread(e_xo)), d_s + fft.rfft(spread(e_d))
    dw_old, d_old = rng.standard_normal(n), fft.irfft(d_full)
    x_hat, s2_nodes, y_hat, dw, z_ks, sums, parts = pre.apply_split(t, u_s, dw_old, d_old)
    e_x, e_s, k_s, l_x = parts
    np.testing.assert_allclose(s2_nodes, s_nodes, atol=1e-12 * np.max(np.abs(s_nodes)))
    s2_hat = x_hat + fft.rfft(spread(e_s))
    np.testing.assert_allclose(s2_hat, s_hat, atol=1e-12 * np.max(np.abs(s_hat)))
    np.testing.assert_array_equal(e_x, -e_u)
    f = fft.irfft(y_hat - k * u_hat) + dw
    f -= np.mean(f) if clamp else 0.0
    np.testing.assert_allclose(f, fft.irfft(f_hat), atol=1e-12 * np.max(np.abs(f)))
    np.testing.assert_allclose(sums, (dw @ s_nodes, dw_old @ s_nodes, dw @ d_old), rtol=1e-11)
    np.testing.assert_allclose(z_ks, z_k(s_hat), atol=1e-11 * np.max(np.abs(z_k(s_hat))))
    np.testing.assert_allclose(k_s, z_k(fft.rfft(spread(e_s))), atol=1e-11 * np.max(np.abs(k_s)))
    np.testing.assert_allclose(l_x, z_k(x_hat), atol=1e-11 * np.max(np.abs(l_x)))
    np.testing.assert_allclose(pre.load, z_k(u_hat), atol=1e-12 * np.max(np.abs(z_k(u_hat))))
    # the products from the parts against the direct ones (the old force f_old = K x_old + dw_old, + a constant
    # where clamped, which the mean-free s does not see)
    k_d, z_kd = z_k(fft.rfft(spread(e_d))), z_k(d_full)
    spectral = kernels.preconditioned_kernels(jit)[3](x_hat, x_old_hat, d_s, k, n)
    np.testing.assert_allclose(spectral, (k_dot(x_hat, x_hat), k_dot(x_old_hat, x_hat), k_dot(d_s, x_hat)),
                               rtol=1e-11)
    rz, f_old_s, f_d_old = cp.split_products(spectral, parts, (e_xo, z_k(x_old_hat)), (e_d, k_d, z_kd), sums)
    np.testing.assert_allclose(rz, float(f @ s_nodes), rtol=1e-10)
    np.testing.assert_allclose(f_old_s, k_dot(x_o, s_hat) + float(dw_old @ s_nodes), rtol=1e-10)
    np.testing.assert_allclose(f_d_old, float(f @ d_old), rtol=1e-10)
    np.testing.assert_allclose(cp.split_energy(k_dot(d_s, d_s), e_d, k_d, z_kd), k_dot(d_full, d_full), rtol=1e-10)
    # a step with a tail keeps Zᵀ K u; a fold leaves the state and no tail
    k_s2 = z_k(fft.rfft(spread(e_s)))
    pre.move(u_s, x_hat, 0.3, z_ks, e_s, k_s2)
    u_hat += 0.3 * s_hat
    np.testing.assert_allclose(pre.load, z_k(u_hat), atol=1e-11 * np.max(np.abs(z_k(u_hat))))
    assert pre.fold(u_s) and not np.any(pre.tail) and not np.any(pre.k_tail) and not pre.fold(u_s)
    np.testing.assert_allclose(u_s, u_hat, atol=1e-12 * np.max(np.abs(u_hat)))
    pre.move(u_s, s_hat, 0.3, None)  # nothing to move it by: made afresh at the next call
    assert pre.load is None


def test_rfft_scratch_is_rfft_and_leaves_the_plan_as_it_was():
    fft = Fft(1 << 14)
    rng = np.random.default_rng(4)
    x, y = fft.empty_nodes(), rng.standard_normal(fft.n)
    x[:] = rng.standard_normal(fft.n)
    expected = fft.rfft(x.copy())
    np.testing.assert_array_equal(fft.rfft_scratch(x), expected)  # the same plan, bit for bit
    np.testing.assert_allclose(fft.rfft(y), np.fft.rfft(y), atol=1e-10 * np.sqrt(fft.n))  # the plan's own input again
    odd = np.empty(fft.n + 1)[1:]  # not aligned as FFTW's input: copied in as rfft does
    odd[:] = y
    np.testing.assert_array_equal(fft.rfft_scratch(odd), fft.rfft(y))


def test_two_level_ramp_reaches_the_default_states(monkeypatch):
    monkeypatch.setattr(cp, "ENGAGE_AFTER", 0)  # the coarse level from the first iteration
    sc, h, model, law, z_of = case(nodes=2048)
    deltas = 3e-9 * np.arange(1, 8)
    ref = ramp(model, law, z_of, deltas, Settings(tolerance=TOL, cohesive_preconditioner="stiffness"))
    two = ramp(model, law, z_of, deltas, Settings(tolerance=TOL, cohesive_preconditioner="two-level"))
    bound = tolerance_bound(model, TOL)
    for a, b in zip(ref, two):
        assert b.method == "ncg" and b.residual < TOL
        assert np.max(np.abs(a.u_z - b.u_z)) < bound
        np.testing.assert_array_equal(a.t_z < 0, b.t_z < 0)
    assert np.mean(ref[-1].t_z < 0) > 0.02  # the last steps are in strong contact ...
    assert sum(r.iterations for r in two[-3:]) < 0.75 * sum(r.iterations for r in ref[-3:])  # ... and cheaper (0.63 here)


def test_two_level_is_built_only_by_steps_that_engage_it(monkeypatch):
    """Its setup (an irfft and cumulative sums over 2N) is paid only by a step that reaches ENGAGE_AFTER
    iterations, once (that the iterates equal the eager build's, the preconditioner being unused before, was
    measured bit for bit on a 2^17 ramp: docs/design/performance.md)."""
    monkeypatch.setattr(cp, "ENGAGE_EARLY", cp.ENGAGE_AFTER)  # no early engagement: a step engages past ENGAGE_AFTER
    built = []
    plain = cp.build
    monkeypatch.setattr(cp, "build", lambda *a, **k: built.append(1) or plain(*a, **k))
    sc, h, model, law, z_of = case(nodes=2048)
    deltas = np.r_[-6e-9, -4e-9, 3e-9 * np.arange(1, 5)]  # two steps out of contact, then into strong adhesion
    runs = ramp(model, law, z_of, deltas, Settings(tolerance=TOL, cohesive_preconditioner="two-level"))
    engaged = [r.iterations > cp.ENGAGE_AFTER for r in runs]
    assert any(engaged) and not all(engaged)  # the case has both kinds of step
    assert len(built) == sum(engaged)  # one build per engaging step, none for the others


def test_two_level_kernel_sums_are_computed_once_per_model(monkeypatch):
    """K's kernel sums (an irfft and two cumulative sums over 2N) are kept on the model's stiffness operator
    (`gfmd.problem.stiffness_operator`): computed by the first engaging step of a ramp only."""
    monkeypatch.setattr(cp, "ENGAGE_AFTER", 0)
    calls = []
    plain = cp.kernel_sums
    monkeypatch.setattr(cp, "kernel_sums", lambda *a: calls.append(1) or plain(*a))
    built = []
    plain_build = cp.build
    monkeypatch.setattr(cp, "build", lambda *a, **k: built.append(1) or plain_build(*a, **k))
    sc, h, model, law, z_of = case(nodes=2048)
    ramp(model, law, z_of, 3e-9 * np.arange(1, 4), Settings(tolerance=TOL, cohesive_preconditioner="two-level"))
    assert len(built) == 3 and len(calls) == 1


def test_auto_is_two_level_on_profiles_with_a_curvature_scale_only():
    assert Settings().cohesive_preconditioner == "auto"
    assert cp.resolve("auto", (256,)) == "two-level" and cp.resolve("auto", None) == "two-level"
    assert cp.resolve("auto", (64, 64)) == "stiffness"  # 2+1-D surface
    assert cp.resolve("auto", (256,), unscaled=True) == "stiffness"  # a law without a curvature scale (a user law)
    assert cp.resolve("stiffness", (256,)) == "stiffness" and cp.resolve("two-level", (256,)) == "two-level"


@pytest.mark.parametrize("value", ["jacobi", "", "Two-Level"])
def test_bad_preconditioner_names_the_key(value):
    sc, h, model, law, z_of = case(nodes=256)
    u0 = np.zeros((model.components, model.nodes // 2 + 1), complex)
    with pytest.raises(ValueError, match="Settings.cohesive_preconditioner"):
        relax(model, law, z_of(1e-9), u0, Settings(cohesive_preconditioner=value), 0.0)


def test_blocks_are_runs_of_consecutive_nodes():
    nodes = np.array([3, 4, 5, 6, 7, 9, 10, 20, 21, 22, 23, 24, 25, 26])
    starts = cp.blocks(nodes, 3)
    np.testing.assert_array_equal(nodes[starts], [3, 6, 9, 20, 23, 26])


def test_cover_adds_one_block_per_gap_and_keeps_the_stiff_blocks():
    stiff = np.array([3, 4, 5, 6, 7, 9, 10, 20, 21, 22, 23, 24, 25, 26])
    nodes, starts = cp.cover(stiff, 30, 3)
    np.testing.assert_array_equal(nodes, np.arange(30))  # every node, in order
    # soft runs 0–2, 8, 11–19, 27–29 one block each; stiff runs cut every 3 nodes as `blocks`
    np.testing.assert_array_equal(starts, [0, 3, 6, 8, 9, 11, 20, 23, 26, 27])
    assert set(stiff[cp.blocks(stiff, 3)]) <= set(starts)


def test_the_dropped_gap_block_is_in_the_coarse_space_on_a_half_plane():
    """On a half-plane the blocks cover the cell and sum to a constant, which Π removes: the last block is dropped
    (E would be singular), and its Π Z column lies in the span of the others: the preconditioner is exact on it too."""
    sc, h, model, law, z_of = case(nodes=256)
    n = model.nodes
    assert model.half_plane
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)
    kn = 20.0 * float(k[1])
    fft = Fft(n)
    pre = cp.TwoLevel(fft, k, True, n, kn)
    k_loc = stiff_patches(n, kn, np.random.default_rng(1))
    assert pre.rebuild(k_loc)
    nodes, starts, p, _ = pre.coarse
    last = np.zeros(n)
    last[nodes.size:] = 1.0  # the dropped block: the nodes after the kept ones
    assert 0 < nodes.size < n and np.all(k_loc[nodes.size:] < cp.STIFF_FRACTION * kn)  # a gap
    proj = np.eye(n) - 1.0 / n
    a_mat = proj @ (np.array([fft.irfft(k * fft.rfft(e)) for e in np.eye(n)]).T + np.diag(pre.d)) @ proj
    m = proj @ dense(lambda f: pre.apply(f)[0], n, fft) @ proj
    zp = proj @ last
    np.testing.assert_allclose(m @ a_mat @ zp, zp, atol=1e-8 * np.max(np.abs(zp)))


def test_signed_curvature_falls_back_to_its_positive_part_where_e_is_not_definite(monkeypatch):
    """A softening tail strong enough to make Zᵀ(K + D)Z indefinite: D = max(k_loc, 0) instead, still SPD; with
    SIGNED_CURVATURE off, max(k_loc, 0) always."""
    sc, h, model, law, z_of = case(nodes=256)
    n = model.nodes
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)
    kn = 20.0 * float(k[1])
    k_loc = stiff_patches(n, kn, np.random.default_rng(1))
    k_loc[105:145] = -kn  # a gap whose constant mode (K's smallest) the tail overwhelms
    pre = cp.TwoLevel(Fft(n), k, True, n, kn)
    stiff = np.flatnonzero(k_loc >= cp.STIFF_FRACTION * kn)
    assert not pre._build(k_loc.copy(), stiff)  # the signed coarse matrix is not definite
    pre = cp.TwoLevel(Fft(n), k, True, n, kn)
    assert pre.rebuild(k_loc) and pre.coarse is not None
    np.testing.assert_array_equal(pre.d, np.maximum(k_loc, 0))
    monkeypatch.setattr(cp, "SIGNED_CURVATURE", False)
    pre = cp.TwoLevel(Fft(n), k, True, n, kn)
    assert pre.rebuild(stiff_patches(n, kn, np.random.default_rng(1)))
    assert np.all(pre.d >= 0)


def test_signed_curvature_tightens_the_preconditioned_spectrum(monkeypatch):
    """A softening tail over the gaps (k_loc < 0 where the fixture has 0; A stays definite): M⁻¹A's smallest
    eigenvalue is larger, its condition number smaller, with D = k_loc than with max(k_loc, 0) (equal if apply
    ignored the sign)."""
    sc, h, model, law, z_of = case(nodes=256)
    n = model.nodes
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)
    kn = 20.0 * float(k[1])
    fft = Fft(n)
    k_loc = stiff_patches(n, kn, np.random.default_rng(1))
    k_loc[k_loc == 0] = -0.05 * kn
    proj = np.eye(n) - 1.0 / n
    a_mat = proj @ (np.array([fft.irfft(k * fft.rfft(e)) for e in np.eye(n)]).T + np.diag(k_loc)) @ proj
    spectra = {}
    for signed in (True, False):
        monkeypatch.setattr(cp, "SIGNED_CURVATURE", signed)
        pre = cp.TwoLevel(fft, k, True, n, kn)
        assert pre.rebuild(k_loc)
        m = proj @ dense(lambda f: pre.apply(f)[0], n, fft) @ proj
        eig = np.real(np.linalg.eigvals(m @ a_mat))
        eig = eig[np.abs(eig) > 1e-9 * np.max(np.abs(eig))]  # the mean mode (Π) is outside the space
        assert eig.min() > 0
        spectra[signed] = eig.min(), eig.max() / eig.min()
    assert spectra[True][0] > spectra[False][0] and spectra[True][1] < spectra[False][1]


def test_slow_step_predicts_from_the_recent_rate():
    assert cp.slow_step(1.0, 1.0, 5, 1e-6, 30)  # no progress
    assert cp.slow_step(1.0, 2.0, 5, 1e-6, 30)
    assert not cp.slow_step(1.0, 1e-7, 5, 1e-6, 30)  # already there
    assert not cp.slow_step(1.0, 1e-3, 5, 1e-6, 30)  # 5 more at this rate
    assert cp.slow_step(1.0, 0.5, 5, 1e-6, 30)  # ≈ 100 more
    assert cp.slow_step(1.0, 0.1, 5, 1e-6, 20) and not cp.slow_step(1.0, 0.1, 5, 1e-6, 30)  # 25 more


def test_slow_steps_engage_early_and_reach_the_same_states(monkeypatch):
    sc, h, model, law, z_of = case(nodes=2048)
    deltas = 3e-9 * np.arange(1, 8)
    settings = Settings(tolerance=TOL, cohesive_preconditioner="two-level")
    monkeypatch.setattr(cp, "ENGAGE_EARLY", cp.ENGAGE_AFTER)
    late = ramp(model, law, z_of, deltas, settings)
    monkeypatch.undo()
    assert cp.ENGAGE_EARLY < cp.ENGAGE_AFTER
    early = ramp(model, law, z_of, deltas, settings)
    bound = tolerance_bound(model, TOL)
    for a, b in zip(late, early):
        assert b.method == "ncg" and b.residual < TOL
        assert np.max(np.abs(a.u_z - b.u_z)) < bound
        np.testing.assert_array_equal(a.t_z < 0, b.t_z < 0)
    slow = [i for i, r in enumerate(late) if r.iterations > cp.ENGAGE_AFTER]
    assert slow  # the case has slow steps, and they cost fewer iterations engaged early
    assert sum(early[i].iterations for i in slow) < sum(late[i].iterations for i in slow)
