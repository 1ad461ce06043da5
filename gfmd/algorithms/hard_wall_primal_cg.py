"""The hard wall by projected preconditioned conjugate gradients on the displacements (the primal).

An active-set method (Polonsky & Keer 1999, Dostál's proportioning) for min ½ uᵀKu over
u ≤ z_ind (`gfmd.problem`); preconditioner M⁻¹ = K⁻¹, two FFT pairs per iteration; 5.8–7.3× fewer
FFT pairs per step than FIRE at N = 2^16–2^17 (docs/design/performance.md). The hard
wall's chain runs it beyond `Settings.dual_contact_limit` (`gfmd.chains`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..fft import Fft, dot
from ..problem import mean_shift, stiffness_operator
from ..stopping import finish, wall_check

#: the name of this algorithm in `Relaxed.method`, result files and the chains (`gfmd.chains`)
LABEL = "cg"


@dataclass(frozen=True)
class Options:
    """What the primal CG reads: the `gfmd.settings.Settings` fields of these names."""

    tolerance: float  # max nodal force residual / p_ref
    max_iterations: int
    proportioning: float  # Dostál's proportioning test: release pulling wall nodes past this × the free residual


def solve(problem, start, options):
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
    primal = _setup(problem, options)
    state = _init(primal, start)
    while state.it < options.max_iterations and not (state.converged or state.message):
        _step(primal, state)
    if not state.converged and not state.message:
        state.message = (f"not converged after {options.max_iterations} iterations "
                         f"(residual {state.residual:.3g} p_ref)")
    u_hat = primal.fft.rfft(state.u)[None, :]
    pairs = primal.fft.pairs
    out = finish(problem, u_hat, state.it, state.residual, state.converged, state.message)
    out.fft_pairs = pairs + 1.5  # finish: one irfft of u_hat and one pair for K u
    out.method = LABEL
    return out


class _Primal(NamedTuple):
    """What one step's primal CG holds fixed."""

    model: object
    options: object
    fft: Fft
    k: np.ndarray  # K's rfft coefficients (Pa/m)
    g: np.ndarray  # M⁻¹ = K⁻¹, 0 at q = 0 (half-plane)
    z: np.ndarray  # z_ind
    wall_tolerance: float
    clamp: bool  # half-plane: ⟨u⟩ = 0
    n: int
    tol: float  # tolerance · p_ref (Pa)
    gamma2: float  # proportioning²


@dataclass
class PrimalState:
    """The primal CG's iterate: u and K u, the active set A, work arrays and the CG recurrence."""

    u: np.ndarray
    ku: np.ndarray
    r: np.ndarray  # the force on F (zero on A)
    s: np.ndarray  # the preconditioned force
    d: np.ndarray  # the search direction
    kd: np.ndarray
    tmp: np.ndarray
    through: np.ndarray  # nodes a step took through the wall
    act: np.ndarray  # A: the node indices on the wall
    rz_old: float = 1.0
    restart: bool = True
    checked: bool = False  # a candidate was tested since the last CG iteration
    it: int = 0
    residual: float = np.inf
    converged: bool = False
    message: str = ""


def _setup(problem, options):
    model = problem.model
    n = model.nodes
    return _Primal(model=model, options=options, fft=Fft(n, grid=model.grid),
                   k=np.ascontiguousarray(np.real(model.k_zz)),
                   g=np.ascontiguousarray(np.real(stiffness_operator(model).inv_mass[0])),
                   z=np.ascontiguousarray(problem.z_ind, dtype=float), wall_tolerance=problem.wall_tolerance,
                   clamp=model.half_plane, n=n, tol=options.tolerance * model.reference_traction,
                   gamma2=options.proportioning**2)


def _init(primal, start):
    """The start projected below the wall (half-plane: ⟨u⟩ = 0 first), its K u and its wall nodes."""
    fft, z, n = primal.fft, primal.z, primal.n
    u = fft.irfft(np.ascontiguousarray(start[-1]))
    shift = mean_shift(u, z) if primal.clamp else 0.0
    u = np.minimum(u + shift, z)
    # work arrays, allocated once; the active set A (a few % of the nodes at most) is kept as indices,
    # so that everything it touches costs O(|A|) and the loop makes no boolean-mask copies of length N
    ku, r, s, d, kd, tmp = (np.empty(n) for _ in range(6))
    d[:] = 0.0
    through = np.empty(n, bool)
    fft.apply_to(primal.k, u, ku)
    act = np.flatnonzero(z - u <= primal.wall_tolerance)
    return PrimalState(u=u, ku=ku, r=r, s=s, d=d, kd=kd, tmp=tmp, through=through, act=act)


