"""One study task: run, continue or reuse one (set, realization) into its run directory (on a Dask worker).

A task directory is a one-realization `gfmd run` directory (gfmd_contact.app.io): the load steps
are checkpointed (every `gfmd_contact.app.checkpoints.CHECKPOINT_SECONDS`); a complete one is reused (its stored scene compared key by key with the
task's), an interrupted one continues from its last saved step. The task directory is
locked while a task writes it, so a second execution of the same task (Dask may run one
twice) waits and then finds the result. The finished load steps are reported to the
scheduler on `STEP_TOPIC` for the study's progress bar, in batches (`REPORT_SECONDS`).

Tasks of one `gfmd_contact.app.methods.solve_key` (they differ only in what they observe, e.g. the
contact rule) run as one group (`run_shared`): one load ramp writes every member's directory,
each exactly what `run_task` would write there (wall times aside).
"""

from __future__ import annotations

import contextlib
import functools
import threading
import time
from functools import partial
from pathlib import Path

from . import io, safe_files
from .study_file import StudyError

#: the Dask event topic a task reports each finished load step on (the study's progress bar)
STEP_TOPIC = "gfmd-study-step"


#: a task reports its finished load steps in batches, at most one event per REPORT_SECONDS (and its last step at
#: once): an event per step cost a worker ≈ 3 ms of its task's time each (the worker's event loop takes the GIL from
#: the solver), measured on 10 hard-wall tasks at 2^17 (H = 0.2, 30 nm, 2 workers, 2 cores): task times
#: 30.9 s in all with an event per step, 24.3 s with none, the study's wall time 19.9 s against 16.1 s
REPORT_SECONDS = 1.0
_reported = {"steps": 0, "since": None}
_report_lock = threading.Lock()


def _report_step(step, steps):
    """Count a finished load step (`step` of 0 … `steps`) for the study's progress bar; sent (`flush_steps`) once
    REPORT_SECONDS have passed since the last event, and at a ramp's last step."""
    with _report_lock:
        now = time.monotonic()
        _reported["steps"] += 1
        if _reported["since"] is None:
            _reported["since"] = now
        due = step >= steps or now - _reported["since"] >= REPORT_SECONDS
    if due:
        flush_steps()


def flush_steps():
    """Send the load steps counted since the last event to the scheduler (`STEP_TOPIC`, the count as the message);
    nothing off a Dask worker or with none counted."""
    with _report_lock:
        count, _reported["steps"], _reported["since"] = _reported["steps"], 0, None
    if not count:
        return
    try:
        from distributed import get_worker

        get_worker().log_event(STEP_TOPIC, count)
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

    The directory is a one-realization `gfmd run` directory (gfmd_contact.app.io): the load steps
    are checkpointed as it goes; a complete one is reused, an interrupted one continues from its last step.
    """
    reuse_freed_arrays()
    out = Path(task_dir)
    # a second execution of the same task (Dask may run one twice, at once) waits here for the first and
    # then finds its result published (meta.json "complete", written last, every file by atomic rename)
    try:
        with safe_files.locked(out, wait=-1, what="task directory", command=command):
            return _run_task_locked(scene, out, command, progress)
    finally:
        flush_steps()  # a ramp that stopped before its last step: its counted steps too


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


def run_shared(members, command=None, progress=_report_step):
    """Run (or continue, or reuse) tasks [(scene, task_dir)] of one `gfmd_contact.app.methods.solve_key` with
    one load ramp; a list of `run_task`'s dicts, one per member, a member's "solved_with" naming the task
    directory (its key) whose solve it shared.

    Every member directory is locked (in path order); complete ones are reused as by `run_task`. The
    ramp continues from the member furthest behind; each member keeps its saved steps and gets the
    rest, so every directory ends as an uninterrupted `run_task` leaves it (wall times aside).
    """
    reuse_freed_arrays()
    outs = [Path(d) for _, d in members]
    try:
        with contextlib.ExitStack() as stack:
            for out in sorted(set(outs)):
                stack.enter_context(safe_files.locked(out, wait=-1, what="task directory", command=command))
            return _run_shared_locked([scene for scene, _ in members], outs, command, progress)
    finally:
        flush_steps()


def _run_shared_locked(scenes, outs, command, progress):
    from gfmd_contact.core.ramp import Variant

    from .methods import method_of, run_realization

    outcomes = [None] * len(outs)
    ramp, parts = [], {}  # members the ramp still writes; member -> its load_part (None: fresh)
    for i, (scene, out) in enumerate(zip(scenes, outs)):
        if io.run_complete(out):
            outcomes[i] = _run_task_locked(scene, out, command, progress)  # reused (or refused)
            continue
        resume = (out / "scene.toml").is_file()
        io.prepare_run_dir(out, scene, resume=resume, overwrite=not resume, command=command)
        parts[i] = io.load_part(out, scene, 0) if resume else None
        if parts[i] is None or not parts[i][2]:
            ramp.append(i)
    start = time.perf_counter()
    saved = {i: len(parts[i][0].curve["step"]) if parts[i] is not None else 0 for i in parts}
    if ramp:
        ramp.sort(key=lambda i: (saved[i] if parts[i] is not None else -1, i))  # the member furthest behind first
        for i in ramp:
            io.start_part(outs[i], 0, parts[i][0] if parts[i] is not None else None)
        first, rest = ramp[0], ramp[1:]
        variants = [Variant(scenes[i], partial(io.save_step, outs[i]), parts[i][:2] if parts[i] else None)
                    for i in rest]
        with io.checkpointing([outs[i] for i in ramp]):  # deferred steps written however the ramp stops
            result = run_realization(scenes[first], 0, progress=progress,
                                     checkpoint=partial(io.save_step, outs[first]),
                                     resume=parts[first][:2] if parts[first] else None, variants=variants)
        export = method_of(scenes[first]).export
        for i, r in [(first, result)] + [(i, v.result) for i, v in zip(rest, variants)]:
            if export is not None:
                with safe_files.writing(outs[i] / "vtu" / "realization0"):
                    export(r, outs[i] / "vtu" / "realization0")
            io.save_realization(outs[i], r)
    for i in parts:
        result = io.load_part(outs[i], scenes[i], 0)[0].finalize()
        io.write_run(outs[i], scenes[i], [result], timings={"total_s": time.perf_counter() - start, "workers": 1},
                     command=command, resume={"realizations_reused": 0, "steps_reused": saved[i]})
        outcomes[i] = {"status": "run", "steps_reused": saved[i], "steps_run": len(result.curve["step"]) - saved[i]}
        if i in ramp[1:]:
            outcomes[i]["solved_with"] = outs[ramp[0]].name
    return outcomes
