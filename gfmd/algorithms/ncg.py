"""The normal-only cohesive law (a potential) by nonlinear preconditioned conjugate gradients.

Polak–Ribière+ CG, preconditioner K⁻¹ as the hard-wall CG, an FFT-free Newton line search on the
elastic + CZ energy (`gfmd.problem`); 5–10× fewer FFT pairs per step than FIRE
(docs/design/performance.md). The law's nodal work runs on the nodes near the indenter
only, the spectral algebra in `gfmd.kernels` (numpy, or fused numba kernels where installed).
The nodal law work is `gfmd.ncg_nodes`'s: seed Eq. 3's (numpy, or one fused numba pass per line-search trial), or
any other law's traction and tangent on the near set, whose cut is the law's `far_reach` (the law protocol,
`gfmd_contact.core.law_protocol`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import cohesive_preconditioner, kernels
from ..ncg_nodes import nodes_for
from ..problem import stiffness_operator
from ..fft import Fft
from ..settings import stall
from ..stopping import finish

#: the name of this algorithm in `Relaxed.method`, result files and the chains (`gfmd.chains`)
LABEL = "ncg"


@dataclass(frozen=True)
class Options:
    """What the NCG reads: the `gfmd.settings.Settings` fields of these names."""

    tolerance: float  # max nodal force residual / p_ref
    max_iterations: int
    check_every: int  # iterations between full residual tests
    line_search_tol: float  # the line search stops at |dE/dα| ≤ this × |dE/dα(0)|
    max_move: float  # largest nodal move per iteration, in law lengths
    cohesive_preconditioner: str  # "auto", "stiffness" or "two-level" (`gfmd.cohesive_preconditioner`)

NCG_BUDGET = 5000

#: NCG: nodes whose attraction (Eq. 3) is at most NCG_FAR_FRACTION · tolerance · p_ref, Δn ≥ s_c δn, are
#: left out of the nodal work; a converged state is checked again with every node
NCG_FAR_FRACTION = 1e-3
#: NCG: the near set holds the nodes with Δn < (s_c + NCG_NEAR_MARGIN) δn; it is rebuilt from the state when
#: a step could have moved a far node by more than the margin
NCG_NEAR_MARGIN = 8.0
#: NCG: every node is near once the near set would hold more than this fraction of them (a gather then
#: costs more than the nodal work it saves)
NCG_NEAR_FULL = 0.5
#: NCG under the two-level preconditioner: û's coarse tail is folded into its spectrum at least every this many
#: iterations (one rfft), keeping the split products' round-off small (`gfmd.cohesive_preconditioner.split_products`;
#: the residual tests fold every `Settings.check_every` iterations anyway). Swept on a whole 2^17 ramp
#: (benchmarks/bench_split_tail.py): 1, 4, 8, 16 and never give the same iterations and states within 1e-14
FOLD_EVERY = 16


def solve(problem, start, options):
    """Normal-only cohesive law by nonlinear preconditioned conjugate gradients, FIRE as fallback.

    The law has a potential (the law protocol's `has_potential`, `potential`): the step minimises
    E(u) = ½ uᵀKu + Σ_j V(Δn_j), Δn = z_ind − u, whose negative gradient is the force
    f = T_n(Δn) − K u of `gfmd.algorithms.dynamics` (mean removed on a half-plane, ⟨u⟩ = 0).
    Polak–Ribière+ CG on the nodal displacements preconditioned as the hard-wall CG, s = K⁻¹ f
    (K(q)⁻¹ on the modes; the q = 0 mode clamped on a half-plane). FIRE's M = K + ⟨k_loc⟩ was
    measured worse here (2^14, δn = 0.25 nm: 2× the iterations; a Jacobi split for the stiff
    contact nodes 1.5–2×): the line search handles the interface stiffness. The line search
    along d needs no FFT: d·Ku and d·Kd are sums (below), and
    dE/dα = d·Ku + α d·Kd − Σ T_n(Δn − αd) d, d²E/dα² = d·Kd + Σ k_loc d² are nodal sums,
    so safeguarded Newton on dE/dα (bracketed; secant or bisection when Newton leaves the
    bracket or the curvature is negative; stop at |dE/dα| ≤ line_search_tol·|dE/dα(0)|) costs
    one exp over the nodes per trial (≈ 1.05 trials per iteration measured). The force is kept
    in Fourier space, f̂ = rfft(T_n) − K û (q = 0 clamped on a half-plane), so K u never drifts
    and an iteration costs one FFT pair (rfft T_n, irfft d); the stopping test is
    `gfmd.algorithms.dynamics`'s, max_j |f_j| < tolerance · p_ref on the nodes (one more irfft), taken
    every `check_every` iterations and whenever the energy norm (f·K⁻¹f)^½ times the last
    measured max-norm/energy-norm ratio predicts it passes: the converged states and their
    residuals mean what FIRE's do.

    Cost per iteration: the nodal law work (the law's tractions, the line search's sums) runs on the near
    set only, the nodes with Δn < (s_c + NCG_NEAR_MARGIN) dn, where beyond s_c dn every |T_n| is below
    NCG_FAR_FRACTION · tolerance · p_ref (the law protocol's `far_reach`; dn its `length_scale`): a far node's
    attraction is below a thousandth of the stopping test. The set is rebuilt from a fresh irfft when a step could
    have brought a far node (Δn falls by α max_j d_j) within s_c dn, and a state that passes the test is
    checked again with every node's attraction (if that fails, every node stays in from then on),
    so the converged states are those of the plain NCG. The spectral algebra is one pass per
    product: d·Ku = Σ_j d_j T_n,j − f·d (f = T_n − K u − ⟨T_n⟩, Σ_j d_j = 0 on a half-plane) and,
    with K s = f, d·Kd = f·s + 2β f·d_old + β² d_old·K d_old: no K d. The nodal work is `gfmd.ncg_nodes.nodes_for`'s:
    a fused kernel for a law whose `nodal_form` names one (seed Eq. 3), the law's tractions and tangent otherwise.

    `Settings.cohesive_preconditioner` = "two-level" (the default "auto" on a profile with a law that gives a
    `curvature_scale`) replaces K⁻¹ after the step's first iterations by K⁻¹
    balanced by a coarse space on the stiff patches (`gfmd.cohesive_preconditioner`); K s ≠ f then, so d·Kd
    is a sum over the modes, and the direction restarts where the preconditioner is rebuilt. Under it the force
    is never formed as f̂: `TwoLevel.apply_split` takes T_n on the nodes and û, gives s and the force as
    irfft(r̂) + D w (f·s, f_old·s, f·d_old as spectral plus nodal sums; the stopping test's irfft of r̂ plus D w),
    and keeps Zᵀ K u on the coarse level, so an iteration costs 3 transforms instead of 5 (the force's rfft and the
    balanced form's two pairs). The third transform, the rfft of s's coarse correction Π Z c₂, is never made
    either: û is kept as a spectral part and a coarse tail, û_s + rfft(Π Z e_u), s and d likewise (x̂' and e_s, d̂_s
    and e_d; `TwoLevel.apply_split`, `move`), and f·s, f_old·s, f·d_old and d·Kd come from the parts
    (`gfmd.cohesive_preconditioner.split_products`, `split_energy`): K-products of the spectral parts plus coarse
    sums with E_K = Zᵀ Π K Π Z, whose products the coarse level already holds. 2 transforms per iteration; the tail
    is folded into û_s (one rfft, `TwoLevel.fold`) before a force residual test, where the coarse space changes,
    where the near set is rebuilt and at least every FOLD_EVERY iterations. Both keep the iterations and the
    states; their CPU gains at 2^17 are in docs/design/solvers.md.

    Stall: a step NCG does not finish within min(NCG_BUDGET, max_iterations / 2) iterations, or
    whose line search finds no descent, is handed over (`Relaxed.stalled`; `gfmd.chains` restarts it
    from the same guess with FIRE and the rest of the iterations, `Relaxed.method` "ncg→fire").
    """
    model, law, z_ind, wall_tolerance = problem.model, problem.law, problem.z_ind, problem.wall_tolerance
    u_hat = start  # the step's initial displacements (c, N//2+1), rfft
    n = model.nodes
    fft = Fft(n, grid=model.grid)
    clamp = model.half_plane
    cz = law.law
    p_ref = model.reference_traction
    dn = float(cz.length_scale)  # the law's length (m): the near set's margins and the line search's first step
    nodal = nodes_for(cz)  # the law's nodal work: a fused kernel for its closed form, else its tractions and tangent
    budget = min(NCG_BUDGET, options.max_iterations // 2) if options.max_iterations > 1 else 1
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)

    def preconditioner():
        g = np.zeros(k.size)
        np.divide(1.0, k, out=g, where=k > 0)
        if clamp:
            g[0] = 0.0
        return g

    g = preconditioner()
    products, direction, advance = kernels.ncg_kernels(grid=model.grid)  # the spectral algebra (numpy or fused)
    products_m, direction_m, combine_m, stiffness_m = kernels.preconditioned_kernels()  # under the two-level one
    cohesive_preconditioner.check(options, model.grid)
    if cz.curvature_scale is None and options.cohesive_preconditioner == "two-level":
        raise ValueError(f"Settings.cohesive_preconditioner = 'two-level' needs a law with a curvature scale "
                         f"(seed Eq. 3's φn/δn²); the {cz.name} gives none")
    preconditioner_name = cohesive_preconditioner.resolve(options.cohesive_preconditioner, model.grid,
                                                          cz.curvature_scale is None)
    # built when a step first engages it (ENGAGE_AFTER iterations): the steps that finish before never pay its setup
    # (an irfft and two cumulative sums over 2N: ≈ 6 ms at 2^17, once per task, K's sums kept on the
    # model's `stiffness_operator`; a φn* = 0.001 task −6 to −11 % CPU)
    two_level = preconditioner_name != "stiffness"
    other = None
    far = NCG_FAR_FRACTION * options.tolerance * p_ref  # a far node's |T_n| is below this (Pa)
    cut = cz.far_reach(far)  # s_c: beyond s_c·dn every node's |T_n| is below `far`
    scaled_gap = nodal.state  # Eq. 3's fused form: (s, e^{−s}); any other law: (T_n, dT_n/dΔn)

    def near(margin, first=False):
        """(near, Δn on it, s, e^{−s}) at the state uh: the nodes with Δn < (s_c + margin) δn
        (slice(None): every node), from a fresh irfft."""
        if other is not None:  # û exact (the two-level preconditioner's coarse tail folded in)
            other.fold(uh)
        gap_all = z_ind - fft.irfft(uh)
        if first:  # an initial guess out of the law's range raises, as FIRE's does
            cz.check_gaps(gap_all)
        idx = np.flatnonzero(gap_all < (cut + margin) * dn) if np.isfinite(cut) else None
        if idx is None or idx.size > NCG_NEAR_FULL * n:
            return slice(None), gap_all, *scaled_gap(gap_all)
        gap_near = gap_all[idx]
        return idx, gap_near, *scaled_gap(gap_near)

    t_nodes = np.zeros(n)  # T_n on every node: zero off the near set

    def traction_nodes():
        """T_n = (φn/δn) s e^{−s} (seed Eq. 3) on every node: on the near set, 0 off it (an array kept until the next
        call)."""
        t = nodal.traction_new(sv, ev)
        if isinstance(idx, slice):
            return t
        t_nodes[idx] = t
        return t_nodes

    def largest_force(f_spec, f_dw):
        """max_j |f_j| (Pa) of the force f = irfft(f_spec) + f_dw (its mean removed where clamped; f_dw None: 0)."""
        f = fft.irfft(f_spec)
        if f_dw is not None:
            f += f_dw
            if clamp:
                f -= np.mean(f)
        return float(np.max(np.abs(f)))

    def force_residual():
        """max_j |f_j| (Pa) of the force at the state; under the two-level preconditioner's split form
        (f_spec = ŷ), f = irfft(ŷ − K û) + D w with û exact (`TwoLevel.fold`: one rfft where it has a tail)."""
        nonlocal folded
        if parts is None:
            return largest_force(f_spec, f_dw)
        if other.fold(uh):
            folded = it
        return largest_force(f_spec - k * uh, f_dw)

    def full_residual():
        """max_j |f_j| / p_ref with every node's attraction (the converged state's check)."""
        gap_all = z_ind - fft.irfft(uh)
        s_all, e_all = scaled_gap(gap_all)
        t_all = nodal.traction(s_all, e_all)
        f_all = fft.rfft(t_all)
        f_all -= k * uh
        if clamp:
            f_all[0] = 0.0
        return float(np.max(np.abs(fft.irfft(f_all)))) / p_ref, gap_all, s_all, e_all, f_all, t_all

    guess = np.array(u_hat, dtype=complex, copy=True)
    uh = np.array(guess[-1], dtype=complex, copy=True)
    if clamp:
        uh[0] = 0.0
    idx, gap, sv, ev = near(NCG_NEAR_MARGIN, first=True)
    slack = NCG_NEAR_MARGIN * dn  # how far a far node may still approach before the near set is stale
    t_full = traction_nodes()  # T_n on every node at the state
    f_hat = fft.rfft(t_full)  # f̂ = rfft(T_n) − K û, q = 0 clamped on a half-plane (under K⁻¹; see below)
    f_hat -= k * uh
    if clamp:
        f_hat[0] = 0.0
    d_hat = np.zeros_like(f_hat)  # the search direction (spectrum), updated in place
    # the force in two parts, f = irfft(f_spec) + f_dw (mean-free where clamped): (f̂, None) under K⁻¹; under the
    # two-level preconditioner (ŷ, D w), f = irfft(ŷ − K û) + D w (`TwoLevel.apply_split`, f never on the nodes but
    # in the residual test, `force_residual`)
    f_spec, f_dw = f_hat, None
    f_old = (f_hat, None, None)  # the last force's (f_spec, f_dw, its x's parts under the two-level one or None)
    parts, d_parts, folded = None, None, 0  # this force's parts, the last direction's (e_d, E_K e_d), the last fold
    d_prev = None  # the last direction on the nodes (for f·d_old with the D w part)
    z_kd = None  # Zᵀ K d of the last direction on the coarse space (`TwoLevel.move`)
    rz_old, c2 = 1.0, 0.0  # f_old·K⁻¹f_old, d·Kd of the last direction
    restart = True
    residual, converged, message, failed = np.inf, False, "", ""
    eta = options.line_search_tol
    ratio = None  # last max|f| / rms(f): predicts when the max-norm test can pass
    engage_at, e_mid = cohesive_preconditioner.ENGAGE_AFTER, None  # earlier on a slow step (`slow_step`)
    early, mid = cohesive_preconditioner.ENGAGE_EARLY, cohesive_preconditioner.ENGAGE_EARLY // 2
    it = 0
    d_nodes = None  # d on the nodes where the preconditioner gives s there (`gfmd.cohesive_preconditioner`)
    while True:
        engaged = two_level and it >= engage_at
        if engaged and other is None:
            other = cohesive_preconditioner.build(preconditioner_name, fft, k, clamp, n, cz.curvature_scale,
                                                  stiffness_operator(model))
        if not engaged:
            rz, f_old_s, f_d_old = products(f_hat, f_old[0], d_hat, g, n)  # f·s, f_old·s, f·d_old; s = K⁻¹ f
            f_spec, f_dw = f_hat, None
        else:  # s = M⁻¹ f (`gfmd.cohesive_preconditioner`), rebuilt from the state (a restart where it changed)
            if (it - engage_at) % cohesive_preconditioner.REBUILD_EVERY == 0:
                k_loc = np.zeros(n)
                k_loc[idx] = nodal.stiffness(sv, ev)
                if other.rebuild(k_loc, uh) or it == engage_at:
                    restart = True
            if it - folded >= FOLD_EVERY and other.fold(uh):  # the tail bounded (its products' round-off)
                folded = it
            s_hat, s_nodes, f_spec, f_dw, z_ks, sums, parts = other.apply_split(t_full, uh, f_old[1], d_prev)
            if parts is not None:  # s = x' − Π Z (e_u + c₂): its products from the parts (`split_products`)
                spectral = stiffness_m(s_hat, s_hat if f_old[2] is None else f_old[2][0], d_hat, k, n)
                rz, f_old_s, f_d_old = cohesive_preconditioner.split_products(
                    spectral, parts, None if restart or f_old[2] is None else f_old[2][1:],
                    None if restart or d_parts is None else (*d_parts, z_kd), sums)
            else:  # no coarse space: ŝ exact (a restart where there was one before)
                rz, f_old_s, f_d_old = products_m(f_spec, f_old[0], d_hat, s_hat, n)
                if f_old[1] is not None:
                    f_old_s += float(np.dot(f_old[1], s_nodes if s_nodes is not None else fft.irfft(s_hat)))
        e_norm = np.sqrt(max(rz, 0.0))
        e_mid = e_norm if it == mid else e_mid
        if ratio is None or it % options.check_every == 0 or e_norm * ratio < options.tolerance * p_ref:
            # the test of `gfmd.algorithms.dynamics` (verification.mutations' stop-early-cohesive mutates all three)
            residual = force_residual() / model.reference_traction
            if residual < options.tolerance:
                if not isinstance(idx, slice):  # the far nodes' attraction included: converged as FIRE's is
                    residual, gap, sv, ev, f_hat, t_full = full_residual()
                    if not residual < options.tolerance:  # it counts after all: every node is near from here
                        idx, restart, ratio = slice(None), True, None
                        continue
                converged = True
                break
            ratio = residual * p_ref / e_norm if e_norm > 0 else 1.0
            if not np.isfinite(residual):
                failed = "non-finite force residual"
                break
        if it >= budget:
            residual = force_residual() / p_ref
            failed = f"not converged after {it} iterations (residual {residual:.3g} p_ref)"
            break
        if (two_level and it == early < engage_at and e_mid is not None and ratio is not None
                and cohesive_preconditioner.slow_step(e_mid, e_norm, it - mid, options.tolerance * p_ref / ratio,
                                                      engage_at - it)):
            engage_at = it + 1  # a slow step: the two-level preconditioner from the next iteration on
        it += 1
        # d = s + β d_old, and K s = f (K K⁻¹ = 1 on every mode but a half-plane's q = 0, where s = f = 0):
        # dE/dα(0) = −f·d = −(f·s + β f·d_old), d·Kd = f·s + 2β f·d_old + β² d_old·K d_old, no K d needed
        beta = 0.0 if restart else max(0.0, (rz - f_old_s) / rz_old)  # Polak–Ribière+
        slope0, c2 = -(rz + beta * f_d_old), rz + beta * (2.0 * f_d_old + beta * c2)
        if not slope0 < 0:  # not a descent direction: restart along s
            beta, slope0, c2 = 0.0, -rz, rz
            if not slope0 < 0:
                failed = "no descent direction"
                break
        if not engaged:
            direction(f_hat, g, beta, d_hat)  # d̂ ← ŝ + β d̂
        else:  # K s ≠ f: d·Kd as a sum over the modes
            c2 = direction_m(s_hat, beta, d_hat, k, n)  # d̂ ← ŝ + β d̂, d·Kd (the spectral parts' under the tails)
            # Zᵀ K d for the coarse load's move (None: made afresh from û at the next application)
            z_kd = z_ks if beta == 0.0 else None if z_ks is None or z_kd is None else z_ks + beta * z_kd
            if parts is not None:  # d's tail e_d = e_s + β e_d and E_K e_d with it; d·Kd from the parts
                e_s, k_s = parts[1], parts[2]
                d_parts = (e_s, k_s) if beta == 0.0 else (e_s + beta * d_parts[0], k_s + beta * d_parts[1])
                c2 = cohesive_preconditioner.split_energy(c2, *d_parts, z_kd)
            else:
                d_parts = None
            if s_nodes is not None and (beta == 0.0 or d_nodes is not None):  # d on the nodes without an irfft
                d_nodes = s_nodes if beta == 0.0 else combine_m(s_nodes, beta, d_nodes)
            else:
                d_nodes = None
        restart = False
        f_old, rz_old = (f_spec, f_dw, None if parts is None else (s_hat, parts[0], parts[3])), rz
        d_all = fft.irfft(d_hat) if not engaged or d_nodes is None else d_nodes
        d_prev = d_all
        approach = float(np.max(d_all)) if not isinstance(idx, slice) else 0.0  # Δn falls by α d: d > 0 approaches
        for _ in range(2):  # a second pass only when the step left the near set stale: rebuilt, searched again
            d = d_all[idx]
            # d·Ku = Σ_j d_j T_n,j − d·f: f = T_n − K u − ⟨T_n⟩ and Σ_j d_j = 0 on a half-plane
            law_slope, law_curvature = nodal.direction_sums(sv, ev, d)  # Σ_j T_n,j d_j, Σ_j k_loc,j d_j²: one pass
            c1 = law_slope + slope0

            alpha, found, gap_a, s_a, e_a = _ncg_line_search(nodal, c1, c2, law_curvature, slope0, gap, sv, ev, d,
                                                             dn, eta, options.max_move)
            if alpha * approach <= slack:
                break
            margin = NCG_NEAR_MARGIN + 2.0 * alpha * approach / dn
            idx, gap, sv, ev = near(margin)
            slack = margin * dn
            t_nodes[:] = 0.0  # T_n off the new near set: 0
        if not found and beta > 0.0:  # a conjugate direction failed: retry once along s = K⁻¹ f
            restart = True
            continue
        if not found:
            failed = "line search found no minimum along the search direction"
            break
        gap, sv, ev = gap_a, s_a, e_a
        slack -= alpha * approach
        t_full = traction_nodes()
        if two_level and it >= engage_at:  # the next iteration's force from t_full and û (`TwoLevel.apply_split`)
            if engaged:
                other.move(uh, d_hat, alpha, z_kd, *(d_parts or (None, None)))  # û ← û + α d, Zᵀ K u with it
            else:  # (a coarse space made at the next iteration computes its Zᵀ K u afresh)
                uh += alpha * d_hat
        else:
            f_hat = fft.rfft(t_full)
            advance(uh, d_hat, alpha, k, f_hat)  # û ← û + α d̂, f̂ ← rfft(T_n) − K û
            if clamp:
                f_hat[0] = 0.0
    if failed:  # the chain's next algorithm restarts from the guess (`gfmd.chains`)
        return stall(guess, it, residual, fft.pairs, LABEL, f"NCG stopped ({failed})")
    pairs = fft.pairs
    out = finish(problem, uh[None, :], it, residual, converged, message)
    out.fft_pairs = pairs + 0.5
    out.method = LABEL
    return out


def _ncg_line_search(nodal, c1, c2, law_curvature, slope0, gap, sv, ev, d, dn, eta, max_move):
    """Safeguarded Newton on dE/dα along d (`solve`): (α, found, Δn, s, e^{−s} at α; another law's T_n, k_loc).

    dE/dα = c1 + α c2 − Σ_j T_n(Δn_j − α d_j) d_j, d²E/dα² = c2 + Σ_j k_loc,j d_j² (`gfmd.ncg_nodes`: `nodal.trial`
    evaluates a trial state, Eq. 3 in one fused pass where numba is installed); stops at |dE/dα| ≤ eta |dE/dα(0)|.
    law_curvature: Σ_j k_loc,j d_j² at α = 0 (`nodal.direction_sums`, with c1's law term). found = False with α = 0:
    no step lowers E.
    """
    curv0 = c2 + law_curvature
    reach = float(np.max(np.abs(d))) if d.size else 0.0
    alpha = -slope0 / curv0 if curv0 > 0 else (max_move * dn / reach if reach > 0 else 1.0)
    lo, hi = 0.0, np.inf
    p_lo, p_hi = slope0, np.inf
    found = False
    widths = []
    for _ in range(100):
        gap_a, s_a, e_a, work, curv = nodal.trial(gap, d, alpha)
        p = c1 + alpha * c2 - work
        if not np.isfinite(p):
            hi, p_hi = alpha, np.inf
        elif abs(p) <= eta * abs(slope0):
            found = True
            break
        elif p < 0:
            lo, p_lo = alpha, p
        else:
            hi, p_hi = alpha, p
        c = c2 + (curv if curv is not None else nodal.curvature_sum(s_a, e_a, d)) if np.isfinite(p) else np.nan
        nxt = alpha - p / c if c > 0 else np.nan
        if np.isfinite(hi):
            if not lo < nxt < hi:
                nxt = lo - p_lo * (hi - lo) / (p_hi - p_lo) if np.isfinite(p_hi) else np.nan
                if not (lo + 0.01 * (hi - lo) < nxt < hi - 0.01 * (hi - lo)):
                    nxt = 0.5 * (lo + hi)
            widths.append(hi - lo)
            if len(widths) > 2 and widths[-1] > 0.5 * widths[-3]:  # Newton creeps (steep repulsive
                nxt = 0.5 * (lo + hi)  # side of the law): bisect whenever two trials did not halve the bracket
            if hi - lo <= 1e-14 * hi:
                alpha = lo if lo > 0 else hi
                gap_a, s_a, e_a, _, _ = nodal.trial(gap, d, alpha)
                found = alpha > 0
                break
        elif not nxt > alpha:
            nxt = 4.0 * alpha
        alpha = nxt
    if not found and lo > 0:  # no tight minimum found, but E decreases up to lo: take that step
        alpha = lo
        gap_a, s_a, e_a, _, _ = nodal.trial(gap, d, alpha)
        found = True
    if not found:
        alpha = 0.0
    return alpha, found, gap_a, s_a, e_a
