"""The shared ramp is checked, not trusted: curve.csv and meta.json recomputed from fields.npz.

GFMD (a half-plane and a layer) and the FE (P2, the layer) each run one load–unload cycle with a jump-in and a
jump-out (scenes `ramp_check_half_plane`, `ramp_check_layer`), fields saved at every step; the run directory
is written by gfmd_contact.app.io as `gfmd run` writes it. `verification.ramp_records` then recomputes with its own
plain numpy, from the saved fields and scene.toml only: δ per step (from h, Δn and u_z at every node, and
from the path's corners), p̄, a_rel, ḡ, ḡ_r, each step's branch and cycle, and the cycle's hysteresis W.

Tolerance: each step's round-off bound derived from the operations (verification/ramp_records.py docstring);
the value recorded is max_k |recorded − recomputed| / bound_k (≤ 1 passes), or a count of mismatches (0).
A bug in the code every method shares (the ramp's δ bookkeeping, the whole-profile ḡ, the hysteresis sign,
verification/mutations.py "ramp-delta-off-by-one", "g-spacing", "hysteresis-sign") fails this case.
"""

from __future__ import annotations

import time

import pytest

from verification import ramp_records as rr
from verification import scenes
from verification.plots import table_plot
from verification.runs import with_method
from gfmd_contact.app.io import write_run
from gfmd_contact.app.methods import run_realization

CASE = "ramp/recorded-vs-saved-fields"
RUNS = {"gfmd-half-plane": ("gfmd", scenes.ramp_check_half_plane, {}),
        "gfmd-layer": ("gfmd", scenes.ramp_check_layer, {}),
        "fe-p2-layer": ("fe", scenes.ramp_check_layer, {"order": 2})}


@pytest.mark.parametrize("label", list(RUNS))
def test_ramp_records_recomputed_from_saved_fields(label, tmp_path, verification_record):
    method, make, options = RUNS[label]
    scene = with_method(make(), method, **options)
    t0 = time.perf_counter()
    result = run_realization(scene)
    assert result.all_converged, result.messages[:3]
    write_run(tmp_path / label, scene, [result], command="verification: ramp records")
    wall = time.perf_counter() - t0
    checks, numbers = rr.check(tmp_path / label)
    assert numbers["saved_steps"] == numbers["steps"] - 1, numbers  # every step but 0 saved
    assert numbers["unloading_steps"] > 0 and numbers["W_J_m2"], numbers
    failed = []
    plots = [table_plot(["check", "max |Δ| / bound (or count)", "tolerance", "max |recorded − recomputed|"],
                        [[n, f"{v:.3g}", t, f"{d:.3g}"] for n, (v, t, d) in checks.items()],
                        title=f"{label}: curve.csv / meta.json vs the saved fields (harness's own numpy)")]
    for name, (value, tolerance, max_diff) in checks.items():
        ok = value <= tolerance
        verification_record(
            case=CASE, metric=f"{label}: {name}", value=value, tolerance=tolerance, methods=(result.method,),
            passed=ok, wall_s=wall,
            tolerance_source=("a count: exact" if tolerance == 0 else
                              "round-off bound per step from the operations (verification/ramp_records.py): "
                              "value = max_k |recorded − recomputed| / bound_k"),
            resolution={"N": numbers["N"], "steps": numbers["steps"], "saved_steps": numbers["saved_steps"]},
            notes=(f"max |recorded − recomputed| = {max_diff:.3g}; W recomputed {numbers['W_J_m2']} vs meta.json "
                   f"{numbers['W_recorded_J_m2']} J/m² (bound {numbers['W_bound_J_m2']}); step 0 has no saved fields: "
                   "its δ is checked against the path and W's first trapezoid uses its recorded p̄"),
            scene=scene, plots=plots if name == next(iter(checks)) else [])
        if not ok:
            failed.append((name, value, tolerance, max_diff))
    assert not failed, failed
