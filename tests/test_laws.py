"""Tests of gfmd_contact.core.laws: the exponential cohesive-zone law (seed Eqs. 2–3, reference-formulas §4.0).

Conventions (gfmd_contact/core/conventions.py): Δ = indenter − body, T_n > 0 is tension.
Quantities are drawn over many decades (δ from 1e-12 to 1e-6 m, φ from 1e-4 to 1e3 J/m²)
and compared in the scaled variables s = Δ/δ, so every tolerance below is relative.
"""

import dataclasses
import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq

from gfmd_contact.core import laws
from gfmd_contact.core.model import jump_in_separation as model_jump_in_separation  # the old entry point, kept
from gfmd_contact.core.scene import default_scene

EPS = np.finfo(float).eps

lengths = st.floats(1e-12, 1e-6)  # δn, δt (m)
works = st.floats(1e-4, 1e3)  # φn, φt (J/m²)
FAST = settings(max_examples=40, derandomize=True, deadline=None)


def _tn(s, phi, dn):
    """Independent transcription of seed Eq. 3 in the scaled gap s = Δn/δn."""
    return phi / dn * s * math.exp(-s)


# ---------------------------------------------------------------- normal law (Eq. 3)

@FAST
@given(works, lengths)
def test_work_of_normal_separation_is_phi_n(phi, dn):
    # ∫0^∞ T_n dΔ = φn ∫0^∞ s e^{-s} ds = φn. quad on [0, ∞) reports an error estimate ≈ 1.4e-14 φn
    # (measured for φ, δ at both ends of the ranges; achieved error ≤ 2.2e-16): rel 1e-12 is safe.
    value, err = quad(lambda s: laws.traction_normal(s * dn, phi, dn) * dn, 0, np.inf,
                      epsabs=0, epsrel=1e-13, limit=200)
    assert err < 1e-12 * phi
    assert value == pytest.approx(phi, rel=1e-12)


@FAST
@given(works, lengths)
def test_peak_tension_at_delta_n(phi, dn):
    # T_n(δn) = φn/(e δn): one multiplication and one exp, round-off level (4 ulp)
    peak = float(laws.traction_normal(dn, phi, dn))
    assert peak == pytest.approx(phi / (math.e * dn), rel=4 * EPS)
    # dT_n/dΔ = 0 exactly at Δ = δn (factor 1 − s = 0), and it is a maximum
    assert float(laws.stiffness_normal(dn, phi, dn)) == 0.0
    s = np.array([0.0, 0.5, 0.99, 1.01, 2.0, 10.0])
    assert np.all(laws.traction_normal(s * dn, phi, dn) < peak)


@FAST
@given(works, lengths, st.floats(-40.0, 60.0))
def test_traction_matches_formula(phi, dn, s):
    # direct transcription of Eq. 3; the relative error of exp(-s) is ≲ eps·|s| (argument round-off)
    got = float(laws.traction_normal(s * dn, phi, dn))
    assert got == pytest.approx(_tn(s, phi, dn), rel=8 * EPS * (2 + abs(s)), abs=1e-300)


@FAST
@given(works, lengths, st.floats(-20.0, 40.0))
def test_traction_is_derivative_of_potential(phi, dn, s):
    # T_n = dV/dΔ with V = −φn(1 + s)e^{−s}, checked against a central difference of
    # potential_normal with step η δn, η = 1e-4. Tolerance = bound of the truncation error
    # η² max|V'''| δn²/6 (V''' = (φn/δn³)(s − 2)e^{−s}) plus the round-off 2·8eps|V|/(2ηδn), ×2.
    eta = 1e-4
    v_plus = float(laws.potential_normal((s + eta) * dn, phi, dn))
    v_minus = float(laws.potential_normal((s - eta) * dn, phi, dn))
    fd = (v_plus - v_minus) / (2 * eta * dn)
    grow = math.exp(-s + eta)
    trunc = eta**2 / 6 * (phi / dn) * (abs(s) + 2 + eta) * grow
    round_off = 16 * EPS * phi * (1 + abs(s) + eta) * grow / (2 * eta * dn)
    assert abs(fd - float(laws.traction_normal(s * dn, phi, dn))) <= 2 * (trunc + round_off)


def test_potential_closed_form_and_limits():
    phi, dn = 0.7, 2e-9
    # V(0) = −φn (the full work of separation), V(∞) = 0, V(δn) = −2φn/e
    assert float(laws.potential_normal(0.0, phi, dn)) == -phi
    assert float(laws.potential_normal(1e6 * dn, phi, dn)) == 0.0
    assert float(laws.potential_normal(dn, phi, dn)) == pytest.approx(-2 * phi / math.e, rel=4 * EPS)


