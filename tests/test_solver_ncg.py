"""The cohesive-law NCG solver: nonlinear preconditioned CG, FIRE as fallback.

* NCG and FIRE reach the same equilibrium on a cohesive ramp (half-plane and layer; δn = 0.25
  and 1 nm), within a bound derived from the stopping tolerance: two states with max nodal
  residual < tol·p_ref differ by at most 2·tol·p_ref·√N / K(q_1) in the 2-norm of the nodal
  displacements (K(q_1): the softest elastic mode; the softening of the law is far weaker
  than K(q_1) on these steps), checked in the max norm (≤ the 2-norm);
* both FFT backends give the same NCG states (and NCG runs through the chosen backend);
* the selector ran what it says: Relaxed.method is "ncg" by default, "fire" with
  Settings.cohesive = "fire", FIRE for a law without the normal-only potential (coupled),
  and an unknown name is refused;
* the fallback: a jump-in step (flat surface, first contact) whose NCG budget is cut to a few
  iterations ends with FIRE, "ncg→fire" in Relaxed.method and the message, at the same state;
  an unconverged fallback is reported, never accepted;
* the converged state is a fixed point (0 iterations from it), and NCG needs fewer FFT pairs
  than FIRE (counts, not times).
"""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import indenter_surface
from gfmd_contact.core.model import build_model
from gfmd_contact.core.scene import default_scene
from gfmd import fft as gfft, kernels
from gfmd.algorithms import ncg as gs
from gfmd_contact.core.law_equations import EXP_UNDERFLOW, attraction_cut
from gfmd.solver import InterfaceLaw, Settings, relax

TOL = 1e-10


def case(nodes=2048, length_normal=0.25e-9, phi=0.15, thickness=None, **extra):
    length = 1.28e-6
    kw = {"surface.nodes": nodes, "surface.length": length, "surface.rolloff_wavelength": length / 8,
          "surface.rollon_wavelength": 4 * length / nodes, "interface.law": "cohesive",
          "interface.phi_n_star": phi, "interface.length_normal": length_normal, **extra}
    if thickness is not None:
        kw["material.thickness"] = thickness
    sc = default_scene().replace(**kw)
    h = surfaces.profile(sc.surface, 0)
    model = build_model(sc, h)
    law = InterfaceLaw(model)
    d0 = sc.loading.initial_separation
    return sc, h, model, law, (lambda d: indenter_surface(h, d0, d0 + d))


