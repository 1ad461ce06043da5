"""Studies: run a grid of scenes × realizations as one resumable, content-addressed command on Dask.

The study file and its tasks are `gfmd_contact.app.study_file` (parse, validate, address); one task
on a worker is `gfmd_contact.app.study_task`; the tables `gfmd_contact.app.study_tables`. This module runs
them: it prepares and locks the study directory, sends the pending tasks to a local Dask
cluster (or an existing one), and writes the tables and study.json at the end.

`gfmd study run STUDY --out DIR` writes

  DIR/tasks/<key>/   one one-realization run directory per task (gfmd_contact.app.io: written step
                     by step, resumable), key = the first 16 hex digits of the SHA-256 of the
                     task scene's values that differ from the scene defaults (`task_key_text`):
                     a newer version that adds a scene key with a default keeps every address;
                     a finished task holds curve.csv, mean_curve.csv, fields.npz, scene.toml, meta.json
  DIR/study.csv, DIR/summary.csv, DIR/summary.nc
                     the tables over the tasks and the per-set means (`gfmd_contact.app.study_tables`)
  DIR/cycles.csv     only where the tasks' loading has a path (gfmd_contact.app.cycles): one row per (task,
                     cycle): set, axis columns, realization, seed, task, cycle, pull_off_pressure (Pa,
                     min p̄ on unloading, < 0 tensile), pull_off_delta and snap_off_delta (m),
                     hysteresis (J/m², ∮ p̄ dδ), closed, jump_in and jump_out (event counts),
                     snap_off_rule (gfmd_contact.core.cycle; empty without a snap-off)
  DIR/study.json     tasks_total, tasks_reused, tasks_run, tasks_failed, tasks_solved_with,
                     steps_reused, every task (set, parameters, realization, seed, key, status,
                     solved_with: the key of the task whose solve it shared, where it did, code
                     version of the run that computed it, messages), the failures with their tracebacks,
                     the study file's name and content, timings, "complete"
  DIR/study.toml     a copy of the study file; DIR/base_scene.toml the resolved base scene

Re-running the same command reuses every finished task (its meta.json says complete) and
continues an interrupted one from its last saved step (`gfmd_contact.app.io.load_part`), so the
final files equal an uninterrupted run's (wall_s aside). Tasks are content-addressed:
any study with the same task scene reuses it; several study files run as one job that computes
each distinct task once: `gfmd_contact.app.study_suite`. Pending tasks are submitted longest first
(`longest_first`, by `task_cost`: the tail where one long task runs alone is shorter); tasks
that differ only in `gfmd_contact.core.observation.OBSERVATION_KEYS` run as one job, one solve (`solve_groups`,
`gfmd_contact.app.study_task.run_shared`), each task directory as a separate run writes it. With
--scheduler the tasks go to an existing Dask cluster; DIR must then be on a file system every
worker sees (the same absolute path).

The names of the three modules above are re-exported here, where other code imports them.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import sys
import time
import traceback
from pathlib import Path

from gfmd_contact.core.errors import SceneError
from gfmd_contact.core.scene import load_scene, scene_to_toml

from . import io, safe_files
from .cycles import write_study_cycles
from .study_file import (STUDY_KEYS, TASK_NAME, Study, StudyError, Task, _describe, load_study,  # noqa: F401
                         longest_first, solve_groups, study_from_dict, task_cost, task_key,
                         task_key_text, task_scene)
from .study_tables import (UNITS, _axis_text, _collect, _write_tables, stickiness_columns,  # noqa: F401
                           study_has_paths, study_is_forced, summary_columns, summary_dataset)
from .study_task import STEP_TOPIC, run_shared, run_task

#: files and folders a study directory holds
STUDY_ENTRIES = ("tasks", "study.json", "study.toml", "base_scene.toml", "study.csv", "summary.csv", "summary.nc",
                 "cycles.csv")


def prepare_study_dir(out, study):
    """Check DIR before any compute: a file, or a non-empty directory that is no study directory, is refused."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise io.RunDirError.options("{out} {path!r} is an existing file, not a directory: choose another {out}",
                                     path=str(out))
    existing = sorted(p.name for p in out.iterdir() if p.name != safe_files.LOCK_NAME) if out.is_dir() else []
    if existing and not any(n in ("tasks", "study.json") for n in existing):
        raise io.RunDirError.options("{out} {path} is not empty and holds no study ({entries}): choose another {out}",
                                     path=out, entries=", ".join(existing[:6]))
    (out / "tasks").mkdir(parents=True, exist_ok=True)
    for p in [*out.glob(".*.tmp"), *(out / "figures").glob(".*.tmp")]:  # a killed writer's (we hold the lock)
        p.unlink(missing_ok=True)
    for name, text in (("study.toml", study.text), ("base_scene.toml", scene_to_toml(study.base))):
        if not (out / name).is_file() or (out / name).read_text() != text:  # a rerun rewrites nothing unchanged
            io._atomic_write(out / name, text)
    return out


