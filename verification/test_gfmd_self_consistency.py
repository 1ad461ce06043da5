"""GFMD self-consistency: the FIRE and damped-Verlet integrators must reach the same equilibria.

Both integrators solve the same discrete equations and stop when the nodal
force residual max_j |r_j| < τ·p_ref (`gfmd.solver`; τ = scene.solver.tolerance,
p_ref = E*·ḡ). Two such solutions differ by what a residual of that size can
move. Tolerance (an a-priori bound, not a fitted number): a residual r changes
the interface traction by ~r per node and the mean pressure by ≤ max|r|, so

    |Δt_n|_j ≲ 2τ p_ref  ⇒  ‖Δt_n‖₂/‖t_n‖₂ ≲ 2τ p_ref √N / ‖t_n‖₂,
    |Δp_k|   ≲ 2τ p_ref  ⇒  ‖Δp‖₂/‖p‖₂    ≲ 2τ p_ref √(K+1) / ‖p‖₂,

times a safety factor SAFETY = 10 for the linearised amplification the bound
ignores (the traction depends non-locally on u through K(q); the hard-wall
contact set and the CZ law's stiffness may shift). Any difference far above
it means one integrator stopped on a wrong state.

Cases (`verification.scenes.small_sinusoid`, one parameter set a line in CASES):

* hard-wall sinusoid (the brief's case): `gfmd.algorithms.hard_wall_dynamics` runs FIRE or
  the damped Verlet (uniform mass, per-mode damping, projection) by `Settings.method`.
  The test fails on identical iteration counts and fields, so that a regression that
  routes both to one integrator is not mistaken for evidence about Verlet.
* cohesive sinusoid (φn* = 0.15, normal-only CZ): `gfmd.algorithms.dynamics` runs FIRE or
  Verlet; the same identity check applies.

"FIRE" is `verification.runs` method "gfmd-fire-only": solver.method = "fire" with the
Settings that pin FIRE itself (hard_wall = cohesive = "fire"); the default under method "fire"
is the projected CG (hard wall) and the NCG (normal-only cohesive law), which
tests/test_gfmd_fast.py and tests/test_solver_ncg.py compare with FIRE.

Cost: < 2 s for both cases.
"""

from __future__ import annotations

import numpy as np
import pytest

from gfmd_contact.core import surfaces
from gfmd_contact.core.model import build_model
from verification.metrics import relative_l2
from verification.plots import curve_plot, profile_plot, table_plot
from verification.records import scene_resolution
from verification.runs import run_methods
from verification.scenes import small_sinusoid

SAFETY = 10.0
METHODS = ("gfmd-fire-only", "gfmd-verlet")  # FIRE itself (Settings cohesive/hard_wall = "fire"), not CG/NCG
TOL_SOURCE = ("a-priori bound from the solver stopping rule max|r| < τ·p_ref: "
              "SAFETY·2τ·p_ref·√n/‖ref‖₂ with SAFETY = 10 (module docstring of "
              "verification/test_gfmd_self_consistency.py)")

METRICS = ("t_n rel. L2 diff, last step", "p(δ) rel. L2 diff")
CASES = [  # (case name, law, description)
    ("gfmd-self-consistency/hard-wall-sinusoid", "hard-wall",
     "FIRE vs Verlet, hard wall, sinusoid A = 5 nm, L = 1 µm, N = 256, δ to 4 nm"),
    ("gfmd-self-consistency/cohesive-sinusoid", "cohesive",
     "FIRE vs Verlet, normal CZ φn* = 0.15, sinusoid A = 5 nm, L = 1 µm, N = 256"),
]


def _bound(tau, p_ref, reference):
    """SAFETY · 2τ p_ref √n / ‖reference‖₂ (dimensionless)."""
    reference = np.asarray(reference, float)
    norm = float(np.linalg.norm(reference))
    return SAFETY * 2 * tau * p_ref * np.sqrt(reference.size) / norm if norm > 0 else np.inf


