"""Ensemble averages: step-wise mean, standard error and count over realizations.

Units: those of the averaged columns (SI, see `gfmd_contact.core.conventions`). Realizations
share the load steps of `gfmd_contact.core.loading`; one that stopped early, or has no value
at a step (ḡ_r without contact), is left out of that step, and the count n says so.
"""

from __future__ import annotations

import numpy as np

#: curve columns averaged over realizations (mean and standard error)
AVERAGED = ("p", "a_rel", "g_r", "g")


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


def ensemble_average(results, loads=None):
    """Per load step: "step", "delta" (m), "U" (m) and, for each of `AVERAGED`, "<name>" (mean),
    "<name>_se" (standard error, 0 for one value) and "<name>_n" (realizations with a value).

    Realizations are matched by step index (the columns of mean_curve.csv). Under displacement control
    they share δ and U at every step (checked). loads: under force control the prescribed p̄ (Pa) of every
    step (`gfmd_contact.core.loading.path_values`): the realizations share the loads and δ, U are outcomes, so
    "delta" and "U" are then their means over the realizations with a value, and "load" is added.
    """
    longest = max(results, key=lambda r: len(r.curve["step"]))
    steps = np.asarray(longest.curve["step"], int)
    cols = {"step": steps, "delta": np.asarray(longest.curve["delta"], float),
            "U": np.asarray(longest.curve["U"], float)}
    if loads is None:
        for r in results:
            k = np.asarray(r.curve["step"], int)
            if not np.array_equal(np.asarray(r.curve["delta"], float), cols["delta"][k]):
                raise ValueError(f"realization {r.realization} does not share the load steps of the others")
    names = AVERAGED if loads is None else ("delta", "U") + AVERAGED
    for name in names:
        table = np.full((len(results), steps.size), np.nan)
        for row, r in zip(table, results):
            row[np.asarray(r.curve["step"], int)] = r.curve[name]
        mean, se, count = mean_standard_error(table)
        if name in ("delta", "U"):
            cols[name] = mean
            continue
        cols[name], cols[name + "_se"], cols[name + "_n"] = mean, se, count
    if loads is not None:
        cols["load"] = np.asarray(loads, float)[steps]
    return cols
