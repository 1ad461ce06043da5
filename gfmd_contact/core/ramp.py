"""The one load ramp: a realization under displacement or force control, for any method (seed §2).

Units: SI (see `gfmd_contact.core.conventions`). `run_ramp` does what every method shares:
profile → the method's cell → for each load step of `gfmd_contact.core.loading` (cut at the
realization's own full-contact limit): warm start (linear extrapolation from the
last two converged states, or the last one), one retry from the last converged
state if the extrapolated start fails, the protocol's warnings, the observables
of `gfmd_contact.core.observables` on the N nodes (or the cell's own `observe`), the saved fields, then the progress and
checkpoint hooks. A method supplies only a `Cell`: how to solve one step. Scenes that differ
only in what they observe (`gfmd_contact.core.observation`) share one ramp: `variants`, each with its
own Result, observables and checkpoint.

A `Cell` has
    method       name of the method and variant, e.g. "gfmd-ncg", "fe-p2"
    model        the model solved, in words; reasons: why (tuple of str)
    physics      the `gfmd_contact.core.model.Model` of the scene (law, unknowns, checks)
    extrapolate  whether a warm start may be extrapolated (state must then be an array)
    diagnostics  method-specific extras for `Result.diagnostics` (dict)
    initial_state()                          the state at U = 0 before relaxation
    solve(displacement, guess, fallback)     → `StepSolution`
and optionally
    observe(scene, h, gap, t_n)              → {p, a_rel, g_r, g} of a step (the observables
                                               of `gfmd_contact.core.result.CURVE_COLUMNS`, SI)
A cell with `observe` computes its own observables from its own fields (the FE reference
does, so that it checks `gfmd_contact.core.observables` instead of sharing it); without it the ramp
uses `gfmd_contact.core.observables.step_observables`.
"""

from __future__ import annotations

import dataclasses
import functools
import time
from dataclasses import dataclass, field
from typing import Any, Callable, NamedTuple

import numpy as np

from . import surfaces
from .force import first_step, solve_load
from .force import tolerance as load_tolerance
from .loading import (FULL_CONTACT_MARGIN, RampState, has_full_contact_limit, extrapolation_allowed, field_step_indices, realization_label, realization_steps, slip_warning,
                      start_warning)
from .model import WARNING
from .observables import profile_gradients, step_observables
from .result import FIELD_NAMES, Result


@dataclass
class StepSolution:
    """One load step as a method solved it (arrays on the N surface nodes, SI; 2+1-D: (Nx, Ny) arrays).

    state: what the next step starts from (the method's unknowns); gap Δn (m) and t_n (Pa,
    tension > 0) give the observables; u_x (m) is needed for the slip check of a coupled
    law (None if the method has no tangential unknowns); fields() returns the saved
    fields {u_z, u_x, gap, t_n, t_t} (called only at saved steps); messages: what went
    wrong or which fallback ran (each becomes a Result message); keep: per-step extras
    stored at saved steps under Result.diagnostics[name][step]; fallback: the method's
    fallback solver ran (the step goes to Result.diagnostics["fallback_steps"]); algorithm: the
    method's name for the algorithm(s) that solved the step, e.g. GFMD's "ncg" or "ncg→fire"
    (Result.diagnostics["algorithms"][step]; "" where the method has none).
    """

    state: Any
    converged: bool
    iterations: int
    residual: float
    gap: np.ndarray
    t_n: np.ndarray
    fields: Callable[[], dict]
    u_x: np.ndarray | None = None
    messages: tuple = ()
    keep: dict = field(default_factory=dict)
    fallback: bool = False
    algorithm: str = ""
    relaxed: bool = True


def _extrapolated(state, previous):
    """The linear warm start 2 u_k − u_{k−1}. Quadratic through three states (3 u_k − 3 u_{k−1} + u_{k−2}) was measured
    and dropped (docs/design/solvers.md): more iterations for every law, and the adhesive ramps on other branches
    after jumps: the states are smooth in δ only between contact events."""
    return 2 * state - previous


