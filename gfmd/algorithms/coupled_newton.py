"""Newton–Krylov on the coupled law's nodal balance (seed Eq. 2; no dynamics, no potential needed).

The coupled chain's first algorithm (3× fewer FFT pairs per step than FIRE on the Fig. 8 ramp,
docs/design/solvers.md) and its fallback where FIRE stalls (`gfmd.chains`): deep in
the slip regime the equilibria are flutter points of any damped dynamics (tests/test_solver_coupled.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.sparse.linalg import gmres

from gfmd_contact.core import laws

from ..coupled_krylov import (GMRES_CYCLES, GMRES_RESTART, balance_state, eisenstat_walker, forcing,
                              newton_direction, nodal_force, nodes_and_stiffness)
from ..fft import Fft
from ..problem import coupled_operators, stiffness_operator
from ..settings import Relaxed
from ..stopping import finish

#: the name of this algorithm in `Relaxed.method`, result files and the chains (`gfmd.chains`)
LABEL = "newton"


@dataclass(frozen=True)
class Options:
    """What Newton–Krylov reads: the `gfmd.settings.Settings` fields of these names (the chains' continuation and
    handover links set the last five)."""

    tolerance: float  # max nodal force residual / p_ref
    coupled_gmres_give_up: bool  # give the step up at the first GMRES solve that misses its tolerance
    coupled_continuation_jump: float  # give it up once an iterate moved a node this many law lengths (0: never)
    coupled_continuation_iterations: int  # give it up after this many iterations (0: COUPLED_NEWTON_ITERATIONS)
    coupled_continuation_gmres_cycles: int  # GMRES restart cycles per solve (0: COUPLED_GMRES_CYCLES)
    coupled_continuation_stagnation: float  # give it up once two iterations each left more than this of it (0: never)

#: Newton iterations a coupled-law step gets after FIRE stalls; each solves the linearised balance by GMRES
#: (restart COUPLED_GMRES_RESTART, at most COUPLED_GMRES_CYCLES cycles).
COUPLED_NEWTON_ITERATIONS = 60
COUPLED_GMRES_RESTART = GMRES_RESTART
COUPLED_GMRES_CYCLES = GMRES_CYCLES
#: Newton step: largest nodal move per iteration in units of min(δn, δt) (trust region)
COUPLED_NEWTON_MAX_MOVE = 2.0
#: GMRES preconditioner: the FIRE mass M_q = K(q) + ⟨k_loc⟩ (True) or K(q) alone (False)
COUPLED_NEWTON_SHIFTED = False
#: GMRES's relative tolerance `gfmd.coupled_krylov.forcing` with Eisenstat–Walker's η (True) or
#: its floor alone (False, the earlier rule: every solve but the last to 1e-3 at 2^17)
COUPLED_NEWTON_EISENSTAT_WALKER = True
#: GMRES on the spectrum, right-preconditioned by K⁻¹: one FFT pair per product (False: nodal, two)
COUPLED_NEWTON_SPECTRAL = True
#: the continuation's jump break-off (`Settings.coupled_continuation_jump`) looks at the iterates from this one on: the
#: first, an inexact step (GMRES to FORCING = 0.1) from the last state, may overshoot a node by a law length on its
#: way to a continuation (the two-level preconditioner's, `gfmd.coupled_preconditioner`: Fig. 8's fig8_small step 99
#: from step 98's state, iterate 1 moved 1.02 law lengths, the converged state 0.75)
JUMP_FROM_ITERATION = 2
#: the break-off's words in `Relaxed.stalled` (`Settings.coupled_continuation_jump`; `gfmd.chains` resumes such a
#: Newton without it where it needs the state Newton stalls at)
BROKE_OFF = "a snap or slip event, no continuation"


def solve(problem, start, options):
    """Newton–Krylov on the coupled law's nodal balance f(u) = t(u) − K u = 0 (no dynamics).

    Each iteration solves (K + D) δu = f by GMRES, D the nodal 2×2 tangent of Eq. 2
    (`gfmd_contact.core.laws.jacobian_coupled`, ∂t/∂u = −D since Δn = z_ind − u_z, Δt = −u_x), K applied
    by FFT: right-preconditioned by K⁻¹ balanced by a coarse space on the stiff nodes (`gfmd.coupled_krylov.newton_direction`,
    `gfmd.coupled_preconditioner`: 3× fewer GMRES products than K⁻¹ alone; K⁻¹ alone on the spectrum where no node
    is stiff, `spectral_step`), one FFT pair per product; with
    COUPLED_NEWTON_SPECTRAL = False on the nodes, preconditioned by K⁻¹ or, COUPLED_NEWTON_SHIFTED, the inverse
    FIRE mass M_q = K(q) + ⟨k_loc⟩, two pairs per product), to the relative tolerance
    min(FORCING, max(η, FORCING_MIN, 0.3 tolerance / residual)) (`gfmd.coupled_krylov.forcing`: no accuracy beyond
    what the stopping test needs; measured on the Fig. 8 ramp at 2^12: 72 FFT pairs per step vs 83 with a fixed
    1e-3, and 184 on the nodes with K⁻¹, 265 with the FIRE mass), η Eisenstat–Walker's (loose while Newton
    converges linearly, tight once quadratically; COUPLED_NEWTON_EISENSTAT_WALKER; measured in
    docs/design/performance.md); the step is capped so that no node moves more than
    COUPLED_NEWTON_MAX_MOVE·min(δn, δt) and halved until ‖f‖₂ decreases (a step into the law's overflow range
    counts as no decrease). The iterations run on the nodes: u and K u are updated by δu and K δu,
    which GMRES sums from its products' parts (`newton_direction`: no transform after the solve, none for a trial
    of the line search; before, 3.5 FFT pairs per iteration beyond the products); where that bookkeeping says
    converged, the state's own force from its spectrum (one pair and a half) decides, and the iterations go on
    where it does not. Half-plane: the mean modes stay
    clamped (the operator acts on zero-mean fields). Stops on the solver's residual
    (max |f| < tolerance·p_ref); `iterations` counts Newton iterations, `fft_pairs` includes
    GMRES's products. Not converged (message says why) after COUPLED_NEWTON_ITERATIONS or
    when the line search finds no decrease; with `Settings.coupled_gmres_give_up` (the Newton-first chain's
    continuation, `gfmd.chains`) also at the first GMRES solve that misses its tolerance in COUPLED_GMRES_CYCLES
    restarts (`stalled`), rather than going on with the inexact direction, and, with
    `Settings.coupled_continuation_jump` > 0, once an unconverged iterate (from the JUMP_FROM_ITERATION-th) has moved a
    node that many law lengths from the start (the continuation's acceptance test would reject such a state); `Settings.coupled_continuation_iterations`
    > 0 replaces COUPLED_NEWTON_ITERATIONS (the continuation's cap) and `Settings.coupled_continuation_gmres_cycles` > 0
    COUPLED_GMRES_CYCLES (a miss within fewer cycles is a break-off, BROKE_OFF, resumable with all of them);
    `Settings.coupled_continuation_stagnation` > 0 breaks off (BROKE_OFF) once two iterations in a row each left more
    than that fraction of the residual before them (a Newton that crawls along a near-singular tangent). Measured
    (docs/design/performance.md): on the fig8_small ramps (N = 4096) no GMRES solve missed; where
    one missed at 2^17, the tangent K + D was near-singular or indefinite along the step (a snap or slip event) and
    the continuation went on for 23–60 iterations (5 400–13 300 FFT pairs) without converging, before FIRE relaxed
    the step from the guess in ~600–700 iterations. The solves of kept continuations took ≤ 104 products (Fig. 8,
    seed 7, steps 161–198 at 2^17; `gfmd.chains.COUPLED_CONTINUATION_GMRES_CYCLES`).
    """
    newton = _setup(problem, options)
    state = _init(problem, newton, start)
    if isinstance(state, Relaxed):
        return state
    while not state.message:
        _confirm(newton, state)
        if state.converged:
            break
        if state.it >= newton.limit:
            state.message = f"not converged after {state.it} Newton iterations (residual {state.residual:.3g} p_ref)"
            break
        _iterate(newton, state)
    return _result(problem, newton, state)


class _Newton(NamedTuple):
    """What one step's Newton holds fixed."""

    model: object
    law: object
    z_ind: np.ndarray
    options: object
    fft: Fft
    stiff: object  # `gfmd.problem.stiffness_operator`
    clamp: bool  # half-plane: the q = 0 modes stay 0
    p_ref: float
    max_move: float  # the largest nodal move of one step (m)
    jump: float  # the continuation's break-off distance (m); 0: none
    limit: int  # Newton iterations
    cycles: int  # GMRES cycles per solve


@dataclass
class NewtonState:
    """The Newton iterate on the nodes, its force and the counters of the stopping and break-off tests."""

    u_hat: np.ndarray  # the spectrum of u, where not `moved`
    f: np.ndarray  # the nodal force t(u) − K u
    u: np.ndarray
    ku: np.ndarray
    origin: np.ndarray  # the nodal start, for the continuation's break-off
    residual: float
    converged: bool
    it: int = 0
    moved: bool = False  # u (and K u) moved on the nodes since u_hat was last their spectrum
    previous: float | None = None  # the last iteration's residual (Eisenstat–Walker's η)
    slow: int = 0  # iterations in a row that left more than `coupled_continuation_stagnation` of it
    message: str = ""


def _setup(problem, options):
    model, law = problem.model, problem.law
    return _Newton(model=model, law=law, z_ind=problem.z_ind, options=options,
                   fft=Fft(model.nodes, grid=model.grid), stiff=stiffness_operator(model), clamp=model.half_plane,
                   p_ref=model.reference_traction, max_move=COUPLED_NEWTON_MAX_MOVE * law.law.length_scale,
                   jump=options.coupled_continuation_jump * law.law.length_scale,
                   limit=options.coupled_continuation_iterations or COUPLED_NEWTON_ITERATIONS,
                   cycles=options.coupled_continuation_gmres_cycles or COUPLED_GMRES_CYCLES)


def _init(problem, newton, start):
    """The clamped start's state; or its `Relaxed` where the law overflows on it."""
    u_hat = np.array(start, dtype=complex, copy=True)  # the step's initial displacements (c, N//2+1), rfft
    if newton.clamp:
        u_hat[:, 0] = 0.0
    known = problem.start_state
    try:
        taken = known is not None and known[0] is start  # the chain evaluated this very start (`better_start`)
        f, u, ku = known[1] if taken else balance_state(newton.model, newton.law, newton.z_ind, u_hat, newton.fft,
                                                        newton.stiff)
    except laws.CompressionOverflowError as exc:
        out = finish(problem, u_hat, 0, np.inf, False, f"diverged: {exc}")
        out.method, out.stalled = LABEL, out.message
        return out
    residual = float(np.max(np.abs(f))) / newton.p_ref
    return NewtonState(u_hat=u_hat, f=f, u=u, ku=ku, origin=u, residual=residual,
                       converged=residual < newton.options.tolerance)


def _spectrum(newton, x):
    """rfft of nodal fields (the clamped q = 0 mode 0)."""
    x_hat = newton.fft.rfft(x)
    if newton.clamp:
        x_hat[:, 0] = 0.0
    return x_hat


def _project(newton, x):
    return x - x.mean(axis=1, keepdims=True) if newton.clamp else x


def _confirm(newton, state):
    """Where the nodal bookkeeping says converged, the state's own force, from its spectrum, decides."""
    if not (state.converged and state.moved):
        return
    state.u_hat, state.moved = _spectrum(newton, state.u), False
    state.f, state.u, state.ku = balance_state(newton.model, newton.law, newton.z_ind, state.u_hat, newton.fft,
                                               newton.stiff)
    state.residual = float(np.max(np.abs(state.f))) / newton.p_ref
    state.converged = state.residual < newton.options.tolerance


def _iterate(newton, state):
    """One Newton iteration: the GMRES direction, the line search, the break-off tests (a stop sets the message)."""
    state.it += 1
    residual = state.residual
    eta = eisenstat_walker(residual, state.previous) if COUPLED_NEWTON_EISENSTAT_WALKER else 0.0
    state.previous = residual
    rtol = forcing(newton.options.tolerance, residual, eta)
    direction = _direction(newton, state, rtol)
    if direction is None:
        return
    trial = _line_search(newton, state, *direction)
    if trial is None:
        state.message = (f"Newton line search found no decrease of |f| (iteration {state.it}, "
                         f"residual {residual:.3g} p_ref)")
        return
    state.f, state.u, state.ku = trial
    state.moved = True
    state.residual = float(np.max(np.abs(state.f))) / newton.p_ref
    if not np.isfinite(state.residual):
        state.message = "diverged: non-finite force residual"
        return
    state.message = _break_off(newton, state)
    if not state.message:
        state.converged = state.residual < newton.options.tolerance


def _direction(newton, state, rtol):
    """(δu, K δu, max |δu|) of GMRES on (K + D) δu = f; None (the message set) where GMRES misses its
    tolerance and the options give up, or where the step is not finite or zero."""
    model, law, z_ind, fft = newton.model, newton.law, newton.z_ind, newton.fft
    before = fft.pairs
    if COUPLED_NEWTON_SPECTRAL:
        du, kdu, info = newton_direction(model, law, z_ind, state.u, state.f, newton.stiff, fft, rtol,
                                         COUPLED_GMRES_RESTART, newton.cycles)
    else:
        a_op, m_op, _ = coupled_operators(model, law, z_ind, state.u, fft, COUPLED_NEWTON_SHIFTED)
        du, info = gmres(a_op, state.f.ravel(), M=m_op, rtol=rtol, restart=COUPLED_GMRES_RESTART,
                         maxiter=newton.cycles)
        du, kdu = nodes_and_stiffness(_spectrum(newton, _project(newton, du.reshape(model.components, model.nodes))),
                                      newton.stiff, fft)
    if newton.options.coupled_gmres_give_up and info != 0:
        message = (f"GMRES missed its tolerance {rtol:.2g} in {fft.pairs - before:.0f} FFT pairs (Newton iteration "
                   f"{state.it}, residual {state.residual:.3g} p_ref): the tangent is near-singular or indefinite "
                   "along the step, no continuation")
        if newton.cycles < COUPLED_GMRES_CYCLES:  # the continuation's shorter solve: resumable as a jump's break-off
            message += f" within {newton.cycles} of {COUPLED_GMRES_CYCLES} cycles: {BROKE_OFF}"
        state.message = message
        return None
    largest = float(np.max(np.abs(du)))
    if not np.isfinite(largest) or largest == 0.0:
        state.message = f"Newton step not finite or zero (residual {state.residual:.3g} p_ref)"
        return None
    return du, kdu, largest


def _line_search(newton, state, du, kdu, largest):
    """(f, u, K u) of the step capped so that no node moves more than max_move and halved until ‖f‖₂ decreases
    (a step into the law's overflow range counts as no decrease); None where no step > 1e-3 does."""
    f, u, ku = state.f, state.u, state.ku
    norm0 = float(np.sqrt(np.einsum("ij,ij->", f, f)))
    step = min(1.0, newton.max_move / largest)
    while step > 1e-3:  # on the nodes: u + step δu and K u + step K δu, no transform
        u_trial, ku_trial = u + step * du, ku + step * kdu
        try:
            f_trial = nodal_force(newton.law, newton.z_ind, u_trial, ku_trial, newton.clamp)
        except laws.CompressionOverflowError:
            step *= 0.5
            continue
        if np.sqrt(np.einsum("ij,ij->", f_trial, f_trial)) <= (1.0 - 1e-4 * step) * norm0:
            return f_trial, u_trial, ku_trial
        step *= 0.5
    return None


def _break_off(newton, state):
    """The continuation's break-off (BROKE_OFF) after an unconverged iterate: a node moved `jump` from the start,
    or two iterations in a row each left more than the stagnation fraction of the residual; "" otherwise."""
    options, residual, it, length = newton.options, state.residual, state.it, newton.law.law.length_scale
    if newton.jump > 0 and residual >= options.tolerance and it >= JUMP_FROM_ITERATION:
        distance = float(np.max(np.abs(state.u - state.origin)))
        if distance >= newton.jump:
            return (f"a node moved {distance / length:.3g} law lengths from the start at Newton "
                    f"iteration {it} (residual {residual:.3g} p_ref): {BROKE_OFF}")
    stagnation = options.coupled_continuation_stagnation
    if stagnation > 0 and residual >= options.tolerance:
        state.slow = state.slow + 1 if residual > stagnation * state.previous else 0
        if state.slow == 2:
            return (f"the residual stagnated: two Newton iterations in a row each left more than {stagnation:g} "
                    f"of it (iteration {it}, residual {residual:.3g} p_ref): {BROKE_OFF}")
    return ""


def _result(problem, newton, state):
    if state.moved:  # a stop before convergence: the state the nodes reached (its residual the nodal one)
        state.u_hat = _spectrum(newton, state.u)
    pairs = newton.fft.pairs
    out = finish(problem, state.u_hat, state.it, state.residual, state.converged, state.message)
    out.fft_pairs = pairs + 0.5
    out.method = LABEL
    out.stalled = "" if out.converged else out.message  # the chain may go on (`gfmd.chains`)
    return out
