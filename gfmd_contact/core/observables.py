"""Observables computed from fields: p, a_rel, ḡ_r, ḡ (seed Eqs. 5–6), for GFMD and the app layer.

1+1-D fields are arrays of N nodes; 2+1-D fields are (Nx, Ny) arrays (the same definitions, the local
gradient over the four neighbours: `local_gradient_squared`; contact patches: `patch_statistics`).

Units: SI (see `gfmd_contact.core.conventions`). A method produces, per load step, the surface
fields u_z, u_x, t_z, t_x and the normal gap Δn on the same N nodes; `step_observables`
turns them into p, a_rel, ḡ_r (what `gfmd_contact.core.ramp` records unless the method's cell
brings its own `observe`). The FE reference does: `reference.fem.observables` is an
independent implementation of the same definitions, so that GFMD–FE comparisons check
this module too.

Contact rule: the law's `in_contact` (`gfmd_contact.core.laws`), chosen by interface.contact_rule:
"traction-tolerance" (default, the seed's §2 rule): hard wall — nodes carrying compressive
traction (−t_z > 0); cohesive laws (the cohesive wall included) — nodes with Δn ≤ Δtol, where
T_n(Δtol) = contact_tolerance·φn/δn on the decaying branch (tension included);
"compressive": nodes with −t_z > 0 for every law; "gap": nodes with Δn ≤ contact_gap·δn for
every law (δn = interface.length_normal, also for the hard wall).
"""

from __future__ import annotations

import numpy as np
import scipy.ndimage

from .laws import law_from_interface, law_from_scene


def local_gradient_squared(h, spacing, periodic=True):
    """g_i² = ½[((h_i − h_{i+1})/l)² + ((h_i − h_{i−1})/l)²] (seed Eq. 6), periodic; 1 (dimensionless).

    2+1-D (h of shape (Nx, Ny), spacing = (lx, ly)): seed Eq. 6 extended to the four neighbours, the
    local |∇h|²: g_ij² = ½[(Δ⁺_x h)² + (Δ⁻_x h)²]/lx² + ½[(Δ⁺_y h)² + (Δ⁻_y h)²]/ly² (periodic).
    periodic = False (a free region, surface.boundary = "free"): no difference across the region's edges; an edge
    node takes its one inner difference for both.
    """
    h = np.asarray(h, float)
    if h.ndim == 2:
        lx, ly = spacing
        parts = []
        for axis, step in ((0, lx), (1, ly)):  # each axis as the 1-D Eq. 6 (same operations, same round-off)
            forward = (h - np.roll(h, -1, axis=axis)) / step
            backward = (h - np.roll(h, 1, axis=axis)) / step
            if not periodic:
                _inner_at_edges(np.moveaxis(forward, axis, 0), np.moveaxis(backward, axis, 0))
            parts.append(0.5 * (forward**2 + backward**2))
        return parts[0] + parts[1]
    forward = (h - np.roll(h, -1)) / spacing
    backward = (h - np.roll(h, 1)) / spacing
    if not periodic:
        _inner_at_edges(forward, backward)
    return 0.5 * (forward**2 + backward**2)


def _inner_at_edges(forward, backward):
    """In place along axis 0: the last node's forward difference and the first's backward one (across the edge)
    replaced by the node's other (inner) difference, up to its sign."""
    forward[-1] = -backward[-1]
    backward[0] = -forward[0]


def rms_gradient(h, spacing, periodic=True):
    """ḡ: root-mean-square gradient over the whole profile (seed Eqs. 5–6 with n = N); 2+1-D: spacing = (lx, ly);
    periodic = False: `local_gradient_squared` of a free region."""
    return float(np.sqrt(np.mean(local_gradient_squared(h, spacing, periodic))))


def rms_gradient_contact(h, spacing, contact):
    """ḡ_r: rms gradient over the contact nodes only (seed Eq. 5); NaN if no node is in contact."""
    return _rms_over_contact(local_gradient_squared(h, spacing), contact)