def _saved_steps(task_dir, scene):
    if io.run_complete(task_dir):
        return scene.loading.steps + 1
    try:
        part = io.load_part(task_dir, scene, 0)
    except (OSError, ValueError):
        return 0
    return len(part[0].curve["step"]) if part is not None else 0


#: Dask's settings for our local cluster (an existing one, `--scheduler`, keeps its own): the diagnostics nothing here
#: reads (no dashboard) off or slowed, since they run in every process beside the solvers and the scheduler: each
#: worker's statistical profiler (a thread sampling the task's stack every 10 ms, taking the GIL), the event loops'
#: 20 ms ticks, the system monitors (500 ms) and the nannies' memory monitors (100 ms): at 2^17 a worker's other threads took 3.8 % of its task's CPU with
#: Dask's defaults, 0.3 % with these.
#: And the workers start without Dask's MALLOC_TRIM_THRESHOLD_=65536 (its nannies' pre-spawn environment, which also
#: leaves it in this process's): under it glibc maps every array above 128 kB afresh, and `gfmd.heap` leaves a
#: setting of the environment alone (a coupled ramp at 2^17: 33 million page faults, 3× the CPU; docs/design/performance.md).
LOCAL_CLUSTER_CONFIG = {"distributed.worker.profile.enabled": False, "distributed.admin.tick.interval": "1s",
                        "distributed.admin.system-monitor.interval": "10s",
                        "distributed.worker.memory.monitor-interval": "1s",
                        "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}


def _client(workers, scheduler):
    """(client, cluster or None): a LocalCluster of `workers` processes (`LOCAL_CLUSTER_CONFIG`), or a client of
    `scheduler`."""
    import logging

    import dask
    from distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler, timeout="30s"), None
    with dask.config.set(LOCAL_CLUSTER_CONFIG):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.ERROR)
        return Client(cluster), cluster


def readdress_tasks(out, unique):
    """Move task directories written under another address to their current key; returns how many.

    A directory of DIR/tasks that is not a key of `unique` but whose stored scene.toml has one of
    them as its address (`task_key`) was written by a version that addressed tasks differently
    (before `task_key_text`): it is renamed, finished or not, unless the current key exists.
    """
    tasks_dir = Path(out) / "tasks"
    moved = 0
    for d in sorted(tasks_dir.iterdir()) if tasks_dir.is_dir() else []:
        if d.name in unique or d.name.startswith(".") or not (d / "scene.toml").is_file():  # .*: a suite's link
            continue
        try:
            key = task_key(load_scene(d / "scene.toml"))
        except (OSError, ValueError, SceneError):
            continue
        if key in unique and not (tasks_dir / key).exists():
            d.rename(tasks_dir / key)
            moved += 1
    return moved


