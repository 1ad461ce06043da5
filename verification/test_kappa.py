"""κ (seed Eq. 1, a_rel = κ p/(ḡ_r E*)): the fit recovers a known synthetic relation.

The points below a_max = 0.1 follow a_rel = κ p_r* exactly with κ = 1.75 (the seed's value);
points above a_max follow another relation, and tensile (p_r* ≤ 0), zero-area and NaN points
are mixed in: `gfmd_contact.core.observables.fit_kappa` must return κ to round-off and count exactly the
qualifying points. A second relation with noise checks the least-squares slope through the
origin against numpy's lstsq on the same points. Added because the mutation run found a κ fit
2 % off uncaught.
"""

import numpy as np
import pytest

from gfmd_contact.core.observables import fit_kappa

KAPPA = 1.75
ROUND_OFF = 1e-12


def synthetic():
    p = np.linspace(0.002, 0.05, 25)
    a = KAPPA * p  # a ≤ 0.0875 < a_max
    extra_p = np.array([0.08, 0.12, -0.01, 0.0, np.nan, 0.03])
    extra_a = np.array([0.2, 0.3, 0.01, 0.0, 0.05, 0.0])  # above a_max, tensile, p = 0, NaN, zero area
    return np.concatenate([p, extra_p]), np.concatenate([a, extra_a]), p.size


def test_kappa_fit_recovers_a_known_relation(verification_record):
    p, a, n = synthetic()
    kappa, used = fit_kappa(p, a)
    verification_record(case="observables/kappa-fit", metric="|κ_fit − κ| / κ (exact synthetic relation)",
                        value=abs(kappa - KAPPA) / KAPPA, tolerance=ROUND_OFF, methods=("analytic",),
                        tolerance_source="an exact relation: round-off only")
    assert used == n
    assert abs(kappa - KAPPA) / KAPPA <= ROUND_OFF, kappa


def test_kappa_fit_is_least_squares_through_the_origin():
    rng = np.random.default_rng(3)
    p = np.linspace(0.002, 0.05, 30)
    a = KAPPA * p * (1 + 0.05 * rng.standard_normal(p.size))
    kappa, used = fit_kappa(p, a)
    expected = np.linalg.lstsq(p[:, None], a, rcond=None)[0][0]
    assert used == p.size and kappa == pytest.approx(expected, rel=1e-12)
