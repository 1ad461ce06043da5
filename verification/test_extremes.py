"""Stability at the extremes (issue #5): one-parameter sweeps around a base scene, plus corners.

Base scene (cohesive, self-affine, small for CI): L = 256 nm, N = 512 (l = 0.5 nm, δn = 2 l),
H = 0.8, h_rms = 4 nm, λr = 64 nm, λs,H = 4 nm, seed 1; half-plane, E = 70 GPa, ν = 0.45;
normal-only CZ φn* = 0.15, δn = 1 nm; δ0 = 8 nm = 8 δn, δ from −8 nm to 4 nm in 24 steps
(ΔU = 0.5 nm); FIRE, tolerance 1e-8. Each sweep changes one parameter (the row), the
corners several. δn/l is swept by N at fixed physics; δ0 at fixed ΔU; N at fixed l with
L = N·l, λr = L/8 (the seed's ratio), h_rms = 10 nm.

Each cell is one load ramp. Status: ok (all steps converged, no warning), warn (all
converged, but a check of `contact.model.scene_warnings` / `contact.loading.start_warning`
fired: its message is shown) or fail (refused with a specific message, or a step did
not converge: the solver's message). Asserted for every cell: no NaN in p, a_rel, the
residuals or the fields (ḡ_r is NaN by definition when nothing is in contact and is not
checked), every converged step meets the solver tolerance, every failure names the
scene key or the residual it is about. Asserted for specific cells: the checks fire
where they must (δn = 0.5 l: "under-resolved δn"; δ0 = 0: "start in contact";
incompressible layer: refused).

Measured (this machine, 2 shared cores; time per cell of 24 steps; "res" = max residual / p_ref,
"it" = FIRE iterations summed over the steps; every converged cell has res < 1e-8):

    sweep                      cell            status  it     s     note
    ν, c = 0.5, half-plane     0 … 0.4999      ok      ≈2250  0.3   coupled CZ
                               0.5             ok      2190   0.2   reduced to normal-only (exact)
    ν, c = 0.5, layer D = L    0 … 0.4999      ok      ≈2250  0.3   M/D up to 1.7e3 E/D at 0.4999
                               0.5             fail    –      0     refused: "material.poisson_ratio = 0.5:
                                                                    an incompressible layer … has no uniform mode"
    φn*                        1e-4 … 1        ok      980 … 3520  0.1 … 0.3
    δn/l (N = 128 … 8192)      0.5, 1          warn    2240   0.2   "under-resolved δn: … refine to δn ≥ 2 l,
                                                                    e.g. surface.nodes = 512"
                               2, 8, 32        ok      2240   0.2 … 0.8
    H                          0.1 … 0.95      ok      2020 … 2260  0.2
    δ0/δn                      0               warn    1230   0.1   "unstable start" (δ_jump = 4.46 δn)
                                                                    + "start in contact"
                               1               warn    1400   0.1   "unstable start" + "jump at start: … smallest
                                                                    gap 0.477 δn after relaxation"
                               2, 4            warn    ≈1700  0.15  "unstable start" only (predicted, conservative:
                                                                    the rough surface did not jump)
                               8, 10           ok      2240   0.2
    N (l = 0.5 nm, L = N l)    2^9, 2^12       ok      1870, 2500   0.2, 0.5
                               2^15 (slow)     warn    5900   36    "unstable start": δ_jump = 9.58 δn > δ0 = 8 δn
                               2^18, 6 steps   warn    46750  857   "unstable start": δ_jump = 11.9 δn; all 7
                               (slow)                               steps converged, ≈ 6700 iterations a step
                                                                    (ΔU = 2 nm) against ≈ 240 at 2^15: the
                                                                    FIRE cost per step grows steeply with L/l
    corners  ν 0.4999, φn* 1, δ0 0, c 0.5      warn    1880   0.3   unstable start + start in contact
             layer ν 0.4999, φn* 1, c 0.5      ok      3510   0.5
             H 0.1, φn* 1, δn/l 0.5            warn    2710   0.2   under-resolved δn
             H 0.95, φn* 1e-4, ν 0             ok      1080   0.1
             ν 0.5, c 0.5, φn* 1, δn/l 32      ok      3490   1.2   N = 8192, normal-only

No cell produced a NaN or an unconverged step; the only failure is the refused incompressible
layer. Coupled and normal-only cost the same number of iterations; iterations grow with φn*
(×3.6 from 1e-4 to 1) and with N at fixed l (per step: 75, 100, 240 at 2^9, 2^12, 2^15;
6700 at 2^18 with 4× larger steps).

GFMD vs FE (P2, `reference.fem`) on layer cells: the base scene on a layer D = L bonded to a
rigid base, δ from −8 nm to 2 nm in 20 steps, N = 256 (CI) and 512 (--full):

    cell                N = 256: Δp    t_n L2   Δa_rel   N = 512: Δp   t_n L2    FE s (256/512)
    ν = 0               3.2e-3         3.8e-3   0         6.7e-4        7.8e-4    1.2 / 7.9
    ν = 0.45            1.2e-2         1.3e-2   0         2.2e-3        2.5e-3    1.2 / 6.1
    ν = 0.4999          3.4e-2         3.0e-2   0         7.0e-3        6.6e-3    1.4 / 6.1
    φn* = 1e-3          1.4e-4         3.3e-4   0         1.2e-5        8.4e-5    1.2 / 4.0
    φn* = 1 (slow)      8.4e-3         3.1e-2   3.9e-3    1.7e-3        6.2e-3    16–35 / 115 (FE Newton fails
                                                                                  at step 8 and PTC does not converge:
                                                                                  "step 8: not converged, residual
                                                                                  0.00195"; GFMD converged, 0.2 s)
    c = 0.5, ν = 0.3    4.3e-3         5.5e-3   3.9e-3    8.4e-4        1.1e-3    2.8 / 15.5

(Δp = max|p_FE − p_GFMD|/max|p|, t_n L2 over the field steps; GFMD 0.1–0.3 s per cell.) The
differences fall with order ≈ 2.3–2.5 from N = 256 to 512 in every cell, also at ν = 0.4999
(P2 elements near incompressibility: the largest difference, but converging, no locking plateau).
N = 256 has δn = l (under-resolved, warned): both methods share the nodes, so the comparison is
of methods, not of the continuum. Bounds: 3 × the N = 256 value × (256/N)², |Δa_rel| ≤ 4/N.
"""

