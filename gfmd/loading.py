"""GFMD load ramp of one realization (seed §2), on the shared protocol of `contact.loading`.

Units: SI (see `contact.conventions`). Each step relaxes the GFMD model
(`gfmd.solver.relax`) warm-started from the previous equilibrium (linearly
extrapolated from the last two steps). Warnings: the model's check findings
(`contact.model.scene_warnings`) are carried in `Result.reasons`, with the
protocol's start and slip warnings; solver failures go to `Result.messages`.
"""

from __future__ import annotations

import time

import numpy as np

from contact import surfaces
from contact.laws import CompressionOverflowError
from contact.loading import (RampState, field_step_indices, indenter_surface, realization_label, realization_steps,
                             slip_warning, start_warning)
from contact.model import WARNING, build_model
from contact.observables import step_observables
from contact.result import Result

from .solver import InterfaceLaw, Settings, relax


def run_realization(scene, realization=0, settings=None, progress=None, method_name=None, *, checkpoint=None,
                    resume=None):
    """Run the whole load ramp for one realization; returns a `Result`.

    settings: `gfmd.solver.Settings` (default from scene.solver); progress: optional
    callable(step, steps) called after every step. checkpoint: optional callable(result,
    state) called after every step with the steps so far and the `RampState` (how
    workbench.io writes a run while it runs). resume: a (result, state) pair such a checkpoint
    saw: the ramp continues after state.step from that exact warm start, so the final
    Result equals an uninterrupted run's (wall times aside). A half-plane realization
    stops early below its own full-contact limit (`realization_steps`, a note in
    `Result.notes`).
    """
    h = surfaces.profile(scene.surface, realization)
    model = build_model(scene, h)
    law = InterfaceLaw(model, scene.interface, scene.work_tangential)
    if settings is None:
        settings = Settings(method=scene.solver.method, tolerance=scene.solver.tolerance,
                            max_iterations=scene.solver.max_iterations)
    steps, stop_note = realization_steps(scene, h, realization)
    label = realization_label(scene, realization)
    if resume is None:
        result = Result(scene=scene, method=method_name or f"gfmd-{settings.method}", model=model.description,
                        realization=realization, x=surfaces.grid(model.nodes, model.length), h=h,
                        reasons=model.reasons, notes=[stop_note] if stop_note else [])
        nq = model.nodes // 2 + 1
        state = RampState(step=-1, u_hat=np.zeros((model.components, nq), complex),
                          u_prev=np.zeros((model.components, nq), complex))
    else:
        result, state = resume
    keep = field_step_indices(scene.loading, scene.output.field_steps)
    wall_tolerance = 1e-12 * max(float(np.ptp(h)), scene.interface.length_normal)
    d0 = scene.loading.initial_separation
    u_hat, u_prev = state.u_hat, state.u_prev
    for k in range(state.step + 1, steps.size):
        displacement = steps[k]
        start = time.perf_counter()
        z_ind = indenter_surface(h, d0, displacement)
        guess = 2 * u_hat - u_prev if k >= 2 else u_hat
        try:
            relaxed = relax(model, law, z_ind, guess, settings, wall_tolerance)
            iterations = relaxed.iterations
        except CompressionOverflowError:  # the extrapolated guess left the law's range
            relaxed, iterations = None, 0
        if (relaxed is None or not relaxed.converged) and k >= 2:  # retry without extrapolation
            relaxed = relax(model, law, z_ind, u_hat, settings, wall_tolerance)
            iterations += relaxed.iterations
        wall = time.perf_counter() - start
        if not relaxed.converged:
            result.messages.append(f"{label}, step {k} (δ = {displacement - d0:.4g} m): {relaxed.message}")
        else:
            u_prev, u_hat = u_hat, relaxed.u_hat
        if k == 0:
            warning = start_warning(scene, model, float(np.min(relaxed.gap)))
            if warning:
                result.reasons = tuple(result.reasons) + (WARNING + warning,)
        if model.tangential and not state.slip_warned:
            slipped = slip_warning(scene, k, displacement - d0, relaxed.gap, relaxed.u_x)
            if slipped:
                result.reasons = tuple(result.reasons) + (WARNING + slipped,)
                state.slip_warned = True
        obs = step_observables(scene, h, relaxed.gap, relaxed.t_z)
        result.append_step(step=k, U=displacement, delta=displacement - d0, iterations=iterations,
                           residual=relaxed.residual, converged=int(relaxed.converged), wall_s=wall, **obs)
        if k in keep:
            result.fields[k] = {"u_z": relaxed.u_z, "u_x": relaxed.u_x, "gap": relaxed.gap,
                                "t_n": relaxed.t_z, "t_t": relaxed.t_x}
        state.step, state.u_hat, state.u_prev = k, u_hat, u_prev
        if checkpoint is not None:
            checkpoint(result, state)
        if progress is not None:
            progress(k, scene.loading.steps)
    return result.finalize()