@FAST
@given(works, lengths, st.floats(-30.0, 60.0))
def test_stiffness_normal_matches_finite_difference(phi, dn, s):
    # dT_n/dΔ vs a central difference of traction_normal, step η δn, η = 1e-4: truncation bound
    # η² max|T'''| δn²/6 with T''' = (φn/δn⁴)(3 − s)e^{−s}, round-off 2·8eps|T|/(2ηδn), ×2.
    eta = 1e-4
    fd = (float(laws.traction_normal((s + eta) * dn, phi, dn))
          - float(laws.traction_normal((s - eta) * dn, phi, dn))) / (2 * eta * dn)
    grow = math.exp(-s + eta)
    trunc = eta**2 / 6 * (phi / dn**2) * (abs(s) + 3 + eta) * grow
    round_off = 16 * EPS * (phi / dn) * (abs(s) + eta) * grow / (2 * eta * dn)
    assert abs(fd - float(laws.stiffness_normal(s * dn, phi, dn))) <= 2 * (trunc + round_off) + 1e-300


def test_initial_stiffness_values():
    # §4.0 table: φn/δn² at Δ = 0, 2e φn/δn² at Δ = −δn (round-off level)
    phi, dn = 1.3, 3e-9
    assert float(laws.stiffness_normal(0.0, phi, dn)) == pytest.approx(phi / dn**2, rel=4 * EPS)
    assert float(laws.stiffness_normal(-dn, phi, dn)) == pytest.approx(2 * math.e * phi / dn**2, rel=4 * EPS)


@FAST
@given(works, lengths, st.floats(-600.0, -1e-12))
def test_repulsive_for_negative_gap(phi, dn, s):
    # compression (Δn < 0) gives T_n < 0: the law pushes the body down (t_z = T_n < 0)
    assert float(laws.traction_normal(s * dn, phi, dn)) < 0.0
    assert float(laws.traction_normal(0.0, phi, dn)) == 0.0
    assert float(laws.traction_normal(-s * dn, phi, dn)) >= 0.0  # tension for an open gap


# ---------------------------------------------------------------- coupled law (Eq. 2)

@FAST
@given(works, lengths, works, lengths, st.floats(-50.0, 50.0), st.floats(0.0, 8.0))
def test_tangential_traction_odd_normal_even(pn, dn, pt, dt, sn, s_t):
    tn_p, tt_p = laws.traction_coupled(sn * dn, s_t * dt, pn, dn, pt, dt)
    tn_m, tt_m = laws.traction_coupled(sn * dn, -s_t * dt, pn, dn, pt, dt)
    # exact symmetries of the formula: (−a)/b = −(a/b) and st² is even in floating point too
    assert float(tt_m) == -float(tt_p)
    assert float(tn_m) == float(tn_p)


@FAST
@given(works, lengths, works, lengths, st.floats(-50.0, 50.0), st.floats(-8.0, 8.0))
def test_coupled_matches_formula(pn, dn, pt, dt, sn, s_t):
    # Eq. 2 transcribed with separate exponentials; exp(a)exp(b) vs exp(a+b) differ by ≲ eps(|a|+|b|)
    tn, tt = laws.traction_coupled(sn * dn, s_t * dt, pn, dn, pt, dt)
    decay = math.exp(-sn) * math.exp(-s_t**2)
    rel = 8 * EPS * (2 + abs(sn) + s_t**2)
    assert float(tn) == pytest.approx(pn / dn * sn * decay, rel=rel, abs=1e-300)
    assert float(tt) == pytest.approx(2 * pt / dt * s_t * decay, rel=rel, abs=1e-300)


@FAST
@given(works, lengths, works, lengths)
def test_work_of_tangential_separation_is_phi_t(pn, dn, pt, dt):
    # ∫0^∞ T_t(0, Δt) dΔt = 2φt ∫0^∞ s e^{−s²} ds = φt; quad error estimate ≈ 3.6e-14 φt (measured)
    value, err = quad(lambda s: laws.traction_coupled(0.0, s * dt, pn, dn, pt, dt)[1] * dt, 0, np.inf,
                      epsabs=0, epsrel=1e-13, limit=200)
    assert err < 1e-12 * pt
    assert value == pytest.approx(pt, rel=1e-12)


