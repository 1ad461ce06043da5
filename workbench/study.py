"""Studies: a grid of scenes × realizations as one resumable, content-addressed command on Dask.

Units: SI (see `contact.conventions`). A study file (TOML) names a base scene and axes
over scene keys by their dotted names:

    name = "fig3_small"                 # optional; default: the file's stem
    base = "fig3_base.toml"             # relative to the study file; or an inline [scene] table
    [axes]                              # the grid is the product of the axes (file order)
    "interface.length_normal" = [0.25e-9, 1e-9]
    [zip]                               # optional: keys that vary together (equal lengths)
    "interface.law" = ["hard-wall", "cohesive", "cohesive"]
    "interface.phi_n_star" = [0.15, 0.001, 0.15]

A parameter set ("set", numbered 0, 1, … in product order, the zip index innermost) is
the base scene with one value of every axis (and one zip entry); each (set,
realization) is one task: the set's scene with surface.seed = seed + realization and
surface.realizations = 1, run as realization 0 (the profile depends on the realization
only through its seed, so this is the same realization as in `gfmd run`). Every set is
validated with `Scene.replace` and the run's checks before any compute; a bad axis (an
unknown key, a value out of range, zip lengths that differ, a key given twice) is refused
naming the key.

`gfmd study run STUDY --out DIR` writes

  DIR/tasks/<key>/   one one-realization run directory per task (workbench.io: written step
                     by step, resumable), key = the first 16 hex digits of the SHA-256 of the
                     task scene's values that differ from the scene defaults (`task_key_text`):
                     a newer version that adds a scene key with a default keeps every address;
                     a finished task holds curve.csv, mean_curve.csv, fields.npz, scene.toml, meta.json
  DIR/study.csv      one row per (task, step): set, one column per axis named by its dotted key
                     (zip keys too), realization, seed, task (the key), then curve.csv's columns
                     `contact.result.CURVE_COLUMNS`: step, U (m), delta (m), p (Pa, > 0 compressive,
                     per unit area of the mean plane), a_rel (1), g_r (1: rms gradient of the
                     contact nodes, "nan" without contact), g (1: of the whole profile),
                     iterations, residual (relative), converged (0/1), wall_s (s), then
                     algorithm (GFMD: what relaxed the step, curve.csv's column; "" for another
                     method), then the set's
                     stickiness diagnostics before any run, stickiness_<key> for every key of
                     `contact.stickiness.KEYS` (process_zone m, process_zone_nodes, johnson_alpha,
                     maugis_lambda, tabor_rough, persson_tosatti, pastewka_robbins: 1; "nan" where a
                     quantity is not defined for the set's scene, meta.json of a task says why)
  DIR/summary.csv    per set and step: set, the axis columns, step, delta (m), U (m) and for each
                     of p, a_rel, g_r, g (`workbench.averages.AVERAGED`) the mean over the set's
                     realizations, <name>_se (its standard error, 0 for one value) and <name>_n
                     (realizations with a value at that step), then the stickiness_<key> columns;
                     where a set's scene has loading.path, branch ("loading"/"unloading") and cycle
                     (0, 1, ...) of each step follow step (the means are per step, so the branches
                     never mix); where some set is under force control (loading.control =
                     "force"), load (Pa, the step's prescribed p̄; nan for a displacement-
                     controlled set) follows them, and delta, U are the means over the
                     realizations; a ramp study's files are unchanged
  DIR/cycles.csv     only where the tasks' loading has a path (workbench.cycles): one row per (task,
                     cycle): set, axis columns, realization, seed, task, cycle, pull_off_pressure (Pa,
                     min p̄ on unloading, < 0 tensile), pull_off_delta and snap_off_delta (m),
                     hysteresis (J/m², ∮ p̄ dδ), closed, jump_in and jump_out (event counts),
                     snap_off_rule (contact.cycle; empty without a snap-off)
  DIR/summary.nc     the same as a labelled N-D dataset (xarray; netCDF3 through scipy, so no
                     netCDF4/HDF5 dependency): dims = the [axes] keys (coordinates: their values),
                     "zip" (coordinates: the zipped keys) if there is a [zip], and "step"; data
                     variables delta, U, set and the columns of summary.csv (NaN / n = 0 where a set
                     has fewer steps; the stickiness_<key> variables per set, without "step"; with
                     a path, branch (text, "" where no step) and cycle (int, -1 where no step);
                     under force control, load);
                     attributes: units, the study file's text
  DIR/study.json     tasks_total, tasks_reused, tasks_run, tasks_failed, steps_reused, every
                     task (set, parameters, realization, seed, key, status, code version of
                     the run that computed it, messages), the failures with their tracebacks,
                     the study file's name and content, timings, "complete"
  DIR/study.toml     a copy of the study file; DIR/base_scene.toml the resolved base scene

Re-running the same command reuses every finished task (its meta.json says complete) and
continues an interrupted one from its last saved step (`workbench.io.load_part`), so the
final files equal an uninterrupted run's (wall_s aside). Tasks are content-addressed:
any study with the same task scene reuses it. With --scheduler the tasks go to an existing
Dask cluster; DIR must then be on a file system every worker sees (the same absolute path).
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import functools
import hashlib
import io as _io
import itertools
import json
import os
import shutil
import sys
import time
import tomllib
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from contact.errors import SceneError
from contact.result import CURVE_COLUMNS
from contact.scene import Scene, load_scene, scene_from_dict, scene_to_dict, scene_to_toml
from contact.stickiness import KEYS as STICKINESS_KEYS
from contact.stickiness import as_dict as stickiness_dict

from . import io, safe_files
from .averages import AVERAGED, ensemble_average
from .cycles import has_path, mean_columns, step_loads, write_study_cycles

STUDY_KEYS = ("name", "description", "base", "scene", "axes", "zip")
#: files and folders a study directory holds
STUDY_ENTRIES = ("tasks", "study.json", "study.toml", "base_scene.toml", "study.csv", "summary.csv", "summary.nc",
                 "cycles.csv")
TASK_NAME = "task"
STEP_TOPIC = "gfmd-study-step"
#: units of the summary columns (netCDF attributes)
UNITS = {"load": "Pa", "delta": "m", "U": "m", "p": "Pa", "a_rel": "1", "g_r": "1", "g": "1"}


class StudyError(SceneError):
    """A study file that cannot run: the message names the file and the key."""


@dataclass(frozen=True)
class Task:
    key: str
    set: int
    realization: int
    seed: int
    scene: object  # contact.scene.Scene, realization 0 of it is run


@dataclass
class Study:
    name: str
    path: Path | None
    text: str
    base: object  # the base Scene
    axes: dict  # key -> list of values (the grid)
    zipped: dict  # key -> list of values (vary together)
    sets: list = field(default_factory=list)  # [{key: value}] for every parameter set
    scenes: list = field(default_factory=list)  # the Scene of every set
    index: list = field(default_factory=list)  # per set: (axis indices..., zip index or None)

    @property
    def keys(self):
        """Every varied key: the axes, then the zipped keys."""
        return list(self.axes) + list(self.zipped)

    @property
    def tasks(self):
        out = []
        for s, scene in enumerate(self.scenes):
            for r in range(scene.surface.realizations):
                task = task_scene(scene, r)
                out.append(Task(task_key(task), s, r, scene.surface.seed + r, task))
        return out


def task_scene(scene, realization):
    """The one-realization scene of (scene, realization): seed + realization, 1 realization, run as 0."""
    task = scene.replace(**{"surface.seed": scene.surface.seed + realization, "surface.realizations": 1,
                            "output.workers": 1})
    return dataclasses.replace(task, name=TASK_NAME)


_MISSING = object()
_DEFAULTS = {section: dataclasses.asdict(getattr(Scene(), section)) for section in scene_to_dict(Scene())}
_DEFAULTS["material"]["thickness"] = "inf"


def task_key_text(task):
    """What a task's address hashes: its resolved values that differ from `contact.scene`'s defaults.

    One "section.key = value" line each, sorted. A key that a later version adds with a default
    equal to the old behaviour leaves every address unchanged, so upgrading the code loses no
    finished task; a reused task's stored scene.toml is compared key by key with the current
    resolved scene (`run_task`), so a changed default is caught instead of reused.
    """
    d = scene_to_dict(task)
    return "".join(f"{section}.{k} = {v!r}\n" for section, values in sorted(d.items())
                   for k, v in sorted(values.items()) if _DEFAULTS.get(section, {}).get(k, _MISSING) != v)


def task_key(task):
    """Content address of a task: the first 16 hex digits of sha256(`task_key_text`(task))."""
    return hashlib.sha256(task_key_text(task).encode()).hexdigest()[:16]


def _values(where, key, values, unique=True):
    if not isinstance(values, list) or not values:
        raise StudyError(f"{where} {key!r} = {values!r}: must be a non-empty list of values")
    seen = []
    for v in values:
        if isinstance(v, (dict, list)):
            raise StudyError(f"{where} {key!r}: value {v!r} must be a number, string or boolean")
        if unique and (type(v), v) in seen:
            raise StudyError(f"{where} {key!r}: value {v!r} appears twice")
        seen.append((type(v), v))
    return values


def _check_key(where, key):
    section, _, name = key.partition(".")
    if not name or not section:
        raise StudyError(f"{where} key {key!r}: must be a dotted scene key like \"interface.phi_n_star\"")


def study_from_dict(d, *, path=None, text="", name=None):
    """Parse and validate a study (dict of the TOML); every parameter set is built and checked."""
    label = f"study {str(path)!r}" if path else "study"
    if not isinstance(d, dict):
        raise StudyError(f"{label}: must be a TOML table")
    for key in d:
        if key not in STUDY_KEYS:
            raise StudyError(f"{label}: unknown key {key!r}; valid keys: {', '.join(STUDY_KEYS)}")
    if ("base" in d) == ("scene" in d):
        raise StudyError(f"{label}: give exactly one of base = \"SCENE.toml\" (relative to the study file) "
                         "or an inline [scene] table")
    if "base" in d:
        if not isinstance(d["base"], str):
            raise StudyError(f"{label}: base = {d['base']!r}: must be a path to a scene TOML file")
        p = Path(d["base"])
        if not p.is_absolute() and path is not None:
            p = Path(path).parent / p
        try:
            base = load_scene(p)
        except SceneError as exc:
            raise StudyError(f"{label}: base scene: {exc}") from None
    else:
        try:
            base = scene_from_dict(d["scene"], name="scene")
        except SceneError as exc:
            raise StudyError(f"{label}: [scene]: {exc}") from None
    study_name = d.get("name", name or (Path(path).stem if path else "study"))
    if not isinstance(study_name, str) or not study_name:
        raise StudyError(f"{label}: name = {study_name!r}: must be a non-empty string")
    import dataclasses

    base = dataclasses.replace(base, name=study_name)
    axes, zipped = d.get("axes", {}), d.get("zip", {})
    for section, table in (("[axes]", axes), ("[zip]", zipped)):
        if not isinstance(table, dict):
            raise StudyError(f"{label}: {section} must be a table of \"section.key\" = [values]")
        for key, values in table.items():
            _check_key(f"{label}: {section}", key)
            _values(f"{label}: {section}", key, values, unique=section == "[axes]")  # zip: entries repeat
    both = [k for k in axes if k in zipped]
    if both:
        raise StudyError(f"{label}: {both[0]!r} is both in [axes] and in [zip]: give it once")
    if zipped and len({len(v) for v in zipped.values()}) > 1:
        lengths = ", ".join(f"{k!r}: {len(v)}" for k, v in zipped.items())
        raise StudyError(f"{label}: [zip] lists must have equal lengths (they vary together); got {lengths}")
    entries = list(zip(*([(type(x), x) for x in v] for v in zipped.values())))
    if len(set(entries)) != len(entries):
        raise StudyError(f"{label}: [zip] keys {', '.join(map(repr, zipped))}: an entry appears twice")
    # every value alone, so that the message names the key and the value
    for section, table in (("[axes]", axes), ("[zip]", zipped)):
        for key, values in table.items():
            for v in values:
                try:
                    base.replace(**{key: v})
                except SceneError as exc:
                    raise StudyError(f"{label}: {section} {key!r} = {v!r}: {exc}") from None
    study = Study(name=study_name, path=Path(path) if path else None, text=text, base=base, axes=axes,
                  zipped=zipped)
    zip_len = len(next(iter(zipped.values()))) if zipped else 0
    for combo in itertools.product(*(range(len(v)) for v in axes.values())):
        for z in (range(zip_len) if zipped else [None]):
            params = {k: axes[k][i] for k, i in zip(axes, combo)}
            if z is not None:
                params.update({k: v[z] for k, v in zipped.items()})
            try:
                scene = base.replace(**params)
                _run_checks(scene)
            except SceneError as exc:
                raise StudyError(f"{label}: parameter set {len(study.sets)} ({_describe(params)}): {exc}") from None
            study.sets.append(params)
            study.scenes.append(scene)
            study.index.append(combo + ((z,) if zipped else ()))
    keys = [t.key for t in study.tasks]
    if len(set(keys)) != len(keys):
        raise StudyError(f"{label}: two parameter sets give the same scene (check the axes for values that "
                         "change nothing)")
    return study


def _run_checks(scene):
    """The refusals `gfmd run` makes before compute (the method's, contact.loading.preflight)."""
    from contact.loading import preflight

    from .methods import method_of

    method_of(scene).refuse(scene)
    preflight(scene)


def _describe(params):
    return ", ".join(f"{k} = {v!r}" for k, v in params.items()) or "the base scene"


def load_study(path):
    """Read and validate a study file (module docstring)."""
    path = Path(path)
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise StudyError(f"study file {str(path)!r} not found") from None
    if path.is_dir():
        raise StudyError(f"study file {str(path)!r} is a directory")
    try:
        d = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise StudyError(f"study file {str(path)!r} is not valid TOML: {exc}") from None
    return study_from_dict(d, path=path, text=text, name=path.stem)


# ---------------------------------------------------------------- one task (runs on a Dask worker)

def _report_step(step, steps):
    try:
        from distributed import get_worker

        get_worker().log_event(STEP_TOPIC, 1)
    except (ImportError, ValueError):  # not on a worker
        pass


# glibc mallopt parameters (malloc.h)
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3


@functools.cache
def reuse_freed_arrays(mmap_threshold=1 << 26, trim_threshold=1 << 27):
    """Let glibc's malloc keep freed arrays of up to 64 MiB for reuse in this process; True if set.

    Dask's nanny starts every worker with MALLOC_TRIM_THRESHOLD_=65536 (its config
    ``distributed.nanny.pre-spawn-environ``), and setting any malloc threshold freezes glibc's
    adaptive mmap threshold at 128 KiB: every array of ≥ 2^14 doubles is then mmap'ed on
    allocation and unmapped on release, each page faulted in anew. The solvers allocate such
    arrays at every iteration, so a worker spent three quarters of its time in page faults
    (measured: one N = 2^17 hard-wall task of the seed's Fig. 3, 21 s in-process, 99 s under
    that variable, 42 million minor page faults instead of 65 thousand). Called at the start of
    each task (on a local cluster's workers and on those of an existing cluster alike), acting
    once per process; a no-op returning False where the C library has no mallopt (not glibc).
    """
    import ctypes
    import ctypes.util

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    return bool(mallopt(_M_MMAP_THRESHOLD, int(mmap_threshold))) and bool(
        mallopt(_M_TRIM_THRESHOLD, int(trim_threshold)))


def run_task(scene, task_dir, command=None, progress=_report_step):
    """Run (or continue, or reuse) one task into its run directory; a small dict of what happened.

    The directory is a one-realization `gfmd run` directory (workbench.io): every load step
    is checkpointed; a complete one is reused, an interrupted one continues from its last step.
    """
    reuse_freed_arrays()
    out = Path(task_dir)
    # a second execution of the same task (Dask may run one twice, at once) waits here for the first and
    # then finds its result published (meta.json "complete", written last, every file by atomic rename)
    with safe_files.locked(out, wait=-1, what="task directory", command=command):
        return _run_task_locked(scene, out, command, progress)


def _run_task_locked(scene, out, command, progress):
    from .ensemble import _run_into

    if io.run_complete(out):
        diff = io.stored_scene_differences(out, scene)
        if diff:
            raise StudyError(f"{out} holds a finished task of another scene ({'; '.join(diff)}): a default "
                             "changed since it ran; remove that task directory to recompute it")
        io.remove_temporaries(out)
        return {"status": "reused", "steps_reused": 0, "steps_run": 0}
    resume = (out / "scene.toml").is_file()
    io.prepare_run_dir(out, scene, resume=resume, overwrite=not resume, command=command)
    start = time.perf_counter()
    part = io.load_part(out, scene, 0) if resume else None
    if part is not None and part[2]:  # every step saved, only the final files missing
        reused, ran = len(part[0].curve["step"]), 0
    else:
        _, reused, ran = _run_into((scene, 0, out), progress)
    result = io.load_part(out, scene, 0)[0].finalize()
    io.write_run(out, scene, [result], timings={"total_s": time.perf_counter() - start, "workers": 1},
                 command=command, resume={"realizations_reused": 0, "steps_reused": reused})
    return {"status": "run", "steps_reused": reused, "steps_run": ran}


# ---------------------------------------------------------------- the study directory

def prepare_study_dir(out, study):
    """Check DIR before any compute: a file, or a non-empty directory that is no study directory, is refused."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise io.RunDirError(f"--out {str(out)!r} is an existing file, not a directory: choose another --out")
    existing = sorted(p.name for p in out.iterdir() if p.name != safe_files.LOCK_NAME) if out.is_dir() else []
    if existing and not any(n in ("tasks", "study.json") for n in existing):
        raise io.RunDirError(f"--out {out} is not empty and holds no study ({', '.join(existing[:6])}): "
                             "choose another --out")
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


def _client(workers, scheduler):
    """(client, cluster or None): a LocalCluster of `workers` processes, or a client of `scheduler`."""
    import logging

    from distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler, timeout="30s"), None
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
        if d.name in unique or not (d / "scene.toml").is_file():
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
        raise io.RunDirError(f"--out {str(out)!r} is an existing file, not a directory: choose another --out")
    command = command or " ".join(sys.argv)
    note = (lambda line: print(f"note: {line}", file=sys.stderr)) if progress else None
    advice = "wait for it to end (or add --wait to wait for it), or stop it first; or choose another --out"
    with safe_files.locked(out, wait=wait, what="study directory", command=command, advice=advice, note=note):
        return _run_study_locked(study, out, workers, scheduler, progress, command)


def _run_study_locked(study, out, workers, scheduler, progress, command):
    from tqdm import tqdm

    out = prepare_study_dir(out, study)
    tasks = study.tasks
    unique = {t.key: t for t in tasks}
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
    pending = [t for k, t in unique.items() if k not in done]
    record = _record(study, out, tasks, {}, {}, complete=False)
    io._atomic_write(out / "study.json", json.dumps(record, indent=2))
    outcomes, failures = {k: {"status": "reused", "steps_reused": 0, "steps_run": 0} for k in done}, {}
    start = time.perf_counter()
    steps_total = sum(t.scene.loading.steps + 1 for t in unique.values())
    steps_saved = sum(_saved_steps(out / "tasks" / t.key, t.scene) for t in unique.values())
    if pending:
        import logging

        workers = workers or os.cpu_count() or 1
        logger = logging.getLogger("distributed")
        level = logger.level
        logger.setLevel(logging.WARNING)  # distributed's INFO lines would bury the progress bar
        client, cluster = _client(min(workers, len(pending)), scheduler)
        bar = tqdm(total=len(unique), initial=len(done), desc=f"{study.name}: tasks", unit="task",
                   disable=not progress)
        steps = [steps_saved]
        write_failed = []

        def stepped(event):
            steps[0] += 1
            bar.set_postfix_str(f"load steps {steps[0]}/{steps_total}", refresh=False)

        try:
            from distributed import as_completed

            client.subscribe_topic(STEP_TOPIC, stepped)
            futures = {client.submit(run_task, t.scene, str(out / "tasks" / t.key), command,
                                     key=f"gfmd-task-{t.key}", pure=False): t.key for t in pending}
            for future in as_completed(futures):
                key = futures[future]
                if future.status == "finished":
                    outcomes[key] = future.result()
                else:
                    exc = future.exception()
                    if isinstance(exc, safe_files.WriteFailed) and exc.code in safe_files.DISK_ERRNOS:
                        write_failed.append(exc)
                    tb = "".join(traceback.format_exception(type(exc), exc, future.traceback()))
                    failures[key] = {"error": f"{type(exc).__name__}: {exc}", "traceback": tb}
                    bar.set_description(f"{study.name}: tasks ({len(failures)} failed)")
                bar.update()
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
    wall = time.perf_counter() - start
    rows, results = _collect(study, out, tasks, failures)
    _write_tables(study, out, rows, results)
    write_study_cycles(study, out, tasks, _axis_text, io._atomic_write)  # load paths only: cycles.csv
    record = _record(study, out, tasks, outcomes, failures, complete=True, wall=wall,
                     workers=None if scheduler else workers,
                     scheduler=scheduler, command=command)
    io._atomic_write(out / "study.json", json.dumps(record, indent=2))
    return record


def _kill_workers(cluster):
    """SIGKILL the worker processes of our LocalCluster (their nannies told not to restart them first);
    a task loses at most the load step it was computing (workbench.io writes atomically)."""
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
        "steps_reused": sum(e["steps_reused"] for e in entries),
        "code_versions": sorted({e["code_version"] for e in entries if e["code_version"]}),
        "tasks": entries,
        "failures": [{"key": k, **v} for k, v in failures.items()],
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": command,
        "timings": {"wall_s": wall, "workers": workers, "scheduler": scheduler},
        "units": "SI: m, Pa, J/m^2; see contact/conventions.py",
    }


def _axis_text(v):
    return io._fmt(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else str(v)


def _collect(study, out, tasks, failures):
    """study.csv rows (strings, as the task's curve.csv holds them) and, per set, the results to average."""
    rows, results = [], {}
    for t in sorted(tasks, key=lambda t: (t.set, t.realization)):
        path = out / "tasks" / t.key / "curve.csv"
        if t.key in failures or not path.is_file():
            continue
        with open(path) as fh:
            curve = list(csv.DictReader(fh))
        params = study.sets[t.set]
        for row in curve:
            rows.append([str(t.set)] + [_axis_text(params[k]) for k in study.keys]
                        + [str(t.realization), str(t.seed), t.key] + [row[c] for c in CURVE_COLUMNS]
                        + [row.get("algorithm") or ""])  # GFMD's per-step label; "" for another method
        values = {c: np.array([float(row[c]) for row in curve]) for c in CURVE_COLUMNS}
        values["step"] = values["step"].astype(int)
        results.setdefault(t.set, []).append(SimpleNamespace(curve=values, realization=t.realization))
    return rows, results


def summary_columns(cycled=False, forced=False):
    """summary.csv's columns after set and the axes; cycled (some set's scene has loading.path):
    branch ("loading"/"unloading") and cycle (0, 1, ...) of each step after step (workbench.cycles);
    forced (some set is under force control): then load (Pa, the step's prescribed p̄; NaN for a set
    under displacement control), before delta and U (there the means over the realizations)."""
    cols = ["step"] + (["branch", "cycle"] if cycled else []) + (["load"] if forced else []) + ["delta", "U"]
    for name in AVERAGED:
        cols += [name, f"{name}_se", f"{name}_n"]
    return cols


def stickiness_columns():
    """The per-set stickiness columns of study.csv / summary.csv: "stickiness_<key>" (contact.stickiness.KEYS)."""
    return [f"stickiness_{k}" for k in STICKINESS_KEYS]


def _stickiness_cells(study):
    """{set: [text per stickiness column]}: the set scene's diagnostics before any run ("nan" where n/a)."""
    cells = {}
    for s, scene in enumerate(study.scenes):
        values = stickiness_dict(scene)
        cells[s] = [io._fmt(values[k]["value"]) if values[k]["value"] is not None else "nan"
                    for k in STICKINESS_KEYS]
    return cells


def _write_tables(study, out, rows, results):
    sticky = _stickiness_cells(study)
    buf = _io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["set"] + study.keys + ["realization", "seed", "task"] + list(CURVE_COLUMNS) + ["algorithm"]
               + stickiness_columns())
    w.writerows(row + sticky[int(row[0])] for row in rows)
    io._atomic_write(out / "study.csv", buf.getvalue())
    averages = {s: ensemble_average(rs, step_loads(study.scenes[s])) for s, rs in sorted(results.items()) if rs}
    cycled, forced = study_has_paths(study), study_is_forced(study)
    for s, cols in averages.items():  # a path: per step its branch and cycle (never mixed by the mean)
        if cycled:
            cols.update(mean_columns(study.scenes[s], cols["step"]))
        if forced and "load" not in cols:  # a displacement-controlled set beside force-controlled ones
            cols["load"] = np.full(cols["step"].size, np.nan)
    buf = _io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["set"] + study.keys + summary_columns(cycled, forced) + stickiness_columns())
    for s, cols in averages.items():
        params = [_axis_text(study.sets[s][k]) for k in study.keys]
        for k in range(cols["step"].size):
            w.writerow([str(s)] + params + [_cell(cols[c][k]) for c in summary_columns(cycled, forced)] + sticky[s])
    io._atomic_write(out / "summary.csv", buf.getvalue())
    dataset = summary_dataset(study, averages)
    io._atomic_write(out / "summary.nc", bytes(dataset.to_netcdf(engine="scipy")), binary=True)


