"""Tests of the verification machinery itself: records, JSON, plots, HTML report, pytest glue (fast)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import textwrap
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from verification import report
from verification import plots as P
from verification.metrics import fitted_order, relative_l2
from verification.records import (SCHEMA_VERSION, Measurement, load_results, results_document, to_jsonable,
                                  write_results)

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}


class Checker(HTMLParser):
    """Tag balance (non-void HTML and all SVG elements), summary rows/verdicts, svg count, URLs."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack, self.errors, self.svg_roots, self.urls = [], [], 0, []
        self.doctype = None
        self.summary_cells, self._in_summary, self._row = [], False, None

    def handle_decl(self, decl):
        self.doctype = decl

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("src", "href", "xlink:href") and value and not value.startswith(("#", "data:")):
                self.urls.append(value)
        if tag == "svg" and "svg" not in self.stack:
            self.svg_roots += 1
        if tag == "table" and ("id", "summary-table") in attrs:
            self._in_summary = True
        if self._in_summary and tag == "tr":
            self._row = []
        if self._in_summary and tag == "td" and self._row is not None:
            self._row.append(dict(attrs).get("class", ""))
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)
        if tag not in VOID:
            self.handle_endtag(tag)

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes {self.stack[-1:]} at {self.getpos()}")
            if tag in self.stack:
                while self.stack and self.stack.pop() != tag:
                    pass
            return
        self.stack.pop()
        if tag == "tr" and self._in_summary and self._row:
            self.summary_cells.append(self._row)
            self._row = None
        if tag == "table" and self._in_summary:
            self._in_summary = False


def parse(text):
    c = Checker()
    c.feed(text)
    c.close()
    return c


def _records():
    x = np.linspace(-0.5, 0.5, 64)
    plots = [
        P.profile_plot(x, {"a": np.sin(x), "b": np.sin(x) + 1e-3}, xlabel="x", ylabel="y", title="profile"),
        P.curve_plot(np.arange(5.0), {"a": np.arange(5.0) ** 2}, xlabel="δ", ylabel="p", title="curve"),
        P.convergence_plot([1 / 8, 1 / 16, 1 / 32], [1e-2, 2.5e-3, 6.25e-4], title="conv"),
        P.table_plot(["k", "v"], [[1, 0.5], [2, np.float64(0.25)]], title="tab"),
        P.pareto_plot([{"label": "N=256", "method": "gfmd-fire", "time": 0.1, "error": 1e-2},
                       {"label": "N=512", "method": "gfmd-fire", "time": 0.3, "error": 3e-3},
                       {"label": "P2", "method": "fe-p2", "time": 2.0, "error": 1e-3}], title="pareto"),
        P.grid_plot(["case", "N=64", "N=1e6", "δn/l=0.5"],
                    [["φn* = 1e-4", {"status": "ok", "message": ""},
                      {"status": "fail", "message": "did not converge"},
                      {"status": "warn", "message": "under-resolved"}]],
                    title="extremes"),
    ]
    good = Measurement(case="demo/good", metric="rel. L2", value=np.float64(1e-4), tolerance=1e-3,
                       methods=("gfmd-fire", "fe-p2"), tolerance_source="study X",
                       resolution={"N": 1024, "mesh": "P2, 5 rows/level"}, wall_s=0.5, plots=plots)
    bad = Measurement(case="demo/bad", metric="max error", value=0.2, tolerance=0.01,
                      methods=("analytic-westergaard",), wall_s=1.0)
    nan = Measurement(case="demo/nan", metric="p", value=float("nan"), tolerance=1.0)
    info = Measurement(case="demo/info", metric="order", value=2.01)
    return [good, bad, nan, info]


def test_default_verdicts():
    good, bad, nan, info = _records()
    assert good.passed is True and bad.passed is False
    assert nan.passed is False  # NaN never passes
    assert info.passed is None  # no tolerance, no verdict
    assert Measurement(case="c", metric="m", value=5.0, tolerance=1.0, passed=True).passed is True