def test_tangential_peak():
    # §4.0: max T_t(0, Δt) = √(2/e) φt/δt at Δt = δt/√2 (round-off level; dT_t/dΔt = 0 there to round-off)
    pn, dn, pt, dt = 1.0, 1e-9, 0.4, 3e-9
    peak = dt / math.sqrt(2)
    tt = float(laws.traction_coupled(0.0, peak, pn, dn, pt, dt)[1])
    assert tt == pytest.approx(math.sqrt(2 / math.e) * pt / dt, rel=8 * EPS)
    others = laws.traction_coupled(0.0, peak * np.array([0.5, 0.99, 1.01, 2.0]), pn, dn, pt, dt)[1]
    assert np.all(others < tt)
    assert abs(float(laws.jacobian_coupled(0.0, peak, pn, dn, pt, dt)[3])) < 8 * EPS * 2 * pt / dt**2


@FAST
@given(works, lengths, works, lengths, st.floats(-600.0, 1e3))
def test_zero_slip_reduces_to_eq3(pn, dn, pt, dt, sn):
    # Δt = 0: e^{−0} = 1 so Eq. 2 is Eq. 3 bit for bit, and T_t = 0
    tn, tt = laws.traction_coupled(sn * dn, 0.0, pn, dn, pt, dt)
    assert float(tn) == float(laws.traction_normal(sn * dn, pn, dn))
    assert float(tt) == 0.0
    jac = laws.jacobian_coupled(sn * dn, 0.0, pn, dn, pt, dt)
    assert float(jac[0]) == pytest.approx(float(laws.stiffness_normal(sn * dn, pn, dn)), rel=4 * EPS, abs=1e-300)
    assert float(jac[1]) == 0.0 and float(jac[2]) == 0.0


@settings(max_examples=60, derandomize=True, deadline=None)
@given(st.floats(1e-4, 1e3), lengths, st.floats(1e-4, 1e3), lengths, st.floats(-30.0, 50.0), st.floats(-6.0, 6.0))
def test_jacobian_matches_finite_difference(pn, dn, pt, dt, sn, s_t):
    # central differences of traction_coupled with step η = 1e-5 (scaled). Error bound: round-off
    # eps/η ~ 2e-11 plus truncation η²·(third derivative)/6 ~ 1e-10, both relative to the local scale
    # (φ/δ²)·e^{−sn−st²}(1+|sn|)(1+|st|)³ of each entry. Measured over 2e4 random points:
    # max |FD − J|/scale = 8.9e-10, so 1e-8 leaves a ×10 margin; a wrong term is O(1) of the scale.
    eta = 1e-5

    def f(a, b):
        return laws.traction_coupled(a * dn, b * dt, pn, dn, pt, dt)

    d_n = [(float(p) - float(m)) / (2 * eta * dn) for p, m in zip(f(sn + eta, s_t), f(sn - eta, s_t))]
    d_t = [(float(p) - float(m)) / (2 * eta * dt) for p, m in zip(f(sn, s_t + eta), f(sn, s_t - eta))]
    fd = (d_n[0], d_t[0], d_n[1], d_t[1])  # ∂Tn/∂Δn, ∂Tn/∂Δt, ∂Tt/∂Δn, ∂Tt/∂Δt
    jac = laws.jacobian_coupled(sn * dn, s_t * dt, pn, dn, pt, dt)
    local = math.exp(-sn - s_t**2) * (1 + abs(sn)) * (1 + abs(s_t)) ** 3
    scales = (pn / dn**2, pn / (dn * dt), pt / (dn * dt), pt / dt**2)
    for j, d, scale in zip(jac, fd, scales):
        assert abs(float(j) - d) <= 1e-8 * scale * local + 1e-300


