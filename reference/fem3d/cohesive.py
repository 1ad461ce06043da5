"""Normal cohesive zone (seed Eq. 3) on the condensed 3-D FE surface: Newton with line search.

Units: SI (see `gfmd_contact.core.conventions`). Each load step minimises the energy per cell

    Π(u) = ½ uᵀ S u + Σ_i W_i V(Δn_i),   Δn = z_ind − u_z,

(nodal quadrature of the boundary term: the law at the Nx·Ny surface nodes, weights W = lx·ly,
GFMD's node collocation), i.e. solves R(u) = S u − W T_n(Δn) = 0 with the tangent
J = S + diag(W dT_n/dΔn). Newton with a dense Cholesky of J; where J is not positive definite
(the law's softening branch) the step is taken with J + σ diag(W φn/δn²), σ raised until the
Cholesky succeeds (so the direction descends Π and a converged point is a stable minimum); the
increment is scaled so that no node moves more than 0.5 max(δn, |Δn_i|) (a node cannot jump across
the law's well at Δn ~ δn in one iteration; nodes far out or deep in move freely), then backtracking (Armijo on
Π, or a decrease of ‖R/W‖ where Π is flat to round-off). Warm start: the previous step's u moved
along the path's tangent du/dU = −J⁻¹ W dT_n/dΔn (`path_tangent`, first order in the step, the
same basin), kept if its energy is not above the plain previous u's. The residual reported is
max_i |R_i/W_i| / p_ref (a traction relative to p_ref = E* ḡ), as in GFMD.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg

from .law import GapRangeError


class CohesiveSurface:
    """The normal-CZ problem on a condensed cell (S, W), law `law`, reference pressure p_ref (Pa)."""

    def __init__(self, stiffness, weights, law, p_ref):
        self.S, self.w, self.law, self.p_ref = stiffness, weights, law, p_ref
        self.mass = weights * law.phi_n / law.delta_n**2  # scale of the shift (N/m)

    def residual(self, u, z_ind):
        return self.S @ u - self.w * self.law.traction(z_ind - u)

    def energy(self, u, z_ind):
        return 0.5 * u @ (self.S @ u) + self.w @ self.law.potential(z_ind - u)

    def measure(self, r):
        return float(np.max(np.abs(r / self.w)) / self.p_ref)

    def direction(self, u, z_ind, r):
        """(du, shifted): the Newton step, shifted until J + σM is positive definite."""
        J = self.S + np.diag(self.w * self.law.slope(z_ind - u))
        sigma, shifted = 0.0, False
        for _ in range(60):
            try:
                chol = scipy.linalg.cho_factor(J + sigma * np.diag(self.mass) if sigma else J)
                break
            except np.linalg.LinAlgError:
                sigma, shifted = (1e-3 if sigma == 0 else 4 * sigma), True
        else:
            raise np.linalg.LinAlgError("no positive definite shifted tangent")
        du = -scipy.linalg.cho_solve(chol, r)
        allowed = 0.5 * np.maximum(self.law.delta_n, np.abs(z_ind - u))
        worst = np.max(np.abs(du) / allowed)
        return (du / worst if worst > 1 else du), shifted

    def path_tangent(self, u, z_ind):
        """du/dU at an equilibrium u (z_ind = z0 − U): J du/dU = −W dT_n/dΔn; None if J is not positive definite."""
        slope = self.w * self.law.slope(z_ind - u)
        try:
            chol = scipy.linalg.cho_factor(self.S + np.diag(slope))
        except np.linalg.LinAlgError:
            return None
        return -scipy.linalg.cho_solve(chol, slope)

    def warm_start(self, u, tangent, step, z_ind):
        """u + step·tangent if its energy at the new z_ind is not above u's (and it is in the law's range), else u."""
        if tangent is None:
            return u
        guess = u + step * tangent
        try:
            return guess if self.energy(guess, z_ind) <= self.energy(u, z_ind) else u
        except GapRangeError:
            return u

    def solve(self, u, z_ind, tol, max_iter=200):
        """(u, residual, iterations, converged) from the guess u."""
        try:
            r = self.residual(u, z_ind)
            e = self.energy(u, z_ind)
        except GapRangeError:
            return u, math.inf, 0, False
        for it in range(max_iter + 1):
            res = self.measure(r)
            if res <= tol:
                return u, res, it, True
            if it == max_iter:
                break
            du, _ = self.direction(u, z_ind, r)
            slope = r @ du
            norm = np.linalg.norm(r / self.w)
            alpha = 1.0
            for _ in range(40):
                trial = u + alpha * du
                try:
                    rt, et = self.residual(trial, z_ind), self.energy(trial, z_ind)
                except GapRangeError:
                    alpha *= 0.5
                    continue
                if et <= e + 1e-4 * alpha * slope or (et <= e + 1e-13 * abs(e)
                                                        and np.linalg.norm(rt / self.w) < norm):
                    break
                alpha *= 0.5
            else:
                return u, res, it, False
            u, r, e = trial, rt, et
        return u, self.measure(r), max_iter, False
