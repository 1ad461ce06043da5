"""Nonlinear conjugate directions on the coupled law's force field (seed Eq. 2; no potential): the NCG's line search
across a snap without an energy (`Settings.coupled = "ncg-first"`, `gfmd.chains`).

The coupled balance f(u) = t(u) − K u is no gradient (the mixed-mode law is non-conservative, reference-formulas
§4.0), but along a direction d the projected force φ(α) = f(u + α d)·d is what an energy's −dE/dα would be: the line
search takes its first zero from above, where the force along d stops pushing (for the normal law the NCG's minimum
along d, `gfmd.algorithms.ncg`), by safeguarded Newton with φ'(α) = −d·K d − dᵀ D d (D the law's nodal 2×2 tangent),
bracketing and bisection; each trial one pass over the nodes (`_trial`), no FFT. Directions: s = M⁻¹ f with the
coupled Newton's two-level preconditioner (`gfmd.coupled_preconditioner`: K⁻¹ balanced by a coarse space of block
constants on the stiff nodes, M⁻¹ f = K⁻¹ (f − D Π Z c), c = E⁻¹ Zᵀ f), rebuilt from the state every REBUILD_EVERY
iterations (a restart), K⁻¹ alone where no node is stiff or f·M⁻¹f ≤ 0 (D is not symmetric); d = s + β d_old with
Polak–Ribière+ β, a restart along s where f·d ≤ 0. K s = Π (f − D Π Z c) on the nodes, so K d needs no transform, and
an iteration costs one FFT pair (rfft of f − D Π Z c, irfft of s). u and K u are kept on the nodes and made afresh
from û every `Settings.check_every` iterations (one FFT pair, `gfmd.coupled_krylov.nodes_and_stiffness`), where the
residual test is taken.
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.core import laws
from gfmd_contact.core.law_equations import MAX_COMPRESSION, jacobian_coupled, traction_coupled

from .. import vector_exp
from ..kernels import jit_backend, numba

from .. import coupled_preconditioner
from ..coupled_kernels import coarse_passes
from ..coupled_krylov import nodal_force, nodes_and_stiffness
from ..fft import Fft
from ..problem import stiffness_operator
from ..settings import stall
from ..stopping import finish

#: the preconditioner: K⁻¹ balanced by the coupled Newton's coarse space on the stiff nodes (`gfmd.coupled_preconditioner`),
#: rebuilt every REBUILD_EVERY iterations (a restart), or K⁻¹ alone
TWO_LEVEL = True
REBUILD_EVERY = 10
#: iterations of one step before it stalls (the chain goes on to FIRE). Measured on the ν = 0.1 ramps at 2^15 (seed 3):
#: the event steps the NCG finished took 30–180 FFT pairs, but two crawled to 1 668 and 1 894 (2 000 iterations allowed);
#: with 400 the chain's FIRE finished them (762, 798 pairs in all)
COUPLED_NCG_BUDGET = 400


def solve(problem, start, settings):
    """Relax the coupled balance by nonlinear conjugate directions (module docstring) to `settings.tolerance`."""
    model, law, z_ind = problem.model, problem.law, problem.z_ind
    n = model.nodes
    fft = Fft(n, grid=model.grid)
    clamp = model.half_plane
    p_ref = model.reference_traction
    stiff = stiffness_operator(model)
    scale = law.law.length_scale
    budget = min(COUPLED_NCG_BUDGET, settings.max_iterations)
    eta = settings.line_search_tol

    guess = np.array(start, dtype=complex, copy=True)
    u_hat = guess.copy()
    if clamp:
        u_hat[:, 0] = 0.0

    def exact():  # u and K u on the nodes from û: one FFT pair
        return nodes_and_stiffness(u_hat, stiff, fft)

    def force(u, ku):
        return nodal_force(law, z_ind, u, ku, clamp)

    try:
        u, ku = exact()
        f = force(u, ku)
    except laws.CompressionOverflowError as exc:
        return stall(guess, 0, np.inf, fft.pairs, "coupled-ncg", f"diverged: {exc}")
    d_hat = np.zeros_like(u_hat)
    kd = np.zeros_like(u)
    f_old, rz_old = None, 1.0
    d = np.zeros_like(u)
    g = np.empty_like(u)
    coarse, tangent = None, None
    cz = law.law
    row_block_sums, coarse_residual, _ = coarse_passes()
    restart = True
    residual, converged, failed, it = np.inf, False, "", 0

    def precondition(f, coarse, tangent):
        """(ŝ, s, K s, f·s) of s = M⁻¹ f: K⁻¹ (f − D Π Z c), c = E⁻¹ Zᵀ f, with a coarse space, else K⁻¹ f; one FFT pair
        (K s = Π (f − D Π Z c) on the nodes)."""
        if coarse is not None:
            starts, widths = coarse.starts.astype(np.int64), coarse.widths.astype(np.int64)
            coarse_residual(*tangent, f, coarse.coefficients(row_block_sums(f, starts, widths)), starts, widths,
                            clamp, g)
            ks = g - g.mean(axis=1, keepdims=True) if clamp else g.copy()
        else:
            g[:] = f
            ks = f.copy()
        g_hat = fft.rfft(g)
        if clamp:
            g_hat[:, 0] = 0.0
        s_hat = stiff._apply(stiff.inv_mass, g_hat)
        if clamp:
            s_hat[:, 0] = 0.0
        s_nodes = fft.irfft(s_hat)
        return s_hat, s_nodes, ks, float(np.einsum("ij,ij->", f, s_nodes))

    since = 0  # iterations since u, K u were last made from û
    while True:
        residual = float(np.max(np.abs(f))) / p_ref
        if residual < settings.tolerance or it % settings.check_every == 0:
            if since:  # the nodal bookkeeping's state: the spectrum's own decides
                u, ku = exact()
                try:
                    f = force(u, ku)
                except laws.CompressionOverflowError as exc:
                    failed = f"diverged: {exc}"
                    break
                since = 0
                residual = float(np.max(np.abs(f))) / p_ref
            if residual < settings.tolerance:
                converged = True
                break
            if not np.isfinite(residual):
                failed = "non-finite force residual"
                break
        if it >= budget:
            failed = f"not converged after {it} iterations (residual {residual:.3g} p_ref)"
            break
        it += 1
        if TWO_LEVEL and (it - 1) % REBUILD_EVERY == 0:  # the coarse space of the stiff nodes at this state
            tangent = tuple(np.ascontiguousarray(np.broadcast_to(np.asarray(x, float), (n,)))
                            for x in cz.tangent(z_ind - u[-1], -u[0]))
            coarse = coupled_preconditioner.coarse_space(stiff, fft, tangent, cz.initial_stiffness)
            restart = True
        s_hat, s_nodes, ks, rz = precondition(f, coarse, tangent)
        if not rz > 0 and coarse is not None:  # M⁻¹ not positive along f (D is not symmetric): K⁻¹ until rebuilt
            coarse, restart = None, True
            s_hat, s_nodes, ks, rz = precondition(f, coarse, tangent)
        beta = 0.0 if restart or f_old is None else max(0.0, (rz - float(np.einsum("ij,ij->", f_old, s_nodes))) / rz_old)
        d_new = s_hat + beta * d_hat
        d = s_nodes + beta * d
        kd_new = ks + beta * kd
        slope0 = float(np.einsum("ij,ij->", f, d))
        if not slope0 > 0:  # not a direction the force pushes along: restart along s
            beta, d_new, d, kd_new = 0.0, s_hat, s_nodes, ks
            slope0 = rz
            if not slope0 > 0:
                failed = "no direction the force pushes along"
                break
        d_hat, kd = d_new, kd_new
        restart = False
        f_old, rz_old = f, rz
        alpha, f_new = _line_search(law, z_ind, u, ku, d, kd, slope0, clamp, eta, settings.max_move * scale)
        if alpha == 0.0:
            if beta > 0.0:
                restart = True
                continue
            failed = "line search found no zero of the force along the direction"
            break
        u += alpha * d
        ku += alpha * kd
        u_hat += alpha * d_hat
        f = f_new
        since += 1
    if failed:
        return stall(guess, it, residual, fft.pairs, "coupled-ncg", f"coupled NCG stopped ({failed})")
    pairs = fft.pairs
    out = finish(problem, u_hat, it, residual, converged, "")
    out.fft_pairs = pairs + 0.5
    out.method = "coupled-ncg"
    return out


def _line_search(law, z_ind, u, ku, d, kd, slope0, clamp, eta, first_move):
    """(α, f at u + α d) at the first zero of φ(α) = f(u + α d)·d from φ(0) = slope0 > 0 (|φ| ≤ eta·slope0);
    (0, None) where none is found. Safeguarded Newton with φ' = −d·K d − dᵀ D d, bracketing, bisection. Σ_j d_j = 0
    where clamped (d from a spectrum with q = 0 at 0), so t's mean drops out of φ."""
    dkd = float(np.einsum("ij,ij->", d, kd))
    kud = float(np.einsum("ij,ij->", d, ku))
    reach = float(np.max(np.abs(d)))
    cz = law.law
    params = (float(cz.work_normal), float(cz.length_normal), float(cz.work_tangential), float(cz.length_tangential))
    lowest = -MAX_COMPRESSION * params[1]
    t = np.empty_like(u)
    e = np.empty(u.shape[1])
    trial_pass = _trial()

    def trial(alpha):
        """(φ, φ') at α; (−inf, nan) in the law's overflow range; t holds the tractions."""
        td, dd, bad = trial_pass(u, d, alpha, z_ind, *params, lowest, t, e)
        if bad:
            return -np.inf, np.nan
        return td - kud - alpha * dkd, -(dkd + dd)

    _, s0 = trial(0.0)
    alpha = -slope0 / s0 if s0 < 0 else (first_move / reach if reach > 0 else 1.0)
    lo, hi, p_lo, p_hi = 0.0, np.inf, slope0, -np.inf
    for _ in range(60):
        p, sl = trial(alpha)
        if np.isfinite(p) and abs(p) <= eta * slope0:
            return alpha, _force(t, ku, kd, alpha, clamp)
        if p > 0:
            lo, p_lo = alpha, p
        else:
            hi, p_hi = alpha, p
        nxt = alpha - p / sl if np.isfinite(p) and sl < 0 else np.nan
        if np.isfinite(hi):
            if not lo < nxt < hi:
                nxt = lo + p_lo * (hi - lo) / (p_lo - p_hi) if np.isfinite(p_hi) else 0.5 * (lo + hi)
                if not (lo + 0.01 * (hi - lo) < nxt < hi - 0.01 * (hi - lo)):
                    nxt = 0.5 * (lo + hi)
            if hi - lo <= 1e-12 * hi:
                break
        elif not nxt > alpha:
            nxt = 4.0 * alpha
        alpha = nxt
    if lo > 0:
        trial(lo)
        return lo, _force(t, ku, kd, lo, clamp)
    return 0.0, None


