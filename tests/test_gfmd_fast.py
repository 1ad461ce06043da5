"""The fast hard-wall solvers (projected preconditioned CG, primal and dual) and the FFT backends.

* CG and FIRE reach the same hard-wall equilibrium (half-plane and layer), and the CG state
  passes an independent KKT check (elastic force recomputed with numpy.fft: no penetration,
  zero force off the wall, no wall node pulling, within the tolerance);
* the CG releases wall nodes that pull away: started with every node on the wall it still
  ends at the KKT point (a CG that never released would stop with pulling nodes, or not at all);
* the CG's fixed point is the KKT point: started there it stops at once, unchanged;
* scipy.fft and ducc0 (when installed) give the same equilibria; the backend choice is checked;
* cost guard by counts (not times): the CG needs at most a third of FIRE's FFT pairs on a
  warm-started self-affine step;
* the dual CG (contact pressures, `gfmd.algorithms.hard_wall_dual_cg`) reaches the primal's equilibrium
  (half-plane and layer, same contact set), passes the same independent KKT check, hands over to
  the primal past `dual_contact_limit`, and needs fewer FFT pairs than the primal on the same ramp;
  its preconditioner, the band of K_AA, is symmetric positive definite for any contact set.
"""

import numpy as np
import pytest
from hypothesis import given, settings as hyp_settings, strategies as st

from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import indenter_surface
from gfmd_contact.core.model import build_model
from gfmd_contact.core.scene import default_scene
from gfmd import fft as gfft
from gfmd.algorithms import hard_wall_dual_cg
from gfmd.links import Link
from gfmd.solver import InterfaceLaw, Settings, relax

TOL = 1e-10
PRIMAL = (Link("hard_wall_primal_cg"),)  # the primal CG alone (`relax`'s chain): the dual CGs' reference


def case(nodes=2048, thickness=None):
    length = 1.28e-6
    kw = {"surface.nodes": nodes, "surface.length": length, "surface.rolloff_wavelength": length / 8,
          "surface.rollon_wavelength": 4 * length / nodes, "interface.law": "hard-wall"}
    if thickness is not None:
        kw["material.thickness"] = thickness
    sc = default_scene().replace(**kw)
    h = surfaces.profile(sc.surface, 0)
    model = build_model(sc, h)
    law = InterfaceLaw(model)
    wall_tol = 1e-12 * float(np.ptp(h))
    return sc, h, model, law, wall_tol


def kkt_violation(model, z, u_z):
    """max over the KKT conditions, in p_ref, recomputed with numpy.fft (independent of the solver)."""
    ku = np.fft.irfft(np.real(model.k_zz) * np.fft.rfft(u_z), n=u_z.size)
    gap = z - u_z
    on = gap <= 1e-12 * np.ptp(z)
    p_far = float(np.mean(ku[~on])) if model.half_plane else 0.0
    force = p_far - ku
    p_ref = model.reference_traction
    penetration = max(0.0, -float(np.min(gap)))
    return max(float(np.max(np.abs(force[~on]))) / p_ref,  # free nodes: no net force
               max(0.0, -float(np.min(force[on], initial=0.0))) / p_ref,  # wall nodes: pushed, not pulled
               penetration * float(np.max(np.real(model.k_zz))) / p_ref)


