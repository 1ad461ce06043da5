"""GFMD vs FE through a jump into contact: `verification.scenes.jump_in_sinusoid`.

The cohesive sinusoid at φn* = 0.15, δ0 = 10 nm (≥ 8 δn), δ from −10 nm to 40 nm in 25 steps. The FE
Newton solve fails at the jump and falls back to its trust-region energy descent; GFMD
(FIRE) relaxes dynamically. Both must land on the same branch. Study: `verification.studies.fe_jump`;
measured differences at N = 64 … 512 in verification/data/fe_jump.json (regenerate:
`python -m verification.studies.fe_jump --write`).

Tolerances: t_n and p at N ≤ SAFETY × the stored difference at the same N; convergence (N = 64, 128 in
CI, 256 slow): every ratio e(N)/e(2N) ≥ the worst stored ratio / SAFETY; |Δa_rel| ≤ 2/N (a rule: one
node per contact edge); the FE must need its fallback.
"""

from __future__ import annotations

import math

import pytest

from verification import measured
from verification.metrics import observed_orders, worst_refinement_ratio
from verification.plots import convergence_plot, curve_plot
from verification.studies import fe_jump as fj

METHODS = ("gfmd-fire", "fe-p2")
CASE = "fe/cohesive-sinusoid-phi0.15-jump"
SAFETY = 1.5  # × the stored difference (value bounds), ÷ the worst stored refinement ratio (convergence)


def bound(metric, n):
    return SAFETY * fj.stored(metric, n)


def source():
    e = measured.entry(fj.NAME, fj.KEY)
    return (f"{SAFETY:g} × the difference stored at the same N by verification.studies.fe_jump "
            f"(verification/data/fe_jump.json [{fj.KEY}], {e['code_version']}, {e['date']})")


@pytest.mark.parametrize("n", [64, 128, pytest.param(256, marks=pytest.mark.slow)])
def test_fe_jump_into_contact(n, verification_record):
    st = fj.study(n)
    sc, out = st["scene"], st["out"]
    rf, rg, tn, p, a = (out[k] for k in ("rf", "rg", "tn", "p", "a"))
    tol_tn, tol_p = bound("tn", n), bound("p", n)
    wall = out["fe_s"] + out["gfmd_s"]
    print(f"\nφn* = 0.15, N = {n}: t_n {tn:.3g}, p {p:.3g}, a_rel {a:.3g}; FE fallbacks: {rf.messages}")
    res = {"N": n, "D/L": 1, "elements": "P2", "fe_fallback_steps": list(rf.diagnostics["fallback_steps"])}
    src = source()
    verification_record(case=CASE, metric="t_n relative L2 (max over field steps)", value=tn, tolerance=tol_tn,
                        methods=METHODS, tolerance_source=src, resolution=res, wall_s=wall, scene=sc,
                        measured=fj.stored("tn", n),
                        plots=[curve_plot(rf.curve["delta"], {"GFMD": rg.curve["p"], "FE": rf.curve["p"]},
                                          xlabel="δ (m)", ylabel="p (Pa)", title=f"p(δ) through the jump-in, N = {n}")])
    verification_record(case=CASE, metric="p(δ) max diff / max|p|", value=p, tolerance=tol_p, methods=METHODS,
                        tolerance_source=src, resolution=res, measured=fj.stored("p", n))
    verification_record(case=CASE, metric="max |Δa_rel|", value=a, tolerance=2 / n, methods=METHODS,
                        tolerance_source="one node per contact edge (2/N)", resolution=res, measured_source="")
    assert rf.diagnostics["fallback_steps"], "the jump into contact should need the FE fallback"
    assert tn < tol_tn and p < tol_p and a <= 2 / n + 1e-12


@pytest.mark.parametrize("ns", [(64, 128), pytest.param((64, 128, 256), marks=pytest.mark.slow)], ids=["ci", "full"])
@pytest.mark.parametrize("metric", ["tn", "p"])
def test_fe_jump_convergence(metric, ns, verification_record):
    """The difference through the jump shrinks at every refinement by at least the worst stored ratio / SAFETY
    (the stored ratios are over N = 64 … 512)."""
    errs = [fj.study(n)["values"][metric] for n in ns]
    worst = worst_refinement_ratio(measured.value(fj.NAME, fj.KEY, metric))
    need = worst / SAFETY
    ratios = [a / b for a, b in zip(errs, errs[1:])]
    label = {"tn": "t_n", "p": "p(δ)"}[metric]
    verification_record(case=CASE, metric=f"smallest ratio of the {label} difference e(N)/e(2N), N = {ns[0]} … {ns[-1]}",
                        value=min(ratios), tolerance=need, lower_bound=True, methods=METHODS,
                        tolerance_source=(f"≥ the worst stored ratio {worst:.3g} / {SAFETY:g} = {need:.3g} "
                                          f"(order ≥ {math.log2(need):.2f}); observed orders "
                                          + ", ".join(f"{o:.2f}" for o in observed_orders(ns, errs))),
                        resolution={"N": list(ns)}, measured=worst,
                        plots=[convergence_plot([1e-6 / n for n in ns], errs, xlabel="l = L/N (m)",
                                                ylabel=f"{label} GFMD–FE difference")])
    assert all(r >= need for r in ratios), (ratios, need)