from __future__ import annotations

import re
import time

import numpy as np
import pytest

import gfmd.loading as gl
from contact.model import warnings_in
from contact.scene import Scene
from verification import harness

CASE = "extremes/sweep"
BASE = {"surface.kind": "self-affine", "surface.nodes": 512, "surface.length": 256e-9, "surface.hurst": 0.8,
        "surface.h_rms": 4e-9, "surface.rolloff_wavelength": 64e-9, "surface.rollon_wavelength": 4e-9,
        "surface.seed": 1, "surface.realizations": 1, "material.youngs_modulus": 70e9,
        "material.poisson_ratio": 0.45, "material.thickness": "inf", "interface.law": "cohesive",
        "interface.phi_n_star": 0.15, "interface.length_normal": 1e-9, "interface.tangential_ratio": 0.0,
        "loading.initial_separation": 8e-9, "loading.final_penetration": 4e-9, "loading.steps": 24,
        "solver.tolerance": 1e-8, "output.field_steps": 4}
DN = 1e-9
STEP = 0.5e-9  # ΔU (m)


def scene(**overrides):
    return Scene().replace(**{**BASE, **overrides})


def _n_at_spacing(n, spacing=0.5e-9):
    """N-sweep: L = N·l, λr = L/8, h_rms = 10 nm, λs,H = 4 nm."""
    length = n * spacing
    return {"surface.nodes": n, "surface.length": length, "surface.rolloff_wavelength": length / 8,
            "surface.h_rms": 10e-9}


def _d0(ratio):
    return {"loading.initial_separation": ratio * DN,
            "loading.steps": int(round((ratio * DN + BASE["loading.final_penetration"]) / STEP))}


def _nodes_for(ratio):
    return {"surface.nodes": int(round(BASE["surface.length"] / (DN / ratio)))}


