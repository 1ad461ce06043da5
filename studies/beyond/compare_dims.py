"""The seed's claims in 1+1-D and 2+1-D side by side: effect sizes of two Fig. 3 studies.

Reads two study directories (`gfmd study run` outputs: study.csv, base_scene.toml, …): a 1+1-D one (e.g.
studies/seed/fig3_small.toml) and a 2+1-D one (studies/beyond/fig3_2d_small.toml), measures the seed's
claims on each with `gfmd_contact.app.claims.evaluate` (the same definitions, mean ± SE over the realizations,
delta-method SE for effects; `gfmd study report` prints the same numbers one study at a time) and writes
one row per claim with the two effect sizes and verdicts:

* κ (Fig. 2): a_rel = κ p/(ḡ_r E*) of the hard wall at 0 < a_rel ≤ 0.1 (ḡ_r: seed Eq. 6; in 2+1-D its
  four-neighbour form);
* nonlinearity (Fig. 3a): NL = 2 a_rel(x/2)/a_rel(x) − 1, x = p_r* at δ_eval; effect NL(largest φn*) −
  NL(smallest φn*);
* ΔNL vs the hard wall: NL(largest φn*) − NL(hard wall of the same surfaces), paired by seed (the
  effect of adhesion itself, as studies/beyond/report.py's ΔNL);
* a_rel at p < 0 (Fig. 3b): the largest a_rel at tensile mean pressure, smallest over the adhesive sets;
* p(δ) (Fig. 4a): the largest |p/p_hard wall − 1| over φn* at δ_eval;
* and, for context, a_rel(δ) (Fig. 4b) and ḡ_r/ḡ (Fig. 4c).

    python studies/beyond/compare_dims.py DIR_1D DIR_2D [--out DIR]

writes DIR/claims_1d_vs_2d.md and .csv (default DIR: the parent of DIR_2D). `render(d1, d2)` returns both.
"""

from __future__ import annotations

import argparse
import csv
import io
import sys
import tomllib
from pathlib import Path

from gfmd_contact.app.claims import _phi_family, eval_delta, evaluate, nonlinearity, read_study_dir, seeded
from gfmd_contact.app.claim_stats import difference

ROWS = (("kappa", "κ (hard wall, 0 < a_rel ≤ 0.1)"),
        ("nonlinearity", "nonlinearity NL(φn* max) − NL(φn* min)"),
        ("adhesive-branch", "a_rel at p < 0 (smallest over adhesive sets)"),
        ("pressure-delta", "p(δ): max |p/p_hw − 1| over φn*"),
        ("area-delta", "a_rel(δ) (Fig. 4b effect)"),
        ("gr-over-g", "ḡ_r/ḡ (Fig. 4c effect)"))


def _scale(d):
    s = tomllib.loads((Path(d) / "base_scene.toml").read_text())["surface"]
    n = f"{s['nodes']} × {s['nodes_y']}" if s.get("nodes_y") else f"{s['nodes']}"
    return f"N = {n}, {s['realizations']} realizations"


def _claims(d):
    return {r.id: r for r in evaluate(read_study_dir(d))}


def _adhesion_effect(d):
    """(ΔNL, SE, n, details): NL(largest φn*) − NL(hard wall) at the nonlinearity claim's δ_eval."""
    fams = _phi_family(read_study_dir(d).with_data, ("interface.law", "interface.phi_n_star"))
    fam = fams[0] if fams else []
    if len(fam) < 2 or not fam[0].hard_wall:
        return None
    delta = eval_delta(fam)
    top = fam[-1]
    m, se, n = difference(seeded(top, nonlinearity(top, delta)), seeded(fam[0], nonlinearity(fam[0], delta)))
    return m, se, n, f"φn* = {top.value('interface.phi_n_star'):g} vs hard wall at δ = {delta * 1e9:.3g} nm"


def _cells(result):
    if result is None or not result.measurements:
        return "—", "", "not in this study", ""
    m = result.measurements[0]
    return f"{m.value:.4g}", f"{m.se:.2g}", m.verdict, m.details


def rows(dir_1d, dir_2d):
    c1, c2 = _claims(dir_1d), _claims(dir_2d)
    out = []
    for cid, label in ROWS:
        v1, se1, verdict1, det1 = _cells(c1.get(cid))
        v2, se2, verdict2, det2 = _cells(c2.get(cid))
        out.append({"claim": cid, "quantity": label, "value_1d": v1, "se_1d": se1, "verdict_1d": verdict1,
                    "value_2d": v2, "se_2d": se2, "verdict_2d": verdict2, "details_1d": det1, "details_2d": det2})
        if cid == "nonlinearity":
            cells = []
            for d in (dir_1d, dir_2d):
                e = _adhesion_effect(d)
                cells.append(("—", "", "not in this study", "") if e is None else
                             (f"{e[0]:.4g}", f"{e[1]:.2g}", f"n = {e[2]} (not a seed claim)", e[3]))
            (v1, se1, verdict1, det1), (v2, se2, verdict2, det2) = cells
            out.append({"claim": "nonlinearity-vs-hard-wall", "quantity": "ΔNL = NL(φn* max) − NL(hard wall)",
                        "value_1d": v1, "se_1d": se1, "verdict_1d": verdict1, "value_2d": v2, "se_2d": se2,
                        "verdict_2d": verdict2, "details_1d": det1, "details_2d": det2})
    return out


def render(dir_1d, dir_2d):
    """(markdown text, csv text) of the side-by-side table."""
    table = rows(dir_1d, dir_2d)
    md = ["# The seed's claims: 1+1-D vs 2+1-D (effect sizes side by side)", "",
          "Written by `studies/beyond/compare_dims.py` with `gfmd_contact.app.claims.evaluate` (definitions: `gfmd study report`).",
          f"1+1-D: `{Path(dir_1d).name}/` ({_scale(dir_1d)}); 2+1-D: `{Path(dir_2d).name}/` ({_scale(dir_2d)}).",
          "Mean ± SE over the realizations; effects with the delta-method SE; verdicts at 2 SE. SMALL scale: NOT the",
          "full-scale answer (studies/seed/fig3.toml, studies/beyond/fig3_2d.toml).", "",
          "| claim | quantity | 1+1-D | verdict | 2+1-D | verdict |", "|---|---|---|---|---|---|"]
    for r in table:
        a = f"{r['value_1d']} ± {r['se_1d']}" if r["se_1d"] else r["value_1d"]
        b = f"{r['value_2d']} ± {r['se_2d']}" if r["se_2d"] else r["value_2d"]
        md.append(f"| {r['claim']} | {r['quantity']} | {a} | {r['verdict_1d']} | {b} | {r['verdict_2d']} |")
    md += ["", "Per set (the claims' details):", ""]
    for r in table:
        md.append(f"- **{r['claim']}** — 1+1-D: {r['details_1d'] or '—'}; 2+1-D: {r['details_2d'] or '—'}")
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(table[0]), lineterminator="\n")
    w.writeheader()
    w.writerows(table)
    return "\n".join(md) + "\n", buf.getvalue()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir_1d")
    ap.add_argument("dir_2d")
    ap.add_argument("--out", default=None, help="folder of claims_1d_vs_2d.md/.csv (default: DIR_2D's parent)")
    a = ap.parse_args(argv)
    out = Path(a.out) if a.out else Path(a.dir_2d).resolve().parent
    md, text = render(a.dir_1d, a.dir_2d)
    (out / "claims_1d_vs_2d.md").write_text(md)
    (out / "claims_1d_vs_2d.csv").write_text(text)
    sys.stdout.write(md)


if __name__ == "__main__":
    main()
