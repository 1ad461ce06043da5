"""How far apart two converged GFMD states of one scene can lie: the bound the cross-checks of a method against
itself (the same problem reached by two routes) derive their tolerances from.

Each state stops at max|f| < τ p_ref (τ the solver tolerance, p_ref the model's reference traction), so the two
displacement fields differ by at most |Δu| ≤ 2τ p_ref √N / k_min and the tractions, hence p̄, by at most
k_max |Δu| + 2τ p_ref, with k_min and k_max the smallest positive and the largest normal stiffness of the
model's kernel and N its node count (the derivation of verification/test_embedded_sinusoid_2d.py).
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.core.model import build_model


def state_bounds(scene, tolerance=None):
    """(|Δu|_max (m), |Δp̄|_max (Pa)) between two converged states of `scene` at `tolerance` (default: the
    scene's solver tolerance)."""
    m = build_model(scene)
    k = np.real(np.asarray(m.k_zz)).ravel()
    tau_p = (scene.solver.tolerance if tolerance is None else tolerance) * m.reference_traction
    du = 2 * tau_p * np.sqrt(m.nodes) / float(np.min(k[k > 0]))
    return float(du), float(np.max(k)) * float(du) + 2 * tau_p
