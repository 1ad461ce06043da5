"""Tests of gfmd_contact.core.observables: seed Eqs. 5–6 (rms gradient), contact rules, pressure sign."""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays

from gfmd_contact.core import laws, observables
from gfmd_contact.core.scene import Interface, scene_from_dict

EPS = np.finfo(float).eps


def _g2_loop(h, spacing):
    """Seed Eq. 6 with periodic neighbours, written as an explicit loop."""
    n = len(h)
    out = np.empty(n)
    for i in range(n):
        forward = (h[i] - h[(i + 1) % n]) / spacing
        backward = (h[i] - h[(i - 1) % n]) / spacing
        out[i] = 0.5 * (forward**2 + backward**2)
    return out


heights = arrays(float, st.integers(3, 40), elements=st.floats(-1e-6, 1e-6))
spacings = st.floats(1e-12, 1e-6)


@settings(max_examples=60, derandomize=True, deadline=None)
@given(heights, spacings)
def test_local_gradient_matches_explicit_loop(h, spacing):
    # the same arithmetic in another order: round-off level (4 eps relative to the largest term)
    got = observables.local_gradient_squared(h, spacing)
    ref = _g2_loop(h, spacing)
    scale = max(ref.max(), 1e-300)
    assert got.shape == h.shape
    assert np.all(np.abs(got - ref) <= 4 * EPS * scale)
    assert np.all(got >= 0)


def test_local_gradient_uses_both_periodic_neighbours():
    # a single spike at node 0 of 6: g² = 1 at the spike (both sides), ½ at nodes 1 and 5 (wrap-around)
    h = np.array([1.0, 0, 0, 0, 0, 0])
    assert np.array_equal(observables.local_gradient_squared(h, 1.0), [1.0, 0.5, 0, 0, 0, 0.5])
    assert np.array_equal(observables.local_gradient_squared(h, 0.5), [4.0, 2.0, 0, 0, 0, 2.0])


@pytest.mark.parametrize("nodes", [8, 64, 1001])
def test_rms_gradient_of_a_sinusoid(nodes):
    # h = a sin(2πx/L): h_i − h_{i+1} = −2a cos(θ_i + φ/2) sin(φ/2), φ = 2π/N, so exactly
    # ḡ² = 2a² sin²(π/N)/l² (→ (a q)²/2, the continuum value, for N → ∞); round-off level
    a, length = 3e-9, 2e-6
    spacing = length / nodes
    x = np.arange(nodes) * spacing
    h = a * np.sin(2 * np.pi * x / length)
    expected = math.sqrt(2) * a * math.sin(math.pi / nodes) / spacing
    assert observables.rms_gradient(h, spacing) == pytest.approx(expected, rel=1e-13)
    assert observables.rms_gradient(np.full(nodes, 5e-9), spacing) == 0.0


@settings(max_examples=40, derandomize=True, deadline=None)
@given(heights, spacings, st.data())
def test_rms_gradient_over_a_mask(h, spacing, data):
    mask = data.draw(arrays(bool, h.size))
    g2 = _g2_loop(h, spacing)
    got = observables.rms_gradient_contact(h, spacing, mask)
    if not mask.any():
        assert math.isnan(got)  # ḡ_r undefined without contact
    else:
        # mean over the contact nodes only (seed Eq. 5, n = number of contact points)
        assert got == pytest.approx(math.sqrt(g2[mask].sum() / mask.sum()), rel=1e-14, abs=1e-300)
    assert observables.rms_gradient_contact(h, spacing, np.ones(h.size, bool)) == pytest.approx(
        observables.rms_gradient(h, spacing), rel=1e-15, abs=1e-300)


def test_rms_gradient_contact_accepts_int_and_list_masks():
    h = np.array([0.0, 1.0, 0.0, 3.0, 0.0, 0.0])
    g2 = _g2_loop(h, 1.0)
    assert observables.rms_gradient_contact(h, 1.0, [0, 1, 0, 1, 0, 0]) == pytest.approx(
        math.sqrt((g2[1] + g2[3]) / 2), rel=1e-15)
    assert math.isnan(observables.rms_gradient_contact(h, 1.0, [0] * 6))
    assert math.isnan(observables.rms_gradient_contact(h, 1.0, np.zeros(6, bool)))