def test_coupled_law_is_not_conservative():
    # ∂Tn/∂Δt − ∂Tt/∂Δn = (2 st e^{−sn−st²}/(δn δt)) (φt − φn sn): non-zero off the line sn = φt/φn
    pn = pt = 1.0
    dn = dt = 1e-9
    jac = laws.jacobian_coupled(2 * dn, 0.5 * dt, pn, dn, pt, dt)
    curl = float(jac[1]) - float(jac[2])
    expected = 2 * 0.5 * math.exp(-2 - 0.25) / (dn * dt) * (pt - 2 * pn)
    assert curl == pytest.approx(expected, rel=1e-13)
    assert abs(curl) > 0.1 * pn / (dn * dt)
    # and the work depends on the path from (0, 0) to (δn, δt) (§4.0: "0.49 vs 0.72"):
    # A (open, then slide) = φn(1 − 2/e) + φt(1 − 1/e)/e; B (slide, then open) = φt(1 − 1/e) + φn(1 − 2/e)/e
    kw = dict(epsabs=0, epsrel=1e-13)
    a1 = quad(lambda x: float(laws.traction_coupled(x, 0.0, pn, dn, pt, dt)[0]), 0, dn, **kw)[0]
    a2 = quad(lambda y: float(laws.traction_coupled(dn, y, pn, dn, pt, dt)[1]), 0, dt, **kw)[0]
    b1 = quad(lambda y: float(laws.traction_coupled(0.0, y, pn, dn, pt, dt)[1]), 0, dt, **kw)[0]
    b2 = quad(lambda x: float(laws.traction_coupled(x, dt, pn, dn, pt, dt)[0]), 0, dn, **kw)[0]
    e = math.e
    work_a = pn * (1 - 2 / e) + pt * (1 - 1 / e) / e
    work_b = pt * (1 - 1 / e) + pn * (1 - 2 / e) / e
    # smooth integrands on a finite interval: Gauss–Kronrod is exact to round-off (rel 1e-12)
    assert a1 + a2 == pytest.approx(work_a, rel=1e-12)
    assert b1 + b2 == pytest.approx(work_b, rel=1e-12)
    assert work_a == pytest.approx(0.4967, abs=1e-4) and work_b == pytest.approx(0.7293, abs=1e-4)


# ---------------------------------------------------------------- range of validity

gaps_scaled = st.one_of(st.floats(-600.0, 50.0), st.floats(50.0, 1e6))
works_wide = st.floats(1e-8, 1e4)  # φn* from ~1e-9 to 1e6 at E = 70 GPa, δn = 1 nm


@settings(max_examples=150, derandomize=True, deadline=None)
@given(gaps_scaled, st.floats(-1e6, 1e6), works_wide, lengths, works_wide, lengths)
def test_finite_over_wide_ranges(sn, s_t, pn, dn, pt, dt):
    values = [laws.traction_normal(sn * dn, pn, dn), laws.stiffness_normal(sn * dn, pn, dn),
              laws.potential_normal(sn * dn, pn, dn),
              *laws.traction_coupled(sn * dn, s_t * dt, pn, dn, pt, dt),
              *laws.jacobian_coupled(sn * dn, s_t * dt, pn, dn, pt, dt)]
    assert all(np.isfinite(v).all() for v in values)


def test_finite_on_dense_arrays_at_the_extremes():
    # the worst corners: tiny δ, large φ, the deepest allowed compression and huge openings
    s = np.concatenate([np.linspace(-laws.MAX_COMPRESSION, 0, 1001), np.geomspace(1e-300, 1e6, 1001)])
    s_t = np.concatenate([np.linspace(-1e3, 1e3, 1001), np.geomspace(1e-300, 1e6, 1001)])
    for pn, dn in [(1e4, 1e-12), (1e-8, 1e-6), (1e4, 1e-6), (1e-8, 1e-12)]:
        gaps = s * dn
        out = [laws.traction_normal(gaps, pn, dn), laws.stiffness_normal(gaps, pn, dn),
               laws.potential_normal(gaps, pn, dn),
               *laws.traction_coupled(gaps, s_t * dn, pn, dn, pn, dn),
               *laws.jacobian_coupled(gaps, s_t * dn, pn, dn, pn, dn)]
        assert all(np.isfinite(v).all() for v in out)
        assert np.all(out[0][s < 0] < 0)  # repulsion does not underflow to 0 or flip sign


@pytest.mark.parametrize("beyond", [-laws.MAX_COMPRESSION * (1 + 1e-9), -601.0, -1e5, -np.inf, np.nan])
def test_compression_overflow_error(beyond):
    dn, phi = 1e-9, 1.0
    gap = np.array([1.0, 0.0, beyond]) * dn  # one bad node in an array is enough
    calls = [lambda: laws.traction_normal(gap, phi, dn), lambda: laws.stiffness_normal(gap, phi, dn),
             lambda: laws.potential_normal(gap, phi, dn),
             lambda: laws.traction_coupled(gap, np.zeros_like(gap), phi, dn, phi, dn),
             lambda: laws.jacobian_coupled(gap, np.zeros_like(gap), phi, dn, phi, dn)]
    for call in calls:
        with pytest.raises(laws.CompressionOverflowError):
            call()
    assert issubclass(laws.CompressionOverflowError, FloatingPointError)


