"""Stickiness diagnostics of a scene, before any run (derivations: docs/stickiness.rst).

Units: SI (see `gfmd_contact.core.conventions`), per unit length of the line contact. w (J/m²) is the
law's work of adhesion and σ_max (Pa) its peak traction (the law protocol's `work_of_adhesion` and
`peak_traction`, `gfmd_contact.core.law_protocol`; seed Eq. 3: w = φn, σ_max = φn/(e δn)),
E* = E/(1 − ν²) (Pa), l = L/N the node spacing (m).

Every quantity is defined for the 1+1-D (plane-strain line-contact) problem this code solves, and
only for the surfaces it was derived for; elsewhere the scene-level functions return `NotDefined`
(value None with the reason, shown as "n/a: <reason>"). None of them applies a 2+1-D formula:

=====================  ==========================================  ============================
quantity               formula (1+1-D form)                        defined for
=====================  ==========================================  ============================
process zone l_pz      E* w / σ_max² = e² E* δn²/φn   (Eq. S1)     adhesive law, any surface
                       (prefactor 1; the Dugdale zone is (π/4) l_pz)
Johnson α              √(2wλ/(π² h0² E*))              (Eq. S2)    sinusoid, half-plane
Maugis λ (cylinder)    4σ_max (R/(π² E*² w))^{1/3}     (Eq. S3)    cylinder, half-plane
                       (Baney & Hui 1997 line contact, σ0 = σ_max)
Tabor-like μ_rough     Eq. S3 with R = 1/κ_rms          (Eq. S4)   self-affine / file, half-plane
Persson–Tosatti θ      U_el/(w L), U_el/L = ½ Σ_{q≠0} k(q)|ĥ_q|²   self-affine / file
                       (Eq. S5; k(q) the model's normal stiffness)
Pastewka–Robbins       not defined for line contacts (`PASTEWKA_ROBBINS_REASON`)
=====================  ==========================================  ============================

The process-zone resolution limit is measured (verification/studies/process_zone.py writes
verification/data/process_zone.json; `PROCESS_ZONE_LIMIT` holds its value, as the core's other
measured limits do, and tests/test_stickiness.py fails when the two differ): below it the grid
error of an adhesive sinusoid exceeds 1 %, and `resolution_warnings` says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import kernels, surfaces
from .laws import law_from_scene

#: l_pz/l below which the adhesive sinusoid's grid error exceeds PROCESS_ZONE_ERROR (verification/studies/
#: process_zone.py, entry "ci" of verification/data/process_zone.json; the core does not read verification/)
PROCESS_ZONE_LIMIT = 2.668
PROCESS_ZONE_ERROR = 0.01
#: kinds of profile the rough-surface measures (Tabor-like μ_rough, Persson–Tosatti θ) apply to
ROUGH_KINDS = ("self-affine", "file")
PASTEWKA_ROBBINS_REASON = (
    "not defined for line contacts: it rests on the 2+1-D area-load law and the perimeter of 2-D contact "
    "patches, with constants fitted to 2+1-D simulations (docs/stickiness.rst)")


@dataclass(frozen=True)
class Diagnostic:
    """One stickiness quantity of a scene: value (None = not defined, `reason` says why) and how to read it."""

    key: str  # column / meta.json key
    label: str  # how it is named in text (with its symbol)
    value: float | None
    unit: str  # "1" for dimensionless
    formula: str
    reason: str = ""  # why it is not defined (value None), else ""
    reading: str = ""  # what the value means (e.g. "JKR-like", "sticky")

    @property
    def defined(self):
        return self.value is not None

    def text(self):
        """'label = value unit (formula; reading)' or 'label = n/a: reason'."""
        if self.value is None:
            return f"{self.label} = n/a: {self.reason}"
        unit = "" if self.unit == "1" else f" {self.unit}"
        tail = f"; {self.reading}" if self.reading else ""
        return f"{self.label} = {self.value:.4g}{unit} ({self.formula}{tail})"

    def as_dict(self):
        return {"value": self.value, "unit": self.unit, "formula": self.formula,
                **({"reason": self.reason} if self.value is None else {"reading": self.reading})}


# ------------------------------------------------------------------------------------- plain formulas
def process_zone_size(contact_modulus, work, peak_traction):
    """l_pz = E* w / σ_max² (m) (Eq. S1, prefactor 1).

    contact_modulus E* (Pa), work w (J/m²), peak_traction σ_max (Pa). The Dugdale cohesive-zone
    length of a plane-strain crack at the edge of a rigid-indenter contact is (π/4) l_pz
    (reference/analytic/jkr_sinusoid.py: πE*w/(4σ0²)).
    """
    return contact_modulus * work / peak_traction**2


def johnson_alpha(work, amplitude, wavelength, contact_modulus):
    """Johnson (1995) parameter of an adhesive sinusoid α = √(2wλ/(π² h0² E*)) (1) (Eq. S2).

    h0 = amplitude (m; peak-to-valley 2h0), λ = wavelength (m). Johnson solved the plane-strain
    (1+1-D) wavy surface, so this is the native form: partial contact has a pull-off for
    α < α_max = 1.065; full contact is reached spontaneously at zero load for α ≥ α_c = 3^{3/4}/4.
    """
    return math.sqrt(2.0 * work * wavelength / (math.pi**2 * amplitude**2 * contact_modulus))


#: Johnson's α_c = 3^{3/4}/4 ≈ 0.570 (spontaneous full contact at zero load) and α_max ≈ 1.065
JOHNSON_ALPHA_CRITICAL = 3.0**0.75 / 4.0
JOHNSON_ALPHA_MAX = 4.0 * (3.0 / 8.0) ** 0.75 * (5.0 / 8.0) ** 1.25


def maugis_lambda(peak_traction, radius, contact_modulus, work):
    """Maugis parameter of a cylinder (line contact) λ = 4σ0 (R/(π² E*² w))^{1/3} (1) (Eq. S3).

    Baney & Hui (1997) form for the plane-strain cylinder with a Dugdale stress σ0; here σ0 = σ_max
    (the exponential law mapped by equal work and equal peak traction). λ ≫ 1: JKR-like; λ ≪ 1:
    DMT-like. (Maugis 1992's sphere has 2σ0(R/(πwK²))^{1/3}, a 2+1-D form not used here.)
    """
    return 4.0 * peak_traction * (radius / (math.pi**2 * contact_modulus**2 * work)) ** (1.0 / 3.0)


def profile_moments(h, length):
    """(h_rms, h'_rms, κ_rms) of a periodic profile h (m) on N nodes over `length` (m), spectrally.

    h_rms = √⟨(h − h̄)²⟩ (m), h'_rms = √(Σ q²|ĥ_q|²) (1), κ_rms = √(Σ q⁴|ĥ_q|²) (1/m), with
    ĥ_q = fft(h)/N, q = 2πn/L (gfmd_contact.core.conventions), summed over every mode but q = 0 (the Nyquist
    mode of even N included as sampled).
    """
    h = np.asarray(h, float)
    c = np.abs(np.fft.fft(h) / h.size) ** 2
    q = 2 * np.pi * np.fft.fftfreq(h.size, d=length / h.size)
    c[0] = 0.0
    return float(np.sqrt(c.sum())), float(np.sqrt(np.sum(q**2 * c))), float(np.sqrt(np.sum(q**4 * c)))


def tabor_rough(peak_traction, curvature_rms, contact_modulus, work):
    """Tabor-like parameter of a rough profile μ_rough = λ_cyl(R = 1/κ_rms) (1) (Eq. S4).

    The line-contact Maugis parameter (Eq. S3) of an asperity whose radius is the profile's rms
    radius of curvature 1/κ_rms: each asperity of a 1+1-D profile touches as a cylinder. μ_rough ≫ 1:
    the asperities adhere JKR-like; ≪ 1: DMT-like (short-range attraction around stiff asperities).
    """
    return maugis_lambda(peak_traction, 1.0 / curvature_rms, contact_modulus, work)


def full_contact_energy(h, length, stiffness):
    """U_el/L = ½ Σ_{q≠0} k(q)|ĥ_q|² (J/m² = Pa·m): elastic energy per unit length to flatten h fully (Eq. S5).

    h: profile (m) on N nodes; stiffness: callable q ↦ k(q) (Pa/m), the normal surface stiffness
    of the model (half-plane E*|q|/2, reference-formulas §1.1; a layer its effective k_zz, §1.3).
    From U = ½∫ p u dx with û_q = ĥ_q on every q ≠ 0 (q = 0 carries the mean load, not roughness).
    """
    h = np.asarray(h, float)
    c = np.abs(np.fft.fft(h) / h.size) ** 2
    q = 2 * np.pi * np.fft.fftfreq(h.size, d=length / h.size)
    keep = q != 0
    return 0.5 * float(np.sum(np.asarray(stiffness(np.abs(q[keep])), float) * c[keep]))


def persson_tosatti_ratio(energy_per_length, work):
    """θ = U_el/(w L) (1) (Eq. S5): the 1+1-D Persson–Tosatti (2001) energy balance.

    The fully conforming state has lower energy than the separated one (w_eff = w − U_el/L > 0,
    "sticky" in Persson–Tosatti's sense) iff θ < 1. For a sinusoid θ = 1/(2πα²) (α of Eq. S2).
    """
    return energy_per_length / work


# ------------------------------------------------------------------------------------- the scene
def measured_process_zone_limit():
    """(l_pz/l limit, source text): `PROCESS_ZONE_LIMIT`, measured by verification/studies/process_zone.py."""
    source = (f"measured: adhesive-sinusoid grid error > {100 * PROCESS_ZONE_ERROR:g} % below it, "
              "verification/studies/process_zone.py")
    return PROCESS_ZONE_LIMIT, source


def _outside(kind_fits, kind_reason, model, half_plane_reason):
    """Why a half-plane formula for one surface kind does not apply to the scene (None where it does)."""
    if not kind_fits:
        return kind_reason
    return None if model.half_plane else half_plane_reason


def _na(key, label, unit, formula, reason):
    return Diagnostic(key, label, None, unit, formula, reason=reason)


def diagnostics(scene, h=None):
    """The stickiness diagnostics of `scene` (list of `Diagnostic`, fixed order and keys).

    h: the profile (m) of realization 0 when already at hand; computed only for the rough kinds
    otherwise. A self-affine profile's moments and θ do not depend on the realization (deterministic
    amplitudes, random phases: `gfmd_contact.core.surfaces.self_affine`), so realization 0 stands for all.
    """
    s, m = scene.surface, scene.material
    law = law_from_scene(scene)
    e_star = m.contact_modulus
    spacing = max(s.spacings)  # 2+1-D: the coarser axis resolves the process zone least
    out = []
    if not law.adhesive:
        why = f"interface.law = {scene.interface.law!r} has no adhesion (w = 0)"
        return [_na(k, lbl, u, f, why) for k, lbl, u, f in _SPECS]
    w, sigma = law.work_of_adhesion, law.peak_traction
    lpz = process_zone_size(e_star, w, sigma)
    limit, _ = measured_process_zone_limit()
    out.append(Diagnostic("process_zone", "process zone l_pz", lpz, "m", "E* w/σ_max²"))
    out.append(Diagnostic("process_zone_nodes", "process zone in nodes l_pz/l", lpz / spacing, "1",
                          "l = L/N", reading=("resolved" if lpz / spacing >= limit else "UNDER-RESOLVED")
                          + f"; measured limit {limit:.3g}"))
    half = "derived for a half-plane; material.thickness is finite (a layer)"
    # Johnson α: sinusoid on a half-plane
    key, label, unit, formula = _SPECS[2]
    reason = _outside(s.kind == "sinusoid", f"defined for a sinusoid (surface.kind = {s.kind!r})", m, half)
    if reason:
        out.append(_na(key, label, unit, formula, reason))
    else:
        a = johnson_alpha(w, s.amplitude, s.length, e_star)
        reading = ("full contact at zero load (α ≥ α_c = 0.570)" if a >= JOHNSON_ALPHA_CRITICAL
                   else "partial contact with pull-off (α < α_c = 0.570)")
        out.append(Diagnostic(key, label, a, unit, formula, reading=reading))
    # Maugis λ: cylinder on a half-plane
    key, label, unit, formula = _SPECS[3]
    reason = _outside(s.kind == "cylinder", f"defined for a cylinder (surface.kind = {s.kind!r})", m, half)
    if reason:
        out.append(_na(key, label, unit, formula, reason))
    else:
        lam = maugis_lambda(sigma, s.radius, e_star, w)
        out.append(Diagnostic(key, label, lam, unit, formula, reading=_regime(lam)))
    # rough-surface measures
    rough = s.kind in ROUGH_KINDS and not s.two_d
    not_rough = (f"defined for a rough profile (self-affine or file; surface.kind = {s.kind!r})" if not s.two_d
                 else "its 1+1-D form is not extended to 2+1-D surfaces here (surface.nodes_y > 0)")
    if rough and h is None:
        h = surfaces.profile(s, 0)
    key, label, unit, formula = _SPECS[4]
    reason = _outside(rough, not_rough, m, half)
    if reason:
        out.append(_na(key, label, unit, formula, reason))
    else:
        _, _, kappa = profile_moments(h, s.length)
        mu = tabor_rough(sigma, kappa, e_star, w) if kappa > 0 else None
        out.append(Diagnostic(key, label, mu, unit, formula, reading=_regime(mu) + f"; κ_rms = {kappa:.4g} 1/m")
                   if mu is not None else _na(key, label, unit, formula, "the profile is flat (κ_rms = 0)"))
    key, label, unit, formula = _SPECS[5]
    if not rough:
        out.append(_na(key, label, unit, formula, not_rough))
    else:
        if m.half_plane:
            def stiffness(q):
                return kernels.halfplane_normal(q, m.youngs_modulus, m.poisson_ratio)
        else:
            def stiffness(q):
                return kernels.layer_normal(q, m.youngs_modulus, m.poisson_ratio, m.thickness)
        theta = persson_tosatti_ratio(full_contact_energy(h, s.length, stiffness), w)
        out.append(Diagnostic(key, label, theta, unit, formula,
                              reading="sticky: full contact lowers the energy" if theta < 1
                              else "not sticky: full contact costs more elastic energy than w gives"))
    out.append(_na(*_SPECS[6], PASTEWKA_ROBBINS_REASON))
    return out


def _regime(lam):
    if lam is None:
        return ""
    return "JKR-like (λ > 5)" if lam > 5 else "DMT-like (λ < 0.1)" if lam < 0.1 else "Maugis transition"


#: (key, label, unit, formula) of every diagnostic, in output order
_SPECS = (
    ("process_zone", "process zone l_pz", "m", "E* w/σ_max²"),
    ("process_zone_nodes", "process zone in nodes l_pz/l", "1", "l = L/N"),
    ("johnson_alpha", "Johnson α (sinusoid)", "1", "√(2wλ/(π²h0²E*))"),
    ("maugis_lambda", "Maugis λ (cylinder)", "1", "4σ_max(R/(π²E*²w))^(1/3)"),
    ("tabor_rough", "Tabor-like μ_rough", "1", "4σ_max(1/(κ_rms π²E*²w))^(1/3)"),
    ("persson_tosatti", "Persson–Tosatti θ", "1", "U_el(full contact)/(w L)"),
    ("pastewka_robbins", "Pastewka–Robbins", "1", "2+1-D criterion"),
)
#: the keys, in order: meta.json "stickiness" and the study-table columns "stickiness.<key>"
KEYS = tuple(spec[0] for spec in _SPECS)


def as_dict(scene, h=None):
    """{key: {value, unit, formula, reason | reading}} for meta.json (value null where not defined)."""
    return {d.key: d.as_dict() for d in diagnostics(scene, h)}


def lines(scene, h=None):
    """One text line per diagnostic (what `gfmd scene --check` prints)."""
    return [d.text() for d in diagnostics(scene, h)]


def resolution_warnings(scene):
    """["under-resolved process zone: …"] when l_pz/l lies below the measured limit, else [] (no adhesion: [])."""
    law = law_from_scene(scene)
    if not law.adhesive:
        return []
    s = scene.surface
    lpz = process_zone_size(scene.material.contact_modulus, law.work_of_adhesion, law.peak_traction)
    limit, source = measured_process_zone_limit()
    spacing, key, length = s.spacing, "surface.nodes", s.length
    if s.two_d and s.spacings[1] > spacing:  # 2+1-D: the coarser axis counts
        spacing, key, length = s.spacings[1], "surface.nodes_y", s.length_y
    ratio = lpz / spacing
    if ratio >= limit:
        return []
    nodes = int(2 ** math.ceil(math.log2(limit * length / lpz)))
    return [f"under-resolved process zone: l_pz = E* w/σ_max² = {lpz:.3g} m = {ratio:.3g} l < {limit:.3g} l "
            f"(l = L/N = {spacing:.3g} m; {source}): refine to {key} = {nodes} or more"]
