"""Interface laws as objects, one per law, built once from the scene (seed Eqs. 2–3).

The equations are module functions of `gfmd_contact.core.law_equations` (`traction_normal`,
`traction_coupled`, ...; re-exported here). The laws as a solver or check sees them are
objects, one per law, built once from the scene by `law_from_scene`: `HardWall`, `NormalCohesive` (Eq. 3),
`CoupledCohesive` (Eq. 2), `CohesiveWall` (Eq. 3's attraction with a hard-wall repulsion); the other laws
have their own modules (`gfmd_contact.core.law_registry`). Callers ask the object through the law protocol
(`gfmd_contact.core.law_protocol`: its contact rule, peak traction, jump-in separation, whether u_x is
needed, ...) instead of branching on the law's name.
Units: SI (see `gfmd_contact.core.conventions`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from .law_equations import (MAX_COMPRESSION, CompressionOverflowError, _check_compression,  # noqa: F401
                            attraction_cut, contact_gap_threshold, jacobian_coupled, jump_in_separation,
                            potential_normal, stiffness_normal, traction_coupled, traction_normal)
from . import law_registry, memo


# ---------------------------------------------------------------- the laws as objects
#
# One object per interface law, built once from the scene (`law_from_scene`), answering the law protocol
# (`gfmd_contact.core.law_protocol`: its members and what they mean); callers ask the object instead of
# branching on the law's name or class. The scene names the laws of this module through `SCENE_LAWS`
# (`gfmd_contact.core.law_registry`). The objects are frozen dataclasses: equal parameters, equal laws; picklable.


#: interface.contact_rule → what it counts as contact (docs/guide/laws.rst; seed §2 is the first)
CONTACT_RULES = {
    "traction-tolerance": "the seed's rule: hard wall — compressive nodes; cohesive laws — Δn ≤ Δtol, "
                          "T_n(Δtol) = contact_tolerance·φn/δn on the decaying branch (tension included)",
    "compressive": "nodes carrying compressive normal traction (−t_z > 0, T_n < 0)",
    "gap": "nodes with Δn ≤ contact_gap·δn (δn = interface.length_normal, also for the hard wall)",
}


def _rule_fields():
    """The contact-rule fields every law object carries (keyword-only, so subclasses may add fields):
    contact_rule (a key of CONTACT_RULES) and rule_gap (m), contact_gap·δn of rule "gap" (None otherwise)."""
    return (field(default="traction-tolerance", kw_only=True), field(default=None, kw_only=True))


def _in_contact(law, gap, traction_z):
    """The contact set of `law` (its contact_rule and contact_gap) on the nodes: boolean array."""
    threshold = law.contact_gap
    if threshold is None:  # compressive traction (rule "compressive", or the hard wall's seed rule)
        return -np.asarray(traction_z) > 0.0
    return np.asarray(gap) <= threshold


def _body_couples(material):
    """Whether the elastic body couples normal and tangential surface motion (G_xz ≠ 0): a bonded
    layer always, a half-plane unless ν = 1/2 (reference-formulas §1; `gfmd_contact.core.kernels`)."""
    return not (material.half_plane and material.poisson_ratio == 0.5)


_NO_FRICTION = "c = φt*/φn* = 0: no tangential traction, u_x decouples (normal-only CZ, seed Eq. 3)"
_FORCED_C0 = ("c = 0 with u_x solved: the coupled law (seed Eq. 2) with φt = 0, whose T_n keeps the "
              "factor exp(−Δt²/δt²); not Eq. 3, which the normal-only model solves")


@dataclass(frozen=True)
class HardWall:
    """Frictionless hard wall: the constraint Δn ≥ 0, compressive reaction only, no CZ parameter.

    contact_rule "traction-tolerance" (the seed's) and "compressive": the compressed nodes (a wall
    carries no tension, so the tolerance rule is the compressive one); "gap": Δn ≤ rule_gap =
    contact_gap·δn with δn = interface.length_normal, the only use of δn for a hard wall: it
    counts a hard-wall solution as a cohesive one would be counted (docs/guide/laws.rst).
    """

    contact_rule: str
    rule_gap: float | None
    contact_rule, rule_gap = _rule_fields()

    name: ClassVar[str] = "hard wall"
    description: ClassVar[str] = "hard wall (frictionless, Δn ≥ 0)"
    constraint: ClassVar[bool] = True
    adhesive: ClassVar[bool] = False
    tangential: ClassVar[bool] = False
    peak_traction: ClassVar[float] = 0.0  # no tension
    work_of_adhesion: ClassVar[float] = 0.0
    steepest_softening: ClassVar[float] = 0.0
    has_potential: ClassVar[bool] = True  # the constraint's indicator: E is the elastic energy where Δn ≥ 0
    curvature_scale: ClassVar[None] = None
    nodal_form: ClassVar[None] = None

    @property
    def contact_gap(self):
        """rule_gap (m) for contact_rule "gap"; else None: contact is compressive traction."""
        return self.rule_gap if self.contact_rule == "gap" else None

    def reference_traction(self, contact_modulus):
        """E* (Pa): the pressure scale of a flat profile pressed against the wall."""
        return contact_modulus

    def in_contact(self, gap, traction_z):
        """The contact rule (class docstring): compressed nodes (−t_z > 0), or Δn ≤ rule_gap for rule "gap"."""
        return _in_contact(self, gap, traction_z)

    def jump_in_separation(self, stiffness):
        """0: nothing attracts the surface, so nothing jumps."""
        return 0.0

    def needs_tangential(self, material):
        return False

    def tangential_reason(self, material):
        return "hard wall: frictionless, no tangential traction, CZ parameters unused"

    def normal_only(self):
        return self


@dataclass(frozen=True)
class _ExponentialCohesive:
    """What the normal part of the exponential CZ law (seed Eqs. 2–3 at Δt = 0) implies.

    work_normal φn (J/m²), length_normal δn (m), contact_tolerance: Δtol solves
    T_n(Δtol) = contact_tolerance·φn/δn on the decaying branch. contact_rule (keyword):
    "traction-tolerance" (the seed's: Δn ≤ Δtol), "compressive" (−t_z > 0) or "gap" (Δn ≤ rule_gap,
    = contact_gap·δn).
    """

    work_normal: float
    length_normal: float
    contact_tolerance: float
    contact_rule: str
    rule_gap: float | None
    contact_rule, rule_gap = _rule_fields()

    constraint: ClassVar[bool] = False
    adhesive: ClassVar[bool] = True

    @property
    def peak_traction(self):
        """φn/(e δn) (Pa), at Δn = δn."""
        return self.work_normal / (np.e * self.length_normal)

    @property
    def work_of_adhesion(self):
        """φn (J/m²): −V(0), the work to separate the interface from Δn = 0."""
        return self.work_normal

    @property
    def curvature_scale(self):
        """φn/δn² (Pa/m): dT_n/dΔn at Δn = 0, the stiffness of a node in contact."""
        return float(self.work_normal) / float(self.length_normal) ** 2

    def far_reach(self, traction):
        """s_c (in units of δn): |T_n| < traction (Pa) for Δn ≥ s_c δn (`attraction_cut`)."""
        return attraction_cut(traction / (float(self.work_normal) / float(self.length_normal)))

    def check_gaps(self, delta_n):
        """Raise `CompressionOverflowError` for gaps beyond the repulsive branch's range (Δn < −MAX_COMPRESSION δn)."""
        _check_compression(delta_n, self.length_normal)

    def reference_traction(self, contact_modulus):
        """The peak traction φn/(e δn) (Pa): a flat profile has no elastic pressure scale E* ḡ."""
        return self.peak_traction

    @property
    def contact_gap(self):
        """The rule's gap threshold (m): "traction-tolerance" Δtol (`contact_gap_threshold`: 9.12 δn at
        contact_tolerance = 1e-3), "gap" rule_gap = contact_gap·δn; "compressive" None."""
        if self.contact_rule == "gap":
            return self.rule_gap
        if self.contact_rule == "compressive":
            return None
        return contact_gap_threshold(self.contact_tolerance, self.length_normal)

    def in_contact(self, gap, traction_z):
        """Nodes with Δn ≤ contact_gap, compressed and tensile alike (rules "traction-tolerance", "gap"), or
        those carrying compressive traction, −t_z > 0 (rule "compressive")."""
        return _in_contact(self, gap, traction_z)

    def jump_in_separation(self, stiffness):
        """δ_jump (m) of a surface of normal stiffness k (Pa/m): module function `jump_in_separation`."""
        return jump_in_separation(stiffness, self.work_normal, self.length_normal)

    @property
    def steepest_softening(self):
        """e^{−2} φn/δn² (Pa/m): −∂T_n/∂Δn at Δn = 2δn."""
        return np.exp(-2) * self.work_normal / self.length_normal**2

    def potential(self, delta_n):
        """V(Δn) = −φn (1 + Δn/δn) e^{−Δn/δn} (J/m²), `potential_normal` (T_n = dV/dΔn at Δt = 0)."""
        return potential_normal(delta_n, self.work_normal, self.length_normal)


