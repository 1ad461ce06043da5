"""GFMD vs the FE cell through a closed load–unload cycle on a cohesive layer (each its own law and observables).

Study, scene and metrics: `verification.studies.fe_cycle` (cohesive_sinusoid with φn* = 0.15, path
[−10, 30, −10] nm in 40 + 80 steps, displacement control from out of contact: one jump-in on loading, one
snap-off on unloading; the FE passes both with its trust-region energy descent). Its differences vs
N = 64, 128, 256 are in verification/data/fe_cycle.json (regenerate: `python -m verification.studies.fe_cycle
--write`). Measured: max |Δp̄|/E* 1.1e-4 → 1.0e-5 → 1.3e-6 (orders 3.4, 2.9), pull-off 3.0e-3 →
4.6e-4 → 7.4e-5 (2.7, 2.6), W = ∮ p̄ dδ 3.3e-3 → 3.3e-4 → 9.5e-5 (3.3, 1.8), jump-in and snap-off at the same
step in both at every N (δ = −5 nm and −8 nm); GFMD's pull-off is converged to 4e-6 at N = 128, so the
difference is the FE's P2 discretization.

Asserted at the CI N (128, ≈ 5 s): each difference ≤ FACTOR × the stored one at that N (the measured
discretization difference; a rerun reproduces it to round-off), jump-in and snap-off in the same step.
"""

from __future__ import annotations

import pytest

from verification import measured
from verification.plots import convergence_plot, table_plot
from verification.studies import fe_cycle as fc

METHODS = ("gfmd-fire", "fe-p2")
CASE = "fe/cohesive-layer-cycle"
FACTOR = 2.0
LABELS = {"p": "max |p̄_FE − p̄_GFMD| / E* over the cycle", "pull-off": "|Δ pull-off| / |pull-off_GFMD|",
          "hysteresis": "|W_FE − W_GFMD| / W_GFMD", "snap-off δ": "|Δ δ_snap-off| / Δδ_unloading",
          "jump-in δ": "|Δ δ_jump-in| / Δδ_loading"}


@pytest.fixture(scope="module")
def ci_run():
    return fc.measure(fc.CI_NODES)


@pytest.mark.parametrize("metric", fc.METRICS)
def test_fe_cycle(metric, ci_run, verification_record):
    diffs, numbers, wall = ci_run
    s = fc.stored()
    e = measured.entry(fc.NAME, "ci")
    i = s["N"].index(fc.CI_NODES)
    bound = FACTOR * s["errors"][metric][i]
    h = [1e-6 / n for n in s["N"]]
    plots = [convergence_plot(h, [max(v, 1e-16) for v in s["errors"][metric]], xlabel="node spacing l (m)",
                              ylabel=LABELS[metric], title=f"{metric}: GFMD–FE difference vs l (stored study)"),
             table_plot(["method", "pull-off (Pa)", "pull-off δ (m)", "snap-off δ (m)", "W (J/m²)", "jump-in δ (m)"],
                        [[m] + list(numbers[m].values()) for m in ("gfmd", "fe")],
                        title=f"cycle observables at N = {fc.CI_NODES}")]
    rec = verification_record(
        case=CASE, metric=f"{LABELS[metric]} at N = {fc.CI_NODES}", value=float(diffs[metric]), tolerance=bound,
        methods=METHODS,
        tolerance_source=(f"{FACTOR:g}× the difference at N = {fc.CI_NODES} in verification/data/fe_cycle.json "
                          f"({e['code_version']}, {e['date']}); orders between N {s['N']}: {s['orders'][metric]}"),
        resolution={"N": fc.CI_NODES, "N_study": s["N"], "steps": list(fc.STEPS)}, wall_s=wall, plots=plots,
        passed=bool(diffs[metric] <= bound), notes=f"jumps {numbers['jumps']}")
    assert rec.passed, (metric, diffs[metric], bound)
