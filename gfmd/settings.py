"""What every GFMD algorithm takes and returns: `Settings` (its parameters) and `Relaxed` (one step's state).

Units: SI (see `gfmd_contact.core.conventions`); the integrators' parameters are dimensionless (time unit 1/ω0,
ω0 = 1). Which algorithm runs is `gfmd.chains`' choice from `Settings.method`, `hard_wall`, `cohesive`
and `dual_contact_limit`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Settings:
    """Integrator parameters (dimensionless; time unit 1/ω0 with ω0 = 1)."""

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
    # cohesive normal-only law (a potential) with method "fire": "ncg" (nonlinear preconditioned CG with
    # a Newton line search, FIRE as fallback) or "fire" (FIRE alone, the integrator before issue 13)
    cohesive: str = "ncg"
    # coupled law (seed Eq. 2) with method "fire": "auto" (default since session 40: "frictionless-first" on a body
    # that barely couples u_x and u_z, `gfmd.coupled_rules.COUPLED_FRICTIONLESS_COUPLING`, else "handover-near"),
    # "frictionless-first" (Newton–Krylov first, else the frictionless reduction's NCG through the event and Newton from
    # there, kept where no node moved a law length from it, else as "handover-near"), "handover-near" (the default of sessions 26–39: Newton–Krylov first,
    # its state kept as a continuation of the ramp's branch, else FIRE to `coupled_handover` and Newton–Krylov from
    # there, kept near FIRE's state, else the "fire" chain), "newton" (the default of issue 24: the continuation,
    # else the "fire" chain), "handover" (as "handover-near", the handed-over state also stability-tested), "ptc"
    # (as "newton", pseudo-transient continuation before FIRE), "ncg-first" (as "handover-near" with the coupled NCG,
    # `gfmd.algorithms.coupled_ncg`, to `coupled_handover` before FIRE; measured, session 52) or "fire" (FIRE;
    # Newton–Krylov, then Verlet after a stall); measured in `gfmd.chains`
    coupled: str = "auto"
    # the handover chains: FIRE stops at this residual (× p_ref) and Newton–Krylov finishes from there, its state kept
    # only near FIRE's (and, "handover", locally stable), else FIRE goes on (`gfmd.chains`). An earlier handover tried
    # first (Newton from FIRE's state at 1e-2 or 1e-3, kept near it, else FIRE on to 1e-4) was measured and dropped
    # (session 45, ν = 0.1, c = 0.5, 2^15, seed 2, one ad hoc ramp each, no bench file kept): the same states, but FFT
    # pairs 17 268 → 23 120 (1e-2) and 20 949 (1e-3, 20 of 28 events kept there): Newton from a looser state costs
    # more GMRES products than FIRE's rest of the way. Re-measured after session 50's nodal Newton (session 51, the same
    # scene, seeds 2 and 3, whole ramps, FFT pairs against 1e-4's 14 666 and 14 827): 1e-3 +15.7 %, +5.1 %; 3e-4 −1.9 %,
    # +0.7 %; 3e-5 (seed 2) +2.6 %; every p̄ within 9e-8 of max p̄ (the same branches).
    coupled_handover: float = 1e-4
    # coupled law: FIRE's largest time step Δt (in place of dt_max, 1.0, which the other laws' FIRE keeps). Near Δt ≈ 0.5
    # a compressed contact patch (local tangent ≈ 0.2 of the half-plane's self-stiffness, far above the cell mean that
    # the mass M_q = K(q) + ⟨k_loc⟩ holds) oscillates unstably: on the coupled event steps FIRE restarted (P ≤ 0), halved
    # Δt three times and grew it back every ≈ 30 iterations, so the slow crawl through a fold's ghost lost its speed
    # at every restart. Measured on whole ramps (benchmarks/results/bench_coupled_dt_max_*.md, the same states): the
    # event steps' FFT pairs are least at 0.4 of 0.2–1.0 (ν = 0.1, 2^13 and 2^15: −44 %, −40 % against 1.0; ν = 0.45,
    # 2^15: −27 %, 0.5 within 0.2 %); at 2^17 (seed 2) the event steps' CPU −41 % (ν = 0.1), −28 % (ν = 0.45). Fig. 8
    # whole (studies/results/seed_full/README.md): coupled task medians −22 % and −11 % on a 1.16–1.34× slower machine,
    # 11 of 804 mean steps on another branch at an event step (≤ 1 % of max p̄), the same verdicts
    coupled_dt_max: float = 0.4
    # coupled law: FIRE's f_dec and n_min, here the other laws' (Bitzek et al.). Milder restarts with Δt capped (f_dec
    # 0.7–0.9, n_min 1–2) cut the event steps' FFT pairs by 7–9 % on whole ramps at 2^13 and 2^15 (seed 2, ν = 0.1 and
    # 0.45, the same states; benchmarks/results/bench_coupled_fire_restarts_*.md), but on fig8_small (2^12) one event
    # step then runs FIRE's whole budget (476 → 4 030 iterations, the ramp 3 266 → 6 620–6 750): not the default
    # (tests/test_coupled_fire_restarts.py)
    coupled_f_dec: float = 0.5
    coupled_n_min: int = 5
    # cohesive NCG's preconditioner (`gfmd.cohesive_preconditioner`): "auto" ("two-level" on a profile with Eq. 3's
    # law, else "stiffness"), "stiffness" (K⁻¹ on the modes) or "two-level" (K⁻¹ balanced by a coarse space on the
    # stiff patches, engaged on the steps that need it)
    cohesive_preconditioner: str = "auto"
    # coupled Newton–Krylov: give the step up at the first GMRES solve that misses its tolerance (True: the
    # Newton-first chain's continuation link, `gfmd.chains`; False: go on with the inexact direction)
    coupled_gmres_give_up: bool = False
    # coupled Newton–Krylov: give the step up once an iterate has moved a node this many law lengths (min(δn, δt))
    # from its start (the Newton-first chain's continuation link: `gfmd.chains.COUPLED_JUMP`, the move its
    # acceptance test rejects; 0: never)
    coupled_continuation_jump: float = 0.0
    # coupled Newton–Krylov: give the step up after this many iterations (the Newton-first chain's continuation link:
    # `gfmd.chains.COUPLED_CONTINUATION_ITERATIONS`; 0: `gfmd.algorithms.coupled_newton.COUPLED_NEWTON_ITERATIONS`)
    coupled_continuation_iterations: int = 0
    # coupled Newton–Krylov: each GMRES solve gets this many restart cycles (the Newton-first chain's continuation
    # link: `gfmd.chains.COUPLED_CONTINUATION_GMRES_CYCLES`, a miss then breaks the step off as a jump does;
    # 0: `gfmd.algorithms.coupled_newton.COUPLED_GMRES_CYCLES`)
    coupled_continuation_gmres_cycles: int = 0
    # coupled Newton–Krylov: give the step up once two iterations in a row each left more than this fraction of the
    # residual before them (the Newton-first chain's continuation link: `gfmd.chains.COUPLED_CONTINUATION_STAGNATION`,
    # a stagnating Newton then breaks the step off as a jump does; 0: never)
    coupled_continuation_stagnation: float = 0.0
    # NCG line search: stop when |dE/dα| ≤ line_search_tol · |dE/dα(0)|
    line_search_tol: float = 0.1
    # hard-wall CG: release the wall nodes that pull away once their forces' norm exceeds
    # proportioning × the free nodes' residual norm (Dostál's MPRGP proportioning test)
    proportioning: float = 0.3
    # hard-wall CG: solve for the contact pressures (the dual CG) while the contact set holds at
    # most this fraction of the nodes, else for the displacements (the primal CG); 0: always the latter
    dual_contact_limit: float = 0.15
    # dual hard-wall CG: coarse blocks of at most this many contact nodes in its two-level preconditioner
    # (`gfmd.algorithms.hard_wall_two_level_cg`); 0: the band preconditioner alone (`hard_wall_dual_cg`,
    # the default before issue 24)
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
    #: "fire", "verlet", "cg-dual2", "cg-dual2→cg", "cg-dual", "cg-dual→cg", "cg", "fire→newton", "fire→newton→verlet",
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
