"""Stability at the extremes: one-parameter sweeps around a base scene, plus corners.

Base scene: `verification.scenes.extremes_base` (cohesive self-affine, L = 256 nm, N = 512, δn = 1 nm
= 2 l, φn* = 0.15, half-plane ν = 0.45, δ0 = 8 δn, δ from −8 nm to 4 nm in 24 steps, FIRE 1e-8).
Each sweep (`SWEEPS`) changes one parameter, the corners several: δn/l by N at fixed physics, δ0
at fixed ΔU, N at fixed l with L = N·l, λr = L/8 (the seed's ratio), h_rms = 10 nm.

Three parts:
* sweep cells (`run_cell`): one load ramp each; status ok (all steps converged, no warning), warn
  (all converged, a check of `gfmd_contact.core.model.scene_warnings` / `gfmd_contact.core.loading.start_warning`
  fired) or fail (refused with a specific message, or a step did not converge);
* GFMD vs FE P2 on layer cells (`fe_compare`): the base scene on a layer D = L, δ from −8 nm to
  2 nm in 20 steps, N = 256 (CI) and 512; Δp = max|p_FE − p_GFMD|/max|p|, t_n L2 over the field steps;
* the δn/l resolution threshold (`threshold_study`, behind `gfmd_contact.core.model.MIN_LENGTH_NORMAL_NODES`):
  one continuum profile (λs,H = 8 or 32 nm, φn* = 0.15 or 0.01) on N = 64 … 4096 (δn/l = 0.25 … 16),
  N = 4096 the reference; max over the steps of |Δp|/max|p| and |Δa_rel|.

    python -m verification.studies.extremes [--full] [--part sweep|fe|threshold …] [--only TEXT] [--write]

runs the CI subset (`--full`: the slow cells too; `--only`: the entries whose key contains TEXT) and
with `--write` stores the results in verification/data/extremes.json (entries "cell/…", "fe/…",
"threshold/…"), from which test_extremes.py takes the measured N = 256 GFMD–FE differences and the
threshold errors that its bounds are derived from.
"""

from __future__ import annotations

import argparse
import re
import time

import numpy as np

from gfmd_contact.core.model import warnings_in
from verification import measured, metrics
from verification.runs import fe_vs_gfmd
from verification.scenes import EXTREMES_BASE, extremes_base

NAME = "extremes"
DN = 1e-9  # δn of the base scene (m)
STEP = 0.5e-9  # ΔU (m)


def _n_at_spacing(n, spacing=0.5e-9):
    """N-sweep: L = N·l, λr = L/8, h_rms = 10 nm, λs,H = 4 nm."""
    length = n * spacing
    return {"surface.nodes": n, "surface.length": length, "surface.rolloff_wavelength": length / 8,
            "surface.h_rms": 10e-9}


def _d0(ratio):
    return {"loading.initial_separation": ratio * DN,
            "loading.steps": int(round((ratio * DN + EXTREMES_BASE["loading.final_penetration"]) / STEP))}


def _nodes_for(ratio):
    return {"surface.nodes": int(round(EXTREMES_BASE["surface.length"] / (DN / ratio)))}