def run_study(study, out, *, workers=None, scheduler=None, progress=True, command=None, wait=0):
    """Run every task of `study` into `out` (module docstring); returns the study.json dict.

    workers: processes of the local cluster (default: all cores); scheduler: the address of an
    existing Dask scheduler instead. Interruptible (KeyboardInterrupt): the local cluster is
    closed at once and the exception propagates; what finished stays on disk. The directory is
    locked meanwhile (`safe_files.DirLock`): another process writing it is refused
    (`safe_files.LockHeld`) unless `wait` (seconds, -1 for ever) lets it end first. A task that
    could not write its files for a reason of the disk (`safe_files.DISK_ERRNOS`: no space, quota,
    file-size limit, read-only) stops the study: its `safe_files.WriteFailed` is raised after the
    cluster closed, before the study's tables are written; any other failure fails that task only.
    """
    out = Path(out).resolve()
    if out.exists() and not out.is_dir():
        raise io.RunDirError.options("{out} {path!r} is an existing file, not a directory: choose another {out}",
                                     path=str(out))
    command = command or " ".join(sys.argv)
    note = (lambda line: print(f"note: {line}", file=sys.stderr)) if progress else None
    advice = "wait for it to end (or add --wait to wait for it), or stop it first; or choose another --out"
    with safe_files.locked(out, wait=wait, what="study directory", command=command, advice=advice, note=note):
        return _run_study_locked(study, out, workers, scheduler, progress, command)


def open_study_dir(study, out, progress=False):
    """Prepare `out` for `study` (`prepare_study_dir`), move tasks written under an older address to
    their key (`readdress_tasks`), tidy the complete ones; returns (out, the set of complete keys)."""
    out = prepare_study_dir(out, study)
    unique = {t.key: t for t in study.tasks}
    moved = readdress_tasks(out, unique)
    if moved and progress:
        print(f"{study.name}: {moved} task director{'y' if moved == 1 else 'ies'} written under an older "
              "address moved to the current one (same scene)", file=sys.stderr)
    done = {k for k in unique if io.run_complete(out / "tasks" / k)}
    for k in done:  # what a task killed after it completed left: its lock file, partial/, temporaries
        task_dir = out / "tasks" / k
        if (task_dir / safe_files.LOCK_NAME).exists() or (task_dir / io.PARTIAL).exists():
            with contextlib.suppress(safe_files.LockHeld), safe_files.locked(task_dir, what="task"):
                shutil.rmtree(task_dir / io.PARTIAL, ignore_errors=True)
                io.remove_temporaries(task_dir)
    return out, done


def _run_study_locked(study, out, workers, scheduler, progress, command):
    out, done = open_study_dir(study, out, progress)
    tasks = study.tasks
    unique = {t.key: t for t in tasks}
    pending = longest_first([t for k, t in unique.items() if k not in done])
    record = _record(study, out, tasks, {}, {}, complete=False)
    io._atomic_write(out / "study.json", json.dumps(record, indent=2))
    outcomes, failures = {k: {"status": "reused", "steps_reused": 0, "steps_run": 0} for k in done}, {}
    start = time.perf_counter()
    if pending:
        workers = workers or os.cpu_count() or 1

        def finished(key, outcome, failure, disk_error):
            if failure is None:
                outcomes[key] = outcome
            else:
                failures[key] = failure

        compute_tasks([(t.key, t.scene, out / "tasks" / t.key) for t in pending], finished, workers=workers,
                      scheduler=scheduler, progress=progress, command=command, name=study.name,
                      total=len(unique), initial=len(done),
                      steps_total=sum(t.scene.loading.steps + 1 for t in unique.values()),
                      steps_saved=sum(_saved_steps(out / "tasks" / t.key, t.scene) for t in unique.values()))
    return finish_study(study, out, outcomes, failures, wall=time.perf_counter() - start,
                        workers=None if scheduler else workers, scheduler=scheduler, command=command)


