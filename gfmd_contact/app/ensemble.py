"""Ensembles: independent realizations in a local process pool, and their averages.

Units: SI (see `gfmd_contact.core.conventions`). Every realization i uses the seed
`surface.seed + i`; all realizations share the same load steps, so averages are
taken step by step (at equal δ).

`run_ensemble` returns the results in memory; `run_to_directory` checkpoints the load
steps of every realization into a run directory as it goes (gfmd_contact.app.io, every
`CHECKPOINT_SECONDS`) and continues an interrupted run there. Both are interruptible: on
KeyboardInterrupt (SIGINT; the CLI maps SIGTERM to it) the worker processes are terminated
at once (SIGTERM: each writes its deferred checkpoint and exits) and the exception
propagates; the workers themselves ignore SIGINT, so a Ctrl-C in the terminal reaches the
main process only.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
from functools import partial

from tqdm import tqdm

from . import io, safe_files
from .methods import method_of, run_realization

_progress_queue = None  # set in each worker process by _init_worker


def _init_worker(queue):
    global _progress_queue
    safe_files.die_with_parent()  # a kill -9 of the main process ends its workers too: no orphan writes on
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the main process decides what an interrupt does
    signal.signal(signal.SIGTERM, _terminated)  # the pool's terminate: the deferred checkpoints first
    _progress_queue = queue


def _terminated(signum, frame):
    raise SystemExit(128 + signum)  # unwinds through `io.checkpointing`, which writes the deferred steps


def _report_step(step, steps):
    if _progress_queue is not None:
        _progress_queue.put(1)


def _pool_map(fn, jobs, workers, bar):
    """fn(job) for every job, yielded as they finish, in `workers` processes (in this one if ≤ 1).

    fn(job, progress) gets a callable(step, steps) that advances `bar` by one load step.
    On any exception, KeyboardInterrupt included, the pool is terminated before it propagates.
    """
    if workers <= 1 or len(jobs) <= 1:
        for job in jobs:
            yield fn(job, lambda k, n: bar.update())
        return
    ctx = multiprocessing.get_context("fork")
    queue = ctx.SimpleQueue()

    def drain():
        while queue.get() is not None:
            bar.update()

    listener = threading.Thread(target=drain, daemon=True)
    listener.start()
    pool = ctx.Pool(workers, initializer=_init_worker, initargs=(queue,))
    try:
        yield from pool.imap_unordered(partial(fn, progress=_report_step), jobs)
    except BaseException:
        # a worker killed here may hold the queue's lock: the daemon listener is left as it is
        pool.terminate()
        pool.join()
        raise
    pool.close()
    pool.join()
    queue.put(None)  # every worker has ended: the lock is free
    listener.join(timeout=5)


def _workers(scene, workers, count):
    workers = workers if workers is not None else scene.output.workers
    return min(count, workers or os.cpu_count() or 1)


def _run_one(job, progress):
    scene, realization = job
    return run_realization(scene, realization, progress=progress)


def _bar(scene, total, progress, initial=0):
    return tqdm(total=total, initial=initial, desc=f"{scene.name}: load steps", unit="step", disable=not progress)


def run_ensemble(scene, workers=None, progress=True):
    """Run all `scene.surface.realizations`; returns the list of `Result` (ordered).

    workers: processes (default scene.output.workers, 0 = all cores); progress: tqdm bar over load steps.
    """
    count = scene.surface.realizations
    jobs = [(scene, i) for i in range(count)]
    with _bar(scene, count * (scene.loading.steps + 1), progress) as bar:
        results = list(_pool_map(_run_one, jobs, _workers(scene, workers, count), bar))
    return sorted(results, key=lambda r: r.realization)


def _run_into(job, progress):
    """Worker: run (or continue) one realization, checkpointing every step into the run directory.

    Returns (realization, steps reused from an interrupted run, steps it ran). A method's own
    files of the finished realization (FE: VTU/PVD) go to out/vtu/realization<i>/.
    """
    scene, realization, out = job
    part = io.load_part(out, scene, realization)
    if part is not None and part[2]:
        return realization, 0, 0
    resume = part[:2] if part is not None else None
    io.start_part(out, realization, resume[0] if resume else None)
    reused = resume[1].step + 1 if resume else 0
    with io.checkpointing([out]):  # the steps save_step deferred are written however the ramp stops
        result = run_realization(scene, realization, progress=progress, resume=resume,
                                 checkpoint=partial(io.save_step, out))
    export = method_of(scene).export
    if export is not None:
        with safe_files.writing(out / "vtu" / f"realization{realization}"):
            export(result, out / "vtu" / f"realization{realization}")
    io.save_realization(out, result)
    return realization, reused, len(result.curve["step"]) - reused


def run_to_directory(scene, out, workers=None, progress=True, note=None):
    """Run every realization into the prepared run directory `out` (gfmd_contact.app.io.prepare_run_dir).

    Every load step is on disk within CHECKPOINT_SECONDS (gfmd_contact.app.checkpoints); realizations already done
    there are reused and an interrupted one continues from its last saved step (so a
    second call after an interrupt resumes). Returns (results, resume), results read
    back from disk in realization order, resume = {"realizations_reused", "steps_reused"}
    (steps_reused: the saved steps of interrupted realizations that were continued). A repair
    of damaged partial files (`gfmd_contact.app.io.load_part`) is reported through note(line).
    """
    count = scene.surface.realizations
    notes = []
    parts = [io.load_part(out, scene, i, notes=notes) for i in range(count)]
    for line in notes if note is not None else ():
        note(line)
    done = [i for i, p in enumerate(parts) if p is not None and p[2]]
    saved = sum(len(p[0].curve["step"]) for p in parts if p is not None)
    jobs = [(scene, i, out) for i in range(count) if i not in done]
    resume = {"realizations_reused": len(done), "steps_reused": 0}
    total = count * (scene.loading.steps + 1)
    with _bar(scene, total, progress, initial=saved) as bar:
        for _, reused, ran in _pool_map(_run_into, jobs, _workers(scene, workers, len(jobs)), bar):
            resume["steps_reused"] += reused
            bar.update(max(0, scene.loading.steps + 1 - reused - ran))  # a realization that stopped early
    results = [io.load_part(out, scene, i)[0].finalize() for i in range(count)]
    return results, resume