COUPLED = {"interface.tangential_ratio": 0.5}
LAYER = {"material.thickness": EXTREMES_BASE["surface.length"]}
#: sweep name -> [(cell label, overrides, slow)]
SWEEPS = {
    "ν (c = 0.5, half-plane)": [(f"ν = {v:g}", {**COUPLED, "material.poisson_ratio": v}, False)
                                for v in (0.0, 0.3, 0.45, 0.49, 0.499, 0.4999, 0.5)],
    "ν (c = 0.5, layer D = L)": [(f"ν = {v:g}", {**COUPLED, **LAYER, "material.poisson_ratio": v}, False)
                                 for v in (0.0, 0.3, 0.45, 0.49, 0.499, 0.4999, 0.5)],
    "φn*": [(f"φn* = {v:g}", {"interface.phi_n_star": v}, False) for v in (1e-4, 1e-3, 0.01, 0.15, 0.5, 1.0)],
    "δn/l (N at fixed L)": [(f"δn/l = {v:g}", _nodes_for(v), False) for v in (0.5, 1, 2, 8, 32)],
    "H": [(f"H = {v:g}", {"surface.hurst": v}, False) for v in (0.1, 0.2, 0.5, 0.8, 0.95)],
    "δ0/δn": [(f"δ0 = {v:g} δn", _d0(v), False) for v in (0, 1, 2, 4, 8, 10)],
    "N (l = δn/2, L = N l)": [(f"N = 2^{k}", _n_at_spacing(2**k), k > 12) for k in (9, 12, 15)]
    + [("N = 2^18, 6 steps", {**_n_at_spacing(2**18), "loading.steps": 6, "solver.max_iterations": 20000}, True)],
    "corners": [
        ("ν = 0.4999, φn* = 1, δ0 = 0, c = 0.5", {**COUPLED, "material.poisson_ratio": 0.4999,
                                                "interface.phi_n_star": 1.0, **_d0(0)}, False),
        ("layer ν = 0.4999, φn* = 1, c = 0.5", {**COUPLED, **LAYER, "material.poisson_ratio": 0.4999,
                                               "interface.phi_n_star": 1.0}, False),
        ("H = 0.1, φn* = 1, δn/l = 0.5", {"surface.hurst": 0.1, "interface.phi_n_star": 1.0,
                                          **_nodes_for(0.5)}, False),
        ("H = 0.95, φn* = 1e-4, ν = 0", {"surface.hurst": 0.95, "interface.phi_n_star": 1e-4,
                                         "material.poisson_ratio": 0.0}, False),
        ("ν = 0.5, c = 0.5, φn* = 1, δn/l = 32", {**COUPLED, "material.poisson_ratio": 0.5,
                                                  "interface.phi_n_star": 1.0, **_nodes_for(32)}, False),
    ],
}

_SPECIFIC = re.compile(r"(surface|material|interface|loading|solver)\.\w+|residual")
_FIELD_CHECKED = ("u_z", "u_x", "gap", "t_n", "t_t")


def names_a_key(message):
    """Whether a failure message names the scene key or the residual it is about."""
    return bool(_SPECIFIC.search(message))


# ----------------------------------------------------------------------------- sweep cells
def verdict(nan, converged, messages, warnings, numbers):
    """{"status", "message"} of a run: fail on a NaN or a non-converged step (its first message), warn on
    the model's warnings, else ok; `numbers` (the run's counts, as text) in every message."""
    if nan:
        return dict(status="fail", message="NaN in the result: " + numbers)
    if not converged.all():
        return dict(status="fail", message=f"{messages[0]} ({len(messages)} steps); {numbers}")
    if warnings:
        return dict(status="warn", message=f"{numbers}; " + " | ".join(warnings))
    return dict(status="ok", message=numbers)