def _rms_over_contact(g2, contact):
    """√⟨g_i²⟩ over the contact nodes (seed Eq. 5) of the local gradients squared g2; NaN without contact."""
    contact = np.asarray(contact, bool)
    if not contact.any():
        return float("nan")
    return float(np.sqrt(np.mean(g2[contact])))


def contact_mask(law, gap, traction_z):
    """Boolean contact set per the seed's rule (see module docstring).

    law: a law object of `gfmd_contact.core.laws` (`law_from_scene`), or a scene's `gfmd_contact.core.scene.Interface`
    (the rule needs no E); gap Δn (m) and traction t_z (Pa) on the nodes.
    """
    if not hasattr(law, "in_contact"):
        law = law_from_interface(law)
    return law.in_contact(gap, traction_z)


def mean_pressure(traction_z):
    """p = −⟨t_z⟩ (Pa), positive when compressive."""
    return float(-np.mean(traction_z))


def step_observables(scene, h, gap, traction_z, gradients=None):
    """Per-step observables dict: p (Pa), a_rel (1), g_r (1), g (1).

    gradients: `profile_gradients(scene, h)` where the caller keeps it over a ramp (the profile's g_i² and ḡ, the same
    numbers every step); computed here otherwise."""
    contact = contact_mask(law_from_scene(scene), gap, traction_z)
    g2, g = profile_gradients(scene, h) if gradients is None else gradients
    return {
        "p": mean_pressure(traction_z),
        "a_rel": float(np.mean(contact)),
        "g_r": _rms_over_contact(g2, contact),  # `rms_gradient_contact` on the kept g_i²
        "g": g,
    }


def profile_gradients(scene, h):
    """(g_i², ḡ) of the profile h on the scene's grid: `local_gradient_squared` (seed Eq. 6) and `rms_gradient`."""
    s = scene.surface
    spacing = s.spacings if s.two_d else s.spacing
    periodic = s.boundary == "periodic"
    return local_gradient_squared(h, spacing, periodic), rms_gradient(h, spacing, periodic)


def contact_patches(contact, periodic=True):
    """Connected contact patches of a 2+1-D contact map (boolean (Nx, Ny)), nearest neighbours (4-connected).

    With periodic = True a patch cut by the cell boundary counts once: the labels of
    `scipy.ndimage.label` are merged across the x and y boundaries (union–find over the wrapped pairs).
    Returns (labels, count): labels an int array, 0 outside contact, 1 … count per patch.
    """
    contact = np.asarray(contact, bool)
    labels, count = scipy.ndimage.label(contact)
    if not periodic or count == 0:
        return labels, count
    parent = np.arange(count + 1)

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in ((labels[0, :], labels[-1, :]), (labels[:, 0], labels[:, -1])):
        for i, j in zip(a[(a > 0) & (b > 0)], b[(a > 0) & (b > 0)]):
            ri, rj = root(i), root(j)
            if ri != rj:
                parent[max(ri, rj)] = min(ri, rj)
    roots = np.array([root(i) for i in range(count + 1)])
    _, dense = np.unique(roots, return_inverse=True)  # root 0 (background) stays 0
    return dense.reshape(roots.shape)[labels], int(dense.max())


def patch_statistics(contact, node_area, periodic=True):
    """Contact patch statistics of a 2+1-D contact map: {"patches": number, "mean_patch_area": m² (NaN if none),
    "largest_patch_area": m²}; node_area = Lx Ly/(Nx Ny) (m²) (`contact_patches`)."""
    labels, count = contact_patches(contact, periodic)
    if count == 0:
        return {"patches": 0, "mean_patch_area": float("nan"), "largest_patch_area": 0.0}
    sizes = np.bincount(labels.ravel())[1:]
    return {"patches": int(count), "mean_patch_area": float(sizes.mean() * node_area),
            "largest_patch_area": float(sizes.max() * node_area)}


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
