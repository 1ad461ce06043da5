"""The hard wall by projected preconditioned conjugate gradients on the displacements (the primal).

An active-set method (Polonsky & Keer 1999, Dostál's proportioning) for min ½ uᵀKu over
u ≤ z_ind (`gfmd.problem`); preconditioner M⁻¹ = K⁻¹, two FFT pairs per iteration; 5.8–7.3× fewer
FFT pairs per step than FIRE at N = 2^16–2^17 (benchmarks/results/bench_vs_tamaas.md). The hard
wall's chain runs it beyond `Settings.dual_contact_limit` (`gfmd.chains`).
"""

from __future__ import annotations

import numpy as np

from ..fft import Fft, dot
from ..problem import mean_shift, stiffness_operator
from ..stopping import finish, wall_check

def solve(problem, start, settings):
    """Hard wall by projected preconditioned conjugate gradients (active set; normal only).

    The step's problem is min ½ uᵀKu over u ≤ z_ind (half-plane: and ⟨u⟩ = 0, whose
    multiplier is the far-field pressure of `gfmd.problem.wall_balance`). Nodes on the wall form the
    active set A (held at their place); on the others, F, the force r = p − Ku (`gfmd.problem.wall_balance`)
    is the negative gradient, and CG runs on F with the mass weighting of the FIRE
    solver as preconditioner, s = Π M⁻¹ r (Π: zero on A and, on a half-plane, mean
    zero over F, so ⟨u⟩ stays 0): the free elastic modes are solved at once, what is
    left is the coupling through the few contact nodes, hence iterations nearly flat in N.

    Set changes (Polonsky & Keer 1999; Dostál's proportioning):
    * a CG step that takes free nodes through the wall is kept and projected (the
      nodes go onto the wall and into A, ⟨u⟩ restored by `gfmd.problem.mean_shift` with A pinned),
      K u is recomputed exactly and CG restarts;
    * wall nodes whose force pulls them off (r < 0) are released once the norm of those
      forces exceeds `proportioning` × the norm of r on F (CG restarts).

    Stop: the residual of `gfmd.algorithms.hard_wall_dynamics` (max |net force| of `gfmd.problem.wall_net_force`,
    pulling wall nodes included, stuck ones zero) below tolerance · p_ref, recomputed
    with a fresh K u, so the converged states and their residuals mean what FIRE's do;
    the fixed points are the KKT points (no pulling wall node, zero force off the wall,
    no penetration). Cost: two FFT pairs per iteration (K d and M⁻¹ r), one more per
    projection; K u is updated with the step instead of recomputed.
    """
    model, law, z_ind, wall_tolerance = problem.model, problem.law, problem.z_ind, problem.wall_tolerance
    u_hat = start  # the step's initial displacements (c, N//2+1), rfft
    n = model.nodes
    fft = Fft(n, grid=model.grid)
    clamp = model.half_plane
    k = np.ascontiguousarray(np.real(model.k_zz))
    g = np.ascontiguousarray(np.real(stiffness_operator(model).inv_mass[0]))  # M⁻¹ = K⁻¹, 0 at q = 0 (half-plane)
    p_ref = model.reference_traction
    tol = settings.tolerance * p_ref
    gamma2 = settings.proportioning**2
    z_ind = np.ascontiguousarray(z_ind, dtype=float)

    u = fft.irfft(np.ascontiguousarray(u_hat[-1]))
    shift = mean_shift(u, z_ind) if clamp else 0.0
    u = np.minimum(u + shift, z_ind)
    # work arrays, allocated once; the active set A (a few % of the nodes at most) is kept as indices,
    # so that everything it touches costs O(|A|) and the loop makes no boolean-mask copies of length N
    ku, r, s, d, kd, tmp = (np.empty(n) for _ in range(6))
    d[:] = 0.0
    through = np.empty(n, bool)
    fft.apply_to(k, u, ku)
    act = np.flatnonzero(z_ind - u <= wall_tolerance)
    rz_old = 1.0
    restart, checked = True, False
    residual, converged, message = np.inf, False, ""
    it = 0
    while it < settings.max_iterations:
        n_free = n - act.size
        p_far = (float(np.sum(ku)) - float(np.sum(ku[act]))) / n_free if clamp and n_free else 0.0
        np.subtract(p_far, ku, out=r)  # force (`gfmd.problem.wall_balance`); on A, the wall's load
        force_act = r[act]
        r[act] = 0.0
        pull = force_act < 0
        r_free2 = dot(r, r)
        if pull.any():
            f_pull = force_act[pull]
            pull2 = dot(f_pull, f_pull)
            if pull2 > gamma2 * r_free2 or r_free2 < tol * tol:  # proportioning: release them
                act = act[~pull]
                restart = True
                continue
        # max |r| < tol needs Σ r² < n_free·tol²: only then is the max worth a pass over r
        worst = max(float(np.max(r)), -float(np.min(r))) if n_free and r_free2 < n_free * tol * tol else np.inf
        if n_free == 0:
            worst = 0.0
        if worst < tol and not checked:  # candidate: the solver's residual with a fresh K u
            residual, converged, message = wall_check(model, fft, k, u, ku, z_ind, wall_tolerance, settings.tolerance)
            if converged or message:
                break
            restart, checked = True, True  # next: a CG iteration (or a release) before checking again
            continue
        it += 1
        checked = False
        fft.apply_to(g, r, s)
        s[act] = 0.0
        if clamp:  # mean zero over F (A stays 0)
            s -= float(np.sum(s)) / n_free
            s[act] = 0.0
        rz = dot(r, s)
        if restart or rz_old <= 0:
            np.copyto(d, s)
            restart = False
        else:
            d *= rz / rz_old
            d += s
        rz_old = rz
        fft.apply_to(k, d, kd)
        curvature = dot(d, kd)
        if not curvature > 0:
            message = "diverged: non-positive curvature along the search direction"
            break
        alpha = rz / curvature
        np.multiply(d, alpha, out=tmp)
        u += tmp
        np.multiply(kd, alpha, out=tmp)
        ku += tmp
        np.greater(u, z_ind, out=through)
        if through.any():  # Polonsky–Keer: keep the step, put the nodes onto the wall, restart
            if clamp:
                active = np.zeros(n, bool)
                active[act] = True
                active |= through
                shift = mean_shift(u, z_ind, active)
                u = np.where(active, z_ind, np.minimum(u + shift, z_ind))
                act = np.flatnonzero(u >= z_ind)
            else:
                np.minimum(u, z_ind, out=u)
                act = np.union1d(act, np.flatnonzero(through))
            fft.apply_to(k, u, ku)
            restart = True
        if not np.isfinite(alpha):
            message = "diverged: non-finite step"
            break
    else:
        message = f"not converged after {settings.max_iterations} iterations (residual {residual:.3g} p_ref)"
    if not converged and not message:
        message = f"not converged after {settings.max_iterations} iterations (residual {residual:.3g} p_ref)"
    u_hat = fft.rfft(u)[None, :]
    pairs = fft.pairs
    out = finish(problem, u_hat, it, residual, converged, message)
    out.fft_pairs = pairs + 1.5  # finish: one irfft of u_hat and one pair for K u
    out.method = "cg"
    return out


#: Half-width (nodes) of the band of K_AA that preconditions the dual hard-wall CG (`_band_stiffness`).