def compute_tasks(jobs, finished, *, workers, scheduler, progress, command, name, total, initial, steps_total,
                  steps_saved):
    """Run `jobs` [(key, task scene, task directory)] on Dask (`run_task`), submitted in this order
    (longest first: `longest_first`), each with a priority that keeps that order on the scheduler; jobs
    of one `solve_address` (they differ only in observation keys) as one group, one solve (`run_shared`);
    finished(key, outcome, failure, disk_error) is called in this process as each ends (outcome: run_task's
    dict, or failure: {"error", "traceback"}). A progress bar counts tasks (`total`, `initial` done) and
    load steps. An interrupt kills the local cluster's workers at once and propagates; a task's disk
    error (`safe_files.DISK_ERRNOS`) is raised after the cluster closed."""
    import logging

    from tqdm import tqdm

    logger = logging.getLogger("distributed")
    level = logger.level
    logger.setLevel(logging.WARNING)  # distributed's INFO lines would bury the progress bar
    groups = solve_groups(jobs)
    client, cluster = _client(min(workers, len(groups)), scheduler)
    bar = tqdm(total=total, initial=initial, desc=f"{name}: tasks", unit="task", disable=not progress)
    steps = [steps_saved]
    write_failed = []

    def stepped(event):  # (time, message): the message counts the load steps a task finished since its last event
        steps[0] += int(event[1]) if isinstance(event, tuple) else 1
        bar.set_postfix_str(f"load steps {steps[0]}/{steps_total}", refresh=False)

    try:
        from distributed import as_completed

        client.subscribe_topic(STEP_TOPIC, stepped)
        # submission order is execution order on a local cluster (checked); the priority keeps it where the
        # scheduler already holds other work (a higher priority runs first). Tasks that differ only in what
        # they observe run as one group, one solve (`solve_groups`, `run_shared`).
        futures = {}
        for i, group in enumerate(groups):
            if len(group) == 1:
                key, scene, task_dir = group[0]
                future = client.submit(run_task, scene, str(task_dir), command, key=f"gfmd-task-{key}", pure=False,
                                       priority=len(groups) - i)
            else:
                future = client.submit(run_shared, [(scene, str(task_dir)) for _, scene, task_dir in group], command,
                                       key=f"gfmd-shared-{group[0][0]}", pure=False, priority=len(groups) - i)
            futures[future] = [key for key, _, _ in group]
        n_failed = 0
        for future in as_completed(futures):
            keys = futures[future]
            if future.status == "finished":
                outcome = future.result()
                for key, o in zip(keys, outcome if len(keys) > 1 else [outcome]):
                    finished(key, o, None, False)
                    bar.update()
            else:
                exc = future.exception()
                disk = isinstance(exc, safe_files.WriteFailed) and exc.code in safe_files.DISK_ERRNOS
                if disk:
                    write_failed.append(exc)
                tb = "".join(traceback.format_exception(type(exc), exc, future.traceback()))
                for key in keys:
                    n_failed += 1
                    finished(key, None, {"error": f"{type(exc).__name__}: {exc}", "traceback": tb}, disk)
                    bar.update()
                bar.set_description(f"{name}: tasks ({n_failed} failed)")
            future.release()
    except BaseException:
        if cluster is not None:
            _kill_workers(cluster)  # at once: a graceful close would wait for the running tasks
        raise
    finally:
        bar.close()
        _close(client, cluster)
        logger.setLevel(level)
    if write_failed:
        raise write_failed[0]


def finish_study(study, out, outcomes, failures, *, wall, workers, scheduler, command, extra=None):
    """Write the study's tables (study.csv, summary.csv, summary.nc, cycles.csv) and its complete
    study.json (updated with `extra`); returns the study.json dict."""
    tasks = study.tasks
    rows, results = _collect(study, out, tasks, failures)
    _write_tables(study, out, rows, results)
    write_study_cycles(study, out, tasks, _axis_text, io._atomic_write)  # load paths only: cycles.csv
    record = _record(study, out, tasks, outcomes, failures, complete=True, wall=wall, workers=workers,
                     scheduler=scheduler, command=command)
    record.update(extra or {})
    io._atomic_write(out / "study.json", json.dumps(record, indent=2))
    return record


