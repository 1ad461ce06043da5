"""Self-contained HTML verification report (`reports/index.html`).

One file, no network: figures are inline SVG written by matplotlib
(`savefig(format="svg")` into a `io.StringIO`), CSS is inline, there is no
JavaScript. Layout:

1. header: provenance, which subset ran (default / --full), pytest exit status
   and outcome counts;
2. summary table: case, methods, metric, value, tolerance, verdict (per case at most
   SUMMARY_ROWS_PER_CASE rows plus every failure; the rest folded into one counted row)
   (colour-coded), time;
3. speed–accuracy trade (every plot of kind "pareto") and extremes
   (every plot of kind "grid"), when records provide them;
4. one section per case: each distinct scene (TOML, folded), its records (resolution, tolerance source, cost,
   notes), provenance and plots.

Plot dicts (built by the helpers in `verification.plots`):

* {"kind": "profile", "x", "series": {label: y}, "xlabel", "ylabel", "title"}:
  fields overlaid; with exactly two series a difference panel (second − first).
* {"kind": "curve", same keys, "difference": bool}: load curves.
* {"kind": "convergence", "h", "error", "order", "xlabel", "ylabel", "title"}:
  log-log, fitted slope annotated (and a reference line of that slope).
* {"kind": "table", "columns", "rows", "title"}: an HTML table.
* {"kind": "pareto", "points": [{"label", "method", "time", "error"}], ...}:
  error vs wall time, log-log, one marker style per method, Pareto front drawn.
* {"kind": "grid", "columns", "rows": [[label, {"status", "message"}, …]], "title"}:
  colour-coded cells (ok green, fail red, anything else amber).

Usage: `write_report(path, records, session)`, or
`python -m verification.report reports/results.json [out.html]` to re-render
from the JSON.
"""

from __future__ import annotations

import html
import math
import re
import sys
from collections import OrderedDict
from pathlib import Path

import numpy as np

from .metrics import fitted_order
from .provenance import provenance as current_provenance
from .records import LOOSE_RATIO, Measurement, load_results, tolerance_rows
from .report_cross_code import section as cross_code_section
from .report_svg import figure_axes as _subplots
from .report_svg import inline_svg as _svg

CSS = """
:root { --ok: #1a7f37; --ok-bg: #dafbe1; --fail: #b42318; --fail-bg: #ffe4e0; --warn: #9a6700;
        --warn-bg: #fff4cc; --line: #d0d7de; --muted: #57606a; }
* { box-sizing: border-box; }
body { font-family: -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; color: #1f2328;
       max-width: 1180px; margin: 0 auto; padding: 1.2rem 1.5rem 3rem; line-height: 1.45; font-size: 15px; }
h1 { font-size: 1.6rem; margin: 0 0 .3rem; }
h2 { font-size: 1.25rem; border-bottom: 2px solid var(--line); padding-bottom: .2rem; margin-top: 2rem; }
h3 { font-size: 1.05rem; margin: 1.2rem 0 .4rem; }
table { border-collapse: collapse; margin: .5rem 0 1rem; font-size: .9rem; }
th, td { border: 1px solid var(--line); padding: .25rem .5rem; text-align: left; vertical-align: top; }
th { background: #f6f8fa; }
table.grid { table-layout: fixed; width: 100%; font-size: .72rem; }
table.grid td { overflow-wrap: anywhere; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
.pass { background: var(--ok-bg); color: var(--ok); font-weight: 600; }
.fail { background: var(--fail-bg); color: var(--fail); font-weight: 600; }
.info { background: var(--warn-bg); color: var(--warn); font-weight: 600; }
.warn { background: #fff8c5; color: var(--warn); font-weight: 600; border: 1px dashed var(--warn); }
.muted { color: var(--muted); font-size: .88rem; }
.banner { padding: .5rem .8rem; border-radius: 6px; margin: .6rem 0; font-weight: 600; }
.kv td:first-child { font-weight: 600; white-space: nowrap; }
figure { margin: .6rem 0 1.2rem; }
figure svg { max-width: 100%; height: auto; display: block; }
figcaption { font-size: .85rem; color: var(--muted); }
.record { border-left: 4px solid var(--line); padding-left: .8rem; margin: 1rem 0; }
.record.r-pass { border-left-color: var(--ok); } .record.r-fail { border-left-color: var(--fail); }
.record.r-info { border-left-color: var(--warn); }
nav ul { columns: 2; margin: .3rem 0; }
code { font-size: .9em; }
@media print {
  body { max-width: none; font-size: 11pt; padding: 0; }
  nav { display: none; }
  section.case, figure, table { break-inside: avoid; page-break-inside: avoid; }
  h2 { break-after: avoid; }
  .pass, .fail, .info, .warn, .banner { -webkit-print-color-adjust: exact; print-color-adjust: exact; }
}
"""


