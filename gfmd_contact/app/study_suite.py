"""Suites: several study files run as one resumable job that computes each distinct task once.

`gfmd study run A.toml B.toml ... --out DIR` gives every study its ordinary study directory
DIR/<study name>/ (what `gfmd study run A.toml --out DIR/<name>` writes there: self-contained,
movable, read by `gfmd study plot / report` unchanged) and runs them on one Dask cluster:

- the union of the studies' pending tasks is submitted once per distinct key (`gfmd_contact.app.study_file`
  task_key), longest first (`gfmd_contact.app.study_file.longest_first`);
- a task is computed in the directory of the first study (command-line order) that needs it, or,
  where an interrupted run left saved load steps, in the one holding the most of them (it continues
  there); when it finishes, every other study that needs it gets a hard-linked copy in its own
  tasks/<key>/ (`link_task`: files os.link'ed, copied across file systems), published by one rename;
- a key complete in ANY of the study directories counts as done and is linked where missing, so a
  rerun resumes, and a study directory computed before (alone) at DIR/<name> is reused;
- each study's tables and study.json are written as soon as its last task is done. study.json gives
  a task's status "reused" (complete in this directory before), "run" (computed here), "linked"
  (from a sibling study, named by "linked_from") or "failed"; tasks_linked; timings: wall_s (from
  the suite's start to this study's tables) and suite_wall_s (added when the suite ends); and
  "suite" (the sibling studies).
- DIR/suite.json: the files, the studies (name, file, tasks, distinct tasks, run / reused /
  linked / failed), distinct_tasks, tasks_linked, tasks_solved_with (tasks observed on another
  task's solve: `gfmd_contact.app.study_task.run_shared`), timings, the code version, "complete".

DIR and every study directory are locked (`safe_files.locked`) while the suite runs; an interrupt
or kill -9 loses at most the load steps in flight (tasks write step by step), as for one study.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import sys
import time
from pathlib import Path

from . import io, safe_files
from .run_dir import code_version
from .study import _record, _saved_steps, compute_tasks, finish_study, open_study_dir
from .study_file import StudyError, longest_first

#: the suffix of a task directory being linked (tasks/.<key>.link), renamed to tasks/<key> when whole
LINKING = ".link"


def check_names(studies):
    """Refuse two studies of one name (they would share DIR/<name>), naming both files."""
    seen = {}
    for s in studies:
        if s.name in seen:
            raise StudyError(f"study name {s.name!r} is given by both {seen[s.name].path} and {s.path}: "
                             "a suite needs distinct names (set name = \"...\" in one of them)")
        seen[s.name] = s


def _link_or_copy(src, dst):
    try:
        os.link(src, dst)
    except OSError as exc:
        if exc.errno not in (errno.EXDEV, errno.EPERM, errno.EMLINK, errno.ENOTSUP):
            raise
        shutil.copy2(src, dst)  # another file system, or one without hard links


def link_task(src, dst):
    """Give `dst` (a task directory) the complete task of `src` as hard links (a copy across file systems).

    Built in dst's sibling .<key>.link, meta.json (what marks a task complete) last, then renamed to
    `dst`, which an incomplete task directory there gives way to: an interrupted link leaves no task
    that looks complete. The lock file, partial/ and temporaries of `src` are left out.
    """
    src, dst = Path(src), Path(dst)
    tmp = dst.parent / f".{dst.name}{LINKING}"
    with safe_files.writing(dst):
        shutil.rmtree(tmp, ignore_errors=True)
        tmp.mkdir()
        files = [p for p in sorted(src.rglob("*")) if p.is_file() and p.name != safe_files.LOCK_NAME
                 and io.PARTIAL not in p.relative_to(src).parts and not p.name.endswith(".tmp")]
        for p in sorted(files, key=lambda p: p.relative_to(src) == Path("meta.json")):
            target = tmp / p.relative_to(src)
            target.parent.mkdir(parents=True, exist_ok=True)
            _link_or_copy(p, target)
        if dst.exists():
            shutil.rmtree(dst)
        tmp.rename(dst)


def _prepare_suite_dir(out):
    out = Path(out).resolve()
    if out.exists() and not out.is_dir():
        raise io.RunDirError(f"--out {str(out)!r} is an existing file, not a directory: choose another --out")
    if (out / "study.json").is_file():
        raise io.RunDirError(f"--out {out} holds one study (study.json): a suite of several study files writes "
                             "DIR/<study name>/ for each; choose another --out")
    return out


def run_suite(studies, out, *, workers=None, scheduler=None, progress=True, command=None, wait=0):
    """Run the studies as one suite into `out` (module docstring); returns the suite.json dict.

    workers, scheduler, wait, interrupts and disk errors: as `gfmd_contact.app.study.run_study`.
    """
    check_names(studies)
    out = _prepare_suite_dir(out)
    command = command or " ".join(sys.argv)
    note = (lambda line: print(f"note: {line}", file=sys.stderr)) if progress else None
    advice = "wait for it to end (or add --wait to wait for it), or stop it first; or choose another --out"
    with contextlib.ExitStack() as stack:
        stack.enter_context(safe_files.locked(out, wait=wait, what="suite directory", command=command,
                                              advice=advice, note=note))
        for s in studies:
            stack.enter_context(safe_files.locked(out / s.name, wait=wait, what="study directory",
                                                  command=command, advice=advice, note=note))
        return _run_suite_locked(studies, out, workers, scheduler, progress, command)


def _run_suite_locked(studies, out, workers, scheduler, progress, command):
    start = time.perf_counter()
    by_name = {s.name: s for s in studies}
    dirs, done = {}, {}
    for s in studies:
        for tmp in (out / s.name / "tasks").glob(f".*{LINKING}"):  # an interrupted link
            shutil.rmtree(tmp, ignore_errors=True)
        dirs[s.name], done[s.name] = open_study_dir(s, out / s.name, progress)
    needs, scene_of = {}, {}  # key -> the studies needing it (command-line order); key -> a Task of it
    for s in studies:
        for t in s.tasks:
            if s.name not in needs.setdefault(t.key, []):
                needs[t.key].append(s.name)
            scene_of.setdefault(t.key, t)
    zero = {"steps_reused": 0, "steps_run": 0}
    outcomes = {s.name: {k: {"status": "reused", **zero} for k in done[s.name]} for s in studies}
    failures = {s.name: {} for s in studies}

    def link(key, source, names):
        for n in names:
            if n != source and key not in outcomes[n]:
                link_task(dirs[source] / "tasks" / key, dirs[n] / "tasks" / key)
                outcomes[n][key] = {"status": "linked", "linked_from": source, **zero}

    for key, names in needs.items():  # complete in any study directory: done, linked where missing
        have = [n for n in names if key in done[n]]
        if have:
            link(key, have[0], names)
    pending = [k for k, names in needs.items() if not any(k in done[n] for n in names)]
    saved = {(n, k): _saved_steps(dirs[n] / "tasks" / k, scene_of[k].scene) for k in pending for n in needs[k]}
    home = {k: max(needs[k], key=lambda n: (saved[n, k], -needs[k].index(n))) for k in pending}
    left = {s.name: {t.key for t in s.tasks} & set(pending) for s in studies}
    workers = (workers or os.cpu_count() or 1) if pending else workers
    records, stop = {}, []
    info = {"suite": {"file": "../suite.json", "studies": [s.name for s in studies]}}

    def finish(name):
        outcome = outcomes[name]
        extra = {**info, "tasks_linked": sum(1 for o in outcome.values() if o["status"] == "linked")}
        records[name] = finish_study(by_name[name], dirs[name], outcome, failures[name],
                                     wall=time.perf_counter() - start, workers=None if scheduler else workers,
                                     scheduler=scheduler, command=command, extra=extra)

    suite = _suite_record(studies, out, needs, records, outcomes, failures, None, workers, scheduler, command)
    io._atomic_write(out / "suite.json", json.dumps(suite, indent=2))
    for s in studies:
        if left[s.name]:
            io._atomic_write(dirs[s.name] / "study.json",
                             json.dumps({**_record(s, dirs[s.name], s.tasks, {}, {}, complete=False), **info},
                                        indent=2))
        else:
            finish(s.name)  # nothing to compute: its tables now

    def finished(key, outcome, failure, disk_error):
        if disk_error:
            stop.append(key)  # the disk is full or read-only: no more tables (raised after the cluster closed)
        source = home[key]
        if failure is None:
            outcomes[source][key] = outcome
            link(key, source, needs[key])
        for n in needs[key]:
            if failure is not None:
                failures[n][key] = failure
            left[n].discard(key)
            if not left[n] and not stop:
                finish(n)

    if pending:
        jobs = [(t.key, t.scene, dirs[home[t.key]] / "tasks" / t.key)
                for t in longest_first([scene_of[k] for k in pending])]
        compute_tasks(jobs, finished, workers=workers, scheduler=scheduler, progress=progress, command=command,
                      name="suite", total=len(needs), initial=len(needs) - len(pending),
                      steps_total=sum(scene_of[k].scene.loading.steps + 1 for k in needs),
                      steps_saved=sum(scene_of[k].scene.loading.steps + 1 for k in needs if k not in pending)
                      + sum(saved[home[k], k] for k in pending))
    wall = time.perf_counter() - start
    for name, record in records.items():  # the suite's wall time in every study's timings
        record["timings"]["suite_wall_s"] = wall
        io._atomic_write(dirs[name] / "study.json", json.dumps(record, indent=2))
    suite = _suite_record(studies, out, needs, records, outcomes, failures, wall, workers, scheduler, command)
    io._atomic_write(out / "suite.json", json.dumps(suite, indent=2))
    return suite


def _suite_record(studies, out, needs, records, outcomes, failures, wall, workers, scheduler, command):
    rows = []
    for s in studies:
        keys = {t.key for t in s.tasks}
        status = [outcomes[s.name].get(k, {}).get("status") for k in keys if k not in failures[s.name]]
        rows.append({"name": s.name, "file": str(s.path) if s.path else None, "dir": s.name,
                     "tasks": len(s.tasks), "distinct_tasks": len(keys), "complete": s.name in records,
                     "tasks_run": status.count("run"), "tasks_reused": status.count("reused"),
                     "tasks_linked": status.count("linked"), "tasks_failed": len(failures[s.name]),
                     "wall_s": records[s.name]["timings"]["wall_s"] if s.name in records else None})
    return {
        "complete": wall is not None and len(records) == len(studies),
        "files": [r["file"] for r in rows],
        "studies": rows,
        "tasks_total": sum(r["tasks"] for r in rows),
        "distinct_tasks": len(needs),
        "tasks_run": sum(r["tasks_run"] for r in rows),
        "tasks_linked": sum(r["tasks_linked"] for r in rows),
        "tasks_solved_with": sum(1 for o in outcomes.values() for v in o.values() if "solved_with" in v),
        "tasks_failed": len({k for f in failures.values() for k in f}),
        "code_version": code_version(),
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": command,
        "timings": {"wall_s": wall, "workers": None if scheduler else workers, "scheduler": scheduler},
    }


def suite_done(studies, out):
    """How many distinct tasks of the studies are complete in any of their directories under `out`."""
    out = Path(out)
    keys = {(t.key, s.name) for s in studies for t in s.tasks}
    return len({k for k, n in keys if io.run_complete(out / n / "tasks" / k)})
