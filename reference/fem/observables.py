"""The FE reference's own per-step observables p, a_rel, ḡ_r, ḡ (seed §2, Eqs. 5–6).

Independent of `gfmd_contact.core.observables` on purpose: the FE cross-checks GFMD, so it turns its
own fields into the observables with its own code (tests/test_fem_observables.py checks
it against hand-computed cases). `FeCell.observe` / `HardWallCell.observe` return these
to `gfmd_contact.core.ramp.run_ramp`, under the names and units of `gfmd_contact.core.result.CURVE_COLUMNS`:

    p      mean pressure −⟨t_z⟩ over the N nodes (Pa), compressive positive (reference-formulas §0)
    a_rel  fraction of the N nodes in contact (1), by the scene's interface.contact_rule
           (`contact_set`); "traction-tolerance", the seed's rule (default):
           hard wall — nodes carrying compressive traction (t_z < 0);
           cohesive  — nodes whose normal traction is above contact_tolerance·φn/δn or that
           lie before the decaying branch, i.e. Δn ≤ Δtol with T_n(Δtol) = tolerance·φn/δn,
           Δtol > δn (compressed and tensile nodes alike);
           "compressive" — t_z < 0 for every law; "gap" — Δn ≤ contact_gap·δn for every law
           (δn = interface.length_normal)
    g_r    ḡ_r = √(Σ_contact g_i² / n), n the number of contact nodes (seed Eq. 5); NaN if n = 0
    g      ḡ, the same over all N nodes

with g_i² = ½[((h_i − h_{i+1})/l)² + ((h_i − h_{i−1})/l)²] (seed Eq. 6), periodic, l the
node spacing (m).
"""

from __future__ import annotations

import numpy as np


def gradient_squared(h, spacing):
    """g_i² of seed Eq. 6 on a periodic profile h (m) with node spacing l (m); dimensionless."""
    h = np.asarray(h, dtype=float)
    slope = np.diff(np.append(h, h[0])) / spacing  # slope[i] = (h_{i+1} − h_i)/l, wrapping at the end
    return 0.5 * (slope**2 + np.append(slope[-1], slope[:-1]) ** 2)  # ½(right² + left²)


def rms_gradient(h, spacing, nodes=None):
    """√(mean g_i²) over `nodes` (boolean mask; all nodes if None) (seed Eq. 5); NaN if none."""
    g2 = gradient_squared(h, spacing)
    if nodes is not None:
        g2 = g2[np.asarray(nodes, dtype=bool)]
    return float(np.sqrt(g2.sum() / g2.size)) if g2.size else float("nan")


def observables(h, spacing, t_z, contact):
    """{p, a_rel, g_r, g} from the nodal traction t_z (Pa, tension > 0) and the contact mask."""
    t_z = np.asarray(t_z, dtype=float)
    contact = np.asarray(contact, dtype=bool)
    return {"p": float(-t_z.sum() / t_z.size),
            "a_rel": float(np.count_nonzero(contact) / contact.size),
            "g_r": rms_gradient(h, spacing, contact),
            "g": rms_gradient(h, spacing)}


def contact_set(interface, gap, t_z, tolerance_gap=None):
    """Boolean contact mask of a step by interface.contact_rule (a scene's `Interface`; module docstring).

    gap Δn (m), t_z (Pa, tension > 0) on the nodes; tolerance_gap: Δtol (m) of the cohesive law's
    traction-tolerance rule (`CohesiveZone.contact_gap`), None for the hard wall (whose tolerance rule
    is the compressive one). A scene from before the rules existed has no contact_rule: the seed's.
    """
    rule = getattr(interface, "contact_rule", "traction-tolerance") if interface is not None else "traction-tolerance"
    if rule == "gap":
        return np.asarray(gap) <= interface.contact_gap * interface.length_normal
    if rule == "compressive" or tolerance_gap is None:
        return np.asarray(t_z) < 0.0
    if rule != "traction-tolerance":
        raise ValueError(f"interface.contact_rule = {rule!r}: unknown to the FE reference")
    return np.asarray(gap) <= tolerance_gap


def hard_wall_observables(h, spacing, t_z, gap=None, interface=None):
    """Observables of a hard-wall step: contact = compressive traction (or the interface's contact_rule)."""
    return observables(h, spacing, t_z, contact_set(interface, gap, t_z))


def cohesive_observables(h, spacing, gap, t_z, contact_gap, interface=None):
    """Observables of a cohesive step: contact = Δn ≤ contact_gap (Δtol, m; `CohesiveZone.contact_gap`), or
    the interface's contact_rule."""
    return observables(h, spacing, t_z, contact_set(interface, gap, t_z, contact_gap))
