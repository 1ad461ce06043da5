"""Speed–accuracy trade: error vs wall time of every method and setting on three scenes.

Scenes (`verification.scenes.SPEED_ACCURACY`): (a) adhesive sinusoid, normal CZ φn* = 0.01;
(b) adhesive self-affine, normal CZ φn* = 0.01, layer D = L; (c) the same profile, hard wall.
Settings (`plan`): GFMD FIRE and Verlet at N × force tolerance (× p_ref); FE P1 and P2 at N
(Newton / primal–dual active set to 1e-10; default graded mesh). Wall time = the whole run (FE:
mesh, assembly and condensation included), best of two below 1 s, one run on a shared machine:
ratios within one table are meaningful, absolute times only roughly.

References (`REFERENCE_TEXT`, stored with each entry). No analytic solution exists for these three scenes
(adhesive CZ sinusoid, self-affine cohesive, self-affine hard wall). p(δ): an independent reference,
`richardson_reference` — the Richardson extrapolation of GFMD FIRE at tolerance 1e-10 on the finest grid
and its two halvings, and of FE P2 on its three finest grids, averaged; its own error estimate is the
difference of the two extrapolations (two independent methods; each one's last-level change is stored too). a_rel and
t_n(x) (node counts and fields: not extrapolated): GFMD FIRE, tolerance 1e-10, on the finest grid.
Errors (`errors`) at the same load steps: e_a = max_k |a_rel − a_ref| (absolute, includes the O(1/N)
quantisation of a node count), e_a,nodes (the reference's contact set sampled on the run's nodes),
e_p = relative L2 of p(δ) against the Richardson reference, e_p,GFMD = the same against the finest GFMD
run alone (the former reference, kept for comparison), e_t = relative L2 of t_n at the last step.
Cross errors (`cross_errors`), what the time-to-accuracy table uses: every GFMD setting against
the finest FE P2 run, every FE setting against the GFMD reference (e_p×, e_a×): no method is
judged against its own finest run (which would favour it by construction).

    python -m verification.studies.speed_accuracy [--subset ci|full] [--write] [SCENE …]

prints every setting's errors and the time to reach 1 % / 0.1 % error; `--write` stores them in
verification/data/speed_accuracy.json (entries "<scene>/<subset>"), with the FE P2 vs GFMD FIRE
difference at FE's finest N that test_speed_accuracy.py derives its agreement bound from.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from gfmd_contact.core.observables import contact_mask
from verification import measured
from verification.metrics import max_abs_difference, relative_l2, worst
from verification.plots import pareto_plot, table_plot
from verification.runs import run_fe, run_gfmd
from verification.scenes import SPEED_ACCURACY as SCENES

NAME = "speed_accuracy"
SUBSET_TEXT = {"ci": "CI subset: GFMD FIRE/Verlet N = 64, 128, 256 × tolerance 1e-2, 1e-4, 1e-8; FE P1/P2 "
                     "N = 64, 128, 256; reference GFMD FIRE N = 1024, tolerance 1e-10",
               "full": "full sweep (--full): GFMD FIRE/Verlet N = 64 … 1024 × tolerance 1e-2, 1e-4, 1e-6, 1e-8; "
                       "FE P1/P2 N = 64 … 512; reference GFMD FIRE N = 4096, tolerance 1e-10"}
REFERENCE_TEXT = ("No analytic solution exists for these three scenes. p(δ) errors (the p Pareto plot and the "
                  "monotonicity check): against the Richardson extrapolation of the finest GFMD (FIRE, tolerance "
                  "1e-10, finest grid and two halvings) and FE P2 (three finest grids) runs, averaged, with its own "
                  "error estimate (the difference of the two extrapolations). a_rel and t_n errors: against GFMD FIRE at tolerance 1e-10 on the finest grid. Time to "
                  "1 % error: each method against the other's finest run (GFMD vs FE P2 at FE's finest N, FE vs the "
                  "GFMD reference), so neither is judged by its own reference.")
#: which reference each error column uses (stored with the data, shown in the report)
CURVE_REFERENCE = {"e_p": "Richardson extrapolation of GFMD and FE P2 (richardson_reference)",
                   "e_p_gfmd": "GFMD FIRE, tolerance 1e-10, finest grid",
                   "e_a": "GFMD FIRE, tolerance 1e-10, finest grid", "e_a_nodes": "GFMD FIRE, tolerance 1e-10, finest grid",
                   "e_t": "GFMD FIRE, tolerance 1e-10, finest grid",
                   "e_p_x": "the other method's finest run", "e_a_x": "the other method's finest run"}
REPEAT_BELOW_S = 1.0  # s: runs cheaper than this are timed twice, the minimum is kept
#: (method, tolerance) of the refinement series compared (tightest GFMD tolerance)
SERIES = (("gfmd-fire", 1e-8), ("gfmd-verlet", 1e-8), ("fe-p1", None), ("fe-p2", None))


@dataclass(frozen=True)
class Setting:
    """One method at one resolution: "gfmd-fire", "gfmd-verlet", "fe-p1" or "fe-p2"; nodes N;
    tolerance: GFMD force-residual tolerance (× p_ref), None for FE (Newton/PDAS to 1e-10)."""

    method: str
    nodes: int
    tolerance: float | None = None

    @property
    def label(self):
        tol = f", tol {self.tolerance:.0e}" if self.tolerance is not None else ""
        return f"{self.method} N={self.nodes}{tol}"

    @property
    def family(self):
        return "GFMD" if self.method.startswith("gfmd") else "FE"


def plan(subset):
    """(settings, reference setting) of the sweep "ci" or "full" (see SUBSET_TEXT)."""
    if subset == "ci":
        ns_g, ns_f, tols, n_ref = (64, 128, 256), (64, 128, 256), (1e-2, 1e-4, 1e-8), 1024
    else:
        ns_g, ns_f, tols, n_ref = (64, 128, 256, 512, 1024), (64, 128, 256, 512), (1e-2, 1e-4, 1e-6, 1e-8), 4096
    settings = [Setting(m, n, t) for m in ("gfmd-fire", "gfmd-verlet") for n in ns_g for t in tols]
    settings += [Setting(m, n) for m in ("fe-p1", "fe-p2") for n in ns_f]
    return settings, Setting("gfmd-fire", n_ref, 1e-10)


def run_setting(scene_of, setting, all_fields=False):
    """(Result, wall time in s of the whole run, FE setup included); all_fields: save every step's fields."""
    sc = scene_of(setting.nodes)
    if all_fields:
        sc = sc.replace(**{"output.field_steps": sc.loading.steps})
    if setting.family == "GFMD":
        from gfmd.solver import Settings
        settings = Settings(method=setting.method.split("-")[1], tolerance=setting.tolerance, max_iterations=200_000)
        return run_gfmd(sc, settings=settings, method_name=setting.method)
    return run_fe(sc, order=int(setting.method[-1]))


