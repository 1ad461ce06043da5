"""Scenes and measurements shared by the `verification/test_analytic_*.py` cases.

Units: SI (see `contact.conventions`). Every function here runs GFMD on one scene
and reduces the saved fields to the observables that the analytic references
(`reference.analytic`) predict. No tolerance lives here; each test module
states its convergence study and the tolerance derived from it.

Observables (why these):
* mean pressure p̄ = −⟨t_n⟩ and mean gap ḡ = ⟨Δn⟩ of the returned fields: on a
  half-plane the mean displacement is clamped, so p̄(ḡ) (not p̄(δ)) is the clean
  load–displacement relation.
* hard-wall contact half-width: (number of nodes with compressive traction)·l/2;
  it is quantised to the grid (error ≲ l).
* cohesive contact half-width: (number of nodes with Δn ≤ δn)·l/2 (the
  compressive region is much smaller than a JKR contact, reference-formulas §4.3).
* Hertz half-width from the pressure's second moment, a = 2√(∫x²p/∫p), exact for
  the elliptic pressure and free of the node-count quantisation.
"""

from __future__ import annotations

import time

import numpy as np

from gfmd.loading import run_realization
from contact.scene import default_scene
from gfmd.solver import Settings

TOL = 1e-10  # solver tolerance (× p_ref) used by every analytic case


def _indenter_scene(kind, shape, nodes, length, law, steps, final, initial, extra):
    d = {"surface.kind": kind, "surface.nodes": int(nodes), "surface.length": length, "surface.realizations": 1,
         "interface.law": law, "loading.initial_separation": initial, "loading.final_penetration": final,
         "loading.steps": steps, "solver.tolerance": TOL, "output.field_steps": steps, **shape}
    d.update(extra)
    return default_scene().replace(**d)


def sinusoid_scene(nodes, amplitude, length, law="hard-wall", steps=6, final=1e-9, initial=0.0, **extra):
    """Sinusoid h = −a cos(2πx/L) on the default half-plane (E = 70 GPa, ν = 0.45)."""
    return _indenter_scene("sinusoid", {"surface.amplitude": amplitude}, nodes, length, law, steps, final, initial,
                           extra)


def cylinder_scene(nodes, radius, length, law="hard-wall", steps=4, final=1e-9, initial=0.0, **extra):
    """Parabolic cylinder h = x²/(2R) centred in a periodic cell on the default half-plane."""
    return _indenter_scene("cylinder", {"surface.radius": radius}, nodes, length, law, steps, final, initial, extra)


def run(scene, tolerance=TOL):
    """(Result, wall seconds) of one realization; raises if a step did not converge."""
    t0 = time.perf_counter()
    result = run_realization(scene, settings=Settings(tolerance=tolerance))
    wall = time.perf_counter() - t0
    if not result.all_converged:
        raise AssertionError(f"GFMD did not converge: {result.messages}")
    return result, wall


def step_fields(result, k):
    """(x, p(x) compressive-positive, gap, p̄, ḡ) at saved step k."""
    f = result.fields[k]
    p = -np.asarray(f["t_n"], float)
    gap = np.asarray(f["gap"], float)
    return result.x, p, gap, float(np.mean(p)), float(np.mean(gap))


def half_width_compressive(p, spacing):
    """Hard-wall half-width (m): (number of nodes with p > 0)·l/2."""
    return 0.5 * spacing * int(np.count_nonzero(p > 0))


def half_width_gap(gap, threshold, spacing):
    """Cohesive half-width (m): (number of nodes with Δn ≤ threshold)·l/2."""
    return 0.5 * spacing * int(np.count_nonzero(gap <= threshold))


def half_width_second_moment(x, p):
    """a = 2√(Σx²p / Σp) (m): exact for p ∝ √(a² − x²)."""
    return 2.0 * float(np.sqrt(np.sum(x**2 * p) / np.sum(p)))


def order(h, error):
    """Least-squares slope of log(error) vs log(h)."""
    h, e = np.asarray(h, float), np.asarray(error, float)
    return float(np.polyfit(np.log(h), np.log(e), 1)[0])


def convergence_study(measure, levels, metrics):
    """Run `measure(level)` at every refinement level.

    `measure` returns (errors {metric: float}, ...); gives (data, errors {metric: array over levels}, wall s).
    """
    t0 = time.perf_counter()
    data = [measure(level) for level in levels]
    wall = time.perf_counter() - t0
    return data, {m: np.array([d[0][m] for d in data]) for m in metrics}, wall


def print_orders(tag, axis, levels, errors, orders):
    """One line per metric: refinement levels, errors and the fitted order (shown with `pytest -s`)."""
    for m, e in errors.items():
        print(f"{tag} {m}: {axis} {[f'{v:.3g}' for v in levels]} error {[f'{x:.2e}' for x in e]} order {orders[m]:.2f}")


def assert_study(records, orders, min_order, errors):
    """Every observed order ≥ its asserted minimum, and every recorded error within its bound."""
    for m, rec in records:
        assert orders[m] >= min_order[m], (m, orders[m], errors[m])
        assert rec.passed, (m, errors[m])
