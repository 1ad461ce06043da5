"""How much the cohesive length δn decides p(δ) and a_rel of adhesive runs.

δn = 1 nm (interface.length_normal) is this project's choice, not the seed paper's.
Together with the contact rule (a node counts as in contact while its gap is at most
Δtol, where T_n(Δtol) = contact_tolerance·φn/δn on the decaying branch: Δtol ≈ 9.1 δn
at tolerance 1e-3, `gfmd_contact.core.laws.contact_gap_threshold`) it sets the measured a_rel and
p/E*. This script runs the default scene's geometry (gfmd_contact/core/default_scene.toml:
self-affine H = 0.8, h_rms = 10 nm, L = 1.28 µm, λr = 160 nm, λs = 2.5 nm, ν = 0.45,
half-plane) for φn* ∈ {0.001, 0.01, 0.05, 0.15} and the hard wall, at δn = 1 nm
(N = 4096, the default) and δn = 0.25 nm (N = 16384: δn/l = 3.2 in both, above the
resolution threshold δn ≥ 2 l of `gfmd_contact.core.model`). The profile is the same continuum
profile in both grids (seed Eq. 4 amplitudes, the same random phases), so the hard
wall is run at both N, and δn = 1 nm also at N = 16384 (`--no-fine-1nm` skips it) to
separate the grid from δn. Every run starts at δ0 = 8 nm (outside the jump-in
separation of every case: at most 6.6 nm, `gfmd_contact.core.model.jump_in_separation`) and goes to
δ = 20 nm in steps of ΔU = 0.5 nm (δ = 10 and 20 nm are on the grid; ΔU = 0.25 nm,
`--step 0.25`, gave the same values to the 4–5 digits reported). For the hard wall the
script also counts its nodes with the cohesive rule, gap ≤ Δtol(δn), to show how much
of the cohesive a_rel is the counting rule rather than adhesion.

Writes studies/results/delta_n_effect.csv (one row per case, realization and δ; the
mean over realizations as realization "mean") and studies/results/delta_n_effect.md
(tables, scene, code version, timings). Run: python studies/delta_n_effect.py
"""

from __future__ import annotations

import argparse
import csv
import platform
import time
from pathlib import Path

import numpy as np

from gfmd_contact.app.io import code_version
from gfmd_contact.core.laws import contact_gap_threshold
from gfmd.loading import run_realization
from gfmd_contact.core.model import build_model, softest_normal_stiffness
from gfmd_contact.core.scene import default_scene, scene_to_toml

HERE = Path(__file__).resolve().parent
PHIS = (0.001, 0.01, 0.05, 0.15)
DELTAS_NM = (10.0, 20.0)  # δ at which p/E* and a_rel are reported (nm)


def case_scene(law, phi, dn, nodes, args):
    """The default scene with the study's interface, grid and loading."""
    d0 = args.initial_separation * 1e-9
    final = max(DELTAS_NM) * 1e-9
    steps = int(round((d0 + final) / (args.step * 1e-9)))
    return default_scene().replace(**{
        "interface.law": law, "interface.phi_n_star": phi, "interface.length_normal": dn,
        "surface.nodes": nodes, "surface.realizations": args.realizations,
        "loading.initial_separation": d0, "loading.final_penetration": final, "loading.steps": steps,
        "output.field_steps": steps})  # every step's fields: the hard wall's gaps are counted below


def cases(args):
    """(label, law, φn*, δn (m), N) of every run."""
    out = []
    for nodes in (4096, 16384):
        out.append(("hard wall", "hard-wall", PHIS[0], 1e-9, nodes))
        for dn in (1e-9, 0.25e-9):
            if dn == 1e-9 and nodes == 16384 and not args.fine_1nm:
                continue
            if dn == 0.25e-9 and nodes == 4096:
                continue  # δn = 0.8 l: under-resolved
            out += [(f"φn* = {phi:g}", "cohesive", phi, dn, nodes) for phi in PHIS]
    return out