@dataclass(frozen=True)
class NormalCohesive(_ExponentialCohesive):
    """Normal-only exponential cohesive zone: T_n(Δn) of seed Eq. 3, T_t ≡ 0 (c = 0, or Δt ≡ 0)."""

    name: ClassVar[str] = "normal-only CZ"
    description: ClassVar[str] = "normal-only CZ (seed Eq. 3)"
    tangential: ClassVar[bool] = False
    has_potential: ClassVar[bool] = True

    @property
    def nodal_form(self):
        """("exponential", δn, φn/δn, φn/δn²): T_n = (φn/δn) s e^{−s}, s = Δn/δn, for a fused nodal kernel."""
        phi, dn = float(self.work_normal), float(self.length_normal)
        return "exponential", dn, phi / dn, phi / dn**2

    def tractions(self, delta_n, delta_t=None):
        """(T_n, T_t) in Pa: Eq. 3, and 0; delta_t is not used."""
        return traction_normal(delta_n, self.work_normal, self.length_normal), 0.0

    def tangent(self, delta_n, delta_t=None):
        """(∂Tn/∂Δn, ∂Tn/∂Δt, ∂Tt/∂Δn, ∂Tt/∂Δt) in Pa/m; only the first is non-zero."""
        return stiffness_normal(delta_n, self.work_normal, self.length_normal), 0.0, 0.0, 0.0

    @property
    def initial_stiffness(self):
        """(k_t, k_n) = (0, φn/δn²) (Pa/m): the slopes at Δ = 0."""
        return 0.0, self.work_normal / self.length_normal**2

    @property
    def length_scale(self):
        """δn (m)."""
        return self.length_normal

    def needs_tangential(self, material):
        return False

    def tangential_reason(self, material):
        return _NO_FRICTION

    def forced_tangential_reason(self):
        """Why u_x solved anyway (solver.unknowns = coupled) means Eq. 2 with φt = 0, not this law."""
        return _FORCED_C0

    def normal_only(self):
        return self


