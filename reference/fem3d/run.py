"""Entry point of the 3-D FE reference: a displacement-controlled ramp on plain inputs.

Units: SI (see `gfmd_contact.core.conventions`). `solve_cell` takes plain numbers and arrays, so that it
does not depend on the scene's 2+1-D keys; `from_scene` is the thin adapter from a `gfmd_contact.core.scene.Scene`.
The indenter at node (i, j) (written here from the convention, not taken from `gfmd_contact.core.loading`):

    z_ind = h − min h + δ0 − U,   Δn = z_ind − u_z,

U the indenter displacement of the step (m), δ0 the initial separation (m). Per step it records
p, a_rel, g_r, g (`observables`), the iterations, the residual and whether it converged, and the
fields u_z, gap, t_n on (Nx, Ny); `Fe3dResult.states` keeps the surface u_z for `export`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .._blas import single_thread
from .assembly import build_cell
from .cohesive import CohesiveSurface
from .hardwall import HardWall
from .law import NormalCohesiveZone
from .observables import contact_mask, observables, rms_gradient

LAWS = ("hard-wall", "cohesive")


@dataclass
class Fe3dResult:
    """The ramp's per-step curve (dict of arrays), fields [{u_z, gap, t_n}] per step, the cell and its states."""

    curve: dict
    fields: list
    states: list
    cell: object
    model: str
    setup_s: float
    solve_s: list
    messages: list = field(default_factory=list)


def solve_cell(heights, length_x, length_y, youngs_modulus, poisson_ratio, thickness, displacements, *,
               law="hard-wall", phi_n_star=None, length_normal=None, contact_rule="traction-tolerance",
               contact_tolerance=1e-3, contact_gap=1.0, initial_separation=0.0, layers=None, top=None,
               tolerance=1e-10):
    """The FE ramp over `displacements` (U, m) for the heights (Nx, Ny) (m) on the Lx × Ly cell.

    Layer of thickness D = `thickness` bonded at z = −D (a half-space is approximated by D ≥ the cell
    size: the error is the layer's, reference-formulas §1.3). law: "hard-wall" or "cohesive" (seed
    Eq. 3 with φn* = phi_n_star, δn = length_normal (m)); contact_rule / contact_tolerance /
    contact_gap as the scene's interface (`observables`). layers / top: the depth grading (`mesh`).
    tolerance: the residual bound per step (dimensionless, / p_ref). Dense solves use one BLAS thread.
    """
    with single_thread():
        return _solve_cell(heights, length_x, length_y, youngs_modulus, poisson_ratio, thickness, displacements,
                           law, phi_n_star, length_normal, contact_rule, contact_tolerance, contact_gap,
                           initial_separation, layers, top, tolerance)