def force_u_max(scene, h):
    """The largest U (m) a force-controlled half-plane realization may reach: (1 − FULL_CONTACT_MARGIN) of its
    full-contact limit mean(h) − min(h) beyond δ = 0 (`gfmd_contact.core.loading.realization_steps`); a layer or a
    free body: none (`has_full_contact_limit`)."""
    if not has_full_contact_limit(scene):
        return np.inf
    return scene.loading.initial_separation + (1.0 - FULL_CONTACT_MARGIN) * float(np.mean(h) - np.min(h))


def y_positions(surface):
    """Node positions along y (m) of a 2+1-D surface (`gfmd_contact.core.surfaces.grid`), None for a profile."""
    return surfaces.grid(surface.nodes_y, surface.length_y) if surface.two_d else None


@dataclass
class Variant:
    """A scene that shares a ramp's solve and observes it its own way (`gfmd_contact.core.observation`): its own
    checkpoint hook and resume (as run_ramp's); `result` is set to its finished Result by run_ramp."""

    scene: Any
    checkpoint: Callable | None = None
    resume: tuple | None = None
    result: Any = None


def _new_result(scene, cell, realization, h, stop_note):
    return Result(scene=scene, method=cell.method, model=cell.model, realization=realization,
                  x=surfaces.grid(scene.surface.nodes, scene.surface.length), h=h, reasons=tuple(cell.reasons),
                  notes=[stop_note] if stop_note else [], y=y_positions(scene.surface))


def run_ramp(scene, realization, prepare, *, progress=None, checkpoint=None, resume=None, variants=()):
    """Run the load ramp of one realization with the cell `prepare(scene, h, realization)` returns.

    Parameters
    ----------
    scene : gfmd_contact.core.scene.Scene
    realization : int
        Realization index i (random profile seed surface.seed + i).
    prepare : callable(scene, h, realization) -> Cell
        The method's cell (module docstring).
    progress : callable(step, steps), optional
        Called after every step (and every variant's).
    checkpoint : callable(result, state), optional
        Called after every step with the steps so far and the `RampState` (gfmd_contact.app.io
        writes them to disk).
    resume : (Result, RampState), optional
        What a checkpoint saw: the ramp continues after state.step from that exact state,
        so the final Result equals an uninterrupted run's (wall times aside).
    variants : list of `Variant`, optional
        Scenes of the same `gfmd_contact.core.observation.solve_key` (displacement control, a cell without its
        own `observe`): each gets the Result its own run_ramp would return (wall times aside), its
        observables its own, all else from this one solve. A variant's resume may be further
        than `resume` (its steps up to there are kept, not appended again), never behind it.

    Returns
    -------
    gfmd_contact.core.result.Result
    """
    h = surfaces.profile(scene.surface, realization)
    cell = prepare(scene, h, realization)
    steps, stop_note = realization_steps(scene, h, realization)
    label = realization_label(scene, realization)
    result, state, targets = _targets(scene, cell, realization, h, stop_note, resume, checkpoint, variants)
    ramp = _ramp(scene, cell, h, label, steps)
    current, previous = state.current, state.previous
    for k in range(state.step + 1, steps.size):
        t0 = time.perf_counter()
        ramp.at[0] = k
        step = _solve_step(ramp, result, k, current, previous)
        step = step._replace(wall=time.perf_counter() - t0)
        if step.solved.converged:
            previous, current = current, step.solved.state
        _record(ramp, targets, k, step, current, previous, progress)
    for v, (_, target, _, _) in zip(variants, targets[1:]):
        v.result = target.finalize()
    return result.finalize()


class _Ramp(NamedTuple):
    """What one realization's ramp holds fixed."""

    scene: Any
    cell: Any
    h: np.ndarray
    label: str  # the realization, in words
    steps: np.ndarray  # displacements U_k (m), or loads p̄_k (Pa) under force control
    keep: Any  # the steps whose fields are saved
    d0: float  # the initial separation (m)
    force: bool  # steps are loads p̄_k (Pa): gfmd_contact.core.force finds U for each
    solve: Callable  # the cell's solve, naming the step in a user law's error
    observe: Callable  # the step's observables
    at: list  # the step being solved, for a user law's error


class _Step(NamedTuple):
    """One solved load step: the method's solution, U (m), the iterations (a retry's included), the load
    control's instability event (or None) and the wall time (s)."""

    solved: StepSolution
    displacement: float
    iterations: int
    event: dict | None
    wall: float = 0.0


