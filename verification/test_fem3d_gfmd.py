"""GFMD 2+1-D vs the 3-D FE (reference.fem3d) node by node; the embedded sinusoid 3-D FE vs 1+1-D FE.

Study, scenes and metrics: `verification.studies.fem3d_gfmd` (L = 1 µm, bonded layer D = L so both
methods solve the same body; egg-box A = 20 nm and a band-limited self-affine surface, H = 0.8, the
same continuum surface at every N; hard wall and normal CZ φn* = 0.01, δn = 2 nm; δ from −2 to 20 nm).
The FE mesh is the family whose mode-stiffness error vs the exact layer kernel is measured in
verification/data/mesh/fem3d_stiffness.json (N/2 Q1 layers, growth 8): GFMD's kernel is exact, so the
GFMD–FE difference at N is the FE's discretisation error at that resolution, O(l²).
Measured differences at N = 16, 32, 64: verification/data/fem3d_gfmd.json
(`python -m verification.studies.fem3d_gfmd --write --full`).

Tolerances: p̄, u_z, t_n, ḡ_r ≤ SAFETY × the stored difference at the same N (ḡ_r at least one node's
share 1/N² of the contact: a flipped node changes it); |Δa_rel| ≤ (stored nodes + 1)/N²;
convergence: e(16)/e(32) ≥ the stored ratio / SAFETY for p̄ and u_z. Independent of the stored
numbers: p̄'s difference is at most the FE's measured stiffness error of the (2, 0) mode at the same N
(the largest of the modes |q|L/2π ≤ 2 that carry the mean load of these surfaces; verification/data/mesh/fem3d_stiffness.json).
Embedded sinusoid: the 3-D FE's fields are constant along y to round-off (≤ 1e-12 of max|t_n|), and its
p̄ and t_n equal the 1+1-D FE's within their discretisation difference (≤ SAFETY × stored, converging).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from verification import measured
from verification.studies import fem3d_gfmd as fg

SAFETY = 1.5
METHODS = ("gfmd", "fe3d-q1")
STIFFNESS = json.loads((Path(__file__).resolve().parent / "data" / "mesh" / "fem3d_stiffness.json").read_text())
CASES = [(s, law) for s in fg.SURFACES for law in fg.LAWS]


def _stored(key, metric, n):
    v = measured.value(fg.NAME, fg.KEY, key)
    return v[metric][v["N"].index(n)]


def _source():
    e = measured.entry(fg.NAME, fg.KEY)
    return (f"verification.studies.fem3d_gfmd (verification/data/fem3d_gfmd.json [{fg.KEY}], {e['code_version']}, "
            f"{e['date']}): ≤ {SAFETY:g} × the stored difference at the same N")


@pytest.mark.parametrize("surface,law", CASES, ids=[f"{s}-{law}" for s, law in CASES])
@pytest.mark.parametrize("n", [16, 32, pytest.param(64, marks=pytest.mark.slow)])
def test_gfmd_equals_fem3d_node_by_node(surface, law, n, verification_record):
    out = fg.compare(surface, law, n)
    key = f"{surface}/{law}"
    tol = {m: SAFETY * _stored(key, m, n) for m in ("p", "uz", "tn", "g")}
    tol["g"] = max(tol["g"], 1.0 / n**2)
    tol["a"] = (_stored(key, "a_node_count", n) + 1) / n**2
    mode_error = abs(STIFFNESS["relative_error_vs_layer"][str(n)]["2,0"])
    common = dict(case=f"fem3d/{surface}-{law}", methods=METHODS, tolerance_source=_source(),
                  resolution={"N": f"{n}x{n}", "D/L": 1, "elements": "Q1", "layers": n // 2}, scene=out["rg"].scene)
    names = {"p": "p̄(δ) max diff / max|p̄|", "a": "max |Δa_rel|", "g": "ḡ_r max diff / max ḡ_r",
             "uz": "u_z L2 diff / max L2 (saved steps)", "tn": "t_n L2 diff / max L2 (saved steps)"}
    for m in ("p", "a", "g", "uz", "tn"):
        verification_record(metric=names[m], value=out[m], tolerance=tol[m], **common)
    verification_record(metric="p̄ diff vs the FE's (2,0) mode stiffness error at N", value=out["p"],
                        tolerance=mode_error, case=common["case"], methods=METHODS, resolution=common["resolution"],
                        tolerance_source="verification/data/mesh/fem3d_stiffness.json relative_error_vs_layer[N]['2,0']")
    for m in ("p", "a", "g", "uz", "tn"):
        assert out[m] <= tol[m] * (1 + 1e-12), f"{key} N={n}: {m} {out[m]:.3g} > {tol[m]:.3g}"
    assert out["p"] <= mode_error, f"{key} N={n}: p̄ differs by {out['p']:.3g}, more than the FE's mode error"


@pytest.mark.parametrize("surface,law", CASES, ids=[f"{s}-{law}" for s, law in CASES])
@pytest.mark.parametrize("metric", ["p", "uz"])
def test_gfmd_fem3d_difference_converges(surface, law, metric, verification_record):
    """e(16)/e(32) ≥ the stored ratio / SAFETY (the stored observed order is about 2: Q1's O(l²))."""
    key = f"{surface}/{law}"
    ratio = fg.compare(surface, law, 16)[metric] / fg.compare(surface, law, 32)[metric]
    stored = _stored(key, metric, 16) / _stored(key, metric, 32)
    verification_record(case=f"fem3d/{surface}-{law}", metric=f"{metric} difference ratio e(16)/e(32)",
                        value=ratio, tolerance=stored / SAFETY, passed=ratio >= stored / SAFETY, methods=METHODS,
                        tolerance_source=_source(), resolution={"N": "16, 32"})
    assert ratio >= stored / SAFETY, f"{key}: {metric} ratio {ratio:.3g} < {stored / SAFETY:.3g}"


@pytest.mark.parametrize("law", fg.LAWS)
@pytest.mark.parametrize("n", [16, 32])
def test_embedded_sinusoid_3d_fe_equals_1d_fe(law, n, verification_record):
    out = fg.compare_embedded(n, law)
    key = f"embedded/{law}"
    tol = {m: SAFETY * _stored(key, m, n) for m in ("p", "tn")}
    tol["a"] = (_stored(key, "a_node_count", n) + 1) / n
    common = dict(case=f"fem3d/embedded-sinusoid-{law}", methods=("fe3d-q1", "fe-p2"), tolerance_source=_source(),
                  resolution={"N": f"{n}x4 (3-D) / {n} (1+1-D P2)"})
    verification_record(metric="3-D FE t_n spread along y / max|t_n|", value=out["y_spread"], tolerance=1e-12,
                        **{**common, "tolerance_source": "round-off (a y-constant field)"})
    for m in ("p", "a", "tn"):
        verification_record(metric=f"3-D FE vs 1+1-D FE {m}", value=out[m], tolerance=tol[m], **common)
        assert out[m] <= tol[m] * (1 + 1e-12), f"{key} N={n}: {m} {out[m]:.3g} > {tol[m]:.3g}"
    assert out["y_spread"] <= 1e-12
    if n == 32:
        ratio, stored = out["p"] and fg.compare_embedded(16, law)["p"] / out["p"], \
            _stored(key, "p", 16) / _stored(key, "p", 32)
        assert ratio >= stored / SAFETY, f"{key}: p̄ difference ratio {ratio:.3g} < {stored / SAFETY:.3g}"
