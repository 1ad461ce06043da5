"""GFMD (finite bonded layer) vs the FE cell on the adhesive sinusoid, normal CZ law (issue #4 (b)).

Scene: `verification.scenes.cohesive_sinusoid` (a = 50 nm, L = D = 1 µm, ν = 0.3, φn* = 0.01, δn = 1 nm,
δ from −2 nm to 60 nm in 20 steps). GFMD: `gfmd.loading.run_realization` (FIRE, tolerance 1e-8); FE: `reference.fem`
P2 (Newton, tolerance 1e-10). Same nodes, same z_ind, observables from
`contact.observables.step_observables`.

Metrics (max over the recorded field steps 4, 8, …, 20, resp. over all steps):
* t_n(x): ‖t_n^FE − t_n^GFMD‖₂ / ‖t_n^GFMD‖₂
* p(δ):   max_k |p_FE − p_GFMD| / max_k |p_GFMD|
* a_rel:  max_k |Δa_rel|

Study (measured when the tolerances were set):

    N          64       128      256      512     (256, 512: --full)
    t_n L2     3.9e-3   6.7e-4   9.4e-5   2.5e-5
    p(δ)       6.7e-4   1.1e-4   1.6e-5   6.7e-7
    a_rel      0        0        0        0
    FE s/step  0.003    0.009    0.12     0.35    (GFMD 0.015–0.03 s/step)

Observed order (t_n): 2.5 (64→128), 2.8 (128→256), 1.9 (256→512; not investigated:
possibly the GFMD tolerance 1e-8); the difference is discretisation
(GFMD: continuum kernel sampled at the nodes; FE: P2 elements + Simpson nodal
quadrature), both converge to the same continuum problem.
Tolerances: t_n L2 ≤ 1e-2·(64/N)², p ≤ 4e-3·(64/N)² (2.5× resp. 6× the N = 64
values, scaled with order 2); |Δa_rel| ≤ 2/N (one node per
contact edge); observed order between N = 64 and 128 ≥ 1.5.
"""

from __future__ import annotations

import numpy as np
import pytest

from verification.plots import convergence_plot, curve_plot, profile_plot
from verification.runs import fe_vs_gfmd
from verification.scenes import cohesive_sinusoid

METHODS = ("gfmd-fire", "fe-p2")
CASE = "fe/cohesive-sinusoid-phi0.01"
SOURCE = ("GFMD–FE study in verification/test_fe_cohesive.py docstring: t_n 3.9e-3, p 6.7e-4 at N = 64, "
          "order ≈ 2.5–2.8; bound = (2.5× t_n, 6× p at N = 64) × (64/N)²")


_CACHE = {}


def compare(n):
    if n not in _CACHE:
        out = _CACHE[n] = fe_vs_gfmd(cohesive_sinusoid(n))
        print(f"\nN={n}: t_n L2 {out['tn']:.3g}  p {out['p']:.3g}  a_rel {out['a']:.3g}  FE {out['fe_s']:.1f} s "
              f"({out['fe_step']:.3f} s/step)  GFMD {out['gfmd_s']:.1f} s ({out['gfmd_step']:.3f} s/step)")
    return _CACHE[n]


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
    scale = (64 / n) ** 2
    rec(case=CASE, metric="t_n relative L2 (max over field steps)", value=out["tn"], tolerance=1e-2 * scale,
        methods=METHODS, tolerance_source=SOURCE, resolution=res, wall_s=out["fe_s"] + out["gfmd_s"], plots=plots,
        scene=rf.scene)
    rec(case=CASE, metric="p(δ) max diff / max|p|", value=out["p"], tolerance=4e-3 * scale, methods=METHODS,
        tolerance_source=SOURCE, resolution=res)
    rec(case=CASE, metric="max |Δa_rel|", value=out["a"], tolerance=2 / n, methods=METHODS,
        tolerance_source="one node per contact edge (2/N)", resolution=res)
    rec(case=CASE, metric="time per load step FE / GFMD (s)", value=[out["fe_step"], out["gfmd_step"]],
        tolerance=None, methods=METHODS, tolerance_source="informational", resolution=res, passed=None)
    assert out["tn"] < 1e-2 * scale and out["p"] < 4e-3 * scale and out["a"] <= 2 / n + 1e-12


@pytest.mark.parametrize("n", [64, 128, pytest.param(256, marks=pytest.mark.slow),
                               pytest.param(512, marks=pytest.mark.slow)])
def test_fe_cohesive_sinusoid(n, verification_record):
    _record(verification_record, n, compare(n))


def test_fe_cohesive_sinusoid_convergence(verification_record):
    ns = [64, 128]
    outs = [compare(n) for n in ns]
    errs = [o["tn"] for o in outs]
    h = [1e-6 / n for n in ns]
    order = float(np.log(errs[0] / errs[1]) / np.log(2))
    verification_record(case=CASE, metric="observed order of the t_n difference (N = 64 → 128)", value=order,
                        tolerance=None, passed=bool(order > 1.5), methods=METHODS,
                        tolerance_source="order ≈ 2.5–2.7 measured (docstring); must exceed 1.5",
                        resolution={"N": ns},
                        plots=[convergence_plot(h, errs, order=order, xlabel="l = L/N (m)",
                                                ylabel="t_n rel. L2 GFMD–FE")])
    assert order > 1.5
