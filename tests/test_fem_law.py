"""The FE reference's own CZ law (reference.fem.law) against the seed's Eqs. 2–3 and GFMD's law.

The FE evaluates the law with its own code (an independent check); here its
values are checked at hand-computed points, its tangents by central differences, and the
two implementations pointwise against each other (a test may import both).
"""

import math

import numpy as np
import pytest

from gfmd_contact.core import laws
from gfmd_contact.core.scene import default_scene
from reference.fem.law import CohesiveZone, LawRangeError

PHI_N, DN, PHI_T, DT = 0.7, 1e-9, 0.3, 2e-9
LAW = CohesiveZone(PHI_N, DN, PHI_T, DT)
GAPS_N = DN * np.array([-5.0, -1.0, -0.3, 0.0, 0.2, 1.0, 2.0, 3.7, 9.0, 25.0])
GAPS_T = DT * np.array([-2.0, -0.7, -0.1, 0.0, 0.4, 1 / math.sqrt(2), 1.5])


def test_hand_values():
    """T_n(δn) = φn/(e δn) (peak), T_n(0) = 0, T_n(−δn) = −e φn/δn; T_t peak √(2/e) φt/δt at Δt = δt/√2."""
    assert LAW.normal(DN) == pytest.approx(PHI_N / (math.e * DN), rel=1e-15)
    assert LAW.normal(0.0) == 0.0
    assert LAW.normal(-DN) == pytest.approx(-math.e * PHI_N / DN, rel=1e-15)
    tn, tt = LAW.coupled(0.0, DT / math.sqrt(2))
    assert tn == 0.0 and tt == pytest.approx(math.sqrt(2 / math.e) * PHI_T / DT, rel=1e-15)
    tn, tt = LAW.coupled(2 * DN, DT)  # e^{-2} e^{-1}
    assert tn == pytest.approx(PHI_N / DN * 2 * math.exp(-3), rel=1e-15)
    assert tt == pytest.approx(2 * PHI_T / DT * math.exp(-3), rel=1e-15)
    assert LAW.normal_slope(0.0) == pytest.approx(PHI_N / DN**2, rel=1e-15)
    assert LAW.normal_slope(-DN) == pytest.approx(2 * math.e * PHI_N / DN**2, rel=1e-15)
    assert LAW.normal_potential(0.0) == pytest.approx(-PHI_N, rel=1e-15)


def test_work_of_separation_is_phi_n():
    """∫₀^∞ T_n dΔn = φn (Eq. 3), and the potential's derivative is T_n."""
    x = np.linspace(0.0, 60 * DN, 600001)
    t = LAW.normal(x)
    assert np.sum(0.5 * (t[1:] + t[:-1]) * np.diff(x)) == pytest.approx(PHI_N, rel=1e-8)
    h = 1e-6 * DN
    fd = (LAW.normal_potential(GAPS_N + h) - LAW.normal_potential(GAPS_N - h)) / (2 * h)
    assert np.allclose(fd, LAW.normal(GAPS_N), rtol=1e-7, atol=1e-9 * PHI_N / DN)


def test_tangents_by_central_differences():
    h_n, h_t = 1e-6 * DN, 1e-6 * DT
    fd = (LAW.normal(GAPS_N + h_n) - LAW.normal(GAPS_N - h_n)) / (2 * h_n)
    assert np.allclose(LAW.normal_slope(GAPS_N), fd, rtol=1e-7, atol=1e-8 * PHI_N / DN**2)
    gn, gt = np.meshgrid(GAPS_N, GAPS_T)
    slopes = LAW.coupled_slopes(gn, gt)
    tn_p, tt_p = LAW.coupled(gn + h_n, gt)
    tn_m, tt_m = LAW.coupled(gn - h_n, gt)
    tn_tp, tt_tp = LAW.coupled(gn, gt + h_t)
    tn_tm, tt_tm = LAW.coupled(gn, gt - h_t)
    expected = ((tn_p - tn_m) / (2 * h_n), (tn_tp - tn_tm) / (2 * h_t),
                (tt_p - tt_m) / (2 * h_n), (tt_tp - tt_tm) / (2 * h_t))
    scale = max(PHI_N / DN**2, PHI_T / DT**2, PHI_N / (DN * DT))
    for got, want in zip(slopes, expected):
        assert np.allclose(got, want, rtol=1e-6, atol=1e-8 * scale)