def _kill_workers(cluster):
    """SIGKILL the worker processes of our LocalCluster (their nannies told not to restart them first);
    a task loses at most the load steps since its last checkpoint (`gfmd_contact.app.checkpoints.CHECKPOINT_SECONDS`) and
    the one it was computing (gfmd_contact.app.io writes atomically)."""
    import logging
    import signal

    logging.getLogger("distributed").setLevel(logging.CRITICAL)  # the closed connections are expected
    for nanny in list(cluster.workers.values()):
        try:
            nanny.close_gracefully(reason="gfmd study interrupted")
            if nanny.pid:
                os.kill(nanny.pid, signal.SIGKILL)
        except (AttributeError, ProcessLookupError, OSError):
            pass


def _close(client, cluster):
    try:
        client.close(timeout=5)
    except Exception:  # noqa: BLE001 - closing after an interrupt must not mask it
        pass
    if cluster is not None:
        try:
            cluster.close(timeout=10)
        except Exception:  # noqa: BLE001
            pass


def _task_meta(task_dir):
    path = Path(task_dir) / "meta.json"
    return json.loads(path.read_text()) if path.is_file() else {}


def _record(study, out, tasks, outcomes, failures, *, complete, wall=None, workers=None, scheduler=None,
            command=None):
    entries = []
    for t in tasks:
        meta = _task_meta(out / "tasks" / t.key) if complete else {}
        status = ("failed" if t.key in failures else outcomes.get(t.key, {}).get("status", "pending"))
        entry = {"key": t.key, "set": t.set, "parameters": study.sets[t.set], "realization": t.realization,
                 "seed": t.seed, "status": status, "code_version": meta.get("code_version"),
                 "steps_reused": outcomes.get(t.key, {}).get("steps_reused", 0),
                 "steps_run": outcomes.get(t.key, {}).get("steps_run", 0),
                 "all_converged": meta.get("all_converged"), "messages": meta.get("messages", [])}
        if "linked_from" in outcomes.get(t.key, {}):  # a suite's task computed or kept in a sibling study
            entry["linked_from"] = outcomes[t.key]["linked_from"]
        if "solved_with" in outcomes.get(t.key, {}):  # observed on the solve of the task of that key
            entry["solved_with"] = outcomes[t.key]["solved_with"]
        if t.key in failures:
            entry["error"] = failures[t.key]["error"]
        entries.append(entry)
    count = lambda s: sum(1 for e in entries if e["status"] == s)  # noqa: E731
    return {
        "complete": complete,
        "study": study.name,
        "study_file": str(study.path) if study.path else None,
        "study_text": study.text,
        "axes": study.axes, "zip": study.zipped,
        "sets": len(study.sets),
        "tasks_total": len(tasks), "tasks_reused": count("reused"), "tasks_run": count("run"),
        "tasks_failed": count("failed"),
        "tasks_solved_with": sum(1 for e in entries if "solved_with" in e),
        "steps_reused": sum(e["steps_reused"] for e in entries),
        "code_versions": sorted({e["code_version"] for e in entries if e["code_version"]}),
        "tasks": entries,
        "failures": [{"key": k, **v} for k, v in failures.items()],
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": command,
        "timings": {"wall_s": wall, "workers": workers, "scheduler": scheduler},
        "units": "SI: m, Pa, J/m^2; see gfmd_contact/core/conventions.py",
    }


def failure_summary(record):
    """Lines naming each failed task: its set's parameters, realization, seed, key and error."""
    lines = []
    by_key = {t["key"]: t for t in record["tasks"]}
    for f in record["failures"]:
        t = by_key[f["key"]]
        lines.append(f"set {t['set']} ({_describe(t['parameters'])}), realization {t['realization']} "
                     f"(seed {t['seed']}), task {t['key']}: {f['error']}")
    return lines


def done_tasks(study, out):
    """How many of the study's tasks are complete in `out`."""
    return sum(1 for t in study.tasks if io.run_complete(Path(out) / "tasks" / t.key))
