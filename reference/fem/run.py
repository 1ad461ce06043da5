"""The FE reference on the one load ramp: which FE problem a scene needs, and its cell.

Units: SI (see `gfmd_contact.core.conventions`). The only FE module that knows every
problem kind: the cohesive law (`solver.SurfaceProblem`, dense, or its sparse
subclass in `sparse`) and the hard wall (`hardwall`).
"""

from __future__ import annotations

import time
from functools import partial

from gfmd_contact.core.errors import SceneError
from gfmd_contact.core.model import build_model
from gfmd_contact.core.ramp import run_ramp

from .._material import near_incompressible
from .._blas import single_thread
from .hardwall import HardWallCell, HardWallProblem
from .solver import FeCell
from .sparse import make_problem


def run_realization(scene, realization=0, order=2, progress=None, mesh_kw=None, tolerance=None, linear="auto",
                    quadrature="nodal", *, checkpoint=None, resume=None):
    """FE reference for one realization on the one load ramp (`gfmd_contact.core.ramp.run_ramp`).

    Same steps and scene as GFMD, its own z_ind, law and observables (`reference.fem`); a `gfmd_contact.core.result.Result` with
    method "fe-p<order>" and diagnostics problem, setup_s, solutions (and wall_forces
    for the hard wall). tolerance: max |R/W|/p_ref per step (default
    min(scene.solver.tolerance, 1e-10)). linear: "dense" (Schur complement S, dense
    LU), "sparse" (SuperLU on the full reduced system, `reference.fem.sparse`),
    "sparse-lagged" (SuperLU reused as GMRES preconditioner) or "auto"
    (`sparse.choose_linear`); quadrature: "nodal" (default) or "gauss" (dense path
    only). A hard wall is solved by `reference.fem.hardwall` (a constraint, not a law).
    Dense solves use single-threaded BLAS. The cohesive wall (interface.law = "cohesive-wall") is not
    modelled: refused (`refusal`).
    """
    why = refusal(scene)
    if why:
        raise SceneError(why)  # every refusal names the key (a ValueError too)
    if scene.interface.law == "hard-wall":  # a constraint, not a law: primal–dual active set
        if quadrature != "nodal":
            raise ValueError(f"quadrature = {quadrature!r}: the hard wall is a nodal constraint, "
                             "only quadrature='nodal' applies")
        prepare = partial(prepare_hard_wall, order=order, mesh_kw=mesh_kw, tolerance=tolerance)
    else:
        prepare = partial(prepare_cohesive, order=order, mesh_kw=mesh_kw, tolerance=tolerance, linear=linear,
                          quadrature=quadrature)
    with single_thread():
        return run_ramp(scene, realization, prepare, progress=progress, checkpoint=checkpoint, resume=resume)


#: why the FE references refuse surface.boundary = "free"
FREE_REFUSAL = ("surface.boundary = \"free\": the FE reference models a periodic cell on a bonded layer only, not an "
                "unbounded body; solve it with method.name = \"gfmd\" (Hockney padding), or use "
                "surface.boundary = \"periodic\" with the FE")


def refusal(scene):
    """Why the FE reference cannot solve `scene` (a str), or None. The cohesive wall (CZ attraction with
    a hard-wall repulsion, `gfmd_contact.core.laws.CohesiveWall`) would need the cohesive Newton and the hard wall's
    active set in one solver, which the FE reference does not have; GFMD solves it. A free boundary: the FE models a
    periodic bonded layer only."""
    if scene.surface.boundary == "free":
        return FREE_REFUSAL
    if near_incompressible(scene):
        return near_incompressible(scene)
    if scene.interface.law == "cohesive-wall":
        return ("interface.law = \"cohesive-wall\": the FE reference does not model the cohesive wall (CZ "
                "attraction with a hard-wall repulsion); solve it with method.name = \"gfmd\", or use "
                "interface.law = \"cohesive\" or \"hard-wall\" with the FE")
    return None


def prepare_cohesive(scene, h, realization=0, order=2, mesh_kw=None, tolerance=None, linear="auto",
                     quadrature="nodal"):
    """The FE cell of a cohesive `scene` with profile h (m): mesh, assembly, condensation."""
    physics = build_model(scene, h)  # the same model choice and checks as every method
    t0 = time.perf_counter()
    prob = make_problem(linear, scene, h, order=order, mesh_kw=mesh_kw, quadrature=quadrature,
                        tangential=physics.tangential)
    setup = time.perf_counter() - t0
    cell = prob.cell
    law = ("coupled CZ (seed Eq. 2)" if prob.tangential else
           f"{physics.law.name} (through the law protocol), u_x free (t_x = 0)" if scene.interface.law != "cohesive" else
           "normal-only CZ (seed Eq. 3), u_x free (t_x = 0)")
    model = (f"{_mesh_text(scene, prob, order)}, {law}, "
             + (f"nodal (FacetBasis-weight) quadrature on {prob.ns} surface points" if quadrature == "nodal" else
                f"Gauss–Legendre quadrature ({prob.gauss.x.size // cell.nodes} points per facet; "
                f"outputs at the {prob.ns} surface points)")
             + (", z_ind at facet midpoints from the Fourier interpolant of h" if order == 2 else "")
             + f"; Newton on the condensed surface, {prob.linear_solver}")
    return FeCell(**_cell_common(scene, prob, physics, order, tolerance, setup), model=model)


def prepare_hard_wall(scene, h, realization=0, order=2, mesh_kw=None, tolerance=None):
    """The FE hard-wall cell of `scene` with profile h (m). tolerance: KKT residual bound per step
    (default min(scene.solver.tolerance, 1e-10)); a step above it is reported as not converged."""
    physics = build_model(scene, h)
    t0 = time.perf_counter()
    prob = HardWallProblem(scene, h, order=order, mesh_kw=mesh_kw)
    setup = time.perf_counter() - t0
    model = (f"{_mesh_text(scene, prob, order)}, frictionless hard wall (u_x free, t_x = 0) on {prob.ns} surface "
             "points" + (", z_ind at facet midpoints from the Fourier interpolant of h" if order == 2 else "")
             + "; primal–dual active set on the condensed surface")
    return HardWallCell(**_cell_common(scene, prob, physics, order, tolerance, setup), model=model)


def _mesh_text(scene, prob, order):
    cell = prob.cell
    return (f"FE P{order} plane strain, periodic cell L = {scene.surface.length:g} m, bonded layer "
            f"D = {scene.material.thickness:g} m, {cell.basis.N} DOFs ({cell.mesh.t.shape[1]} triangles, graded)")


def _cell_common(scene, prob, physics, order, tolerance, setup):
    """What every FE cell carries besides its model text (see gfmd_contact.core.ramp for the protocol)."""
    reasons = ("FE mesh of the finite layer on its bonded base, periodic cell; the model choice and checks of "
               "gfmd_contact.core.model, as for every method",) + physics.reasons
    return dict(scene=scene, prob=prob, physics=physics,
                tolerance=tolerance if tolerance is not None else min(scene.solver.tolerance, 1e-10),
                method=f"fe-p{order}", reasons=reasons,
                diagnostics={"problem": prob, "setup_s": setup, "fallback_steps": [], "reaction_pressure": []})