def test_coupled_reduces_to_eq3_and_is_not_conservative():
    tn, tt = LAW.coupled(GAPS_N, 0.0 * GAPS_N)
    assert np.array_equal(tn, LAW.normal(GAPS_N)) and not np.any(tt)
    _, dtn_dt, dtt_dn, _ = LAW.coupled_slopes(2 * DN, 0.5 * DT)
    assert not np.isclose(dtn_dt, dtt_dn)


def test_agrees_with_gfmd_law_pointwise():
    """The two implementations (FE's and gfmd_contact.core.laws) agree to round-off everywhere."""
    gn, gt = np.meshgrid(GAPS_N, GAPS_T)
    assert np.allclose(LAW.normal(GAPS_N), laws.traction_normal(GAPS_N, PHI_N, DN), rtol=1e-13, atol=0)
    assert np.allclose(LAW.normal_slope(GAPS_N), laws.stiffness_normal(GAPS_N, PHI_N, DN), rtol=1e-13, atol=0)
    assert np.allclose(LAW.normal_potential(GAPS_N), laws.potential_normal(GAPS_N, PHI_N, DN), rtol=1e-13, atol=0)
    for mine, theirs in zip(LAW.coupled(gn, gt), laws.traction_coupled(gn, gt, PHI_N, DN, PHI_T, DT)):
        assert np.allclose(mine, theirs, rtol=1e-13, atol=0)
    for mine, theirs in zip(LAW.coupled_slopes(gn, gt), laws.jacobian_coupled(gn, gt, PHI_N, DN, PHI_T, DT)):
        assert np.allclose(mine, theirs, rtol=1e-12, atol=1e-14 * np.max(np.abs(theirs)))
    for tol in (1e-4, 1e-3, 0.05, 0.3):
        assert LAW.contact_gap(tol) == pytest.approx(laws.contact_gap_threshold(tol, DN), rel=1e-12)


def test_from_scene_matches_the_scene_parameters():
    scene = default_scene().replace(**{"interface.tangential_ratio": 0.5})
    law = CohesiveZone.from_scene(scene)
    assert law.phi_n == pytest.approx(scene.work_normal, rel=1e-15)
    assert law.phi_t == pytest.approx(scene.work_tangential, rel=1e-15)
    assert (law.delta_n, law.delta_t) == (scene.interface.length_normal, scene.interface.length_tangential)


def test_contact_gap():
    """Δtol lies on the decaying branch with T_n(Δtol) = tol φn/δn; 9.12 δn at 1e-3 (README)."""
    for tol in (1e-5, 1e-3, 0.1, 0.36):
        gap = LAW.contact_gap(tol)
        assert gap > DN
        assert LAW.normal(gap) == pytest.approx(tol * PHI_N / DN, rel=1e-12)
    assert LAW.contact_gap(1e-3) / DN == pytest.approx(9.1180, abs=1e-4)
    for bad in (0.0, -1e-3, 1 / math.e, 0.5):
        with pytest.raises(ValueError):
            LAW.contact_gap(bad)


def test_out_of_range_gaps_raise():
    for gap in (-601 * DN, np.nan, -np.inf):
        with pytest.raises(LawRangeError):
            LAW.normal(np.array([0.0, gap]))
        with pytest.raises(LawRangeError):
            LAW.coupled(np.array([gap]), np.array([0.0]))
    assert np.isfinite(LAW.normal(-600 * DN))
    assert issubclass(LawRangeError, FloatingPointError)