def ramp(model, law, z_of, deltas, settings):
    u = prev = np.zeros((model.components, model.nodes // 2 + 1), complex)
    out = []
    for k, d in enumerate(deltas):
        guess = 2 * u - prev if k >= 2 else u
        r = relax(model, law, z_of(d), guess, settings, 0.0)
        assert r.converged, r.message
        out.append(r)
        prev, u = u, r.u_hat
    return out


def tolerance_bound(model, tol):
    """Largest nodal distance (m) of two states whose max residuals are < tol·p_ref (module docstring)."""
    k = np.real(model.k_zz)
    k1 = float(np.min(k[1:]))
    return 2 * tol * model.reference_traction * np.sqrt(model.nodes) / k1


@pytest.mark.parametrize("length_normal, thickness", [(0.25e-9, None), (1e-9, None), (0.25e-9, 0.5e-6)])
def test_ncg_equals_fire(length_normal, thickness):
    sc, h, model, law, z_of = case(length_normal=length_normal, thickness=thickness)
    deltas = 1.5e-9 * np.arange(1, 6)
    ncg = ramp(model, law, z_of, deltas, Settings(tolerance=TOL))
    fire = ramp(model, law, z_of, deltas, Settings(tolerance=TOL, cohesive="fire"))
    bound = tolerance_bound(model, TOL)
    for a, b in zip(ncg, fire):
        assert a.method == "ncg" and b.method == "fire"
        assert a.residual < TOL and b.residual < TOL
        assert np.max(np.abs(a.u_z - b.u_z)) < bound, (np.max(np.abs(a.u_z - b.u_z)), bound)
        np.testing.assert_array_equal(a.t_z < 0, b.t_z < 0)  # same contact set
    # the bound is tight enough to mean something: far below the law's length and the steps
    assert bound < 1e-3 * length_normal


@pytest.mark.skipif(gfft._ducc_fft is None or gfft._pyfftw is None, reason="ducc0 or pyfftw not installed")
def test_ncg_fft_backends_agree(monkeypatch):
    sc, h, model, law, z_of = case()
    out = {}
    for backend in ("scipy", "ducc0", "fftw"):
        monkeypatch.setenv("GFMD_FFT", backend)
        assert gfft.fft_backend() == backend
        out[backend] = ramp(model, law, z_of, 1.5e-9 * np.arange(1, 4), Settings(tolerance=TOL))
    for fast in ("ducc0", "fftw"):
        for a, b in zip(out["scipy"], out[fast]):
            assert a.method == b.method == "ncg"
            assert np.max(np.abs(a.u_z - b.u_z)) < tolerance_bound(model, TOL)


def test_selector_runs_what_it_says():
    sc, h, model, law, z_of = case(nodes=512)
    z = z_of(3e-9)
    u0 = np.zeros((1, model.nodes // 2 + 1), complex)
    assert relax(model, law, z, u0, Settings(tolerance=1e-8), 0.0).method == "ncg"
    assert relax(model, law, z, u0, Settings(tolerance=1e-8, cohesive="fire"), 0.0).method == "fire"
    assert relax(model, law, z, u0, Settings(tolerance=1e-8, method="verlet"), 0.0).method == "verlet"
    with pytest.raises(ValueError, match="cohesive"):
        relax(model, law, z, u0, Settings(cohesive="newton"), 0.0)
    # a law without the normal-only potential (coupled, u_x solved) never takes the NCG path
    sc2, h2, model2, law2, z_of2 = case(nodes=256, **{"interface.tangential_ratio": 0.5,
                                                      "material.poisson_ratio": 0.3})
    if model2.tangential:
        r = relax(model2, law2, z_of2(2e-9), np.zeros((2, 129), complex), Settings(tolerance=1e-6), 0.0)
        assert "ncg" not in r.method and r.method.split("→")[0] in ("newton", "fire", "verlet"), r.method


def test_jump_in_fallback_to_fire(monkeypatch):
    """A jump-in step (flat start, first contact) with the NCG budget cut: FIRE finishes it."""
    sc, h, model, law, z_of = case()
    z = z_of(1.5e-9)
    u0 = np.zeros((1, model.nodes // 2 + 1), complex)
    ref = relax(model, law, z, u0, Settings(tolerance=TOL), 0.0)
    assert ref.converged and ref.method == "ncg"
    assert np.mean(ref.t_z < 0) > 0  # the step does jump into contact
    monkeypatch.setattr(gs, "NCG_BUDGET", 3)
    r = relax(model, law, z, u0, Settings(tolerance=TOL), 0.0)
    assert r.converged and r.method == "ncg→fire"
    assert "NCG stopped" in r.message and "FIRE" in r.message
    assert r.iterations > 3
    assert np.max(np.abs(r.u_z - ref.u_z)) < tolerance_bound(model, TOL)
    bad = relax(model, law, z, u0, Settings(tolerance=TOL, max_iterations=8), 0.0)
    assert not bad.converged and bad.method == "ncg→fire" and "not converged" in bad.message


def test_ncg_fixed_point_and_cost():
    sc, h, model, law, z_of = case(nodes=4096)
    deltas = 1.5e-9 * np.arange(1, 5)
    ncg = ramp(model, law, z_of, deltas, Settings(tolerance=TOL))
    fire = ramp(model, law, z_of, deltas, Settings(tolerance=TOL, cohesive="fire"))
    again = relax(model, law, z_of(deltas[-1]), ncg[-1].u_hat, Settings(tolerance=TOL), 0.0)
    assert again.converged and again.iterations == 0
    assert np.max(np.abs(again.u_z - ncg[-1].u_z)) == 0.0
    assert np.median([r.fft_pairs for r in ncg]) < np.median([r.fft_pairs for r in fire]) / 2


def test_line_search_through_deep_compression():
    """Strong adhesion (φn* = 0.5, δn = 0.1 nm) with 2 nm steps: the extrapolated guess of the fourth
    step puts nodes tens of δn into the exponential repulsive branch, where Newton on dE/dα creeps by
    about δn per trial; the line search bisects when two trials do not halve its bracket, so NCG
    finishes the step itself (it used to hand it to FIRE after 60 trials)."""
    sc, h, model, law, z_of = case(length_normal=0.1e-9, phi=0.5)
    out = ramp(model, law, z_of, 2e-9 * np.arange(1, 5), Settings(tolerance=TOL))
    assert [r.method for r in out] == ["ncg"] * 4, [(r.method, r.message) for r in out]


@pytest.mark.parametrize("far_fraction, margin", [
    (0.0, 8.0),  # every node near: the plain NCG
    (1e9, 8.0),  # a cut at Δn = 1 δn: the far nodes' attraction fails the final check, every node comes back
    (1e-3, 0.01),  # a near set rebuilt from the state almost every step
])
def test_near_set_gives_the_state_of_every_node(monkeypatch, far_fraction, margin):
    """The nodal work on the near set only (`NCG_FAR_FRACTION`, `NCG_NEAR_MARGIN`) changes no equilibrium:
    the default run equals runs with every node, with a cut whose far attraction counts (the converged
    check with every node must catch it), and with a near set that goes stale at once."""
    sc, h, model, law, z_of = case(nodes=4096)
    deltas = 1.5e-9 * np.arange(1, 6)
    default = ramp(model, law, z_of, deltas, Settings(tolerance=TOL))
    # the default did take the near-set path: few nodes lie within the cut (+ margin) of the indenter
    cut = attraction_cut(gs.NCG_FAR_FRACTION * TOL * model.reference_traction * 0.25e-9
                         / float(law.law.work_normal))
    assert np.isfinite(cut)
    near = np.mean(default[-1].gap < (cut + gs.NCG_NEAR_MARGIN) * 0.25e-9)
    assert 0 < near < gs.NCG_NEAR_FULL
    monkeypatch.setattr(gs, "NCG_FAR_FRACTION", far_fraction)
    monkeypatch.setattr(gs, "NCG_NEAR_MARGIN", margin)
    other = ramp(model, law, z_of, deltas, Settings(tolerance=TOL))
    for a, b in zip(default, other):
        assert a.method == b.method == "ncg"
        assert a.residual < TOL and b.residual < TOL
        assert np.max(np.abs(a.u_z - b.u_z)) < tolerance_bound(model, TOL)


@given(st.floats(1e-300, 0.999 * np.exp(-1.0)))
def test_attraction_cut_solves_the_tail_equation(x):
    """s_c e^{−s_c} = x on the falling branch s_c ≥ 1 (Eq. 3's attraction in units of φn/δn), capped where
    e^{−s} underflows."""
    s = attraction_cut(x)
    assert 1.0 <= s <= EXP_UNDERFLOW
    assert s * np.exp(-s) == pytest.approx(x, rel=1e-9)


def test_attraction_cut_limits():
    assert attraction_cut(0.0) == np.inf  # tolerance 0: every node counts
    assert attraction_cut(1.0) == 1.0  # no attraction reaches x: the cut at the law's peak
    assert attraction_cut(5e-324) <= EXP_UNDERFLOW  # the smallest double: e^{−s} underflows just beyond


JIT_BACKENDS = ["numpy"] + (["numba"] if kernels.numba is not None else [])


@pytest.mark.parametrize("backend", JIT_BACKENDS)
@settings(deadline=None)  # the first example may compile the fused kernels (over 200 ms on a loaded machine)
@given(n=st.integers(2, 64), seed=st.integers(0, 2**32 - 1), beta=st.floats(0, 2), alpha=st.floats(-1, 1))
def test_ncg_kernels_are_the_nodal_algebra(backend, n, seed, beta, alpha):
    """products, direction and advance (gfmd.kernels) against the same algebra on the nodes (numpy.fft),
    for even and odd N, clamped q = 0 or not: s = K⁻¹ f, d ← s + β d, u ← u + α d, f ← T − K u."""
    rng = np.random.default_rng(seed)
    t, f_old, d, u = rng.standard_normal((4, n))
    k = rng.random(n // 2 + 1) + 0.1
    k[0] = 0.0 if seed % 2 else k[0]  # a half-plane's clamped mode, or a layer's stiff one
    g = np.divide(1.0, k, out=np.zeros_like(k), where=k > 0)
    products, direction, advance = kernels.ncg_kernels(backend)
    f = np.fft.irfft(np.fft.rfft(t) - k * np.fft.rfft(u), n)
    s = np.fft.irfft(g * np.fft.rfft(f), n)
    got = products(np.fft.rfft(f), np.fft.rfft(f_old), np.fft.rfft(d), g, n)
    np.testing.assert_allclose(got, [f @ s, f_old @ s, f @ d], rtol=1e-10, atol=1e-10 * n)
    d_hat = np.fft.rfft(d)
    direction(np.fft.rfft(f), g, beta, d_hat)
    np.testing.assert_allclose(np.fft.irfft(d_hat, n), s + beta * d, atol=1e-12 * n)
    u_hat, f_hat = np.fft.rfft(u), np.fft.rfft(t)
    advance(u_hat, np.fft.rfft(d), alpha, k, f_hat)
    u_new = u + alpha * d
    np.testing.assert_allclose(np.fft.irfft(u_hat, n), u_new, atol=1e-12 * n)
    np.testing.assert_allclose(np.fft.irfft(f_hat, n), np.fft.irfft(np.fft.rfft(t) - k * np.fft.rfft(u_new), n),
                               atol=1e-12 * n)


@pytest.mark.parametrize("backend", JIT_BACKENDS)
@settings(deadline=None)  # the first example compiles the numba kernels
@given(n=st.integers(2, 64), seed=st.integers(0, 2**32 - 1), beta=st.sampled_from([0.0, 0.3, 1.7]))
def test_preconditioned_kernels_are_the_nodal_algebra(backend, n, seed, beta):
    """products, direction_energy, combine and stiffness_products of the two-level preconditioner's NCG
    (gfmd.kernels.preconditioned_kernels) against the algebra on the nodes, for even and odd N and any s (not K⁻¹ f):
    f·s, f_old·s, f·d; d ← s + β d and d·Kd = Σ_j d_j (K d)_j; s + β d on the nodes; s·Ks, f_old·Ks, d·Ks."""
    rng = np.random.default_rng(seed)
    f, f_old, d, s = rng.standard_normal((4, n))
    k = rng.random(n // 2 + 1) + 0.1
    k[0] = 0.0 if seed % 2 else k[0]
    products, direction_energy, combine, stiffness_products = kernels.preconditioned_kernels(backend)
    rf = np.fft.rfft
    got = products(rf(f), rf(f_old), rf(d), rf(s), n)
    np.testing.assert_allclose(got, [f @ s, f_old @ s, f @ d], rtol=1e-10, atol=1e-10 * n)
    ks = np.fft.irfft(k * rf(s), n)
    np.testing.assert_allclose(stiffness_products(rf(s), rf(f_old), rf(d), k, n), [s @ ks, f_old @ ks, d @ ks],
                               rtol=1e-10, atol=1e-10 * n)
    d_hat = rf(d)
    energy = direction_energy(rf(s), beta, d_hat, k, n)
    d_new = s + beta * d
    np.testing.assert_allclose(np.fft.irfft(d_hat, n), d_new, atol=1e-12 * n)
    np.testing.assert_allclose(energy, d_new @ np.fft.irfft(k * rf(d_new), n), rtol=1e-10, atol=1e-10 * n)
    np.testing.assert_allclose(combine(s.copy(), beta, d.copy()), d_new, atol=1e-14 * n)


@pytest.mark.parametrize("backend", JIT_BACKENDS)
@settings(deadline=None)  # the first example may compile the fused kernels
@given(n=st.integers(1, 300), seed=st.integers(0, 2**32 - 1), alpha=st.floats(-2, 2),
       dn=st.sampled_from([0.25e-9, 1e-9]))
def test_eq3_nodes_are_the_law(backend, n, seed, alpha, dn):
    """gfmd.ncg_nodes.Eq3Nodes (numpy and fused) against seed Eq. 3 written out here: at the trial gaps
    Δ = Δn − α d (s = Δ/δn capped at −MAX_COMPRESSION), Σ T_n d and Σ k_loc d² with T_n = (φn/δn) s e^{−s},
    k_loc = (φn/δn²)(1 − s) e^{−s}; the gaps span deep compression (the cap) to the far tail."""
    from gfmd_contact.core.laws import MAX_COMPRESSION
    from gfmd.ncg_nodes import Eq3Nodes

    rng = np.random.default_rng(seed)
    phi = 0.01
    gap = dn * rng.uniform(-1.2 * MAX_COMPRESSION, 60.0, n) * (rng.random(n) < 0.05) + dn * rng.uniform(-3, 40, n)
    d = dn * rng.standard_normal(n)
    nodes = Eq3Nodes(dn, phi / dn, phi / dn**2, backend)
    gap_a, s, e, work, curv = nodes.trial(gap, d, alpha)
    trial_gap = gap - alpha * d
    s_ref = np.maximum(trial_gap / dn, -MAX_COMPRESSION)
    t_ref = phi / dn * s_ref * np.exp(-s_ref)
    k_ref = phi / dn**2 * (1.0 - s_ref) * np.exp(-s_ref)
    np.testing.assert_allclose(gap_a, trial_gap, rtol=1e-14, atol=1e-14 * dn * np.abs(alpha) * 40)
    np.testing.assert_allclose(s, s_ref, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(e, np.exp(-s_ref), rtol=1e-12)
    scale_t = float(np.sum(np.abs(t_ref * d)))  # the sums' round-off grows with their terms' magnitudes
    scale_k = float(np.sum(np.abs(k_ref) * d**2))
    assert abs(work - t_ref @ d) <= 1e-12 * scale_t
    if backend == "numba":
        assert curv is not None
    else:
        assert curv is None  # numpy leaves it to curvature_sum
        curv = nodes.curvature_sum(s, e, d)
    assert abs(curv - k_ref @ d**2) <= 1e-12 * scale_k
    assert abs(nodes.curvature_sum(s, e, d) - k_ref @ d**2) <= 1e-12 * scale_k
    np.testing.assert_allclose(nodes.traction_new(s, e), t_ref, rtol=1e-12, atol=1e-12 * phi / dn)
    work0, curv0 = nodes.direction_sums(s, e, d)  # the line search's start: both sums at the state along d
    assert abs(work0 - t_ref @ d) <= 1e-12 * scale_t and abs(curv0 - k_ref @ d**2) <= 1e-12 * scale_k


def test_jit_backend_choice(monkeypatch):
    assert kernels.jit_backend("numpy") == "numpy"
    with pytest.raises(ValueError, match="GFMD_JIT"):
        kernels.jit_backend("cython")
    monkeypatch.setattr(kernels, "numba", None)
    assert kernels.jit_backend("auto") == "numpy"
    with pytest.raises(ImportError, match="numba"):
        kernels.jit_backend("numba")


@pytest.mark.skipif(kernels.numba is None, reason="numba not installed (the `fast` extra)")
def test_ncg_jit_backends_agree(monkeypatch):
    """The whole NCG ramp with the numpy and the fused kernels: the same states and iterations."""
    sc, h, model, law, z_of = case(nodes=4096)
    deltas = 1.5e-9 * np.arange(1, 5)
    out = {}
    for backend in ("numpy", "numba"):
        monkeypatch.setenv("GFMD_JIT", backend)
        out[backend] = ramp(model, law, z_of, deltas, Settings(tolerance=TOL))
    for a, b in zip(out["numpy"], out["numba"]):
        assert a.method == b.method == "ncg"
        assert abs(a.iterations - b.iterations) <= 2
        assert np.max(np.abs(a.u_z - b.u_z)) < tolerance_bound(model, TOL)


def test_results_name_the_backends(monkeypatch):
    """A GFMD cell's reasons (stored with every Result) say which FFT and NCG kernels ran."""
    from gfmd.loading import prepare
    sc, h, *_ = case(nodes=256)
    monkeypatch.setenv("GFMD_FFT", "scipy")
    monkeypatch.setenv("GFMD_JIT", "numpy")
    assert "backends: FFT scipy (GFMD_FFT), cohesive NCG spectral algebra numpy (GFMD_JIT)" in prepare(sc, h).reasons