def test_compression_limit_itself_is_allowed():
    dn = 1e-9
    t = laws.traction_normal(-laws.MAX_COMPRESSION * dn, 1.0, dn)
    assert np.isfinite(t) and t < 0
    assert laws.traction_normal(np.array([]), 1.0, dn).size == 0  # empty input is fine


# ---------------------------------------------------------------- contact threshold

@settings(max_examples=60, derandomize=True, deadline=None)
@given(st.floats(1e-200, math.exp(-1) * (1 - 1e-6)), lengths, works)
def test_contact_gap_threshold(tol, dn, phi):
    # (within ~1e-10 of 1/e scipy's lambertw at its branch point returns s ≈ 1 with a residual
    # ~ (1/e − tol)/tol ≲ 1e-10 — measured; such tolerances are meaningless, so they are left out)
    gap = laws.contact_gap_threshold(tol, dn)
    assert gap > dn  # on the decaying branch, beyond the peak
    # T_n(Δtol) = tol φn/δn; Lambert W is accurate to a few ulp, and s e^{−s} amplifies a relative
    # error of s by |1 − s| (s ≤ 461 for tol ≥ 1e-200): rel 1e-15·(1 + s) is the propagated bound ×~5
    s = gap / dn
    assert float(laws.traction_normal(gap, phi, dn)) == pytest.approx(tol * phi / dn, rel=1e-15 * (1 + s))


def test_contact_gap_threshold_seed_value():
    # seed: tolerance ~0.001 φn/δn → s e^{−s} = 1e-3 on the decaying branch, s = 9.1180064...
    s = laws.contact_gap_threshold(1e-3, 1.0)
    assert s * math.exp(-s) == pytest.approx(1e-3, rel=1e-13)
    assert s == pytest.approx(9.118006470, rel=1e-9)


@pytest.mark.parametrize("tol", [0.0, -1e-3, math.exp(-1), 0.5, 1.0, math.nan, math.inf])
def test_contact_gap_threshold_rejects(tol):
    with pytest.raises(ValueError, match="contact_tolerance"):
        laws.contact_gap_threshold(tol, 1e-9)


# ---------------------------------------------------------------- the laws as objects (gfmd_contact.core.laws.law_from_scene)

def _scene(**kw):
    base = {"surface.kind": "flat", "surface.nodes": 64, "surface.length": 1e-6, "interface.phi_n_star": 0.05,
            "interface.length_normal": 2e-9, "interface.length_tangential": 3e-9}
    return default_scene().replace(**{**base, **kw})


HARD = {"interface.law": "hard-wall"}
NORMAL = {"interface.law": "cohesive", "interface.tangential_ratio": 0.0}
COUPLED = {"interface.law": "cohesive", "interface.tangential_ratio": 0.7}


def _tt(sn, st, phi_t, dt):
    """Independent transcription of T_t of seed Eq. 2 in scaled gaps."""
    return 2 * phi_t / dt * st * math.exp(-sn - st * st)


def test_law_from_scene_picks_the_class_and_its_parameters():
    hard, normal, coupled = (laws.law_from_scene(_scene(**kw)) for kw in (HARD, NORMAL, COUPLED))
    assert type(hard) is laws.HardWall and type(normal) is laws.NormalCohesive
    assert type(coupled) is laws.CoupledCohesive
    sc = _scene(**COUPLED)
    e = sc.material.youngs_modulus
    # φn = φn* δn E and φt = c φn* δt E, the scene's own values
    assert coupled.work_normal == sc.work_normal == 0.05 * 2e-9 * e
    assert coupled.work_tangential == sc.work_tangential == 0.7 * 0.05 * 3e-9 * e
    assert (coupled.length_normal, coupled.length_tangential, coupled.tangential_ratio) == (2e-9, 3e-9, 0.7)
    assert coupled.contact_tolerance == normal.contact_tolerance == sc.interface.contact_tolerance
    assert normal.work_normal == _scene(**NORMAL).work_normal