def ramp(model, law, z_of, deltas, settings, wall_tol, chain=None):
    u = prev = np.zeros((1, model.nodes // 2 + 1), complex)
    out = []
    for k, d in enumerate(deltas):
        guess = 2 * u - prev if k >= 2 else u
        r = relax(model, law, z_of(d), guess, settings, wall_tol, chain=chain)
        assert r.converged, r.message
        out.append(r)
        prev, u = u, r.u_hat
    return out


def two_ramps(first, second, thickness=None, nodes=2048, steps=5, second_chain=None):
    """The same ramp of `steps` steps of 1.5 nm under two Settings (the second on `relax`'s chain `second_chain`
    where given): (model, z_of, deltas, h, runs, runs)."""
    sc, h, model, law, wall_tol = case(nodes=nodes, thickness=thickness)
    d0 = sc.loading.initial_separation

    def z_of(d):
        return indenter_surface(h, d0, d0 + d)

    deltas = 1.5e-9 * np.arange(1, steps + 1)
    return (model, z_of, deltas, h, ramp(model, law, z_of, deltas, first, wall_tol),
            ramp(model, law, z_of, deltas, second, wall_tol, second_chain))


def assert_same_kkt_equilibria(model, z_of, deltas, h, runs, reference):
    """Every step of `runs` converged, passes the independent KKT check and equals `reference`'s."""
    for d, a, b in zip(deltas, runs, reference):
        assert a.residual < TOL
        assert kkt_violation(model, z_of(d), a.u_z) < TOL * (1 + 1e-3)
        assert np.max(np.abs(a.u_z - b.u_z)) < 1e-9 * float(np.std(h))
        np.testing.assert_array_equal(a.t_z < 0, b.t_z < 0)  # same contact set
        np.testing.assert_allclose(np.mean(a.t_z), np.mean(b.t_z), rtol=1e-8)
        assert a.fft_pairs > 0


@pytest.mark.parametrize("thickness", [None, 0.5e-6])
def test_cg_equals_fire_and_is_kkt(thickness):
    model, z_of, deltas, h, cg, fire = two_ramps(Settings(tolerance=TOL), Settings(tolerance=TOL, hard_wall="fire"),
                                                 thickness)
    assert_same_kkt_equilibria(model, z_of, deltas, h, cg, fire)


#: (dual_contact_limit, dual_coarse_block, relax's chain, label): the primal CG alone; the band dual CG and the
#: two-level dual CG however large the set
CGS = [(1.0, 16, PRIMAL, "cg"), (1.0, 0, None, "cg-dual"), (1.0, 16, None, "cg-dual2")]


@pytest.mark.parametrize("dual_limit, block, chain, label", CGS)
def test_cg_releases_pulling_wall_nodes(dual_limit, block, chain, label):
    """Start with every node on the wall (u = z − ⟨z⟩): almost all of them pull away."""
    sc, h, model, law, wall_tol = case()
    d0 = sc.loading.initial_separation
    z = indenter_surface(h, d0, d0 + 5e-9)
    guess = np.fft.rfft(z - np.mean(z))[None, :]
    r = relax(model, law, z, guess, Settings(tolerance=TOL, dual_contact_limit=dual_limit, dual_coarse_block=block),
              wall_tol, chain=chain)
    assert r.method == label
    ref = relax(model, law, z, np.zeros_like(guess), Settings(tolerance=TOL, hard_wall="fire"), wall_tol)
    assert r.converged, r.message
    assert np.mean(r.t_z < 0) < 0.2  # most nodes left the wall
    assert kkt_violation(model, z, r.u_z) < TOL * (1 + 1e-3)
    assert np.max(np.abs(r.u_z - ref.u_z)) < 1e-9 * float(np.std(h))


@pytest.mark.parametrize("dual_limit, block, chain, label", CGS)
def test_cg_fixed_point_is_the_kkt_point(dual_limit, block, chain, label):
    sc, h, model, law, wall_tol = case()
    d0 = sc.loading.initial_separation
    z = indenter_surface(h, d0, d0 + 8e-9)
    settings = Settings(tolerance=TOL, dual_contact_limit=dual_limit, dual_coarse_block=block)
    first = relax(model, law, z, np.zeros((1, model.nodes // 2 + 1), complex), settings, wall_tol, chain=chain)
    again = relax(model, law, z, first.u_hat, settings, wall_tol, chain=chain)
    assert again.converged and again.iterations == 0
    assert np.max(np.abs(again.u_z - first.u_z)) < 1e-15 * float(np.std(h))


@pytest.mark.parametrize("dual_limit, block, chain, label", CGS)
def test_cg_unconverged_is_reported(dual_limit, block, chain, label):
    sc, h, model, law, wall_tol = case()
    d0 = sc.loading.initial_separation
    r = relax(model, law, indenter_surface(h, d0, d0 + 8e-9), np.zeros((1, model.nodes // 2 + 1), complex),
              Settings(tolerance=TOL, max_iterations=2, dual_contact_limit=dual_limit, dual_coarse_block=block), wall_tol,
              chain=chain)
    assert not r.converged and "not converged" in r.message and r.iterations == 2


def test_cg_needs_far_fewer_fft_pairs_than_fire():
    *_, cg, fire = two_ramps(Settings(tolerance=TOL), Settings(tolerance=TOL, hard_wall="fire"), nodes=8192, steps=4)
    cg_pairs = np.median([r.fft_pairs for r in cg])
    fire_pairs = np.median([2 * r.iterations for r in fire])
    assert cg_pairs < fire_pairs / 3, (cg_pairs, fire_pairs)


@pytest.mark.parametrize("thickness", [None, 0.5e-6])
@pytest.mark.parametrize("block, label", [(0, "cg-dual"), (16, "cg-dual2")])
def test_dual_equals_primal_and_is_kkt(thickness, block, label):
    model, z_of, deltas, h, dual, primal = two_ramps(Settings(tolerance=TOL, dual_contact_limit=1.0,
                                                              dual_coarse_block=block),
                                                     Settings(tolerance=TOL), thickness, second_chain=PRIMAL)
    assert {r.method for r in dual} == {label} and {r.method for r in primal} == {"cg"}
    assert_same_kkt_equilibria(model, z_of, deltas, h, dual, primal)


@pytest.mark.parametrize("block, label", [(0, "cg-dual"), (16, "cg-dual2")])
def test_dual_hands_over_to_the_primal_past_its_contact_limit(block, label):
    """Limit below the ramp's contact fractions: the dual hands over (from its state once A passes
    DUAL_TRANSIENT_FACTOR × the limit, or at once from a guess past the limit) and the primal ends at
    the KKT point."""
    sc, h, model, law, wall_tol = case()
    d0 = sc.loading.initial_separation

    def z_of(d):
        return indenter_surface(h, d0, d0 + d)

    deltas = 1.5e-9 * np.arange(1, 6)
    out = ramp(model, law, z_of, deltas, Settings(tolerance=TOL, dual_contact_limit=2e-3, dual_coarse_block=block), wall_tol)
    areas = [float(np.mean(r.t_z < 0)) for r in out]
    assert areas[-1] > 2e-3
    assert {r.method for r in out} >= {label, f"{label}→cg", "cg"}  # dual; handed over in a step; primal at once
    for d, r, a in zip(deltas, out, areas):
        # the dual never ends on a set past its transient limit (a guess that already passes is returned as is)
        assert r.method != label or a <= hard_wall_dual_cg.DUAL_TRANSIENT_FACTOR * 2e-3 or r.iterations == 0
        assert kkt_violation(model, z_of(d), r.u_z) < TOL * (1 + 1e-3)


@pytest.mark.parametrize("limit", [-0.1, 0.0, 1.5, float("nan")])
def test_dual_contact_limit_outside_0_1_is_refused(limit):
    sc, h, model, law, wall_tol = case()
    with pytest.raises(ValueError, match="Settings.dual_contact_limit"):
        relax(model, law, indenter_surface(h, sc.loading.initial_separation, sc.loading.initial_separation + 5e-9),
              np.zeros((1, model.nodes // 2 + 1), complex), Settings(dual_contact_limit=limit), wall_tol)


def test_dual_needs_fewer_fft_pairs_than_the_primal():
    *_, dual, primal = two_ramps(Settings(tolerance=TOL, dual_contact_limit=1.0),
                                 Settings(tolerance=TOL), nodes=8192, second_chain=PRIMAL)
    assert np.median([r.fft_pairs for r in dual]) < np.median([r.fft_pairs for r in primal])


@hyp_settings(max_examples=40, deadline=None)
@given(st.integers(8, 200), st.lists(st.integers(0, 199), min_size=1, max_size=60, unique=True), st.integers(1, 40))
def test_band_stiffness_is_symmetric_positive_definite(n, picks, half_width):
    q = np.fft.rfftfreq(n)
    k_kernel = np.fft.irfft(np.abs(q) * 2 * np.pi, n=n)  # |q|: a half-plane's K up to units, K(0) = 0
    act = np.unique(np.asarray(picks) % n)
    if act.size == n:  # the dual's contact set is never every node (a half-plane's K_AA is then singular)
        act = act[1:]
    band = hard_wall_dual_cg._band_stiffness(k_kernel, act, n, half_width).toarray()
    dense = np.fft.irfft(np.abs(q) * 2 * np.pi, n=n)[(act[:, None] - act[None, :]) % n]
    near = np.abs(act[:, None] - act[None, :]) <= half_width
    np.testing.assert_allclose(band, np.where(near, dense, 0.0), rtol=0, atol=1e-14)
    np.testing.assert_allclose(band, band.T, atol=0)
    assert np.min(np.linalg.eigvalsh(band)) > 0


@pytest.mark.skipif(gfft._ducc_fft is None or gfft._pyfftw is None, reason="ducc0 or pyfftw not installed")
@pytest.mark.parametrize("law_name", ["hard-wall", "cohesive"])
def test_fft_backends_agree(monkeypatch, law_name):
    sc, h, _, _, wall_tol = case()
    sc = sc.replace(**{"interface.law": law_name})
    model = build_model(sc, h)
    law = InterfaceLaw(model)
    d0 = sc.loading.initial_separation
    z = indenter_surface(h, d0, d0 + 6e-9)
    out = {}
    for backend in ("scipy", "ducc0", "fftw"):
        monkeypatch.setenv("GFMD_FFT", backend)
        out[backend] = relax(model, law, z, np.zeros((1, model.nodes // 2 + 1), complex), Settings(tolerance=TOL),
                             wall_tol)
        assert out[backend].converged
    for backend in ("ducc0", "fftw"):
        assert np.max(np.abs(out["scipy"].u_z - out[backend].u_z)) < 1e-9 * float(np.std(h))


def test_fft_backend_choice(monkeypatch):
    assert gfft.fft_backend("scipy") == "scipy"
    with pytest.raises(ValueError, match="GFMD_FFT"):
        gfft.fft_backend("mkl")
    monkeypatch.setattr(gfft, "_pyfftw", None)
    with pytest.raises(ImportError, match="pyfftw"):
        gfft.fft_backend("fftw")
    assert gfft.fft_backend("auto") == ("ducc0" if gfft._ducc_fft is not None else "scipy")
    monkeypatch.setattr(gfft, "_ducc_fft", None)
    assert gfft.fft_backend("auto") == "scipy"
    with pytest.raises(ImportError, match="ducc0"):
        gfft.fft_backend("ducc0")
    x = np.random.default_rng(1).standard_normal(64)
    fft = gfft.Fft(64, "scipy")
    np.testing.assert_allclose(fft.irfft(fft.rfft(x)), x, atol=1e-14)
    assert fft.pairs == 1
