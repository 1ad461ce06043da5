"""Observables computed from fields: p, a_rel, ḡ_r, ḡ (seed Eqs. 5–6), for GFMD and the app layer.

Units: SI (see `contact.conventions`). A method produces, per load step, the surface
fields u_z, u_x, t_z, t_x and the normal gap Δn on the same N nodes; `step_observables`
turns them into p, a_rel, ḡ_r (what `contact.ramp` records unless the method's cell
brings its own `observe`). The FE reference does: `reference.fem.observables` is an
independent implementation of the same definitions, so that GFMD–FE comparisons check
this module too (issue 12).

Contact rule: the law's `in_contact` (`contact.laws`), chosen by interface.contact_rule:
"traction-tolerance" (default, the seed's §2 rule): hard wall — nodes carrying compressive
traction (−t_z > 0); cohesive laws (the cohesive wall included) — nodes with Δn ≤ Δtol, where
T_n(Δtol) = contact_tolerance·φn/δn on the decaying branch (tension included);
"compressive": nodes with −t_z > 0 for every law; "gap": nodes with Δn ≤ contact_gap·δn for
every law (δn = interface.length_normal, also for the hard wall).
"""

from __future__ import annotations

import numpy as np

from .laws import law_from_interface, law_from_scene


def local_gradient_squared(h, spacing):
    """g_i² = ½[((h_i − h_{i+1})/l)² + ((h_i − h_{i−1})/l)²] (seed Eq. 6), periodic; 1 (dimensionless)."""
    forward = (h - np.roll(h, -1)) / spacing
    backward = (h - np.roll(h, 1)) / spacing
    return 0.5 * (forward**2 + backward**2)


def rms_gradient(h, spacing):
    """ḡ: root-mean-square gradient over the whole profile (seed Eqs. 5–6 with n = N)."""
    return float(np.sqrt(np.mean(local_gradient_squared(h, spacing))))


def rms_gradient_contact(h, spacing, contact):
    """ḡ_r: rms gradient over the contact nodes only (seed Eq. 5); NaN if no node is in contact."""
    contact = np.asarray(contact, bool)
    if not contact.any():
        return float("nan")
    return float(np.sqrt(np.mean(local_gradient_squared(h, spacing)[contact])))


def contact_mask(law, gap, traction_z):
    """Boolean contact set per the seed's rule (see module docstring).

    law: a law object of `contact.laws` (`law_from_scene`), or a scene's `contact.scene.Interface`
    (the rule needs no E); gap Δn (m) and traction t_z (Pa) on the nodes.
    """
    if not hasattr(law, "in_contact"):
        law = law_from_interface(law)
    return law.in_contact(gap, traction_z)


def mean_pressure(traction_z):
    """p = −⟨t_z⟩ (Pa), positive when compressive."""
    return float(-np.mean(traction_z))


def step_observables(scene, h, gap, traction_z):
    """Per-step observables dict: p (Pa), a_rel (1), g_r (1), g (1)."""
    contact = contact_mask(law_from_scene(scene), gap, traction_z)
    spacing = scene.surface.spacing
    return {
        "p": mean_pressure(traction_z),
        "a_rel": float(np.mean(contact)),
        "g_r": rms_gradient_contact(h, spacing, contact),
        "g": rms_gradient(h, spacing),
    }


def reduced_pressure(p, g_r, contact_modulus):
    """p_r* = p/(ḡ_r E*) (dimensionless, seed §1); NaN where ḡ_r is undefined."""
    return np.asarray(p) / (np.asarray(g_r) * contact_modulus)


def fit_kappa(reduced, a_rel, a_max=0.1):
    """Slope κ of a_rel = κ p_r* (seed Eq. 1), least squares through the origin.

    Uses the points with 0 < a_rel ≤ a_max and finite p_r* > 0; returns (κ, number of points).
    Raises ValueError when no point qualifies.
    """
    reduced = np.asarray(reduced, float)
    a_rel = np.asarray(a_rel, float)
    use = np.isfinite(reduced) & (reduced > 0) & (a_rel > 0) & (a_rel <= a_max)
    if not use.any():
        raise ValueError(f"no step with 0 < a_rel ≤ {a_max} and p > 0 to fit κ")
    x, y = reduced[use], a_rel[use]
    return float(x @ y / (x @ x)), int(use.sum())