def study_is_forced(study):
    """Whether some set's scene is under force control: its summaries then carry the prescribed load."""
    return any(step_loads(scene) is not None for scene in study.scenes)


def study_has_paths(study):
    """Whether some set's scene loads along a path (loading.path): its summaries then carry branch and cycle."""
    return any(has_path(scene) for scene in study.scenes)


def _cell(value):
    return value if isinstance(value, str) else io._fmt(value)


def _float_or_nan(value):
    return float("nan") if value is None else float(value)


def _coordinate(values):
    """Axis values as one netCDF3-writable array: numbers as float/int, anything mixed as text."""
    if all(isinstance(v, bool) for v in values):
        return np.array([str(v).lower() for v in values])
    if all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return np.array(values, dtype=np.int32 if all(abs(v) < 2**31 for v in values) else float)
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        return np.array(values, dtype=float)
    return np.array([str(v) for v in values])


def summary_dataset(study, averages):
    """The summary as an xarray.Dataset: dims = the [axes] keys, "zip" (if any), "step"."""
    import xarray as xr

    dims = list(study.axes) + (["zip"] if study.zipped else [])
    shape = [len(v) for v in study.axes.values()] + ([len(next(iter(study.zipped.values())))] if study.zipped else [])
    steps = max((cols["step"].size for cols in averages.values()), default=0)
    steps = max([steps] + [s.loading.steps + 1 for s in study.scenes])
    data = {c: np.full(shape + [steps], 0 if c.endswith("_n") else np.nan,
                       dtype=np.int32 if c.endswith("_n") else float)
            for c in summary_columns(forced=study_is_forced(study))[1:]}
    set_index = np.full(shape, -1, dtype=np.int32)
    cycled = study_has_paths(study)
    if cycled:  # per set and step, from its scene's path (also where a set has no result yet)
        branch, cycle = np.full(shape + [steps], "", dtype=object), np.full(shape + [steps], -1, dtype=np.int32)
    for s, idx in enumerate(study.index):
        set_index[idx] = s
        if cycled:
            n = study.scenes[s].loading.steps + 1
            marks = mean_columns(study.scenes[s], np.arange(n))
            branch[idx + (slice(0, n),)] = marks["branch"]
            cycle[idx + (slice(0, n),)] = marks["cycle"]
        cols = averages.get(s)
        if cols is None:
            continue
        for c in data:
            if c in cols:  # load: only the force-controlled sets
                data[c][idx + (slice(0, cols["step"].size),)] = cols[c]
    coords = {k: _coordinate(v) for k, v in study.axes.items()}
    coords.update({k: ("zip", _coordinate(v)) for k, v in study.zipped.items()})
    coords["step"] = np.arange(steps, dtype=np.int32)
    variables = {"set": (dims, set_index, {"long_name": "parameter set (the set column of summary.csv); -1: none"})}
    for c, values in data.items():
        base = c.rsplit("_", 1)[0] if c.endswith(("_se", "_n")) else c
        if c.endswith("_n"):
            attrs = {"long_name": f"realizations with a value of {base}", "units": "1"}
        elif c.endswith("_se"):
            attrs = {"long_name": f"standard error of the mean of {base}", "units": UNITS[base]}
        else:
            attrs = {"long_name": f"mean of {c} over realizations" if c in AVERAGED else c, "units": UNITS[c]}
            if c == "load":
                attrs["long_name"] = "prescribed mean pressure p̄ of the step (force control; NaN: displacement control)"
        variables[c] = (dims + ["step"], values, attrs)
    if cycled:
        variables["branch"] = (dims + ["step"], branch, {
            "long_name": "branch of the load path at the step: loading (δ grows) or unloading; empty: no step",
            "units": "1"})
        variables["cycle"] = (dims + ["step"], cycle, {
            "long_name": "cycle of the load path at the step (0, 1, ...); -1: no step", "units": "1"})
    sticky = [stickiness_dict(scene) for scene in study.scenes]  # per set, before any run (contact.stickiness)
    for key in STICKINESS_KEYS:
        cells = np.full(shape, np.nan)  # NaN: not defined for the set's scene
        for s, idx in enumerate(study.index):
            cells[idx] = _float_or_nan(sticky[s][key]["value"])
        variables[f"stickiness_{key}"] = (dims, cells, {
            "long_name": f"stickiness diagnostic {key} of the set (contact.stickiness; NaN: not defined)",
            "units": sticky[0][key]["unit"] if sticky else "1"})
    return xr.Dataset(variables, coords=coords,
                      attrs={"study": study.name, "study_text": study.text,
                             "conventions": "SI units; p > 0 compressive; see contact/conventions.py"})


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