@dataclass(frozen=True)
class CoupledCohesive(_ExponentialCohesive):
    """Coupled exponential cohesive zone: (T_n, T_t)(Δn, Δt) of seed Eq. 2 (no potential).

    Besides the normal parameters: work_tangential φt = c φn* δt E (J/m²), length_tangential
    δt (m), tangential_ratio c = φt*/φn*. At Δt = 0, T_n is Eq. 3 and T_t = 0.
    """

    work_tangential: float
    length_tangential: float
    tangential_ratio: float

    name: ClassVar[str] = "coupled CZ"
    description: ClassVar[str] = "coupled CZ (seed Eq. 2)"
    tangential: ClassVar[bool] = True
    has_potential: ClassVar[bool] = False  # ∂T_n/∂Δt ≠ ∂T_t/∂Δn

    @property
    def nodal_form(self):
        """("coupled exponential", (φn, δn, φt, δt)): seed Eq. 2, for the fused coupled kernels."""
        return "coupled exponential", (self.work_normal, self.length_normal, self.work_tangential,
                                       self.length_tangential)

    def normal_only(self):
        """The frictionless reduction: seed Eq. 3 (Eq. 2 at Δt = 0, T_t ≡ 0) with this law's φn, δn and rule."""
        return NormalCohesive(work_normal=self.work_normal, length_normal=self.length_normal,
                              contact_tolerance=self.contact_tolerance, contact_rule=self.contact_rule,
                              rule_gap=self.rule_gap)

    def tractions(self, delta_n, delta_t):
        """(T_n, T_t) in Pa, seed Eq. 2."""
        return traction_coupled(delta_n, delta_t, self.work_normal, self.length_normal, self.work_tangential,
                                self.length_tangential)

    def tangent(self, delta_n, delta_t):
        """(∂Tn/∂Δn, ∂Tn/∂Δt, ∂Tt/∂Δn, ∂Tt/∂Δt) in Pa/m, `jacobian_coupled` (non-symmetric)."""
        return jacobian_coupled(delta_n, delta_t, self.work_normal, self.length_normal, self.work_tangential,
                                self.length_tangential)

    @property
    def initial_stiffness(self):
        """(k_t, k_n) = (2φt/δt², φn/δn²) (Pa/m): the slopes at Δ = 0."""
        return 2 * self.work_tangential / self.length_tangential**2, self.work_normal / self.length_normal**2

    @property
    def length_scale(self):
        """min(δn, δt) (m)."""
        return min(self.length_normal, self.length_tangential)

    def needs_tangential(self, material):
        """c > 0 on a body that couples normal and tangential motion."""
        return self.tangential_ratio > 0 and _body_couples(material)

    def tangential_reason(self, material):
        if self.tangential_ratio == 0:
            return _NO_FRICTION
        if not _body_couples(material):
            return "ν = 0.5 half-plane: kernel uncoupled, u_x ≡ 0 is exact (T_t(Δt=0) = 0)"
        return (f"c = {self.tangential_ratio:g} > 0 and ν = {material.poisson_ratio:g} couples u_x and u_z: "
                "coupled CZ (seed Eq. 2)")

    def forced_tangential_reason(self):
        """None where c > 0 (the law solved with u_x is this law); with c = 0 it is not Eq. 3."""
        return _FORCED_C0 if self.tangential_ratio == 0 else None


