"""`gfmd study report DIR [DIR …]`: one self-contained HTML page (DIR/report.html) of the seed's claims.

Units: the effect sizes are dimensionless (`gfmd_contact.app.claims`). The page holds, per study
directory, what it is (sets, tasks finished, a red note when partial), the claims table
(claim, seed figure, the measured effect ± its standard error over realizations, n, verdict,
the numbers behind it), the definitions of the effect sizes and the verdict rule, and the
figures of `gfmd_contact.app.study_plots` embedded as base64 PNG (no file beside the page is needed).
With several directories the claims table has one row per claim and directory that has the
sets (a claim no directory has is listed once as "not in this study"), and the figures of each.
"""

from __future__ import annotations

import base64
import html
import io
import time
from pathlib import Path

import numpy as np

from . import claims as C
from . import safe_files
from .study_plots import make_study_figures

_VERDICT_COLOR = {C.REPRODUCED: "#d9f2d9", C.NOT_REPRODUCED: "#f8d0d0", C.INCONCLUSIVE: "#fff2c6",
                  C.NOT_IN_STUDY: "#eeeeee", C.DEPENDS: "#dde6fb", C.SINGLE: "#fff2c6"}

_CSS = """body{font-family:system-ui,sans-serif;max-width:1250px;margin:1.5em auto;color:#222}
table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #bbb;padding:4px 6px;vertical-align:top}
th{background:#f0f0f0}.num{white-space:nowrap;font-family:monospace}.det{font-size:12px;color:#333}
.partial{color:#b00;font-weight:bold}img{max-width:100%;border:1px solid #ddd;margin:4px 0}
.figs{display:grid;grid-template-columns:1fr 1fr;gap:8px}"""


def _e(text):
    return html.escape(str(text))


def _num(m):
    if m is None or not np.isfinite(m.value):
        return "—"
    return f"{m.value:.4g} ± {m.se:.2g}"


