"""GFMD on the one load ramp (`gfmd_contact.core.ramp.run_ramp`): the cell that relaxes one load step.

Units: SI (see `gfmd_contact.core.conventions`). `prepare` builds the model of the scene
(`gfmd_contact.core.model.build_model`: unknowns, kernel, checks) and the interface law once
per realization; `GfmdCell.solve` relaxes one step (`gfmd.chains.relax`) from the
ramp's warm start. `run_realization` runs a whole realization.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial

import numpy as np

from gfmd_contact.core.laws import CompressionOverflowError
from gfmd_contact.core.loading import indenter_surface
from gfmd_contact.core.model import build_model
from gfmd_contact.core.ramp import StepSolution, run_ramp
from gfmd_contact.core.scene_sections import Interface

from . import blas, heap, kernels
from .chains import chain_key, describe, relax
from .cohesive_preconditioner import resolve as resolve_preconditioner
from .fft import backend_words
from .free_cell import FreeRegion
from .problem import InterfaceLaw, Problem
from .settings import Settings


@dataclass
class GfmdCell:
    """One realization's GFMD problem: model, law and settings (see gfmd_contact.core.ramp for the protocol)."""

    scene: object
    h: np.ndarray
    physics: object  # gfmd_contact.core.model.Model
    law: InterfaceLaw
    settings: Settings
    method: str
    extrapolate: bool = True
    diagnostics: dict = field(default_factory=dict)

    @property
    def model(self):
        return self.physics.description

    @property
    def reasons(self):
        """The model's reasons, the algorithms, then the internals (`INTERNALS`: speed and round-off only)."""
        return self.physics.reasons + (integrator(self.physics, self.settings), backends(),
                                       f"memory: {heap.STATE} (gfmd.heap, speed only; GFMD_KEEP_HEAP=0: glibc's defaults)",
                                       f"BLAS threads: {blas.state()} (speed only)")

    def initial_state(self):
        """u_hat = 0: the undeformed surface, rfft modes of each solved component: (c, N//2+1); on a 2+1-D
        surface (1, Nx, Ny//2+1), the rfft2 half-spectrum (Model.spectrum_shape)."""
        return np.zeros((self.physics.components,) + tuple(self.physics.spectrum_shape), complex)

    def solve(self, displacement, guess, fallback):
        """Relax the load step at indenter displacement U (m) from the rfft displacements `guess` (extrapolated from
        `fallback`, the last converged state, unless it is that: `gfmd.chains.relax`'s `previous`); the step's
        `algorithm` is the chain's label of what relaxed it (`Relaxed.method`: "ncg", "ncg→fire", ...)."""
        z_ind = self.indenter(displacement)
        wall_tolerance = wall_tolerance_of(self.scene, self.h)
        try:
            r = relax(self.physics, self.law, z_ind, guess, self.settings, wall_tolerance,
                      previous=None if fallback is guess else fallback)
        except CompressionOverflowError as exc:  # the extrapolated guess left the law's range
            return StepSolution(state=guess, converged=False, iterations=0, residual=np.nan, gap=z_ind,
                                t_n=np.zeros_like(z_ind), fields=dict, messages=(str(exc),), relaxed=False)
        fields = {"u_z": r.u_z, "u_x": r.u_x, "gap": r.gap, "t_n": r.t_z, "t_t": r.t_x}
        if not all(np.all(np.isfinite(v)) for v in fields.values()):  # a diverged iterate: no state of the step
            return StepSolution(state=guess, converged=False, iterations=r.iterations, residual=np.nan, gap=z_ind,
                                t_n=np.zeros_like(z_ind), fields=dict, relaxed=False,
                                messages=(r.message or "diverged: non-finite displacements",))
        return StepSolution(state=r.u_hat, converged=r.converged, iterations=r.iterations, residual=r.residual,
                            gap=r.gap, t_n=r.t_z, fields=lambda: fields,
                            u_x=r.u_x if self.physics.tangential else None,
                            messages=() if r.converged else (r.message,), algorithm=r.method)


    def indenter(self, displacement):
        """The indenter surface z_ind (m) on the model's grid at displacement U (m)."""
        return indenter_surface(self.h, self.scene.loading.initial_separation, displacement)


class FreeGfmdCell(FreeRegion, GfmdCell):
    """`GfmdCell` of a free-boundary model (`gfmd.free_cell.FreeRegion`)."""


#: how the reasons that describe this process rather than the model begin (FFT and kernel backends, the heap, BLAS
#: threads): they change speed or round-off only; meta.json keeps them, `gfmd run` prints them with --verbose
INTERNALS = ("backends: ", "memory: ", "BLAS threads: ")


