"""The projected preconditioned CG on the contact pressures (the dual of the hard wall), shared by the dual
hard-wall algorithms: `gfmd.algorithms.hard_wall_dual_cg` (the band of K_AA) and
`gfmd.algorithms.hard_wall_two_level_cg` (the band balanced by a coarse space). Not an algorithm itself: each
algorithm module keeps its preconditioner and `solve(problem, start, options)`, and calls `solve_dual` with them
and its options (`DualOptions`, or one that extends it).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import NamedTuple

import numpy as np

from .fft import Fft, dot
from .problem import stiffness_operator
from .settings import Relaxed, not_converged, stall
from .stopping import finish, wall_check, wall_residual

#: The dual hard-wall CG hands a step over to the primal only when its contact set grows past this
#: multiple of `Settings.dual_contact_limit` (`solve_dual`). Measured (section 7, N = 2^16):
#: with factor 1, steps ending at a_rel = 0.025–0.055 were handed over mid-way and cost 1.1–1.5× the
#: dual alone.
TRANSIENT_FACTOR = 2.0


@dataclass(frozen=True)
class DualOptions:
    """What the dual CG reads: the `gfmd.settings.Settings` fields of these names."""

    tolerance: float  # max nodal force residual / p_ref
    max_iterations: int
    proportioning: float  # Dostál's proportioning test: release pulling wall nodes past this × the free residual
    dual_contact_limit: float  # the fraction of the nodes past which the step goes to the primal CG


def solve_dual(problem, start, options, *, label, band_stiffness, preconditioner=None):
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
    0.25) and – / 17.3 / 14.0 / 13.6 (up to 0.083); with 1.8 nm jumps (docs/design/performance.md,
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
    model = problem.model
    fft = Fft(model.nodes, grid=model.grid)
    k = np.ascontiguousarray(np.real(model.k_zz))
    z = np.ascontiguousarray(problem.z_ind, dtype=float)
    guess = _guess(problem, start, options, fft, k, z, label)
    if isinstance(guess, Relaxed):
        return guess
    dual = _setup(problem, options, fft, k, z, band_stiffness, preconditioner)
    state = _init(dual, *guess)
    while not (state.hand_over or state.converged or state.message) and state.it < options.max_iterations:
        _step(dual, state)
    return _result(problem, dual, state, label)


class _Dual(NamedTuple):
    """What one step's dual CG holds fixed: the operators, the targets and two scratch arrays."""

    model: object
    options: object
    fft: Fft
    k: np.ndarray  # K's rfft coefficients (Pa/m)
    g: np.ndarray  # G = K⁻¹'s rfft coefficients
    z: np.ndarray  # z_ind
    wall_tolerance: float
    tol: float  # tolerance · p_ref (Pa)
    gamma2: float  # proportioning²
    transient_limit: float  # the contact set's size that hands over mid-way
    k_kernel: np.ndarray  # K's real-space kernel
    band_stiffness: object
    wrap: object  # the algorithm's `precondition(r, band, act)`, or None: the band alone
    sparse_in: np.ndarray  # G's input, zero off the nodes being written
    g_d: np.ndarray  # G d of the search direction


@dataclass
class DualState:
    """The dual CG's iterate: pressures on the contact set A, the gaps, the band of K_AA and the CG recurrence."""

    pressure: np.ndarray  # P (Pa), full length, zero off A
    act: np.ndarray  # A: sorted node indices (a new object whenever A changes)
    gap: np.ndarray  # Δ = z_ind + G P
    ku: np.ndarray  # K u of the last candidate tested (of the guess before)
    band_nodes: np.ndarray  # U ⊇ A, the nodes the band was built on
    k_band: object = None  # K_UU truncated to the band (CSR)
    band_in: np.ndarray = None
    d: np.ndarray = None  # the search direction on A
    rz_old: float = 1.0
    restart: bool = True
    stop: float = 0.5  # a candidate is tested when max |s| < stop · tol
    it: int = 0
    residual: float = np.inf
    converged: bool = False
    message: str = ""
    hand_over: bool = False


