"""The FE reference's own observables (reference.fem.observables) on hand-computed cases.

The FE computes p, a_rel, ḡ_r, ḡ with its own code (an independent check of
gfmd_contact.core.observables); the numbers below are worked out by hand from seed Eqs. 5–6 and the
contact rule, and the two implementations are compared on a random case.
"""

import math

import numpy as np
import pytest

from gfmd_contact.core.observables import step_observables
from gfmd_contact.core.scene import default_scene
from reference.fem.law import CohesiveZone
from reference.fem.observables import (cohesive_observables, gradient_squared, hard_wall_observables, observables,
                                       rms_gradient)

L = 0.5  # node spacing (m) of the hand cases


def test_gradient_squared_by_hand():
    """h = (0, 1, 3, 1) periodic, l = 0.5."""
    h = np.array([0.0, 1.0, 3.0, 1.0])
    # g_i² = ½[((h_i − h_{i+1})/l)² + ((h_i − h_{i−1})/l)²]
    # i=0: ½[(−1/.5)² + (−1/.5)²] = 4;  i=1: ½[(−2/.5)² + (1/.5)²] = ½(16 + 4) = 10
    # i=2: ½[(2/.5)² + (2/.5)²] = 16;   i=3: ½[(1/.5)² + (−2/.5)²] = ½(4 + 16) = 10
    assert np.allclose(gradient_squared(h, L), [4.0, 10.0, 16.0, 10.0], rtol=1e-15)
    assert rms_gradient(h, L) == pytest.approx(math.sqrt(10.0), rel=1e-15)
    assert rms_gradient(h, L, [False, True, True, False]) == pytest.approx(math.sqrt(13.0), rel=1e-15)
    assert math.isnan(rms_gradient(h, L, [False] * 4))


def test_sinusoid_rms_gradient():
    """ḡ of h = a sin(2πx/λ) on N nodes: exactly (2a/l) sin(π l/λ) / √2 (discrete slope)."""
    n, lam, a = 64, 1.0, 0.01
    spacing = lam / n
    h = a * np.sin(2 * np.pi * np.arange(n) * spacing / lam)
    expected = 2 * a / spacing * math.sin(math.pi * spacing / lam) / math.sqrt(2)
    assert rms_gradient(h, spacing) == pytest.approx(expected, rel=1e-12)


def test_observables_by_hand():
    h = np.array([0.0, 1.0, 3.0, 1.0])
    t_z = np.array([-3.0, 1.0, -5.0, 0.0])  # Pa, tension > 0
    obs = observables(h, L, t_z, [True, False, True, False])
    assert obs == pytest.approx({"p": 7.0 / 4, "a_rel": 0.5, "g_r": math.sqrt(10.0), "g": math.sqrt(10.0)}, rel=1e-15)


def test_hard_wall_contact_is_compression():
    h = np.array([0.0, 1.0, 3.0, 1.0])
    obs = hard_wall_observables(h, L, np.array([-3.0, 0.0, -1e-30, 2.0]))
    assert obs["a_rel"] == 0.5 and obs["g_r"] == pytest.approx(math.sqrt(10.0), rel=1e-15)
    assert obs["p"] == pytest.approx((3.0 + 1e-30 - 2.0) / 4, rel=1e-15)
    assert math.isnan(hard_wall_observables(h, L, np.zeros(4))["g_r"])


def test_cohesive_contact_is_the_gap_rule():
    """Nodes with T_n > tol φn/δn or before the peak (compressed, tensile rising branch) are in contact."""
    law = CohesiveZone(phi_n=1.0, delta_n=1.0)
    tol = 1e-3
    cut = law.contact_gap(tol)
    gap = np.array([-2.0, 0.5, 3.0, cut * (1 - 1e-9), cut * (1 + 1e-9), 30.0])
    h = np.arange(6.0) ** 2
    obs = cohesive_observables(h, L, gap, law.normal(gap), cut)
    assert obs["a_rel"] == pytest.approx(4 / 6, rel=1e-15)
    contact = law.normal(gap) > tol * law.phi_n / law.delta_n
    contact |= gap <= law.delta_n  # compressed and rising-branch nodes: T_n below tol there only by sign
    assert np.array_equal(contact, [True, True, True, True, False, False])
    assert obs["g_r"] == pytest.approx(math.sqrt(np.mean(gradient_squared(h, L)[contact])), rel=1e-15)
    assert obs["p"] == pytest.approx(-np.mean(law.normal(gap)), rel=1e-15)


@pytest.mark.parametrize("law", ["cohesive", "hard-wall"])
def test_agrees_with_contact_observables(law):
    """On a random step both implementations give the same numbers (a test may import both)."""
    scene = default_scene().replace(**{"interface.law": law})
    rng = np.random.default_rng(3)
    n = scene.surface.nodes
    h = rng.normal(size=n) * 1e-8
    dn = scene.interface.length_normal
    gap = rng.uniform(-3 * dn, 20 * dn, n)
    zone = CohesiveZone.from_scene(scene)
    if law == "cohesive":
        t_n = zone.normal(gap)
        mine = cohesive_observables(h, scene.surface.spacing, gap, t_n,
                                    zone.contact_gap(scene.interface.contact_tolerance))
    else:
        t_n = np.where(rng.random(n) < 0.3, -rng.random(n), 0.0)
        mine = hard_wall_observables(h, scene.surface.spacing, t_n)
    theirs = step_observables(scene, h, gap, t_n)
    assert set(mine) == set(theirs)
    assert 0 < mine["a_rel"] < 1
    for key in theirs:
        assert mine[key] == pytest.approx(theirs[key], rel=1e-12), key
