"""The FE pressure from its own nodal reaction forces (`Result.diagnostics["reaction_pressure"]`).

Hard wall: −Σ (S u)_z / L = Σ μ / L at equilibrium, and the nodal tractions lump the midpoint forces
onto the vertices, so it equals the observable p = −⟨t_z⟩ to round-off (an identity). Cohesive: one value
per step, from S u (the elastic force at the surface), not from the tractions: it differs from the node
mean (verification/test_fe_cohesive.py measures by how much).
"""

import numpy as np

from verification.runs import run_method, with_method
from verification.scenes import cohesive_sinusoid, hard_wall_self_affine


def test_hard_wall_reaction_pressure_is_the_wall_force_mean():
    r = run_method(with_method(hard_wall_self_affine(64), "fe", order=2))
    pr = np.asarray(r.diagnostics["reaction_pressure"])
    assert pr.size == len(r.curve["p"])
    np.testing.assert_allclose(pr, r.curve["p"], rtol=0, atol=1e-12 * np.max(np.abs(r.curve["p"])))


def test_cohesive_reaction_pressure_is_from_the_elastic_force():
    r = run_method(with_method(cohesive_sinusoid(64), "fe", order=2))
    pr = np.asarray(r.diagnostics["reaction_pressure"])
    prob, k = r.diagnostics["problem"], max(r.diagnostics["solutions"])
    u = r.diagnostics["solutions"][k]
    assert pr.size == len(r.curve["p"])
    assert pr[k] == -float(np.sum(prob.S @ u)) / r.scene.surface.length
    assert not np.allclose(pr, r.curve["p"], rtol=1e-6, atol=0)  # a different estimate, not a copy of p
