"""Pseudo-transient continuation (Ψtc) on the coupled law's nodal balance (seed Eq. 2; the snap and slip event steps).

Ψtc (Kelley & Keyes 1998; Coffey, Kelley & Keyes 2003) follows the overdamped flow M du/dτ = f(u) by
implicit Euler steps with a pseudo-time step Δτ grown as the residual falls (switched evolution relaxation):
small Δτ follows the flow through a snap or slip event, large Δτ is Newton's step. The coupled chains
(`gfmd.chains`) run it as their last resort before damped Verlet, its state kept where locally stable; before FIRE,
or in FIRE's place as the handover link, it reached the same states at more cost (docs/design/solvers.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gfmd_contact.core import laws

from ..coupled_kernels import divided_blocks
from ..coupled_krylov import balance, forcing, spectral_step
from ..fft import Fft, spectral_weights
from ..problem import Elastic, stiffness_operator
from ..settings import stall
from ..stopping import finish

#: the name of this algorithm in `Relaxed.method`, result files and the chains (`gfmd.chains`)
LABEL = "ptc"


@dataclass(frozen=True)
class Options:
    """What Ψtc reads: the `gfmd.settings.Settings` fields of these names."""

    tolerance: float  # max nodal force residual / p_ref
    max_iterations: int


#: Ψtc iterations a step gets (each one GMRES solve and one force)
PTC_ITERATIONS = 100
#: first pseudo-time step and its cap, in units of the mass's time scale (Δτ = 1: σM equals the mass's stiffness).
#: Swept on the six fig8_small event steps (ν = 0.1, seeds 1 and 2, from the default chain's guesses; every converged
#: state FIRE's or Newton's to ≤ 1.5e-7 δn): Δτ₀ = 0.01 and 0.1 converged 1 and 5 of 6 in 100 iterations; 1, 3, 10,
#: 100 all 6 in 2 829, 2 014, 1 913, 1 704 FFT pairs in all. 10 keeps a few flow-like steps; 100 is Newton without a
#: line search from the guess.
PTC_DT_START = 10.0
PTC_DT_MAX = 1e12
#: smallest Δτ before the step is given up (GMRES misses or overflows keep halving it)
PTC_DT_MIN = 1e-6
#: largest nodal move per iteration in units of min(δn, δt), as Newton's trust region
PTC_MAX_MOVE = 2.0
#: the mass M: "modes", the FIRE mass per mode M_q = K(q) + ⟨k_loc⟩ (the flow equalises the elastic modes);
#: "nodes", a nodal identity scaled by that mass's diagonal (mean_q M_q per component). Measured (Δτ₀ = 0.1, the
#: six steps above): "nodes" converged none in 100 iterations (Δτ does not grow: the stiff modes' flow), "modes" 5.
PTC_MASS = "modes"


def solve(problem, start, options):
    """Ψtc on f(u) = t(u) − K u = 0 from `start`; `Relaxed` with method "ptc".

    Each iteration solves (σM + K + D) δu = f, σ = 1/Δτ, D the law's nodal tangent (as `coupled_newton`), by
    GMRES on the spectrum right-preconditioned by (σM + K)⁻¹, diagonal in q (`_shifted`), to Newton's forcing
    tolerance; the step is capped so that no node moves more than PTC_MAX_MOVE·min(δn, δt) and always taken
    (no decrease test: the flow may raise |f| through an event). Δτ_k = Δτ_{k−1} ‖f_{k−1}‖/‖f_k‖ (SER), not
    grown while the move cap cut the step, at most PTC_DT_MAX; a GMRES solve that misses its tolerance or a
    trial state in the law's overflow range halves Δτ and the iteration is retried. Stops on the solver's
    residual (max |f| < tolerance·p_ref); `stalled` (the chain goes on) after PTC_ITERATIONS or
    `max_iterations` iterations, when Δτ falls below PTC_DT_MIN, or on a start in the overflow range.
    `iterations` counts Ψtc iterations, `fft_pairs` every product.
    """
    model, law, z_ind = problem.model, problem.law, problem.z_ind
    fft = Fft(model.nodes, grid=model.grid)
    p_ref = model.reference_traction
    u_hat = np.array(start, dtype=complex, copy=True)
    clamp = model.half_plane
    if clamp:
        u_hat[:, 0] = 0.0
    stiff = stiffness_operator(model)
    max_move = PTC_MAX_MOVE * law.law.length_scale

    force = balance(law, z_ind, fft, stiff, clamp)  # uh ↦ (f̂, f, u)

    try:
        fh, f, u = force(u_hat)
    except laws.CompressionOverflowError as exc:
        return stall(u_hat, 0, np.inf, fft.pairs, LABEL, f"diverged: {exc}")  # no fields: `finish` would raise
    k_mean = law.mean_stiffness(u, z_ind)
    residual = float(np.max(np.abs(f))) / p_ref
    norm = float(np.linalg.norm(f))
    dt, it, message = PTC_DT_START, 0, ""
    budget = min(PTC_ITERATIONS, options.max_iterations)
    converged = residual < options.tolerance
    while not converged:
        if it >= budget:
            message = f"Ψtc not converged after {it} iterations (residual {residual:.3g} p_ref, Δτ {dt:.3g})"
            break
        if dt < PTC_DT_MIN:
            message = f"Ψtc pseudo-time step fell below {PTC_DT_MIN:g} (iteration {it}, residual {residual:.3g} p_ref)"
            break
        it += 1
        rtol = forcing(options.tolerance, residual)
        du_hat, info = spectral_step(model, law, z_ind, u, fh, _shifted(model, k_mean, 1.0 / dt), fft, rtol)
        if info != 0:  # the shifted tangent is near-singular or indefinite along the step: more mass
            dt *= 0.5
            continue
        du = fft.irfft(du_hat)
        largest = float(np.max(np.abs(du)))
        if not np.isfinite(largest) or largest == 0.0:
            message = f"Ψtc step not finite or zero (iteration {it}, residual {residual:.3g} p_ref)"
            break
        scale = min(1.0, max_move / largest)
        try:
            trial = force(u_hat + scale * du_hat)
        except laws.CompressionOverflowError:
            dt *= 0.5
            continue
        new_norm = float(np.linalg.norm(trial[1]))
        if not np.isfinite(new_norm):
            dt *= 0.5
            continue
        u_hat = u_hat + scale * du_hat
        fh, f, u = trial
        residual = float(np.max(np.abs(f))) / p_ref
        ser = dt * norm / max(new_norm, 1e-300)
        dt = min(PTC_DT_MAX, ser if scale == 1.0 else min(ser, dt))
        norm = new_norm
        converged = residual < options.tolerance
    return _out(problem, u_hat, it, residual, converged, message, fft)


def _shifted(model, k_mean, sigma):
    """`Elastic` whose `inv_mass` is (σM + K)⁻¹ per mode (the GMRES right preconditioner; `PTC_MASS`)."""
    k_x, k_z = k_mean
    if PTC_MASS == "nodes":  # M = diag(m_x, m_z) on every node, m the FIRE mass's nodal diagonal
        w = spectral_weights(model.nodes) / model.nodes
        m_z = float(np.sum(w * model.k_zz.real)) + k_z
        m_x = float(np.sum(w * model.k_xx.real)) + k_x if model.tangential else 0.0
        return Elastic(model, sigma * m_x, sigma * m_z)
    if PTC_MASS != "modes":
        raise ValueError(f"coupled_ptc.PTC_MASS = {PTC_MASS!r}: expected 'modes' or 'nodes'")
    # σ(K + k̄) + K = (1 + σ)(K + σ k̄ / (1 + σ))
    shifted = Elastic(model, sigma * k_x / (1.0 + sigma), sigma * k_z / (1.0 + sigma))
    shifted.inv_mass = divided_blocks(shifted.inv_mass, 1.0 + sigma)
    return shifted


def _out(problem, u_hat, it, residual, converged, message, fft):
    out = finish(problem, u_hat, it, residual, converged, message)
    out.fft_pairs = fft.pairs + 0.5
    out.method = LABEL
    out.stalled = "" if out.converged else out.message  # the chain may go on (`gfmd.chains`)
    return out