# --------------------------------------------------------------------------- formatting
def esc(x):
    return html.escape(str(x), quote=True)


def fmt(x, digits=3):
    """Short human number: ints as is, floats to `digits` significant digits, None/NaN as '—'."""
    if x is None:
        return "—"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (float, np.floating)):
        x = float(x)
        if not math.isfinite(x):
            return str(x)
        if x == 0:
            return "0"
        if 1e-3 <= abs(x) < 1e5:
            return f"{x:.{digits}g}"
        return f"{x:.{max(digits - 1, 1)}e}"
    if isinstance(x, (list, tuple)):
        return ", ".join(fmt(v, digits) for v in x)
    return str(x)


def verdict_of(rec):
    """('pass'|'fail'|'info', text) for a record, taking the test outcome into account."""
    outcome = rec.test_outcome
    if rec.passed is True:
        cls, text = "pass", "pass"
    elif rec.passed is False:
        cls, text = "fail", "fail"
    else:
        cls, text = "info", "no tolerance"
    if outcome in ("failed", "error") and cls != "fail":
        cls, text = "fail", f"{text} (test {outcome})"
    return cls, text


def slug(text):
    return "case-" + (re.sub(r"[^A-Za-z0-9_-]+", "-", str(text)).strip("-") or "x")


# --------------------------------------------------------------------------- figures
def _arr(v):
    return np.asarray([np.nan if e is None else e for e in v], float)


def svg_lines(plot):
    """SVG of a 'profile' or 'curve' plot: overlay (+ difference panel for two series)."""
    x = _arr(plot["x"])
    series = {k: _arr(v) for k, v in plot["series"].items()}
    two = len(series) == 2 and plot.get("difference", plot["kind"] == "profile")
    if two:
        fig, (ax, axd) = _subplots(2, figsize=(7.5, 5.2), sharex=True,
                                   gridspec_kw={"height_ratios": [2.2, 1]})
    else:
        fig, ax = _subplots(figsize=(7.5, 3.8))
    styles = ["-", "--", ":", "-."]
    markers = plot["kind"] == "curve" and len(x) <= 60
    for i, (label, y) in enumerate(series.items()):
        ax.plot(x[: len(y)], y, styles[i % 4], lw=1.6, marker="o" if markers else None, ms=3, label=label)
    ax.set_ylabel(plot.get("ylabel", ""))
    ax.grid(alpha=.3)
    if series:
        ax.legend(fontsize=8)
    if plot.get("title"):
        ax.set_title(plot["title"], fontsize=10)
    if two:
        (la, a), (lb, b) = series.items()
        n = min(len(a), len(b))
        axd.plot(x[:n], b[:n] - a[:n], color="C3", lw=1.2)
        axd.set_ylabel("difference", fontsize=9)
        axd.set_title(f"{lb} − {la}", fontsize=8)
        axd.grid(alpha=.3)
        axd.set_xlabel(plot.get("xlabel", ""))
    else:
        ax.set_xlabel(plot.get("xlabel", ""))
    return _svg(fig)


