"""Quasi-static displacement-controlled loading of one realization (seed §2).

Units: SI (see `gfmd.conventions`). The indenter starts with its closest point
δ0 above the undeformed surface; U goes from 0 to δ0 + final_penetration in
`steps` equal increments (step 0 is U = 0), each step warm-started from the
previous equilibrium (linearly extrapolated from the last two steps).
"""

from __future__ import annotations

import time

import numpy as np

from . import surfaces
from .model import build_model
from .observables import step_observables
from .result import Result
from .laws import CompressionOverflowError
from .solver import InterfaceLaw, Settings, relax


def displacement_steps(loading):
    """Imposed indenter displacements U_k (m), k = 0 … steps, equal increments from 0."""
    total = loading.initial_separation + loading.final_penetration
    return np.linspace(0.0, total, loading.steps + 1)


def field_step_indices(loading, count):
    """Indices of the `count` evenly spaced steps whose fields are saved (last step included)."""
    if count <= 0:
        return set()
    return set(np.unique(np.round(np.linspace(0, loading.steps, count + 1)[1:]).astype(int)).tolist())


def indenter_surface(h, initial_separation, displacement):
    """z_ind(x) = h − min h + δ0 − U (m), gfmd.conventions."""
    return h - np.min(h) + initial_separation - displacement


def check_penetration_limit(scene, h, realization=0):
    """Raise ValueError if a half-plane run would be pushed past full contact.

    With the mean plane clamped (gfmd.conventions), the indenter's mean height above
    it is ⟨h⟩ − min h − δ; full contact, and an unbounded pressure, is reached at
    δ_max = ⟨h⟩ − min h (m).
    """
    if not scene.material.half_plane:
        return
    limit = float(np.mean(h) - np.min(h))
    if scene.loading.final_penetration >= limit:
        raise ValueError(
            f"loading.final_penetration = {scene.loading.final_penetration:.4g} m reaches full contact for "
            f"realization {realization}: on a half-plane δ is measured from the mean plane and cannot exceed "
            f"mean(h) − min(h) = {limit:.4g} m. Lower final_penetration (e.g. to {0.8 * limit:.3g} m) "
            "or use a finite material.thickness.")


def run_realization(scene, realization=0, settings=None, progress=None, method_name=None):
    """Run the whole load ramp for one realization; returns a `Result`.

    settings: `gfmd.solver.Settings` (default from scene.solver); progress: optional
    callable(step, steps) called after every step.
    """
    h = surfaces.profile(scene.surface, realization)
    check_penetration_limit(scene, h, realization)
    model = build_model(scene, h)
    law = InterfaceLaw(model, scene.interface, scene.work_tangential)
    if settings is None:
        settings = Settings(method=scene.solver.method, tolerance=scene.solver.tolerance,
                            max_iterations=scene.solver.max_iterations)
    result = Result(scene=scene, method=method_name or f"gfmd-{settings.method}", model=model.description,
                    realization=realization, x=surfaces.grid(model.nodes, model.length), h=h,
                    reasons=model.reasons)
    keep = field_step_indices(scene.loading, scene.output.field_steps)
    wall_tolerance = 1e-12 * max(float(np.ptp(h)), scene.interface.length_normal)
    nq = model.nodes // 2 + 1
    u_hat = np.zeros((model.components, nq), complex)
    u_prev = u_hat.copy()
    d0 = scene.loading.initial_separation
    for k, displacement in enumerate(displacement_steps(scene.loading)):
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
            result.messages.append(f"realization {realization}, step {k} (δ = {displacement - d0:.4g} m): "
                                   f"{relaxed.message}")
        else:
            u_prev, u_hat = u_hat, relaxed.u_hat
        obs = step_observables(scene, h, relaxed.gap, relaxed.t_z)
        result.append_step(step=k, U=displacement, delta=displacement - d0, iterations=iterations,
                           residual=relaxed.residual, converged=int(relaxed.converged), wall_s=wall, **obs)
        if k in keep:
            result.fields[k] = {"u_z": relaxed.u_z, "u_x": relaxed.u_x, "gap": relaxed.gap,
                                "t_n": relaxed.t_z, "t_t": relaxed.t_x}
        if progress is not None:
            progress(k, scene.loading.steps)
    return result.finalize()