def errors(result, reference):
    """Errors of `result` against `reference` (same load steps, reference on a finer grid whose every
    m-th node is a node of `result`, fields saved at every step): a, a_nodes, p, t (module docstring)."""
    n, n_ref = result.x.size, reference.x.size
    m = n_ref // n
    if n_ref % n or not np.allclose(reference.x[::m], result.x):
        raise ValueError(f"reference grid (N = {n_ref}) does not contain the nodes of N = {n}")
    if not np.allclose(result.curve["delta"], reference.curve["delta"]):
        raise ValueError("reference and run have different load steps")
    steps = np.arange(1, len(reference.curve["delta"]))  # step 0 (U = 0) has no saved fields
    missing = [k for k in steps if k not in reference.fields]
    if missing:
        raise ValueError(f"reference lacks the fields of steps {missing[:5]}: run it with output.field_steps = steps")
    iface = reference.scene.interface
    a_nodes = [np.mean(contact_mask(iface, reference.fields[k]["gap"][::m], reference.fields[k]["t_n"][::m]))
               for k in steps]
    k, k_ref = max(result.fields), max(reference.fields)
    t_ref = reference.fields[k_ref]["t_n"][::m]
    return {"a": max_abs_difference(result, reference),
            "a_nodes": float(np.max(np.abs(result.curve["a_rel"][steps] - np.asarray(a_nodes)))),
            "p": relative_l2(result.curve["p"], reference.curve["p"], reference.curve["p"]),
            "t": relative_l2(result.fields[k]["t_n"], t_ref, t_ref)}


