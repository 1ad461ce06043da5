"""The 3-D FE reference on the one load ramp (`gfmd_contact.core.ramp`): its `Cell` for a 2+1-D scene.

Units: SI (see `gfmd_contact.core.conventions`). Same steps, profile and ramp protocol as GFMD; its own
z_ind (z_ind = h − min h + δ0 − U, `run`), its own law (`law`), solvers (`hardwall`, `cohesive`)
and observables (`observables`, through `Cell.observe`), as `reference.fem.run` does in 1+1-D.
What the 3-D FE cannot model is refused by `refusal` (the CLI says it before any work).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from gfmd_contact.core import law_registry
from gfmd_contact.core.errors import SceneError
from gfmd_contact.core.model import build_model
from gfmd_contact.core.ramp import StepSolution, run_ramp

from .._blas import single_thread
from .._material import near_incompressible
from .assembly import build_cell
from .cohesive import CohesiveSurface
from .hardwall import HardWall
from .law import LawZone, NormalCohesiveZone
from .observables import contact_mask, observables, rms_gradient

#: the largest surface the dense condensed solve is meant for (Nx·Ny ≤ 64²: S is 4096² doubles, 128 MiB)
MAX_NODES = 64 * 64
LAWS = ("hard-wall", "cohesive")


def _protocol_law(name):
    """Whether the 3-D FE takes interface.law = name through the law protocol (`LawZone`): a registered
    normal-only law that is not a wall (it has no implementation of its own of any)."""
    return name in law_registry.names() and name not in ("hard-wall", "cohesive-wall") and \
        law_registry.entry(name).normal_only


def refusal(scene):
    """Why the 3-D FE cannot solve the 2+1-D `scene` (a str naming the key), or None."""
    s, m, i = scene.surface, scene.material, scene.interface
    if s.boundary == "free":
        return ("surface.boundary = \"free\": the 3-D FE models a periodic cell on a bonded layer only, not an "
                "unbounded body; solve it with method.name = \"gfmd\" (Hockney padding), or use "
                "surface.boundary = \"periodic\"")
    if near_incompressible(scene):
        return near_incompressible(scene)
    if m.half_plane:
        return ("material.thickness = \"inf\": the 3-D FE models a finite bonded layer only; give a finite "
                "material.thickness (a layer of D = L stands in for the half-space with the truncation error "
                "k_layer/k_half − 1 of its fundamental mode, verification/data/mesh/fem3d_stiffness.json: "
                "halfspace_truncation_k_layer_over_k_half_minus_1), or use method.name = \"gfmd\"")
    if i.law not in LAWS and not _protocol_law(i.law):
        return (f"interface.law = {i.law!r}: the 3-D FE solves the normal cohesive zone (\"cohesive\", seed Eq. 3), "
                "the hard wall (\"hard-wall\") and a normal law with a potential through the law protocol only; use "
                "method.name = \"gfmd\"")
    if s.nodes * s.nodes_y > MAX_NODES:
        return (f"surface.nodes × surface.nodes_y = {s.nodes} × {s.nodes_y}: the 3-D FE's dense condensed solve is "
                f"meant for at most 64 × 64 = {MAX_NODES} surface nodes on a 2-core machine; reduce surface.nodes / "
                "surface.nodes_y or use method.name = \"gfmd\"")
    if min(s.nodes, s.nodes_y) < 3:
        return (f"surface.nodes = {s.nodes}, surface.nodes_y = {s.nodes_y}: the 3-D FE needs at least 3 surface "
                "nodes per direction")
    if scene.method.quadrature != "nodal":
        return (f"method.quadrature = {scene.method.quadrature!r}: the 3-D FE has nodal quadrature of the "
                "boundary term only")
    return None


def run_realization(scene, realization=0, progress=None, mesh_kw=None, tolerance=None, *, checkpoint=None,
                    resume=None):
    """The 3-D FE for one realization of a 2+1-D scene on the one load ramp; a `gfmd_contact.core.result.Result`
    with method "fe3d-q1". mesh_kw: `build_cell`'s layers / top (default: its grading from the lateral
    spacing). tolerance: residual bound per step (/ p_ref; default min(scene.solver.tolerance, 1e-10))."""
    why = refusal(scene)
    if why:
        raise SceneError(why)  # every refusal names the key (a ValueError too)

    def prepare(scene, h, realization=0):
        return prepare_cell(scene, h, mesh_kw=mesh_kw, tolerance=tolerance)

    with single_thread():
        return run_ramp(scene, realization, prepare, progress=progress, checkpoint=checkpoint, resume=resume)


def prepare_cell(scene, h, mesh_kw=None, tolerance=None):
    """The `Fe3dCell` of `scene` with heights h (Nx, Ny) (m): assembly, condensation, the law's problem."""
    physics = build_model(scene, h)  # the model choice and checks every method shares
    s, m, i = scene.surface, scene.material, scene.interface
    t0 = time.perf_counter()
    cell = build_cell(s.nodes, s.nodes_y, s.length, s.length_y or s.length, m.thickness, m.youngs_modulus,
                      m.poisson_ratio, **(mesh_kw or {}))
    S, w = cell.stiffness(), cell.weights
    e_star = m.youngs_modulus / (1.0 - m.poisson_ratio**2)
    g = rms_gradient(h, cell.spacing)
    if i.law != "hard-wall":  # its own Eq. 3, or a law it has none of through the law protocol
        law = (NormalCohesiveZone.from_dimensionless(i.phi_n_star, i.length_normal, m.youngs_modulus)
               if i.law == "cohesive" else LawZone(physics.law))
        problem = CohesiveSurface(S, w, law, e_star * g if g > 0 else law.phi_n / (np.e * law.delta_n))
        tolerance_gap = law.contact_gap(i.contact_tolerance) if i.contact_rule == "traction-tolerance" else None
        rule_gap = i.contact_gap * i.length_normal  # δn of every law's "gap" rule
    else:
        problem = HardWall(S, w, e_star * g if g > 0 else e_star)
        tolerance_gap, rule_gap = None, i.contact_gap * i.length_normal
    setup = time.perf_counter() - t0
    model = (f"FE Q1 hexahedra, periodic {s.nodes}×{s.nodes_y} cell Lx = {s.length:g} m, Ly = {cell.lengths[1]:g} m, "
             f"bonded layer D = {m.thickness:g} m in {cell.layers} graded layers, {cell.dofs} DOFs; {i.law} "
             + ("(normal CZ, seed Eq. 3)" if i.law == "cohesive" else "(frictionless)" if i.law == "hard-wall" else
                f"({physics.law.name}, through the law protocol)")
             + " with nodal quadrature on the surface nodes, u_x, u_y free (t_x = t_y = 0); "
             + ("primal–dual active set" if i.law == "hard-wall" else "Newton with line search")
             + " on the condensed surface (lateral Fourier block diagonalisation); method.order/linear do not apply")
    reasons = ("3-D FE (reference.fem3d) of the finite layer on its bonded base, periodic cell; the model choice and "
               "checks of gfmd_contact.core.model, as for every method",) + physics.reasons
    return Fe3dCell(scene=scene, cell=cell, problem=problem, physics=physics,
                    z0=(h - h.min() + scene.loading.initial_separation).ravel(), shape=h.shape,
                    tolerance=tolerance if tolerance is not None else min(scene.solver.tolerance, 1e-10),
                    tolerance_gap=tolerance_gap, rule_gap=rule_gap, model=model, reasons=reasons,
                    diagnostics={"setup_s": setup, "fallback_steps": [], "reaction_pressure": [],
                                 "fe3d_layers": cell.layers, "fe3d_dofs": cell.dofs,
                                 "fe3d_mesh_kw": dict(mesh_kw or {})})


