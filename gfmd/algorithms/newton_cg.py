"""Normal-only cohesive law (a potential) by trust-region Newton–CG (Steihaug), the K⁻¹-preconditioned CG inside.

The Newton model of the energy E(u) = Σ_j [½ u_j (K u)_j + V(Δn_j)] (per node length, `gfmd.problem`) at û is
m(s) = −f·s + ½ sᵀ H s, H = K + diag(k_loc), k_loc = dT_n/dΔn (Eq. 3: (φn/δn²)(1 − s) e^{−s}, negative
beyond Δn = δn: the attractive tail makes H indefinite where patches are about to snap in). Steihaug's CG
minimises m inside the trust region ‖s‖_K ≤ Δ (the preconditioner's norm), stopping on the boundary when
it meets negative curvature or leaves the region, or inside when the residual falls below the forcing
term. The step is kept where the energy falls by at least TR_ACCEPT of what the model predicts; otherwise a
backtracking along it (Armijo, FFT-free: the trial gaps are Δn − α s) keeps the CG's work; Δ grows or
shrinks by the usual ratio test (Nocedal & Wright, Alg. 4.1 and 7.2).

Measured (issue 24, benchmarks/results/bench_adhesion_scaling_full.md, φn* = 0.15 on the seed ramp): 49.7 FFT
pairs per step at N = 2^17 against the NCG's 44.2 (max 338 vs 238): the inner CG's K⁻¹ preconditioning of
H = K + diag(k_loc) costs what the NCG's iterations cost, and the snap-in steps take more Newton iterations
than NCG iterations. Hence opt-in (Settings.cohesive = "newton-cg"), not the default.
"""

from __future__ import annotations

import numpy as np

from contact import laws

from ..fft import Fft, dot, spectral_weights
from ..settings import stall
from ..stopping import finish

#: Newton iterations per step before the step is handed over (`gfmd.chains`: NCG then FIRE)
NEWTON_CG_ITERATIONS = 60
#: CG iterations (Hessian products, one FFT pair each) per Newton iteration
NEWTON_CG_INNER = 400
#: forcing term: the inner CG stops at ‖r‖ ≤ η ‖f‖ (K⁻¹-norms), η = min(NEWTON_CG_ETA, (‖f‖/‖f₀‖)^½)
NEWTON_CG_ETA = 0.5
#: trust region: keep a step where (actual / predicted decrease) ≥ TR_ACCEPT; shrink below TR_SHRINK,
#: grow (×2) above TR_GROW on the boundary; the first radius is TR_START ‖K⁻¹f‖_K
TR_ACCEPT, TR_SHRINK, TR_GROW, TR_START = 1e-4, 0.25, 0.75, 10.0
#: a radius below this fraction of the first one is a stall
TR_FLOOR = 1e-10
#: relative round-off of the energy difference E(u) − E(u + s) (a sum over N nodes of differences of V):
#: where the model's decrease is below it, the ratio test cannot judge the step, and the step is taken
ENERGY_ROUNDOFF = 1e-13


