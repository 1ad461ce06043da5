"""The hard wall by projected preconditioned conjugate gradients on the contact pressures (the dual).

The dual of `gfmd.problem`'s hard-wall problem, preconditioned by a band of K on the contact set,
one FFT pair per iteration: 8.6–10× fewer FFT pairs per step than FIRE at N = 2^16–2^17
(benchmarks/results/bench_vs_tamaas.md). First in the hard wall's chain while the contact set
holds at most `Settings.dual_contact_limit` (15 %) of the nodes (`gfmd.chains`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse

from ..fft import Fft, dot
from ..problem import Elastic
from ..problem import band_stiffness as _band_stiffness
from ..settings import not_converged, stall
from ..stopping import finish, wall_check, wall_residual

DUAL_BAND_HALF_WIDTH = 32
#: 2+1-D surfaces: the preconditioner keeps K_ij for |x_i − x_j|, |y_i − y_j| ≤ this many nodes (periodic), a
#: (2w + 1)² window per row (`_band_stiffness_surface`; K's kernel decays as 1/r³ in 2-D). Measured
#: (benchmarks/bench_gfmd_2d.py's hard-wall ramp, 5 steps to a_rel ≈ 3 %), CG iterations per step for
#: w = 0 (diagonal) / 1 / 2 / 3 / 4 / 6: 128²: 8–28 / 7–14 / 7–14 / 7–14 / 7–14 / 7–14; 256²: 10–48 / 8–20 /
#: 8–21 / 8–19 / 8–19 / 8–19: the nearest neighbours carry the gain, a wider window only costs.
DUAL_WINDOW_HALF_WIDTH_2D = 1
#: The dual hard-wall CG hands a step over to the primal only when its contact set grows past this
#: multiple of `Settings.dual_contact_limit` (`solve`). Measured (section 7, N = 2^16):
#: with factor 1, steps ending at a_rel = 0.025–0.055 were handed over mid-way and cost 1.1–1.5× the
#: dual alone.
DUAL_TRANSIENT_FACTOR = 2.0


def _band_stiffness_surface(k_kernel, act, grid, half_width):
    """`_band_stiffness` on a 2+1-D surface (flat node indices act on the grid (Nx, Ny), row-major): K_AA
    truncated to the periodic window |Δi_x|, |Δi_y| ≤ half_width (CSR, Pa/m). K_ij = k[|Δi_x|, |Δi_y|]
    (the kernel is even in each offset): exactly symmetric; the same diagonal-dominance argument as in
    1+1-D makes it positive definite. The window is cut to (N − 1)//2 per axis so no pair is counted twice."""
    nx, ny = grid
    kk = np.reshape(k_kernel, grid)
    wx, wy = min(half_width, (nx - 1) // 2), min(half_width, (ny - 1) // 2)
    position = np.full(nx * ny, -1, np.int64)
    position[act] = np.arange(act.size)
    ix, iy = np.divmod(act, ny)
    rows, cols, data = [], [], []
    for dx in range(-wx, wx + 1):
        row_x = ((ix + dx) % nx) * ny
        for dy in range(-wy, wy + 1):
            j = position[row_x + (iy + dy) % ny]
            hit = np.flatnonzero(j >= 0)
            rows.append(hit)
            cols.append(j[hit])
            data.append(np.full(hit.size, kk[abs(dx), abs(dy)]))
    rows, cols, data = np.concatenate(rows), np.concatenate(cols), np.concatenate(data)
    return scipy.sparse.csr_matrix((data, (rows, cols)), shape=(act.size, act.size))


def solve(problem, start, settings):
    """Hard wall by projected preconditioned CG on the contact pressures (the dual, small contact sets).

    With P ≥ 0 the wall's pressure on the nodes (Pa), u = −G P (G = K⁻¹; on a half-plane
    G(0) = 0, so ⟨u⟩ = 0 and the far-field load is ⟨P⟩) and the gap Δ = z_ind − u = z_ind + G P,
    the step is  min ½ Pᵀ G P + z_indᵀ P  over P ≥ 0  (gradient Δ; KKT: P ≥ 0, Δ ≥ 0, P Δ = 0),
    the primal problem of `gfmd.algorithms.hard_wall_primal_cg` seen from the wall. CG runs on the contact set
    A = {P > 0} with residual −Δ_A and preconditioner K_AA truncated to |i − j| ≤
    DUAL_BAND_HALF_WIDTH (`_band_stiffness`; G⁻¹ = K, and K's kernel decays as 1/x² while G's is
    logarithmic): a sparse product, so an iteration costs one FFT pair (G d) where the primal CG
    needs two (K d and its preconditioner K⁻¹ r). s = K_band Δ_A is ≈ the nodal force the gap
    error makes, the stopping measure.

    Set changes, as the primal: a step that drives pressures negative is kept and projected
    (P ← max(P, 0), the nodes leave A, Δ recomputed, restart: Polonsky & Keer 1999); nodes off A
    that penetrate (Δ < 0) join A with P = 0 once the norm of their gaps exceeds `proportioning` ×
    that of Δ_A (restart).

    Stop: the same residual as `gfmd.algorithms.hard_wall_primal_cg` (max |net force| of
    `gfmd.problem.wall_net_force`, K u recomputed from u = z_ind on A, z_ind − max(Δ, 0) off A) below
    tolerance · p_ref; the candidate is tested when max |s| < ½ tolerance · p_ref, then at tenfold tighter thresholds.
    A guess that already passes is returned unchanged (iterations 0): the fixed points are the
    KKT points. The step is handed over (`Relaxed.stalled`; the hard wall's chain then runs the primal
    `gfmd.algorithms.hard_wall_primal_cg` from the guess) when its contact set
    holds more than `Settings.dual_contact_limit` of the nodes (beyond, the band products and set
    changes cost more than the pair they save; measured on whole Fig. 3 hard-wall study tasks, N = 2^17,
    0.04 nm steps, CPU s for limits 0 / 0.05 / 0.15 / 0.3: 36.9 / 27.5 / 23.5 / 24.7 (a_rel up to
    0.25) and – / 17.3 / 14.0 / 13.6 (up to 0.083); with 1.8 nm jumps (benchmarks/bench_vs_tamaas.py,
    section 7) the dual is 1.05× the primal at a_rel 0.08 and 1.7× at 0.13), and from
    the current state when A grows past DUAL_TRANSIENT_FACTOR × that limit (the nodes that join in
    bulk after an extrapolated guess can double A before the projections thin it out: measured
    1553 → 745 nodes at N = 2^17), when A would hold every node but one (a half-plane's G_AA is
    singular on all nodes), or when the tighter thresholds do not reach the tolerance.
    """
    model, law, z_ind, wall_tolerance = problem.model, problem.law, problem.z_ind, problem.wall_tolerance
    u_hat = start  # the step's initial displacements (c, N//2+1), rfft
    n = model.nodes
    fft = Fft(n, grid=model.grid)
    clamp = model.half_plane
    if len(model.grid) > 1:  # 2+1-D: the periodic window of `_band_stiffness_surface`
        def band_stiffness(kernel, nodes):
            return _band_stiffness_surface(kernel, nodes, model.grid, DUAL_WINDOW_HALF_WIDTH_2D)
    else:
        def band_stiffness(kernel, nodes):
            return _band_stiffness(kernel, nodes, n, DUAL_BAND_HALF_WIDTH)
    k = np.ascontiguousarray(np.real(model.k_zz))
    g = np.ascontiguousarray(np.real(Elastic(model, 0.0, 0.0).inv_mass[0]))
    p_ref = model.reference_traction
    tol = settings.tolerance * p_ref
    gamma2 = settings.proportioning**2
    limit = settings.dual_contact_limit * n
    transient_limit = min(DUAL_TRANSIENT_FACTOR * limit, n - 2)
    z = np.ascontiguousarray(z_ind, dtype=float)

    u_hat_z = np.ascontiguousarray(u_hat[-1])
    u = fft.irfft(u_hat_z)
    ku = fft.irfft(k * u_hat_z)
    if float(np.max(u - z)) <= wall_tolerance:  # feasible up to round-off: already converged?
        residual = wall_residual(model, u, ku, z, wall_tolerance)
        if residual < settings.tolerance:
            out = finish(problem, fft.rfft(np.minimum(u, z))[None, :], 0, residual, True, "")
            out.fft_pairs, out.method = fft.pairs + 1.5, "cg-dual"  # finish: 1.5 pairs
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
    k_band = band_stiffness(k_kernel, band_nodes)
    band_in = np.zeros(band_nodes.size)

    def precondition(r):  # K_band restricted to A, times r
        at = np.searchsorted(band_nodes, act)
        band_in[at] = r
        out = (k_band @ band_in)[at]
        band_in[at] = 0.0
        return out

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
                    k_band = band_stiffness(k_kernel, band_nodes)
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
        return stall(fft.rfft(u)[None, :], it, residual, fft.pairs + 0.5, "cg-dual",
                     "contact set too large for the dual")
    if not converged and not message:
        message = not_converged(settings.max_iterations, residual)
    state = (u, ku) if converged else None  # converged: K u of this very u was the last check's
    out = finish(problem, fft.rfft(u)[None, :], it, residual, converged, message, state)
    out.fft_pairs = fft.pairs + (0.0 if converged else 1.0)  # finish otherwise: irfft of u_hat and of K û
    out.method = "cg-dual"
    return out
