"""The 3-D FE's own per-step observables on the Nx × Ny surface nodes (seed §2, Eqs. 5–6 in 2+1-D).

Independent of `gfmd_contact.core.observables` (SPEC2D definitions, written here again):

    p      = −⟨t_z⟩ over the Nx·Ny nodes (Pa), compressive positive
    a_rel  = fraction of nodes in contact, by the contact rule:
             "traction-tolerance" (the seed's): hard wall — t_z < 0; cohesive — Δn ≤ Δtol
             (`law.NormalCohesiveZone.contact_gap`); "compressive": t_z < 0; "gap": Δn ≤ contact_gap·δn
    g_r    = √(Σ_contact g_i² / n) (seed Eq. 5), NaN without contact; g the same over all nodes, with
    g_i²   = ½[(Δ⁺_x h)² + (Δ⁻_x h)²]/lx² + ½[(Δ⁺_y h)² + (Δ⁻_y h)²]/ly²  (Eq. 6 over the four neighbours),
             periodic; axis 0 is x, axis 1 is y.
"""

from __future__ import annotations

import numpy as np

CONTACT_RULES = ("traction-tolerance", "compressive", "gap")


def gradient_squared(h, spacing):
    """g_i² (dimensionless) on the periodic (Nx, Ny) heights h (m); spacing (lx, ly) (m)."""
    h = np.asarray(h, dtype=float)
    g2 = np.zeros_like(h)
    for axis, step in enumerate(spacing):
        forward = (np.roll(h, -1, axis=axis) - h) / step
        backward = (h - np.roll(h, 1, axis=axis)) / step
        g2 += 0.5 * (forward**2 + backward**2)
    return g2


def rms_gradient(h, spacing, nodes=None):
    """√(mean g_i²) over the boolean mask `nodes` (all if None); NaN if the mask is empty."""
    g2 = gradient_squared(h, spacing)
    if nodes is not None:
        g2 = g2[np.asarray(nodes, dtype=bool)]
    return float(np.sqrt(g2.mean())) if g2.size else float("nan")


def contact_mask(rule, gap, t_z, tolerance_gap=None, rule_gap=None):
    """Boolean contact mask by `rule` (module docstring). tolerance_gap: Δtol (m), None for the hard wall;
    rule_gap: the "gap" rule's threshold (m)."""
    if rule not in CONTACT_RULES:
        raise ValueError(f"contact_rule = {rule!r}: one of {', '.join(CONTACT_RULES)}")
    if rule == "gap":
        return np.asarray(gap) <= rule_gap
    if rule == "compressive" or tolerance_gap is None:
        return np.asarray(t_z) < 0.0
    return np.asarray(gap) <= tolerance_gap


def observables(h, spacing, t_z, contact):
    """{p, a_rel, g_r, g} of one step from the nodal t_z (Pa, tension > 0) and the contact mask."""
    t_z = np.asarray(t_z, dtype=float)
    contact = np.asarray(contact, dtype=bool)
    return {"p": float(-t_z.mean()), "a_rel": float(contact.mean()),
            "g_r": rms_gradient(h, spacing, contact), "g": rms_gradient(h, spacing)}