def _targets(scene, cell, realization, h, stop_note, resume, checkpoint, variants):
    """(result, state, targets): the ramp's Result and RampState, new or resumed, and every Result this solve
    writes, with its scene, state and checkpoint hook; each with the cell's extras in its diagnostics."""
    if resume is None:
        result = _new_result(scene, cell, realization, h, stop_note)
        start = cell.initial_state()
        state = RampState(step=-1, current=start, previous=start)
    else:
        result, state = resume
    targets = [(scene, result, state, checkpoint)]  # every Result this solve writes, with its scene and hook
    if variants:
        if scene.loading.control == "force" or getattr(cell, "observe", None) is not None:
            raise ValueError("run_ramp variants: only a displacement-controlled ramp of the shared observables "
                             "(gfmd_contact.core.observables) can be shared (gfmd_contact.core.observation)")
        for v in variants:
            if v.resume is not None and v.resume[1].step < state.step:
                raise ValueError(f"run_ramp variants: a variant resumes at step {v.resume[1].step}, behind the "
                                 f"ramp's {state.step}: resume the ramp from the variant furthest behind")
            v_result, v_state = v.resume if v.resume is not None else (
                _new_result(v.scene, cell, realization, h, stop_note), RampState(step=-1, current=None, previous=None))
            targets.append((v.scene, v_result, v_state, v.checkpoint))
    for _, target, _, _ in targets:  # the cell's extras; lists (fallback_steps) continue those of a resumed run
        target.diagnostics.update({k: v for k, v in cell.diagnostics.items()
                                   if not (isinstance(v, list) and k in target.diagnostics)})
    return result, state, targets


def _ramp(scene, cell, h, label, steps):
    at = [0]
    observe = getattr(cell, "observe", None)  # the cell's own observables if it has them
    if observe is None:  # the profile's gradients (ḡ, and ḡ_r's g_i²) once per ramp, not per step
        observe = functools.partial(step_observables, gradients=profile_gradients(scene, h))
    return _Ramp(scene=scene, cell=cell, h=h, label=label, steps=steps,
                 keep=field_step_indices(scene.loading, scene.output.field_steps), d0=scene.loading.initial_separation,
                 force=scene.loading.control == "force", solve=_naming_step(cell.solve, label, at), observe=observe,
                 at=at)


def _solve_step(ramp, result, k, current, previous):
    """Load step k: under force control, U for the load p̄_k (`gfmd_contact.core.force.solve_load`); else the
    cell's solve from the warm start, retried once from the last converged state if the extrapolated start fails."""
    scene, h, solve, observe = ramp.scene, ramp.h, ramp.solve, ramp.observe
    if ramp.force and k > 0:
        base = (float(result.curve["U"][-1]), current, {"p": float(result.curve["p"][-1]),
                                                        "a_rel": float(result.curve["a_rel"][-1])}, None)
        loaded = solve_load(solve, lambda sol: observe(scene, h, sol.gap, sol.t_n), float(ramp.steps[k]), base,
                            step=first_step(scene.loading), tolerance=load_tolerance(scene.loading),
                            u_max=force_u_max(scene, h))
        solved = dataclasses.replace(loaded.solved, converged=loaded.converged)
        return _Step(solved, loaded.U, loaded.iterations, loaded.event)
    displacement = 0.0 if ramp.force else ramp.steps[k]
    extrapolate = ramp.cell.extrapolate and extrapolation_allowed(scene.loading, k)  # not across a turning point
    guess = _extrapolated(current, previous) if extrapolate else current
    solved = solve(displacement, guess, current)
    iterations = solved.iterations
    if not solved.converged and extrapolate:  # retry from the last converged state
        solved = solve(displacement, current, current)
        iterations += solved.iterations
    return _Step(solved, displacement, iterations, None)


