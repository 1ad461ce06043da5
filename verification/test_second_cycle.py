"""A second load–unload cycle: its start and its hysteresis W by two routes (energy identities of an elastic body).

Johnson's adhesive sinusoid of `verification.scenes.ramp_check_half_plane` (h0 = 10 nm, L = 1 µm, half-plane,
w = 3.9 J/m², δn = 0.55 nm, N = 256, FIRE at 1e-10 p_ref; jump-in on loading, snap-off at δ ≈ −3.6 nm) is run
along three displacement paths, each observed by the run's own `gfmd_contact.core.cycle` (meta.json "cycles"):

* one cycle    [−6, 6, −6] nm in 30 + 40 steps: W;
* a reversible excursion [−6, 6, 4, 6, −6] nm in 30 + 5 + 5 + 40 steps: cycle 0 ends and cycle 1 starts at 4 nm,
  in contact, on the attached branch (no jump between 4 and 6 nm: the excursion is elastic and stores what it takes).
  Energy identity: W₀ + W₁ = W of the one-cycle run (the excursion adds ∫ p̄ dδ forth and back on the same δ grid);
* two cycles   [−6, 6, −6, 6, −6] nm in 30 + 40 + 30 + 40 steps: the state at −6 nm is detached, so the second
  cycle repeats the first: W₁ = W₀, and the same pull-off and snap-off δ.

Each cycle's δ_start must be the path's corner where it begins (read from the scene's loading.path).

Tolerances (derived, `verification.converged_bounds`): two converged states of one problem differ in p̄ by at most
Δp̄ (k_max|Δu| + 2τ p_ref), so a trapezoid sum over a δ path of length Σ|Δδ| differs by at most Δp̄·Σ|Δδ| per run
compared; δ_start within the path arithmetic's round-off (4ε·max|δ|); pull-off within Δp̄; snap-off δ the same step.
A cycle that starts at its own first step instead of the previous cycle's last (verification/mutations.py
"cycle-start-dropped") loses the excursion's first trapezoid (≈ 0.1 J/m², the bound ≈ 6e-5 J/m²) and moves
δ_start.
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.app.cycles import realization_cycles
from verification import analytic_cases as ac
from verification.converged_bounds import state_bounds
from verification.plots import curve_plot, table_plot
from verification.scenes import ramp_check_half_plane

CASE = "cycle/second-cycle-energy"
METHODS = ("gfmd-fire",)
EPS = np.finfo(float).eps
PATHS = {"one cycle": ([-6e-9, 6e-9, -6e-9], [30, 40]),
         "excursion": ([-6e-9, 6e-9, 4e-9, 6e-9, -6e-9], [30, 5, 5, 40]),
         "two cycles": ([-6e-9, 6e-9, -6e-9, 6e-9, -6e-9], [30, 40, 30, 40])}


def _run(label):
    path, steps = PATHS[label]
    scene = ramp_check_half_plane().replace(**{"loading.path": path, "loading.steps": steps, "output.field_steps": 0})
    result, wall = ac.run(scene)
    curve = {k: np.asarray(result.curve[k], float) for k in ("delta", "p", "a_rel")}
    rows, _ = realization_cycles(scene, curve)
    return scene, curve, rows, wall


def _corners(path):
    """δ (m) where each cycle starts: step 0's δ, then each corner where δ turns from unloading to loading."""
    return [path[0]] + [path[i] for i in range(1, len(path) - 1) if path[i] < path[i - 1] and path[i + 1] > path[i]]


def test_second_cycle_energy_and_start(verification_record):
    runs = {label: _run(label) for label in PATHS}
    dp = state_bounds(runs["one cycle"][0])[1]
    travel = {label: float(np.sum(np.abs(np.diff(c["delta"])))) for label, (_, c, _, _) in runs.items()}
    w = {label: [r["hysteresis"] for r in rows] for label, (_, _, rows, _) in runs.items()}
    two = runs["two cycles"][2]
    checks = {
        "W₀ + W₁ (excursion) − W (one cycle) (J/m²)": (abs(sum(w["excursion"]) - w["one cycle"][0]),
                                                     dp * (travel["excursion"] + travel["one cycle"])),
        "W₁ − W₀ (two cycles) (J/m²)": (abs(w["two cycles"][1] - w["two cycles"][0]), dp * travel["two cycles"]),
        "pull-off₁ − pull-off₀ (two cycles) (Pa)": (abs(two[1]["pull_off_pressure"] - two[0]["pull_off_pressure"]),
                                                    2 * dp),
        "snap-off step₁ − step₀ − 70 (two cycles)": (abs(two[1]["snap_off_step"] - two[0]["snap_off_step"] - 70), 0),
    }
    for label, (scene, _, rows, _) in runs.items():
        corners = _corners(scene.loading.path)
        starts = [r["delta_start"] for r in rows]
        diff = max(abs(a - b) for a, b in zip(starts, corners)) if len(starts) == len(corners) else np.inf
        checks[f"δ_start − the path's corner, {label} (m)"] = (diff, 4 * EPS * max(abs(x) for x in scene.loading.path))
    table = table_plot(["path", "cycles", "W per cycle (J/m²)", "δ_start (nm)"],
                       [[lbl, len(rows), ", ".join(f"{x:.6g}" for x in w[lbl]),
                         ", ".join(f"{r['delta_start'] * 1e9:.4g}" for r in rows)] for lbl, (_, _, rows, _) in runs.items()],
                       title="cycle observables of the three paths (ramp_check_half_plane scene)")
    curve = runs["excursion"][1]
    plot = curve_plot(list(curve["delta"]), {"p̄ (excursion path)": list(curve["p"])}, xlabel="δ (m)", ylabel="p̄ (Pa)",
                      title="the reversible excursion 6 → 4 → 6 nm inside the loop")
    failed = []
    for i, (metric, (value, tol)) in enumerate(checks.items()):
        verification_record(
            case=CASE, metric=metric, value=float(value), tolerance=float(tol), methods=METHODS,
            wall_s=sum(r[3] for r in runs.values()), scene=runs["excursion"][0],
            tolerance_source=("converged-state bound Δp̄ × the δ travel" if "W" in metric else
                              "path round-off 4ε·max|δ|" if "δ_start" in metric else
                              "converged-state bound" if "pull-off" in metric else "a count: exact"),
            resolution={"N": 256, "steps": {k: len(v[1]["delta"]) - 1 for k, v in runs.items()}},
            plots=[table, plot] if i == 0 else [],
            notes=f"W one cycle {w['one cycle'][0]:.6g} J/m², Δp̄ bound {dp:.3g} Pa")
        if not value <= tol:
            failed.append((metric, value, tol))
    assert not failed, failed
