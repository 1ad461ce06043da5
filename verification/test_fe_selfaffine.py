"""GFMD (finite bonded layer) vs the FE cell on self-affine adhesive profiles, H = 0.8 and 0.2 (case 2).

Study, scene and metrics: `verification.studies.fe_selfaffine` (L = 1 µm, λs,H = L/64, so every N ≥ 128
samples the same 32 modes: refining N refines the discretisation only; t_n, p, ḡ_r, a_rel differences).
Its differences at N = 256 … 2048 are in verification/data/fe_selfaffine.json (regenerate:
`python -m verification.studies.fe_selfaffine --write`, a few minutes), shown in the report.

ḡ_r and a_rel differ only where a node's contact status flips (the contact rule is a threshold on the gap).

Tolerances: t_n, p ≤ SAFETY × the stored difference at the same N and H; ḡ_r ≤ max(SAFETY × stored, 1/N)
and |Δa_rel| ≤ (stored nodes + 1)/N (a rule on top of the measurement: one more node may flip; the count is
stored as an int, `measured.node_count`); convergence of t_n
and p: every ratio e(N)/e(2N) ≥ the worst stored ratio / SAFETY.
"""

from __future__ import annotations

import math

import pytest

from verification import measured
from verification.metrics import observed_orders, worst_refinement_ratio
from verification.plots import convergence_plot, curve_plot, profile_plot
from verification.studies import fe_selfaffine as fs

METHODS = ("gfmd-fire", "fe-p2")
SAFETY = 1.5  # × the stored difference (value bounds), ÷ the worst stored refinement ratio (convergence)
compare = fs.compare


def source():
    e = measured.entry(fs.NAME, fs.KEY)
    return (f"verification.studies.fe_selfaffine (verification/data/fe_selfaffine.json [{fs.KEY}], "
            f"{e['code_version']}, {e['date']}): t_n, p ≤ {SAFETY:g} × the stored difference at the same N; "
            f"ḡ_r ≤ max({SAFETY:g} × stored, 1/N); |Δa_rel| ≤ (stored nodes + 1)/N")


def bounds(n, hurst):
    s = {m: fs.stored(m, n, hurst) for m in fs.METRICS}
    return ({"tn": SAFETY * s["tn"], "p": SAFETY * s["p"], "g": max(SAFETY * s["g"], 1 / n),
             "a": (fs.stored_node_count(n, hurst) + 1) / n}, s)


@pytest.mark.parametrize("hurst", [0.8, 0.2])
@pytest.mark.parametrize("n", [256, 512, pytest.param(1024, marks=pytest.mark.slow),
                               pytest.param(2048, marks=pytest.mark.slow)])
def test_fe_selfaffine(n, hurst, verification_record):
    out = compare(n, hurst)
    tol, st = bounds(n, hurst)
    rf, rg = out["rf"], out["rg"]
    case = f"fe/cohesive-self-affine-H{hurst}"
    res = {"N": n, "D/L": 1, "elements": "P2", "H": hurst, "lambda_s/l": n / 64}
    k = max(rf.fields)
    e_star = rf.scene.material.contact_modulus
    x_um = rf.x * 1e6
    plots = [profile_plot(x_um, {"GFMD": rg.fields[k]["t_n"] / e_star, "FE": rf.fields[k]["t_n"] / e_star},
                          xlabel="x (µm)", ylabel="t_n / E* (> 0 tensile)",
                          title=f"t_n at the last step, H = {hurst}, N = {n}"),
             curve_plot(rf.curve["delta"] * 1e9, {"GFMD": rg.curve["p"] / e_star, "FE": rf.curve["p"] / e_star},
                        xlabel="δ (nm)", ylabel="p / E*", title="p(δ)", difference=True),
             curve_plot(rf.curve["delta"] * 1e9, {"GFMD": rg.curve["a_rel"], "FE": rf.curve["a_rel"]},
                        xlabel="δ (nm)", ylabel="a_rel", title="a_rel(δ)")]
    common = dict(case=case, methods=METHODS, tolerance_source=source(), resolution=res, scene=rf.scene)
    verification_record(metric="t_n relative L2 (max over field steps)", value=out["tn"], tolerance=tol["tn"],
                        wall_s=out["fe_s"] + out["gfmd_s"], plots=plots, measured=st["tn"], **common)
    verification_record(metric="p(δ) max diff / max|p|", value=out["p"], tolerance=tol["p"], measured=st["p"], **common)
    verification_record(metric="ḡ_r max diff / max ḡ_r", value=out["g"], tolerance=tol["g"], measured=st["g"], **common)
    verification_record(metric="max |Δa_rel|", value=out["a"], tolerance=tol["a"], measured=st["a"], **common)
    verification_record(metric="time per load step FE / GFMD (s)", value=[out["fe_step"], out["gfmd_step"]],
                        tolerance=None, passed=None, case=case, methods=METHODS, resolution=res,
                        tolerance_source="informational")
    for m in ("tn", "p", "g", "a"):
        assert out[m] <= tol[m] * (1 + 1e-12), f"{m}: {out[m]:.3g} > {tol[m]:.3g} (H = {hurst}, N = {n})"


@pytest.mark.parametrize("ns", [(256, 512), pytest.param((256, 512, 1024, 2048), marks=pytest.mark.slow)],
                         ids=["ci", "full"])
@pytest.mark.parametrize("metric", ["tn", "p"])
@pytest.mark.parametrize("hurst", [0.8, 0.2])
def test_fe_selfaffine_convergence(hurst, metric, ns, verification_record):
    """The difference shrinks at every refinement by at least the worst stored ratio / SAFETY."""
    errs = [compare(n, hurst)[metric] for n in ns]
    worst = worst_refinement_ratio(measured.value(fs.NAME, fs.KEY, f"H={hurst:g}")[metric])
    need = worst / SAFETY
    ratios = [a / b for a, b in zip(errs, errs[1:])]
    label = {"tn": "t_n", "p": "p(δ)"}[metric]
    verification_record(case=f"fe/cohesive-self-affine-H{hurst}",
                        metric=f"smallest ratio of the {label} difference e(N)/e(2N), N = {ns[0]} … {ns[-1]}",
                        value=min(ratios), tolerance=need, lower_bound=True, methods=METHODS,
                        measured=worst, resolution={"N": list(ns), "H": hurst},
                        tolerance_source=(f"≥ the worst stored ratio {worst:.3g} / {SAFETY:g} = {need:.3g} (order ≥ "
                                          f"{math.log2(need):.2f}); observed orders "
                                          + ", ".join(f"{o:.2f}" for o in observed_orders(ns, errs))),
                        plots=[convergence_plot([1e-6 / n for n in ns], errs, xlabel="l = L/N (m)",
                                                ylabel=f"{label} GFMD–FE difference")])
    assert all(r >= need for r in ratios), f"{label}: ratios {ratios} below {need:.3g} (H = {hurst})"
