"""Frictionless, non-adhesive hard wall on the condensed FE surface.

Units: SI (see `gfmd_contact.core.conventions`). The linear cell is condensed once onto the
normal surface displacements u_z (`Cell.schur(("z",))`: u_x of the surface is
free, t_x = 0, the interior follows linearly). Each load step is the convex QP

    min ½ uᵀ S u   subject to   u_i ≤ z_ind,i   (Δn = z_ind − u_z ≥ 0)

at every surface point i (P2: vertices and facet midpoints, z_ind at the
midpoints from the band-limited interpolant of h, as `reference.fem.solver`).
KKT: S u + μ = 0, μ ≥ 0 (wall force per unit length out of plane, N/m),
Δn ≥ 0, μ_i Δn_i = 0. The contact traction on the body at surface point i is
t_z = −μ_i/W_i (W the FacetBasis nodal weights, m), so −t_z ≥ 0 only where
Δn = 0 (gfmd_contact.core.conventions "Hard wall"). On the N GFMD nodes the Result reports
t_z = −(nodal wall force)/l, the P2 midpoint forces lumped onto their vertices
(`HardWallProblem.node_traction`), so that p = −⟨t_z⟩ is the exact Σμ/L.

Solver: primal–dual active set (Hintermüller, Ito & Kunisch 2003, a semismooth
Newton method for the complementarity function μ − max(0, μ + c(u − z))), on
the compliance C = S⁻¹ (factorised once per run): for an active set A,

    μ_A = −C_AA⁻¹ z_A,   μ_I = 0,   u = −C μ,

then A ← {i : μ_i + c_i (u_i − z_i) > 0} with c_i = S_ii (N/m² per m); stop when A
repeats. Each iteration costs one |A|×|A| Cholesky, so partial contact is cheap.
Each step is warm-started from the previous step's (u, μ). A repeated
(cycling) active set, which PDAS does not exclude for a general SPD S, falls
back to the dual bound-constrained least-squares problem (Lawson–Hanson NNLS,
finite termination) and is listed in `Result.messages`.

Stored per recorded step k (scene.output.field_steps), besides the fields on the
N nodes: `Result.solutions[k]` = u, the surface u_z at all surface points (the
unknowns of the condensed problem, the same kind of vector the cohesive FE
stores: `problem.solve_interior(u)` gives every DOF, which `reference.fem.export`
writes), and `Result.wall_forces[k]` = μ (N/m). z_ind of step k is
`problem.indenter(δ0, U_k)`. Every step's pressure from the nodal reaction forces, −Σ (S u)_z / L
(= Σμ/L at equilibrium), is in `Result.diagnostics["reaction_pressure"]`.

Residual reported per step (dimensionless, / p_ref, p_ref = E* ḡ as GFMD):
max over the points of |S u + μ|/W, max(0, −μ)/W and max(0, u − z)·S_ii/W.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.optimize

from gfmd_contact.core.ramp import StepSolution

from .assembly import build_cell
from .geometry import fourier_interpolate, surface_indenter  # the FE's own z_ind (P2 midpoints: Fourier interpolant)
from .observables import hard_wall_observables, rms_gradient


class HardWallProblem:
    """Condensed normal surface system of one scene for the hard wall (see module docstring).

    scene: a hard-wall `gfmd_contact.core.scene.Scene` with finite material.thickness; h: the
    profile (m) on the N nodes; order: 1 (P1) or 2 (P2).
    """

    def __init__(self, scene, h, order=2, mesh_kw=None):
        m = scene.material
        if m.half_plane:
            raise ValueError("the FE reference models a finite layer only: set material.thickness (e.g. 2 L)")
        if scene.interface.law != "hard-wall":
            raise ValueError(f"HardWallProblem needs interface.law = 'hard-wall', got {scene.interface.law!r}")
        self.scene = scene
        self.cell = build_cell(scene.surface.nodes, scene.surface.length, m.thickness, m.youngs_modulus,
                               m.poisson_ratio, order=order, **(mesh_kw or {}))
        self.S, self.solve_interior = self.cell.schur(("z",))
        self.ns = self.cell.surface_x.size
        self.w = self.cell.weights
        self.h_surface = fourier_interpolate(h, self.ns // h.size)
        self.h_min = float(np.min(h))  # nodal min: z_ind at the vertices is exactly GFMD's
        g = rms_gradient(h, scene.surface.spacing)
        self.p_ref = m.contact_modulus * g if g > 0 else m.contact_modulus
        self.c = np.diag(self.S).copy()  # PDAS complementarity scale (N/m per m)
        try:
            chol = scipy.linalg.cho_factor(self.S, check_finite=False)
        except scipy.linalg.LinAlgError as exc:
            raise RuntimeError(f"surface stiffness S is not positive definite ({exc}): mesh or material "
                               "invalid") from exc
        self.C = scipy.linalg.cho_solve(chol, np.eye(self.ns), check_finite=False)
        self.C = 0.5 * (self.C + self.C.T)

    def node_traction(self, mu):
        """t_z at the N GFMD nodes (Pa): −(nodal wall force)/l, as GFMD's nodal tractions.

        P1: −μ/W (W = l). P2: each facet midpoint's force goes to its vertices, half
        each, or all to the one vertex in contact when only one is, so that the mean
        over the nodes is the exact mean pressure Σμ/L and a node counts as in contact
        (−t_z > 0) only if it touches the wall or a contact lies between two free
        vertices. (The vertex value μ/W alone, Simpson weight l/3, would drop the
        midpoint forces: its node mean missed Westergaard's p̄ by 3e-3 p* at N = 64,
        against 4e-5 lumped.)
        """
        vp = self.cell.vertex_points
        spacing = self.scene.surface.spacing
        if vp.size == self.ns:
            return -mu / self.w
        force = mu[vp].copy()
        mid = mu[vp + 1]  # midpoint between vertex j and j + 1 (periodic)
        left_on, right_on = force > 0, np.roll(force > 0, -1)
        to_left = np.where(left_on == right_on, 0.5, np.where(left_on, 1.0, 0.0)) * mid
        force += to_left
        force += np.roll(mid - to_left, 1)
        return -force / spacing

    def indenter(self, initial_separation, displacement):
        """z_ind = h − min_nodes h + δ0 − U (m) at all surface points (gfmd_contact.core.conventions)."""
        return surface_indenter(self.h_surface, self.h_min, initial_separation, displacement)

    def state(self, active, z_ind):
        """(u, μ) for the active set `active` (bool, surface points): μ_A = −C_AA⁻¹ z_A, u = −C μ."""
        mu = np.zeros(self.ns)
        if active.any():
            idx = np.flatnonzero(active)
            c_aa = self.C[np.ix_(idx, idx)]
            mu[idx] = -scipy.linalg.solve(c_aa, z_ind[idx], assume_a="pos", check_finite=False)
        return -self.C @ mu, mu

    def residual(self, u, mu, z_ind):
        """KKT residual (dimensionless, / p_ref): equilibrium, wall tension and penetration."""
        eq = np.abs(self.S @ u + mu) / self.w
        tension = np.maximum(-mu, 0.0) / self.w
        penetration = np.maximum(u - z_ind, 0.0) * self.c / self.w
        return float(max(eq.max(), tension.max(), penetration.max()) / self.p_ref)

    def next_active(self, u, mu, z_ind, tie):
        """PDAS update A = {μ + c(u − z) > tie} (tie: N/m, separates round-off from contact)."""
        return mu + self.c * (u - z_ind) > tie

    def solve_step(self, z_ind, u0, mu0, tol, max_iter=100):
        """Equilibrium of one step from the previous (u0, μ0); returns (u, μ, iterations, converged, how)."""
        tie = tol * self.p_ref * float(np.min(self.w))
        active = self.next_active(u0, mu0, z_ind, tie)
        seen = set()
        it = 0
        for it in range(1, max_iter + 1):
            u, mu = self.state(active, z_ind)
            new = self.next_active(u, mu, z_ind, tie)
            if np.array_equal(new, active):
                return u, mu, it, self.residual(u, mu, z_ind) <= tol, "pdas"
            seen.add(active.tobytes())
            if new.tobytes() in seen:
                break
            active = new
        u, mu = self.dual_nnls(z_ind)
        why = "cycled" if it < max_iter else f"not settled in {max_iter} iterations"
        return u, mu, it + 1, self.residual(u, mu, z_ind) <= tol, f"nnls fallback (active set {why})"

    def dual_nnls(self, z_ind):
        """Dual min_{μ≥0} ½μᵀCμ + zᵀμ as NNLS ‖Rμ + R⁻ᵀz‖, C = RᵀR (finite termination); (u, μ)."""
        r = scipy.linalg.cholesky(self.C, lower=False, check_finite=False)
        rhs = -scipy.linalg.solve_triangular(r, z_ind, trans="T", check_finite=False)
        mu, _ = scipy.optimize.nnls(r, rhs, maxiter=50 * self.ns)
        return -self.C @ mu, mu


@dataclass
class HardWallCell:
    """One realization's FE hard-wall problem (see gfmd_contact.core.ramp for the protocol). The state is
    the stacked (u_z at the surface points, wall forces μ): the active set warm-starts from the
    previous step, never from an extrapolation (a constraint, not a smooth law)."""

    scene: object
    prob: HardWallProblem
    physics: object  # gfmd_contact.core.model.Model
    tolerance: float
    method: str
    model: str
    reasons: tuple
    diagnostics: dict
    extrapolate: bool = False

    def initial_state(self):
        return np.zeros((2, self.prob.ns))

    def observe(self, scene, h, gap, t_n):
        """p, a_rel, ḡ_r, ḡ of a step from the FE's own observables (contact: scene.interface.contact_rule;
        the seed's is the compressive nodes)."""
        self.diagnostics.setdefault("reaction_pressure", []).append(self._reaction)
        return hard_wall_observables(h, scene.surface.spacing, t_n, gap=gap, interface=scene.interface)

    def solve(self, displacement, guess, fallback):
        prob, vp = self.prob, self.prob.cell.vertex_points
        z_ind = prob.indenter(self.scene.loading.initial_separation, displacement)
        u, mu, its, ok, how = prob.solve_step(z_ind, guess[0], guess[1], self.tolerance)
        if not np.all(np.isfinite(u)):
            raise FloatingPointError(f"step at U = {displacement:.4g} m: non-finite hard-wall solution")
        res = prob.residual(u, mu, z_ind)
        gap = np.maximum(z_ind - u, 0.0)  # round-off penetration (≤ tol) shown as contact
        t_n = prob.node_traction(mu)
        self._reaction = float(-np.sum(prob.S @ u) / self.scene.surface.length)  # −Σ (S u)_z / L, recorded by observe()
        messages = (() if how == "pdas" else (how,)) + (() if ok else (f"not converged, KKT residual {res:.3g} p_ref",))

        def fields():
            ux = prob.solve_interior(u)[prob.cell.surface_dofs[0]]
            return {"u_z": u[vp].copy(), "u_x": ux[vp].copy(), "gap": gap[vp].copy(), "t_n": t_n.copy(),
                    "t_t": np.zeros(vp.size)}

        return StepSolution(state=np.vstack([u, mu]), converged=ok, iterations=its, residual=res, gap=gap[vp],
                            t_n=t_n, fields=fields, messages=messages,
                            keep={"solutions": u.copy(), "wall_forces": mu.copy()}, fallback=how != "pdas")
