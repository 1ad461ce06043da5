"""Model only what a scene requires: the reduced models against the full ones, side by side.

Study, scene and metrics: `verification.studies.reduced_models` (extremes_base, N = 512, loaded to
δ = 8 nm); its measured numbers are in verification/data/reduced_models.json (regenerate:
`python -m verification.studies.reduced_models --write`), and the report shows them with each record.

(a) The seed's claim: coupled law c = 0.5 vs normal-only c = 0 at equal δ. Bounds: |Δa_rel| ≤ the stored
    difference + 1/N (a_rel moves in steps of 1/N: one node more than measured); at ν = 0.45
    Δp_r*/max p_r* ≤ SAFETY × stored; at ν = 0.3 the Δp_r* is a real effect: it must exceed stored / SAFETY.
(a') Exactness of the reduction (`solver.unknowns = "coupled"` forcing the full model): ν = 1/2, c = 0.5:
    u_x ≡ 0 is exact, |Δp| ≤ 2·tolerance·p_ref (each state leaves a residual ≤ tolerance·p_ref);
    c = 0, ν = 0.45: Eq. 2 with φt = 0 is not Eq. 3 (its T_n keeps e^{−Δt²/δt²}): |Δp| lies between
    100·tolerance·p_ref and SAFETY × stored; |Δa_rel| ≤ 1/N (one node at the threshold) in both.
(b) Half-plane vs a layer on a rigid base at equal effective penetration: for D ≥ L the mean |Δp|/p_ref
    and |Δa_rel| ≤ SAFETY × (the stored largest ratio to the floor) × this run's floor; D = L/4 must differ
    by more than (its stored ratio to the floor) / SAFETY × floor (the test can see a layer).
"""

from __future__ import annotations

import numpy as np
import pytest

from verification import measured
from verification.plots import convergence_plot, curve_plot, table_plot
from verification.studies import reduced_models as rm

N = rm.N
TOL = rm.TOL
CASE = "reduced-models"
SAFETY = 1.5  # × a stored difference (upper bounds), ÷ a stored effect (lower bounds)
run, reduced = rm.run, rm.reduced


def stored(*path):
    v = measured.value(rm.NAME, rm.KEY, path[0])
    for k in path[1:]:
        v = v[k]
    return v


def source(what):
    e = measured.entry(rm.NAME, rm.KEY)
    return (f"{what}; stored by verification.studies.reduced_models (verification/data/reduced_models.json "
            f"[{rm.KEY}], {e['code_version']}, {e['date']})")


def _plots(a, b, label_a, label_b, title):
    return [curve_plot(a[1].curve["delta"], {label_a: a[1].curve["a_rel"], label_b: b[1].curve["a_rel"]},
                       xlabel="δ (m)", ylabel="a_rel", title=f"a_rel(δ): {title}", difference=True),
            curve_plot(a[1].curve["delta"], {label_a: reduced(*a[:2]), label_b: reduced(*b[:2])},
                       xlabel="δ (m)", ylabel="p/(ḡ_r E*)", title=f"p_r*(δ): {title}", difference=True)]


@pytest.mark.parametrize("nu", rm.NUS_CLAIM)
def test_seed_claim_coupled_vs_normal_only(nu, verification_record):
    coupled, normal, da, dp = rm.seed_claim(nu)
    assert "coupled CZ" in coupled[1].model and "normal-only" in normal[1].model
    print(f"\nν = {nu}: c = 0.5 vs c = 0: |Δa_rel| {da:.3g}, |Δp_r*|/max {dp:.3g}; time {coupled[2]:.2f} s vs "
          f"{normal[2]:.2f} s")
    res = {"N": N, "ν": nu, "c": [0.5, 0.0]}
    methods = ("gfmd-coupled", "gfmd-normal-only")
    nodes_stored, dp_stored = stored("seed_claim", f"{nu:g}", "da_node_count"), stored("seed_claim", f"{nu:g}", "dp")
    da_stored, tol_a = nodes_stored / N, (nodes_stored + 1) / N  # an int count: the bound keeps its one node
    verification_record(case=f"{CASE}/seed-claim ν={nu}", metric="max |Δa_rel| at equal δ (c = 0.5 vs 0)", value=da,
                        tolerance=tol_a, methods=methods, measured=da_stored,
                        tolerance_source=source("the stored difference + 1/N (one node)"), resolution=res,
                        plots=_plots(coupled, normal, "c = 0.5", "c = 0", f"ν = {nu}"), scene=coupled[0])
    real_effect = nu < 0.4  # at ν = 0.3 friction moves p_r* by a quarter of its range: asserted as an effect
    tol_p = dp_stored / SAFETY if real_effect else SAFETY * dp_stored
    verification_record(case=f"{CASE}/seed-claim ν={nu}", metric="max |Δp_r*| / max |p_r*| at equal δ", value=dp,
                        tolerance=tol_p, methods=methods, resolution=res, measured=dp_stored, lower_bound=real_effect,
                        tolerance_source=source(f"a real effect: must exceed the stored value / {SAFETY:g}" if real_effect
                                                else f"{SAFETY:g} × the stored difference"))
    verification_record(case=f"{CASE}/seed-claim ν={nu}", metric="wall time coupled / normal-only (s)",
                        value=[coupled[2], normal[2]], methods=methods, resolution=res, passed=None,
                        tolerance_source="informational (shared machine)")
    assert da <= tol_a + 1e-12
    if real_effect:
        assert dp > tol_p
    else:
        assert dp <= tol_p