def extrapolate(levels):
    """Richardson extrapolation of p(δ) curves at N doubling: levels [(N, p array)] by increasing N (≥ 2).

    Observed order q = log2(‖p_{N/4} − p_{N/2}‖ / ‖p_{N/2} − p_N‖) from the last three levels; with q > 0.5,
    p∞ = p_N + (p_N − p_{N/2}) / (2^q − 1), else (two levels, or no clean order) p∞ = p_N. Error estimate:
    the last-level change ‖p_N − p_{N/2}‖ / ‖p_N‖ (conservative for q ≥ 1).
    Returns {"p": p∞, "order": q, "error": estimate, "N": [levels' N]}."""
    ns = [n for n, _ in levels]
    if any(b != 2 * a for a, b in zip(ns, ns[1:])):
        raise ValueError(f"levels must double: N = {ns}")
    p1, p2 = (np.asarray(levels[-2][1], float), np.asarray(levels[-1][1], float))
    d_last = np.linalg.norm(p2 - p1)
    q = float("nan")
    if len(levels) >= 3:
        d_prev = np.linalg.norm(p1 - np.asarray(levels[-3][1], float))
        q = float(np.log2(d_prev / d_last)) if d_last > 0 and d_prev > 0 else float("nan")
    p_inf = p2 + (p2 - p1) / (2**q - 1) if np.isfinite(q) and q > 0.5 else p2
    return {"p": p_inf, "order": q, "error": float(d_last / np.linalg.norm(p2)), "N": ns}


def richardson_reference(gfmd_levels, fe_levels):
    """The independent p(δ) reference: the mean of the GFMD and FE P2 extrapolations (`extrapolate`), with
    its own error estimate ‖p_G∞ − p_F∞‖/‖p∞‖ (the two methods' extrapolations differ by that much).
    Returns {"p", "error", "difference", "gfmd": extrapolation, "fe": extrapolation}."""
    g, f = extrapolate(gfmd_levels), extrapolate(fe_levels)
    p_inf = 0.5 * (g["p"] + f["p"])
    diff = float(np.linalg.norm(g["p"] - f["p"]) / np.linalg.norm(p_inf))
    return {"p": p_inf, "error": diff, "difference": diff, "gfmd": g, "fe": f}


def cross_errors(result, other):
    """e_p× (relative L2 of p(δ)) and e_a× (max |Δa_rel|) against the other method's finest run."""
    if not np.allclose(result.curve["delta"], other.curve["delta"]):
        raise ValueError("the run and the other method's reference have different load steps")
    return {"p_x": relative_l2(result.curve["p"], other.curve["p"], other.curve["p"]),
            "a_x": max_abs_difference(result, other)}


_STUDIES = {}


def study(name, subset):
    """The sweep of `subset` on scene `name` (cached per process):
    {"reference": (Setting, wall_s, Result), "rows": [(Setting, wall_s, errors, Result)], "wall_s"}."""
    key = (name, subset)
    if key not in _STUDIES:
        t0 = time.perf_counter()
        scene_of = SCENES[name]
        settings, ref_setting = plan(subset)
        reference, ref_wall = run_setting(scene_of, ref_setting, all_fields=True)
        rows = []
        for s in settings:
            result, wall = run_setting(scene_of, s)
            if wall < REPEAT_BELOW_S:  # cheap runs: best of two (first-call and load noise)
                wall = min(wall, run_setting(scene_of, s)[1])
            rows.append((s, wall, errors(result, reference), result))
        fe_reference = max(((s.nodes, r) for s, _, _, r in rows if s.method == "fe-p2"), key=lambda t: t[0])[1]
        for s, _, e, r in rows:
            e.update(cross_errors(r, fe_reference if s.family == "GFMD" else reference))
        # the independent p(δ) reference: GFMD at the reference tolerance on the finest grid and two halvings,
        # FE P2 on its three finest grids, both extrapolated (`richardson_reference`)
        g_levels = [(ref_setting.nodes // m, run_setting(scene_of, Setting(ref_setting.method, ref_setting.nodes // m,
                                                                           ref_setting.tolerance))[0].curve["p"])
                    for m in (4, 2)] + [(ref_setting.nodes, reference.curve["p"])]
        f_levels = sorted((s.nodes, r.curve["p"]) for s, _, _, r in rows if s.method == "fe-p2")[-3:]
        rich = richardson_reference(g_levels, f_levels)
        for s, _, e, r in rows:
            e["p_gfmd"] = e["p"]
            e["p"] = relative_l2(r.curve["p"], rich["p"], rich["p"])
        _STUDIES[key] = {"reference": (ref_setting, ref_wall, reference), "fe_reference": fe_reference,
                         "richardson": rich, "rows": rows, "wall_s": time.perf_counter() - t0}
    return _STUDIES[key]