def test_law_as_solved_on_the_unknowns():
    # tangential=True: Eq. 2 (φt = 0 when c = 0: solver.unknowns = coupled); False: Eq. 3 (Δt ≡ 0)
    forced = laws.law_from_scene(_scene(**NORMAL), tangential=True)
    assert type(forced) is laws.CoupledCohesive and forced.work_tangential == 0.0
    reduced = laws.law_from_scene(_scene(**COUPLED), tangential=False)
    assert reduced == laws.law_from_scene(_scene(**NORMAL))  # same φn, δn, tolerance: equal objects
    assert laws.law_from_scene(_scene(**HARD), tangential=False) == laws.HardWall()
    with pytest.raises(ValueError, match="frictionless"):
        laws.law_from_scene(_scene(**HARD), tangential=True)


def test_flags_and_descriptions():
    hard, normal, coupled = (laws.law_from_scene(_scene(**kw)) for kw in (HARD, NORMAL, COUPLED))
    assert [(x.constraint, x.adhesive, x.tangential) for x in (hard, normal, coupled)] == [
        (True, False, False), (False, True, False), (False, True, True)]
    assert [x.name for x in (hard, normal, coupled)] == ["hard wall", "normal-only CZ", "coupled CZ"]
    assert "Eq. 3" in normal.description and "Eq. 2" in coupled.description and "hard wall" in hard.description


@pytest.mark.parametrize("sn", [-30.0, -2.0, -0.3, 0.0, 0.4, 1.0, 2.0, 7.5, 40.0])
def test_normal_law_object_is_seed_eq3(sn):
    law = laws.law_from_scene(_scene(**NORMAL))
    phi, dn = law.work_normal, law.length_normal
    t_n, t_t = law.tractions(np.array([sn * dn]))
    assert float(t_n[0]) == pytest.approx(_tn(sn, phi, dn), rel=8 * EPS * (2 + abs(sn)), abs=1e-300)
    assert t_t == 0.0
    slope = phi / dn**2 * (1 - sn) * math.exp(-sn)  # dT_n/dΔn of Eq. 3
    jac = law.tangent(np.array([sn * dn]))
    assert float(jac[0][0]) == pytest.approx(slope, rel=8 * EPS * (2 + abs(sn)), abs=1e-300 + 8 * EPS * phi / dn**2)
    assert jac[1:] == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("sn, st", [(-2.0, 0.5), (0.0, 0.0), (0.3, -1.2), (1.0, 0.7), (3.0, 2.0), (-0.5, -3.0)])
def test_coupled_law_object_is_seed_eq2(sn, st):
    law = laws.law_from_scene(_scene(**COUPLED))
    pn, dn, pt, dt = law.work_normal, law.length_normal, law.work_tangential, law.length_tangential
    t_n, t_t = law.tractions(sn * dn, st * dt)
    tol = 8 * EPS * (2 + abs(sn) + st * st)
    assert float(t_n) == pytest.approx(_tn(sn, pn, dn) * math.exp(-st * st), rel=tol, abs=1e-300)
    assert float(t_t) == pytest.approx(_tt(sn, st, pt, dt), rel=tol, abs=1e-300)
    # the tangent is the derivative of these tractions (central differences in the scaled gaps)
    eta = 1e-6
    jac = law.tangent(sn * dn, st * dt)
    for col, (a, b) in enumerate([(eta * dn, 0.0), (0.0, eta * dt)]):
        plus, minus = law.tractions(sn * dn + a, st * dt + b), law.tractions(sn * dn - a, st * dt - b)
        step = 2 * (a or b)
        scale = (pn / dn**2 + pt / dt**2) * 50
        assert float(jac[col]) == pytest.approx((float(plus[0]) - float(minus[0])) / step, abs=1e-7 * scale)
        assert float(jac[2 + col]) == pytest.approx((float(plus[1]) - float(minus[1])) / step, abs=1e-7 * scale)
    # at Δt = 0 the normal traction is Eq. 3, bit for bit
    normal = laws.law_from_scene(_scene(**COUPLED), tangential=False)
    assert float(law.tractions(sn * dn, 0.0)[0]) == float(normal.tractions(sn * dn)[0])


def test_initial_stiffness_and_length_scale():
    normal, coupled = laws.law_from_scene(_scene(**NORMAL)), laws.law_from_scene(_scene(**COUPLED))
    assert normal.initial_stiffness == (0.0, normal.work_normal / normal.length_normal**2)
    jac = coupled.tangent(0.0, 0.0)
    assert coupled.initial_stiffness == pytest.approx((float(jac[3]), float(jac[0])), rel=4 * EPS)
    assert coupled.initial_stiffness[0] == 2 * coupled.work_tangential / coupled.length_tangential**2
    assert normal.length_scale == 2e-9 and coupled.length_scale == 2e-9
    assert laws.law_from_scene(_scene(**COUPLED, **{"interface.length_tangential": 1e-9})).length_scale == 1e-9