def _guess(problem, start, options, fft, k, z, label):
    """The guess's (pressures, contact set, K u): P = p_far − K u where positive, p_far = K u on the nodes the
    guess leaves free; or its `Relaxed` when it already passes the test or its contact set is too large."""
    model, wall_tolerance = problem.model, problem.wall_tolerance
    u_hat_z = np.ascontiguousarray(start[-1])
    u = fft.irfft(u_hat_z)
    ku = fft.irfft(k * u_hat_z)
    if float(np.max(u - z)) <= wall_tolerance:  # feasible up to round-off: already converged?
        residual = wall_residual(model, u, ku, z, wall_tolerance)
        if residual < options.tolerance:
            out = finish(problem, fft.rfft(np.minimum(u, z))[None, :], 0, residual, True, "", (u, ku))
            out.fft_pairs, out.method = fft.pairs, label  # the fields from the arrays the residual was taken on
            return out
    free = z - u > 0
    p_far = float(np.median(ku[free])) if model.half_plane and free.any() else 0.0
    pressure = p_far - ku  # full length; zero off A from here on
    on_wall = pressure > 1e-9 * float(np.max(np.abs(ku)))
    if np.count_nonzero(on_wall) > options.dual_contact_limit * model.nodes:  # the primal CG from the guess
        return stall(start, 0, np.inf, fft.pairs, "",  # not run: no label
                     f"contact set of the guess above {options.dual_contact_limit:g} of the nodes")
    pressure[~on_wall] = 0.0
    return pressure, np.flatnonzero(on_wall), ku


def _setup(problem, options, fft, k, z, band_stiffness, preconditioner):
    """The fixed part of one step (`_Dual`); calls the algorithm's preconditioner factory once."""
    model = problem.model
    n = model.nodes
    g = np.ascontiguousarray(np.real(stiffness_operator(model).inv_mass[0]))
    k_kernel = stiffness_operator(model).kept(("stiffness kernel", fft.backend), lambda: fft.irfft(k.astype(complex)))
    wrap = preconditioner(fft, g) if preconditioner is not None else None
    limit = options.dual_contact_limit * n
    return _Dual(model=model, options=options, fft=fft, k=k, g=g, z=z, wall_tolerance=problem.wall_tolerance,
                 tol=options.tolerance * model.reference_traction, gamma2=options.proportioning**2,
                 transient_limit=min(TRANSIENT_FACTOR * limit, n - 2), k_kernel=k_kernel,
                 band_stiffness=band_stiffness, wrap=wrap, sparse_in=np.zeros(n), g_d=np.empty(n))


def _init(dual, pressure, act, ku):
    """The first iterate: the guess's gaps and the band on its contact set."""
    state = DualState(pressure=pressure, act=act, gap=np.empty(dual.model.nodes), ku=ku, band_nodes=act,
                      d=np.zeros(act.size))
    _recompute_gap(dual, state)
    _rebuild_band(dual, state)
    return state


def _g_times(dual, act, values, out):
    """out ← G χ_A values: one FFT pair."""
    dual.sparse_in[act] = values
    dual.fft.apply_to(dual.g, dual.sparse_in, out)
    dual.sparse_in[act] = 0.0
    return out


def _recompute_gap(dual, state):
    """Δ = z_ind + G P, from the pressures on A."""
    _g_times(dual, state.act, state.pressure[state.act], state.gap)
    np.add(state.gap, dual.z, out=state.gap)


def _primal_state(dual, state):
    """u = z_ind on A, z_ind − max(Δ, 0) off A."""
    u_new = dual.z - np.maximum(state.gap, 0.0)
    u_new[state.act] = dual.z[state.act]
    return u_new


def _rebuild_band(dual, state):
    """The band on U = A. It is rebuilt only when nodes outside U join A (leaving A needs no rebuild:
    rows and columns of U \\ A meet zeros and are not read)."""
    state.band_nodes = state.act
    state.k_band = dual.band_stiffness(dual.k_kernel, state.band_nodes)
    state.band_in = np.zeros(state.band_nodes.size)


def _band(state, r):
    """K_band restricted to A, times r."""
    at = np.searchsorted(state.band_nodes, state.act)
    state.band_in[at] = r
    out = (state.k_band @ state.band_in)[at]
    state.band_in[at] = 0.0
    return out


