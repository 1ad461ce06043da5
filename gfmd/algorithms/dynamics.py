"""FIRE and damped Verlet on a law with a traction function (normal CZ, coupled law; reference-formulas §5.2).

* ``fire`` (`options.method`): FIRE (Bitzek et al. 2006, with the FIRE 2.0 back-step) on
  mass-weighted modes, M_q = K(q) + ⟨k_loc⟩·I, so that every free elastic mode has the same
  frequency and the interface stiffness, averaged over the cell as long waves see it (⟨∂T/∂Δ⟩
  from the law's tangent, refreshed when it changes by 2×), does not slow or destabilise them.
  A trust region limits every nodal move per iteration to `max_move`·min(δn, δt). On the coupled law Δt is
  capped at `coupled_dt_max` (a compressed contact patch's stability) and a restart cuts Δt by `coupled_f_dec`, its
  regrowth waiting `coupled_n_min` steps (`gfmd.settings`).
* ``verlet``: the seed's damped Störmer–Verlet, uniform mass, every mode damped critically for
  the discrete scheme (γΔt = ωΔt√(4 − (ωΔt)²), `gfmd.integrators.verlet_coefficients`).

Stops on `gfmd.stopping`'s residual, max_j |f_j| < tolerance·p_ref, taken every `check_every`
iterations.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from gfmd_contact.core import laws

from ..fft import Fft, spectral_weights
from ..fire_kernels import fire_kernels, largest_change
from ..integrators import DynamicsOptions, Fire, verlet_coefficients
from ..problem import Elastic, stiffness_operator
from ..settings import check_coupled_fire, not_converged
from ..stopping import finish


@dataclass(frozen=True)
class Options(DynamicsOptions):
    """What it reads: FIRE's and Verlet's options, the largest nodal move and the mass refresh, and the coupled
    law's FIRE (`Settings.coupled_dt_max`, `coupled_f_dec`, `coupled_n_min`)."""

    max_move: float  # largest nodal move per iteration, in law lengths
    mass_refresh: int  # iterations between re-evaluations of the mean interface stiffness
    coupled_dt_max: float
    coupled_f_dec: float
    coupled_n_min: int


def solve(problem, start, options):
    """Relax a law with a traction function by FIRE (`options.method` "fire") or damped Verlet ("verlet")."""
    model = problem.model
    dyn = _setup(problem, options)
    state = _init(dyn, start)
    while state.it < options.max_iterations:
        state.it += 1
        f_hat = _force(dyn, state)
        if f_hat is None:  # the law overflowed: the last finite state is kept
            break
        if state.it % options.check_every == 0 or state.it == 1:
            state.residual = residual = float(np.max(np.abs(dyn.fft.irfft(f_hat)))) / model.reference_traction
            if residual < options.tolerance:
                state.converged = True
                break
            if not np.isfinite(residual):
                state.message = "diverged: non-finite force residual"
                break
        _move(dyn, state, f_hat)
    if not state.converged and not state.message:
        state.message = not_converged(options.max_iterations, state.residual)
    pairs = dyn.fft.pairs
    out = finish(problem, state.u_hat, state.it, state.residual, state.converged, state.message)
    out.fft_pairs = pairs + 0.5
    out.method = "verlet" if state.fire is None else "fire"
    out.stalled = "" if out.converged else out.message  # the chain may go on (`gfmd.chains`)
    return out


class _Dynamics(NamedTuple):
    """What one step's dynamics hold fixed."""

    model: object
    law: object
    z_ind: np.ndarray
    options: object  # the coupled law's FIRE: Δt capped, restarts milder
    fft: Fft
    w: np.ndarray  # the half-spectrum's weights (`gfmd.fft.spectral_weights`)
    force_power: object  # `gfmd.fire_kernels`
    accelerate: object
    mix_move: object
    stiffness: tuple  # K(q)'s blocks
    verlet: tuple | None  # Verlet's (ρ, γ dt) per mode; None under FIRE
    max_move: float  # the trust region (m): min(δn, δt) where u_x is solved, else δn
    change: object  # `gfmd.fire_kernels.largest_change`


@dataclass
class DynamicsState:
    """The dynamics' iterate: û and v̂, the mass weighting, FIRE's own state and the trust region's last states."""

    u_hat: np.ndarray
    v: np.ndarray
    k_mean: tuple  # ⟨∂T/∂Δ⟩ the mass was built with
    elastic: Elastic  # the mass-weighted operator of k_mean
    fire: Fire | None  # None: Verlet
    dt: float
    acc: np.ndarray  # M⁻¹ f̂ (`accelerate`'s output buffer)
    kept: list  # û at the last two iterations' starts, alternately (no copy allocated)
    u_hat_prev: np.ndarray  # û at this iteration's start (one of `kept`)
    last_finite: np.ndarray  # the last û the law evaluated (a copy, rewritten only two iterations on)
    u_prev: np.ndarray  # u at this iteration's start
    power: float = 0.0  # FIRE's f·v
    it: int = 0
    residual: float = np.inf
    converged: bool = False
    message: str = ""