def _force(t, ku, kd, alpha, clamp):
    if clamp:
        t -= t.mean(axis=1, keepdims=True)
    t -= ku
    t -= alpha * kd
    return t


if numba is not None:
    @numba.njit(cache=True, fastmath=vector_exp.STRICT_FLAGS)
    def _exp_kernel(u, d, alpha, z_ind, length_normal, length_tangential, lowest, e):
        """e = exp(−Δn/δn − Δt²/δt²) at v = u + α d (a vectorized loop); the count of nodes out of the law's range."""
        bad = 0
        for i in range(z_ind.size):
            gap = z_ind[i] - (u[1, i] + alpha * d[1, i])
            bad += 0 if (gap >= lowest and gap < np.inf) else 1
            st = (u[0, i] + alpha * d[0, i]) / length_tangential
            e[i] = vector_exp.exp(-gap / length_normal - st * st)
        return bad

    @numba.njit(cache=True, fastmath={"reassoc", "contract", "nsz"})
    def _sums_kernel(u, d, alpha, z_ind, e, work_normal, length_normal, work_tangential, length_tangential, t):
        """Eq. 2's tractions t at v = u + α d from e (`_exp_kernel`), Σ t·d and Σ dᵀ D d (D the law's tangent, rows and
        columns (x, z))."""
        c_n = work_normal / length_normal
        c_t = 2.0 * (work_tangential / length_tangential)
        td = 0.0
        dd = 0.0
        for i in range(z_ind.size):
            dx, dz = d[0, i], d[1, i]
            sn = (z_ind[i] - (u[1, i] + alpha * dz)) / length_normal
            st = -(u[0, i] + alpha * dx) / length_tangential
            tn = c_n * sn * e[i]
            tt = c_t * st * e[i]
            t[1, i] = tn
            t[0, i] = tt
            td += tt * dx + tn * dz
            d_nn = c_n / length_normal * (1.0 - sn) * e[i]
            d_nt = -2.0 * st / length_tangential * tn
            d_tn = -tt / length_normal
            d_tt = c_t / length_tangential * (1.0 - 2.0 * st * st) * e[i]
            dd += d_tt * dx * dx + (d_tn + d_nt) * dx * dz + d_nn * dz * dz
        return td, dd