def svg_convergence(plot):
    h, e = _arr(plot["h"]), _arr(plot["error"])
    order = plot.get("order")
    order = fitted_order(h, e) if order is None else float(order)
    fig, ax = _subplots(figsize=(6.2, 4.2))
    ok = np.isfinite(h) & np.isfinite(e) & (h > 0) & (e > 0)
    ax.loglog(h[ok], e[ok], "o-", lw=1.5, label="measured")
    if ok.sum() >= 2 and math.isfinite(order):
        hh = np.geomspace(h[ok].min(), h[ok].max(), 20)
        c = np.exp(np.mean(np.log(e[ok]) - order * np.log(h[ok])))
        ax.loglog(hh, c * hh**order, "k--", lw=1, label=f"slope {order:.2f}")
        ax.annotate(f"fitted order {order:.2f}", xy=(0.04, 0.92), xycoords="axes fraction", fontsize=10,
                    bbox=dict(boxstyle="round", fc="white", ec="0.7"))
    ax.set_xlabel(plot.get("xlabel", "h"))
    ax.set_ylabel(plot.get("ylabel", "error"))
    ax.grid(alpha=.3, which="both")
    ax.legend(fontsize=8, loc="lower right")
    if plot.get("title"):
        ax.set_title(plot["title"], fontsize=10)
    return _svg(fig)


def pareto_front(points):
    """Indices of the points not dominated in (time, error), sorted by time."""
    pts = [(float(p["time"]), float(p["error"]), i) for i, p in enumerate(points)
           if p.get("time") is not None and p.get("error") is not None]
    pts.sort()
    front, best = [], math.inf
    for t, e, i in pts:
        if e < best:
            front.append(i)
            best = e
    return front


def svg_pareto(plot):
    """Log-log error vs time, one marker per method; the Pareto front dotted and labelled."""
    points = plot["points"]
    fig, ax = _subplots(figsize=(6.8, 4.4))
    methods = list(OrderedDict.fromkeys(p.get("method", "") for p in points))
    marks = "osD^v<>Xp*"
    for j, m in enumerate(methods):
        sel = [p for p in points if p.get("method", "") == m and p.get("time") and p.get("error")]
        ax.loglog([p["time"] for p in sel], [p["error"] for p in sel], marks[j % len(marks)], ms=7,
                  alpha=.85, label=m or "?")
    front = pareto_front(points)
    for i in front:  # label the front only: every point labelled is unreadable (the table lists them all)
        p = points[i]
        ax.annotate(str(p.get("label", "")), (p["time"], p["error"]), fontsize=7, xytext=(4, 3),
                    textcoords="offset points")
    if len(front) >= 2:
        ax.loglog([points[i]["time"] for i in front], [points[i]["error"] for i in front], "k:", lw=1,
                  label="Pareto front")
    ax.set_xlabel(plot.get("xlabel", "wall time (s)"))
    ax.set_ylabel(plot.get("ylabel", "error"))
    ax.grid(alpha=.3, which="both")
    ax.legend(fontsize=8)
    if plot.get("title"):
        ax.set_title(plot["title"], fontsize=10)
    return _svg(fig)