def _setup(problem, options):
    model, law = problem.model, problem.law
    force_power, accelerate, mix_move = fire_kernels(components=model.components)
    # K(q)'s blocks, made once per model (`stiffness_operator`)
    stiffness = stiffness_operator(model).stiffness_blocks if model.tangential else (model.k_zz,)
    if options.method != "verlet" and problem.kind == "coupled":  # FIRE's Δt capped, its restarts milder (`Settings`)
        check_coupled_fire(options)
        options = replace(options, dt_max=min(options.dt_max, options.coupled_dt_max),
                           f_dec=options.coupled_f_dec, n_min=options.coupled_n_min)
    verlet = None
    if options.method == "verlet":  # per-mode ω² from the diagonal stiffness plus the law's initial slope
        k_diag = [model.k_zz] if not model.tangential else [model.k_xx.real, model.k_zz]
        k_int = [law.k_int_z] if not model.tangential else [law.k_int_x, law.k_int_z]
        verlet = verlet_coefficients(np.stack([k + ki for k, ki in zip(k_diag, k_int)]), options)
    return _Dynamics(model=model, law=law, z_ind=problem.z_ind, options=options,
                     fft=Fft(model.nodes, grid=model.grid), w=spectral_weights(model.grid),
                     force_power=force_power, accelerate=accelerate, mix_move=mix_move, stiffness=stiffness,
                     verlet=verlet, max_move=options.max_move * law.law.length_scale, change=largest_change())


def _init(dyn, start):
    """The start (half-plane: the q = 0 modes clamped) at rest, its mass weighting and FIRE."""
    model, options, fft = dyn.model, dyn.options, dyn.fft
    u_hat = np.array(start, dtype=complex, copy=True)
    if model.half_plane:
        u_hat[:, 0] = 0.0
    k_mean = dyn.law.mean_stiffness(fft.irfft(u_hat), dyn.z_ind)
    fire = None if options.method == "verlet" else Fire(options)
    kept = [u_hat.copy(), u_hat.copy()]
    return DynamicsState(u_hat=u_hat, v=np.zeros_like(u_hat), k_mean=k_mean, elastic=Elastic(model, *k_mean),
                         fire=fire, dt=fire.dt if fire else 1.0, acc=np.empty_like(u_hat), kept=kept,
                         u_hat_prev=kept[0], last_finite=kept[0], u_prev=fft.irfft(u_hat))


def _force(dyn, state):
    """f̂ = t̂ − K û (q = 0 clamped) after the trust region and the mass refresh; FIRE: with its power f·v in
    one pass (`gfmd.fire_kernels`). None (the message set, û the last finite) where the law overflows."""
    options, fire = dyn.options, state.fire
    u = _trust_region(dyn, state)
    try:
        t, _ = dyn.law.traction(u, dyn.z_ind)
    except laws.CompressionOverflowError as exc:
        state.message = f"diverged: {exc}"
        state.u_hat = state.last_finite
        return None
    state.last_finite = state.u_hat_prev
    if fire and state.it % options.mass_refresh == 0:
        _refresh_mass(dyn, state, u)
    f_hat = dyn.fft.rfft(t)
    if fire is None:
        f_hat -= state.elastic.stiffness(state.u_hat)
        if state.elastic.clamp:
            f_hat[:, 0] = 0.0
    else:
        state.power = dyn.force_power(f_hat, dyn.stiffness, state.u_hat, state.v, dyn.w, state.elastic.clamp)
    return f_hat


def _trust_region(dyn, state):
    """u of û, scaled back (with v) so that no node moves more than max_move per iteration; keeps û and u as
    the next iteration's start."""
    u = dyn.fft.irfft(state.u_hat)
    u_prev, u_hat_prev = state.u_prev, state.u_hat_prev
    move = dyn.change(u, u_prev)
    if move > dyn.max_move:
        scale = dyn.max_move / move
        state.u_hat = u_hat_prev + scale * (state.u_hat - u_hat_prev)
        u = u_prev + scale * (u - u_prev)
        state.v *= scale
        if state.fire:
            state.fire.dt *= dyn.options.f_dec
    state.u_hat_prev = state.kept[state.it % 2]  # the buffer not holding last_finite
    np.copyto(state.u_hat_prev, state.u_hat)
    state.u_prev = u
    return u


def _refresh_mass(dyn, state, u):
    """Where the interface stiffness changed 2×: re-weight the modes, restart FIRE."""
    k_now = dyn.law.mean_stiffness(u, dyn.z_ind)
    if any(b > 2 * a + 1e-300 or a > 2 * b + 1e-300 for a, b in zip(state.k_mean, k_now)):
        state.k_mean = k_now
        state.elastic = Elastic(dyn.model, *k_now)
        state.v[:] = 0.0
        state.fire.reset()


def _move(dyn, state, f_hat):
    """One move of û and v̂: damped Verlet, or FIRE (v += Δt M⁻¹f, v ← keep v + β M⁻¹f, û += Δt v)."""
    fire, v, clamp = state.fire, state.v, state.elastic.clamp
    if fire is None:
        rho, gdt = dyn.verlet
        dt = state.dt
        v = ((1 - gdt / 2) * v + dt * f_hat / rho) / (1 + gdt / 2)
        if clamp:
            v[:, 0] = 0.0
        state.v = v
        state.u_hat += dt * v
        return
    restart = fire.adapt(state.power)
    state.dt = dt = fire.dt
    if restart:
        state.u_hat -= 0.5 * dt * v
        v[:] = 0.0
    state.acc, f_norm, v_norm = dyn.accelerate(f_hat, state.elastic.inv_mass, state.elastic.mass, v, dt, dyn.w,
                                               state.acc)
    keep, beta = 1.0, 0.0
    if f_norm > 0:
        keep, beta = 1 - fire.alpha, fire.alpha * np.sqrt(max(v_norm, 0.0) / f_norm)
    dyn.mix_move(v, state.acc, keep, beta, state.u_hat, dt, clamp)