def _solve_cell(heights, length_x, length_y, youngs_modulus, poisson_ratio, thickness, displacements, law,
                phi_n_star, length_normal, contact_rule, contact_tolerance, contact_gap, initial_separation, layers,
                top, tolerance):
    h = np.asarray(heights, dtype=float)
    if h.ndim != 2 or min(h.shape) < 2:
        raise ValueError(f"heights: shape {h.shape}; need a 2-D array (Nx, Ny) with Nx, Ny ≥ 2")
    if not np.all(np.isfinite(h)):
        raise ValueError("heights: not all finite")
    if law not in LAWS:
        raise ValueError(f"law = {law!r}: one of {', '.join(LAWS)}")
    steps = np.atleast_1d(np.asarray(displacements, dtype=float))
    if steps.ndim != 1 or not steps.size or not np.all(np.isfinite(steps)):
        raise ValueError("displacements: need a non-empty list of finite indenter displacements (m)")
    t0 = time.perf_counter()
    cell = build_cell(h.shape[0], h.shape[1], length_x, length_y, thickness, youngs_modulus, poisson_ratio,
                      layers=layers, top=top)
    S, w = cell.stiffness(), cell.weights
    spacing = cell.spacing
    e_star = youngs_modulus / (1.0 - poisson_ratio**2)
    g = rms_gradient(h, spacing)
    if law == "cohesive":
        if length_normal is None or phi_n_star is None:
            raise ValueError("law = 'cohesive' needs phi_n_star and length_normal")
        czl = NormalCohesiveZone.from_dimensionless(phi_n_star, length_normal, youngs_modulus)
        p_ref = e_star * g if g > 0 else czl.phi_n / (np.e * czl.delta_n)
        problem = CohesiveSurface(S, w, czl, p_ref)
        tolerance_gap = czl.contact_gap(contact_tolerance) if contact_rule == "traction-tolerance" else None
        rule_gap = contact_gap * czl.delta_n
    else:
        p_ref = e_star * g if g > 0 else e_star
        problem = HardWall(S, w, p_ref)
        tolerance_gap, rule_gap = None, (contact_gap * length_normal if length_normal else 0.0)
    setup = time.perf_counter() - t0
    z0 = (h - h.min() + initial_separation).ravel()
    u = np.zeros(h.size)
    mu = np.zeros(h.size)
    rows, fields, states, times, messages = [], [], [], [], []
    tangent, previous = None, None
    for k, U in enumerate(steps):
        t1 = time.perf_counter()
        z_ind = z0 - U
        if law == "cohesive":
            start = problem.warm_start(u, tangent, U - previous, z_ind) if previous is not None else u
            u, res, its, ok = problem.solve(start, z_ind, tolerance)
            tangent, previous = (problem.path_tangent(u, z_ind), U) if ok else (None, None)
            if ok and tangent is None:
                messages.append(f"step {k}: equilibrium with a tangent that is not positive definite (unstable)")
            t_z = problem.law.traction(z_ind - u)
        else:
            u, mu, its, ok, how = problem.solve(z_ind, u, mu, tolerance)
            res = problem.residual(u, mu, z_ind)
            t_z = -mu / w
            if how != "pdas":
                messages.append(f"step {k}: {how}")
        times.append(time.perf_counter() - t1)
        gap = np.maximum(z_ind - u, 0.0) if law == "hard-wall" else z_ind - u
        mask = contact_mask(contact_rule, gap, t_z, tolerance_gap, rule_gap)
        obs = observables(h, spacing, t_z.reshape(h.shape), mask.reshape(h.shape))
        rows.append({"step": k, "displacement": float(U), "delta": float(U - initial_separation), **obs,
                     "reaction_p": float(-np.sum(S @ u) / (length_x * length_y)),
                     "iterations": its, "residual": res, "converged": bool(ok)})
        if not ok:
            messages.append(f"step {k}: not converged, residual {res:.3g} p_ref")
        fields.append({"u_z": u.reshape(h.shape).copy(), "gap": gap.reshape(h.shape).copy(),
                       "t_n": t_z.reshape(h.shape).copy()})
        states.append(u.copy())
    curve = {key: np.array([r[key] for r in rows]) for key in rows[0]}
    model = (f"FE Q1 hexahedra, periodic {cell.shape[0]}×{cell.shape[1]} cell Lx = {length_x:g} m, "
             f"Ly = {length_y:g} m, bonded layer D = {thickness:g} m in {cell.layers} graded layers, "
             f"{cell.dofs} DOFs; {law} with nodal quadrature on the surface nodes; "
             + ("Newton with line search" if law == "cohesive" else "primal–dual active set")
             + " on the condensed surface (lateral Fourier block diagonalisation of the FE matrix)")
    return Fe3dResult(curve=curve, fields=fields, states=states, cell=cell, model=model, setup_s=setup,
                      solve_s=times, messages=messages)


def from_scene(scene, heights, displacements, **kw):
    """`solve_cell` for a 2+1-D `gfmd_contact.core.scene.Scene` (SPEC2D keys: surface.nodes_y, surface.length_y)
    with its heights (Nx, Ny) (m) and the indenter displacements U (m) of its ramp."""
    s, m, i = scene.surface, scene.material, scene.interface
    if getattr(s, "nodes_y", 0) < 2:
        raise ValueError("surface.nodes_y: the 3-D FE needs a 2+1-D scene (nodes_y ≥ 2)")
    if m.half_plane:
        raise ValueError("material.thickness: the FE models a finite layer; set it (e.g. ≥ the cell size)")
    if i.law not in LAWS:
        raise ValueError(f"interface.law = {i.law!r}: the 3-D FE solves {', '.join(LAWS)}")
    return solve_cell(heights, s.length, getattr(s, "length_y", None) or s.length, m.youngs_modulus,
                      m.poisson_ratio, m.thickness, displacements, law=i.law, phi_n_star=i.phi_n_star,
                      length_normal=i.length_normal, contact_rule=i.contact_rule,
                      contact_tolerance=i.contact_tolerance, contact_gap=i.contact_gap,
                      initial_separation=scene.loading.initial_separation, **kw)