slow = pytest.mark.slow
COUPLED = {"interface.tangential_ratio": 0.5}
LAYER = {"material.thickness": BASE["surface.length"]}
# sweep name -> [(column label, overrides, marks)]
SWEEPS = {
    "ν (c = 0.5, half-plane)": [(f"ν = {v:g}", {**COUPLED, "material.poisson_ratio": v}, ())
                                for v in (0.0, 0.3, 0.45, 0.49, 0.499, 0.4999, 0.5)],
    "ν (c = 0.5, layer D = L)": [(f"ν = {v:g}", {**COUPLED, **LAYER, "material.poisson_ratio": v}, ())
                                 for v in (0.0, 0.3, 0.45, 0.49, 0.499, 0.4999, 0.5)],
    "φn*": [(f"φn* = {v:g}", {"interface.phi_n_star": v}, ()) for v in (1e-4, 1e-3, 0.01, 0.15, 0.5, 1.0)],
    "δn/l (N at fixed L)": [(f"δn/l = {v:g}", _nodes_for(v), ()) for v in (0.5, 1, 2, 8, 32)],
    "H": [(f"H = {v:g}", {"surface.hurst": v}, ()) for v in (0.1, 0.2, 0.5, 0.8, 0.95)],
    "δ0/δn": [(f"δ0 = {v:g} δn", _d0(v), ()) for v in (0, 1, 2, 4, 8, 10)],
    "N (l = δn/2, L = N l)": [(f"N = 2^{k}", _n_at_spacing(2**k), (slow,) if k > 12 else ()) for k in (9, 12, 15)]
    + [("N = 2^18, 6 steps", {**_n_at_spacing(2**18), "loading.steps": 6, "solver.max_iterations": 20000}, (slow,))],
    "corners": [
        ("ν = 0.4999, φn* = 1, δ0 = 0, c = 0.5", {**COUPLED, "material.poisson_ratio": 0.4999,
                                                "interface.phi_n_star": 1.0, **_d0(0)}, ()),
        ("layer ν = 0.4999, φn* = 1, c = 0.5", {**COUPLED, **LAYER, "material.poisson_ratio": 0.4999,
                                               "interface.phi_n_star": 1.0}, ()),
        ("H = 0.1, φn* = 1, δn/l = 0.5", {"surface.hurst": 0.1, "interface.phi_n_star": 1.0,
                                          **_nodes_for(0.5)}, ()),
        ("H = 0.95, φn* = 1e-4, ν = 0", {"surface.hurst": 0.95, "interface.phi_n_star": 1e-4,
                                         "material.poisson_ratio": 0.0}, ()),
        ("ν = 0.5, c = 0.5, φn* = 1, δn/l = 32", {**COUPLED, "material.poisson_ratio": 0.5,
                                                  "interface.phi_n_star": 1.0, **_nodes_for(32)}, ()),
    ],
}

_SPECIFIC = re.compile(r"(surface|material|interface|loading|solver)\.\w+|residual")
_FIELD_CHECKED = ("u_z", "u_x", "gap", "t_n", "t_t")


def run_cell(overrides):
    """Run one cell; returns a dict with status, message and the numbers (never raises for scene errors)."""
    t0 = time.perf_counter()
    sc = None
    try:
        sc = scene(**overrides)
        result = gl.run_realization(sc)
    except ValueError as exc:  # SceneError, ModelCheckError, full-contact refusal: all ValueError
        return {"status": "fail", "message": f"refused: {exc}", "refused": True, "wall_s": time.perf_counter() - t0,
                "scene": sc or "",
                "nan": False, "residual_ok": True, "iterations": 0, "residual": float("nan"), "steps": 0}
    wall = time.perf_counter() - t0
    c = result.curve
    finite = [np.asarray(c[k], float) for k in ("p", "a_rel", "residual", "U", "delta")]
    finite += [np.asarray(f[name], float) for f in result.fields.values() for name in _FIELD_CHECKED]
    nan = not all(np.all(np.isfinite(a)) for a in finite)
    conv = np.asarray(c["converged"], bool)
    residual = np.asarray(c["residual"], float)
    residual_ok = bool(np.all(residual[conv] < sc.solver.tolerance))
    warnings = warnings_in(result.reasons)
    out = {"refused": False, "scene": sc, "wall_s": wall, "nan": nan, "residual_ok": residual_ok, "steps": int(conv.size),
           "iterations": int(np.sum(c["iterations"])), "residual": float(np.max(residual)),
           "model": result.model, "warnings": warnings, "messages": list(result.messages),
           "p": np.asarray(c["p"]), "a_rel": np.asarray(c["a_rel"]), "delta": np.asarray(c["delta"])}
    numbers = (f"{conv.sum()}/{conv.size} steps, max residual {out['residual']:.2g} p_ref, "
               f"{out['iterations']} iterations, {wall:.2f} s")
    if nan:
        out.update(status="fail", message="NaN in the result: " + numbers)
    elif not conv.all():
        out.update(status="fail", message=f"{result.messages[0]} ({len(result.messages)} steps); {numbers}")
    elif warnings:
        out.update(status="warn", message=f"{numbers}; " + " | ".join(warnings))
    else:
        out.update(status="ok", message=numbers)
    return out


