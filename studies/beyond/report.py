"""Beyond the seed: pull-off, hysteresis and the seed's nonlinearity against stickiness.

Reads the outputs of the studies in studies/beyond/ (`gfmd study run`): per study directory
`cycles.csv` (pull-off p̄ and hysteresis W per realization and cycle), `study.csv` (every realization's
steps: δ, p, a_rel, ḡ_r, and the stickiness diagnostics of its scene) and `summary.csv` (the branch of
every step), and `base_scene.toml` (E, ν). Writes a claims-style table (mean ± SE over the
realizations, SE = s/√n and, for effects, the delta-method SE of `gfmd_contact.app.claim_stats`).

* Pull-off p̄_po (MPa, < 0 tensile) and hysteresis W = ∮ p̄ dδ (mJ/m²) of cycle 0 per parameter set.
* The seed's nonlinearity (`gfmd_contact.app.claims.nonlinearity`, same definition) on the loading branch:
  NL = 2 a_rel(x_max/2)/a_rel(x_max) − 1, x = p_r* = p/(ḡ_r E*), x_max = p_r* at δ_eval (the
  largest δ every set of the study reached on loading, ≤ 20 nm); NL = 0 for a_rel ∝ p_r*. Its
  effect per adhesive set is ΔNL = NL(cohesive) − NL(hard wall of the same surface), paired by seed.
* Against the stickiness diagnostics of the adhesive set's scene (`gfmd_contact.core.stickiness`):
  Persson–Tosatti θ = U_el(full contact)/(w L) and the Tabor-like μ_rough (their 1+1-D forms,
  README "Stickiness"). The closing line gives Spearman's rank correlation of ΔNL with θ and with
  μ_rough over the distinct adhesive sets (a set that appears in two studies is counted once).

Run (after the three small studies; see README "Beyond the seed"):
    python studies/beyond/report.py studies/results/beyond_small
writes DIR/table.md and DIR/table.csv. `render(DIR)` returns the two texts (the test compares them
with the committed files).
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys
import tomllib
from pathlib import Path

import numpy as np

from gfmd_contact.app.claim_stats import difference, stats
from gfmd_contact.app.claims import at_level

STUDIES = ("fig3_cycle", "fig6a_cycle", "fig6b_cycle")
DELTA_SEED = 20e-9
PARAMS = (("interface.phi_n_star", "φn*"), ("surface.hurst", "H"), ("surface.h_rms", "h_rms (nm)"))


def _rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _float(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


def _e_star(study_dir):
    scene = tomllib.loads((study_dir / "base_scene.toml").read_text())
    m = scene["material"]
    return float(m["youngs_modulus"]) / (1.0 - float(m["poisson_ratio"]) ** 2)


def _scene_params(study_dir):
    """(hurst, h_rms) of the base scene: the values of sets that do not vary them."""
    s = tomllib.loads((study_dir / "base_scene.toml").read_text())["surface"]
    return float(s["hurst"]), float(s["h_rms"])


def load_study(study_dir):
    """Per set: its parameters, hard_wall, {seed: pull-off}, {seed: W}, per-seed loading curves, stickiness."""
    study_dir = Path(study_dir)
    e_star = _e_star(study_dir)
    hurst0, hrms0 = _scene_params(study_dir)
    branch = {(r["set"], r["step"]): r["branch"] for r in _rows(study_dir / "summary.csv")}
    sets = {}
    for r in _rows(study_dir / "study.csv"):
        s = sets.setdefault(r["set"], {
            "set": int(r["set"]), "hard_wall": r.get("interface.law") == "hard-wall",
            "phi": _float(r.get("interface.phi_n_star")), "hurst": _float(r.get("surface.hurst", hurst0)),
            "h_rms": _float(r.get("surface.h_rms", hrms0)), "curves": {}, "theta": {}, "mu": {},
            "pull_off": {}, "hysteresis": {}, "jumps": [0, 0]})
        seed = int(r["seed"])
        s["theta"][seed] = _float(r["stickiness_persson_tosatti"])
        s["mu"][seed] = _float(r["stickiness_tabor_rough"])
        if branch.get((r["set"], r["step"])) == "loading" and r["converged"] in ("1", "True"):
            c = s["curves"].setdefault(seed, {"delta": [], "pr": [], "a_rel": [], "p": []})
            p, g_r = _float(r["p"]), _float(r["g_r"])
            c["delta"].append(_float(r["delta"]))
            c["p"].append(p)
            c["a_rel"].append(_float(r["a_rel"]))
            c["pr"].append(p / (g_r * e_star) if p > 0 and g_r > 0 else math.nan)
    for r in _rows(study_dir / "cycles.csv"):
        if r["cycle"] == "0":
            s = sets[r["set"]]
            s["pull_off"][int(r["seed"])] = _float(r["pull_off_pressure"])
            s["hysteresis"][int(r["seed"])] = _float(r["hysteresis"])
            s["jumps"][0] += int(r["jump_in"])
            s["jumps"][1] += int(r["jump_out"])
    return [sets[k] for k in sorted(sets, key=int)]


def nonlinearity(curve, delta):
    """2 a_rel(x_max/2)/a_rel(x_max) − 1 of one loading curve (`gfmd_contact.app.claims.nonlinearity`)."""
    d = np.asarray(curve["delta"])
    if d.size == 0 or d.max() < delta - 1e-3 * abs(delta) - 1e-15:
        return math.nan
    k = int(np.argmin(np.abs(d - delta)))
    xmax, amax = curve["pr"][k], curve["a_rel"][k]
    if not (np.isfinite(xmax) and xmax > 0 and amax):
        return math.nan
    half = at_level(curve["pr"], curve["a_rel"], 0.5 * xmax)
    return 2 * half / amax - 1


def eval_delta(sets):
    """min(20 nm, the largest δ every realization of every set reached on loading)."""
    return min([DELTA_SEED] + [max(c["delta"]) for s in sets for c in s["curves"].values()])


def reference_of(s, sets):
    for r in sets:
        if r["hard_wall"] and r["hurst"] == s["hurst"] and r["h_rms"] == s["h_rms"]:
            return r
    return None


def _pm(m, se, n, scale=1.0, digits=3):
    if not np.isfinite(m):
        return "—"
    return f"{m * scale:.{digits}g} ± {se * scale:.2g} (n={n})"


def _mean(sample):
    v = [x for x in sample.values() if np.isfinite(x)]
    return float(np.mean(v)) if v else math.nan


def _spearman(x, y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size < 3:
        return math.nan
    rx, ry = np.argsort(np.argsort(x)), np.argsort(np.argsort(y))
    return float(np.corrcoef(rx, ry)[0, 1])


def table(root):
    """(rows, note): one row per parameter set of the studies under `root`, and the correlation line."""
    root = Path(root)
    rows, adhesive = [], {}
    for name in STUDIES:
        study_dir = root / f"{name}_small" if (root / f"{name}_small").is_dir() else root / name
        if not study_dir.is_dir():
            continue
        sets = load_study(study_dir)
        d = eval_delta(sets)
        nl = {s["set"]: {seed: nonlinearity(c, d) for seed, c in s["curves"].items()} for s in sets}
        for s in sets:
            ref = None if s["hard_wall"] else reference_of(s, sets)
            eff = difference(nl[s["set"]], nl[ref["set"]]) if ref else (math.nan, math.nan, 0)
            row = {"study": study_dir.name, "set": s["set"],
                   "law": "hard wall" if s["hard_wall"] else "cohesive",
                   "phi_n_star": "" if s["hard_wall"] else f"{s['phi']:g}", "hurst": f"{s['hurst']:g}",
                   "h_rms_nm": f"{s['h_rms'] * 1e9:g}", "delta_eval_nm": f"{d * 1e9:.4g}",
                   "pull_off": stats(s["pull_off"]), "hysteresis": stats(s["hysteresis"]),
                   "nl": stats(nl[s["set"]]), "dnl": eff, "jumps": s["jumps"],
                   "theta": _mean(s["theta"]), "mu_rough": _mean(s["mu"])}
            rows.append(row)
            if not s["hard_wall"] and np.isfinite(eff[0]):
                adhesive.setdefault((row["phi_n_star"], row["hurst"], row["h_rms_nm"]), row)
    uniq = list(adhesive.values())
    dnl = [r["dnl"][0] for r in uniq]
    rho_t = _spearman([r["theta"] for r in uniq], dnl)
    rho_m = _spearman([r["mu_rough"] for r in uniq], dnl)
    note = (f"Spearman rank correlation of ΔNL with θ over the {len(uniq)} distinct adhesive sets: "
            f"{rho_t:.2f}; with μ_rough: {rho_m:.2f}.")
    return rows, note


def _scale_line(root):
    """The grid and realizations of the studies' base scene; a warning unless it is the seed's N = 2^17."""
    dirs = sorted(p for p in Path(root).iterdir() if (p / "base_scene.toml").is_file())
    scene = tomllib.loads((dirs[0] / "base_scene.toml").read_text())
    n, r = scene["surface"]["nodes"], scene["surface"]["realizations"]
    steps = scene["loading"]["steps"]
    text = f"N = {n}, {r} realizations, steps per segment {steps}"
    if n < 131072:
        return (f"**Small scale ({text}): NOT the full-scale answer.** The full-scale studies "
                "(N = 2^17, 10 realizations) are studies/beyond/fig*_cycle.toml.")
    return f"Full scale ({text})."


def render(root):
    """(table.md text, table.csv text) of the studies under `root`."""
    rows, note = table(root)
    md = ["# Beyond the seed: pull-off, hysteresis and the seed's nonlinearity vs stickiness", "",
          "Written by `studies/beyond/report.py` from the committed `cycles.csv`, `study.csv` and `summary.csv`",
          f"under `{Path(root).name}/`. Mean ± SE over the realizations (n); ΔNL: NL(cohesive) − NL(hard wall",
          "of the same surface), paired by seed, delta-method SE (`gfmd_contact.app.claim_stats`). p̄_po: most tensile",
          "p̄ on unloading (MPa, < 0 tensile); W = ∮ p̄ dδ (mJ/m²); jumps: summed over the realizations; NL = 2 a_rel(x_max/2)/a_rel(x_max) − 1 on the",
          "loading branch, x = p_r*, x_max at δ_eval; θ: Persson–Tosatti U_el(full contact)/(wL); μ_rough: Tabor-like.",
          "", _scale_line(root), "",
          "| study | law | φn* | H | h_rms (nm) | δ_eval (nm) | p̄_po (MPa) | W (mJ/m²) | jumps in/out | NL | ΔNL vs hard wall | θ | μ_rough |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['study']} | {r['law']} | {r['phi_n_star'] or '—'} | {r['hurst']} | {r['h_rms_nm']} | "
                  f"{r['delta_eval_nm']} | {_pm(*r['pull_off'], scale=1e-6)} | {_pm(*r['hysteresis'], scale=1e3)} | "
                  f"{r['jumps'][0]}/{r['jumps'][1]} | "
                  f"{_pm(*r['nl'])} | {_pm(*r['dnl'])} | "
                  f"{'—' if not np.isfinite(r['theta']) else format(r['theta'], '.3g')} | "
                  f"{'—' if not np.isfinite(r['mu_rough']) else format(r['mu_rough'], '.3g')} |")
    md += ["", note, ""]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["study", "set", "law", "phi_n_star", "hurst", "h_rms_nm", "delta_eval_nm",
                "pull_off_MPa", "pull_off_se", "hysteresis_mJ_m2", "hysteresis_se", "n", "jump_in", "jump_out",
                "nonlinearity", "nonlinearity_se", "dnl", "dnl_se", "theta", "mu_rough"])
    for r in rows:
        w.writerow([r["study"], r["set"], r["law"], r["phi_n_star"], r["hurst"], r["h_rms_nm"], r["delta_eval_nm"],
                    f"{r['pull_off'][0] * 1e-6:.6g}", f"{r['pull_off'][1] * 1e-6:.6g}",
                    f"{r['hysteresis'][0] * 1e3:.6g}", f"{r['hysteresis'][1] * 1e3:.6g}", r["pull_off"][2],
                    r["jumps"][0], r["jumps"][1],
                    f"{r['nl'][0]:.6g}", f"{r['nl'][1]:.6g}", f"{r['dnl'][0]:.6g}", f"{r['dnl'][1]:.6g}",
                    f"{r['theta']:.6g}", f"{r['mu_rough']:.6g}"])
    return "\n".join(md), buf.getvalue()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("root", type=Path, help="directory holding the studies' output directories")
    args = ap.parse_args(argv)
    md, tab = render(args.root)
    (args.root / "table.md").write_text(md)
    (args.root / "table.csv").write_text(tab)
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