# ----------------------------------------------------------------------------- reductions
def refinement_series(rows, method, tolerance, metric="p"):
    """[(N, error)] of one method at one tolerance, by increasing N."""
    return sorted((s.nodes, e[metric]) for s, _, e, _ in rows if s.method == method and s.tolerance == tolerance)


def worst_refinement_ratio(series, floor):
    """max over consecutive N of e(2N)/e(N), pairs whose finer error is below `floor` (noise) skipped."""
    ratios = [b / a for (_, a), (_, b) in pairwise(series) if not b <= floor]  # a NaN error is kept
    return worst(ratios) if ratios else 0.0


def agreement(rows):
    """(N, p(δ) rel. L2, max |Δa_rel|) of FE P2 against GFMD FIRE (tolerance 1e-8) on FE's finest grid."""
    n_f, rf = max((s.nodes, r) for s, _, _, r in rows if s.method == "fe-p2")
    rg = next(r for s, _, _, r in rows if s.method == "gfmd-fire" and s.tolerance == 1e-8 and s.nodes == n_f)
    return n_f, relative_l2(rf.curve["p"], rg.curve["p"], rg.curve["p"]), max_abs_difference(rf, rg)


def cheapest_below(rows, family, metric, level=0.01):
    """(wall s, label) of the cheapest setting of `family` with error[metric] < level, or None."""
    ok = [(wall, s.label) for s, wall, e, _ in rows if s.family == family and e[metric] < level]
    return min(ok) if ok else None


def time_to_accuracy_rows(name, rows, level=0.01):
    """Table rows "to reach 1 % error in a_rel / p (and 0.1 % in p): GFMD needs X s, FE needs Y s", each
    method's error taken against the other method's finest run (`cross_errors`)."""
    out = []
    for metric, what, lvl in (("a_x", "|a_rel − a_ref| (absolute)", level), ("p_x", "p(δ) rel. L2", level),
                              ("p_x", "p(δ) rel. L2", level / 10)):
        cells = []
        for family in ("GFMD", "FE"):
            best = cheapest_below(rows, family, metric, lvl)
            cells.append("not reached" if best is None else f"{best[0]:.2f} s ({best[1]})")
        out.append([name, f"to reach {lvl:.1%} error in {what}", *cells])
    return out


def report_plots(name, st, subset):
    """Pareto plots (p, a_rel, t_n error vs wall time), the table of all settings, time to 1 %."""
    rows = st["rows"]
    ref_s, ref_wall, _ = st["reference"]
    plots = []
    for metric, what in (("p", "p(δ) rel. L2 error vs the Richardson reference"), ("a", "max |a_rel − a_ref|"),
                         ("t", "t_n rel. L2 (last step)")):
        points = [{"label": s.label, "method": s.method, "time": wall, "error": e[metric]} for s, wall, e, _ in rows]
        plots.append(pareto_plot(points, ylabel=what, title=f"{name}: {what} vs wall time ({subset})"))
    rich = st["richardson"]
    table = [[s.label, f"{wall:.3g}", f"{e['a']:.2e}", f"{e['a_nodes']:.2e}", f"{e['p']:.2e}", f"{e['p_gfmd']:.2e}",
              f"{e['t']:.2e}"] for s, wall, e, _ in rows]
    plots.append(table_plot(["setting", "wall s", "|Δa_rel|", "|Δa_rel| (ref. on the nodes)",
                             "p rel. L2 (Richardson ref.)", "p rel. L2 (finest GFMD)", "t_n rel. L2"], table,
                            title=f"{name}: all settings; p against the Richardson reference (error estimate "
                                  f"{rich['error']:.2g}), a_rel and t_n against {ref_s.label} ({ref_wall:.2f} s)"))
    plots.append(table_plot(["error column", "reference"], [[k, v] for k, v in CURVE_REFERENCE.items()],
                            title=f"{name}: which reference each error uses"))
    plots.append(table_plot(["scene", "target", "GFMD needs", "FE needs"], time_to_accuracy_rows(name, rows),
                            title=f"{name}: cheapest setting below 1 % error (0.1 % in p), wall time"))
    return plots


