"""The cohesive wall (`gfmd_contact.core.laws.CohesiveWall`: Eq. 3's attraction for Δn > 0, Δn ≥ 0 a constraint).

The hard wall's projected FIRE (or Verlet) with the attraction added to the nodal force, the
cohesive dynamics' mass weighting and trust region; the same residual, and KKT fixed points
(Δn ≥ 0, reaction ≥ 0 on the wall, zero force off it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..fft import irfft_nodes, rfft_nodes, spectral_weights
from ..integrators import DynamicsOptions, Fire, fire_wall_velocity, verlet_coefficients
from ..problem import Elastic, mean_shift, project_onto_wall
from ..settings import Relaxed, not_converged


@dataclass(frozen=True)
class Options(DynamicsOptions):
    """What it reads: FIRE's and Verlet's options, the largest nodal move and the mass refresh."""

    max_move: float  # largest nodal move per iteration, in law lengths
    mass_refresh: int  # iterations between re-evaluations of the mean interface stiffness


def solve(problem, start, options):
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
    if problem.model.tangential:
        raise ValueError("the cohesive wall is frictionless and normal-only: no tangential unknowns")
    wall = _setup(problem, options)
    state = _init(wall, start)
    while state.it < options.max_iterations and not (state.converged or state.message):
        state.it += 1
        _step(wall, state)
    if not state.converged and not state.message:
        state.message = not_converged(options.max_iterations, state.residual)
    return _result(wall, state)


class _Wall(NamedTuple):
    """What one step's cohesive-wall dynamics hold fixed."""

    model: object
    options: object
    law: object  # the cohesive law of the attraction (`CohesiveWall.law`)
    z: np.ndarray  # z_ind
    wall_tolerance: float
    n: int
    grid: object
    clamp: bool  # half-plane: ⟨u⟩ = 0
    k: np.ndarray  # K's rfft coefficients (Pa/m)
    weights: np.ndarray  # the half-spectrum's weights (`gfmd.fft.spectral_weights`)
    max_move: float  # the trust region (m)
    p_ref: float
    verlet: tuple | None  # Verlet's (ρ, γ dt), None under FIRE


@dataclass
class WallState:
    """The dynamics' iterate: u and v on the nodes, the mass weighting and FIRE's own state."""

    u: np.ndarray
    v: np.ndarray
    k_mean: float  # ⟨∂T_n/∂Δn⟩₊ the mass was built with
    inv_mass: np.ndarray  # M⁻¹ on the spectrum
    inv_mass_diag: float  # its real-space diagonal
    fire: Fire | None  # None: Verlet
    dt: float
    it: int = 0
    residual: float = np.inf
    converged: bool = False
    message: str = ""


def _setup(problem, options):
    model, cz = problem.model, problem.law.law
    verlet = None
    if options.method == "verlet":
        verlet = verlet_coefficients(np.real(model.k_zz) + cz.initial_stiffness[1], options)
    return _Wall(model=model, options=options, law=cz, z=problem.z_ind, wall_tolerance=problem.wall_tolerance,
                 n=model.nodes, grid=model.grid, clamp=model.half_plane, k=model.k_zz,
                 weights=spectral_weights(model.grid), max_move=options.max_move * cz.length_scale,
                 p_ref=model.reference_traction, verlet=verlet)


def _init(wall, start):
    """The start projected below the wall (half-plane: ⟨u⟩ = 0 first), at rest, and its mass weighting."""
    z = wall.z
    u = irfft_nodes(start[-1], wall.grid)
    shift = mean_shift(u, z) if wall.clamp else 0.0
    u = np.minimum(u + shift, z)
    k_mean = _mean_slope(wall, z - u)
    inv_mass, inv_mass_diag = _preconditioner(wall, k_mean)
    fire = Fire(wall.options) if wall.verlet is None else None
    return WallState(u=u, v=np.zeros(wall.n), k_mean=k_mean, inv_mass=inv_mass, inv_mass_diag=inv_mass_diag,
                     fire=fire, dt=fire.dt if fire else 1.0)


def _mean_slope(wall, gap):
    """⟨∂T_n/∂Δn⟩₊ over the nodes off the wall (a sum over those, divided by all N)."""
    off = gap > wall.wall_tolerance
    if not off.any():
        return 0.0
    return float(np.sum(np.maximum(wall.law.tangent(gap[off])[0], 0.0))) / wall.n