def run_cell(overrides):
    """Run one cell; a dict with status, message and the numbers (never raises for scene errors)."""
    from gfmd_contact.app.methods import run_realization
    t0 = time.perf_counter()
    sc = None
    try:
        sc = extremes_base(**overrides)
        result = run_realization(sc)
    except ValueError as exc:  # SceneError, ModelCheckError, full-contact refusal: all ValueError
        return {"status": "refused", "message": f"refused: {exc}", "refused": True, "wall_s": time.perf_counter() - t0,
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
    out = {"refused": False, "scene": sc, "wall_s": wall, "nan": nan, "residual_ok": residual_ok,
           "steps": int(conv.size), "iterations": int(np.sum(c["iterations"])), "residual": float(np.max(residual)),
           "model": result.model, "warnings": warnings, "messages": list(result.messages),
           "p": np.asarray(c["p"]), "a_rel": np.asarray(c["a_rel"]), "delta": np.asarray(c["delta"])}
    numbers = (f"{conv.sum()}/{conv.size} steps, max residual {out['residual']:.2g} p_ref, "
               f"{out['iterations']} iterations, {wall:.2f} s")
    out.update(verdict(nan, conv, result.messages, warnings, numbers))
    return out


_CELLS = {}


def overrides_of(sweep, label):
    return dict(next(o for lab, o, _ in SWEEPS[sweep] if lab == label))


def cell(sweep, label):
    """run_cell of one sweep cell, cached per process."""
    key = (sweep, label)
    if key not in _CELLS:
        _CELLS[key] = run_cell(overrides_of(sweep, label))
    return _CELLS[key]


def cell_entry(sweep, label, out):
    return measured.make_entry({k: out[k] for k in ("status", "message", "steps", "iterations", "residual",
                                                    "wall_s")},
                               scene="verification.scenes.extremes_base(**overrides)",
                               overrides=overrides_of(sweep, label))


# ----------------------------------------------------------------------------- GFMD vs FE on layer cells
FE_BASE = {"material.thickness": EXTREMES_BASE["surface.length"], "loading.final_penetration": 2e-9,
           "loading.steps": 20, "output.field_steps": 4}
#: label -> (overrides, slow)
FE_CELLS = {
    "ν = 0": ({"material.poisson_ratio": 0.0}, False),
    "ν = 0.45": ({}, False),
    "ν = 0.4999": ({"material.poisson_ratio": 0.4999}, False),
    "φn* = 1e-3": ({"interface.phi_n_star": 1e-3}, False),
    "φn* = 1": ({"interface.phi_n_star": 1.0}, True),
    "c = 0.5, ν = 0.3": ({"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3}, False),
}
FE_SIZES = (256, 512)  # 512: slow
_FE = {}


def fe_scene(label, n):
    return extremes_base(**{**FE_BASE, **FE_CELLS[label][0], "surface.nodes": n})


def fe_compare(label, n):
    """GFMD and FE (P2) on one layer cell, cached: runs.fe_vs_gfmd's dict plus "scene" and "fe_failures"
    (the FE messages of unconverged steps; FE may fail where GFMD converges)."""
    if (label, n) not in _FE:
        sc = fe_scene(label, n)
        out = fe_vs_gfmd(sc, check=False)
        out.update(scene=sc, fe_failures=[m for m in out["rf"].messages if "not converged" in m])
        _FE[label, n] = out
    return _FE[label, n]


def fe_key(label, n):
    return f"fe/{label}/N={n}"


def fe_entry(label, n, out):
    return measured.make_entry({"p": out["p"], "t_n": out["tn"], "a_rel": out["a"], "gfmd_s": out["gfmd_s"],
                                "fe_s": out["fe_s"], "fe_failures": out["fe_failures"]},
                               scene="verification.scenes.extremes_base(**FE_BASE, **overrides, surface.nodes=N)",
                               FE_BASE=FE_BASE, overrides=FE_CELLS[label][0], N=n)


def measured_fe(label, n=256):
    """The stored (Δp, t_n L2) of one layer cell at N (verification/data/extremes.json)."""
    values = measured.entry(NAME, fe_key(label, n))["values"]
    return values["p"], values["t_n"]


# ----------------------------------------------------------------------------- δn/l resolution threshold
THRESHOLD_NODES = (64, 128, 256, 512, 1024, 2048, 4096)  # the last one is the reference
THRESHOLD_CASES = {
    "φn* = 0.15, λs = 8 nm": {"interface.phi_n_star": 0.15, "surface.rollon_wavelength": 8e-9},
    "φn* = 0.01, λs = 8 nm": {"interface.phi_n_star": 0.01, "surface.rollon_wavelength": 8e-9},
    "φn* = 0.15, λs = 32 nm": {"interface.phi_n_star": 0.15, "surface.rollon_wavelength": 32e-9},
    "φn* = 0.01, λs = 32 nm": {"interface.phi_n_star": 0.01, "surface.rollon_wavelength": 32e-9},
}
_THRESHOLD = {}


def threshold_study(case):
    """The case's profile on every N of THRESHOLD_NODES, against the finest (cached): {"ratio" δn/l,
    "N", "dp" max|Δp|/max|p|, "da" max|Δa_rel|, "warned" (an under-resolved warning), "wall_s"}."""
    if case not in _THRESHOLD:
        from gfmd_contact.app.methods import run_realization
        t0 = time.perf_counter()
        runs = {}
        for n in THRESHOLD_NODES:
            runs[n] = run_realization(extremes_base(**{"surface.nodes": n, **THRESHOLD_CASES[case]}))
            assert runs[n].all_converged, (case, n, runs[n].messages)
        ref = runs[THRESHOLD_NODES[-1]].curve
        scale = np.max(np.abs(ref["p"]))
        out = {"ratio": [], "N": [], "dp": [], "da": [], "warned": []}
        for n, r in runs.items():
            out["ratio"].append(DN / (EXTREMES_BASE["surface.length"] / n))
            out["N"].append(n)
            out["dp"].append(float(np.max(np.abs(r.curve["p"] - ref["p"])) / scale))
            out["da"].append(float(np.max(np.abs(r.curve["a_rel"] - ref["a_rel"]))))
            out["warned"].append(any(w.startswith("under-resolved") for w in warnings_in(r.reasons)))
        out["wall_s"] = time.perf_counter() - t0
        _THRESHOLD[case] = out
    return _THRESHOLD[case]


def threshold_entry(case, out):
    return measured.make_entry({k: out[k] for k in ("ratio", "N", "dp", "da", "warned")},
                               scene="verification.scenes.extremes_base(**overrides, surface.nodes=N)",
                               overrides=THRESHOLD_CASES[case], reference_N=THRESHOLD_NODES[-1],
                               wall_s=out["wall_s"])


def resolved_worst(values, min_ratio):
    """(max |Δp|/max|p|, max |Δa_rel|) over min_ratio ≤ δn/l < that of the reference."""
    ok = [i for i, r in enumerate(values["ratio"]) if min_ratio <= r < values["ratio"][-1]]
    return metrics.worst(values["dp"][i] for i in ok), metrics.worst(values["da"][i] for i in ok)


def measured_threshold_worst(min_ratio):
    """(Δp, Δa_rel, keys): the largest resolved errors over every stored threshold case."""
    entries = {k: e for k, e in measured.load(NAME)["entries"].items() if k.startswith("threshold/")}
    if len(entries) < len(THRESHOLD_CASES):
        measured.entry(NAME, "threshold/" + next(c for c in THRESHOLD_CASES if "threshold/" + c not in entries))
    worst = [resolved_worst(e["values"], min_ratio) for e in entries.values()]
    return metrics.worst(w[0] for w in worst), metrics.worst(w[1] for w in worst), sorted(entries)


# ----------------------------------------------------------------------------- command line
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="the slow cells too (N = 2^18 alone takes ~15 min)")
    ap.add_argument("--part", nargs="*", choices=("sweep", "fe", "threshold"), default=None,
                    help="which parts (default: all three)")
    ap.add_argument("--only", default="", help="only the entries whose key contains this text")
    ap.add_argument("--write", action="store_true", help="store the results in verification/data/extremes.json")
    args = ap.parse_args(argv)
    parts = args.part or ("sweep", "fe", "threshold")
    entries = {}

    def wanted(key, slow):
        return args.only in key and (args.full or not slow)

    if "sweep" in parts:
        for sweep, cells in SWEEPS.items():
            for label, _, slow in cells:
                key = f"cell/{sweep} | {label}"
                if wanted(key, slow):
                    out = cell(sweep, label)
                    print(f"{key}: {out['status']}: {out['message']}", flush=True)
                    entries[key] = cell_entry(sweep, label, out)
    if "fe" in parts:
        for label, (_, slow) in FE_CELLS.items():
            for n in FE_SIZES:
                key = fe_key(label, n)
                if wanted(key, slow or n > FE_SIZES[0]):
                    out = fe_compare(label, n)
                    print(f"{key}: Δp {out['p']:.3g}, t_n L2 {out['tn']:.3g}, Δa_rel {out['a']:.3g}; "
                          f"GFMD {out['gfmd_s']:.2f} s, FE {out['fe_s']:.1f} s {out['fe_failures'][:1]}", flush=True)
                    entries[key] = fe_entry(label, n, out)
    if "threshold" in parts:
        for case in THRESHOLD_CASES:
            key = f"threshold/{case}"
            if wanted(key, False):
                out = threshold_study(case)
                print(f"{key}: δn/l {[f'{r:g}' for r in out['ratio']]}  |Δp|/max|p| "
                      f"{[f'{v:.2g}' for v in out['dp']]}  |Δa_rel| {[f'{v:.2g}' for v in out['da']]}  "
                      f"({out['wall_s']:.1f} s)", flush=True)
                entries[key] = threshold_entry(case, out)
    if args.write and entries:
        print(measured.write(NAME, entries, description="extremes: sweep cells (status, iterations, time), GFMD vs "
                                                        "FE P2 on layer cells, δn/l resolution threshold"))


if __name__ == "__main__":
    main()
