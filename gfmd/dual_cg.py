"""The projected preconditioned CG on the contact pressures (the dual of the hard wall), shared by the dual
hard-wall algorithms: `gfmd.algorithms.hard_wall_dual_cg` (the band of K_AA) and
`gfmd.algorithms.hard_wall_two_level_cg` (the band balanced by a coarse space). Not an algorithm itself: each
algorithm module keeps its preconditioner and `solve(problem, start, settings)`, and calls `solve_dual` with them.
"""

from __future__ import annotations

import numpy as np

from .fft import Fft, dot
from .problem import stiffness_operator
from .settings import not_converged, stall
from .stopping import finish, wall_check, wall_residual

#: The dual hard-wall CG hands a step over to the primal only when its contact set grows past this
#: multiple of `Settings.dual_contact_limit` (`solve_dual`). Measured (section 7, N = 2^16):
#: with factor 1, steps ending at a_rel = 0.025–0.055 were handed over mid-way and cost 1.1–1.5× the
#: dual alone.
TRANSIENT_FACTOR = 2.0


def solve_dual(problem, start, settings, *, label, band_stiffness, preconditioner=None):
    """Hard wall by projected preconditioned CG on the contact pressures (the dual, small contact sets).

    With P ≥ 0 the wall's pressure on the nodes (Pa), u = −G P (G = K⁻¹; on a half-plane
    G(0) = 0, so ⟨u⟩ = 0 and the far-field load is ⟨P⟩) and the gap Δ = z_ind − u = z_ind + G P,
    the step is  min ½ Pᵀ G P + z_indᵀ P  over P ≥ 0  (gradient Δ; KKT: P ≥ 0, Δ ≥ 0, P Δ = 0),
    the primal problem of `gfmd.algorithms.hard_wall_primal_cg` seen from the wall. CG runs on the contact set
    A = {P > 0} with residual −Δ_A and preconditioner K_AA truncated to a band (the algorithm's
    `band_stiffness`; G⁻¹ = K, and K's kernel decays as 1/x² while G's is
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
    the current state when A grows past TRANSIENT_FACTOR × that limit (the nodes that join in
    bulk after an extrapolated guess can double A before the projections thin it out: measured
    1553 → 745 nodes at N = 2^17), when A would hold every node but one (a half-plane's G_AA is
    singular on all nodes), or when the tighter thresholds do not reach the tolerance.

    Hooks (the algorithm module's): `band_stiffness(k_kernel, nodes)` → K_AA truncated to the band on the
    sorted node indices `nodes` (CSR, Pa/m), rebuilt when nodes outside the current band join A;
    `preconditioner(fft, g)` (None: the band alone), called once after the setup (G's rfft coefficients g),
    returns `precondition(r, band, act)` → s, where band(r) is K_band restricted to A times r and act the
    contact set's node indices (the same object until A changes). `label` names the algorithm
    (`Relaxed.method`).
    """
    model, z_ind, wall_tolerance = problem.model, problem.z_ind, problem.wall_tolerance
    u_hat = start  # the step's initial displacements (c, N//2+1), rfft
    n = model.nodes
    fft = Fft(n, grid=model.grid)
    clamp = model.half_plane
    k = np.ascontiguousarray(np.real(model.k_zz))
    g = np.ascontiguousarray(np.real(stiffness_operator(model).inv_mass[0]))
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
            out = finish(problem, fft.rfft(np.minimum(u, z))[None, :], 0, residual, True, "", (u, ku))
            out.fft_pairs, out.method = fft.pairs, label  # the fields from the arrays the residual was taken on
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
    k_kernel = stiffness_operator(model).kept(("stiffness kernel", fft.backend), lambda: fft.irfft(k.astype(complex)))
    wrap = preconditioner(fft, g) if preconditioner is not None else None
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

    def band(r):  # K_band restricted to A, times r
        at = np.searchsorted(band_nodes, act)
        band_in[at] = r
        out = (k_band @ band_in)[at]
        band_in[at] = 0.0
        return out

    def precondition(r):
        return band(r) if wrap is None else wrap(r, band, act)

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
        return stall(fft.rfft(u)[None, :], it, residual, fft.pairs + 0.5, label,
                     "contact set too large for the dual")
    if not converged and not message:
        message = not_converged(settings.max_iterations, residual)
    state = (u, ku) if converged else None  # converged: K u of this very u was the last check's
    out = finish(problem, fft.rfft(u)[None, :], it, residual, converged, message, state)
    out.fft_pairs = fft.pairs + (0.0 if converged else 1.0)  # finish otherwise: irfft of u_hat and of K û
    out.method = label
    return out