def _trial_numba(u, d, alpha, z_ind, work_normal, length_normal, work_tangential, length_tangential, lowest, t, e):
    bad = _exp_kernel(u, d, alpha, z_ind, length_normal, length_tangential, lowest, e)
    if bad:
        return 0.0, 0.0, bad
    td, dd = _sums_kernel(u, d, alpha, z_ind, e, work_normal, length_normal, work_tangential, length_tangential, t)
    return td, dd, 0


def _trial_numpy(u, d, alpha, z_ind, work_normal, length_normal, work_tangential, length_tangential, lowest, t, e):
    v = u + alpha * d
    gap, slip = z_ind - v[1], -v[0]
    bad = int(np.count_nonzero(~((gap >= lowest) & (gap < np.inf))))
    if bad:
        return 0.0, 0.0, bad
    t[1], t[0] = traction_coupled(gap, slip, work_normal, length_normal, work_tangential, length_tangential)
    d_nn, d_nt, d_tn, d_tt = jacobian_coupled(gap, slip, work_normal, length_normal, work_tangential, length_tangential)
    dx, dz = d
    td = float(np.dot(t[0], dx) + np.dot(t[1], dz))
    dd = float(np.sum(d_tt * dx * dx + (d_tn + d_nt) * dx * dz + d_nn * dz * dz))
    return td, dd, 0


def _trial(name=None):
    """The line search's trial, `gfmd.kernels.jit_backend(name)`'s: (u, d, α, z_ind, φn, δn, φt, δt, lowest, t, e) ↦
    (Σ t·d, Σ dᵀ D d, the count of nodes out of the law's range) at v = u + α d, Eq. 2's tractions written to t (x, z;
    e a scratch array over the nodes; where a node is out of range t is not written)."""
    return _trial_numba if jit_backend(name) == "numba" else _trial_numpy