def html_table(plot):
    head = "".join(f"<th>{esc(c)}</th>" for c in plot["columns"])
    body = []
    for row in plot["rows"]:
        cells = []
        for v in row:
            num = isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)
            cells.append(f'<td class="num">{esc(fmt(v))}</td>' if num else f"<td>{esc(fmt(v))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    cap = f"<caption>{esc(plot['title'])}</caption>" if plot.get("title") else ""
    return f"<table>{cap}<thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def html_grid(plot):
    head = "".join(f"<th>{esc(c)}</th>" for c in plot["columns"])
    body = []
    for row in plot["rows"]:
        cells = []
        for v in row:
            if isinstance(v, dict) and not v.get("status") and not v.get("message"):
                cells.append("<td></td>")  # padding of a shorter row
            elif isinstance(v, dict):
                status = str(v.get("status", ""))
                cls = {"ok": "pass", "pass": "pass", "fail": "fail", "failed": "fail", "warn": "warn",
                       "warning": "warn"}.get(status.lower(), "info")
                msg = v.get("message", "")
                cells.append(f'<td class="{cls}">{esc(status)}'
                             + (f'<br><span class="muted">{esc(msg)}</span>' if msg else "") + "</td>")
            else:
                cells.append(f"<th>{esc(fmt(v))}</th>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    cap = f"<caption>{esc(plot['title'])}</caption>" if plot.get("title") else ""
    return (f'<table class="grid">{cap}<thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>')


def render_plot(plot):
    """HTML fragment of one plot dict; a visible error box (not an exception) if it cannot be drawn."""
    kind = plot.get("kind")
    try:
        if kind in ("profile", "curve"):
            inner = svg_lines(plot)
        elif kind == "convergence":
            inner = svg_convergence(plot)
        elif kind == "pareto":
            inner = svg_pareto(plot)
        elif kind == "table":
            return html_table(plot)
        elif kind == "grid":
            return html_grid(plot)
        else:
            raise ValueError(f"unknown plot kind {kind!r}")
    except Exception as exc:  # noqa: BLE001 - show it in the page, keep the report
        return (f'<p class="banner fail">plot {esc(kind)} “{esc(plot.get("title", ""))}” could not be drawn: '
                f"{esc(type(exc).__name__)}: {esc(exc)}</p>")
    return f'<figure class="plot plot-{esc(kind)}">{inner}</figure>'


# --------------------------------------------------------------------------- page
def _kv(d):
    rows = "".join(f"<tr><td>{esc(k)}</td><td>{esc(fmt(v))}</td></tr>" for k, v in d.items())
    return f'<table class="kv"><tbody>{rows}</tbody></table>'


def _session_banner(session):
    if not session:
        return ""
    counts = session.get("counts", {})
    status = session.get("exitstatus")
    ok = status == 0
    cls = "pass" if ok else "fail"
    counts_text = ", ".join(f"{v} {k}" for k, v in counts.items() if v) or "no tests counted"
    return (f'<p class="banner {cls}">pytest exit status {esc(status)} ({esc(session.get("exitstatus_name", ""))})'
            f" — {esc(counts_text)}</p>")


#: summary rows shown per case before the rest is folded into one line (failures are never folded)
SUMMARY_ROWS_PER_CASE = 8


def summary_rows(recs):
    """(shown, folded): the first SUMMARY_ROWS_PER_CASE records of a case plus every failing one."""
    shown, folded = [], []
    for r in recs:
        keep = len(shown) < SUMMARY_ROWS_PER_CASE or verdict_of(r)[0] == "fail"
        (shown if keep else folded).append(r)
    return shown, folded


def render_html(records, session=None, provenance=None, report_dir=None):
    """The whole page as a string; report_dir: where the cross-code records of every solver are
    (`verification.report_cross_code`)."""
    records = [r if isinstance(r, Measurement) else Measurement.from_dict(r) for r in records]
    session = session or {}
    prov = provenance or current_provenance()
    cases = OrderedDict()
    for r in records:
        cases.setdefault(r.case, []).append(r)
    n_pass = sum(verdict_of(r)[0] == "pass" for r in records)
    n_fail = sum(verdict_of(r)[0] == "fail" for r in records)
    n_info = len(records) - n_pass - n_fail  # measured without a tolerance: informational, not a check
    subset = session.get("subset", "?")
    out = ['<!DOCTYPE html>', '<html lang="en">', "<head>", '<meta charset="utf-8">',
           '<meta name="viewport" content="width=device-width, initial-scale=1">',
           "<title>GFMD verification report</title>", f"<style>{CSS}</style>", "</head>", "<body>",
           "<header>", "<h1>GFMD verification report</h1>",
           f'<p class="muted">Code {esc(prov.get("code_version", "?"))} · {esc(prov.get("date", ""))} · '
           f'subset <strong>{esc(subset)}</strong>'
           + (" (all studies, <code>--full</code>)" if subset == "full" else
              " (representative CI subset; <code>--full</code> adds the studies marked slow)"
              if subset == "default" else "") + "</p>",
           _session_banner(session),
           f'<p>{len(records)} measurements in {len(cases)} cases: '
           f'<span class="pass">&nbsp;{n_pass} pass&nbsp;</span> '
           f'<span class="fail">&nbsp;{n_fail} fail&nbsp;</span> '
           f'<span class="info">&nbsp;{n_info} no tolerance (informational)&nbsp;</span></p>', "</header>"]

    out += _summary_section(cases, records)
    out += _tolerance_section(records)
    out += _independence_section()

    pareto = [(r, p) for r in records for p in r.plots if p.get("kind") == "pareto"]
    grids = [(r, p) for r in records for p in r.plots if p.get("kind") == "grid"]
    if pareto:
        out.append('<section id="speed-accuracy"><h2>Speed–accuracy trade</h2>')
        for r, p in pareto:
            out.append(f'<p class="muted">from case <a href="#{slug(r.case)}">{esc(r.case)}</a>, '
                       f"metric {esc(r.metric)}</p>" + render_plot(p))
        out.append("</section>")
    out += cross_code_section(report_dir)
    out += _mutation_section()
    if grids:
        out.append('<section id="extremes"><h2>Extremes</h2>')
        for r, p in grids:
            out.append(f'<p class="muted">from case <a href="#{slug(r.case)}">{esc(r.case)}</a></p>'
                       + render_plot(p))
        out.append("</section>")

    if cases:
        out.append("<nav><h2>Cases</h2><ul>" + "".join(
            f'<li><a href="#{slug(c)}">{esc(c)}</a></li>' for c in cases) + "</ul></nav>")
    for name, recs in cases.items():
        out += _case_section(name, recs, prov)

    out.append('<section id="provenance"><h2>Provenance</h2>' + _kv(prov))
    if session:
        out.append("<h3>Session</h3>" + _kv({k: v for k, v in session.items() if k != "counts"}))
        out.append(_kv(session.get("counts", {})))
    out.append("</section></body></html>")
    return "\n".join(out)


def _summary_section(cases, records):
    """"Summary": a row per shown measurement of each case, the rest of a case folded into one row."""
    out = ['<section id="summary"><h2>Summary</h2>',
           '<table id="summary-table"><thead><tr><th>case</th><th>methods</th><th>metric</th><th>value</th>'
           "<th>tolerance</th><th>verdict</th><th>time (s)</th></tr></thead><tbody>"]
    for name, recs in cases.items():
        shown, folded = summary_rows(recs)
        for r in shown:
            cls, text = verdict_of(r)
            out.append(f'<tr class="row-{cls}"><td><a href="#{slug(r.case)}">{esc(r.case)}</a></td>'
                       f"<td>{esc(', '.join(r.methods))}</td><td>{esc(r.metric)}</td>"
                       f'<td class="num">{esc(fmt(r.value))}</td><td class="num">{esc(fmt(r.tolerance))}</td>'
                       f'<td class="{cls}">{esc(text)}</td><td class="num">{esc(fmt(r.wall_s))}</td></tr>')
        if folded:
            tally = OrderedDict()
            for r in folded:
                v = verdict_of(r)[1]
                tally[v] = tally.get(v, 0) + 1
            out.append(f'<tr class="row-folded"><td><a href="#{slug(name)}">{esc(name)}</a></td>'
                       f'<td colspan="6" class="muted">… and {len(folded)} more measurements of this case ('
                       + ", ".join(f"{n} {v}" for v, n in tally.items()) + "), listed in its section</td></tr>")
    if not records:
        out.append('<tr><td colspan="7">no measurements were recorded</td></tr>')
    out.append("</tbody></table></section>")
    return out


def _case_section(name, recs, prov):
    """One case's section: each measurement with its verdict, tolerance source, cost, scene (once) and plots."""
    out = [f'<section class="case" id="{slug(name)}"><h2>{esc(name)}</h2>']
    shown_scenes = set()
    for r in recs:
        cls, text = verdict_of(r)
        mem = "—" if r.peak_memory_bytes is None else f"{r.peak_memory_bytes / 2**20:.3g} MiB"
        info = OrderedDict([
            ("methods", ", ".join(r.methods)),
            ("value / tolerance", f"{fmt(r.value, 4)} / {'≥ ' if r.lower_bound else ''}{fmt(r.tolerance, 4)} → {text}"),
            ("tolerance source", r.tolerance_source or "—"),
            ("resolution", "; ".join(f"{k} = {fmt(v, 4)}" for k, v in r.resolution.items()) or "—"),
            ("cost", f"wall {fmt(r.wall_s)} s; peak memory {mem} ({r.memory_method or 'not measured'})"),
            ("test", f"{r.test or '—'} ({r.test_outcome or 'outcome unknown'})"),
        ])
        if r.notes:
            info["notes"] = r.notes
        out.append(f'<div class="record r-{cls}"><h3>{esc(r.metric)} '
                   f'<span class="{cls}">&nbsp;{esc(text)}&nbsp;</span></h3>{_kv(info)}')
        if r.scene and r.scene not in shown_scenes:  # each distinct scene of a case once
            shown_scenes.add(r.scene)
            out.append(f'<details class="scene"><summary>scene (TOML, SI units)</summary>'
                       f"<pre>{esc(r.scene)}</pre></details>")
        for p in r.plots:
            if p.get("kind") in ("pareto", "grid"):
                out.append('<p class="muted">(shown above under '
                           + ("Speed–accuracy trade" if p["kind"] == "pareto" else "Extremes") + ")</p>")
            else:
                out.append(render_plot(p))
        if r.provenance and r.provenance != prov:
            out.append("<details><summary>provenance of this record</summary>" + _kv(r.provenance)
                       + "</details>")
        out.append("</div>")
    out.append("</section>")
    return out


def _tolerance_section(records):
    """"Tolerances": every verification tolerance with the number it rests on (`records.tolerance_rows`)."""
    rows = tolerance_rows(records)
    if not rows:
        return []
    n_loose = sum(r["loose"] for r in rows)
    n_stored = sum(r["basis"] == "stored" for r in rows)
    n_loose_stored = sum(r["loose"] and r["basis"] == "stored" for r in rows)
    out = ['<section id="tolerances"><h2>Tolerances</h2>',
           f'<p>{len(rows)} assertions with a tolerance; {n_stored} rest on a number a study measured and '
           "stored (verification/data/*.json, regenerated by the study), the others on the value measured in "
           "this run (rules: round-off, one node per contact edge, a solver tolerance). Ratio = tolerance / "
           "measured (for a lower bound ≥, an observed order or refinement ratio: measured / tolerance); "
           f'<span class="warn">&nbsp;loose&nbsp;</span> where it exceeds {LOOSE_RATIO:g} '
           f"({n_loose} of {len(rows)}: {n_loose_stored} over a stored measurement, {n_loose - n_loose_stored} rules "
           "over this run's value, most of them a node-count or round-off rule over a difference of exactly 0). "
           "Generated from the records the tests made.</p>",
           '<table id="tolerance-table"><thead><tr><th>case</th><th>metric</th><th>tolerance</th><th>measured</th>'
           "<th>basis</th><th>ratio</th><th>this run</th><th>tolerance source</th><th>measured by</th>"
           "</tr></thead><tbody>"]
    for r in rows:
        ratio = "∞" if r["ratio"] == math.inf else fmt(r["ratio"])
        cls = ' class="num warn"' if r["loose"] else ' class="num"'
        src = "<br>".join(esc(line) for line in r["measured_source"].splitlines()) or "—"
        out.append(f'<tr><td><a href="#{slug(r["case"])}">{esc(r["case"])}</a></td><td>{esc(r["metric"])}</td>'
                   f'<td class="num">{"≥ " if r["lower"] else ""}{esc(fmt(r["tolerance"]))}</td><td class="num">{esc(fmt(r["measured"]))}</td>'
                   f"<td>{esc(r['basis'])}</td><td{cls}>{esc(ratio)}{' loose' if r['loose'] else ''}</td>"
                   f'<td class="num">{esc(fmt(r["value"]))}</td><td class="muted">{esc(r["source"] or "—")}</td>'
                   f'<td class="muted">{src}</td></tr>')
    out.append("</tbody></table></section>")
    return out


def _independence_section(root=None):
    """"Independence of the FE reference": what reference.fem shares with GFMD on purpose, generated from
    the allowed list of tests/test_architecture.py (FE_MAY_IMPORT) and the FE's imports read now."""
    from .independence import fe_shared_inputs
    try:
        info = fe_shared_inputs(root)
    except FileNotFoundError as exc:  # an installed package: the tests/ folder is not shipped
        return ['<section id="independence"><h2>Independence of the FE reference</h2><p>The allowed list '
                "(<code>tests/test_architecture.py</code>) is part of the source checkout, not of the installed "
                f"package: run <code>gfmd verify</code> in a checkout for this section ({esc(exc)}).</p></section>"]
    except Exception as exc:  # noqa: BLE001 - show it in the page, keep the report
        return [f'<section id="independence"><h2>Independence of the FE reference</h2><p class="banner fail">'
                f"could not read the allowed imports: {esc(type(exc).__name__)}: {esc(exc)}</p></section>"]
    rows = "".join(f'<tr><td><code>{esc(m)}</code></td><td>{esc(what)}</td>'
                   f'<td>{esc(", ".join(users) or "—")}</td></tr>' for m, what, users in info["shared"])
    extra = info["not_allowed"]
    out = ['<section id="independence"><h2>Independence of the FE reference</h2>',
           "<p>The FE reference (<code>reference.fem</code>) shares the <em>inputs</em> with GFMD on purpose and "
           "nothing it checks. It may import from the core (<code>contact</code>) only the modules below "
           "(<code>tests/test_architecture.py</code>, <code>FE_MAY_IMPORT</code>, which fails on any other; "
           "the list is read from that file).</p>",
           "<table><thead><tr><th>shared module</th><th>what it provides</th><th>FE modules importing it directly</th>"
           f"</tr></thead><tbody>{rows}</tbody></table>",
           "<p>Independent (own code in <code>reference.fem</code>, never imported from GFMD or the core): "
           + "; ".join(f"{esc(k)} (<code>{esc(v)}</code>)" for k, v in info["independent"].items()) + ".</p>"]
    if extra:
        out.append('<p class="banner fail">reference.fem imports core modules outside the allowed list: '
                   + esc("; ".join(f"{m}: {', '.join(t)}" for m, t in extra.items())) + "</p>")
    out.append("</section>")
    return out


def _mutation_section(doc=None):
    """The "Mutation score" section from verification/data/mutations.json (`verification.mutations`),
    or nothing if no mutation run is stored."""
    if doc is None:
        from verification import measured
        try:
            doc = measured.load("mutations")
        except measured.MissingMeasurement:
            return []
    out = ['<section id="mutations"><h2>Mutation score</h2>']
    for key, e in doc.get("entries", {}).items():
        v = e["values"]
        out.append(f'<p>{v["caught"]} of {v["total"]} single-point physics mutations caught by '
                   f'<code>pytest verification -x</code> alone ({esc(key)}; code {esc(e.get("code_version", "?"))}, '
                   f'{esc(e.get("date", ""))}; <code>python -m verification.mutations --write</code>)</p>')
        rows = "".join(f'<tr><td>{esc(r["id"])}</td><td>{esc(r["what"])}</td>'
                       f'<td class="{"pass" if r["caught"] else "fail"}">{"caught" if r["caught"] else "not caught"}'
                       f'</td><td>{esc(r["first_failure"])}</td><td>{fmt(r["seconds"])}</td></tr>' for r in v["rows"])
        out.append("<table><thead><tr><th>mutation</th><th>what</th><th>verdict</th><th>first failing test</th>"
                   f"<th>s</th></tr></thead><tbody>{rows}</tbody></table>")
    out.append("</section>")
    return out


def write_report(path, records, session=None, provenance=None):
    """Write the HTML page to `path` (parents created); returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    from gfmd_contact.app.safe_files import atomic_write  # a kill or a full disk never leaves half a page

    atomic_write(path, render_html(records, session, provenance, report_dir=path.parent))
    return path


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv:
        print("usage: python -m verification.report results.json [index.html]", file=sys.stderr)
        return 2
    doc, records = load_results(argv[0])
    out = argv[1] if len(argv) > 1 else str(Path(argv[0]).with_name("index.html"))
    write_report(out, records, doc.get("session"), doc.get("provenance"))
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