def internal(reason):
    """True for a reason line about this process's internals (`INTERNALS`), not about the model solved."""
    return reason.startswith(INTERNALS)


def wall_tolerance_of(scene, h):
    """The gap (m) within which a node counts as on a wall, a round-off allowance: 1e-12 × the profile's height range,
    or on a flat profile × δn (interface.length_normal) for a law with a cohesive zone and × 1 nm (the default δn) for
    the hard wall, whose equilibrium has no length of its own (so δn stays an observation-only key of a hard-wall
    solve, `gfmd_contact.core.observation`)."""
    floor = Interface().length_normal if scene.interface.law == "hard-wall" else scene.interface.length_normal
    wall_tolerance = 1e-12 * max(float(np.ptp(h)), floor)  # (verification.mutations' wall-leak mutates this line)
    return wall_tolerance


def backends():
    """The FFT and the NCG's spectral kernels this process uses, in words (they change round-off only)."""
    return (f"backends: FFT {backend_words()}, cohesive NCG spectral algebra {kernels.jit_backend()} "
            "(GFMD_JIT)")


def chain(physics, settings):
    """The key of the algorithm chain (`gfmd.chains.CHAINS`) that relaxes the steps of this model and settings."""
    return chain_key(Problem(physics, InterfaceLaw(physics), None), settings)


def integrator(physics, settings):
    """Which GFMD algorithms relax the steps (`gfmd.chains`), in words: the chain, then which law kind and
    solver.method chose it ("fire": the law's production chain, whatever its first algorithm)."""
    key = chain(physics, settings)
    preconditioner = ""
    if key[1] == "ncg":  # which preconditioner the NCG runs (`gfmd.cohesive_preconditioner`)
        name = resolve_preconditioner(settings.cohesive_preconditioner, physics.grid, physics.law.curvature_scale is None)
        preconditioner = f"; NCG preconditioner {name!r} (Settings.cohesive_preconditioner = " \
                         f"{settings.cohesive_preconditioner!r})"
    chosen = "the production chain" if settings.method == "fire" else "damped Verlet throughout"
    return (f"algorithms: {describe(key, settings)} (gfmd.chains {key[0]} / {key[1]}, {chosen} of solver.method = "
            f"{settings.method!r}; each step's algorithm is in curve.csv's algorithm column{preconditioner})")


def describe_scene(scene, settings=None):
    """What relaxes the steps of `scene`, in words, for the CLI's progress line: "GFMD ncg (then fire where it
    stalls)" (the model built without a profile: the chain depends on the law and the unknowns only)."""
    physics = build_model(scene)
    settings = settings or settings_of(scene)
    return f"GFMD {describe(chain(physics, settings), settings)}"


def settings_of(scene):
    """The `Settings` of the scene's [solver] keys."""
    return Settings(method=scene.solver.method, tolerance=scene.solver.tolerance,
                    max_iterations=scene.solver.max_iterations)


def method_label(physics, settings):
    """The Result's method label: "gfmd-" and the chain's key ("gfmd-ncg", "gfmd-cg-dual2", "gfmd-fire",
    "gfmd-handover-near", "gfmd-verlet")."""
    return f"gfmd-{chain(physics, settings)[1]}"


def prepare(scene, h, realization=0, settings=None, method_name=None):
    """The GFMD cell of `scene` with profile h (m); settings default from scene.solver."""
    physics = build_model(scene, h)
    if settings is None:
        settings = settings_of(scene)
    cell = FreeGfmdCell if physics.free else GfmdCell  # a free boundary: the region of a padded cell (gfmd.free_cell)
    return cell(scene=scene, h=h, physics=physics, law=InterfaceLaw(physics), settings=settings,
                method=method_name or method_label(physics, settings))


def run_realization(scene, realization=0, settings=None, progress=None, method_name=None, *, checkpoint=None,
                    resume=None, variants=()):
    """Run the whole load ramp of one realization with GFMD.

    Parameters
    ----------
    scene : gfmd_contact.core.scene.Scene
    realization : int
        Realization index i (random profile seed surface.seed + i).
    settings : gfmd.solver.Settings, optional
        Integrator settings (default: from scene.solver).
    progress, checkpoint, resume, variants
        The hooks and the variants (`gfmd_contact.core.ramp.Variant`) of `gfmd_contact.core.ramp.run_ramp`.
    method_name : str, optional
        The Result's method label (default `method_label`: "gfmd-" and the chain's key, e.g. "gfmd-ncg").

    Returns
    -------
    gfmd_contact.core.result.Result
    """
    return run_ramp(scene, realization, partial(prepare, settings=settings, method_name=method_name),
                    progress=progress, checkpoint=checkpoint, resume=resume, variants=variants)