def test_json_round_trip(tmp_path):
    records = _records()
    path = tmp_path / "results.json"
    write_results(path, records, {"subset": "default", "exitstatus": 0})
    text = path.read_text()
    doc = json.loads(text)  # strict JSON: NaN was written as null
    assert "NaN" not in text and doc["schema"] == SCHEMA_VERSION
    assert {"code_version", "platform", "python", "date", "command"} <= set(doc["provenance"])
    doc2, back = load_results(path)
    assert [r.case for r in back] == [r.case for r in records]
    assert back[0].methods == ("gfmd-fire", "fe-p2") and back[0].resolution["mesh"] == "P2, 5 rows/level"
    assert back[0].value == pytest.approx(1e-4) and back[1].passed is False
    assert back[2].value is None and back[2].passed is False
    assert back[0].plots[0]["series"]["b"][3] == pytest.approx(np.sin(np.linspace(-0.5, 0.5, 64))[3] + 1e-3)
    # and once more: the JSON of the loaded records is the same document
    assert results_document(back, doc["session"])["records"] == doc["records"]


def test_to_jsonable():
    out = to_jsonable({"a": np.arange(3), 1: (np.int64(2), np.float32(0.5)), "inf": -math.inf,
                               "b": np.bool_(True), "p": Path("x/y")})
    assert out == {"a": [0, 1, 2], "1": [2, 0.5], "inf": None, "b": True, "p": "x/y"}
    json.dumps(out, allow_nan=False)


def test_html_well_formed_self_contained():
    records = _records()
    records[1].test_outcome = "failed"
    text = report.render_html(records, {"subset": "full", "exitstatus": 1, "exitstatus_name": "TESTS_FAILED",
                                        "counts": {"passed": 3, "failed": 1}})
    c = parse(text)
    assert c.doctype and c.doctype.lower() == "doctype html"
    assert not c.errors, c.errors[:5]
    assert not c.stack, f"unclosed: {c.stack}"
    assert len(c.summary_cells) == len(records)
    verdicts = [row[5] for row in c.summary_cells]
    assert verdicts == ["pass", "fail", "fail", "info"]
    assert "1 pass" in text and "2 fail" in text and "1 no tolerance (informational)" in text  # header counts all
    assert c.svg_roots == 4  # profile, curve, convergence, pareto (table and grid are HTML)
    assert c.urls == [], c.urls  # no external references of any kind
    assert "http://" not in text and "https://" not in text
    assert "<script" not in text and "<link" not in text
    assert "@media print" in text and "subset <strong>full</strong>" in text
    assert "did not converge" in text and 'class="fail"' in text  # grid cell
    assert '<td class="warn">warn' in text  # warnings have their own style
    assert "TESTS_FAILED" in text


def test_plot_error_is_shown_not_raised():
    html = report.render_plot({"kind": "profile", "x": [0, 1], "series": {"a": "not numbers"}})
    assert "could not be drawn" in html
    with pytest.raises(ValueError):
        P.validate_plot({"kind": "pie"})


def test_helpers():
    assert fitted_order([1, 0.5, 0.25], [1, 0.25, 0.0625]) == pytest.approx(2.0)
    pts = [{"time": 1, "error": 1}, {"time": 2, "error": 2}, {"time": 3, "error": 0.1}]
    assert report.pareto_front(pts) == [0, 2]
    assert relative_l2([1.0, 0.0], [1.0, 0.0]) == 0.0
    assert relative_l2([3.0, 4.0], [3.0, 4.5]) == pytest.approx(0.1)


PLUGIN_TEST = textwrap.dedent("""
    def test_one(verification_record):
        rec = verification_record(case="tmp/case", metric="err", value=0.5, tolerance=0.1,
                                  methods=("gfmd-fire",), plots=[{"kind": "curve", "x": [0, 1],
                                  "series": {"a": [0, 1]}, "title": "t"}])
        assert rec.passed is False and rec.wall_s >= 0 and rec.peak_memory_bytes >= 0

    def test_two():
        assert False
""")