def test_peak_reference_traction_and_softening():
    law = laws.law_from_scene(_scene(**NORMAL))
    phi, dn = law.work_normal, law.length_normal
    s = np.linspace(-1, 20, 210001)  # step 1e-4: s = 1 and s = 2 are on the grid
    t = law.tractions(s * dn)[0]
    assert law.peak_traction == pytest.approx(phi / (math.e * dn), rel=4 * EPS)
    assert law.peak_traction == pytest.approx(float(t.max()), rel=1e-12)  # the grid's maximum, at s = 1
    assert law.reference_traction(123.0) == law.peak_traction  # a flat profile: the law's own scale
    assert laws.HardWall().reference_traction(123.0) == 123.0  # E*
    assert laws.HardWall().peak_traction == 0.0
    slope = law.tangent(s * dn)[0]
    assert law.steepest_softening == pytest.approx(float(-slope.min()), rel=1e-12)  # at s = 2
    assert law.steepest_softening == pytest.approx(math.exp(-2) * phi / dn**2, rel=4 * EPS)
    coupled = laws.law_from_scene(_scene(**COUPLED))
    assert (coupled.peak_traction, coupled.steepest_softening) == (law.peak_traction, law.steepest_softening)
    assert laws.HardWall().steepest_softening == 0.0


@pytest.mark.parametrize("tol", [1e-9, 1e-3, 0.05, 0.3])
def test_contact_gap_is_the_closed_form_threshold(tol):
    law = laws.law_from_scene(_scene(**NORMAL, **{"interface.contact_tolerance": tol}))
    dn = law.length_normal
    s = brentq(lambda x: x * math.exp(-x) - tol, 1.0, 200.0, xtol=1e-15, rtol=4 * EPS)  # decaying branch
    assert law.contact_gap == pytest.approx(s * dn, rel=1e-13)
    assert law.contact_gap == laws.contact_gap_threshold(tol, dn)
    gaps = np.array([-3 * dn, 0.0, law.contact_gap, law.contact_gap * (1 + 1e-12), 1e3 * dn])
    assert law.in_contact(gaps, np.full(5, 1e9)).tolist() == [True, True, True, False, False]
    coupled = laws.law_from_scene(_scene(**COUPLED, **{"interface.contact_tolerance": tol}))
    assert coupled.contact_gap == law.contact_gap


def test_seed_contact_gap_value():
    law = laws.law_from_scene(_scene(**NORMAL, **{"interface.contact_tolerance": 1e-3}))
    assert law.contact_gap == pytest.approx(9.118006470 * law.length_normal, rel=1e-9)


def test_hard_wall_contact_rule():
    wall = laws.HardWall()
    assert wall.contact_gap is None
    t_z = np.array([-1.0, -1e-300, 0.0, -0.0, 2.0])
    assert wall.in_contact(np.zeros(5), t_z).tolist() == [True, True, False, False, False]
    assert wall.in_contact(np.full(5, 1.0), t_z).tolist() == [True, True, False, False, False]  # gap ignored


@pytest.mark.parametrize("fraction", [0.999999, 0.9, 0.5, 0.1, 1e-3, 1e-6])
def test_jump_in_separation_of_the_law(fraction):
    law = laws.law_from_scene(_scene(**NORMAL))
    phi, dn = law.work_normal, law.length_normal
    k = fraction * math.exp(-2) * phi / dn**2
    d = law.jump_in_separation(k)
    assert d == model_jump_in_separation(k, phi, dn) == laws.jump_in_separation(k, phi, dn)
    # independently: stability is lost at s* > 2 where k = −dT_n/dΔn, and δ_jump = δn s*²/(s* − 1)
    s = brentq(lambda x: (x - 1) * math.exp(-x) - k * dn**2 / phi, 2.0, 800.0, xtol=1e-14, rtol=4 * EPS)
    assert d == pytest.approx(dn * s * s / (s - 1), rel=1e-9)
    assert laws.law_from_scene(_scene(**COUPLED)).jump_in_separation(k) == d
    # stiffer than the steepest softening: nothing jumps; the hard wall never jumps
    assert law.jump_in_separation(1.000001 * law.steepest_softening) == 0.0
    assert laws.HardWall().jump_in_separation(k) == 0.0


