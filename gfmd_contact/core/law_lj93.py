"""The Lennard-Jones 9-3 wall: a flat half-space of LJ atoms integrated over depth (interface.law = "lj93").

The interaction of a surface with a wall of Lennard-Jones atoms (Pastewka & Robbins, PNAS 2014; the 9-3 wall of
ContactEngineering's Adhesion), written in the two numbers the scene gives, SI:

    interface.work_of_adhesion  w (J/m²)   the work to separate the interface from its equilibrium
    interface.range_length      z0 (m)     the wall's equilibrium distance, which sets the interaction range

With z = z0 + Δn the distance to the wall and x = z0/z (Δn = 0 the unloaded equilibrium, as for seed Eq. 3;
Δn = indenter − body, T_n > 0 tensile, `gfmd_contact.core.conventions`):

    V(Δn) = w (x⁹/2 − 3x³/2),   T_n = dV/dΔn = (9w/(2z)) (x³ − x⁹),   dT_n/dΔn = (9w/z²) (5x⁹ − 2x³)

so V(0) = −w, T_n(0) = 0, dT_n/dΔn(0) = 27 w/z0². The traction peaks at x_p⁶ = 2/5 with (27/10)(w/z0) x_p⁴ and
softens most steeply at x_s⁶ = 2/11, −dT_n/dΔn = (108/11)(w/z0²) x_s⁵. Closer than the core z < CORE·z0 the energy
continues as the cubic that matches V, T_n, dT_n/dΔn and d²T_n/dΔn² there (a repulsion growing quadratically in
T_n), so every gap has finite values and the tangent is continuous with its slope: a solver's trial state deep in
the wall is repelled instead of overflowing or, past z = 0, attracted. The long-range tail T_n ~ z⁻⁴ has no cut-off.

Normal-only (T_t ≡ 0) and a potential: the NCG and the FE's energy line search apply. No fused kernel (`nodal_form`
None: a method evaluates `tractions`/`tangent`), and no curvature scale (the two-level preconditioner was measured on
seed Eq. 3 only). Contact rules as for every law (`gfmd_contact.core.laws`): "traction-tolerance" Δn ≤ Δtol where
T_n falls to contact_tolerance·e·peak_traction beyond the peak (as a user law's), "compressive", "gap" Δn ≤
contact_gap·interface.length_normal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
from scipy.optimize import brentq

from .law_equations import CompressionOverflowError
from .law_registry import LawKey, SceneLaw

#: the wall core: closer than CORE·z0 (x > 1/CORE) the energy continues as a cubic
CORE = 0.5
#: x at the traction peak (x⁶ = 2/5) and at the steepest softening (x⁶ = 2/11)
X_PEAK = (2.0 / 5.0) ** (1.0 / 6.0)
X_STEEP = (2.0 / 11.0) ** (1.0 / 6.0)


def _lj(z, w, z0):
    """(V, T_n, dT_n/dΔn) of the 9-3 wall at distances z > 0 (module docstring)."""
    x3 = (z0 / z) ** 3
    x9 = x3 * x3 * x3
    return w * (0.5 * x9 - 1.5 * x3), 4.5 * w / z * (x3 - x9), 9.0 * w / (z * z) * (5.0 * x9 - 2.0 * x3)


def _tangent_slope(z, w, z0):
    """d²T_n/dΔn² (Pa/m²) of the 9-3 wall at z > 0: −(9w/(z0² z)) (55x¹¹ − 10x⁵)."""
    x = z0 / z
    return -9.0 * w / (z0 * z0 * z) * (55.0 * x**11 - 10.0 * x**5)


@dataclass(frozen=True)
class Lj93Wall:
    """The LJ 9-3 wall (module docstring): work_of_adhesion w (J/m²), range_length z0 (m), the scene's contact rule."""

    work_of_adhesion: float
    range_length: float
    contact_tolerance: float = 1e-3
    contact_rule: str = "traction-tolerance"
    rule_gap: float | None = None
    core: tuple = field(init=False, repr=False, compare=False)

    name: ClassVar[str] = "LJ 9-3 wall"
    description: ClassVar[str] = "Lennard-Jones 9-3 wall (w, z0; Δn from the equilibrium distance z0)"
    constraint: ClassVar[bool] = False
    adhesive: ClassVar[bool] = True
    tangential: ClassVar[bool] = False
    has_potential: ClassVar[bool] = True
    nodal_form: ClassVar[None] = None
    curvature_scale: ClassVar[None] = None

    def __post_init__(self):
        for key in ("work_of_adhesion", "range_length"):
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"interface.{key} = {v!r}: must be a finite number > 0 (SI)")
        zc = CORE * self.range_length
        object.__setattr__(self, "core", (zc, *_lj(zc, self.work_of_adhesion, self.range_length),
                                          _tangent_slope(zc, self.work_of_adhesion, self.range_length)))

    # -- the equations ----------------------------------------------------------------------------------------
    def _evaluate(self, delta_n):
        z = self.range_length + np.asarray(delta_n, dtype=float)
        zc, _, tc, kc, jc = self.core
        v, t, k = _lj(np.maximum(z, zc), self.work_of_adhesion, self.range_length)
        d = np.minimum(z - zc, 0.0)  # the cubic continuation inside the core (0 outside it)
        return (v + (tc + (0.5 * kc + jc * d / 6.0) * d) * d, t + (kc + 0.5 * jc * d) * d,
                np.where(z < zc, kc + jc * d, k))

    def potential(self, delta_n):
        """V(Δn) (J/m²)."""
        return self._evaluate(delta_n)[0]

    def tractions(self, delta_n, delta_t=None):
        """(T_n, T_t) in Pa: the wall's traction, and 0."""
        return self._evaluate(delta_n)[1], 0.0

    def tangent(self, delta_n, delta_t=None):
        """(∂Tn/∂Δn, 0, 0, 0) in Pa/m."""
        return self._evaluate(delta_n)[2], 0.0, 0.0, 0.0

    def check_gaps(self, delta_n):
        """Every finite gap is in range (the core's continuation); a non-finite one raises."""
        if np.size(delta_n) and not np.all(np.isfinite(delta_n)):
            raise CompressionOverflowError("non-finite normal gap passed to the LJ 9-3 wall")

    # -- the scalars of the law protocol ----------------------------------------------------------------------
    @property
    def length_scale(self):
        """z0 (m)."""
        return self.range_length

    @property
    def length_normal(self):
        """z0 (m), the normal length of the resolution and start checks."""
        return self.range_length

    @property
    def initial_stiffness(self):
        """(k_t, k_n) = (0, 27 w/z0²) (Pa/m)."""
        return 0.0, 27.0 * self.work_of_adhesion / self.range_length**2

    @property
    def peak_traction(self):
        """(27/10)(w/z0) x_p⁴ (Pa), at z = z0/x_p."""
        return 2.7 * self.work_of_adhesion / self.range_length * X_PEAK**4

    @property
    def steepest_softening(self):
        """(108/11)(w/z0²) x_s⁵ (Pa/m), at z = z0/x_s."""
        return 108.0 / 11.0 * self.work_of_adhesion / self.range_length**2 * X_STEEP**5

    def reference_traction(self, contact_modulus):
        """peak_traction (Pa): a flat profile's residual scale."""
        return self.peak_traction

    def _tail_gap(self, traction):
        """Δn (m) beyond the peak where T_n = traction (0 < traction < peak_traction)."""
        w, z0 = self.work_of_adhesion, self.range_length
        z_hi = 1.01 * (4.5 * w * z0**3 / traction) ** 0.25  # T_n < 9w z0³/(2z⁴): below `traction` beyond (4.5 w z0³/t)^¼
        z = brentq(lambda s: float(_lj(s, w, z0)[1]) - traction, z0 / X_PEAK, max(z_hi, z0 / X_PEAK),
                   xtol=1e-15 * z0, rtol=4 * np.finfo(float).eps)
        return z - z0

    def far_reach(self, traction):
        """s_c: |T_n| ≤ traction (Pa) for Δn ≥ s_c z0 (the tail falls monotonically beyond the peak)."""
        if not traction > 0:
            return np.inf
        if traction >= self.peak_traction:
            return 1.0 / X_PEAK - 1.0
        return self._tail_gap(traction) / self.range_length

    def jump_in_separation(self, stiffness):
        """δ_jump (m) of a flat surface on a spring k (Pa/m): Δ* + T_n(Δ*)/k at the Δ* beyond the steepest point
        where dT_n/dΔn = −k (`gfmd_contact.core.laws.jump_in_separation`'s construction); 0 if k ≥ steepest."""
        if stiffness >= self.steepest_softening or stiffness <= 0:
            return 0.0
        w, z0 = self.work_of_adhesion, self.range_length
        z_hi = 1.01 * (18.0 * w * z0**3 / stiffness) ** 0.2  # dT_n/dΔn > −18 w z0³/z⁵: above −k beyond (18 w z0³/k)^⅕
        z = brentq(lambda s: float(_lj(s, w, z0)[2]) + stiffness, z0 / X_STEEP, max(z_hi, z0 / X_STEEP),
                   xtol=1e-15 * z0, rtol=4 * np.finfo(float).eps)
        return z - z0 + float(_lj(z, w, z0)[1]) / stiffness

    # -- the contact rule and the tangential unknowns ---------------------------------------------------------
    @property
    def contact_gap(self):
        """The rule's gap threshold (m): Δtol (traction-tolerance), rule_gap ("gap"), None ("compressive")."""
        if self.contact_rule == "gap":
            return self.rule_gap
        if self.contact_rule == "compressive":
            return None
        return self._tail_gap(self.contact_tolerance * np.e * self.peak_traction)

    def in_contact(self, gap, traction_z):
        """Nodes with Δn ≤ contact_gap, or −t_z > 0 where contact_gap is None."""
        threshold = self.contact_gap
        if threshold is None:
            return -np.asarray(traction_z) > 0.0
        return np.asarray(gap) <= threshold

    def needs_tangential(self, material):
        return False

    def tangential_reason(self, material):
        return "LJ 9-3 wall: frictionless (T_t ≡ 0), u_x decouples"

    def forced_tangential_reason(self):
        return None  # the scene refuses solver.unknowns = "coupled" for it

    def normal_only(self):
        return self


def _build(interface, work_normal, work_tangential, tangential, scene=None):
    """The registry's builder: the wall from interface.work_of_adhesion, interface.range_length and the rule."""
    if tangential:
        raise ValueError("the LJ 9-3 wall is frictionless and normal-only: no tangential unknowns")
    p, i = dict(interface.parameters), interface
    return Lj93Wall(work_of_adhesion=p["work_of_adhesion"], range_length=p["range_length"],
                    contact_tolerance=i.contact_tolerance, contact_rule=i.contact_rule,
                    rule_gap=i.contact_gap * i.length_normal if i.contact_rule == "gap" else None)


#: the law of this module as the scene names it (`gfmd_contact.core.law_registry`)
SCENE_LAWS = {"lj93": SceneLaw(_build, keys=(
    LawKey("work_of_adhesion", "J/m²", "the work to separate the interface from its equilibrium, w"),
    LawKey("range_length", "m", "the wall's equilibrium distance z0, which sets the interaction range")))}