def _step(primal, state):
    """One pass of the loop: release pulling wall nodes, or test a candidate, or take one CG iteration."""
    act, ku, r, tol = state.act, state.ku, state.r, primal.tol
    n_free = primal.n - act.size
    p_far = (float(np.sum(ku)) - float(np.sum(ku[act]))) / n_free if primal.clamp and n_free else 0.0
    np.subtract(p_far, ku, out=r)  # force (`gfmd.problem.wall_balance`); on A, the wall's load
    force_act = r[act]
    r[act] = 0.0
    r_free2 = dot(r, r)
    if _release(primal, state, force_act, r_free2):
        return
    # max |r| < tol needs Σ r² < n_free·tol²: only then is the max worth a pass over r
    worst = max(float(np.max(r)), -float(np.min(r))) if n_free and r_free2 < n_free * tol * tol else np.inf
    if n_free == 0:
        worst = 0.0
    if worst < tol and not state.checked:
        _candidate(primal, state)
        return
    _cg_iteration(primal, state, n_free)


def _release(primal, state, force_act, r_free2):
    """Proportioning: the wall nodes whose force pulls them off leave A (restart) once the norm of those forces
    exceeds `proportioning` × that of r on F, or r on F is negligible; True if they did."""
    pull = force_act < 0
    if not pull.any():
        return False
    f_pull = force_act[pull]
    pull2 = dot(f_pull, f_pull)
    if not (pull2 > primal.gamma2 * r_free2 or r_free2 < primal.tol * primal.tol):
        return False
    state.act = state.act[~pull]
    state.restart = True
    return True


def _candidate(primal, state):
    """The solver's residual with a fresh K u; not passing, a CG iteration (or a release) comes before the next."""
    state.residual, state.converged, state.message = wall_check(
        primal.model, primal.fft, primal.k, state.u, state.ku, primal.z, primal.wall_tolerance,
        primal.options.tolerance)
    if state.converged or state.message:
        return
    state.restart, state.checked = True, True


def _cg_iteration(primal, state, n_free):
    """One preconditioned CG step on F; K u updated with the step; nodes taken through the wall: `_project`."""
    fft, r, s, d, kd, tmp = primal.fft, state.r, state.s, state.d, state.kd, state.tmp
    state.it += 1
    state.checked = False
    fft.apply_to(primal.g, r, s)
    s[state.act] = 0.0
    if primal.clamp:  # mean zero over F (A stays 0)
        s -= float(np.sum(s)) / n_free
        s[state.act] = 0.0
    rz = dot(r, s)
    if state.restart or state.rz_old <= 0:
        np.copyto(d, s)
        state.restart = False
    else:
        d *= rz / state.rz_old
        d += s
    state.rz_old = rz
    fft.apply_to(primal.k, d, kd)
    curvature = dot(d, kd)
    if not curvature > 0:
        state.message = "diverged: non-positive curvature along the search direction"
        return
    alpha = rz / curvature
    np.multiply(d, alpha, out=tmp)
    state.u += tmp
    np.multiply(kd, alpha, out=tmp)
    state.ku += tmp
    np.greater(state.u, primal.z, out=state.through)
    if state.through.any():
        _project(primal, state)
    if not np.isfinite(alpha):
        state.message = "diverged: non-finite step"


def _project(primal, state):
    """Polonsky–Keer: keep the step, put the nodes through the wall onto it and into A (half-plane: ⟨u⟩ restored
    with A pinned), K u recomputed exactly, restart."""
    z, u, through = primal.z, state.u, state.through
    if primal.clamp:
        active = np.zeros(primal.n, bool)
        active[state.act] = True
        active |= through
        shift = mean_shift(u, z, active)
        state.u = np.where(active, z, np.minimum(u + shift, z))
        state.act = np.flatnonzero(state.u >= z)
    else:
        np.minimum(u, z, out=u)
        state.act = np.union1d(state.act, np.flatnonzero(through))
    primal.fft.apply_to(primal.k, state.u, state.ku)
    state.restart = True