def _precondition(dual, state, r):
    return _band(state, r) if dual.wrap is None else dual.wrap(r, partial(_band, state), state.act)


def _step(dual, state):
    """One pass of the loop: admit penetrating nodes to A, or test a candidate, or take one CG iteration."""
    r = -state.gap[state.act]
    s = _precondition(dual, state, r)
    worst = float(np.max(np.abs(s))) if state.act.size else 0.0
    if _admit(dual, state, r, worst):
        return
    if worst < state.stop * dual.tol:
        _candidate(dual, state)
        return
    _cg_iteration(dual, state, r, s)


def _admit(dual, state, r, worst):
    """Nodes off A that penetrate join A with P = 0 (restart) once the norm of their gaps exceeds
    `proportioning` × that of Δ_A or the CG has settled; True if any joined."""
    gap, tol = state.gap, dual.tol
    # penetration off A, counted once its force (≈ K(0)_jj |Δ_j|) is not negligible
    enter = np.empty(0, np.int64)
    penetration_tol = 0.1 * state.stop * tol / dual.k_kernel[0]
    if float(np.min(gap)) < -penetration_tol:
        off = gap < -penetration_tol
        off[state.act] = False
        enter = np.flatnonzero(off)
    if not enter.size:
        return False
    g_enter = gap[enter]
    if not (dot(g_enter, g_enter) > dual.gamma2 * dot(r, r) or worst < state.stop * tol):
        return False
    state.act = np.union1d(state.act, enter)
    state.hand_over = state.act.size > dual.transient_limit
    if not np.isin(enter, state.band_nodes, assume_unique=True).all():
        _rebuild_band(dual, state)
    state.restart = True
    return True


def _candidate(dual, state):
    """The primal residual with a fresh K u; not passing, the next test waits for a tenfold smaller max |s|."""
    u = _primal_state(dual, state)
    state.residual, state.converged, state.message = wall_check(
        dual.model, dual.fft, dual.k, u, state.ku, dual.z, dual.wall_tolerance, dual.options.tolerance)
    if state.converged or state.message:
        return
    state.stop *= 0.1
    state.hand_over = state.stop < 1e-4


def _cg_iteration(dual, state, r, s):
    """One preconditioned CG step on A; pressures it drives negative are projected to zero and leave A
    (Polonsky–Keer: the step is kept, Δ recomputed, restart)."""
    state.it += 1
    rz = dot(r, s)
    if state.restart or state.rz_old <= 0:
        state.d = s.copy()
        state.restart = False
    else:
        state.d = s + (rz / state.rz_old) * state.d
    state.rz_old = rz
    act, d, g_d = state.act, state.d, dual.g_d
    _g_times(dual, act, d, g_d)
    curvature = dot(d, g_d[act])
    if not curvature > 0:
        state.message = "diverged: non-positive curvature along the search direction"
        return
    alpha = rz / curvature
    if not np.isfinite(alpha):
        state.message = "diverged: non-finite step"
        return
    p_act = state.pressure[act] + alpha * d
    g_d *= alpha
    state.gap += g_d
    negative = p_act < 0
    if negative.any():
        p_act[negative] = 0.0
        state.pressure[act] = p_act
        state.act = act[~negative]
        _recompute_gap(dual, state)
        state.restart = True
    else:
        state.pressure[act] = p_act


def _result(problem, dual, state, label):
    """The step's `Relaxed`: handed over to the primal CG (with the iterations left, `gfmd.chains`), or finished."""
    fft = dual.fft
    u = _primal_state(dual, state)
    if state.hand_over and not state.message:
        return stall(fft.rfft(u)[None, :], state.it, state.residual, fft.pairs + 0.5, label,
                     "contact set too large for the dual")
    message = state.message
    if not state.converged and not message:
        message = not_converged(dual.options.max_iterations, state.residual)
    wall_state = (u, state.ku) if state.converged else None  # converged: K u of this very u was the last check's
    out = finish(problem, fft.rfft(u)[None, :], state.it, state.residual, state.converged, message, wall_state)
    out.fft_pairs = fft.pairs + (0.0 if state.converged else 1.0)  # finish otherwise: irfft of u_hat and of K û
    out.method = label
    return out
