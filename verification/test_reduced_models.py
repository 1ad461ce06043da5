"""Model only what a scene requires (issue #5): the reduced models against the full ones, side by side.

Scene: `verification.scenes.extremes_base` (self-affine, H = 0.8, h_rms = 4 nm,
L = 256 nm, N = 512, φn* = 0.15, δn = 1 nm, δ0 = 8 nm) loaded further, δ to 8 nm
(32 steps; 48 in (b)); FIRE, tolerance 1e-8; p_ref = E*ḡ.

(a) The seed's claim (its conclusions: "compressibility and friction ... affect [the load-area
    relation] negligibly ... a traction-separation law in normal direction will suffice"):
    coupled law c = 0.5 (u_x, u_z; seed Eq. 2) against normal-only c = 0 (u_z; Eq. 3), at
    equal δ. Measured (N = 512):

        ν      max|Δa_rel|       max|Δp_r*| / max|p_r*|   time c = 0.5 / c = 0
        0.45   0.0020 (1 node)   0.018                     0.70 s / 0.45 s
        0.30   0.0039 (2 nodes)  0.25                      1.14 s / 0.71 s

    So a_rel(δ) barely moves, but at ν = 0.3 friction changes the pressure by a quarter
    of its range: the claim holds for the area, and for p only near incompressibility.
    Bounds ≈ 3× measured: |Δa_rel| ≤ 3/N (ν = 0.45), 6/N (ν = 0.3); Δp_r* ≤ 0.05 of its
    range at ν = 0.45; at ν = 0.3 the Δp_r* is recorded and must exceed 0.1 (the effect
    is real, not noise).

(a') Exactness of the reduction, with `solver.unknowns = "coupled"` forcing the full model:
    ν = 1/2 half-plane, c = 0.5: u_x ≡ 0 is exact; measured |Δa_rel| = 0,
    |Δp| = 4e-7 Pa = 6e-18 p_ref; bound: 2·tolerance·p_ref (each state leaves a residual
    ≤ tolerance·p_ref), |Δa_rel| ≤ 1/N. Time full / reduced: 1.08 s / 0.71 s.
    c = 0, ν = 0.45: the forced full model runs the coupled law Eq. 2 with φt = 0, whose
    T_n still carries e^{−Δt²/δt²}: it is *not* Eq. 3, and the difference measures that
    factor, not an error of the reduction: |Δp| = 2.7e-4 p_ref (ν = 0.45; 2.7e-3 at ν = 0.3),
    |Δa_rel| = 1/N; time 1.04 s / 0.45 s. Recorded; asserted to lie between
    100·tolerance·p_ref and 3× measured.

(b) Half-plane against a layer on a rigid base, D = L/4 … 8L, compared at equal
    *effective* penetration: the layer's uniform mode shifts the mean plane by
    ū = −pD/M, so its state at δ matches the half-plane at δ_eff = δ − pD/M; the
    half-plane curves are interpolated linearly at δ_eff. Floor: the half-plane against
    itself on a grid shifted by half a step. Mean over the steps of |Δp|/p_ref and of
    |Δa_rel| (48 steps):

        D/L        floor    1/4      1/2      1        2        4        8
        |Δp|/p_ref 3.6e-6   2.6e-4   3.3e-5   5.6e-6   6.2e-6   5.3e-6   6.6e-6
        |Δa_rel|   0.0015   0.0030   0.0013   0.0014   0.0016   0.0018   0.0016
        max shift ū / δn    0.17     0.25     0.42     0.70     1.11     1.57

    The kernels differ by O(e^{−2q₁D}) (q₁ = 2π/L: 4e-2, 2e-3, 3e-6 at D = L/4, L/2, L),
    so from D = L on the difference is at the interpolation floor; in δ itself the
    layer differs by the growing ū. Time: the same (one FFT pair per iteration either way,
    ≈ 0.9–1.3 s). Bounds: for D ≥ L, mean |Δp|/p_ref ≤ 3× floor and mean |Δa_rel| ≤ 2×
    floor (measured ≤ 1.8× and 1.2×); D = L/4 must differ by > 10× floor (the test can see
    a layer).
"""

from __future__ import annotations

import time

import numpy as np
import pytest

import gfmd.loading as gl
from contact.kernels import constrained_modulus
from contact.observables import reduced_pressure
from verification.plots import convergence_plot, curve_plot, table_plot
from verification.scenes import extremes_base

N = 512
TOL = 1e-8
CASE = "reduced-models"


def run(steps=32, **overrides):
    sc = extremes_base(**{"loading.final_penetration": 8e-9, "loading.steps": steps, **overrides})
    t0 = time.perf_counter()
    result = gl.run_realization(sc)
    wall = time.perf_counter() - t0
    assert result.all_converged, result.messages
    return sc, result, wall