def _run_pytest(tmp_path, *args):
    (tmp_path / "test_tmp_case.py").write_text(PLUGIN_TEST)
    root = Path(__file__).resolve().parent.parent
    cmd = [sys.executable, "-m", "pytest", "-p", "verification.conftest", "-q", "-p", "no:cacheprovider",
           "--rootdir", str(tmp_path), str(tmp_path / "test_tmp_case.py"), *args]
    env = {"PYTHONPATH": str(root), "PATH": "/usr/bin:/bin", "MPLBACKEND": "Agg"}
    return subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path, timeout=120, env=env)


def test_fixture_and_session_report(tmp_path):
    out = tmp_path / "rep"
    proc = _run_pytest(tmp_path, "--report-dir", str(out))
    assert proc.returncode == 1, proc.stdout + proc.stderr  # test_two fails: outcome unchanged by the report
    doc, records = load_results(out / "results.json")
    assert doc["session"]["exitstatus"] == 1 and doc["session"]["counts"]["failed"] == 1
    assert doc["session"]["counts"]["passed"] == 1 and doc["session"]["subset"] == "default"
    assert len(records) == 1 and records[0].passed is False and records[0].test_outcome == "passed"
    assert records[0].test.endswith("test_one")
    assert "verification report:" in proc.stdout
    c = parse((out / "index.html").read_text())
    assert not c.errors and len(c.summary_cells) == 1 and c.summary_cells[0][5] == "fail"


def test_report_failure_warns_without_crashing(tmp_path):
    blocker = tmp_path / "not-a-dir"
    blocker.write_text("a file where the report directory should go")
    proc = _run_pytest(tmp_path, "--report-dir", str(blocker), "-k", "test_one")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "verification report NOT written" in proc.stdout


def test_render_check_flags_a_broken_page(tmp_path):
    """The Chromium check fails on a console error, a missing image and an empty summary (skipped without Chromium)."""
    from verification import render_check
    if render_check.find_chromium() is None:
        pytest.skip("no Chromium (apt-get install -y chromium)")
    page = tmp_path / "index.html"
    page.write_text('<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>t</title></head><body>'
                    '<table id="summary-table"><tbody></tbody></table><img src="missing.png" alt="x">'
                    '<script>console.error("boom")</script></body></html>')
    proc = subprocess.run([sys.executable, "-m", "verification.render_check", str(page)], capture_output=True,
                          text=True, timeout=120, cwd=Path(__file__).resolve().parent.parent)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    for needle in ("summary table", "<img> not loaded", "boom"):
        assert needle in proc.stderr, proc.stderr
    assert (tmp_path / "screenshot.png").stat().st_size > 0


def test_scene_shown_once_per_case_and_round_trips(tmp_path):
    from gfmd_contact.core.scene import default_scene, load_scene
    sc = default_scene().replace(**{"surface.nodes": 8192})
    recs = [Measurement(case="c", metric=f"m{i}", value=1e-3, tolerance=1e-2, scene=sc) for i in range(3)]
    assert recs[0].scene.startswith("# resolved scene")  # a Scene is stored as its TOML
    text = report.render_html(recs)
    assert text.count('<details class="scene">') == 1 and "nodes = 8192" in text
    write_results(tmp_path / "r.json", recs)
    _, back = load_results(tmp_path / "r.json")
    (tmp_path / "default.toml").write_text(back[0].scene)
    assert load_scene(tmp_path / "default.toml") == sc