def _png(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return base64.b64encode(buf.getvalue()).decode()


def claims_rows(results_by_dir):
    """[(ClaimResult or None, study, Measurement or None)] of the table: per claim, each directory that has it."""
    rows = []
    for i, claim in enumerate(C.CLAIMS):
        got = [(name, res[i]) for name, res in results_by_dir if res[i].verdict != C.NOT_IN_STUDY]
        if not got:
            rows.append((claim, "—", None, C.NOT_IN_STUDY))
            continue
        for name, r in got:
            rows.append((claim, name, r, r.verdict))
    return rows


def _claims_table(results_by_dir):
    out = ["<table><tr><th>seed</th><th>claim</th><th>study</th><th>measured effect ± SE</th><th>n</th>"
           "<th>verdict</th><th>numbers (mean ± SE over realizations)</th></tr>"]
    for claim, name, r, verdict in claims_rows(results_by_dir):
        ms = r.measurements if r is not None else []
        if ms:
            effect = "<br>".join(_e((f"{m.context}: " if m.context else "") + _num(m)) for m in ms)
            n = "<br>".join(str(m.n) for m in ms)
            det = "<br>".join(_e((f"[{m.context}] " if m.context else "") + f"{m.verdict}: {m.details}")
                              if m.context else _e(m.details) for m in ms)
        else:
            effect, n, det = "—", "—", ""
        out.append(f"<tr><td>{_e(claim.figure)}</td><td>{_e(claim.claim)}</td><td>{_e(name)}</td>"
                   f"<td class=num>{effect}</td><td class=num>{n}</td>"
                   f"<td style='background:{_VERDICT_COLOR.get(verdict, '#fff')}'><b>{_e(verdict)}</b></td>"
                   f"<td class=det>{det}</td></tr>")
    out.append("</table>")
    return "\n".join(out)


def _definitions():
    items = "\n".join(f"<li><b>{_e(c.figure)} — {_e(c.claim)}</b> (<code>{c.id}</code>): {_e(c.definition)}</li>"
                      for c in C.CLAIMS)
    rule = ("Per set, a value is the mean over its realizations and SE = s/√n (s: sample standard deviation over "
            "the n realizations, from study.csv); differences between sets with the same seeds are taken per "
            "realization (paired), otherwise SE = √(SE₁² + SE₂²). Verdict: <i>reproduced</i> when value ± 2 SE lies "
            "wholly on the claim's side of its limit, <i>not reproduced</i> when wholly on the other side, "
            "<i>inconclusive (within 2 SE)</i> otherwise (and when fewer than two realizations give the value); <i>not in this study</i> when the study lacks the sets; "
            "<i>depends on δn / the contact rule</i> when the study varies interface.length_normal (or a "
            "contact-rule key) and the verdicts for its values differ (each value's number is listed). "
            "δ_eval = min(20 nm, the largest δ every compared set reached).")
    return f"<p>{rule}</p><ul>{items}</ul>"


def _study_section(data, figs):
    sets = ", ".join(f"set {s.index}: {C.set_label(s, data.keys) or 'base scene'}" for s in data.sets)
    note = data.partial_note()
    imgs = "\n".join(f"<figure><img alt='{_e(name)}' src='data:image/png;base64,{_png(fig)}'>"
                     f"<figcaption>{_e(name)}</figcaption></figure>" for name, fig in figs.items())
    return (f"<h2>Study {_e(data.name)} <small>({_e(data.path)})</small></h2>"
            + (f"<p class=partial>{_e(note)}</p>" if note else "")
            + f"<p>{len(data.sets)} parameter set(s), {data.tasks_done} of {data.tasks_total} task(s) finished, "
              f"{data.tasks_failed} failed; curves from {_e(data.source)}. Varied keys: "
              f"{_e(', '.join(data.keys) or 'none')}.</p><p class=det>{_e(sets)}</p>"
            + f"<div class=figs>{imgs}</div>")


def write_report(dirs, out=None, figures=True):
    """Evaluate every claim on each study directory and write one HTML page; returns its path.

    out: the page (default: the first directory's report.html). Raises claims.StudyDirError for a
    directory that is not a study directory or has no finished task.
    """
    dirs = [Path(d) for d in dirs]
    datas = [C.read_study_dir(d) for d in dirs]
    results = [(d.name if sum(x.name == d.name for x in datas) == 1 else f"{d.name} ({d.path})", C.evaluate(d))
               for d in datas]
    sections = []
    for d in datas:
        figs = make_study_figures(d.path, data=d) if figures else {}
        sections.append(_study_section(d, figs))
    title = "Seed claims: " + ", ".join(d.name for d in datas)
    page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{_e(title)}</title><style>{_CSS}</style>"
            f"</head><body><h1>{_e(title)}</h1><p>Written {time.strftime('%Y-%m-%d %H:%M:%S %z')} by "
            f"<code>gfmd study report</code> from {_e(', '.join(str(d) for d in dirs))}. Seed: the adhesive rough "
            "line-contact paper (its Figs. 2–8).</p>"
            + ("".join(f"<p class=partial>{_e(d.name)}: {_e(d.partial_note())}</p>" for d in datas if d.partial))
            + "<h2>Claims</h2>" + _claims_table(results)
            + "<h2>Effect sizes and verdicts: definitions</h2>" + _definitions()
            + "".join(sections) + "</body></html>")
    out = Path(out) if out else dirs[0] / "report.html"
    safe_files.atomic_write(out, page)
    return out


def claims_text(dirs):
    """The claims table as plain text lines (for the terminal and the README)."""
    datas = [C.read_study_dir(d) for d in dirs]
    lines = []
    for claim, name, r, verdict in claims_rows([(d.name, C.evaluate(d)) for d in datas]):
        ms = r.measurements if r is not None else []
        single = len(ms) == 1 and not ms[0].context
        effect = f"{_num(ms[0])} (n = {ms[0].n})" if single else ("—" if not ms else "per context:")
        lines.append(f"{claim.figure:8} {claim.id:16} {name:18} {effect:32} {verdict}")
        if not single:
            lines += [f"{'':44}{m.context}: {_num(m)} (n = {m.n}) {m.verdict}" for m in ms]
    return lines
