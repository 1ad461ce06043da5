"""GFMD on the one load ramp (`contact.ramp.run_ramp`): the cell that relaxes one load step.

Units: SI (see `contact.conventions`). `prepare` builds the model of the scene
(`contact.model.build_model`: unknowns, kernel, checks) and the interface law once
per realization; `GfmdCell.solve` relaxes one step (`gfmd.solver.relax`) from the
ramp's warm start. `run_realization` runs a whole realization.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial

import numpy as np

from contact.laws import CompressionOverflowError, NormalCohesive
from contact.loading import indenter_surface
from contact.model import build_model
from contact.ramp import StepSolution, run_ramp

from . import kernels
from .solver import InterfaceLaw, Settings, fft_backend, relax


@dataclass
class GfmdCell:
    """One realization's GFMD problem: model, law and settings (see contact.ramp for the protocol)."""

    scene: object
    h: np.ndarray
    physics: object  # contact.model.Model
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
        return self.physics.reasons + (integrator(self.physics, self.settings), backends())

    def initial_state(self):
        """u_hat = 0: the undeformed surface, rfft modes of each solved component."""
        return np.zeros((self.physics.components, self.physics.nodes // 2 + 1), complex)

    def solve(self, displacement, guess, fallback):
        """Relax the load step at indenter displacement U (m) from the rfft displacements `guess`."""
        loading = self.scene.loading
        z_ind = indenter_surface(self.h, loading.initial_separation, displacement)
        wall_tolerance = 1e-12 * max(float(np.ptp(self.h)), self.scene.interface.length_normal)
        try:
            r = relax(self.physics, self.law, z_ind, guess, self.settings, wall_tolerance)
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
                            messages=() if r.converged else (r.message,))


def backends():
    """The FFT and the NCG's spectral kernels this process uses, in words (they change round-off only)."""
    return (f"backends: FFT {fft_backend()} (GFMD_FFT), cohesive NCG spectral algebra {kernels.jit_backend()} "
            "(GFMD_JIT)")


def integrator(physics, settings):
    """Which GFMD integrator relaxes the steps (gfmd.solver.relax), in words."""
    if physics.law.constraint and physics.law.adhesive:  # the cohesive wall (gfmd.solver._relax_cohesive_wall)
        return ("integrator: " + ("damped Störmer–Verlet" if settings.method == "verlet" else "FIRE on mass-weighted modes")
                + ", CZ attraction off the wall, projected onto the wall (cohesive wall)")
    if physics.law.constraint and settings.method == "fire" and settings.hard_wall == "cg":
        return ("integrator: projected preconditioned conjugate gradients (hard wall): on the contact pressures while "
                f"the contact set holds at most {settings.dual_contact_limit:g} of the nodes, on the displacements "
                "off the wall beyond (solver.method = fire selects it, Settings.hard_wall = \"fire\" the FIRE "
                "projection)")
    if (settings.method == "fire" and settings.cohesive == "ncg" and not physics.tangential
            and type(physics.law) is NormalCohesive):
        return ("integrator: nonlinear preconditioned conjugate gradients with a Newton line search (normal-only "
                "cohesive law; FIRE as fallback, Settings.cohesive = \"fire\" selects FIRE)")
    if settings.method == "verlet":
        return "integrator: damped Störmer–Verlet (seed §2)" + (", projected onto the wall" if physics.law.constraint
                                                                 else "")
    if physics.tangential and not physics.law.constraint:  # the coupled law (gfmd.solver._relax_coupled_fire)
        return ("integrator: FIRE on mass-weighted modes; where FIRE stalls, Newton–Krylov on the law's tangent "
                "(locally stable equilibria only), then damped Störmer–Verlet (coupled law)")
    return "integrator: FIRE on mass-weighted modes" + (", projected onto the wall" if physics.law.constraint else "")


def prepare(scene, h, realization=0, settings=None, method_name=None):
    """The GFMD cell of `scene` with profile h (m); settings default from scene.solver."""
    physics = build_model(scene, h)
    if settings is None:
        settings = Settings(method=scene.solver.method, tolerance=scene.solver.tolerance,
                            max_iterations=scene.solver.max_iterations)
    return GfmdCell(scene=scene, h=h, physics=physics, law=InterfaceLaw(physics), settings=settings, method=method_name or f"gfmd-{settings.method}")


def run_realization(scene, realization=0, settings=None, progress=None, method_name=None, *, checkpoint=None,
                    resume=None):
    """Run the whole load ramp of one realization with GFMD.

    Parameters
    ----------
    scene : contact.scene.Scene
    realization : int
        Realization index i (random profile seed surface.seed + i).
    settings : gfmd.solver.Settings, optional
        Integrator settings (default: from scene.solver).
    progress, checkpoint, resume
        The hooks of `contact.ramp.run_ramp`.
    method_name : str, optional
        The Result's method label (default "gfmd-<integrator>").

    Returns
    -------
    contact.result.Result
    """
    return run_ramp(scene, realization, partial(prepare, settings=settings, method_name=method_name),
                    progress=progress, checkpoint=checkpoint, resume=resume)