# ---------------------------------------------------------------- contact rules

def test_hard_wall_contact_is_compressive_traction():
    interface = Interface(law="hard-wall")
    t_z = np.array([-1e6, -1e-300, 0.0, -0.0, 1e-300, 2e6])  # t_z < 0 is compression (p = −t_z)
    gap = np.zeros(6)  # the gap does not enter the hard-wall rule
    assert np.array_equal(observables.contact_mask(interface, gap, t_z), [True, True, False, False, False, False])
    assert np.array_equal(observables.contact_mask(interface, gap + 1.0, t_z),
                          observables.contact_mask(interface, gap, t_z))


@pytest.mark.parametrize("tol", [1e-3, 1e-6, 0.2])
def test_cohesive_contact_is_gap_below_threshold(tol):
    dn = 2e-9
    interface = Interface(law="cohesive", length_normal=dn, contact_tolerance=tol)
    threshold = laws.contact_gap_threshold(tol, dn)
    gap = np.array([-5 * dn, 0.0, dn, threshold * (1 - 1e-12), threshold, threshold * (1 + 1e-12), 50 * dn])
    t_z = np.full(gap.size, 1e9)  # traction does not enter the cohesive rule (tension counts as contact)
    mask = observables.contact_mask(interface, gap, t_z)
    assert np.array_equal(mask, [True, True, True, True, True, False, False])
    # equivalently: contact ⇔ Δn ≤ δn or T_n(Δn) ≥ tol·φn/δn on the decaying branch
    phi = 1.0
    t_n = laws.traction_normal(gap, phi, dn)
    open_far = (gap > dn) & (t_n < tol * phi / dn * (1 - 1e-9))
    assert np.array_equal(mask[[0, 1, 2, 6]], ~open_far[[0, 1, 2, 6]])


def test_seed_contact_tolerance_threshold_value():
    # seed: tolerance ~0.001 φn/δn → Δtol = 9.118 δn
    interface = Interface(law="cohesive", length_normal=1e-9, contact_tolerance=1e-3)
    gap = np.array([9.11e-9, 9.12e-9])
    assert np.array_equal(observables.contact_mask(interface, gap, np.zeros(2)), [True, False])


def test_contact_mask_asks_the_law_object():
    # the rule is the law's (gfmd_contact.core.laws: in_contact); an Interface gives the same mask as the scene's law
    gap = np.array([-1.0, 0.0, 5.0, 9.1, 9.2, 30.0]) * 1e-9
    t_z = np.array([-3.0, 0.0, 2.0, 1.0, -1.0, 0.0]) * 1e6
    for law_name, expected in (("hard-wall", [True, False, False, False, True, False]),
                               ("cohesive", [True, True, True, True, False, False])):
        scene = scene_from_dict({"interface": {"law": law_name, "length_normal": 1e-9, "contact_tolerance": 1e-3}})
        law = laws.law_from_scene(scene)
        assert observables.contact_mask(law, gap, t_z).tolist() == expected
        assert observables.contact_mask(scene.interface, gap, t_z).tolist() == expected
        assert law.in_contact(gap, t_z).tolist() == expected


# ---------------------------------------------------------------- pressure and per-step observables

def test_mean_pressure_sign():
    assert observables.mean_pressure(np.array([-2e6, -4e6])) == 3e6  # compressive → positive
    assert observables.mean_pressure(np.array([1e6, 1e6])) == -1e6  # adhesive tension → negative
    assert isinstance(observables.mean_pressure(np.zeros(3)), float)


