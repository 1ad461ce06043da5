"""Run a cross-code case against one solver, and keep the outcome: one record per metric (or one "n/a" record
with the adapter's reason), stored per solver in `cross_code-<solver>.json` of the report directory, so that
the runs of several `--solver` sessions combine on one page.
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

from verification.solvers.protocol import not_applicable

FILE_PREFIX = "cross_code-"


def _record(case, solver, **kw):
    base = {"case": case.name, "solver": solver.name, "reference": case.reference, "metric": "", "error": None,
            "tolerance": None, "lower_bound": False, "passed": None, "reason": "", "wall_s": None,
            "iterations": None, "resolution": "", "ran": "", "tolerance_source": case.tolerance_source}
    base.update(kw)
    return base


def _verdict(value, tolerance, lower):
    if value is None or not math.isfinite(value):
        return False
    return bool(value >= tolerance if lower else value <= tolerance)


def run_case(solver, case):
    """The records of `case` solved by `solver`: n/a with the reason, failed with the error message, or one
    per metric with the error, tolerance, cost and verdict."""
    problems = case.problems()
    reasons = [r for r in (not_applicable(solver, p) for p in problems) if r]
    if reasons:
        return [_record(case, solver, reason=reasons[0])]
    t0, answers = time.perf_counter(), []
    try:
        answers = [solver.solve(p) for p in problems]
    except Exception as exc:  # noqa: BLE001 - a code that fails on a case fails the case, with its words
        return [_record(case, solver, passed=False, reason=f"{type(exc).__name__}: {exc}",
                        wall_s=time.perf_counter() - t0)]
    errors, tolerances = case.errors(answers, problems), case.tolerances()
    iterations = [a.cost.iterations for a in answers]
    cost = {"wall_s": sum(a.cost.wall_s for a in answers),
            "iterations": None if None in iterations else sum(iterations),
            "resolution": " + ".join("×".join(str(n) for n in p.heights.shape) for p in problems),
            "ran": answers[-1].ran}
    lower = set(case.minimum)
    records = [_record(case, solver, metric=m, error=float(errors[m]), tolerance=float(tolerances[m]),
                       lower_bound=m in lower, passed=_verdict(float(errors[m]), tolerances[m], m in lower), **cost)
               for m in tolerances]
    if case.sweep is not None:  # one (nodes, wall time, error) point per resolution, for the speed–accuracy plot
        records[0]["sweep"] = [{"nodes": int(p.heights.size), "wall_s": a.cost.wall_s,
                                "error": float(case.sweep(a, p))} for a, p in zip(answers, problems)]
    return records


def results_path(report_dir, solver_name):
    return Path(report_dir) / f"{FILE_PREFIX}{solver_name}.json"


def store(report_dir, solver_name, records):
    """Replace this solver's records of the cases in `records` in its file; keep its other cases."""
    path = results_path(report_dir, solver_name)
    old = json.loads(path.read_text()) if path.is_file() else {"solver": solver_name, "records": []}
    cases = {r["case"] for r in records}
    old["records"] = [r for r in old["records"] if r["case"] not in cases] + list(records)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(old, indent=1, ensure_ascii=False))
    return path


def load_all(report_dir):
    """Every solver's records found in `report_dir`: {solver: [records]}."""
    out = {}
    for path in sorted(Path(report_dir).glob(f"{FILE_PREFIX}*.json")):
        doc = json.loads(path.read_text())
        out[doc["solver"]] = doc["records"]
    return out
