"""Measured cost of finished studies: per study its wall time, per parameter set its task times and algorithms.

Usage: python benchmarks/study_costs.py DIR [DIR ...] [--out FILE.md]

Reads what `gfmd study run` wrote (DIR/study.json, DIR/tasks/<key>/curve.csv and meta.json); computes nothing
anew. Per study: tasks, load steps, wall time (study.json timings: the last run's where the study was resumed),
the sum of the task times (meta.json timings.total_s: the time each task spent on its worker, or for a task resumed
after an interruption the sum of its steps' wall times, which covers every run; tasks that shared a solve,
study.json `solved_with`, carry the shared solve's time and count once) and how close the workers came to the
ideal sum / workers. Per set: its parameters, the median and largest task time, load steps per task-second, the
mean iterations per step, and the steps per algorithm label (curve.csv `algorithm`, e.g. "newton→fire": the
continuation Newton gave the step to FIRE; `gfmd.chains`). Task times are wall seconds on a worker, so they
include what else ran on the machine: say what did when quoting them.
"""

from __future__ import annotations

import argparse
import csv
import json
import statistics
import sys
from collections import Counter
from pathlib import Path


def task_costs(task_dir):
    """{'total_s', 'steps', 'iterations', 'algorithms': Counter, 'step_wall_s': [..]} of one task (None: unfinished)."""
    meta = json.loads((task_dir / "meta.json").read_text())
    if not meta.get("complete"):
        return None
    with open(task_dir / "curve.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    step_wall = [float(r["wall_s"]) for r in rows]
    total = float(meta["timings"]["total_s"])
    # a task resumed after an interruption: total_s is the last run's, its steps' wall times cover the whole ramp
    resumed = sum(step_wall) > total
    return {"total_s": max(total, sum(step_wall)), "steps": len(rows), "resumed": resumed,
            "iterations": sum(int(r["iterations"]) for r in rows),
            "algorithms": Counter(r.get("algorithm", "") for r in rows),
            "step_wall_s": step_wall}


def study_costs(out):
    """(study.json record, [(set, parameters, [task_costs ...])]) of a finished study directory."""
    out = Path(out)
    record = json.loads((out / "study.json").read_text())
    sets = {}
    for t in record["tasks"]:
        task_dir = out / "tasks" / t["key"]
        if not (task_dir / "meta.json").is_file() or not (task_dir / "curve.csv").is_file():
            continue
        costs = task_costs(task_dir)
        if costs is not None:
            costs["shared"] = bool(t.get("solved_with"))  # its time is the shared solve's, counted once
            sets.setdefault(t["set"], (t["parameters"], []))[1].append(costs)
    return record, [(s, p, c) for s, (p, c) in sorted(sets.items())]


def _params(p):
    short = {"interface.": "", "material.": "", "surface.": ""}
    text = []
    for k, v in p.items():
        for prefix, repl in short.items():
            k = k.replace(prefix, repl)
        text.append(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}")
    return ", ".join(text)


def report(dirs):
    """Markdown: one study table (wall time) and one set table per study."""
    lines = ["| study | tasks | solves | load steps | wall (min) | sum of solve times (min) | workers | efficiency | code |",
             "|---|---|---|---|---|---|---|---|---|"]
    per_set = []
    for d in dirs:
        record, sets = study_costs(d)
        costs = [c for _, _, cs in sets for c in cs]
        wall = record.get("timings", {}).get("wall_s")
        workers = record.get("timings", {}).get("workers") or 1
        total = sum(c["total_s"] for c in costs if not c["shared"])  # a shared solve once
        steps = sum(c["steps"] for c in costs)
        eff = total / (workers * wall) if wall else float("nan")
        resumed = sum(c["resumed"] for c in costs)
        lines.append(f"| {record['study']} | {len(costs)}/{record['tasks_total']}"
                     f"{f' ({resumed} resumed)' if resumed else ''} | "
                     f"{sum(not c['shared'] for c in costs)} | {steps} | "
                     f"{wall / 60 if wall else float('nan'):.1f} | {total / 60:.1f} | {workers} | {eff:.0%} | "
                     f"{', '.join(record.get('code_versions', []))} |")
        per_set += ["", f"### {record['study']}", "",
                    "| set | parameters | tasks | task s median / max | steps per task-s | iterations per step | "
                    "slowest step s | algorithms (steps) |", "|---|---|---|---|---|---|---|---|"]
        for s, p, cs in sets:
            times = [c["total_s"] for c in cs]
            n_steps = sum(c["steps"] for c in cs)
            algos = sum((c["algorithms"] for c in cs), Counter())
            slowest = max(max(c["step_wall_s"]) for c in cs)
            per_set.append(
                f"| {s} | {_params(p)} | {len(cs)} | {statistics.median(times):.1f} / {max(times):.1f} | "
                f"{n_steps / sum(times):.2f} | {sum(c['iterations'] for c in cs) / n_steps:.1f} | {slowest:.1f} | "
                + ", ".join(f"{k} {v}" for k, v in algos.most_common()) + " |")
    return "\n".join(lines + per_set) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+", type=Path, help="finished study directories")
    ap.add_argument("--out", type=Path, help="also write the tables to this markdown file")
    args = ap.parse_args(argv)
    for d in args.dirs:
        if not (d / "study.json").is_file():
            ap.error(f"{d} holds no study.json: not a study directory")
    text = report(args.dirs)
    print(text)
    if args.out:
        args.out.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