def test_summary_folds_long_cases_but_never_a_failure():
    recs = [Measurement(case="sweep", metric=f"cell {i}", value=1e-3, tolerance=1e-2) for i in range(20)]
    recs[15] = Measurement(case="sweep", metric="cell 15", value=1.0, tolerance=1e-2)  # a late failure
    recs.append(Measurement(case="other", metric="m", value=1e-3, tolerance=1e-2))
    text = report.render_html(recs)
    c = parse(text)
    assert not c.errors and not c.stack
    summary = text[text.index('id="summary-table"'):text.index("</table>", text.index('id="summary-table"'))]
    assert "<td>cell 15</td>" in summary and "<td>cell 9</td>" not in summary and "<td>m</td>" in summary
    assert len(c.summary_cells) == report.SUMMARY_ROWS_PER_CASE + 1 + 1 + 1  # shown, failure, other, fold row
    assert summary.count('class="row-folded"') == 1 and "11 more measurements of this case (11 pass)" in summary


def test_measured_data_round_trip(tmp_path, monkeypatch):
    """Data files: entries carry their provenance, writing merges by key, a missing entry names the study."""
    from verification import measured
    monkeypatch.setattr(measured, "DATA_DIR", tmp_path)
    with pytest.raises(measured.MissingMeasurement, match="python -m verification.studies.demo --write"):
        measured.load("demo")
    measured.write("demo", {"a": measured.make_entry({"x": [1.23456789e-7, 2.0]}, scene="scenes.demo(N)")})
    measured.write("demo", {"b": measured.make_entry({"x": float("nan")})}, description="demo study")
    doc = json.loads((tmp_path / "demo.json").read_text())
    assert doc["study"] == "verification.studies.demo" and doc["description"] == "demo study"
    assert sorted(doc["entries"]) == ["a", "b"] and doc["entries"]["b"]["values"]["x"] is None
    assert measured.value("demo", "a", "x") == [1.235e-7, 2.0]  # stored to 4 significant digits
    assert {"code_version", "date", "scene"} <= set(measured.entry("demo", "a"))
    with pytest.raises(measured.MissingMeasurement, match="no measured entry 'c'"):
        measured.entry("demo", "c")


def test_data_files_name_their_study():
    """Every data file under verification/data/ names its study, and every entry its code version and date."""
    from verification import measured
    files = sorted(measured.DATA_DIR.glob("*.json"))
    assert {p.stem for p in files} >= {"westergaard", "speed_accuracy", "extremes"}
    for p in files:
        doc = measured.load(p.stem)
        assert doc["study"] == f"verification.studies.{p.stem}" and doc["entries"], p
        assert all({"code_version", "date", "values"} <= set(e) for e in doc["entries"].values()), p


def test_worst_does_not_drop_a_nan():
    """Python's max([1e-3, nan]) is 1e-3: a failed measurement would pass as a small error."""
    import math

    from verification.metrics import worst, worst_signed

    assert math.isnan(worst([1e-3, float("nan")])) and math.isnan(worst([float("nan"), 1e-3]))
    assert worst([1e-3, 2e-3]) == 2e-3
    assert math.isnan(worst_signed([-0.2, float("nan"), 0.1])) and worst_signed([-0.2, 0.1]) == -0.2
    with pytest.raises(ValueError):
        worst([])


def test_a_test_that_failed_unrecorded_appears_as_a_failure():
    from verification.records import Measurement, failure_records

    recorded = [Measurement(case="a", metric="m", value=1.0, test="verification/test_a.py::test_ok")]
    failures = {"verification/test_a.py::test_ok": ("failed", "after recording"),
                "verification/test_b.py::test_x[1]": ("error", "Traceback ... ImportError")}
    extra = failure_records(failures, recorded)
    assert [r.test for r in extra] == ["verification/test_b.py::test_x[1]"]
    assert extra[0].passed is False and extra[0].case == "test_b" and "ImportError" in extra[0].notes