def print_study(name, st):
    ref_s, ref_wall, _ = st["reference"]
    print(f"\n== {name}: reference {ref_s.label} ({ref_wall:.2f} s)")
    print(f"{'setting':34s} {'wall s':>8s} {'e_a':>9s} {'e_a,nodes':>9s} {'e_p':>9s} {'e_t':>9s}")
    for s, wall, e, _ in st["rows"]:
        print(f"{s.label:34s} {wall:8.2f} {e['a']:9.2e} {e['a_nodes']:9.2e} {e['p']:9.2e} {e['t']:9.2e}")
    for row in time_to_accuracy_rows(name, st["rows"]):
        print("  ", " | ".join(row))
    n_f, dp, da = agreement(st["rows"])
    print(f"   FE P2 vs GFMD FIRE at N = {n_f}: p rel. L2 {dp:.3g}, max |Δa_rel| {da:.3g}")
    rich = st["richardson"]
    print(f"   p reference (Richardson, GFMD N = {rich['gfmd']['N']} order {rich['gfmd']['order']:.2f}, FE P2 N = "
          f"{rich['fe']['N']} order {rich['fe']['order']:.2f}): error estimate {rich['error']:.3g}, "
          f"extrapolations differ by {rich['difference']:.3g}")


# ----------------------------------------------------------------------------- data file
def entry(name, subset, st):
    """The data-file entry "<name>/<subset>" of a study run."""
    ref_s, ref_wall, _ = st["reference"]
    n_f, dp, da = agreement(st["rows"])
    settings = [{"setting": s.label, "wall_s": wall, **{f"e_{k}": v for k, v in e.items()}}
                for s, wall, e, _ in st["rows"]]
    series = {f"{m} tol {t:g}" if t else m: refinement_series(st["rows"], m, t) for m, t in SERIES}
    rich = st["richardson"]
    p_reference = {"error": rich["error"], "difference_of_extrapolations": rich["difference"],
                   **{f"{m}_{k}": rich[m][k] for m in ("gfmd", "fe") for k in ("N", "order", "error")}}
    return measured.make_entry({"agreement_fe_p2_vs_gfmd_fire": {"N": n_f, "p_rel_l2": dp, "max_abs_a_rel": da},
                                "p_reference": p_reference, "curve_reference": CURVE_REFERENCE,
                                "p_error_series": series, "settings": settings,
                                "time_to_accuracy": time_to_accuracy_rows(name, st["rows"])},
                               scene=f"verification.scenes.{SCENES[name].__name__}(N)", subset=subset,
                               reference=f"{ref_s.label} ({ref_wall:.2f} s)", wall_s=st["wall_s"])


def measured_agreement(name, subset):
    """The stored {"N", "p_rel_l2", "max_abs_a_rel"} of FE P2 vs GFMD FIRE (verification/data/speed_accuracy.json)."""
    return measured.value(NAME, f"{name}/{subset}", "agreement_fe_p2_vs_gfmd_fire")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--subset", choices=("ci", "full"), default="ci")
    ap.add_argument("--write", action="store_true", help="store the results in verification/data/speed_accuracy.json")
    ap.add_argument("scenes", nargs="*", metavar="SCENE", help=f"default: all of {', '.join(SCENES)}")
    args = ap.parse_args(argv)
    unknown = sorted(set(args.scenes) - set(SCENES))
    if unknown:
        ap.error(f"unknown scene(s) {unknown}; known: {list(SCENES)}")
    entries = {}
    for name in args.scenes or SCENES:
        st = study(name, args.subset)
        print_study(name, st)
        print(f"   total {st['wall_s']:.1f} s")
        entries[f"{name}/{args.subset}"] = entry(name, args.subset, st)
    if args.write:
        print(measured.write(NAME, entries, description="speed–accuracy sweeps: every setting's errors against the "
                                                        "reference and its wall time; FE P2 vs GFMD FIRE at FE's "
                                                        "finest N"))


if __name__ == "__main__":
    main()
