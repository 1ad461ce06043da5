"""The trust-region Newton–CG (gfmd.algorithms.newton_cg, Settings.cohesive = "newton-cg"; issue 24).

* it reaches the NCG's equilibrium on a cohesive ramp (half-plane, δn = 0.25 nm, φn* = 0.15), within the
  tolerance bound of tests/test_solver_ncg.py (two states with max nodal residual < tol·p_ref differ by at
  most 2·tol·p_ref·√N / K(q_1)), with the same contact set;
* its Hessian product (one FFT pair on the spectrum) is `Problem.tangent_times`; its energy drop along a step is
  `Problem.energy`'s;
* negative curvature: Steihaug's CG, given a Hessian with a negative direction, ends on the trust-region boundary
  with a model decrease (never a division by a negative curvature);
* the fallback: a step whose Newton budget is cut hands over to the NCG chain ("newton-cg→ncg", at the NCG's
  state); a converged state is a fixed point (0 Hessian products).
"""

from dataclasses import replace

import numpy as np
import pytest

from gfmd import chains
from gfmd.algorithms import newton_cg
from gfmd.fft import Fft, spectral_weights
from gfmd.problem import Problem
from gfmd.solver import Settings, relax

from test_solver_ncg import TOL, case, ramp, tolerance_bound


@pytest.fixture(scope="module")
def cohesive_ramp():
    sc, h, model, law, z_of = case(length_normal=0.25e-9, phi=0.15)
    deltas = 1.5e-9 * np.arange(1, 6)
    return model, law, z_of, deltas


def test_newton_cg_equals_ncg(cohesive_ramp):
    model, law, z_of, deltas = cohesive_ramp
    newton = ramp(model, law, z_of, deltas, Settings(tolerance=TOL, cohesive="newton-cg"))
    ncg = ramp(model, law, z_of, deltas, Settings(tolerance=TOL))
    bound = tolerance_bound(model, TOL)
    for a, b in zip(newton, ncg):
        assert a.method == "newton-cg" and b.method == "ncg"
        assert a.residual < TOL
        assert np.max(np.abs(a.u_z - b.u_z)) < bound, (np.max(np.abs(a.u_z - b.u_z)), bound)
        np.testing.assert_array_equal(a.t_z < 0, b.t_z < 0)
    assert any(np.any(r.t_z < 0) for r in newton)  # the ramp reaches contact: the law's nonlinear range is used
    again = newton_cg.solve(Problem(model, law, z_of(deltas[-1])), newton[-1].u_hat, Settings(tolerance=TOL))
    assert again.converged and again.iterations == 0


