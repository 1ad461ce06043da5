"""Ensembles: independent realizations in a local process pool, and their averages.

Units: SI (see `contact.conventions`). Every realization i uses the seed
`surface.seed + i`; all realizations share the same load steps, so averages are
taken step by step (at equal δ).

`run_ensemble` returns the results in memory; `run_to_directory` writes every load
step of every realization to a run directory as it is computed (workbench.io) and
continues an interrupted run there. Both are interruptible: on KeyboardInterrupt
(SIGINT; the CLI maps SIGTERM to it) the worker processes are terminated at once
and the exception propagates; the workers themselves ignore SIGINT, so a Ctrl-C in
the terminal reaches the main process only.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
from functools import partial

import numpy as np
from tqdm import tqdm

from . import io
from gfmd.loading import run_realization

#: curve columns averaged over realizations (mean and standard error)
AVERAGED = ("p", "a_rel", "g_r", "g")

_progress_queue = None  # set in each worker process by _init_worker


def _init_worker(queue):
    global _progress_queue
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the main process decides what an interrupt does
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _progress_queue = queue


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
        pool.close()
    except BaseException:
        pool.terminate()
        raise
    finally:
        pool.join()
        queue.put(None)
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

    Returns (realization, steps reused from an interrupted run, steps it ran).
    """
    scene, realization, out = job
    part = io.load_part(out, scene, realization)
    if part is not None and part[2]:
        return realization, 0, 0
    resume = part[:2] if part is not None else None
    io.start_part(out, realization, resume[0] if resume else None)
    reused = resume[1].step + 1 if resume else 0
    result = run_realization(scene, realization, progress=progress, resume=resume,
                             checkpoint=partial(io.save_step, out))
    io.save_realization(out, result)
    return realization, reused, len(result.curve["step"]) - reused


def run_to_directory(scene, out, workers=None, progress=True):
    """Run every realization into the prepared run directory `out` (workbench.io.prepare_run_dir).

    Every load step is on disk as soon as it is computed; realizations already done
    there are reused and an interrupted one continues from its last saved step (so a
    second call after an interrupt resumes). Returns (results, resume), results read
    back from disk in realization order, resume = {"realizations_reused", "steps_reused"}
    (steps_reused: the saved steps of interrupted realizations that were continued).
    """
    count = scene.surface.realizations
    parts = [io.load_part(out, scene, i) for i in range(count)]
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


def mean_standard_error(values):
    """Column-wise mean and standard error of `values` (realizations × steps), ignoring NaN.

    Returns (mean, se, count); mean is NaN where no realization has a value, se is 0
    where fewer than two have one.
    """
    values = np.asarray(values, dtype=float)
    valid = np.isfinite(values)
    count = valid.sum(axis=0)
    mean = np.divide(np.where(valid, values, 0.0).sum(axis=0), count, out=np.full(values.shape[1], np.nan),
                     where=count > 0)
    dev = np.where(valid, values - mean, 0.0)
    var = np.divide((dev**2).sum(axis=0), count - 1, out=np.zeros(values.shape[1]), where=count > 1)
    return mean, np.sqrt(var / np.maximum(count, 1)), count


def ensemble_average(results):
    """Step-wise mean and standard error over realizations.

    Returns dict with "delta" (m), and for each of `AVERAGED`: "<name>" (mean) and
    "<name>_se" (standard error, 0 for one realization). ḡ_r is averaged over the
    realizations where it is defined (contact present); "g_r_count" says how many.
    """
    delta = np.asarray(results[0].curve["delta"])
    for r in results[1:]:
        if not np.allclose(r.curve["delta"], delta, rtol=0, atol=1e-15):
            raise ValueError("realizations do not share the same load steps")
    out = {"delta": delta, "U": np.asarray(results[0].curve["U"])}
    for name in AVERAGED:
        mean, se, count = mean_standard_error([r.curve[name] for r in results])
        out[name] = mean
        out[name + "_se"] = se
        if name == "g_r":
            out["g_r_count"] = count
    return out