def p_ref(sc, result):
    return sc.material.contact_modulus * float(result.curve["g"][0])


def reduced(sc, result):
    return reduced_pressure(result.curve["p"], result.curve["g_r"], sc.material.contact_modulus)


def relation_difference(a, b):
    """(max|Δa_rel|, max|Δp_r*| / max|p_r*|) at equal δ for two runs (sc, result, wall)."""
    pa, pb = reduced(*a[:2]), reduced(*b[:2])
    ok = np.isfinite(pa) & np.isfinite(pb)
    da = float(np.max(np.abs(a[1].curve["a_rel"] - b[1].curve["a_rel"])))
    return da, float(np.max(np.abs(pa - pb)[ok]) / np.max(np.abs(pb[ok])))


def _plots(a, b, label_a, label_b, title):
    return [curve_plot(a[1].curve["delta"], {label_a: a[1].curve["a_rel"], label_b: b[1].curve["a_rel"]},
                       xlabel="δ (m)", ylabel="a_rel", title=f"a_rel(δ): {title}", difference=True),
            curve_plot(a[1].curve["delta"], {label_a: reduced(*a[:2]), label_b: reduced(*b[:2])},
                       xlabel="δ (m)", ylabel="p/(ḡ_r E*)", title=f"p_r*(δ): {title}", difference=True)]


@pytest.mark.parametrize("nu, area_nodes, p_bound", [(0.45, 3, 0.05), (0.3, 6, None)])
def test_seed_claim_coupled_vs_normal_only(nu, area_nodes, p_bound, verification_record):
    normal = run(**{"material.poisson_ratio": nu})
    coupled = run(**{"material.poisson_ratio": nu, "interface.tangential_ratio": 0.5})
    assert "coupled CZ" in coupled[1].model and "normal-only" in normal[1].model
    da, dp = relation_difference(coupled, normal)
    print(f"\nν = {nu}: c = 0.5 vs c = 0: |Δa_rel| {da:.3g}, |Δp_r*|/max {dp:.3g}; time {coupled[2]:.2f} s vs "
          f"{normal[2]:.2f} s")
    res = {"N": N, "ν": nu, "c": [0.5, 0.0]}
    src = "≈3× measured (module docstring)"
    methods = ("gfmd-coupled", "gfmd-normal-only")
    verification_record(case=f"{CASE}/seed-claim ν={nu}", metric="max |Δa_rel| at equal δ (c = 0.5 vs 0)", value=da,
                        tolerance=area_nodes / N, methods=methods, tolerance_source=src, resolution=res,
                        plots=_plots(coupled, normal, "c = 0.5", "c = 0", f"ν = {nu}"), scene=coupled[0])
    verification_record(case=f"{CASE}/seed-claim ν={nu}", metric="max |Δp_r*| / max |p_r*| at equal δ", value=dp,
                        tolerance=p_bound, methods=methods, resolution=res,
                        tolerance_source=src if p_bound else "informational: must exceed 0.1 (a real effect)",
                        passed=None if p_bound else bool(dp > 0.1))
    verification_record(case=f"{CASE}/seed-claim ν={nu}", metric="wall time coupled / normal-only (s)",
                        value=[coupled[2], normal[2]], methods=methods, resolution=res, passed=None,
                        tolerance_source="informational (shared machine)")
    assert da <= area_nodes / N + 1e-12
    if p_bound:
        assert dp <= p_bound
    else:
        assert dp > 0.1


@pytest.mark.parametrize("nu, c, exact", [(0.5, 0.5, True), (0.45, 0.0, False)])
def test_forced_full_model_against_reduced(nu, c, exact, verification_record):
    auto = run(**{"material.poisson_ratio": nu, "interface.tangential_ratio": c})
    full = run(**{"material.poisson_ratio": nu, "interface.tangential_ratio": c, "solver.unknowns": "coupled"})
    assert "u_x, u_z" in full[1].model and "unknowns u_z" in auto[1].model
    scale = p_ref(*auto[:2])
    dp = float(np.max(np.abs(full[1].curve["p"] - auto[1].curve["p"]))) / scale
    da = float(np.max(np.abs(full[1].curve["a_rel"] - auto[1].curve["a_rel"])))
    print(f"\nν = {nu}, c = {c}: full vs reduced |Δp| {dp:.3g} p_ref, |Δa_rel| {da:.3g}; time {full[2]:.2f} s vs "
          f"{auto[2]:.2f} s")
    case = f"{CASE}/full-vs-reduced ν={nu} c={c}"
    methods = ("gfmd-full (solver.unknowns = coupled)", "gfmd-auto")
    if exact:
        tol, src = 2 * TOL, "both states leave a residual ≤ tolerance·p_ref: |Δp| ≤ 2·tolerance·p_ref"
    else:
        tol, src = 8e-4, "Eq. 2 (φt = 0) vs Eq. 3: 3× the measured 2.7e-4 p_ref; must exceed 100·tolerance"
    verification_record(case=case, metric="max |Δp| / p_ref", value=dp, tolerance=tol, methods=methods,
                        tolerance_source=src, resolution={"N": N, "ν": nu, "c": c},
                        plots=_plots(full, auto, "full (u_x, u_z)", "reduced", f"ν = {nu}, c = {c}"),
                        scene=full[0])
    verification_record(case=case, metric="max |Δa_rel|", value=da, tolerance=1 / N, methods=methods,
                        tolerance_source="one node at the contact threshold", resolution={"N": N})
    verification_record(case=case, metric="wall time full / reduced (s)", value=[full[2], auto[2]], methods=methods,
                        passed=None, tolerance_source="informational (shared machine)", resolution={"N": N})
    assert dp <= tol and da <= 1 / N + 1e-12
    if not exact:
        assert dp > 100 * TOL


