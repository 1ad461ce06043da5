"""Ensembles: independent realizations in a local process pool, and their averages.

Units: SI (see `gfmd.conventions`). Every realization i uses the seed
`surface.seed + i`; all realizations share the same load steps, so averages are
taken step by step (at equal δ).
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor

import numpy as np
from tqdm import tqdm

from . import surfaces
from .loading import check_penetration_limit, run_realization

#: curve columns averaged over realizations (mean and standard error)
AVERAGED = ("p", "a_rel", "g_r", "g")


def _run_one(args):
    scene, realization = args
    return run_realization(scene, realization)


def run_ensemble(scene, workers=None, progress=True):
    """Run all `scene.surface.realizations`; returns the list of `Result` (ordered).

    workers: processes (default scene.output.workers, 0 = all cores); progress: tqdm bar.
    """
    count = scene.surface.realizations
    for i in range(count):  # fail before any work is spent
        check_penetration_limit(scene, surfaces.profile(scene.surface, i), i)
    workers = workers if workers is not None else scene.output.workers
    workers = min(count, workers or os.cpu_count() or 1)
    jobs = [(scene, i) for i in range(count)]
    bar = tqdm(total=count, desc=f"{scene.name}: realizations", unit="run", disable=not progress)
    results = []
    if workers <= 1:
        for job in jobs:
            results.append(_run_one(job))
            bar.update()
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            for result in pool.map(_run_one, jobs):
                results.append(result)
                bar.update()
    bar.close()
    return results


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