def test_step_observables():
    scene = scene_from_dict({"surface": {"kind": "sinusoid", "nodes": 8, "length": 8e-9, "amplitude": 1e-9},
                             "interface": {"law": "hard-wall"}})
    h = np.array([0.0, 1.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0]) * 1e-9
    t_z = np.array([-4.0, -2.0, 0.0, 1.0, 0.0, 0.0, 0.0, -2.0]) * 1e6
    gap = np.zeros(8)
    obs = observables.step_observables(scene, h, gap, t_z)
    assert set(obs) == {"p", "a_rel", "g_r", "g"}
    assert obs["p"] == pytest.approx(7e6 / 8, rel=1e-15)
    assert obs["a_rel"] == 3 / 8
    g2 = _g2_loop(h, 1e-9)
    assert obs["g_r"] == pytest.approx(math.sqrt((g2[0] + g2[1] + g2[7]) / 3), rel=1e-14)
    assert obs["g"] == pytest.approx(math.sqrt(g2.mean()), rel=1e-14)
    # no contact at all: a_rel = 0 and ḡ_r = NaN
    empty = observables.step_observables(scene, h, gap, np.zeros(8))
    assert empty["a_rel"] == 0.0 and math.isnan(empty["g_r"]) and empty["p"] == 0.0


def test_step_observables_cohesive():
    scene = scene_from_dict({"surface": {"kind": "flat", "nodes": 8, "length": 8e-9},
                             "interface": {"law": "cohesive", "length_normal": 1e-9, "contact_tolerance": 1e-3}})
    gap = np.array([0.0, 1.0, 5.0, 9.0, 9.2, 20.0, -0.5, 3.0]) * 1e-9
    t_z = laws.traction_normal(gap, scene.work_normal, 1e-9)
    obs = observables.step_observables(scene, np.zeros(8), gap, t_z)
    assert obs["a_rel"] == 6 / 8  # all but 9.2 δn and 20 δn (Δtol = 9.118 δn)
    assert obs["p"] == pytest.approx(-np.mean(t_z), rel=1e-15)
    assert obs["g_r"] == 0.0 and obs["g"] == 0.0


def test_reduced_pressure():
    e_star = 70e9 / (1 - 0.45**2)
    assert observables.reduced_pressure(1e6, 0.1, e_star) == pytest.approx(1e6 / (0.1 * e_star), rel=1e-15)
    out = observables.reduced_pressure(np.array([1e6, 2e6]), np.array([0.2, np.nan]), e_star)
    assert out[0] == pytest.approx(1e6 / (0.2 * e_star), rel=1e-15) and math.isnan(out[1])


@settings(max_examples=40, derandomize=True, deadline=None)
@given(st.integers(8, 64).flatmap(lambda n: st.tuples(
    arrays(float, n, elements=st.floats(-1e-8, 1e-8)), arrays(float, n, elements=st.floats(-1e-9, 2e-8)),
    arrays(float, n, elements=st.floats(-1e7, 1e7)))), st.sampled_from(["hard-wall", "cohesive"]))
def test_step_observables_from_the_ramps_gradients_are_the_same_numbers(fields, law):
    # gfmd_contact.core.ramp computes the profile's g_i² once (`profile_gradients`) and hands it to every step: the
    # observables must be those computed from the heights at every step (rms_gradient, rms_gradient_contact on the
    # contact mask, as step_observables did before), bit for bit, with or without the kept gradients
    h, gap, t_z = fields
    scene = scene_from_dict({"surface": {"kind": "flat", "nodes": h.size, "length": h.size * 1e-9},
                             "interface": {"law": law}})
    spacing = scene.surface.spacing
    contact = observables.contact_mask(laws.law_from_scene(scene), gap, t_z)
    alone = {"p": observables.mean_pressure(t_z), "a_rel": float(np.mean(contact)),
             "g_r": observables.rms_gradient_contact(h, spacing, contact), "g": observables.rms_gradient(h, spacing)}
    for kept in (observables.step_observables(scene, h, gap, t_z),
                 observables.step_observables(scene, h, gap, t_z, gradients=observables.profile_gradients(scene, h))):
        assert alone.keys() == kept.keys()
        for key in alone:
            assert alone[key] == kept[key] or (math.isnan(alone[key]) and math.isnan(kept[key])), key