@dataclass(frozen=True)
class CohesiveWall(NormalCohesive):
    """CZ attraction with a hard-wall repulsion: T_n(Δn) of seed Eq. 3 for Δn > 0 and the constraint
    Δn ≥ 0 (no repulsive branch; the wall's reaction is compressive), frictionless (T_t ≡ 0).

    How the FFT-BEM peers model adhesion; a NormalCohesive with the repulsive branch replaced by the
    constraint (the solvers dispatch on the exact type). `constraint` is True: the solver keeps Δn ≥ 0 by
    projection (`gfmd.algorithms.cohesive_wall`); `tractions` is the attraction alone, Eq. 3 at
    max(Δn, 0), which is 0 on the wall (T_n(0) = 0), so a wall node's traction is its reaction.
    Contact rules as for the cohesive laws: "traction-tolerance" Δn ≤ Δtol (every wall node and the
    tensile ones up to Δtol), "compressive" the nodes the wall pushes, "gap" Δn ≤ contact_gap·δn.
    """

    name: ClassVar[str] = "cohesive wall"
    description: ClassVar[str] = "cohesive wall (seed Eq. 3 attraction for Δn > 0, hard wall Δn ≥ 0, frictionless)"
    constraint: ClassVar[bool] = True
    tangential: ClassVar[bool] = False
    nodal_form: ClassVar[None] = None  # Eq. 3 for Δn > 0 only

    def tractions(self, delta_n, delta_t=None):
        """(T_n, T_t) in Pa: the attraction Eq. 3 at max(Δn, 0) (tension ≥ 0; 0 on the wall), and 0."""
        return traction_normal(np.maximum(delta_n, 0.0), self.work_normal, self.length_normal), 0.0

    def tangent(self, delta_n, delta_t=None):
        """(∂Tn/∂Δn, 0, 0, 0) in Pa/m of the attraction at max(Δn, 0)."""
        return stiffness_normal(np.maximum(delta_n, 0.0), self.work_normal, self.length_normal), 0.0, 0.0, 0.0

    # initial_stiffness (0, φn/δn²: the attraction's slopes at Δ = 0+), length_scale δn and
    # needs_tangential (False) are NormalCohesive's

    def tangential_reason(self, material):
        return "cohesive wall: frictionless (c = 0), no tangential traction, u_x decouples"

    def forced_tangential_reason(self):
        return None  # the scene refuses solver.unknowns = "coupled" for it


