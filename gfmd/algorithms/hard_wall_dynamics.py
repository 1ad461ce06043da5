"""The hard wall by projected damped dynamics: FIRE (``Settings.hard_wall = "fire"``) or Verlet.

The hard wall is a constraint, not a penalty: after each move the nodes that went through the
wall are projected back onto it (u_z ≤ z_ind, `gfmd.problem.project_onto_wall`) and the velocity
that carried them there is removed with the same correction. Same residual and KKT fixed points
as the hard-wall CGs (`gfmd.stopping`).
"""

from __future__ import annotations

import numpy as np

from ..fft import irfft_nodes, rfft_nodes, spectral_weights
from ..integrators import DynamicsOptions, Fire, fire_wall_velocity, verlet_coefficients
from ..problem import mean_shift, project_onto_wall, stiffness_operator, wall_net_force
from ..settings import not_converged
from ..stopping import finish

#: what it reads: FIRE's and Verlet's options
Options = DynamicsOptions


def solve(problem, start, options):
    """Hard-wall relaxation in real space by projected FIRE or damped Verlet (`options.method`; normal only).

    The wall reaction enters as a force: on nodes touching the wall, a net force
    pushing into it is cancelled (net 0), so the dynamics sees the true KKT
    residual. A Euclidean projection after a non-diagonal preconditioner has
    spurious fixed points (a wall node's pull-off force smeared into push-in
    accelerations that the wall absorbs), so the mass-weighted acceleration M⁻¹f
    is zeroed on the stuck nodes (Z M⁻¹ Z, positive definite on the rest), and on
    wall nodes that pull away it is capped at their diagonal-preconditioned value
    f_j·diag(M⁻¹) < 0: at a fixed point no node pulls on the wall and f = 0 on the
    free set, i.e. the fixed points are exactly the KKT points. Positions are
    projected onto {u ≤ z_ind} (and ⟨u⟩ = 0 for the half-plane, stuck nodes
    pinned), and the velocity into the wall of projected nodes is removed.
    Each iteration costs two rfft/irfft pairs: K u and the mass-weighted acceleration
    (FIRE), or the damped velocity update in Fourier space (Verlet, uniform mass).
    """
    model, law, z_ind, wall_tolerance = problem.model, problem.law, problem.z_ind, problem.wall_tolerance
    u_hat = start  # the step's initial displacements (c, N//2+1), rfft
    n, grid = model.nodes, model.grid
    elastic = stiffness_operator(model)
    k = model.k_zz
    inv_mass = elastic.inv_mass[0]
    inv_mass_diag = float(np.sum(spectral_weights(grid) * inv_mass)) / n  # real-space diagonal of M⁻¹
    fire = None if options.method == "verlet" else Fire(options)
    if fire is None:
        rho, gdt = verlet_coefficients(k, options)
    dt = fire.dt if fire else 1.0
    u = irfft_nodes(u_hat[-1], grid)
    shift = mean_shift(u, z_ind) if elastic.clamp else 0.0
    u = np.minimum(u + shift, z_ind)
    v = np.zeros(n)
    residual, converged, message = np.inf, False, ""
    it = 0
    for it in range(1, options.max_iterations + 1):
        on_wall = z_ind - u <= wall_tolerance
        force, stuck = wall_net_force(model, k, u, on_wall, n)
        if it % options.check_every == 0 or it == 1:
            residual = float(np.max(np.abs(force))) / model.reference_traction
            if residual < options.tolerance:
                converged = True
                break
            if not np.isfinite(residual):
                message = "diverged: non-finite force residual"
                break
        if fire is None:
            v_hat = rfft_nodes(v, grid)
            v_hat = ((1 - gdt / 2) * v_hat + dt * rfft_nodes(force, grid) / rho) / (1 + gdt / 2)
            if elastic.clamp:
                v_hat[0] = 0.0
            v = irfft_nodes(v_hat, grid)
        else:
            dt = fire_wall_velocity(fire, force, u, v, stuck, on_wall, inv_mass, inv_mass_diag, grid)
        u += dt * v
        u = project_onto_wall(u, v, z_ind, stuck, elastic.clamp)
    else:
        message = not_converged(options.max_iterations, residual)
    u_hat = rfft_nodes(u, grid)[None, :]
    out = finish(problem, u_hat, it, residual, converged, message)
    out.method = "verlet" if fire is None else "fire"
    return out
