"""Frictionless, non-adhesive hard wall on the condensed 3-D FE surface: primal–dual active set.

Units: SI (see `gfmd_contact.core.conventions`). Each load step is the convex QP

    min ½ uᵀ S u   subject to   u_i ≤ z_ind,i   (Δn = z_ind − u_z ≥ 0)

on the Nx·Ny surface nodes (S: `assembly.Cell3D.stiffness`, N/m). KKT: S u + μ = 0, μ ≥ 0 (the
wall's nodal force, N), Δn ≥ 0, μ_i Δn_i = 0; the nodal traction on the body is t_z = −μ_i/W_i.
Primal–dual active set (Hintermüller, Ito & Kunisch 2003) on the compliance C = S⁻¹ (one dense
Cholesky per run): for an active set A, μ_A = −C_AA⁻¹ z_A, μ_I = 0, u = −C μ; then
A ← {μ + c(u − z) > tie}, c = diag S; stop when A repeats. Warm-started from the previous step.
A cycling active set falls back to the dual NNLS (Lawson–Hanson, finite termination).

The residual (dimensionless, / p_ref): max over the nodes of |S u + μ|/W, max(0, −μ)/W and
max(0, u − z)·c/W.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.optimize


class HardWall:
    """The hard-wall problem on a condensed cell (S, W) with reference pressure p_ref (Pa)."""

    def __init__(self, stiffness, weights, p_ref):
        self.S, self.w, self.p_ref = stiffness, weights, p_ref
        self.c = np.diag(stiffness).copy()
        n = stiffness.shape[0]
        self.C = scipy.linalg.cho_solve(scipy.linalg.cho_factor(stiffness), np.eye(n))
        self.C = 0.5 * (self.C + self.C.T)

    def state(self, active, z_ind):
        """(u, μ) of the active set `active` (bool)."""
        mu = np.zeros(z_ind.size)
        if active.any():
            idx = np.flatnonzero(active)
            mu[idx] = -scipy.linalg.solve(self.C[np.ix_(idx, idx)], z_ind[idx], assume_a="pos")
        return -self.C @ mu, mu

    def residual(self, u, mu, z_ind):
        eq = np.abs(self.S @ u + mu) / self.w
        tension = np.maximum(-mu, 0.0) / self.w
        penetration = np.maximum(u - z_ind, 0.0) * self.c / self.w
        return float(max(eq.max(), tension.max(), penetration.max()) / self.p_ref)

    def solve(self, z_ind, u0, mu0, tol, max_iter=200):
        """(u, μ, iterations, converged, how) from the previous step's (u0, μ0)."""
        tie = tol * self.p_ref * float(np.min(self.w))
        active = mu0 + self.c * (u0 - z_ind) > tie
        seen = set()
        for it in range(1, max_iter + 1):
            u, mu = self.state(active, z_ind)
            new = mu + self.c * (u - z_ind) > tie
            if np.array_equal(new, active):
                return u, mu, it, self.residual(u, mu, z_ind) <= tol, "pdas"
            seen.add(active.tobytes())
            if new.tobytes() in seen:
                break
            active = new
        r = scipy.linalg.cholesky(self.C, lower=False)
        rhs = -scipy.linalg.solve_triangular(r, z_ind, trans="T")
        mu, _ = scipy.optimize.nnls(r, rhs, maxiter=50 * z_ind.size)
        u = -self.C @ mu
        return u, mu, it + 1, self.residual(u, mu, z_ind) <= tol, "nnls fallback (active set cycled)"