def _against_half_plane(layer, half):
    """Mean |Δp|/p_ref and |Δa_rel| of a layer run against the half-plane run at δ_eff = δ − pD/M."""
    sc, r = layer[:2]
    p, a, d = (np.asarray(r.curve[k], float) for k in ("p", "a_rel", "delta"))
    if sc.material.half_plane:
        shift = np.zeros_like(p)
    else:
        shift = p * sc.material.thickness / constrained_modulus(sc.material.youngs_modulus, sc.material.poisson_ratio)
    d_eff = d - shift
    dh = np.asarray(half[1].curve["delta"], float)
    ok = (d_eff >= dh.min()) & (d_eff <= dh.max())
    ph = np.interp(d_eff[ok], dh, half[1].curve["p"])
    ah = np.interp(d_eff[ok], dh, half[1].curve["a_rel"])
    scale = p_ref(*half[:2])
    return (float(np.mean(np.abs(p[ok] - ph))) / scale, float(np.mean(np.abs(a[ok] - ah))),
            float(np.max(np.abs(shift))) / sc.interface.length_normal)


def test_half_plane_vs_deep_layer(verification_record):
    steps = 48
    half = run(steps)
    shifted = run(steps, **{"loading.initial_separation": 8e-9 + 0.5 * 16e-9 / steps})
    floor_p, floor_a, _ = _against_half_plane(shifted, half)
    rows, out = [["floor (half-plane, shifted grid)", floor_p, floor_a, 0.0, half[2]]], {}
    for ratio in (0.25, 0.5, 1, 2, 4, 8):
        layer = run(steps, **{"material.thickness": ratio * half[0].surface.length})
        out[ratio] = _against_half_plane(layer, half)
        rows.append([f"D = {ratio:g} L", *out[ratio], layer[2]])
        print(f"\nD = {ratio} L: mean |Δp| {out[ratio][0]:.3g} p_ref, |Δa_rel| {out[ratio][1]:.3g}, "
              f"max ū {out[ratio][2]:.3g} δn, {layer[2]:.2f} s (half-plane {half[2]:.2f} s)")
    deep = [r for r in out if r >= 1]
    verification_record(
        case=f"{CASE}/half-plane-vs-layer", metric="max over D ≥ L of mean |Δp| / p_ref (at δ_eff)",
        value=max(out[r][0] for r in deep), tolerance=3 * floor_p, methods=("gfmd-layer", "gfmd-half-plane"),
        tolerance_source="3× the interpolation floor of this run (measured ≤ 1.8×)", resolution={"N": N, "steps": steps},
        plots=[table_plot(["comparison", "mean |Δp|/p_ref", "mean |Δa_rel|", "max ū/δn", "time (s)"], rows,
                          title="half-plane vs layer on a rigid base, at equal effective penetration"),
               convergence_plot(list(out), [out[r][0] for r in out], xlabel="D/L",
                                ylabel="mean |Δp|/p_ref vs half-plane")])
    verification_record(case=f"{CASE}/half-plane-vs-layer", metric="max over D ≥ L of mean |Δa_rel| (at δ_eff)",
                        value=max(out[r][1] for r in deep), tolerance=2 * floor_a,
                        methods=("gfmd-layer", "gfmd-half-plane"), resolution={"N": N, "steps": steps},
                        tolerance_source="2× the interpolation floor of this run (measured ≤ 1.2×)")
    assert all(out[r][0] <= 3 * floor_p for r in deep), (out, floor_p)
    assert all(out[r][1] <= 2 * floor_a for r in deep), (out, floor_a)
    assert out[0.25][0] > 10 * floor_p  # a thin layer is visibly different: the comparison can fail
