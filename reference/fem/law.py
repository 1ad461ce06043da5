"""The FE reference's own cohesive-zone law (seed Eqs. 2–3), written from the seed paper.

Independent of `gfmd_contact.core.laws` on purpose: the FE cross-checks GFMD, so it evaluates the
interface law with its own code (a unit test, tests/test_fem_law.py, compares the two
pointwise). Only the scene's numbers are shared.

Units: SI (see `gfmd_contact.core.conventions`). Gaps Δn = z_ind − u_z and Δt = −u_x (m), lengths
δn, δt (m), works of separation φn, φt (J/m²), tractions (Pa), T_n > 0 tensile, acting on
the body as t_z = T_n, t_x = T_t (reference-formulas §0).

    coupled (seed Eq. 2):  T_n = (φn/δn)(Δn/δn) e^{−Δn/δn} e^{−Δt²/δt²}
                           T_t = 2(φt/δt)(Δt/δt) e^{−Δn/δn} e^{−Δt²/δt²}
    normal only (Eq. 3):   T_n = (φn/δn)(Δn/δn) e^{−Δn/δn}

with φn = φn* δn E and φt = c φn* δt E (seed §2.1: φn* = φn/(δn E), c = φt*/φn*).

A law the FE has no implementation of (a user-defined law, interface.law = "user"; a law added to the core's
`gfmd_contact.core.law_registry`) has nothing to be independent from: the FE evaluates it through the law protocol
(`LawZone`), which answers what `CohesiveZone` answers for the normal law. The FE's built-in laws stay its own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

#: most negative Δn/δn evaluated: e^{700} is still finite in double precision, e^{710} is not
LARGEST_OVERLAP = 600.0


class LawRangeError(FloatingPointError):
    """A normal gap so compressive (or not finite) that the exponential would overflow."""


@dataclass(frozen=True)
class CohesiveZone:
    """The seed's CZ law with its four parameters (φn, δn, φt, δt), SI."""

    phi_n: float
    delta_n: float
    phi_t: float = 0.0
    delta_t: float = 1.0

    @classmethod
    def from_scene(cls, scene):
        """φn, φt from the scene's dimensionless works of separation (seed §2.1)."""
        i, youngs = scene.interface, scene.material.youngs_modulus
        return cls(phi_n=i.phi_n_star * i.length_normal * youngs, delta_n=i.length_normal,
                   phi_t=i.tangential_ratio * i.phi_n_star * i.length_tangential * youngs,
                   delta_t=i.length_tangential)

    def _normal_scaled(self, gap_n):
        """Δn/δn, refusing gaps beyond the exponential's range."""
        s = np.asarray(gap_n, dtype=float) / self.delta_n
        if s.size and not (np.all(np.isfinite(s)) and s.min() >= -LARGEST_OVERLAP):
            raise LawRangeError(f"normal gap down to {np.min(s):.4g} δn: outside the law's range "
                                f"(Δn ≥ −{LARGEST_OVERLAP:g} δn); the iterate diverged")
        return s

    # -- Eq. 3: normal only ------------------------------------------------------------------
    def normal(self, gap_n):
        """T_n(Δn) of Eq. 3 (Pa)."""
        s = self._normal_scaled(gap_n)
        return self.phi_n / self.delta_n * s * np.exp(-s)

    def normal_slope(self, gap_n):
        """dT_n/dΔn of Eq. 3 (Pa/m): (φn/δn²)(1 − s) e^{−s}, s = Δn/δn."""
        s = self._normal_scaled(gap_n)
        return self.phi_n / self.delta_n**2 * (1.0 - s) * np.exp(-s)

    def normal_potential(self, gap_n):
        """V(Δn) with dV/dΔn = T_n and V(∞) = 0: −φn (1 + s) e^{−s} (J/m²)."""
        s = self._normal_scaled(gap_n)
        return -self.phi_n * (1.0 + s) * np.exp(-s)

    # -- Eq. 2: coupled ------------------------------------------------------------------------
    def coupled(self, gap_n, gap_t):
        """(T_n, T_t) of Eq. 2 (Pa)."""
        s = self._normal_scaled(gap_n)
        r = np.asarray(gap_t, dtype=float) / self.delta_t
        decay = np.exp(-s) * np.exp(-r * r)
        return self.phi_n / self.delta_n * s * decay, 2.0 * self.phi_t / self.delta_t * r * decay

    def coupled_slopes(self, gap_n, gap_t):
        """(∂T_n/∂Δn, ∂T_n/∂Δt, ∂T_t/∂Δn, ∂T_t/∂Δt) of Eq. 2 (Pa/m); ∂T_n/∂Δt ≠ ∂T_t/∂Δn."""
        s = self._normal_scaled(gap_n)
        r = np.asarray(gap_t, dtype=float) / self.delta_t
        decay = np.exp(-s) * np.exp(-r * r)
        a = self.phi_n / self.delta_n  # T_n = a s decay
        b = 2.0 * self.phi_t / self.delta_t  # T_t = b r decay
        # d(decay)/dΔn = −decay/δn, d(decay)/dΔt = −2 r decay/δt
        return (a * (1.0 - s) * decay / self.delta_n,
                a * s * (-2.0 * r) * decay / self.delta_t,
                -b * r * decay / self.delta_n,
                b * (1.0 - 2.0 * r * r) * decay / self.delta_t)

    @property
    def peak_traction(self):
        """φn/(e δn) (Pa): the flat profile's residual scale."""
        return self.phi_n / (np.e * self.delta_n)

    # -- the seed's contact rule -------------------------------------------------------------------
    def contact_gap(self, tolerance):
        """Δtol (m): the gap on the decaying branch (Δn > δn) where T_n = tolerance·φn/δn (Eq. 3).

        Nodes with Δn ≤ Δtol are in contact (those under tension above the tolerance and all
        compressed ones). s e^{−s} = tolerance is solved by bracketing on (1, 800).
        """
        if not 0.0 < tolerance < np.exp(-1.0):
            raise ValueError(f"contact tolerance {tolerance!r} must lie in (0, 1/e), the peak of s e^(-s)")
        s = brentq(lambda v: v * np.exp(-v) - tolerance, 1.0, 800.0, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        return s * self.delta_n


class LawZone:
    """A law the FE has no implementation of (a user law, `gfmd_contact.core.user_law`; a law added to
    `gfmd_contact.core.law_registry`, such as the LJ 9-3 wall), normal-only with a potential, as the FE's Newton sees
    a law: T_n, dT_n/dΔn, V, through the law protocol (`gfmd_contact.core.law_protocol`).

    delta_n is the law's length (the Newton step limit 0.5 δn), phi_n = e·peak_traction·length so that
    φn/(e δn) is its peak traction and φn/δn² a stiffness scale (pseudo-transient continuation's mass).
    """

    def __init__(self, law):
        if law.tangential or law.constraint or not law.has_potential:
            raise ValueError(f"the FE solves normal-only laws with a potential through the law protocol, not the "
                             f"{law.name}")
        self.law = law
        self.delta_n = law.length_scale
        self.phi_n = np.e * law.peak_traction * law.length_scale
        self.phi_t, self.delta_t = 0.0, 1.0

    @property
    def peak_traction(self):
        return self.law.peak_traction

    def normal(self, gap_n):
        return self.law.tractions(gap_n)[0]

    def normal_slope(self, gap_n):
        return self.law.tangent(gap_n)[0]

    def normal_potential(self, gap_n):
        return self.law.potential(gap_n)

    def contact_gap(self, tolerance):
        """Δtol (m) of the law at this tolerance (its traction-tolerance rule: T_n = tolerance·e·peak_traction)."""
        import dataclasses
        return dataclasses.replace(self.law, contact_tolerance=tolerance, contact_rule="traction-tolerance").contact_gap
