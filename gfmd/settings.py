"""What every GFMD algorithm takes and returns: `Settings` (its parameters) and `Relaxed` (one step's state).

Units: SI (see `gfmd_contact.core.conventions`); the integrators' parameters are dimensionless (time unit 1/ω0,
ω0 = 1). Which algorithms run is `gfmd.chains`' choice from `Settings.method`, `hard_wall`, `cohesive`,
`coupled` and `dual_coarse_block`; the measurements behind the defaults: docs/design/solvers.md.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Settings:
    """What a scene (`gfmd.loading.settings_of`) or a caller sets for GFMD: which chain runs (method, hard_wall,
    cohesive, coupled, dual_coarse_block) and the algorithms' parameters. An algorithm that declares options of its
    own reads only those fields (`gfmd.links.options_for`). Integrator parameters are dimensionless (time unit
    1/ω0 with ω0 = 1)."""

    method: str = "fire"
    tolerance: float = 1e-8
    max_iterations: int = 200_000
    check_every: int = 10
    # FIRE (Bitzek et al. 2006 defaults, FIRE 2.0 back-step)
    dt_start: float = 0.3
    dt_max: float = 1.0
    n_min: int = 5
    f_inc: float = 1.1
    f_dec: float = 0.5
    alpha_start: float = 0.1
    f_alpha: float = 0.99
    # Verlet: ω_max Δt
    verlet_omega_dt: float = 1.0
    # cohesive laws: largest nodal move per iteration, in units of min(δn, δt)
    max_move: float = 0.5
    # FIRE, cohesive laws: iterations between re-evaluations of the mean interface stiffness
    mass_refresh: int = 100
    # hard wall with method "fire": "cg" (projected preconditioned CG, default) or "fire" (FIRE)
    hard_wall: str = "cg"
    # normal-only law with a potential, method "fire": "ncg" (nonlinear preconditioned CG with a Newton line
    # search, FIRE as fallback) or "fire" (FIRE alone)
    cohesive: str = "ncg"
    # coupled law (seed Eq. 2) with method "fire": "auto" ("frictionless-first" on a body that barely couples u_x
    # and u_z, `gfmd.coupled_rules.COUPLED_FRICTIONLESS_COUPLING`, else "handover-near"), "frictionless-first",
    # "handover-near" (Newton–Krylov first, then the frictionless reduction's NCG or FIRE to `coupled_handover` and
    # Newton from there, `gfmd.chains`) or "fire" (FIRE; Newton–Krylov, then Verlet after a stall)
    coupled: str = "auto"
    # the handover chains: FIRE (or the frictionless NCG) stops at this residual (× p_ref) and Newton–Krylov finishes
    # from there, its state kept only near the handed-over one, else FIRE goes on (`gfmd.chains`)
    coupled_handover: float = 1e-4
    # coupled law: FIRE's largest time step Δt (in place of dt_max, which the other laws' FIRE keeps): near Δt ≈ 0.5 a
    # compressed contact patch, far stiffer than the mass M_q = K(q) + ⟨k_loc⟩ holds, oscillates unstably and FIRE
    # restarts, losing its speed through a fold's ghost
    coupled_dt_max: float = 0.4
    # coupled law: FIRE's f_dec and n_min, the other laws' (Bitzek et al.); milder restarts were measured and not kept
    # (tests/test_coupled_fire_restarts.py)
    coupled_f_dec: float = 0.5
    coupled_n_min: int = 5
    # cohesive NCG's preconditioner (`gfmd.cohesive_preconditioner`): "auto" ("two-level" on a profile with Eq. 3's
    # law, else "stiffness"), "stiffness" (K⁻¹ on the modes) or "two-level" (K⁻¹ balanced by a coarse space on the
    # stiff patches, engaged on the steps that need it)
    cohesive_preconditioner: str = "auto"
    # coupled Newton–Krylov: give the step up at the first GMRES solve that misses its tolerance (True: the coupled
    # chains' continuation and handover links, `gfmd.chains`; False: go on with the inexact direction)
    coupled_gmres_give_up: bool = False
    # coupled Newton–Krylov: give the step up once an iterate has moved a node this many law lengths (min(δn, δt))
    # from its start (the coupled chains' continuation link: `gfmd.chains.COUPLED_JUMP`, the move its
    # acceptance test rejects; 0: never)
    coupled_continuation_jump: float = 0.0
    # coupled Newton–Krylov: give the step up after this many iterations (the coupled chains' continuation link:
    # `gfmd.chains.COUPLED_CONTINUATION_ITERATIONS`; 0: `gfmd.algorithms.coupled_newton.COUPLED_NEWTON_ITERATIONS`)
    coupled_continuation_iterations: int = 0
    # coupled Newton–Krylov: each GMRES solve gets this many restart cycles (the coupled chains' continuation
    # link: `gfmd.chains.COUPLED_CONTINUATION_GMRES_CYCLES`, a miss then breaks the step off as a jump does;
    # 0: `gfmd.algorithms.coupled_newton.COUPLED_GMRES_CYCLES`)
    coupled_continuation_gmres_cycles: int = 0
    # coupled Newton–Krylov: give the step up once two iterations in a row each left more than this fraction of the
    # residual before them (the coupled chains' continuation link: `gfmd.chains.COUPLED_CONTINUATION_STAGNATION`,
    # a stagnating Newton then breaks the step off as a jump does; 0: never)
    coupled_continuation_stagnation: float = 0.0
    # NCG line search: stop when |dE/dα| ≤ line_search_tol · |dE/dα(0)|
    line_search_tol: float = 0.1
    # hard-wall CG: release the wall nodes that pull away once their forces' norm exceeds
    # proportioning × the free nodes' residual norm (Dostál's MPRGP proportioning test)
    proportioning: float = 0.3
    # hard-wall CG: solve for the contact pressures (the dual CG) while the contact set holds at
    # most this fraction of the nodes (in (0, 1]), else for the displacements (the primal CG)
    dual_contact_limit: float = 0.15
    # dual hard-wall CG: coarse blocks of at most this many contact nodes in its two-level preconditioner
    # (`gfmd.algorithms.hard_wall_two_level_cg`); 0: the band preconditioner alone (`hard_wall_dual_cg`)
    dual_coarse_block: int = 16


def check_coupled_fire(settings):
    """Raise ValueError naming the Settings key for a coupled FIRE parameter out of range."""
    if not settings.coupled_dt_max > 0:
        raise ValueError(f"Settings.coupled_dt_max = {settings.coupled_dt_max!r}: expected a time step > 0")
    if not 0 < settings.coupled_f_dec < 1:
        raise ValueError(f"Settings.coupled_f_dec = {settings.coupled_f_dec!r}: expected a factor in (0, 1)")
    if isinstance(settings.coupled_n_min, bool) or not isinstance(settings.coupled_n_min, (int, np.integer)) \
            or settings.coupled_n_min < 0:
        raise ValueError(f"Settings.coupled_n_min = {settings.coupled_n_min!r}: expected a step count ≥ 0")


@dataclass
class Relaxed:
    """Equilibrium of one load step: fields on the N nodes (SI) and solver record.

    An algorithm that gives the step up for the next one of its chain (`gfmd.chains`) returns
    `stalled` (why) with its end state u_hat, iterations and FFT pairs; its fields may then be None.
    """

    u_hat: np.ndarray  # (c, N//2+1) rfft of u
    u_z: np.ndarray  # m
    u_x: np.ndarray  # m (zeros when not solved)
    gap: np.ndarray  # Δn (m)
    t_z: np.ndarray  # traction on the body (Pa), = T_n
    t_x: np.ndarray  # Pa, = T_t
    iterations: int
    residual: float  # max |r| / p_ref
    converged: bool
    message: str = ""
    fft_pairs: float = 0.0  # rfft+irfft pairs the relaxation used (0 where not counted)
    #: the algorithms that produced this state, joined by "→" where a fallback ran: "ncg", "ncg→fire",
    #: "fire", "verlet", "cg-dual2", "cg-dual2→cg", "cg-dual", "cg-dual→cg", "cg" (the dual handed
    #: over at once), "fire→newton", "fire→newton→verlet",
    #: "newton→fire→newton" (a handover chain's Newton finished FIRE's step)
    method: str = ""
    stalled: str = ""  # non-empty: the algorithm hands the step over to the next of its chain (why)


def stall(u_hat, iterations, residual, fft_pairs, method, reason):
    """A `Relaxed` without fields: the algorithm stopped early and hands over (`Relaxed.stalled`)."""
    return Relaxed(u_hat=u_hat, u_z=None, u_x=None, gap=None, t_z=None, t_x=None, iterations=iterations,
                   residual=float(residual), converged=False, fft_pairs=fft_pairs, method=method, stalled=reason)


def not_converged(iterations, residual):
    """The message of a step that used its iterations up."""
    return f"not converged after {iterations} iterations (residual {residual:.3g} p_ref)"
