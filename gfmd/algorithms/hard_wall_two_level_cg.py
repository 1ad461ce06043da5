"""The hard wall by the dual CG with a two-level preconditioner: the band of K plus a coarse space.

`gfmd.algorithms.hard_wall_dual_cg`'s projected CG on the contact pressures, its band-of-K_AA
preconditioner wrapped in a balancing (BNN) coarse correction on blocks of the contact patches: the
first in the hard wall's chain (`gfmd.chains`, ``Settings.dual_coarse_block > 0``). Why: the dual CG's
count grows with N because its linear part does (benchmarks/results/bench_vs_tamaas.md, section 8: CG on
a fixed contact set, K_AA-preconditioned, 16 → 35 iterations from N = 2^12 to 2^18), not because of set
changes: K_AA is the Dirichlet-to-Neumann map of the whole line restricted to a patch, G_AA⁻¹ its Schur
complement, and the two differ on the smooth modes of each patch (the open-arc log² growth of the
hypersingular-preconditioned single layer, Steinbach & Wendland 1998). The coarse space, piecewise
constants on blocks of ≤ `Settings.dual_coarse_block` consecutive contact nodes, takes exactly those
modes; a block size fixed in nodes makes the condition number independent of N (the two-level bound
depends on the block / node ratio only; benchmarks/results/bench_hardwall_scaling.md: on the 0.1 nm
Fig. 3 step 5–10 iterations per step from N = 2^14 to 2^20, the band alone 14 → 36). The coarse level's cost is
dense in contact nodes × blocks (G_AA Z): where even one block per patch would exceed
COARSE_ENTRIES_PER_NODE · N entries (many patches: a_rel ≈ 0.06 on the Fig. 3 profile), the band
preconditions alone, as in the dual CG.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..fft import Fft, dot
from ..problem import Elastic, band_stiffness
from ..settings import not_converged, stall
from ..stopping import finish, wall_check, wall_residual

#: half-width (nodes) of the band of K_AA (the fine level; as the dual CG's)
BAND_HALF_WIDTH = 32
#: the step is handed over when A grows past this multiple of `Settings.dual_contact_limit` (as the dual CG)
TRANSIENT_FACTOR = 2.0
#: G_AA Z holds at most this many entries per grid node (contact nodes × coarse blocks ≤ this × N): the blocks
#: grow beyond `Settings.dual_coarse_block` nodes where the contact set is large, and where even one block
#: per contact patch would exceed it the band preconditions alone. Each iteration reads G_AA Z twice and each
#: change of the contact set rebuilds it, so beyond a few N entries the coarse level costs more time than
#: the FFT pairs it saves. Measured (N = 2^17, Fig. 3 profile, 0.1 nm steps at δ ≈ 28.5 nm, a_rel = 0.058,
#: one run under load): with 16 N entries 13–16 iterations per step against the band's 94–166, but 10.9 CPU s
#: for the ramp there against 7.1; with 4 N the band alone (as the dual CG); at δ ≈ 19.5 nm (a_rel = 0.011,
#: the end of Fig. 3's ramp) both 8–11 iterations against 37–41 and 1.3–1.4 CPU s against 2.6.
COARSE_ENTRIES_PER_NODE = 4


def coarse_blocks(act, block):
    """Start positions (in act) of the coarse blocks: ≤ block consecutive nodes, never across a gap."""
    pos = np.arange(act.size)
    run_start = np.r_[0, np.flatnonzero(np.diff(act) > 1) + 1]
    first_of_run = run_start[np.cumsum(np.isin(pos, run_start)) - 1]
    return np.flatnonzero((pos - first_of_run) % block == 0)


def coarse_space(g_sum, act, n, block):
    """(starts, G_AA Z, Cholesky factor of E = Zᵀ G_AA Z) on the blocks of `coarse_blocks`, or None (the cost
    gate: one block per patch over COARSE_ENTRIES_PER_NODE · n entries; the blocks grow past `block` below it).

    g_sum: cumulative sum of G's real-space kernel over the offsets −n … n−1 (`solve`), so that the
    column of block [j0, j1] is G_AA Z_J = Σ_{j=j0}^{j1} g(i − j) = g_sum[i − j0 + n] − g_sum[i − j1 − 1 + n].
    None where E is not positive definite (round-off on a nearly full set): the band alone then.
    """
    budget = COARSE_ENTRIES_PER_NODE * n
    runs = 1 + np.count_nonzero(np.diff(act) > 1)
    if act.size < 2 or runs * act.size > budget:
        return None
    starts = coarse_blocks(act, max(block, -(-act.size * act.size // budget)))
    first = act[starts]
    last = act[np.r_[starts[1:], act.size] - 1]
    gz = g_sum[act[:, None] - first[None, :] + n] - g_sum[act[:, None] - last[None, :] - 1 + n]
    e = np.add.reduceat(gz, starts, axis=0)
    try:
        factor = scipy.linalg.cho_factor(0.5 * (e + e.T))
    except np.linalg.LinAlgError:
        return None
    return starts, gz, factor


def two_level(r, fine, coarse):
    """The balancing preconditioner (I − P G) M (I − G P) + P, P = Z E⁻¹ Zᵀ, M the band (`fine`), on r."""
    if coarse is None:
        return fine(r)
    starts, gz, factor = coarse
    sizes = np.diff(np.r_[starts, r.size])
    c = scipy.linalg.cho_solve(factor, np.add.reduceat(r, starts))
    y = fine(r - gz @ c)
    c2 = scipy.linalg.cho_solve(factor, gz.T @ y)
    return y + np.repeat(c - c2, sizes)


def solve(problem, start, settings):
    """Hard wall by projected two-level-preconditioned CG on the contact pressures (small contact sets).

    As `gfmd.algorithms.hard_wall_dual_cg.solve` (the problem min ½ PᵀGP + z_indᵀP over P ≥ 0, the set
    changes, the stopping test and its residual, the hand-over to the primal CG), with the preconditioner
    `two_level`: the band of K_AA (half-width BAND_HALF_WIDTH) balanced by the coarse space of blocks of
    `Settings.dual_coarse_block` contact nodes (`coarse_space`), rebuilt when the contact set changes; no
    FFT is added (G_AA Z from G's real-space kernel). The preconditioned residual s is the stopping
    measure, as there (≈ the nodal force of the gap error: the preconditioner approximates G_AA⁻¹).
    """
    model, law, z_ind, wall_tolerance = problem.model, problem.law, problem.z_ind, problem.wall_tolerance
    u_hat = start  # the step's initial displacements (c, N//2+1), rfft
    n = model.nodes
    fft = Fft(n)
    clamp = model.half_plane
    k = np.ascontiguousarray(np.real(model.k_zz))
    g = np.ascontiguousarray(np.real(Elastic(model, 0.0, 0.0).inv_mass[0]))
    p_ref = model.reference_traction
    tol = settings.tolerance * p_ref
    gamma2 = settings.proportioning**2
    limit = settings.dual_contact_limit * n
    transient_limit = min(TRANSIENT_FACTOR * limit, n - 2)
    z = np.ascontiguousarray(z_ind, dtype=float)

    u_hat_z = np.ascontiguousarray(u_hat[-1])
    u = fft.irfft(u_hat_z)
    ku = fft.irfft(k * u_hat_z)
    if float(np.max(u - z)) <= wall_tolerance:  # feasible up to round-off: already converged?
        residual = wall_residual(model, u, ku, z, wall_tolerance)
        if residual < settings.tolerance:
            out = finish(problem, fft.rfft(np.minimum(u, z))[None, :], 0, residual, True, "")
            out.fft_pairs, out.method = fft.pairs + 1.5, "cg-dual2"  # finish: 1.5 pairs
            return out
    # the guess's pressures: P = p_far − K u where positive; p_far = K u on the nodes the guess leaves free
    free = z - u > 0
    p_far = float(np.median(ku[free])) if clamp and free.any() else 0.0
    pressure = p_far - ku  # full length; zero off A from here on
    on_wall = pressure > 1e-9 * float(np.max(np.abs(ku)))
    if np.count_nonzero(on_wall) > limit:  # a large contact set: the primal CG from the guess
        return stall(u_hat, 0, np.inf, fft.pairs, "",  # not run: no label
                     f"contact set of the guess above {settings.dual_contact_limit:g} of the nodes")
    pressure[~on_wall] = 0.0
    act = np.flatnonzero(on_wall)
    k_kernel = fft.irfft(k.astype(complex))
    g_sum = np.cumsum(fft.irfft(g.astype(complex))[np.arange(-n, n) % n])  # `coarse_space`
    sparse_in, g_d, gap = np.zeros(n), np.empty(n), np.empty(n)

    def g_times(values, out):  # out ← G χ_A values: one FFT pair
        sparse_in[act] = values
        fft.apply_to(g, sparse_in, out)
        sparse_in[act] = 0.0
        return out

    def recompute_gap():
        g_times(pressure[act], gap)
        np.add(gap, z, out=gap)

    def primal_state():
        u_new = z - np.maximum(gap, 0.0)
        u_new[act] = z[act]
        return u_new

    recompute_gap()
    # the band on a superset U ⊇ A, rebuilt only when nodes outside U join A (leaving A needs no rebuild:
    # rows and columns of U \ A meet zeros and are not read)
    band_nodes = act
    k_band = band_stiffness(k_kernel, band_nodes, n, BAND_HALF_WIDTH)
    band_in = np.zeros(band_nodes.size)

    def band(r):  # K_band restricted to A, times r
        at = np.searchsorted(band_nodes, act)
        band_in[at] = r
        out = (k_band @ band_in)[at]
        band_in[at] = 0.0
        return out

    coarse_of = [None, None]  # (the contact set it was built on, the coarse space)

    def precondition(r):
        if coarse_of[0] is not act:
            coarse_of[:] = act, coarse_space(g_sum, act, n, settings.dual_coarse_block)
        return two_level(r, band, coarse_of[1])

    d = np.zeros(act.size)
    rz_old, restart, stop = 1.0, True, 0.5
    residual, converged, message, hand_over = np.inf, False, "", False
    it = 0
    while not hand_over and it < settings.max_iterations:
        r = -gap[act]
        s = precondition(r)
        worst = float(np.max(np.abs(s))) if act.size else 0.0
        # penetration off A, counted once its force (≈ K(0)_jj |Δ_j|) is not negligible
        enter = np.empty(0, np.int64)
        penetration_tol = 0.1 * stop * tol / k_kernel[0]
        if float(np.min(gap)) < -penetration_tol:
            off = gap < -penetration_tol
            off[act] = False
            enter = np.flatnonzero(off)
        if enter.size:
            g_enter = gap[enter]
            if dot(g_enter, g_enter) > gamma2 * dot(r, r) or worst < stop * tol:
                act = np.union1d(act, enter)
                hand_over = act.size > transient_limit
                if not np.isin(enter, band_nodes, assume_unique=True).all():
                    band_nodes = act
                    k_band = band_stiffness(k_kernel, band_nodes, n, BAND_HALF_WIDTH)
                    band_in = np.zeros(band_nodes.size)
                restart = True
                continue
        if worst < stop * tol:  # candidate: the primal residual with a fresh K u
            u = primal_state()
            residual, converged, message = wall_check(model, fft, k, u, ku, z, wall_tolerance, settings.tolerance)
            if converged or message:
                break
            stop *= 0.1
            hand_over = stop < 1e-4
            continue
        it += 1
        rz = dot(r, s)
        if restart or rz_old <= 0:
            d = s.copy()
            restart = False
        else:
            d = s + (rz / rz_old) * d
        rz_old = rz
        g_times(d, g_d)
        curvature = dot(d, g_d[act])
        if not curvature > 0:
            message = "diverged: non-positive curvature along the search direction"
            break
        alpha = rz / curvature
        if not np.isfinite(alpha):
            message = "diverged: non-finite step"
            break
        p_act = pressure[act] + alpha * d
        g_d *= alpha
        gap += g_d
        negative = p_act < 0
        if negative.any():  # Polonsky–Keer: keep the step, project, those nodes leave A
            p_act[negative] = 0.0
            pressure[act] = p_act
            act = act[~negative]
            recompute_gap()
            restart = True
        else:
            pressure[act] = p_act
    u = primal_state()
    if hand_over and not message:  # the primal CG from here, with the iterations left (`gfmd.chains`)
        return stall(fft.rfft(u)[None, :], it, residual, fft.pairs + 0.5, "cg-dual2",
                     "contact set too large for the dual")
    if not converged and not message:
        message = not_converged(settings.max_iterations, residual)
    state = (u, ku) if converged else None  # converged: K u of this very u was the last check's
    out = finish(problem, fft.rfft(u)[None, :], it, residual, converged, message, state)
    out.fft_pairs = fft.pairs + (0.0 if converged else 1.0)  # finish otherwise: irfft of u_hat and of K û
    out.method = "cg-dual2"
    return out
