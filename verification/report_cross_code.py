"""The report's cross-code section: every solver's cross-code records found in the report directory
(cross_code-<solver>.json, one per `--solver` run, `verification.cross_code.outcomes`), side by side.

Per case and metric, each code's error against the independent reference, the tolerance (the same for every
code), its cost (wall time; iterations where the code exposes them) and its verdict; a case a code cannot answer
shows the adapter's reason. Below the table, per case, which code was most accurate and which fastest, and a
speed–accuracy plot (error / tolerance against wall time, every code and case; the resolution sweep as lines).
"""

from __future__ import annotations

from html import escape
from pathlib import Path

from verification.cross_code.outcomes import load_all
from verification.report_svg import inline_svg


def _fmt(x):
    return "—" if x is None else f"{x:.3g}"


def _cell(r):
    if r is None:
        return '<td class="muted">not run</td>'
    if r["passed"] is None:
        return f'<td class="info" title="{escape(r["reason"])}">n/a: {escape(r["reason"])}</td>'
    cls = "pass" if r["passed"] else "fail"
    if r["error"] is None:
        return f'<td class="fail">failed: {escape(r["reason"][:300])}</td>'
    cost = f'{_fmt(r["wall_s"])} s' + (f', {r["iterations"]} it.' if r["iterations"] is not None else "")
    return (f'<td class="{cls}" title="{escape(r["ran"])}">{_fmt(r["error"])} ({cls})<br>'
            f'<span class="muted">{cost}</span></td>')


def _rows(by_solver):
    """[(case, metric, a record with the tolerance, {solver: record})], cases and metrics in the order first seen;
    a solver's n/a (or failed) record of a case stands in every metric row of that case."""
    metrics, whole = {}, {}
    for solver, recs in by_solver.items():
        for r in recs:
            ms = metrics.setdefault(r["case"], {})
            if r["metric"]:
                ms.setdefault(r["metric"], {})[solver] = r
            else:
                whole.setdefault(r["case"], {})[solver] = r
    rows = []
    for case, ms in metrics.items():
        for metric, recs in (ms.items() or [("", {})]):
            first = next(iter(recs.values()), None) or next(iter(whole[case].values()))
            rows.append((case, metric, first, {**whole.get(case, {}), **recs}))
    return rows


def _tolerance_text(r):
    if r["tolerance"] is None:
        return ""
    return f'{"≥" if r["lower_bound"] else "≤"} {_fmt(r["tolerance"])}'


TIE = 0.1  # errors within 10 % of the best count as equally accurate


def _comparison(case, recs):
    """One sentence: the most accurate codes (ties within TIE) and the fastest, among the codes that answered."""
    answered = {s: r for s, r in recs.items() if r["error"] is not None and r["metric"]}
    if len(answered) < 2:
        return ""
    lower = any(r["lower_bound"] for r in answered.values())
    best = (max if lower else min)(r["error"] for r in answered.values())
    close = sorted(s for s, r in answered.items()
                   if (r["error"] >= best * (1 - TIE) if lower else r["error"] <= best * (1 + TIE) or r["error"] == best))
    fastest = min(answered, key=lambda s: answered[s]["wall_s"])
    metric = next(iter(answered.values()))["metric"]
    return (f"<li>{escape(case)} ({escape(metric)}): most accurate {escape(', '.join(close))}"
            f"{' (tied)' if len(close) > 1 else ''}; fastest {escape(fastest)}</li>")


def speed_accuracy_svg(by_solver):
    """Two log-log panels, one colour and marker per code: every case's error / tolerance against its wall time,
    and the resolution sweep's error against wall time (one point per N)."""
    from matplotlib.figure import Figure
    fig = Figure(figsize=(9.0, 3.8))
    cases_ax, sweep_ax = fig.subplots(1, 2)
    for i, (solver, recs) in enumerate(sorted(by_solver.items())):
        style = {"color": f"C{i}", "marker": "osD^v<>ph"[i % 9], "label": solver}
        pts = [(r["wall_s"], r["error"] / r["tolerance"]) for r in recs
               if r["error"] and r["tolerance"] and r["wall_s"] and not r["lower_bound"]]
        if pts:
            cases_ax.loglog(*zip(*pts), ls="", alpha=0.7, **style)
        for r in (r for r in recs if r.get("sweep")):
            sweep_ax.loglog([p["wall_s"] for p in r["sweep"]], [p["error"] for p in r["sweep"]], **style)
    cases_ax.axhline(1.0, color="0.5", lw=0.8, ls="--")
    cases_ax.set(xlabel="wall time (s)", ylabel="error / tolerance", title="every case and metric")
    sweep_ax.set(xlabel="wall time (s)", ylabel="error", title="resolution sweep (convergence case)")
    for ax in (cases_ax, sweep_ax):
        if ax.has_data():
            ax.legend(fontsize=7)
    return inline_svg(fig)


def section(report_dir):
    """The section's HTML parts ([] when no cross-code records are in `report_dir`); a file it cannot read or
    draw gives a failure banner in the section, never a page lost."""
    by_solver = load_all(report_dir) if report_dir is not None and Path(report_dir).is_dir() else {}
    if not by_solver:
        return []
    try:
        return _section(by_solver)
    except Exception as exc:  # noqa: BLE001 - the rest of the report still goes out
        return [('<section id="cross-code"><h2>Cross-code verification</h2><p class="banner fail">the cross-code '
                f"records in {escape(str(report_dir))} could not be shown: {escape(type(exc).__name__)}: "
                f"{escape(str(exc))}</p></section>")]


def _section(by_solver):
    solvers = sorted(by_solver)
    out = ['<section id="cross-code"><h2>Cross-code verification</h2>',
           (f'<p class="muted">Codes: {escape(", ".join(solvers))} (one <code>--solver</code> run each). Each code is '
           "held to the same tolerance per case and metric; n/a gives the adapter's own reason.</p>"),
           "<table><thead><tr><th>case</th><th>metric</th><th>tolerance</th>"
           + "".join(f"<th>{escape(s)}</th>" for s in solvers) + "</tr></thead><tbody>"]
    per_case = {}
    for case, metric, first, recs in _rows(by_solver):
        out.append(f"<tr><td>{escape(case)}</td><td>{escape(metric or '—')}</td><td>{_tolerance_text(first)}</td>"
                   + "".join(_cell(recs.get(s)) for s in solvers) + "</tr>")
        if metric:
            per_case.setdefault(case, recs)
    out.append("</tbody></table>")
    lines = [c for c in (_comparison(case, recs) for case, recs in per_case.items()) if c]
    if lines:
        out.append("<p>Per case (first metric):</p><ul>" + "".join(lines) + "</ul>")
    out += [speed_accuracy_svg(by_solver), "</section>"]
    return out
