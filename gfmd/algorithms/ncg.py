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
from typing import NamedTuple

import numpy as np

from .. import cohesive_preconditioner, kernels
from ..ncg_nodes import line_search, nodes_for
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
#: (docs/design/performance.md): 1, 4, 8, 16 and never give the same iterations and states within 1e-14
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
    ncg = _setup(problem, options)
    st = _init(ncg, start)
    model = problem.model
    while not (st.converged or st.failed):
        e_norm = _preconditioned_products(ncg, st)
        if st.ratio is None or st.it % options.check_every == 0 or e_norm * st.ratio < options.tolerance * ncg.p_ref:
            # the test of `gfmd.algorithms.dynamics` (verification.mutations' stop-early-cohesive mutates all three)
            st.residual = residual = _force_residual(ncg, st) / model.reference_traction
            if residual < options.tolerance:
                st.converged = _confirmed(ncg, st)  # else every node is near from here, and the test comes again
                continue
            st.ratio = residual * ncg.p_ref / e_norm if e_norm > 0 else 1.0
            if not np.isfinite(residual):
                st.failed = "non-finite force residual"
                break
        if st.it >= ncg.budget:
            st.residual = _force_residual(ncg, st) / ncg.p_ref
            st.failed = f"not converged after {st.it} iterations (residual {st.residual:.3g} p_ref)"
            break
        _engage_early(ncg, st, e_norm)
        st.it += 1
        _iterate(ncg, st)
    return _result(ncg, st)


class _Ncg(NamedTuple):
    """What one step's NCG holds fixed: the problem, the law's nodal work, the spectral kernels, the preconditioner."""

    problem: object
    model: object
    law: object  # the law (the law protocol)
    z_ind: np.ndarray
    options: Options
    fft: Fft
    n: int
    clamp: bool  # half-plane: the q = 0 mode stays 0
    p_ref: float
    dn: float  # the law's length (m): the near set's margins and the line search's first step
    nodal: object  # the law's nodal work: a fused kernel for its closed form, else its tractions and tangent
    budget: int  # the step's iterations before it is handed over
    k: np.ndarray  # K's rfft coefficients (Pa/m)
    g: np.ndarray  # K⁻¹'s, 0 on a half-plane's q = 0
    kernels: tuple  # the spectral algebra under K⁻¹ (numpy or fused): products, direction, advance
    split_kernels: tuple  # ... under the two-level preconditioner: products, direction, combine, stiffness
    preconditioner: str  # `cohesive_preconditioner.resolve`'s name
    two_level: bool  # a two-level preconditioner engages after the step's first iterations
    cut: float  # s_c: beyond s_c·dn every node's |T_n| is below NCG_FAR_FRACTION · tolerance · p_ref
    early: int  # the iteration that tests for a slow step (`cohesive_preconditioner.slow_step`)
    mid: int  # ... measuring its rate from this one


@dataclass
class NcgState:
    """The NCG iterate: the displacements, the near set, the force in its parts and the CG recurrence."""

    guess: np.ndarray  # the step's start (what a stalled step hands back)
    uh: np.ndarray  # û (rfft; under the two-level preconditioner a spectral part plus its coarse tail)
    t_nodes: np.ndarray  # T_n on every node: zero off the near set
    idx: object = None  # the near set: node indices, or slice(None) for every node
    gap: np.ndarray = None  # Δn on the near set
    sv: np.ndarray = None  # the law's nodal state there (`gfmd.ncg_nodes`: Eq. 3's (s, e^{−s}), else (T_n, k_loc))
    ev: np.ndarray = None
    slack: float = 0.0  # how far a far node may still approach before the near set is stale
    t_full: np.ndarray = None  # T_n on every node at the state
    f_hat: np.ndarray = None  # f̂ = rfft(T_n) − K û, q = 0 clamped on a half-plane (under K⁻¹)
    d_hat: np.ndarray = None  # the search direction (spectrum), updated in place
    # the force in two parts, f = irfft(f_spec) + f_dw (mean-free where clamped): (f̂, None) under K⁻¹; under the
    # two-level preconditioner (ŷ, D w), f = irfft(ŷ − K û) + D w (`TwoLevel.apply_split`, f never on the nodes but
    # in the residual test, `_force_residual`)
    f_spec: np.ndarray = None
    f_dw: np.ndarray = None
    f_old: tuple = None  # the last force's (f_spec, f_dw, its x's parts under the two-level one or None)
    parts: tuple = None  # this force's parts under the two-level preconditioner
    d_parts: tuple = None  # the last direction's (e_d, E_K e_d)
    folded: int = 0  # the iteration of the last fold of û's coarse tail
    d_prev: np.ndarray = None  # the last direction on the nodes (for f·d_old with the D w part)
    z_kd: np.ndarray = None  # Zᵀ K d of the last direction on the coarse space (`TwoLevel.move`)
    d_nodes: np.ndarray = None  # d on the nodes where the preconditioner gives s there
    rz_old: float = 1.0  # f_old·s_old
    c2: float = 0.0  # d·Kd of the direction
    restart: bool = True
    other: object = None  # the two-level preconditioner, once a step engages it
    engage_at: int = 0  # the iteration from which it runs (earlier on a slow step)
    e_mid: float = None  # the energy norm at iteration `mid`
    ratio: float = None  # last max|f| / energy norm: predicts when the max-norm test can pass
    # this iteration's preconditioned products: f·s, f_old·s, f·d_old; s and its nodal values and Zᵀ K s
    engaged: bool = False
    rz: float = 0.0
    f_old_s: float = 0.0
    f_d_old: float = 0.0
    s_hat: np.ndarray = None
    s_nodes: np.ndarray = None
    z_ks: np.ndarray = None
    it: int = 0
    residual: float = np.inf
    converged: bool = False
    failed: str = ""  # why the step is handed over


