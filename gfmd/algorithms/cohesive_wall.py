"""The cohesive wall (`gfmd_contact.core.laws.CohesiveWall`: Eq. 3's attraction for Δn > 0, Δn ≥ 0 a constraint).

The hard wall's projected FIRE (or Verlet) with the attraction added to the nodal force, the
cohesive dynamics' mass weighting and trust region; the same residual, and KKT fixed points
(Δn ≥ 0, reaction ≥ 0 on the wall, zero force off it).
"""

from __future__ import annotations

import numpy as np

from ..fft import irfft_nodes, rfft_nodes, spectral_weights
from ..integrators import Fire, fire_wall_velocity, verlet_coefficients
from ..problem import Elastic, mean_shift, project_onto_wall
from ..settings import Relaxed, not_converged

def solve(problem, start, settings):
    """Cohesive wall (`gfmd_contact.core.laws.CohesiveWall`): Eq. 3's attraction off the wall, Δn ≥ 0 projected.

    The `gfmd.algorithms.hard_wall_dynamics` projected FIRE (or Verlet) with the attraction T_n(Δn) added to the
    nodal force, f = T_n(Δn) + p − K u (p: the half-plane's far-field load keeping ⟨u⟩ = 0, the
    mean of K u − T_n over the nodes off the wall; 0 on a layer). Nodes on the wall (Δn ≤
    wall_tolerance) pushed into it (f > 0) are "stuck": the wall takes their force (reaction
    f ≥ 0, compressive) and their preconditioned acceleration is zeroed; wall nodes pulled away keep
    their force, capped as in `gfmd.algorithms.hard_wall_dynamics`. After each move the nodes pushed through the
    wall are projected back (u_z ≤ z_ind, ⟨u⟩ = 0 on a half-plane with the stuck nodes pinned)
    and their velocity into the wall is removed. The mass M_q = K(q) + ⟨∂T_n/∂Δn⟩₊ (mean over
    the nodes off the wall, refreshed as in `gfmd.algorithms.dynamics`) and a trust region of
    `max_move`·δn per iteration follow the cohesive solver. Residual: max |net force| (stuck
    nodes 0, pulling wall nodes and free nodes their force) / p_ref, the hard wall's semantics;
    the fixed points are the KKT points: Δn ≥ 0, reaction ≥ 0 on the wall, f = 0 off it.
    Returns `Relaxed` with t_z = T_n(Δn) off the wall and T_n − reaction on it (normal only).
    """
    model, law, z_ind, wall_tolerance = problem.model, problem.law, problem.z_ind, problem.wall_tolerance
    u_hat = start  # the step's initial displacements (c, N//2+1), rfft
    if model.tangential:
        raise ValueError("the cohesive wall is frictionless and normal-only: no tangential unknowns")
    cz = law.law
    n, grid = model.nodes, model.grid
    clamp = model.half_plane
    k = model.k_zz
    weights = spectral_weights(grid)

    def attraction(gap):
        return cz.tractions(gap)[0]

    def mean_slope(gap):
        off = gap > wall_tolerance
        if not off.any():
            return 0.0
        return float(np.sum(np.maximum(cz.tangent(gap[off])[0], 0.0))) / n

    def net_force(u):
        gap = z_ind - u
        on_wall = gap <= wall_tolerance
        t = attraction(gap)
        ku = irfft_nodes(k * rfft_nodes(u, grid), grid)
        free = ~on_wall
        p = float(np.mean(ku[free] - t[free])) if clamp and free.any() else 0.0
        force = t + p - ku
        stuck = on_wall & (force > 0)
        return np.where(stuck, 0.0, force), stuck, on_wall, force, t

    u = irfft_nodes(u_hat[-1], grid)
    shift = mean_shift(u, z_ind) if clamp else 0.0
    u = np.minimum(u + shift, z_ind)
    k_mean = mean_slope(z_ind - u)

    def preconditioner(k_mean):
        inv = Elastic(model, 0.0, k_mean).inv_mass[0]
        return inv, float(np.sum(weights * inv)) / n  # M⁻¹ and its real-space diagonal

    inv_mass, inv_mass_diag = preconditioner(k_mean)
    fire = Fire(settings) if settings.method != "verlet" else None
    if fire is None:
        rho, gdt = verlet_coefficients(np.real(k) + cz.initial_stiffness[1], settings)
    dt = fire.dt if fire else 1.0
    max_move = settings.max_move * cz.length_scale
    p_ref = model.reference_traction
    v = np.zeros(n)
    residual, converged, message = np.inf, False, ""
    it = 0
    for it in range(1, settings.max_iterations + 1):
        force, stuck, on_wall, _, _ = net_force(u)
        if it % settings.check_every == 0 or it == 1:
            residual = float(np.max(np.abs(force))) / p_ref
            if residual < settings.tolerance:
                converged = True
                break
            if not np.isfinite(residual):
                message = "diverged: non-finite force residual"
                break
        if fire is not None and it % settings.mass_refresh == 0:
            k_now = mean_slope(z_ind - u)
            if k_now > 2 * k_mean + 1e-300 or k_mean > 2 * k_now + 1e-300:
                k_mean = k_now  # interface stiffness changed 2×: re-weight the modes, restart FIRE
                inv_mass, inv_mass_diag = preconditioner(k_mean)
                v[:] = 0.0
                fire.reset()
        if fire is None:
            v_hat = rfft_nodes(v, grid)
            v_hat = ((1 - gdt / 2) * v_hat + dt * rfft_nodes(force, grid) / rho) / (1 + gdt / 2)
            if clamp:
                v_hat[0] = 0.0
            v = irfft_nodes(v_hat, grid)
            v[stuck] = np.minimum(v[stuck], 0.0)
        else:
            dt = fire_wall_velocity(fire, force, u, v, stuck, on_wall, inv_mass, inv_mass_diag, grid)
        move = float(np.max(np.abs(dt * v)))
        if move > max_move:  # trust region: no node moves more than max_move per iteration
            v *= max_move / move
            if fire is not None:
                fire.dt *= settings.f_dec
        u += dt * v
        u = project_onto_wall(u, v, z_ind, stuck, clamp)
    else:
        message = not_converged(settings.max_iterations, residual)
    u_hat = rfft_nodes(u, grid)[None, :]
    u = irfft_nodes(u_hat[-1], grid)
    gap = np.maximum(z_ind - u, 0.0)
    u = z_ind - gap
    _, stuck, on_wall, force, t = net_force(u)
    t_z = np.where(on_wall, t - np.maximum(force, 0.0), t)  # the wall's reaction on top of T_n (0 at Δn = 0)
    return Relaxed(u_hat=u_hat, u_z=u, u_x=np.zeros(n), gap=gap, t_z=t_z, t_x=np.zeros(n), iterations=it,
                   residual=float(residual), converged=bool(converged), message=message,
                   method="verlet" if fire is None else "fire")