_CACHE = {}


def cell(sweep, label):
    key = (sweep, label)
    if key not in _CACHE:
        overrides = dict(next(o for lab, o, _ in SWEEPS[sweep] if lab == label))
        _CACHE[key] = run_cell(overrides)
    return _CACHE[key]


def _params(include_slow):
    for sweep, cells in SWEEPS.items():
        for label, _, marks in cells:
            yield pytest.param(sweep, label, marks=marks, id=f"{sweep}|{label}")


def check_cell(out):
    assert not out["nan"], out["message"]
    assert out["residual_ok"], out["message"]
    if out["status"] == "fail":
        assert _SPECIFIC.search(out["message"]), f"unspecific failure message: {out['message']}"


@pytest.mark.parametrize("sweep, label", list(_params(True)))
def test_extreme_cell(sweep, label, verification_record):
    out = cell(sweep, label)
    print(f"\n{sweep} | {label}: {out['status']}: {out['message']}")
    verification_record(case=CASE, metric=f"{sweep} | {label}: status", value=out["status"], tolerance=None,
                        methods=("gfmd-fire",), passed=not out["nan"] and out["residual_ok"],
                        tolerance_source="no NaN; converged steps below solver.tolerance; failures name a key",
                        resolution={"sweep": sweep, "cell": label}, wall_s=out["wall_s"], notes=out["message"],
                        scene=out["scene"])
    check_cell(out)


def test_checks_fire_where_they_must():
    """The specific messages appear on the cells built to trigger them."""
    under = cell("δn/l (N at fixed L)", "δn/l = 0.5")
    assert under["status"] == "warn" and "δn = 0.5 l is under-resolved" in under["message"]
    start = cell("δ0/δn", "δ0 = 0 δn")
    assert start["status"] == "warn" and "start in contact" in start["message"]
    layer = cell("ν (c = 0.5, layer D = L)", "ν = 0.5")
    assert layer["refused"] and "material.poisson_ratio" in layer["message"]
    base = cell("φn*", "φn* = 0.15")
    assert base["status"] == "ok", base["message"]


def test_extremes_grid(verification_record, request):
    """The colour-coded table of every cell run in this session (CI subset, or all with --full)."""
    full = request.config.getoption("--full", default=False)
    rows, width = [], max(len(c) for c in SWEEPS.values())
    for sweep, cells in SWEEPS.items():
        row = [sweep]
        for label, _, marks in cells:
            if marks and not full:
                row.append({"status": "skipped", "message": f"{label}: slow (--full)"})
                continue
            out = cell(sweep, label)
            check_cell(out)
            row.append({"status": out["status"], "message": f"{label}: {out['message']}"})
        row += [{"status": "", "message": ""}] * (width - len(cells))
        rows.append(row)
    counts = {s: sum(1 for r in rows for c in r[1:] if c["status"] == s) for s in ("ok", "warn", "fail")}
    verification_record(case=CASE, metric="cells ok / warn / fail", value=[counts["ok"], counts["warn"],
                        counts["fail"]], tolerance=None, methods=("gfmd-fire",), passed=None,
                        tolerance_source="informational (each cell is asserted by test_extreme_cell)",
                        resolution={"subset": "full" if full else "CI"},
                        plots=[harness.grid_plot(["sweep"] + [str(i + 1) for i in range(width)], rows,
                                                 title="GFMD at the extremes: status, residual, iterations, time")])


# --------------------------------------------------------------------------- GFMD vs FE on layer cells
FE_BASE = {"material.thickness": BASE["surface.length"], "loading.final_penetration": 2e-9, "loading.steps": 20,
           "output.field_steps": 4}