def test_report_dir_without_a_test_path_keeps_the_outcomes(tmp_path):
    """`pytest --report-dir DIR` from the root, no test path: pytest takes DIR for a path, finds
    verification/conftest.py only while collecting (after session start), and the outcomes of the
    verification tests were lost (a failing case then read as its recorded verdict)."""
    out = tmp_path / "report"
    root = Path(__file__).resolve().parent.parent
    if not (root / "pyproject.toml").is_file():
        pytest.skip("a source checkout's behaviour (pytest from its root); this suite is an installed package")
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--report-dir", str(out),
                          "-k", "test_hertz_convergence and not fine"], cwd=root, capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    records = json.loads((out / "results.json").read_text())["records"]
    assert records and {r["test_outcome"] for r in records} == {"passed"}


def test_tolerance_list_is_generated_from_the_records():
    """Every record with a tolerance is listed with the number it rests on, the ratio, the study; > 10 is loose."""
    from verification.records import LOOSE_RATIO, tolerance_rows
    recs = [Measurement(case="a", metric="stored", value=1e-4, tolerance=3e-4, measured=2e-4,
                        measured_source="verification.studies.x → verification/data/x.json [ci].p"),
            Measurement(case="a", metric="loose", value=1e-5, tolerance=1e-3, measured=2e-5),
            Measurement(case="b", metric="rule", value=1e-5, tolerance=1e-3),
            Measurement(case="b", metric="informational", value=1.0)]
    rows = tolerance_rows(recs)
    assert [r["metric"] for r in rows] == ["stored", "loose", "rule"]
    assert rows[0]["ratio"] == pytest.approx(1.5) and rows[0]["basis"] == "stored" and not rows[0]["loose"]
    assert rows[1]["ratio"] == pytest.approx(50) and rows[1]["loose"] and 50 > LOOSE_RATIO
    assert rows[2]["basis"] == "this run" and rows[2]["ratio"] == pytest.approx(100) and rows[2]["loose"]
    page = report.render_html(recs, {})
    assert 'id="tolerance-table"' in page and "data/x.json [ci].p" in page and page.count(" loose</td>") == 2
    Checker().feed(page)


def test_measured_lookups_become_the_record_source():
    """The fixture fills measured_source from the look-ups made since the test started."""
    from verification import measured
    start = measured.reset_accesses()
    measured.entry("fe_cohesive", "full")
    measured.value("fe_cohesive", "full", "N")
    assert measured.accessed_sources(start) == [
        "verification.studies.fe_cohesive → verification/data/fe_cohesive.json [full].N"]


def test_independence_section_lists_the_architecture_allow_list():
    """The shared inputs are read from tests/test_architecture.py's FE_MAY_IMPORT, not copied."""
    import importlib
    from verification.independence import INDEPENDENT, PURPOSE, ROOT, allowed_imports, fe_shared_inputs
    if not (ROOT / "tests" / "test_architecture.py").is_file():
        pytest.skip("the allow list is tests/test_architecture.py of the source checkout; this suite is installed")
    info = fe_shared_inputs()
    assert {m for m, _, _ in info["shared"]} == allowed_imports() and not info["not_allowed"]
    assert all(m in PURPOSE for m in allowed_imports()), "describe every shared module"
    for mod in INDEPENDENT.values():
        importlib.import_module(mod)
    page = "\n".join(report._independence_section())
    assert all(f"<code>{m}</code>" in page for m in allowed_imports())


def test_lower_bounds_in_the_tolerance_list():
    """A lower bound (an order, a refinement ratio) passes when value ≥ tolerance; its ratio is measured / bound."""
    from verification.records import tolerance_rows
    ok = Measurement(case="c", metric="ratio", value=5.0, tolerance=2.0, measured=4.0, lower_bound=True)
    bad = Measurement(case="c", metric="ratio", value=1.0, tolerance=2.0, measured=4.0, lower_bound=True)
    assert ok.passed is True and bad.passed is False
    assert tolerance_rows([ok])[0]["ratio"] == pytest.approx(2.0) and tolerance_rows([ok])[0]["lower"]
    assert "≥ 2" in report.render_html([ok], {})