def value_at(curve, name, delta):
    """The curve's value at the step whose δ equals `delta` (m) to round-off."""
    k = int(np.argmin(np.abs(curve["delta"] - delta)))
    if abs(curve["delta"][k] - delta) > 1e-15:
        raise ValueError(f"δ = {delta:g} m is not on the load grid (closest {curve['delta'][k]:g} m)")
    return float(curve[name][k])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--realizations", type=int, default=2, help="realizations (seeds 1, 2, ...), default 2")
    parser.add_argument("--step", type=float, default=0.5, help="ΔU (nm), default 0.5")
    parser.add_argument("--initial-separation", type=float, default=8.0, help="δ0 (nm), default 8")
    parser.add_argument("--no-fine-1nm", dest="fine_1nm", action="store_false",
                        help="skip δn = 1 nm at N = 16384")
    parser.add_argument("--only", help="run only the cases whose label contains this text (for timing)")
    parser.add_argument("--out", type=Path, default=HERE / "results", help="output folder")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)

    rows, summary, timings = [], [], []
    start_all, cpu_all = time.perf_counter(), time.process_time()
    for label, law, phi, dn, nodes in cases(args):
        if args.only and args.only not in f"{label} δn={dn * 1e9:g} N={nodes}":
            continue
        scene = case_scene(law, phi, dn, nodes, args)
        e_star = scene.material.contact_modulus
        model = build_model(scene, None)
        jump = model.law.jump_in_separation(softest_normal_stiffness(model))
        per = {d: {"p": [], "a": [], "a_tol": {dn_: [] for dn_ in (1e-9, 0.25e-9)}} for d in DELTAS_NM}
        wall0, cpu0 = time.perf_counter(), time.process_time()
        warnings, unconverged = set(), 0
        for i in range(scene.surface.realizations):
            result = run_realization(scene, i)
            warnings |= {r for r in result.reasons if r.startswith("WARNING")}
            unconverged += int(np.sum(result.curve["converged"] == 0))
            for d in DELTAS_NM:
                p = value_at(result.curve, "p", d * 1e-9) / e_star
                a = value_at(result.curve, "a_rel", d * 1e-9)
                per[d]["p"].append(p)
                per[d]["a"].append(a)
                if law == "hard-wall":  # the same solution counted with the cohesive rule gap ≤ Δtol(δn)
                    k = int(np.argmin(np.abs(result.curve["delta"] - d * 1e-9)))
                    gap = result.fields[k]["gap"]
                    for dn_ in per[d]["a_tol"]:
                        limit = contact_gap_threshold(scene.interface.contact_tolerance, dn_)
                        per[d]["a_tol"][dn_].append(float(np.mean(gap <= limit)))
                rows.append({"case": label, "law": law, "phi_n_star": phi if law == "cohesive" else "",
                             "delta_n_nm": dn * 1e9 if law == "cohesive" else "", "nodes": nodes,
                             "realization": i, "seed": scene.surface.seed + i, "delta_nm": d,
                             "p_over_Estar": p, "a_rel": a})
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
        for d in DELTAS_NM:
            rows.append({"case": label, "law": law, "phi_n_star": phi if law == "cohesive" else "",
                         "delta_n_nm": dn * 1e9 if law == "cohesive" else "", "nodes": nodes,
                         "realization": "mean", "seed": "", "delta_nm": d,
                         "p_over_Estar": float(np.mean(per[d]["p"])), "a_rel": float(np.mean(per[d]["a"]))})
        summary.append({"label": label, "law": law, "phi": phi, "dn": dn, "nodes": nodes, "jump": jump,
                        "per": per, "warnings": sorted(warnings), "unconverged": unconverged})
        timings.append((label, dn, nodes, wall, cpu, scene.loading.steps))
        print(f"{label:12s} δn = {dn * 1e9:4g} nm  N = {nodes:5d}: "
              + "  ".join(f"δ = {d:g} nm: p/E* = {np.mean(per[d]['p']):.5f}, a_rel = {np.mean(per[d]['a']):.4f}"
                          for d in DELTAS_NM)
              + f"  ({wall:.1f} s wall, {cpu:.1f} s CPU)", flush=True)
    total_wall, total_cpu = time.perf_counter() - start_all, time.process_time() - cpu_all

    with open(args.out / "delta_n_effect.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    write_markdown(args, summary, timings, total_wall, total_cpu)


def _fmt(x, digits=5):
    return f"{x:.{digits}f}"


def write_markdown(args, summary, timings, total_wall, total_cpu):
    base = case_scene("cohesive", 0.15, 1e-9, 4096, args)
    hard = {s["nodes"]: s for s in summary if s["law"] == "hard-wall"}
    tol = base.interface.contact_tolerance
    lines = [
        "# Effect of the cohesive length δn on p(δ) and a_rel",
        "",
        "Written by `studies/delta_n_effect.py` (see its docstring). "
        f"Code version `{code_version()}`, Python {platform.python_version()}, {platform.machine()}.",
        "",
        "Scene: the default scene's geometry (`gfmd_contact/core/default_scene.toml`): self-affine H = 0.8, h_rms = 10 nm, "
        "L = 1.28 µm, λr = 160 nm, λs,H = 2.5 nm, E = 70 GPa, ν = 0.45, half-plane, normal-only CZ (c = 0); "
        f"realizations with seeds {', '.join(str(1 + i) for i in range(args.realizations))} "
        "(the same continuum profile on both grids); "
        f"δ0 = {args.initial_separation:g} nm (outside every case's jump-in separation), ΔU = {args.step:g} nm, "
        "FIRE, tolerance 1e-8. δn = 1 nm on N = 4096 (l = 0.31 nm) and on N = 16384; "
        "δn = 0.25 nm on N = 16384 (l = 0.078 nm): δn/l = 3.2 in both default pairings. "
        f"Contact rule: gap ≤ Δtol = {contact_gap_threshold(tol, 1.0):.2f} δn (contact_tolerance = {tol:g}); "
        "hard wall: nodes with compressive traction.",
        "",
        "Values are means over the realizations; Δ = cohesive − hard wall on the same grid.",
        "",
    ]
    for d in DELTAS_NM:
        lines += [f"## δ = {d:g} nm", "",
                  "| case | δn (nm) | N | p/E* | Δp/E* vs hard wall | a_rel | Δa_rel vs hard wall |",
                  "|---|---|---|---|---|---|---|"]
        for s in summary:
            p, a = np.mean(s["per"][d]["p"]), np.mean(s["per"][d]["a"])
            ref = hard.get(s["nodes"])
            if s["law"] == "hard-wall" or ref is None:
                dp = da = "—"
            else:
                dp = f"{p - np.mean(ref['per'][d]['p']):+.5f}"
                da = f"{a - np.mean(ref['per'][d]['a']):+.4f}"
            dn = "—" if s["law"] == "hard-wall" else f"{s['dn'] * 1e9:g}"
            lines.append(f"| {s['label']} | {dn} | {s['nodes']} | {_fmt(p)} | {dp} | {a:.4f} | {da} |")
        lines.append("")
    tol_text = ", ".join(f"Δtol = {contact_gap_threshold(tol, dn_) * 1e9:.2f} nm (δn = {dn_ * 1e9:g} nm)"
                         for dn_ in (1e-9, 0.25e-9))
    lines += ["## The hard-wall solution counted with the cohesive rule", "",
              f"Fraction of the hard wall's nodes with gap ≤ Δtol(δn) ({tol_text}): the part of the cohesive a_rel "
              "that the counting rule gives without any adhesion.", "",
              "| N | δ (nm) | a_rel (compressive nodes) | gap ≤ Δtol(1 nm) | gap ≤ Δtol(0.25 nm) |",
              "|---|---|---|---|---|"]
    for nodes, s in sorted(hard.items()):
        for d in DELTAS_NM:
            a_tol = s["per"][d]["a_tol"]
            lines.append(f"| {nodes} | {d:g} | {np.mean(s['per'][d]['a']):.4f} | {np.mean(a_tol[1e-9]):.4f} | "
                         f"{np.mean(a_tol[0.25e-9]):.4f} |")
    lines += ["", "## Per realization", "",
              "| case | δn (nm) | N | δ (nm) | p/E* per realization | a_rel per realization |",
              "|---|---|---|---|---|---|"]
    for s in summary:
        dn = "—" if s["law"] == "hard-wall" else f"{s['dn'] * 1e9:g}"
        for d in DELTAS_NM:
            lines.append(f"| {s['label']} | {dn} | {s['nodes']} | {d:g} | "
                         + ", ".join(_fmt(x) for x in s["per"][d]["p"]) + " | "
                         + ", ".join(f"{x:.4f}" for x in s["per"][d]["a"]) + " |")
    lines += ["", "## Checks and timings", "",
              "| case | δn (nm) | N | jump-in separation (nm) | steps | unconverged steps | warnings | wall (s) "
              "| CPU (s) |",
              "|---|---|---|---|---|---|---|---|---|"]
    for s, (label, dn, nodes, wall, cpu, steps) in zip(summary, timings):
        dn_text = "—" if s["law"] == "hard-wall" else f"{dn * 1e9:g}"
        warn = "; ".join(w.split(":")[1].strip() for w in s["warnings"]) or "none"
        lines.append(f"| {label} | {dn_text} | {nodes} | {s['jump'] * 1e9:.2f} | {steps} | {s['unconverged']} | "
                     f"{warn} | {wall:.1f} | {cpu:.1f} |")
    lines += ["", f"Total: {total_wall:.0f} s wall, {total_cpu:.0f} s CPU (one process).", "",
              "Base scene (φn* = 0.15, δn = 1 nm, N = 4096; the other cases change interface.law, "
              "interface.phi_n_star, interface.length_normal and surface.nodes):", "", "```toml",
              scene_to_toml(base).strip(), "```", ""]
    (args.out / "delta_n_effect.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