def test_hessian_product_is_the_problems_tangent(cohesive_ramp):
    """H p̂ = K p̂ + rfft(k_loc irfft p̂) (the Steihaug CG's product) equals Problem.tangent_times, and the nodal
    energy difference the trust region tests equals Problem.energy's."""
    model, law, z_of, deltas = cohesive_ramp
    r = relax(model, law, z_of(deltas[-1]), np.zeros((1, model.nodes // 2 + 1), complex), Settings(tolerance=1e-6))
    problem = Problem(model, law, z_of(deltas[-1]))
    rng = np.random.default_rng(0)
    fft = Fft(model.nodes)
    k = np.real(model.k_zz)
    kloc = law.law.tangent(r.gap, None)[0]
    w = spectral_weights(model.nodes) / model.nodes
    g = np.where(k > 0, 1.0 / np.where(k > 0, k, 1.0), 0.0)
    f = rng.standard_normal(model.nodes)
    f_hat = fft.rfft(f - f.mean())
    f_hat[0] = 0.0

    def sdot(a, b, weight=w):
        return float(np.sum(weight * (a.real * b.real + a.imag * b.imag)))

    rz = sdot(f_hat, g * f_hat)
    x, _, used, boundary = newton_cg._steihaug(f_hat, kloc, k, g, w, w * k, w * g, 1e12, 1e-10 * np.sqrt(rz), 2000,
                                              fft, True, sdot)
    assert not boundary  # a stable equilibrium: H positive definite, the CG solves H x = f
    hx = problem.tangent_times(r.u_hat, fft.irfft(x)[None])[0]
    target = fft.irfft(f_hat)
    assert np.max(np.abs(hx - target)) < 1e-6 * np.max(np.abs(target)), np.max(np.abs(hx - target))
    v = rng.standard_normal((1, model.nodes))
    v -= v.mean()
    s = 1e-3 * law.law.length_normal * v / np.max(np.abs(v))
    s_hat = fft.rfft(s[0])
    w = spectral_weights(model.nodes) / model.nodes
    ku = k * r.u_hat[0]
    a1 = float(np.sum(w * (s_hat.conj() * ku).real))
    a2 = float(np.sum(w * k * np.abs(s_hat) ** 2))
    nodal = a1 + 0.5 * a2 + float(np.sum(law.law.potential(r.gap - s[0]) - law.law.potential(r.gap)))
    whole = (problem.energy(r.u_hat + s_hat[None]) - problem.energy(r.u_hat)) * model.nodes / model.length
    assert abs(nodal - whole) < 1e-6 * abs(whole), (nodal, whole)


def test_negative_curvature_goes_to_the_boundary():
    """An indefinite model H = K + diag(k_loc), k_loc ≪ −K on some nodes: the CG meets pᵀHp ≤ 0 and stops on
    ‖s‖_K = radius with m(0) − m(s) > 0."""
    n = 64
    fft = Fft(n)
    q = np.arange(n // 2 + 1, dtype=float)
    k = 1.0 + q  # K(q) > 0 on every mode (no clamp)
    g = 1.0 / k
    w = spectral_weights(n) / n
    kloc = np.zeros(n)
    kloc[10:20] = -50.0 * k.max()
    rng = np.random.default_rng(1)
    f_hat = fft.rfft(rng.standard_normal(n))

    def sdot(a, b, weight=w):
        return float(np.sum(weight * (a.real * b.real + a.imag * b.imag)))

    radius = 1e3  # large: only the negative curvature, not the region, can stop the CG on its boundary
    s, drop, used, boundary = newton_cg._steihaug(f_hat, kloc, k, g, w, w * k, w * g, radius, 1e-12, 50, fft, False,
                                                  sdot)
    assert boundary and drop > 0 and used < 50
    assert abs(np.sqrt(sdot(s, s, w * k)) - radius) < 1e-9 * radius
    s_nodes = fft.irfft(s)  # the model decrease reported is m(0) − m(s) of this s
    model = -sdot(f_hat, s) + 0.5 * (sdot(s, s, w * k) + float(np.sum(kloc * s_nodes**2)))
    assert abs(drop + model) < 1e-9 * abs(model)


def test_falls_back_to_ncg(cohesive_ramp, monkeypatch):
    model, law, z_of, deltas = cohesive_ramp
    monkeypatch.setattr(newton_cg, "NEWTON_CG_ITERATIONS", 1)
    z = z_of(deltas[2])
    guess = np.zeros((1, model.nodes // 2 + 1), complex)
    r = relax(model, law, z, guess, Settings(tolerance=TOL, cohesive="newton-cg"), 0.0)
    assert r.converged and r.method == "newton-cg→ncg", r.method
    assert "Newton–CG stopped" in r.message
    ncg = relax(model, law, z, guess, Settings(tolerance=TOL), 0.0)
    assert np.max(np.abs(r.u_z - ncg.u_z)) < tolerance_bound(model, TOL)


def test_chain_and_labels():
    assert chains.CHAINS[("cohesive", "newton-cg")][0].algorithm == "newton_cg"
    settings = replace(Settings(), cohesive="newton-cg")
    assert chains.labels(("cohesive", "newton-cg"), settings) == ("newton-cg", "ncg", "fire")
    with pytest.raises(ValueError, match="Settings.cohesive"):
        sc, h, model, law, z_of = case(nodes=256)
        relax(model, law, z_of(0.0), np.zeros((1, 129), complex), replace(Settings(), cohesive="newton"), 0.0)
