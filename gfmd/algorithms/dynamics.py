"""FIRE and damped Verlet on a law with a traction function (normal CZ, coupled law; reference-formulas §5.2).

* ``fire`` (`settings.method`): FIRE (Bitzek et al. 2006, with the FIRE 2.0 back-step) on
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

from dataclasses import replace

import numpy as np

from gfmd_contact.core import laws

from ..fft import Fft, spectral_weights
from ..fire_kernels import fire_kernels, largest_change
from ..integrators import Fire, verlet_coefficients
from ..problem import Elastic, stiffness_operator
from ..settings import check_coupled_fire, not_converged
from ..stopping import finish


def solve(problem, start, settings):
    """Relax a law with a traction function by FIRE (`settings.method` "fire") or damped Verlet ("verlet")."""
    model, law, z_ind, wall_tolerance = problem.model, problem.law, problem.z_ind, problem.wall_tolerance
    u_hat = start  # the step's initial displacements (c, N//2+1), rfft
    n = model.nodes
    fft = Fft(n, grid=model.grid)
    w = spectral_weights(model.grid)
    u_hat = np.array(u_hat, dtype=complex, copy=True)
    if model.half_plane:
        u_hat[:, 0] = 0.0
    v = np.zeros_like(u_hat)
    k_mean = law.mean_stiffness(fft.irfft(u_hat), z_ind)
    elastic = Elastic(model, *k_mean)

    force_power, accelerate, mix_move = fire_kernels(components=model.components)
    # K(q)'s blocks, made once per model (`stiffness_operator`)
    stiffness = stiffness_operator(model).stiffness_blocks if model.tangential else (model.k_zz,)
    acc = np.empty_like(u_hat)

    if settings.method != "verlet" and problem.kind == "coupled":  # FIRE's Δt capped, its restarts milder (`Settings`)
        check_coupled_fire(settings)
        settings = replace(settings, dt_max=min(settings.dt_max, settings.coupled_dt_max),
                           f_dec=settings.coupled_f_dec, n_min=settings.coupled_n_min)
    fire = None if settings.method == "verlet" else Fire(settings)
    if fire is None:  # Verlet: per-mode ω² from the diagonal stiffness plus the law's initial slope
        k_diag = [model.k_zz] if not model.tangential else [model.k_xx.real, model.k_zz]
        k_int = [law.k_int_z] if not model.tangential else [law.k_int_x, law.k_int_z]
        rho, gdt = verlet_coefficients(np.stack([k + ki for k, ki in zip(k_diag, k_int)]), settings)
    dt = fire.dt if fire else 1.0

    residual = np.inf
    message = ""
    converged = False
    it = 0
    max_move = settings.max_move * law.law.length_scale  # min(δn, δt) where u_x is solved, else δn
    change = largest_change()
    kept = [u_hat.copy(), u_hat.copy()]  # û at the last two iterations' starts, alternately (no copy allocated)
    u_hat_prev = _last_finite = kept[0]
    u_prev = fft.irfft(u_hat)
    for it in range(1, settings.max_iterations + 1):
        u = fft.irfft(u_hat)
        move = change(u, u_prev)
        if move > max_move:  # trust region: no node moves more than max_move per iteration
            scale = max_move / move
            u_hat = u_hat_prev + scale * (u_hat - u_hat_prev)
            u = u_prev + scale * (u - u_prev)
            v *= scale
            if fire:
                fire.dt *= settings.f_dec
        u_hat_prev = kept[it % 2]  # the buffer not holding _last_finite
        np.copyto(u_hat_prev, u_hat)
        u_prev = u
        try:
            t, _ = law.traction(u, z_ind)
        except laws.CompressionOverflowError as exc:
            message = f"diverged: {exc}"
            u_hat = _last_finite
            break
        _last_finite = u_hat_prev  # (a copy of û, rewritten only two iterations on)
        if fire and it % settings.mass_refresh == 0:
            k_now = law.mean_stiffness(u, z_ind)
            if any(b > 2 * a + 1e-300 or a > 2 * b + 1e-300 for a, b in zip(k_mean, k_now)):
                k_mean = k_now  # interface stiffness changed 2×: re-weight the modes, restart FIRE
                elastic = Elastic(model, *k_mean)
                v[:] = 0.0
                fire.reset()
        f_hat = fft.rfft(t)
        if fire is None:
            f_hat -= elastic.stiffness(u_hat)
            if elastic.clamp:
                f_hat[:, 0] = 0.0
        else:  # f̂ = t̂ − K û (q = 0 clamped) and FIRE's power f·v in one pass (`gfmd.fire_kernels`)
            power = force_power(f_hat, stiffness, u_hat, v, w, elastic.clamp)
        if it % settings.check_every == 0 or it == 1:
            residual = float(np.max(np.abs(fft.irfft(f_hat)))) / model.reference_traction
            if residual < settings.tolerance:
                converged = True
                break
            if not np.isfinite(residual):
                message = "diverged: non-finite force residual"
                break
        if fire is None:
            v = ((1 - gdt / 2) * v + dt * f_hat / rho) / (1 + gdt / 2)
            if elastic.clamp:
                v[:, 0] = 0.0
            u_hat += dt * v
        else:
            restart = fire.adapt(power)
            dt = fire.dt
            if restart:
                u_hat -= 0.5 * dt * v
                v[:] = 0.0
            acc, f_norm, v_norm = accelerate(f_hat, elastic.inv_mass, elastic.mass, v, dt, w, acc)  # v += Δt M⁻¹f
            keep, beta = 1.0, 0.0
            if f_norm > 0:
                keep, beta = 1 - fire.alpha, fire.alpha * np.sqrt(max(v_norm, 0.0) / f_norm)
            mix_move(v, acc, keep, beta, u_hat, dt, elastic.clamp)  # v ← keep v + β M⁻¹f, û += Δt v
    else:
        message = not_converged(settings.max_iterations, residual)

    pairs = fft.pairs
    out = finish(problem, u_hat, it, residual, converged, message)
    out.fft_pairs = pairs + 0.5
    out.method = "verlet" if fire is None else "fire"
    out.stalled = "" if out.converged else out.message  # the chain may go on (`gfmd.chains`)
    return out

