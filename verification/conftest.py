"""pytest glue for verification: the `verification_record` fixture and the report.

Every measurement a verification test records goes to one session-wide list;
at session end `reports/results.json` (machine-readable) and
`reports/index.html` (self-contained page, `verification.report`) are written
— to `--report-dir DIR` (or $GFMD_REPORT_DIR) instead of `reports/` if given. They are written only
if a measurement was recorded or a test under `verification/` ran. A failure
while writing prints a clear warning and never changes the session's outcome.

Fixture (see `verification.records.Measurement` for the fields):

    def test_x(verification_record):
        verification_record(case="…", metric="…", value=…, tolerance=…,
                            methods=("gfmd-fire", "fe-p2"), tolerance_source="…",
                            resolution={"N": 1024}, wall_s=…, passed=None, plots=[…],
                            scene=scene,  # a gfmd Scene (stored as TOML, shown in the report) or ""
                            measured=…)  # the stored number the tolerance rests on (the list of tolerances)

wall_s defaults to the time since the test started, peak memory to the
process ru_maxrss delta since then; passed defaults to |value| ≤ tolerance.
measured_source defaults to the `verification.measured` look-ups the test made so far (study → data
file [entry].value). The fixture returns the `Measurement`; the test still asserts on its own.
"""

from __future__ import annotations

import os
import sys
import time
import traceback
from pathlib import Path

import pytest

from verification import measured as _measured
from verification.provenance import MEMORY_RSS, max_rss_bytes
from verification.records import Measurement, failure_records, write_results

_VERIFICATION_DIR = Path(__file__).resolve().parent
_RECORDS_KEY = pytest.StashKey[list]()
_STATE_KEY = pytest.StashKey[dict]()


def pytest_addoption(parser):
    # pytest only sees this when verification/ is on the command line (`pytest verification …`): a
    # conftest below the rootdir is loaded after option parsing otherwise. The root conftest may add
    # the same option (then this one is skipped); $GFMD_REPORT_DIR works in every case.
    try:
        parser.addoption("--report-dir", action="store", default=None, metavar="DIR",
                         help="where the verification report (results.json, index.html) is written "
                              "(default: $GFMD_REPORT_DIR, else reports/ under the repository root)")
    except ValueError:  # already added by the root conftest
        pass


def pytest_configure(config):
    # a historic hook: it also runs when this conftest is found only during collection (`pytest`
    # from the root without a path), where pytest_sessionstart has already run and is not replayed
    _CONFIG["config"] = config
    config.stash[_RECORDS_KEY] = []
    config.stash[_STATE_KEY] = {"outcomes": {}, "verification_ran": False, "started": time.time(),
                                "counts": {"passed": 0, "failed": 0, "error": 0, "skipped": 0,
                                           "xfailed": 0, "xpassed": 0}}


def _is_verification(nodeid, config):
    path = Path(str(config.rootpath)) / nodeid.split("::")[0]
    if config.getoption("pyargs", default=False) and (_VERIFICATION_DIR / nodeid.split("::")[0]).is_file():
        return True  # `pytest --pyargs verification` of an installed package: node ids relative to the package
    try:
        path.resolve().relative_to(_VERIFICATION_DIR)
        return True
    except ValueError:
        return False


@pytest.hookimpl(trylast=True)
def pytest_runtest_logreport(report):
    # called through the item's ihook: only for tests under verification/ (whole-session counts
    # come from the terminal reporter at session end)
    config = _CONFIG.get("config")
    if config is None or _STATE_KEY not in config.stash:
        return
    state = config.stash[_STATE_KEY]
    counts, outcomes = state["counts"], state["outcomes"]
    outcome = None
    if report.when == "call" or (report.when == "setup" and not report.passed):
        if hasattr(report, "wasxfail"):
            outcome = "xfailed" if report.skipped else "xpassed"
        elif report.failed:
            outcome = "failed" if report.when == "call" else "error"
        else:
            outcome = report.outcome  # passed / skipped
    elif report.when == "teardown" and report.failed:
        outcome = "error"
    if outcome is None:
        return
    counts[outcome] = counts.get(outcome, 0) + 1
    if outcome != "error" or outcomes.get(report.nodeid) in (None, "passed"):
        outcomes[report.nodeid] = outcome
    if outcome != "skipped" and _is_verification(report.nodeid, config):
        state["verification_ran"] = True
        if outcome in ("failed", "error"):  # kept for the summary even if nothing was recorded
            state.setdefault("failures", {})[report.nodeid] = (outcome, str(report.longreprtext)[-600:])


