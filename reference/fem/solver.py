"""Nonlinear surface solve of the FE cell and the displacement-controlled load ramp.

Units: SI (see `gfmd_contact.core.conventions`). Two linear paths, chosen by
`run_realization(linear=...)`: "dense" condenses the linear interior once onto
the top surface (dense Schur complement S from `reference.fem.assembly`);
"sparse" / "sparse-lagged" (`reference.fem.sparse`) never forms S and solves
the full reduced system with SuperLU per Newton iteration (optionally a lagged
factorisation as GMRES preconditioner); "auto" takes dense up to 2048 surface
unknowns (the measured break-even, docs/design/performance.md).
Both paths share the algorithms below unchanged. Each load step solves the
surface equilibrium

    R(u) = S u − W t(u) = 0,   t_z = T_n(Δn, Δt), t_x = T_t(Δn, Δt),
    Δn = z_ind − u_z, Δt = −u_x,

with W the nodal quadrature weights of a FacetBasis load vector (P1: l per
node, as GFMD's nodal forces; P2: Simpson weights l/3 at vertices, 2l/3 at
facet midpoints, where z_ind uses the band-limited (Fourier) interpolant of
h). Newton with the consistent (for the coupled law non-symmetric) tangent,
each iteration's surface-displacement increment limited to 0.5 δn (0.5 δt
tangentially), then backtracking on ‖R‖. If Newton fails, or converges to an
unstable equilibrium (`locally_stable`: normal law, tangent not positive
definite; coupled law, an eigenvalue of W⁻¹J with Re λ ≤ 0), e.g. at a jump
into or out of contact, the step falls back: for the normal law (a potential)
to a trust-region minimisation of the FE energy (`descend`), for the coupled
law to pseudo-transient continuation (shifted Newton, residual decrease), each
polished by Newton and accepted only at a locally stable state; those steps
are listed in `Result.messages`, a step that does not converge is reported so. The residual reported is
max_i |R_i/W_i| / p_ref (a traction relative to p_ref = E* ḡ), as in GFMD.

`quadrature="gauss"` (`reference.fem.quadrature`) replaces W t(u) by the
consistent Gauss–Legendre force Bᵀ(w_g ∘ T(Δ_g)) (tangent Bᵀ diag(w_g ∂T/∂Δ) B,
energy Σ w_g V(Δ_g)), with z_ind at the Gauss points from the Fourier
interpolant of h. Everything else is unchanged: the nodal weights W still scale
the residual measure, the continuation mass and the stability test (damping
W u̇ = −R), and the outputs are nodal, i.e. the fields t_n, t_t are T at the
GFMD nodes' gaps and p = −⟨t_z⟩ over the nodes (`FeCell.observe`, the FE's own
`reference.fem.observables`), for both quadratures, as for GFMD. The law is the FE's
own (`reference.fem.law`), not GFMD's. The FE's pressure from its own nodal reaction forces,
−Σ (S u)_z / L (`SurfaceProblem.reaction_pressure`), is kept per step in
`Result.diagnostics["reaction_pressure"]` (one value per curve row of a run that was not resumed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from gfmd_contact.core.ramp import StepSolution
from gfmd_contact.core import law_registry

from .assembly import build_cell
from .geometry import fourier_interpolate, surface_indenter
from .law import CohesiveZone, LawRangeError, LawZone
from .observables import cohesive_observables, rms_gradient
from .quadrature import fourier_evaluate, gauss_surface_quadrature

QUADRATURES = ("nodal", "gauss")  # boundary-term quadrature (module docstring)


def locally_stable(jacobian, weights, symmetric):
    """Local stability of an equilibrium of R(u) = S u − W t(u) = 0 from its tangent J = ∂R/∂u.

    jacobian: J (Pa: N/m of nodal force per m of displacement); weights: nodal
    quadrature weights W (m), one per unknown; symmetric: True when the law
    derives from a potential (normal law), so that J is symmetric.

    * Normal law: Π = ½uᵀSu + Σ W V(Δn) exists and J = ∇²Π; the equilibrium is
      a strict local minimum iff J is positive definite (Cholesky).
    * Coupled law (seed Eq. 2, no potential, J non-symmetric): there is no energy
      to minimise; the equilibrium is stable iff perturbations decay under the
      overdamped dynamics W u̇ = −R(u) (damping per unit surface, as in the
      quasi-static limit of GFMD's damped dynamics), i.e. iff every eigenvalue of
      W⁻¹J has a positive real part. A positive definite symmetric part of J is
      sufficient (Re λ = v*sym(W^-½JW^-½)v / v*v > 0) but not necessary: the coupled
      tangent's antisymmetric part makes sym(J) indefinite at stable states. So
      Cholesky of sym(J) is tried first (cheap); the eigenvalues (dense, O(n³),
      ≈ 20 solves: 13 s vs 0.7 s at n = 2048) are computed only when it fails.
    """
    try:
        scipy.linalg.cho_factor(0.5 * (jacobian + jacobian.T) if not symmetric else jacobian, check_finite=False)
        return True
    except scipy.linalg.LinAlgError:
        if symmetric:
            return False
    scaled = jacobian / np.sqrt(np.outer(weights, weights))  # W^-½ J W^-½, similar to W⁻¹J
    eigenvalues = scipy.linalg.eigvals(scaled, check_finite=False)
    return bool(np.all(np.isfinite(eigenvalues)) and np.min(eigenvalues.real) > 0.0)


class SurfaceProblem:
    """Condensed surface system of one scene (see module docstring).

    quadrature: "nodal" (lumped weights W, the default) or "gauss" (consistent
    Gauss–Legendre boundary term, `reference.fem.quadrature`).
    """

    linear_solver = "dense LU"

    def __init__(self, scene, h, order=2, mesh_kw=None, quadrature="nodal", tangential=None):
        if quadrature not in QUADRATURES:
            raise ValueError(f"quadrature = {quadrature!r}: one of {', '.join(map(repr, QUADRATURES))}")
        self.quadrature = quadrature
        m, i = scene.material, scene.interface
        if m.half_plane:
            raise ValueError(
                "the FE reference models a finite layer only: material.thickness = inf (half-plane) cannot be "
                f"meshed. Use a depth, e.g. material.thickness = {2 * scene.surface.length:g} m (D = 2L: the "
                "fundamental mode's compliance equals the half-plane's to ~1e-9), and run GFMD with the same depth.")
        if i.law in ("hard-wall", "cohesive-wall"):
            raise NotImplementedError(f"interface.law = {i.law!r}: SurfaceProblem solves the cohesive laws; the hard "
                                      "wall is reference.fem.hardwall (run_realization routes the walls)")
        self.scene = scene
        # u_x solved: the core's model choice (gfmd_contact.core.model) when given, else wherever c > 0
        self.tangential = i.tangential_ratio > 0 if tangential is None else bool(tangential)
        self.h_min = float(np.min(h))
        self.cell = build_cell(scene.surface.nodes, scene.surface.length, m.thickness, m.youngs_modulus,
                               m.poisson_ratio, order=order, **(mesh_kw or {}))
        comps = ("x", "z") if self.tangential else ("z",)
        self.S, self.solve_interior = self.condense(comps)
        self.ns = self.cell.surface_x.size
        self.h_surface = fourier_interpolate(h, self.ns // h.size)
        self.w = self.cell.weights
        # the FE's own law (reference.fem.law); a law it has none of through the law protocol (nothing to be
        # independent from: a user law's callables, a law added to the core's registry)
        self.law = CohesiveZone.from_scene(scene) if i.law == "cohesive" else LawZone(
            law_registry.entry(i.law).build(i, float("nan"), float("nan"), False, scene))
        self.phi_n, self.dn = self.law.phi_n, self.law.delta_n
        self.phi_t, self.dt = self.law.phi_t, self.law.delta_t
        g = rms_gradient(h, scene.surface.spacing)
        self.p_ref = m.contact_modulus * g if g > 0 else self.law.peak_traction
        self.wt = np.tile(self.w, 2 if self.tangential else 1)
        if quadrature == "gauss":
            self.gauss = gauss_surface_quadrature(self.cell.surface_x, scene.surface.length, order)
            self.h_gauss = fourier_evaluate(h, scene.surface.length, self.gauss.x)  # h at the Gauss points (m)

    # -- law -------------------------------------------------------------------------------
    def split(self, u):
        if self.tangential:
            return u[:self.ns], u[self.ns:]
        return np.zeros(self.ns), u

    def tractions(self, u, z_ind):
        """(t_x, t_z, Δn) at the surface points."""
        ux, uz = self.split(u)
        gap = z_ind - uz
        if self.tangential:
            tn, tt = self.law.coupled(gap, -ux)
        else:
            tn, tt = self.law.normal(gap), np.zeros(self.ns)
        return tt, tn, gap

    def law_gaps(self, u, z_ind):
        """(Δn, Δt) (m) where the boundary term evaluates the law: surface points (nodal) or Gauss points.

        z_ind: indenter at the surface points; z_ind − h_surface is a constant
        (`reference.fem.geometry.surface_indenter`), added to h at the Gauss points.
        """
        ux, uz = self.split(u)
        if self.quadrature == "nodal":
            return z_ind - uz, -ux
        b = self.gauss.interpolation
        z_gauss = self.h_gauss + float(np.mean(z_ind - self.h_surface))
        return z_gauss - b @ uz, -(b @ ux)

    def law_weights(self):
        """Quadrature weights (m) of the law points: W (nodal) or w_g (gauss)."""
        return self.w if self.quadrature == "nodal" else self.gauss.weights

    def to_surface(self, point_forces):
        """Nodal forces (N/m) from forces at the law points: identity (nodal) or Bᵀ (gauss)."""
        return point_forces if self.quadrature == "nodal" else self.gauss.interpolation.T @ point_forces

    def residual(self, u, z_ind):
        """R(u) = S u − f(u) (N/m per surface unknown), f the boundary-term nodal forces."""
        gap_n, gap_t = self.law_gaps(u, z_ind)
        w = self.law_weights()
        if self.tangential:
            tn, tt = self.law.coupled(gap_n, gap_t)
            f = np.concatenate([self.to_surface(w * tt), self.to_surface(w * tn)])
        else:
            f = self.to_surface(w * self.law.normal(gap_n))
        return self.S @ u - f

    def reaction_pressure(self, u):
        """Mean pressure from the FE's own nodal reaction forces, −Σ_i (S u)_z,i / L (Pa).

        S u is the elastic force the condensed body exerts at the surface points (the assembled K u at the
        surface with the interior eliminated; by global equilibrium of the periodic cell it equals the
        reaction at the bonded base). It involves the law only through the equilibrium solved, not through
        the nodal tractions the observable p = −⟨t_z⟩ averages: the two agree to the quadrature of the
        boundary term (P2: the Simpson midpoint forces the node mean omits) and the solver tolerance.
        """
        _, fz = self.split(self.S @ u)
        return float(-np.sum(fz) / self.scene.surface.length)

    def condense(self, comps):
        """(S, solve_interior) for the surface components `comps` (dense Schur complement, `Cell.schur`)."""
        return self.cell.schur(comps)

    def surface_tangent(self, u, z_ind):
        """Law part −∂f/∂u of the tangent as (rows, cols, values) in the unknowns' indexing (N/m²·m = Pa).

        (row, col) pairs are distinct. Nodal: diagonal (2×2 blocks per point for
        the coupled law); gauss: Bᵀ diag(w_g ∂T/∂Δ) B per block.
        """
        if self.quadrature == "gauss":
            return self._gauss_tangent(u, z_ind)
        ux, uz = self.split(u)
        gap = z_ind - uz
        idx = np.arange(self.ns)
        if self.tangential:
            nn, nt, tn_, tt_ = self.law.coupled_slopes(gap, -ux)
            # f_x = w T_t, f_z = w T_n; dΔn/du_z = −1, dΔt/du_x = −1; J = S − df/du
            rows = np.concatenate([idx, idx, self.ns + idx, self.ns + idx])
            cols = np.concatenate([idx, self.ns + idx, idx, self.ns + idx])
            return rows, cols, np.concatenate([self.w * tt_, self.w * tn_, self.w * nt, self.w * nn])
        return idx, idx, self.w * self.law.normal_slope(gap)

    def _gauss_tangent(self, u, z_ind):
        """`surface_tangent` for quadrature="gauss": blocks Bᵀ diag(w_g ∂T/∂Δ) B (Pa)."""
        gap_n, gap_t = self.law_gaps(u, z_ind)
        w, b = self.gauss.weights, self.gauss.interpolation
        if self.tangential:  # same block layout as the nodal coupled tangent: (x,x), (x,z), (z,x), (z,z)
            nn, nt, tn_, tt_ = self.law.coupled_slopes(gap_n, gap_t)
            blocks = {(0, 0): tt_, (0, 1): tn_, (1, 0): nt, (1, 1): nn}
        else:
            blocks = {(0, 0): self.law.normal_slope(gap_n)}
        rows, cols, values = [], [], []
        for (r, c), slope in blocks.items():
            block = (b.T @ sp.diags(w * slope) @ b).tocoo()
            block.sum_duplicates()
            rows.append(r * self.ns + block.row)
            cols.append(c * self.ns + block.col)
            values.append(block.data)
        return np.concatenate(rows), np.concatenate(cols), np.concatenate(values)

    def jacobian(self, u, z_ind, shift=None):
        """Tangent J = S − ∂(W t)/∂u (Pa), plus diag(shift) if given (pseudo-transient continuation)."""
        J = self.S.copy()
        rows, cols, values = self.surface_tangent(u, z_ind)
        J[rows, cols] += values  # (row, col) pairs are distinct
        if shift is not None:
            J[np.diag_indices_from(J)] += shift
        return J

    def solve_linear(self, J, rhs):
        """Solve J x = rhs for a tangent from `jacobian` (dense LU); raises LinAlgError if singular."""
        return scipy.linalg.solve(J, rhs, check_finite=False)

    def energy(self, u, z_ind):
        """Π = ½uᵀSu + Σ W V(Δn) (J/m; Σ w_g V(Δn_g) for gauss), normal law only."""
        gap_n, _ = self.law_gaps(u, z_ind)
        return 0.5 * u @ (self.S @ u) + self.law_weights() @ self.law.normal_potential(gap_n)

    def measure(self, r):
        return float(np.max(np.abs(r / self.wt)) / self.p_ref)

    def limit(self, du):
        """Scale du so that no surface increment exceeds 0.5 δn (0.5 δt for u_x)."""
        dux, duz = self.split(du)
        worst = max(np.max(np.abs(duz)) / (0.5 * self.dn),
                    np.max(np.abs(dux)) / (0.5 * self.dt) if self.tangential else 0.0)
        return du / worst if worst > 1 else du

    def stable(self, u, z_ind):
        """True if the equilibrium u is locally stable (see `locally_stable`)."""
        return locally_stable(self.jacobian(u, z_ind), self.wt, symmetric=not self.tangential)

    # -- solvers ---------------------------------------------------------------------------
    def _safe_residual(self, u, z_ind):
        try:
            r = self.residual(u, z_ind)
        except LawRangeError:
            return None
        return r if np.all(np.isfinite(r)) else None

    def newton(self, u, z_ind, tol, max_iter=60):
        r = self._safe_residual(u, z_ind)
        if r is None:
            return u, math.inf, 0, False
        it = 0
        for it in range(1, max_iter + 1):
            if self.measure(r) <= tol:
                return u, self.measure(r), it - 1, True
            J = self.jacobian(u, z_ind)
            try:
                du = self.limit(self.solve_linear(J, -r))
            except (scipy.linalg.LinAlgError, ValueError):
                return u, self.measure(r), it, False
            norm0 = np.linalg.norm(r / self.wt)
            alpha, accepted = 1.0, False
            for _ in range(30):
                trial = u + alpha * du
                rt = self._safe_residual(trial, z_ind)
                if rt is not None and np.linalg.norm(rt / self.wt) < (1 - 1e-4 * alpha) * norm0:
                    accepted = True
                    break
                alpha *= 0.5
            if not accepted:
                return u, self.measure(r), it, False
            u, r = trial, rt
        return u, self.measure(r), max_iter, self.measure(r) <= tol

    def ptc(self, u, z_ind, tol, max_iter=2000):
        """Pseudo-transient continuation (coupled law, no potential): (J + σ M) du = −R, σ adapted (SER),
        M = W·φn/δn², a step accepted while ‖R‖ grows less than 1.5×."""
        mass = self.wt * (self.phi_n / self.dn**2)
        sigma = 10.0
        r = self._safe_residual(u, z_ind)
        if r is None:
            return u, math.inf, 0, False
        for it in range(1, max_iter + 1):
            res = self.measure(r)
            if res <= tol:
                return u, res, it - 1, True
            J = self.jacobian(u, z_ind, shift=sigma * mass)
            try:
                du = self.limit(self.solve_linear(J, -r))
            except (scipy.linalg.LinAlgError, ValueError):
                sigma *= 10
                continue
            trial = u + du
            rt = self._safe_residual(trial, z_ind)
            if rt is not None and np.linalg.norm(rt / self.wt) < 1.5 * np.linalg.norm(r / self.wt):
                ratio = np.linalg.norm(rt / self.wt) / max(np.linalg.norm(r / self.wt), 1e-300)
                sigma = max(sigma * min(max(ratio, 0.1), 2.0), 1e-12)
                u, r = trial, rt
            else:
                sigma *= 4
        return u, self.measure(r), max_iter, self.measure(r) <= tol

    def descend(self, u, z_ind, tol, max_iter=1000):
        """Trust-region minimisation of Π (normal law): (J + σM) du = −R, M = W·φn/δn², σ from the ratio test.

        The Levenberg–Marquardt form of a trust region on the energy Π = ½uᵀSu + Σ W V(Δn), whose gradient
        is R and Hessian J (`energy`, `jacobian`). A step is accepted iff Π does not rise (beyond
        round-off, 1e-12 |Π|); ρ = ΔΠ / ΔΠ_model with the quadratic model ΔΠ_model = c gᵀdu + ½c² duᵀJdu,
        duᵀJdu = −gᵀdu − σ duᵀMdu from the solve (no extra product; c ≤ 1 the increment limit 0.5 δn).
        σ shrinks ×0.1 where ρ > 0.75 (down to 0: Newton), grows ×4 where ρ < 0.25 or the step is rejected
        or not a descent direction (J + σM indefinite). σ ≥ e⁻² makes J + σM positive definite (the law's
        most negative slope is −e⁻² φn/δn², S is positive definite), so the descent cannot stall at an
        unstable equilibrium: through a jump-in or snap-off the surface follows Π downhill to the basin of
        a stable state (`stable` checks it). Returns (u, residual, iterations, converged).
        """
        mass = self.wt * (self.phi_n / self.dn**2)
        sigma = 1.0
        r = self._safe_residual(u, z_ind)
        if r is None:
            return u, math.inf, 0, False
        e = self.energy(u, z_ind)
        for it in range(1, max_iter + 1):
            res = self.measure(r)
            if res <= tol:
                return u, res, it - 1, True
            try:
                du = self.solve_linear(self.jacobian(u, z_ind, shift=sigma * mass if sigma > 0 else None), -r)
            except (scipy.linalg.LinAlgError, ValueError):
                sigma = max(4 * sigma, 1.0)
                continue
            slope = float(r @ du)
            if not (np.isfinite(slope) and slope < 0):  # not a descent direction: J + σM indefinite
                sigma = max(4 * sigma, 1.0)
                continue
            curvature = -slope - sigma * float(du @ (mass * du))  # duᵀ J du
            limited = self.limit(du)
            c = float(np.max(np.abs(limited)) / np.max(np.abs(du)))
            model = c * slope + 0.5 * c * c * curvature
            trial = u + limited
            rt = self._safe_residual(trial, z_ind)
            et = self.energy(trial, z_ind) if rt is not None else math.inf
            if not et <= e + 1e-12 * abs(e):
                sigma = max(4 * sigma, 1e-3)
                continue
            rho = (et - e) / model if model < 0 else 0.0
            if rho > 0.75:
                sigma = 0.1 * sigma if sigma > 1e-6 else 0.0
            elif rho < 0.25:
                sigma = max(4 * sigma, 1e-3)
            u, r, e = trial, rt, et
        return u, self.measure(r), max_iter, self.measure(r) <= tol

    def solve_step(self, u0, z_ind, tol, fallback_from=None):
        """Equilibrium from guess u0; returns (u, residual, iterations, converged, how)."""
        u, res, it, ok = self.newton(u0.copy(), z_ind, tol)
        how = "newton"
        if ok and not self.stable(u, z_ind):
            ok, how = False, "unstable"
        if not ok and fallback_from is not None and fallback_from is not u0:
            u2, res2, it2, ok2 = self.newton(fallback_from.copy(), z_ind, tol)
            it += it2
            if ok2 and self.stable(u2, z_ind):
                return u2, res2, it, True, "newton (restart from previous step)"
        if not ok:
            start = fallback_from if fallback_from is not None else u0
            why = "after unstable Newton root" if how == "unstable" else "Newton failed"
            if self.tangential:  # no potential: pseudo-transient continuation on the residual
                u, res, it3, ok = self.ptc(start.copy(), z_ind, tol * 1e3)
                how = f"pseudo-transient continuation ({why})"
            else:  # a potential: minimise it (trust region)
                u, res, it3, ok = self.descend(start.copy(), z_ind, tol * 1e3)
                how = f"trust-region energy descent ({why})"
            it += it3
            if ok:  # polish with Newton from the stable basin
                u, res, it4, ok = self.newton(u, z_ind, tol)
                it += it4
            if ok and not self.stable(u, z_ind):
                ok, how = False, how + ", landed on an unstable equilibrium"
        return u, res, it, ok, how


@dataclass
class FeCell:
    """One realization's FE cohesive problem (see gfmd_contact.core.ramp for the protocol): Newton with
    the problem's own fallbacks per step, warm-started from the ramp's extrapolation."""

    scene: object
    prob: object  # SurfaceProblem (dense) or its sparse subclass
    physics: object  # gfmd_contact.core.model.Model: the model choice and checks shared with every method
    tolerance: float
    method: str
    model: str
    reasons: tuple
    diagnostics: dict
    extrapolate: bool = True

    def initial_state(self):
        return np.zeros(self.prob.S.shape[0])

    def observe(self, scene, h, gap, t_n):
        """p, a_rel, ḡ_r, ḡ of a step from the FE's own observables (`reference.fem.observables`); the
        step's pressure from the nodal reaction forces goes to diagnostics["reaction_pressure"]."""
        self.diagnostics.setdefault("reaction_pressure", []).append(self._reaction)
        contact_gap = self.prob.law.contact_gap(scene.interface.contact_tolerance)
        return cohesive_observables(h, scene.surface.spacing, gap, t_n, contact_gap, interface=scene.interface)

    def solve(self, displacement, guess, fallback):
        prob, vp = self.prob, self.prob.cell.vertex_points
        loading = self.scene.loading
        z_ind = surface_indenter(prob.h_surface, prob.h_min, loading.initial_separation, displacement)
        u_new, res, its, ok, how = prob.solve_step(guess, z_ind, self.tolerance, fallback_from=fallback)
        sol = u_new if ok or np.all(np.isfinite(u_new)) else fallback
        try:
            tt, tn, gap = prob.tractions(sol, z_ind)
        except LawRangeError as exc:  # a diverged iterate beyond the law's range: a non-converged step, no state
            self._reaction = np.nan  # recorded by observe(), once per step
            gap = z_ind - prob.split(fallback)[1]
            return StepSolution(state=fallback, converged=False, iterations=its, residual=np.nan, gap=gap[vp],
                                t_n=np.zeros_like(gap[vp]), fields=dict, messages=(f"{how}: not converged, {exc}",),
                                fallback=how != "newton", relaxed=False)
        self._reaction = prob.reaction_pressure(sol)  # recorded by observe(), once per step
        ux, uz = prob.split(sol)
        messages = (() if how == "newton" else (how,)) + (() if ok else (f"not converged, residual {res:.3g}",))

        def fields():
            u_x = ux if prob.tangential else prob.solve_interior(sol)[prob.cell.surface_dofs[0]]
            return {"u_z": uz[vp].copy(), "u_x": u_x[vp].copy(), "gap": gap[vp].copy(), "t_n": tn[vp].copy(),
                    "t_t": tt[vp].copy()}

        return StepSolution(state=u_new, converged=ok, iterations=its, residual=res, gap=gap[vp], t_n=tn[vp],
                            fields=fields, u_x=ux[vp] if prob.tangential else None, messages=messages,
                            keep={"solutions": sol.copy()}, fallback=how != "newton")