@pytest.mark.parametrize("nu, c, exact", [(0.5, 0.5, True), (0.45, 0.0, False)])
def test_forced_full_model_against_reduced(nu, c, exact, verification_record):
    full, auto, dp, da = rm.forced_full(nu, c)
    assert "u_x, u_z" in full[1].model and "unknowns u_z" in auto[1].model
    print(f"\nν = {nu}, c = {c}: full vs reduced |Δp| {dp:.3g} p_ref, |Δa_rel| {da:.3g}; time {full[2]:.2f} s vs "
          f"{auto[2]:.2f} s")
    case = f"{CASE}/full-vs-reduced ν={nu} c={c}"
    methods = ("gfmd-full (solver.unknowns = coupled)", "gfmd-auto")
    dp_stored = stored("forced_full", f"nu={nu:g} c={c:g}", "dp")
    if exact:
        tol, src, basis = 2 * TOL, "both states leave a residual ≤ tolerance·p_ref: |Δp| ≤ 2·tolerance·p_ref", None
    else:
        tol = SAFETY * dp_stored
        src = source(f"Eq. 2 (φt = 0) vs Eq. 3: {SAFETY:g} × the stored difference; must exceed 100·tolerance")
        basis = dp_stored
    verification_record(case=case, metric="max |Δp| / p_ref", value=dp, tolerance=tol, methods=methods,
                        tolerance_source=src, resolution={"N": N, "ν": nu, "c": c}, measured=basis,
                        **({} if basis is not None else {"measured_source": ""}),  # a rule, not a measurement
                        plots=_plots(full, auto, "full (u_x, u_z)", "reduced", f"ν = {nu}, c = {c}"),
                        scene=full[0])
    verification_record(case=case, metric="max |Δa_rel|", value=da, tolerance=1 / N, methods=methods,
                        tolerance_source="one node at the contact threshold", resolution={"N": N},
                        measured_source="")
    verification_record(case=case, metric="wall time full / reduced (s)", value=[full[2], auto[2]], methods=methods,
                        passed=None, tolerance_source="informational (shared machine)", resolution={"N": N})
    assert dp <= tol and da <= 1 / N + 1e-12
    if not exact:
        assert dp > 100 * TOL


def test_half_plane_vs_deep_layer(verification_record):
    hb = rm.half_plane_vs_layer()
    half, (floor_p, floor_a), out = hb["half"], hb["floor"], hb["out"]
    rows = [["floor (half-plane, shifted grid)", floor_p, floor_a, 0.0, half[2]]]
    for ratio in rm.DEPTHS:
        rows.append([f"D = {ratio:g} L", *out[ratio], hb["layers"][ratio][2]])
        print(f"\nD = {ratio} L: mean |Δp| {out[ratio][0]:.3g} p_ref, |Δa_rel| {out[ratio][1]:.3g}, "
              f"max ū {out[ratio][2]:.3g} δn")
    deep = [r for r in out if r >= 1]
    kp, ka, kthin = (stored("half_plane", k) for k in ("deep_p_over_floor", "deep_a_over_floor", "thin_p_over_floor"))
    tol_p, tol_a, need_thin = SAFETY * kp * floor_p, SAFETY * ka * floor_a, kthin / SAFETY * floor_p
    steps = rm.STEPS_B
    verification_record(
        case=f"{CASE}/half-plane-vs-layer", metric="max over D ≥ L of mean |Δp| / p_ref (at δ_eff)",
        value=max(out[r][0] for r in deep), tolerance=tol_p, methods=("gfmd-layer", "gfmd-half-plane"),
        measured=kp * floor_p,
        tolerance_source=source(f"{SAFETY:g} × the stored ratio to the interpolation floor ({kp:.3g}) × this run's floor"),
        resolution={"N": N, "steps": steps},
        plots=[table_plot(["comparison", "mean |Δp|/p_ref", "mean |Δa_rel|", "max ū/δn", "time (s)"], rows,
                          title="half-plane vs layer on a rigid base, at equal effective penetration"),
               convergence_plot(list(out), [out[r][0] for r in out], xlabel="D/L",
                                ylabel="mean |Δp|/p_ref vs half-plane")])
    verification_record(case=f"{CASE}/half-plane-vs-layer", metric="max over D ≥ L of mean |Δa_rel| (at δ_eff)",
                        value=max(out[r][1] for r in deep), tolerance=tol_a, measured=ka * floor_a,
                        methods=("gfmd-layer", "gfmd-half-plane"), resolution={"N": N, "steps": steps},
                        tolerance_source=source(f"{SAFETY:g} × the stored ratio to the floor ({ka:.3g}) × this run's floor"))
    verification_record(case=f"{CASE}/half-plane-vs-layer", metric="mean |Δp| / p_ref at D = L/4 (a layer is seen)",
                        value=out[0.25][0], tolerance=need_thin, lower_bound=True,
                        methods=("gfmd-layer", "gfmd-half-plane"), resolution={"N": N, "steps": steps},
                        measured=kthin * floor_p,
                        tolerance_source=source(f"must exceed the stored ratio to the floor ({kthin:.3g}) / {SAFETY:g} "
                                                "× this run's floor"))
    assert all(out[r][0] <= tol_p for r in deep), (out, floor_p)
    assert all(out[r][1] <= tol_a for r in deep), (out, floor_a)
    assert out[0.25][0] > need_thin  # a thin layer is visibly different: the comparison can fail


def test_reduced_models_data_is_consistent():
    """The stored numbers describe the scene the tests run (N) and every case they read."""
    v = measured.entry(rm.NAME, rm.KEY)["values"]
    assert v["N"] == N and set(v["seed_claim"]) == {f"{nu:g}" for nu in rm.NUS_CLAIM}
    assert np.all(np.isfinite(v["half_plane"]["p"])) and v["half_plane"]["D/L"] == list(rm.DEPTHS)
