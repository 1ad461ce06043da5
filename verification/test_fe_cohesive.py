"""GFMD (finite bonded layer) vs the FE cell on the adhesive sinusoid, normal CZ law (issue #4 (b)).

Study, scene and metrics: `verification.studies.fe_cohesive` (t_n(x) relative L2, p(δ), a_rel; GFMD FIRE
vs FE P2); its measured differences and t_n orders are in verification/data/fe_cohesive.json
(regenerate: `python -m verification.studies.fe_cohesive --write`, N = 64, 128; `--full` adds 256, 512).

Tolerances: t_n L2 ≤ 2.5 × (stored t_n at N = 64) × (64/N)², p ≤ 6 × (stored p at N = 64) × (64/N)²
(the N = 64 values scaled with order 2, entry "ci"); |Δa_rel| ≤ 2/N (one node per contact edge);
observed t_n order between N = 64 and 128 > 1.5.
"""

from __future__ import annotations

import pytest

from verification import measured
from verification.plots import convergence_plot, curve_plot, profile_plot
from verification.studies import fe_cohesive as fc

METHODS = ("gfmd-fire", "fe-p2")
CASE = "fe/cohesive-sinusoid-phi0.01"
FACTOR = {"tn": 2.5, "p": 6.0}  # × the stored N = 64 difference, scaled with (64/N)²


def bound(metric, n):
    """FACTOR × the stored N = 64 difference × (64/N)² (verification/data/fe_cohesive.json, entry "ci")."""
    errors, nodes = fc.measured_errors("ci")
    return FACTOR[metric] * errors[metric][nodes.index(64)] * (64 / n) ** 2


def source():
    e = measured.entry(fc.NAME, "ci")
    return (f"verification.studies.fe_cohesive (verification/data/fe_cohesive.json, {e['code_version']}, "
            f"{e['date']}): bound = ({FACTOR['tn']:g}× t_n, {FACTOR['p']:g}× p at N = 64) × (64/N)²")


def compare(n):
    return fc.compare(n)


def _record(rec, n, out):
    rf, rg = out["rf"], out["rg"]
    k = max(rf.fields)
    res = {"N": n, "D/L": 1, "elements": "P2"}
    plots = [profile_plot(rf.x, {"GFMD": rg.fields[k]["t_n"], "FE": rf.fields[k]["t_n"]}, xlabel="x (m)",
                          ylabel="t_n (Pa)", title=f"t_n at the last step, N = {n}"),
             curve_plot(rf.curve["delta"], {"GFMD": rg.curve["p"], "FE": rf.curve["p"]}, xlabel="δ (m)",
                        ylabel="p (Pa)", title=f"p(δ), N = {n}"),
             curve_plot(rf.curve["delta"], {"GFMD": rg.curve["a_rel"], "FE": rf.curve["a_rel"]}, xlabel="δ (m)",
                        ylabel="a_rel", title=f"a_rel(δ), N = {n}")]
    tol_tn, tol_p = bound("tn", n), bound("p", n)
    rec(case=CASE, metric="t_n relative L2 (max over field steps)", value=out["tn"], tolerance=tol_tn,
        methods=METHODS, tolerance_source=source(), resolution=res, wall_s=out["fe_s"] + out["gfmd_s"], plots=plots,
        scene=rf.scene)
    rec(case=CASE, metric="p(δ) max diff / max|p|", value=out["p"], tolerance=tol_p, methods=METHODS,
        tolerance_source=source(), resolution=res)
    rec(case=CASE, metric="max |Δa_rel|", value=out["a"], tolerance=2 / n, methods=METHODS,
        tolerance_source="one node per contact edge (2/N)", resolution=res)
    rec(case=CASE, metric="time per load step FE / GFMD (s)", value=[out["fe_step"], out["gfmd_step"]],
        tolerance=None, methods=METHODS, tolerance_source="informational", resolution=res, passed=None)
    assert out["tn"] < tol_tn and out["p"] < tol_p and out["a"] <= 2 / n + 1e-12


@pytest.mark.parametrize("n", [64, 128, pytest.param(256, marks=pytest.mark.slow),
                               pytest.param(512, marks=pytest.mark.slow)])
def test_fe_cohesive_sinusoid(n, verification_record):
    _record(verification_record, n, compare(n))


def test_fe_cohesive_sinusoid_convergence(verification_record):
    ns = [64, 128]
    errs = [compare(n)["tn"] for n in ns]
    h = [1e-6 / n for n in ns]
    order = fc.order(errs[0], errs[1])
    verification_record(case=CASE, metric="observed order of the t_n difference (N = 64 → 128)", value=order,
                        tolerance=None, passed=bool(order > 1.5), methods=METHODS,
                        tolerance_source=f"must exceed 1.5 (measured {measured.value(fc.NAME, 'ci', 'orders_tn')[0]:.2f}, verification/data/fe_cohesive.json)",
                        resolution={"N": ns},
                        plots=[convergence_plot(h, errs, order=order, xlabel="l = L/N (m)",
                                                ylabel="t_n rel. L2 GFMD–FE")])
    assert order > 1.5