def _record(ramp, targets, k, step, current, previous, progress):
    """Step k into every target's Result (those not resumed beyond it), then its state, checkpoint and progress."""
    scene, cell, h, d0 = ramp.scene, ramp.cell, ramp.h, ramp.d0
    solved, displacement, event = step.solved, step.displacement, step.event
    where = f"{ramp.label}, step {k} (δ = {displacement - d0:.4g} m)"
    if event is not None:
        event.update(step=k, delta_before=event["U_before"] - d0, delta_after=event["U_after"] - d0)
    warning = (start_warning(scene, cell.physics, float(np.min(solved.gap)))
               if k == 0 and cell.physics is not None else None)
    slipped = (slip_warning(scene, k, displacement - d0, solved.gap, solved.u_x)
               if solved.u_x is not None and not all(t[2].slip_warned for t in targets) else None)
    fields = None
    for t_scene, target, t_state, t_checkpoint in targets:
        if t_state.step >= k:  # a variant resumed further than the ramp: this step is in its Result
            continue
        if k in ramp.keep and fields is None:
            fields = (solved.fields() if solved.relaxed
                      else {name: np.full(h.shape, np.nan) for name in FIELD_NAMES})
        _record_step(target, t_state, k, solved, event, where, warning, slipped, d0, displacement,
                     step.iterations, step.wall, ramp.observe(t_scene, h, solved.gap, solved.t_n if solved.relaxed
                                                              else np.zeros_like(solved.gap)), fields)
        t_state.step, t_state.current, t_state.previous = k, current, previous
        if t_checkpoint is not None:
            t_checkpoint(target, t_state)
        if progress is not None:
            progress(k, scene.loading.steps)


def _naming_step(solve, label, at):
    """The cell's solve; a user law's error (`gfmd_contact.core.user_law.UserLawError`: which law, callable and
    gaps) raised in it also names the realization, the step at[0] and the displacement U."""
    from .user_law import UserLawError

    def solve_naming(U, guess, fallback):
        try:
            return solve(U, guess, fallback)
        except UserLawError as exc:
            raise UserLawError(f"{label}, step {at[0]} (U = {U:.4g} m): {exc}") from exc
    return solve_naming


def _record_step(result, state, k, solved, event, where, warning, slipped, d0, displacement, iterations, wall, obs,
                 fields):
    """Append load step k to `result`: its event, messages, fallback and algorithm, warnings, the curve row
    of the observables `obs` (NaN where the step has no state) and, at a saved step, its `fields`."""
    if event is not None:
        result.diagnostics.setdefault("instabilities", []).append(event)
        result.notes.append(
            f"{where}: instability at the load p̄ = {event['load']:.6g} Pa: no equilibrium near the previous one "
            f"(δ = {event['delta_before']:.4g} m, a_rel = {event['a_rel_before']:.4g}); "
            + ("the body detached: no equilibrium carries this tensile load, the step records the indenter at its "
               f"start δ = {-d0:.4g} m with p̄ = {event['p_after']:.4g} Pa" if event["detached"] else
               f"continued on the branch it jumps to (δ = {event['delta_after']:.4g} m, "
               f"a_rel = {event['a_rel_after']:.4g})"))
    result.messages.extend(f"{where}: {m}" for m in solved.messages)
    if solved.fallback:
        result.diagnostics.setdefault("fallback_steps", []).append(k)
    if solved.algorithm:  # one label per step (a retry's: the state kept is the retry's)
        labels = result.diagnostics.setdefault("algorithms", [])
        labels[k:] = [""] * (k - len(labels)) + [solved.algorithm]
    if warning:
        result.reasons = tuple(result.reasons) + (WARNING + warning,)
    if slipped and not state.slip_warned:
        result.reasons = tuple(result.reasons) + (WARNING + slipped,)
        state.slip_warned = True
    if not solved.relaxed:  # no state of this step: nothing observed (ḡ is the profile's, known without one)
        # (observe still ran, on the step's gap and zero traction, so a cell keeps one per-step record per step)
        obs = dict(obs, p=np.nan, a_rel=np.nan, g_r=np.nan)
    converged = solved.converged and solved.relaxed
    residual = float(solved.residual)
    result.append_step(step=k, U=displacement, delta=displacement - d0, iterations=iterations,
                       residual=residual if np.isfinite(residual) else np.nan,  # NaN: no finite residual
                       converged=int(converged), wall_s=wall, **obs)
    if fields is not None:
        result.fields[k] = fields
        for name, value in solved.keep.items():
            result.diagnostics.setdefault(name, {})[k] = value
