"""The 3-D FE's own normal cohesive-zone law (seed Eq. 3) and the seed's contact gap, from the paper.

Units: SI (see `gfmd_contact.core.conventions`). Independent of `gfmd_contact.core.laws` (and of `reference.fem.law`):
only the numbers are shared. Gap Δn = z_ind − u_z (m), T_n > 0 tensile, acting on the body as t_z = T_n:

    T_n(Δn) = (φn/δn) s e^{−s},   s = Δn/δn   (seed Eq. 3),   φn = φn* δn E   (seed §2.1)
    V(Δn)   = −φn (1 + s) e^{−s}  (J/m², dV/dΔn = T_n, V(∞) = 0, V(0) = −φn)
    dT_n/dΔn = (φn/δn²)(1 − s) e^{−s}

A law it has no implementation of (a user law, a law added to `gfmd_contact.core.law_registry` such as the LJ 9-3
wall) it evaluates through the law protocol (`LawZone`): nothing to be independent from.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

#: most compressive s = Δn/δn evaluated (e^{600} is finite in double precision)
LARGEST_OVERLAP = 600.0


class GapRangeError(FloatingPointError):
    """A gap so compressive (or not finite) that e^{−s} would overflow: the iterate diverged."""


@dataclass(frozen=True)
class NormalCohesiveZone:
    """T_n(Δn) of seed Eq. 3 with work of separation φn (J/m²) and length δn (m)."""

    phi_n: float
    delta_n: float

    def __post_init__(self):
        for key, v in (("phi_n", self.phi_n), ("length_normal", self.delta_n)):
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"{key} = {v!r}: the cohesive law needs a finite positive value")

    @classmethod
    def from_dimensionless(cls, phi_n_star, length_normal, youngs_modulus):
        """φn = φn* δn E (seed §2.1)."""
        if not (np.isfinite(phi_n_star) and phi_n_star > 0):
            raise ValueError(f"phi_n_star = {phi_n_star!r}: the cohesive law needs a finite positive φn*")
        return cls(phi_n=phi_n_star * length_normal * youngs_modulus, delta_n=length_normal)

    def _s(self, gap):
        s = np.asarray(gap, dtype=float) / self.delta_n
        if s.size and not (np.all(np.isfinite(s)) and s.min() >= -LARGEST_OVERLAP):
            raise GapRangeError(f"gap down to {np.min(s):.4g} δn: outside the law's range (≥ −{LARGEST_OVERLAP:g} δn)")
        return s

    def traction(self, gap):
        """T_n (Pa)."""
        s = self._s(gap)
        return self.phi_n / self.delta_n * s * np.exp(-s)

    def slope(self, gap):
        """dT_n/dΔn (Pa/m)."""
        s = self._s(gap)
        return self.phi_n / self.delta_n**2 * (1.0 - s) * np.exp(-s)

    def potential(self, gap):
        """V(Δn) (J/m²)."""
        s = self._s(gap)
        return -self.phi_n * (1.0 + s) * np.exp(-s)

    def contact_gap(self, tolerance):
        """Δtol (m): the gap past the peak (s > 1) where T_n = tolerance·φn/δn (the seed's §2 contact rule)."""
        if not 0.0 < tolerance < np.exp(-1.0):
            raise ValueError(f"contact_tolerance = {tolerance!r}: must lie in (0, 1/e), the peak of s e^(-s)")
        return self.delta_n * brentq(lambda s: s * np.exp(-s) - tolerance, 1.0, 800.0, xtol=1e-15)


class LawZone:
    """A law the 3-D FE has no implementation of (a user law, a law added to `gfmd_contact.core.law_registry`),
    normal-only with a potential, as `NormalCohesiveZone` answers: through the law protocol
    (`gfmd_contact.core.law_protocol`), nothing to be independent from. delta_n is the law's length, phi_n =
    e·peak_traction·length (so that φn/(e δn) is its peak traction and φn/δn² a stiffness scale)."""

    def __init__(self, law):
        if law.tangential or law.constraint or not law.has_potential:
            raise ValueError(f"the 3-D FE solves normal-only laws with a potential, not the {law.name}")
        self.law, self.delta_n = law, law.length_scale
        self.phi_n = np.e * law.peak_traction * law.length_scale

    def _gap(self, gap):
        gap = np.asarray(gap, dtype=float)
        if gap.size and not np.all(np.isfinite(gap)):
            raise GapRangeError("non-finite gap: the iterate diverged")
        return gap

    def traction(self, gap):
        return self.law.tractions(self._gap(gap))[0]

    def slope(self, gap):
        return self.law.tangent(self._gap(gap))[0]

    def potential(self, gap):
        return self.law.potential(self._gap(gap))

    def contact_gap(self, tolerance):
        """Δtol (m) of the law's traction-tolerance rule at this tolerance."""
        import dataclasses
        return dataclasses.replace(self.law, contact_tolerance=tolerance, contact_rule="traction-tolerance").contact_gap