@pytest.mark.parametrize("case, law, description", [pytest.param(*c, id=c[0]) for c in CASES])
def test_fire_vs_verlet(case, law, description, verification_record):
    scene = small_sinusoid(law)
    runs = run_methods(scene, METHODS)
    fire, verlet = (runs[m].result for m in METHODS)
    for m in METHODS:
        assert runs[m].result.all_converged, runs[m].result.messages

    h = surfaces.profile(scene.surface, 0)
    e_star = scene.material.contact_modulus
    p_ref = build_model(scene, h).reference_traction
    tau = scene.solver.tolerance
    last = scene.loading.steps
    tn_f, tn_v = fire.fields[last]["t_n"], verlet.fields[last]["t_n"]
    p_f, p_v = fire.curve["p"], verlet.curve["p"]
    same = (np.array_equal(fire.curve["iterations"], verlet.curve["iterations"])
            and np.array_equal(tn_f, tn_v))
    notes = (f"{description}. p_ref = E*·ḡ = {p_ref:.4g} Pa, τ = {tau:g}. "
             f"Iterations over the ramp: FIRE {int(np.sum(fire.curve['iterations']))}, "
             f"Verlet {int(np.sum(verlet.curve['iterations']))}.")
    if same:
        notes += (" WARNING: identical iteration counts and bit-identical fields — the two runs are the same "
                  "computation, so this record says nothing about the Verlet integrator.")
    wall = sum(r.wall_s for r in runs.values())
    peak = max(r.peak_memory_bytes for r in runs.values())
    resolution = dict(scene_resolution(scene), law=scene.interface.law, safety=SAFETY, p_ref_Pa=p_ref)
    x_um = fire.x * 1e6
    delta_rel = fire.curve["delta"] / scene.surface.amplitude
    plots_tn = [
        profile_plot(x_um, {"gfmd-fire": -tn_f / e_star, "gfmd-verlet": -tn_v / e_star},
                     xlabel="x (µm)", ylabel="−t_n / E* (> 0 compressive)",
                     title=f"normal traction at the last step (δ = {fire.curve['delta'][-1] * 1e9:.3g} nm)"),
    ]
    plots_p = [
        curve_plot(delta_rel, {"gfmd-fire": p_f / e_star, "gfmd-verlet": p_v / e_star},
                   xlabel="penetration δ / A", ylabel="mean pressure p / E*", title="p–δ", difference=True),
        curve_plot(delta_rel, {"gfmd-fire": fire.curve["a_rel"], "gfmd-verlet": verlet.curve["a_rel"]},
                   xlabel="penetration δ / A", ylabel="relative contact area a_rel", title="a_rel–δ"),
        table_plot(["step", "δ (nm)", "FIRE iterations", "Verlet iterations", "FIRE residual / p_ref",
                    "Verlet residual / p_ref"],
                   [[k, fire.curve["delta"][k] * 1e9, fire.curve["iterations"][k],
                     verlet.curve["iterations"][k], fire.curve["residual"][k], verlet.curve["residual"][k]]
                    for k in range(last + 1)], title="solver record per load step"),
    ]
    common = dict(case=case, methods=METHODS, tolerance_source=TOL_SOURCE, resolution=resolution, wall_s=wall,
                  peak_memory_bytes=peak,
                  memory_method=runs[METHODS[0]].memory_method, notes=notes, scene=scene)

    err_tn = relative_l2(tn_f, tn_v)
    tol_tn = _bound(tau, p_ref, tn_f)
    rec_tn = verification_record(metric=METRICS[0], value=err_tn, tolerance=tol_tn, plots=plots_tn, **common)
    err_p = relative_l2(p_f, p_v)
    tol_p = _bound(tau, p_ref, p_f)
    rec_p = verification_record(metric=METRICS[1], value=err_p, tolerance=tol_p, plots=plots_p, **common)

    assert not same, "FIRE and Verlet gave bit-identical runs: both went through one integrator"
    assert rec_tn.passed, f"t_n: FIRE vs Verlet rel. L2 {err_tn:.3g} > {tol_tn:.3g}"
    assert rec_p.passed, f"p(δ): FIRE vs Verlet rel. L2 {err_p:.3g} > {tol_p:.3g}"