@dataclass
class Fe3dCell:
    """One realization's 3-D FE problem (see gfmd_contact.core.ramp for the protocol). State: u_z of the surface
    (cohesive) or the stacked (u_z, μ) (hard wall); the cohesive warm start is the path tangent (`cohesive`)."""

    scene: object
    cell: object  # assembly.Cell3D
    problem: object  # HardWall or CohesiveSurface
    physics: object
    z0: np.ndarray
    shape: tuple
    tolerance: float
    tolerance_gap: float | None
    rule_gap: float
    model: str
    reasons: tuple
    diagnostics: dict
    method: str = "fe3d-q1"
    extrapolate: bool = False
    _last: dict = field(default_factory=dict, repr=False)

    @property
    def hard_wall(self):
        return isinstance(self.problem, HardWall)

    def initial_state(self):
        n = self.z0.size
        return np.zeros((2, n)) if self.hard_wall else np.zeros(n)

    def observe(self, scene, h, gap, t_n):
        """p, a_rel, ḡ_r, ḡ from the FE's own observables (`observables`, contact rule of the scene)."""
        self.diagnostics["reaction_pressure"].append(self._last.get("reaction", np.nan))
        mask = contact_mask(scene.interface.contact_rule, gap, t_n, self.tolerance_gap, self.rule_gap)
        return observables(h, self.cell.spacing, t_n, mask)

    def solve(self, displacement, guess, fallback):
        z_ind = self.z0 - displacement
        prob, messages, how = self.problem, [], "pdas"
        with single_thread():
            if self.hard_wall:
                u, mu, its, ok, how = prob.solve(z_ind, guess[0], guess[1], self.tolerance)
                res = prob.residual(u, mu, z_ind)
                t_n = -mu / prob.w
                gap = np.maximum(z_ind - u, 0.0)  # round-off penetration (≤ tol) shown as contact
                state = np.vstack([u, mu])
                if how != "pdas":
                    messages.append(how)
            else:
                last = self._last
                start = guess
                if last.get("U") is not None and np.array_equal(guess, last.get("u")):
                    start = prob.warm_start(guess, last["tangent"], displacement - last["U"], z_ind)
                u, res, its, ok = prob.solve(start, z_ind, self.tolerance)
                if ok:
                    tangent = prob.path_tangent(u, z_ind)
                    self._last.update(u=u, U=displacement, tangent=tangent)
                    if tangent is None:
                        messages.append("equilibrium with a tangent that is not positive definite (unstable)")
                gap = z_ind - u
                t_n = prob.law.traction(gap)
                state = u
        if not np.all(np.isfinite(u)):
            raise FloatingPointError(f"step at U = {displacement:.4g} m: non-finite 3-D FE solution")
        if not ok:
            messages.append(f"not converged, residual {res:.3g} p_ref")
        self._last["reaction"] = float(-np.sum(prob.S @ u) / (self.cell.lengths[0] * self.cell.lengths[1]))
        shape = self.shape

        def fields():
            return {"u_z": u.reshape(shape).copy(), "u_x": np.zeros(shape), "gap": gap.reshape(shape).copy(),
                    "t_n": t_n.reshape(shape).copy(), "t_t": np.zeros(shape)}

        return StepSolution(state=state, converged=bool(ok), iterations=int(its), residual=float(res),
                            gap=gap.reshape(shape), t_n=t_n.reshape(shape), fields=fields, messages=tuple(messages),
                            keep={"solutions": u.copy()}, fallback=how != "pdas")


def export_vtu(result, directory):
    """`<directory>/fe3d_step<k>.vtu` of the saved steps k of a ramp `Result` (`export.step_mesh`: the hexahedral
    mesh, displacement at every vertex, gap and t_n on the surface); [] if none saved."""
    from pathlib import Path
    from types import SimpleNamespace

    from .export import step_mesh

    sols = result.diagnostics.get("solutions") or {}
    if not sols:
        return []
    s, m = result.scene.surface, result.scene.material
    cell = build_cell(s.nodes, s.nodes_y, s.length, s.length_y or s.length, m.thickness, m.youngs_modulus,
                      m.poisson_ratio, **(result.diagnostics.get("fe3d_mesh_kw") or {}))
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    for k in sorted(sols):
        view = SimpleNamespace(cell=cell, states=[np.asarray(sols[k])], fields=[result.fields[k]])
        path = directory / f"fe3d_step{k}.vtu"
        step_mesh(view, 0).write(path)
        paths.append(path)
    return paths