# label -> (overrides, measured N = 256 differences (p, t_n) of the module docstring, slow)
FE_CELLS = {
    "ν = 0": ({"material.poisson_ratio": 0.0}, (3.2e-3, 3.8e-3), False),
    "ν = 0.45": ({}, (1.2e-2, 1.3e-2), False),
    "ν = 0.4999": ({"material.poisson_ratio": 0.4999}, (3.4e-2, 3.0e-2), False),
    "φn* = 1e-3": ({"interface.phi_n_star": 1e-3}, (1.4e-4, 3.3e-4), False),
    "φn* = 1": ({"interface.phi_n_star": 1.0}, (8.4e-3, 3.1e-2), True),
    "c = 0.5, ν = 0.3": ({"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3}, (4.3e-3, 5.5e-3), False),
}
FE_SOURCE = ("GFMD–FE study in the verification/test_extremes.py docstring (N = 256 → 512, order ≈ 2.3): "
             "bound = 3 × (N = 256 value) × (256/N)²; |Δa_rel| ≤ 4/N")
_FE_CACHE = {}


def fe_compare(label, n):
    """GFMD and FE (P2) on the same layer cell; differences over all steps / field steps."""
    if (label, n) in _FE_CACHE:
        return _FE_CACHE[label, n]
    overrides = FE_CELLS[label][0]
    sc = scene(**{**FE_BASE, **overrides, "surface.nodes": n})
    rf, rg, fe_s, gfmd_s = harness.run_fe_and_gfmd(sc)
    p = harness.curve_difference(rf, rg, "p")
    a = float(np.max(np.abs(rf.curve["a_rel"] - rg.curve["a_rel"])))
    tn = harness.field_difference(rf, rg, "t_n")
    out = {"p": p, "a": a, "tn": tn, "gfmd_s": gfmd_s, "fe_s": fe_s, "rg": rg, "rf": rf, "scene": sc}
    _FE_CACHE[label, n] = out
    return out


def _fe_params():
    for label, (_, _, is_slow) in FE_CELLS.items():
        for n in (256, 512):
            marks = (slow,) if is_slow or n > 256 else ()
            yield pytest.param(label, n, marks=marks, id=f"{label}|N={n}")


@pytest.mark.parametrize("label, n", list(_fe_params()))
def test_extreme_cell_gfmd_vs_fe(label, n, verification_record):
    out = fe_compare(label, n)
    e_p, e_tn = FE_CELLS[label][1]
    scale = 3 * (256 / n) ** 2
    rg, rf = out["rg"], out["rf"]
    fe_bad = [m for m in rf.messages if "not converged" in m]
    status = "ok" if out["p"] <= scale * e_p and out["tn"] <= scale * e_tn and out["a"] <= 4 / n + 1e-12 else "fail"
    message = (f"N = {n}: Δp {out['p']:.2g}, t_n L2 {out['tn']:.2g}, Δa_rel {out['a']:.2g}; GFMD {out['gfmd_s']:.2f} s, "
               f"FE {out['fe_s']:.1f} s" + (f"; FE: {fe_bad[0]}" if fe_bad else ""))
    print(f"\nFE cell {label}: {status}: {message}")
    _FE_GRID[label, n] = {"status": "warn" if fe_bad and status == "ok" else status, "message": message}
    res = {"N": n, "D/L": 1, "cell": label, "elements": "P2"}
    verification_record(case="extremes/gfmd-vs-fe", metric=f"{label}: p(δ) max diff / max|p|", value=out["p"],
                        tolerance=scale * e_p, methods=("gfmd-fire", "fe-p2"), tolerance_source=FE_SOURCE,
                        resolution=res, wall_s=out["gfmd_s"] + out["fe_s"], notes=message, scene=out["scene"],
                        plots=[harness.curve_plot(rg.curve["delta"], {"GFMD": rg.curve["p"], "FE": rf.curve["p"]},
                                                  xlabel="δ (m)", ylabel="p (Pa)", title=f"{label}, N = {n}",
                                                  difference=True)])
    verification_record(case="extremes/gfmd-vs-fe", metric=f"{label}: t_n relative L2", value=out["tn"],
                        tolerance=scale * e_tn, methods=("gfmd-fire", "fe-p2"), tolerance_source=FE_SOURCE,
                        resolution=res)
    assert rg.all_converged, rg.messages
    assert all(_SPECIFIC.search(m) for m in fe_bad), fe_bad
    assert out["p"] <= scale * e_p and out["tn"] <= scale * e_tn and out["a"] <= 4 / n + 1e-12, message


_FE_GRID = {}


def test_gfmd_vs_fe_grid(verification_record):
    """Colour-coded table of the GFMD–FE cells run in this session (runs after the cells: same module)."""
    if not _FE_GRID:
        pytest.skip("no GFMD–FE cell ran")
    sizes = sorted({n for _, n in _FE_GRID})
    rows = [[label] + [_FE_GRID.get((label, n), {"status": "skipped", "message": "slow (--full)"}) for n in sizes]
            for label in FE_CELLS]
    verification_record(case="extremes/gfmd-vs-fe", metric="cells", value=len(_FE_GRID), passed=None,
                        tolerance_source="informational", methods=("gfmd-fire", "fe-p2"),
                        plots=[harness.grid_plot(["layer cell (D = L)"] + [f"N = {n}" for n in sizes], rows,
                                                 title="GFMD vs FE (P2) at the extremes: differences and cost")])


# --------------------------------------------------------------------------- the δn/l threshold
def test_length_normal_resolution_threshold(verification_record):
    """The study behind contact.model.MIN_LENGTH_NORMAL_NODES (its docstring, φn* = 0.15, λs,H = 8 nm):
    the same continuum profile on N = 64 … 4096 (δn/l = 0.25 … 16), N = 4096 the reference.
    Bounds: for δn ≥ 2 l, |Δp|/max|p| ≤ 3 × 0.0022 and |Δa_rel| ≤ 3 × 0.0056 (the largest measured
    values of the contact.model table); at δn = l the pressure error must be > 3× the δn = 2 l one
    (measured 16×), i.e. the threshold separates two regimes."""
    from contact.model import MIN_LENGTH_NORMAL_NODES

    runs = {}
    for n in (64, 128, 256, 512, 1024, 2048, 4096):
        sc = scene(**{"surface.nodes": n, "surface.rollon_wavelength": 8e-9})
        runs[n] = gl.run_realization(sc)
        assert runs[n].all_converged, runs[n].messages
    ref = runs[4096].curve
    scale = np.max(np.abs(ref["p"]))
    rows, err = [], {}
    for n, r in runs.items():
        ratio = DN / (BASE["surface.length"] / n)
        dp = float(np.max(np.abs(r.curve["p"] - ref["p"])) / scale)
        da = float(np.max(np.abs(r.curve["a_rel"] - ref["a_rel"])))
        err[ratio] = (dp, da)
        flagged = any(w.startswith("under-resolved") for w in warnings_in(r.reasons))
        rows.append([f"{ratio:g}", n, dp, da, "warned" if flagged else ""])
        assert flagged == (ratio < MIN_LENGTH_NORMAL_NODES)
    print("\n" + "\n".join(str(r) for r in rows))
    resolved = [k for k in err if MIN_LENGTH_NORMAL_NODES <= k < 16]
    verification_record(case="extremes/length-normal-resolution", metric="max |Δp|/max|p| for δn ≥ 2 l",
                        value=max(err[k][0] for k in resolved), tolerance=3 * 0.0022,
                        methods=("gfmd-fire",), resolution={"N": list(runs), "reference N": 4096},
                        tolerance_source="3× the largest measured value (contact.model docstring)",
                        plots=[harness.table_plot(["δn/l", "N", "|Δp|/max|p|", "|Δa_rel|", "check"], rows,
                                                  title="error vs δn/l against N = 4096"),
                               harness.convergence_plot([1 / k for k in err if k < 16],
                                                        [err[k][0] for k in err if k < 16],
                                                        xlabel="l/δn", ylabel="|Δp|/max|p| vs N = 4096")])
    verification_record(case="extremes/length-normal-resolution", metric="max |Δa_rel| for δn ≥ 2 l",
                        value=max(err[k][1] for k in resolved), tolerance=3 * 0.0056, methods=("gfmd-fire",),
                        tolerance_source="3× the largest measured value (contact.model docstring)")
    assert all(err[k][0] <= 3 * 0.0022 and err[k][1] <= 3 * 0.0056 for k in resolved), err
    assert err[1.0][0] > 3 * err[2.0][0], err