def solve(problem, start, settings):
    """Relax one step of the normal-only cohesive law by trust-region Newton–CG (module docstring).

    Spectral unknowns û (rfft, the q = 0 mode clamped on a half-plane); the Hessian product
    H p̂ = K p̂ + rfft(k_loc · irfft p̂) costs one FFT pair (it is `gfmd.problem.Problem.tangent_times` on the
    spectrum; tests/test_newton_cg.py checks the two agree); the preconditioner K⁻¹ is diagonal on the
    modes. Stopping test: `gfmd.algorithms.dynamics`'s, max_j |f_j| < tolerance · p_ref, after every
    Newton iteration. Stall (`Relaxed.stalled`, the chain's next link restarts from the guess): not
    converged within NEWTON_CG_ITERATIONS, the CG budget min(max_iterations, …) used up, or the radius
    collapsed (no step lowers E). `iterations` counts Hessian products plus Newton iterations.
    """
    model, law, z_ind = problem.model, problem.law, problem.z_ind
    n = model.nodes
    fft = Fft(n)
    clamp = model.half_plane
    cz = law.law
    p_ref = model.reference_traction
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)
    w = spectral_weights(n) / n  # Σ_j a_j b_j = Σ_q w_q Re(conj(â_q) b̂_q)
    g = np.zeros(k.size)
    np.divide(1.0, k, out=g, where=k > 0)
    if clamp:
        g[0] = 0.0
    wk, wg = w * k, w * g

    def sdot(a, b, weight=w):
        return float(np.sum(weight * (a.real * b.real + a.imag * b.imag)))

    guess = np.array(start, dtype=complex, copy=True)
    uh = guess[-1].copy()
    if clamp:
        uh[0] = 0.0

    def state(u_spec):
        """(gap, T_n, k_loc, V) at û, or None outside the law's range; one irfft."""
        gap = z_ind - fft.irfft(u_spec)
        try:
            t, _ = cz.tractions(gap, None)
            stiff = cz.tangent(gap, None)[0]
            v = cz.potential(gap)
        except laws.CompressionOverflowError:
            return None
        return gap, np.asarray(t, float), np.asarray(stiff, float), np.asarray(v, float)

    def force_hat(t):
        fh = fft.rfft(t) - k * uh
        if clamp:
            fh[0] = 0.0
        return fh

    first = state(uh)
    if first is None:
        laws._check_compression(z_ind - fft.irfft(uh), float(cz.length_scale))  # raises, as FIRE's start does
    gap, t, kloc, v = first
    f_hat = force_hat(t)
    budget = max(1, settings.max_iterations)
    products, newton, residual, radius, radius0, f0 = 0, 0, np.inf, None, None, None
    failed, converged = "", False
    while True:
        residual = float(np.max(np.abs(fft.irfft(f_hat)))) / p_ref
        if residual < settings.tolerance:
            converged = True
            break
        if not np.isfinite(residual):
            failed = "non-finite force residual"
            break
        if newton >= NEWTON_CG_ITERATIONS or products >= budget:
            failed = f"not converged after {newton} Newton iterations, {products} Hessian products " \
                     f"(residual {residual:.3g} p_ref)"
            break
        newton += 1
        f_norm = np.sqrt(max(sdot(f_hat, f_hat, wg), 0.0))  # ‖f‖_{K⁻¹}
        if radius is None:
            radius = radius0 = TR_START * f_norm
            f0 = f_norm
        eta = min(NEWTON_CG_ETA, np.sqrt(f_norm / f0))
        # no inner accuracy beyond what the max-norm test needs: ‖r‖_{K⁻¹} ≤ ½ tolerance·p_ref ‖f‖_{K⁻¹}/max|f|
        floor = 0.5 * settings.tolerance * p_ref * f_norm / (residual * p_ref)
        s, model_drop, used, boundary = _steihaug(f_hat, kloc, k, g, w, wk, wg, radius, max(eta * f_norm, floor),
                                                  min(NEWTON_CG_INNER, budget - products), fft, clamp, sdot)
        products += used
        s_nodes = fft.irfft(s)  # the trial gaps Δn − α s need no further FFT
        a1, a2 = sdot(s, k * uh), sdot(s, s, wk)  # s·K u, s·K s

        def drop_at(alpha):
            """E(u) − E(u + α s): Σ_j V differences on the nodes, no cancellation of large E's; −inf out of range."""
            trial_gap = gap - alpha * s_nodes
            try:
                dv = float(np.sum(cz.potential(trial_gap) - v))
            except laws.CompressionOverflowError:
                return -np.inf, trial_gap
            return -(alpha * a1 + 0.5 * alpha * alpha * a2 + dv), trial_gap

        actual, trial_gap = drop_at(1.0)
        rho = actual / model_drop if model_drop > 0 else -np.inf
        noise = ENERGY_ROUNDOFF * (float(np.sum(np.abs(v))) + abs(a1))  # the energy difference's round-off
        if np.isfinite(actual) and 0 < model_drop < noise:  # below it ρ is noise: the model is trusted
            rho = 1.0
        alpha = 1.0
        if not rho >= TR_ACCEPT:  # backtrack along s (Armijo, quadratic interpolation): the CG's work is kept
            slope = -sdot(s, f_hat)  # dE/dα at 0
            alpha, actual = _backtrack(drop_at, slope) if slope < 0 else (0.0, 0.0)
            if alpha > 0:
                trial_gap = drop_at(alpha)[1]
        s_norm = np.sqrt(max(a2, 0.0))
        if rho < TR_SHRINK:
            radius = max(0.25, alpha) * s_norm if alpha > 0 else 0.25 * s_norm
        elif rho > TR_GROW and boundary:
            radius = 2.0 * radius
        if alpha > 0:
            uh = uh + alpha * s
            gap = trial_gap
            t, _ = cz.tractions(gap, None)
            kloc, v = cz.tangent(gap, None)[0], cz.potential(gap)
            f_hat = force_hat(t)
        elif radius <= TR_FLOOR * radius0:
            failed = f"trust region collapsed (no step lowers the energy; residual {residual:.3g} p_ref)"
            break
    if failed:
        return stall(guess, products + newton, residual, fft.pairs, "newton-cg", f"Newton–CG stopped ({failed})")
    pairs = fft.pairs
    out = finish(problem, uh[None, :], products + newton, residual, converged, "")
    out.fft_pairs = pairs + 0.5
    out.method = "newton-cg"
    return out