def _setup(problem, options):
    """The fixed part of one step (`_Ncg`); refuses "two-level" for a law without a curvature scale."""
    model, cz = problem.model, problem.law.law
    fft = Fft(model.nodes, grid=model.grid)
    p_ref = model.reference_traction
    nodal = nodes_for(cz)
    budget = min(NCG_BUDGET, options.max_iterations // 2) if options.max_iterations > 1 else 1
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)
    g = _inverse(k, model.half_plane)
    spectral = kernels.ncg_kernels(grid=model.grid)  # the spectral algebra (numpy or fused)
    split = kernels.preconditioned_kernels()  # under the two-level one
    cohesive_preconditioner.check(options, model.grid)
    if cz.curvature_scale is None and options.cohesive_preconditioner == "two-level":
        raise ValueError(f"Settings.cohesive_preconditioner = 'two-level' needs a law with a curvature scale "
                         f"(seed Eq. 3's φn/δn²); the {cz.name} gives none")
    preconditioner_name = cohesive_preconditioner.resolve(options.cohesive_preconditioner, model.grid,
                                                          cz.curvature_scale is None)
    # built when a step first engages it (ENGAGE_AFTER iterations): the steps that finish before never pay its setup
    # (an irfft and two cumulative sums over 2N: ≈ 6 ms at 2^17, once per task, K's sums kept on the
    # model's `stiffness_operator`; a φn* = 0.001 task −6 to −11 % CPU)
    far = NCG_FAR_FRACTION * options.tolerance * p_ref  # a far node's |T_n| is below this (Pa)
    return _Ncg(problem=problem, model=model, law=cz, z_ind=problem.z_ind, options=options, fft=fft, n=model.nodes,
                clamp=model.half_plane, p_ref=p_ref, dn=float(cz.length_scale), nodal=nodal, budget=budget, k=k, g=g,
                kernels=spectral, split_kernels=split, preconditioner=preconditioner_name,
                two_level=preconditioner_name != "stiffness", cut=cz.far_reach(far),
                early=cohesive_preconditioner.ENGAGE_EARLY, mid=cohesive_preconditioner.ENGAGE_EARLY // 2)


def _inverse(k, clamp):
    """K⁻¹ on the modes (0 where K is not positive, and on a half-plane's q = 0)."""
    g = np.zeros(k.size)
    np.divide(1.0, k, out=g, where=k > 0)
    if clamp:
        g[0] = 0.0
    return g


def _init(ncg, start):
    """The first iterate: the start's last state (q = 0 clamped), its near set and its force f̂."""
    guess = np.array(start, dtype=complex, copy=True)
    uh = np.array(guess[-1], dtype=complex, copy=True)
    if ncg.clamp:
        uh[0] = 0.0
    st = NcgState(guess=guess, uh=uh, t_nodes=np.zeros(ncg.n), engage_at=cohesive_preconditioner.ENGAGE_AFTER)
    st.idx, st.gap, st.sv, st.ev = _near(ncg, st, NCG_NEAR_MARGIN, first=True)
    st.slack = NCG_NEAR_MARGIN * ncg.dn
    st.t_full = _traction_nodes(ncg, st)
    f_hat = ncg.fft.rfft(st.t_full)
    f_hat -= ncg.k * uh
    if ncg.clamp:
        f_hat[0] = 0.0
    st.f_hat, st.d_hat = f_hat, np.zeros_like(f_hat)
    st.f_spec, st.f_dw = f_hat, None
    st.f_old = (f_hat, None, None)
    return st


def _near(ncg, st, margin, first=False):
    """(near, Δn on it, the law's nodal state there) at the state û: the nodes with Δn < (s_c + margin) δn
    (slice(None): every node), from a fresh irfft."""
    if st.other is not None:  # û exact (the two-level preconditioner's coarse tail folded in)
        st.other.fold(st.uh)
    gap_all = ncg.z_ind - ncg.fft.irfft(st.uh)
    if first:  # an initial guess out of the law's range raises, as FIRE's does
        ncg.law.check_gaps(gap_all)
    idx = np.flatnonzero(gap_all < (ncg.cut + margin) * ncg.dn) if np.isfinite(ncg.cut) else None
    if idx is None or idx.size > NCG_NEAR_FULL * ncg.n:
        return slice(None), gap_all, *ncg.nodal.state(gap_all)
    gap_near = gap_all[idx]
    return idx, gap_near, *ncg.nodal.state(gap_near)


def _traction_nodes(ncg, st):
    """T_n on every node: the law's on the near set, 0 off it (an array kept until the next call)."""
    t = ncg.nodal.traction_new(st.sv, st.ev)
    if isinstance(st.idx, slice):
        return t
    st.t_nodes[st.idx] = t
    return st.t_nodes


def _largest_force(ncg, f_spec, f_dw):
    """max_j |f_j| (Pa) of the force f = irfft(f_spec) + f_dw (its mean removed where clamped; f_dw None: 0)."""
    f = ncg.fft.irfft(f_spec)
    if f_dw is not None:
        f += f_dw
        if ncg.clamp:
            f -= np.mean(f)
    return float(np.max(np.abs(f)))


def _force_residual(ncg, st):
    """max_j |f_j| (Pa) of the force at the state; under the two-level preconditioner's split form
    (f_spec = ŷ), f = irfft(ŷ − K û) + D w with û exact (`TwoLevel.fold`: one rfft where it has a tail)."""
    if st.parts is None:
        return _largest_force(ncg, st.f_spec, st.f_dw)
    if st.other.fold(st.uh):
        st.folded = st.it
    return _largest_force(ncg, st.f_spec - ncg.k * st.uh, st.f_dw)


def _confirmed(ncg, st):
    """Whether a state that passed the test on the near set passes it with every node's attraction (the converged
    state's check, as FIRE's); if not, the far nodes count after all: every node is near from here, the
    direction restarts."""
    if isinstance(st.idx, slice):
        return True
    gap_all = ncg.z_ind - ncg.fft.irfft(st.uh)
    s_all, e_all = ncg.nodal.state(gap_all)
    t_all = ncg.nodal.traction(s_all, e_all)
    f_all = ncg.fft.rfft(t_all)
    f_all -= ncg.k * st.uh
    if ncg.clamp:
        f_all[0] = 0.0
    st.residual = float(np.max(np.abs(ncg.fft.irfft(f_all)))) / ncg.p_ref
    st.gap, st.sv, st.ev, st.f_hat, st.t_full = gap_all, s_all, e_all, f_all, t_all
    if not st.residual < ncg.options.tolerance:
        st.idx, st.restart, st.ratio = slice(None), True, None
        return False
    return True


def _preconditioned_products(ncg, st):
    """f·s, f_old·s and f·d_old for s the preconditioned force (K⁻¹ f, or the two-level M⁻¹ f once engaged, which
    is built here when first engaged); returns the energy norm (f·s)^½."""
    st.engaged = ncg.two_level and st.it >= st.engage_at
    if st.engaged and st.other is None:
        st.other = cohesive_preconditioner.build(ncg.preconditioner, ncg.fft, ncg.k, ncg.clamp, ncg.n,
                                                 ncg.law.curvature_scale, stiffness_operator(ncg.model))
    if not st.engaged:
        products = ncg.kernels[0]
        st.rz, st.f_old_s, st.f_d_old = products(st.f_hat, st.f_old[0], st.d_hat, ncg.g, ncg.n)  # s = K⁻¹ f
        st.f_spec, st.f_dw = st.f_hat, None
    else:
        _two_level_products(ncg, st)
    e_norm = np.sqrt(max(st.rz, 0.0))
    st.e_mid = e_norm if st.it == ncg.mid else st.e_mid
    return e_norm


def _two_level_products(ncg, st):
    """s = M⁻¹ f (`gfmd.cohesive_preconditioner`), M rebuilt from the state every REBUILD_EVERY iterations (a restart
    where it changed), û's coarse tail folded at least every FOLD_EVERY; the products from the split parts."""
    products_m, _, _, stiffness_m = ncg.split_kernels
    if (st.it - st.engage_at) % cohesive_preconditioner.REBUILD_EVERY == 0:
        k_loc = np.zeros(ncg.n)
        k_loc[st.idx] = ncg.nodal.stiffness(st.sv, st.ev)
        if st.other.rebuild(k_loc, st.uh) or st.it == st.engage_at:
            st.restart = True
    if st.it - st.folded >= FOLD_EVERY and st.other.fold(st.uh):  # the tail bounded (its products' round-off)
        st.folded = st.it
    st.s_hat, st.s_nodes, st.f_spec, st.f_dw, st.z_ks, sums, st.parts = st.other.apply_split(
        st.t_full, st.uh, st.f_old[1], st.d_prev)
    f_old = st.f_old
    if st.parts is not None:  # s = x' − Π Z (e_u + c₂): its products from the parts (`split_products`)
        spectral = stiffness_m(st.s_hat, st.s_hat if f_old[2] is None else f_old[2][0], st.d_hat, ncg.k, ncg.n)
        st.rz, st.f_old_s, st.f_d_old = cohesive_preconditioner.split_products(
            spectral, st.parts, None if st.restart or f_old[2] is None else f_old[2][1:],
            None if st.restart or st.d_parts is None else (*st.d_parts, st.z_kd), sums)
    else:  # no coarse space: ŝ exact (a restart where there was one before)
        st.rz, st.f_old_s, st.f_d_old = products_m(st.f_spec, f_old[0], st.d_hat, st.s_hat, ncg.n)
        if f_old[1] is not None:
            s_nodes = st.s_nodes if st.s_nodes is not None else ncg.fft.irfft(st.s_hat)
            st.f_old_s += float(np.dot(f_old[1], s_nodes))


def _engage_early(ncg, st, e_norm):
    """A slow step (`cohesive_preconditioner.slow_step`, at iteration `early`) engages the two-level preconditioner
    from the next iteration on."""
    if (ncg.two_level and st.it == ncg.early < st.engage_at and st.e_mid is not None and st.ratio is not None
            and cohesive_preconditioner.slow_step(st.e_mid, e_norm, st.it - ncg.mid,
                                                  ncg.options.tolerance * ncg.p_ref / st.ratio, st.engage_at - st.it)):
        st.engage_at = st.it + 1


def _iterate(ncg, st):
    """One NCG iteration from this iteration's products: the direction, the line search along it, the move."""
    beta, slope0 = _conjugate(st)
    if st.failed:
        return
    _direction(ncg, st, beta)
    st.restart = False
    st.f_old = (st.f_spec, st.f_dw, None if st.parts is None else (st.s_hat, st.parts[0], st.parts[3]))
    st.rz_old = st.rz
    alpha, found, approach, trial = _search(ncg, st, slope0)
    if not found and beta > 0.0:  # a conjugate direction failed: retry once along s = K⁻¹ f
        st.restart = True
        return
    if not found:
        st.failed = "line search found no minimum along the search direction"
        return
    _move(ncg, st, alpha, approach, trial)


def _conjugate(st):
    """Polak–Ribière+ β and the slope dE/dα(0) along d = s + β d_old, d·Kd into `c2`; a restart along s where d is
    no descent direction (`failed` where s is none either)."""
    # d = s + β d_old, and K s = f (K K⁻¹ = 1 on every mode but a half-plane's q = 0, where s = f = 0):
    # dE/dα(0) = −f·d = −(f·s + β f·d_old), d·Kd = f·s + 2β f·d_old + β² d_old·K d_old, no K d needed
    rz, f_d_old = st.rz, st.f_d_old
    beta = 0.0 if st.restart else max(0.0, (rz - st.f_old_s) / st.rz_old)  # Polak–Ribière+
    slope0, st.c2 = -(rz + beta * f_d_old), rz + beta * (2.0 * f_d_old + beta * st.c2)
    if not slope0 < 0:  # not a descent direction: restart along s
        beta, slope0, st.c2 = 0.0, -rz, rz
        if not slope0 < 0:
            st.failed = "no descent direction"
    return beta, slope0


def _direction(ncg, st, beta):
    """d̂ ← ŝ + β d̂; under the two-level preconditioner (K s ≠ f) also d·Kd as a sum over the modes, Zᵀ K d,
    d's coarse tail and d on the nodes where s is there."""
    if not st.engaged:
        direction = ncg.kernels[1]
        direction(st.f_hat, ncg.g, beta, st.d_hat)  # d̂ ← ŝ + β d̂
        return
    _, direction_m, combine_m, _ = ncg.split_kernels
    # d̂ ← ŝ + β d̂ and d·Kd (the spectral parts' under the tails)
    st.c2 = direction_m(st.s_hat, beta, st.d_hat, ncg.k, ncg.n)
    # Zᵀ K d for the coarse load's move (None: made afresh from û at the next application)
    st.z_kd = st.z_ks if beta == 0.0 else None if st.z_ks is None or st.z_kd is None else st.z_ks + beta * st.z_kd
    if st.parts is not None:  # d's tail e_d = e_s + β e_d and E_K e_d with it; d·Kd from the parts
        e_s, k_s = st.parts[1], st.parts[2]
        st.d_parts = (e_s, k_s) if beta == 0.0 else (e_s + beta * st.d_parts[0], k_s + beta * st.d_parts[1])
        st.c2 = cohesive_preconditioner.split_energy(st.c2, *st.d_parts, st.z_kd)
    else:
        st.d_parts = None
    if st.s_nodes is not None and (beta == 0.0 or st.d_nodes is not None):  # d on the nodes without an irfft
        st.d_nodes = st.s_nodes if beta == 0.0 else combine_m(st.s_nodes, beta, st.d_nodes)
    else:
        st.d_nodes = None


def _search(ncg, st, slope0):
    """The line search along d on the near set (`gfmd.ncg_nodes.line_search`): (α, found, max_j d_j, the trial's
    (Δn, nodal state)); searched again on a rebuilt near set where the step could have brought a far node near."""
    d_all = ncg.fft.irfft(st.d_hat) if not st.engaged or st.d_nodes is None else st.d_nodes
    st.d_prev = d_all
    approach = float(np.max(d_all)) if not isinstance(st.idx, slice) else 0.0  # Δn falls by α d: d > 0 approaches
    for _ in range(2):  # a second pass only when the step left the near set stale: rebuilt, searched again
        d = d_all[st.idx]
        # d·Ku = Σ_j d_j T_n,j − d·f: f = T_n − K u − ⟨T_n⟩ and Σ_j d_j = 0 on a half-plane
        law_slope, law_curvature = ncg.nodal.direction_sums(st.sv, st.ev, d)  # Σ_j T_n,j d_j, Σ_j k_loc,j d_j²
        c1 = law_slope + slope0

        alpha, found, gap_a, s_a, e_a = line_search(ncg.nodal, c1, st.c2, law_curvature, slope0, st.gap, st.sv, st.ev,
                                                    d, ncg.dn, ncg.options.line_search_tol, ncg.options.max_move)
        if alpha * approach <= st.slack:
            break
        margin = NCG_NEAR_MARGIN + 2.0 * alpha * approach / ncg.dn
        st.idx, st.gap, st.sv, st.ev = _near(ncg, st, margin)
        st.slack = margin * ncg.dn
        st.t_nodes[:] = 0.0  # T_n off the new near set: 0
    return alpha, found, approach, (gap_a, s_a, e_a)


def _move(ncg, st, alpha, approach, trial):
    """û ← û + α d̂ with the trial state's nodal values; f̂ ← rfft(T_n) − K û under K⁻¹ (under the two-level
    preconditioner the next iteration's force comes from T_n and û, `TwoLevel.apply_split`)."""
    st.gap, st.sv, st.ev = trial
    st.slack -= alpha * approach
    st.t_full = _traction_nodes(ncg, st)
    if ncg.two_level and st.it >= st.engage_at:
        if st.engaged:
            st.other.move(st.uh, st.d_hat, alpha, st.z_kd, *(st.d_parts or (None, None)))  # û ← û + α d, Zᵀ K u
        else:  # (a coarse space made at the next iteration computes its Zᵀ K u afresh)
            st.uh += alpha * st.d_hat
    else:
        st.f_hat = ncg.fft.rfft(st.t_full)
        advance = ncg.kernels[2]
        advance(st.uh, st.d_hat, alpha, ncg.k, st.f_hat)  # û ← û + α d̂, f̂ ← rfft(T_n) − K û
        if ncg.clamp:
            st.f_hat[0] = 0.0


def _result(ncg, st):
    """The step's `Relaxed`; a failed step is handed over from its guess (the chain's next algorithm)."""
    if st.failed:
        return stall(st.guess, st.it, st.residual, ncg.fft.pairs, LABEL, f"NCG stopped ({st.failed})")
    pairs = ncg.fft.pairs
    out = finish(ncg.problem, st.uh[None, :], st.it, st.residual, st.converged, "")
    out.fft_pairs = pairs + 0.5
    out.method = LABEL
    return out