def _rule(interface):
    """The contact-rule keywords of a law object from the scene's Interface."""
    i = interface
    return dict(contact_rule=i.contact_rule,
                rule_gap=i.contact_gap * i.length_normal if i.contact_rule == "gap" else None)


def _hard_wall(interface, work_normal, work_tangential, tangential, scene=None):
    if tangential:
        raise ValueError("the hard wall is frictionless and always normal-only: no tangential unknowns")
    return HardWall(**_rule(interface))


def _cohesive(interface, work_normal, work_tangential, tangential, scene=None):
    i = interface
    coupled = i.tangential_ratio > 0 if tangential is None else tangential
    if not coupled:
        return NormalCohesive(work_normal=work_normal, length_normal=i.length_normal,
                              contact_tolerance=i.contact_tolerance, **_rule(i))
    return CoupledCohesive(work_normal=work_normal, length_normal=i.length_normal,
                           contact_tolerance=i.contact_tolerance, work_tangential=work_tangential,
                           length_tangential=i.length_tangential, tangential_ratio=i.tangential_ratio, **_rule(i))


def _cohesive_wall(interface, work_normal, work_tangential, tangential, scene=None):
    if tangential:
        raise ValueError("the cohesive wall is frictionless and always normal-only: no tangential unknowns")
    return CohesiveWall(work_normal=work_normal, length_normal=interface.length_normal,
                        contact_tolerance=interface.contact_tolerance, **_rule(interface))


#: the laws of this module as the scene names them (`gfmd_contact.core.law_registry`)
SCENE_LAWS = {"hard-wall": law_registry.SceneLaw(_hard_wall, unused_friction=True),
              "cohesive": law_registry.SceneLaw(_cohesive, normal_only=False),
              "cohesive-wall": law_registry.SceneLaw(_cohesive_wall)}


def law_from_scene(scene, tangential=None):
    """The interface law of `scene` as an object answering the law protocol (`gfmd_contact.core.law_protocol`),
    built by the module `gfmd_contact.core.law_registry` names for interface.law.

    tangential=None: the law the scene describes (cohesive: c = 0 → Eq. 3, c > 0 → Eq. 2).
    True / False: the law as solved with / without the tangential unknowns u_x, which
    `gfmd_contact.core.model` decides: Eq. 2 with φt = c φn* δt E (also for c = 0, when
    solver.unknowns = "coupled" forces u_x), or Eq. 3 (u_x ≡ 0, so Δt = 0). φn and φt are
    the scene's (`Scene.work_normal`, `Scene.work_tangential`). A normal-only law refuses tangential=True.
    Built once per scene object and handed to every later caller (`gfmd_contact.core.memo`); the solved law
    is the described one where their tangential unknowns agree, else built once more.
    """
    described = memo.per_owner(scene, "law", lambda: build_law(scene))
    if tangential is None or bool(tangential) == described.tangential:
        return described
    return memo.per_owner(scene, ("law", bool(tangential)), lambda: build_law(scene, tangential))


def build_law(scene, tangential=None):
    """`law_from_scene` built anew: the module `gfmd_contact.core.law_registry` names for interface.law builds it."""
    return law_registry.entry(scene.interface.law).build(scene.interface, scene.work_normal, scene.work_tangential,
                                                          tangential, scene)


def law_from_interface(interface):
    """The law of a scene's `Interface` alone, for what needs no elastic modulus: the contact
    rule (`in_contact`, `contact_gap`), names, `constraint`/`adhesive`/`tangential`.

    φn = φn* δn E needs E, so its works of separation are NaN: use `law_from_scene` for tractions.
    """
    return law_registry.entry(interface.law).build(interface, math.nan, math.nan, None, None)