def _backtrack(drop_at, slope, shrink=(0.1, 0.5), tries=30):
    """(α, E(u) − E(u + α s)): the largest α of a backtracking from 1 with E(u + αs) ≤ E(u) + 1e-4 α slope
    (slope = dE/dα(0) < 0; each trial the minimiser of the quadratic through E(0), slope, E(α), kept
    within shrink · α); (0, 0) if none."""
    alpha = 1.0
    for _ in range(tries):
        drop, _ = drop_at(alpha)
        if drop >= -1e-4 * alpha * slope:
            return alpha, drop
        curv = 2.0 * (-drop - slope * alpha) / (alpha * alpha) if np.isfinite(drop) else np.inf
        nxt = -slope / curv if curv > 0 and np.isfinite(curv) else shrink[0] * alpha
        alpha = min(max(nxt, shrink[0] * alpha), shrink[1] * alpha)
    return 0.0, 0.0


def _steihaug(f_hat, kloc, k, g, w, wm, wg, radius, tol, max_products, fft, clamp, sdot):
    """Steihaug's CG on H s = f in ‖s‖_K ≤ radius, preconditioned by K⁻¹: (ŝ, m(0) − m(s), products, on boundary).

    Stops at ‖r‖_{K⁻¹} ≤ tol, on the boundary where pᵀHp ≤ 0 (negative curvature: the model falls without
    bound along p) or where the next iterate would leave the region, or after max_products.
    """
    s = np.zeros_like(f_hat)
    r = f_hat.copy()
    z = g * r
    p = z.copy()
    rz = sdot(r, z)
    drop = 0.0  # m(0) − m(s), tracked exactly: m(s + αp) = m(s) − α p·r + ½ α² pᵀHp
    ss, used = 0.0, 0  # ‖s‖_K²
    while used < max_products:
        p_nodes = fft.irfft(p)
        hp = k * p + fft.rfft(kloc * p_nodes)
        if clamp:
            hp[0] = 0.0
        used += 1
        php = sdot(p, p, w * k) + dot(kloc * p_nodes, p_nodes)
        pr = sdot(p, r)
        sp, pp = sdot(s, p, wm), sdot(p, p, wm)
        if php <= 0.0:  # negative curvature: to the boundary along p
            tau = _to_boundary(ss, sp, pp, radius)
            return s + tau * p, drop + tau * pr - 0.5 * tau * tau * php, used, True
        alpha = rz / php
        if ss + 2 * alpha * sp + alpha * alpha * pp >= radius * radius:  # leaves the region
            tau = _to_boundary(ss, sp, pp, radius)
            return s + tau * p, drop + tau * pr - 0.5 * tau * tau * php, used, True
        s += alpha * p
        drop += alpha * pr - 0.5 * alpha * alpha * php
        ss = sdot(s, s, wm)
        r -= alpha * hp
        z = g * r
        rz_new = sdot(r, z)
        if np.sqrt(max(rz_new, 0.0)) <= tol:
            break
        p *= rz_new / rz
        p += z
        rz = rz_new
    return s, drop, used, False


def _to_boundary(ss, sp, pp, radius):
    """τ ≥ 0 with ‖s + τ p‖_K = radius (ss = ‖s‖², sp = s·p, pp = ‖p‖², K-inner products)."""
    if pp <= 0.0:
        return 0.0
    disc = sp * sp + pp * (radius * radius - ss)
    return (-sp + np.sqrt(max(disc, 0.0))) / pp
