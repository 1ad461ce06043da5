"""A study's tables: collect the finished tasks' curves into study.csv, summary.csv and summary.nc.

Units: SI (see `gfmd_contact.core.conventions`). In the study directory DIR (`gfmd_contact.app.study`):

  DIR/study.csv      one row per (task, step): set, one column per axis named by its dotted key
                     (zip keys too), realization, seed, task (the key), then curve.csv's columns
                     `gfmd_contact.core.result.CURVE_COLUMNS`: step, U (m), delta (m), p (Pa, > 0 compressive,
                     per unit area of the mean plane), a_rel (1), g_r (1: rms gradient of the
                     contact nodes, "nan" without contact), g (1: of the whole profile),
                     iterations, residual (relative), converged (0/1), wall_s (s), then
                     algorithm (GFMD: what relaxed the step, curve.csv's column; "" for another
                     method), then the set's
                     stickiness diagnostics before any run, stickiness_<key> for every key of
                     `gfmd_contact.core.stickiness.KEYS` (process_zone m, process_zone_nodes, johnson_alpha,
                     maugis_lambda, tabor_rough, persson_tosatti, pastewka_robbins: 1; "nan" where a
                     quantity is not defined for the set's scene, meta.json of a task says why)
  DIR/summary.csv    per set and step: set, the axis columns, step, delta (m), U (m) and for each
                     of p, a_rel, g_r, g (`gfmd_contact.app.averages.AVERAGED`) the mean over the set's
                     realizations, <name>_se (its standard error, 0 for one value) and <name>_n
                     (realizations with a value at that step), then the stickiness_<key> columns;
                     where a set's scene has loading.path, branch ("loading"/"unloading") and cycle
                     (0, 1, ...) of each step follow step (the means are per step, so the branches
                     never mix); where some set is under force control (loading.control =
                     "force"), load (Pa, the step's prescribed p̄; nan for a displacement-
                     controlled set) follows them, and delta, U are the means over the
                     realizations; a ramp study's files are unchanged
  DIR/summary.nc     the same as a labelled N-D dataset (xarray; netCDF3 through scipy, so no
                     netCDF4/HDF5 dependency): dims = the [axes] keys (coordinates: their values),
                     "zip" (coordinates: the zipped keys) if there is a [zip], and "step"; data
                     variables delta, U, set and the columns of summary.csv (NaN / n = 0 where a set
                     has fewer steps; the stickiness_<key> variables per set, without "step"; with
                     a path, branch (text, "" where no step) and cycle (int, -1 where no step);
                     under force control, load);
                     attributes: units, the study file's text

(DIR/cycles.csv, for load paths, is `gfmd_contact.app.cycles.write_study_cycles`.)
"""

from __future__ import annotations

import csv
import io as _io
from types import SimpleNamespace

import numpy as np

from gfmd_contact.core.result import CURVE_COLUMNS
from gfmd_contact.core.stickiness import KEYS as STICKINESS_KEYS
from gfmd_contact.core.stickiness import as_dict as stickiness_dict

from . import io
from .averages import AVERAGED, ensemble_average
from .cycles import has_path, mean_columns, step_loads

#: units of the summary columns (netCDF attributes)
UNITS = {"load": "Pa", "delta": "m", "U": "m", "p": "Pa", "a_rel": "1", "g_r": "1", "g": "1"}


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
    branch ("loading"/"unloading") and cycle (0, 1, ...) of each step after step (gfmd_contact.app.cycles);
    forced (some set is under force control): then load (Pa, the step's prescribed p̄; NaN for a set
    under displacement control), before delta and U (there the means over the realizations)."""
    cols = ["step"] + (["branch", "cycle"] if cycled else []) + (["load"] if forced else []) + ["delta", "U"]
    for name in AVERAGED:
        cols += [name, f"{name}_se", f"{name}_n"]
    return cols


def stickiness_columns():
    """The per-set stickiness columns of study.csv / summary.csv: "stickiness_<key>" (gfmd_contact.core.stickiness.KEYS)."""
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
    sticky = [stickiness_dict(scene) for scene in study.scenes]  # per set, before any run (gfmd_contact.core.stickiness)
    for key in STICKINESS_KEYS:
        cells = np.full(shape, np.nan)  # NaN: not defined for the set's scene
        for s, idx in enumerate(study.index):
            cells[idx] = _float_or_nan(sticky[s][key]["value"])
        variables[f"stickiness_{key}"] = (dims, cells, {
            "long_name": f"stickiness diagnostic {key} of the set (gfmd_contact.core.stickiness; NaN: not defined)",
            "units": sticky[0][key]["unit"] if sticky else "1"})
    return xr.Dataset(variables, coords=coords,
                      attrs={"study": study.name, "study_text": study.text,
                             "conventions": "SI units; p > 0 compressive; see gfmd_contact/core/conventions.py"})