_CONFIG = {}


@pytest.hookimpl(tryfirst=True)
def pytest_sessionstart(session):
    _CONFIG["config"] = session.config


@pytest.fixture
def verification_record(request):
    """Callable that records one measurement (see module docstring); returns the Measurement."""
    records = request.config.stash[_RECORDS_KEY]
    t0 = time.perf_counter()
    rss0 = max_rss_bytes()
    looked_up = _measured.reset_accesses()

    def record(*, case, metric, value, tolerance=None, methods=(), tolerance_source="", resolution=None,
               wall_s=None, passed=None, plots=None, peak_memory_bytes=None, memory_method=None, notes="",
               scene="", measured=None, measured_source=None, lower_bound=False):
        if peak_memory_bytes is None:
            peak_memory_bytes = max(0, max_rss_bytes() - rss0)
            memory_method = memory_method or MEMORY_RSS + ", since test start"
        if wall_s is None:
            wall_s = time.perf_counter() - t0
        rec = Measurement(case=case, metric=metric, value=value, tolerance=tolerance,
                          tolerance_source=tolerance_source, methods=methods, resolution=resolution or {},
                          wall_s=wall_s, peak_memory_bytes=peak_memory_bytes, memory_method=memory_method or "",
                          passed=passed, plots=plots or [], notes=notes, test=request.node.nodeid,
                          scene=scene if scene is not None else "", measured=measured, lower_bound=lower_bound,
                          measured_source=("\n".join(_measured.accessed_sources(looked_up))
                                           if measured_source is None else measured_source))
        records.append(rec)
        return rec

    return record


def _session_counts(config, state):
    """Outcome counts of the whole session (terminal reporter), else of the verification tests only."""
    tr = config.pluginmanager.get_plugin("terminalreporter")
    if tr is not None and hasattr(tr, "stats"):
        keys = ("passed", "failed", "error", "skipped", "xfailed", "xpassed", "deselected")
        return {k: len(tr.stats.get(k, [])) for k in keys}
    return dict(state["counts"], scope="verification tests only")


def _report_dir(config):
    opt = config.getoption("--report-dir", default=None) or os.environ.get("GFMD_REPORT_DIR")
    return Path(opt) if opt else Path(str(config.rootpath)) / "reports"


def _warn(config, text):
    tr = config.pluginmanager.get_plugin("terminalreporter")
    if tr is not None:
        tr.write_line(text, yellow=True, bold=True)
    else:
        print(text, file=sys.stderr)


def pytest_sessionfinish(session, exitstatus):
    config = session.config
    if _RECORDS_KEY not in config.stash or hasattr(config, "workerinput"):  # xdist workers: controller writes
        return
    records = config.stash[_RECORDS_KEY]
    state = config.stash[_STATE_KEY]
    if not records and not state["verification_ran"]:
        return
    try:
        from verification import report
        records = records + failure_records(state.get("failures", {}), records)
        for r in records:
            r.test_outcome = state["outcomes"].get(r.test, "")
        try:
            name = pytest.ExitCode(int(exitstatus)).name
        except ValueError:
            name = ""
        session_info = {
            "subset": "full" if config.getoption("--full", default=False) else "default",
            "exitstatus": int(exitstatus),
            "exitstatus_name": name,
            "counts": _session_counts(config, state),
            "collected": session.testscollected,
            "duration_s": round(time.time() - state["started"], 2),
            "args": list(config.invocation_params.args),
        }
        out = _report_dir(config)
        write_results(out / "results.json", records, session_info)
        report.write_report(out / "index.html", records, session_info)
        config.stash[_STATE_KEY]["written"] = out
    except Exception as exc:  # noqa: BLE001 - never crash the session for the report, but say so loudly
        _warn(config, "WARNING: verification report NOT written: "
                      f"{type(exc).__name__}: {exc}\n{traceback.format_exc()}")


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    # sessionfinish runs before the terminal summary: report where the files went
    out = config.stash.get(_STATE_KEY, {}).get("written") if _STATE_KEY in config.stash else None
    if out is not None:
        terminalreporter.write_line(f"verification report: {out / 'index.html'} (data: {out / 'results.json'})")