def _preconditioner(wall, k_mean):
    """M⁻¹ and its real-space diagonal."""
    inv = Elastic(wall.model, 0.0, k_mean).inv_mass[0]
    return inv, float(np.sum(wall.weights * inv)) / wall.n


def _net_force(wall, u):
    """(net force, stuck, on_wall, force, T_n): the force with the wall's reaction taken off the stuck nodes."""
    gap = wall.z - u
    on_wall = gap <= wall.wall_tolerance
    t = wall.law.tractions(gap)[0]
    ku = irfft_nodes(wall.k * rfft_nodes(u, wall.grid), wall.grid)
    free = ~on_wall
    p = float(np.mean(ku[free] - t[free])) if wall.clamp and free.any() else 0.0
    force = t + p - ku
    stuck = on_wall & (force > 0)
    return np.where(stuck, 0.0, force), stuck, on_wall, force, t


def _step(wall, state):
    """One iteration: the residual test (every `check_every`), the mass refresh, the velocity and the move."""
    options, it = wall.options, state.it
    force, stuck, on_wall, _, _ = _net_force(wall, state.u)
    if it % options.check_every == 0 or it == 1:
        state.residual = residual = float(np.max(np.abs(force))) / wall.p_ref
        if residual < options.tolerance:
            state.converged = True
            return
        if not np.isfinite(residual):
            state.message = "diverged: non-finite force residual"
            return
    if state.fire is not None and it % options.mass_refresh == 0:
        _refresh_mass(wall, state)
    if state.fire is None:
        _verlet_velocity(wall, state, force, stuck)
    else:
        state.dt = fire_wall_velocity(state.fire, force, state.u, state.v, stuck, on_wall, state.inv_mass,
                                      state.inv_mass_diag, wall.grid)
    dt, v = state.dt, state.v
    move = float(np.max(np.abs(dt * v)))
    if move > wall.max_move:  # trust region: no node moves more than max_move per iteration
        v *= wall.max_move / move
        if state.fire is not None:
            state.fire.dt *= options.f_dec
    state.u += dt * v
    state.u = project_onto_wall(state.u, v, wall.z, stuck, wall.clamp)


def _refresh_mass(wall, state):
    """Where the interface stiffness changed 2×: re-weight the modes, restart FIRE."""
    k_now = _mean_slope(wall, wall.z - state.u)
    k_mean = state.k_mean
    if k_now > 2 * k_mean + 1e-300 or k_mean > 2 * k_now + 1e-300:
        state.k_mean = k_now
        state.inv_mass, state.inv_mass_diag = _preconditioner(wall, k_now)
        state.v[:] = 0.0
        state.fire.reset()


def _verlet_velocity(wall, state, force, stuck):
    """Damped Verlet's velocity on the spectrum (half-plane: the q = 0 mode 0); stuck nodes keep no velocity
    into the wall."""
    rho, gdt = wall.verlet
    dt, grid = state.dt, wall.grid
    v_hat = rfft_nodes(state.v, grid)
    v_hat = ((1 - gdt / 2) * v_hat + dt * rfft_nodes(force, grid) / rho) / (1 + gdt / 2)
    if wall.clamp:
        v_hat[0] = 0.0
    v = irfft_nodes(v_hat, grid)
    v[stuck] = np.minimum(v[stuck], 0.0)
    state.v = v


def _result(wall, state):
    """The `Relaxed`: t_z = T_n off the wall, T_n less the wall's reaction on it."""
    grid, z, n = wall.grid, wall.z, wall.n
    u_hat = rfft_nodes(state.u, grid)[None, :]
    u = irfft_nodes(u_hat[-1], grid)
    gap = np.maximum(z - u, 0.0)
    u = z - gap
    _, stuck, on_wall, force, t = _net_force(wall, u)
    t_z = np.where(on_wall, t - np.maximum(force, 0.0), t)  # the wall's reaction on top of T_n (0 at Δn = 0)
    return Relaxed(u_hat=u_hat, u_z=u, u_x=np.zeros(n), gap=gap, t_z=t_z, t_x=np.zeros(n), iterations=state.it,
                   residual=float(state.residual), converged=bool(state.converged), message=state.message,
                   method="verlet" if state.fire is None else "fire")