@pytest.mark.parametrize("law_kw, material, expected", [
    (HARD, {"material.poisson_ratio": 0.3}, False),
    (HARD, {"material.thickness": 1e-6}, False),
    (NORMAL, {"material.poisson_ratio": 0.3}, False),
    (NORMAL, {"material.thickness": 1e-6}, False),
    (COUPLED, {"material.poisson_ratio": 0.3}, True),  # half-plane, ν < 1/2: coupled kernel
    (COUPLED, {"material.poisson_ratio": 0.5}, False),  # half-plane, ν = 1/2: G_xz = 0
    (COUPLED, {"material.poisson_ratio": 0.3, "material.thickness": 1e-6}, True),  # bonded layer: always
    (COUPLED, {"material.poisson_ratio": -0.5, "material.thickness": 1e-6}, True),
])
def test_needs_tangential_truth_table(law_kw, material, expected):
    sc = _scene(**law_kw, **material)
    law = laws.law_from_scene(sc)
    assert law.needs_tangential(sc.material) is expected
    assert isinstance(law.tangential_reason(sc.material), str)


def test_needs_tangential_of_the_forced_coupled_form_with_c_zero():
    # Eq. 2 with φt = 0 (c = 0) needs no u_x by itself: only solver.unknowns = coupled solves it
    sc = _scene(**NORMAL, **{"material.poisson_ratio": 0.3})
    forced = laws.law_from_scene(sc, tangential=True)
    assert forced.needs_tangential(sc.material) is False
    assert "c = φt*/φn* = 0" in forced.tangential_reason(sc.material)
    assert forced.forced_tangential_reason() is not None  # says it is not Eq. 3
    assert laws.law_from_scene(_scene(**COUPLED)).forced_tangential_reason() is None


def test_law_from_interface_answers_the_contact_rule_without_E():
    sc = _scene(**COUPLED, **{"interface.contact_tolerance": 0.01})
    full, bare = laws.law_from_scene(sc), laws.law_from_interface(sc.interface)
    assert type(bare) is type(full) and bare.contact_gap == full.contact_gap
    assert math.isnan(bare.work_normal)  # φn needs E: not guessed
    assert laws.law_from_interface(_scene(**HARD).interface) == laws.HardWall()


def test_law_objects_are_frozen_equal_and_picklable():
    for kw in (HARD, NORMAL, COUPLED):
        law = laws.law_from_scene(_scene(**kw))
        assert pickle.loads(pickle.dumps(law)) == law == laws.law_from_scene(_scene(**kw))
        if dataclasses.fields(law):
            with pytest.raises(dataclasses.FrozenInstanceError):
                setattr(law, dataclasses.fields(law)[0].name, 1.0)


# ---------------------------------------------------------------- the methods ask the law protocol
_LAW_CLASSES = {"HardWall", "NormalCohesive", "CoupledCohesive", "CohesiveWall", "UserLaw", "Lj93Wall"}
_LAW_PARAMETERS = {"work_normal", "length_normal", "work_tangential", "length_tangential", "tangential_ratio", "user"}


def law_identity_reads(source):
    """[(line, what)] where `source` names a law's class or reads one law's own parameters from anything but the
    scene's Interface (the law protocol, gfmd_contact.core.law_protocol, is what a method may ask)."""
    import ast

    found = []
    for node in ast.walk(ast.parse(source)):
        name = node.id if isinstance(node, ast.Name) else node.attr if isinstance(node, ast.Attribute) else None
        if name in _LAW_CLASSES:
            found.append((node.lineno, name))
        elif isinstance(node, ast.Attribute) and name in _LAW_PARAMETERS and "interface" not in ast.unparse(node.value).lower():
            found.append((node.lineno, ast.unparse(node)))
    return found


def test_the_methods_ask_the_law_protocol_not_a_laws_class_or_parameters():
    """gfmd (every algorithm, the preconditioners, the NCG's nodal work, the chains) and the stickiness diagnostics
    never name a law's class nor read Eq. 3's parameters; a planted read is caught."""
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    files = sorted((root / "gfmd").rglob("*.py")) + [root / "gfmd_contact" / "core" / "stickiness.py"]
    wrong = {str(p.relative_to(root)): law_identity_reads(p.read_text(encoding="utf-8")) for p in files}
    assert not {k: v for k, v in wrong.items() if v}, wrong
    planted = "ok = type(law) is laws.NormalCohesive\nphi = cz.work_normal\nd = i.interface.length_normal"
    assert sorted(law_identity_reads(planted)) == [(1, "NormalCohesive"), (2, "cz.work_normal")]
