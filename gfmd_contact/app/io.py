"""Result files of a run directory: assembled at its end, and read back.

Units: SI (see `gfmd_contact.core.conventions`). A finished run directory holds
  curve.csv       one row per (realization, step): realization, seed + CURVE_COLUMNS (SI) and, for
                  GFMD, `algorithm`: what relaxed the step ("ncg", "ncg→fire", "cg-dual", ...)
  mean_curve.csv  per step: δ, U and, for each of gfmd_contact.app.averages.AVERAGED, the mean over
                  realizations, its standard error and the count n of realizations with a value
  fields.npz      x, h_r<i> and, for the saved steps, r<i>_s<k>_<field> (FIELD_NAMES); a 2+1-D surface
                  adds y, and h and the fields are (Nx, Ny) arrays (axis 0 x, axis 1 y)
  scene.toml      the fully resolved scene
  meta.json       "complete", code version, method (GFMD: "gfmd-" and its algorithm chain's key, e.g.
                  "gfmd-ncg"), "algorithms" (GFMD: load steps per algorithm label, all realizations),
                  model solved and why, notes, messages,
                  timings, "resume" {"realizations_reused", "steps_reused"}, platform, "stickiness"
                  (the scene's diagnostics before any run, `gfmd_contact.core.stickiness.as_dict`: per key
                  value (null where not defined), unit, formula, reading or reason); a free boundary
                  (surface.boundary = "free") adds "far_field_shift" {"r<i>": {step: s (m)}} at the saved steps
                  (`gfmd_contact.core.free_boundary`: u + s the free displacement, δ − s the far-field approach)
ḡ_r is written as "nan" at steps without contact (undefined, seed Eq. 5).

Before any compute the directory is checked and started (`gfmd_contact.app.run_dir`: scene.toml and
meta.json "complete": false); while a run goes, every realization checkpoints each load step
into partial/ (`gfmd_contact.app.checkpoints`); `write_run` assembles the final files and removes
partial/; `read_run` reads a finished or unfinished run. Every file is written to a temporary
name and renamed, so an interrupt never leaves a half-written result.

The names of the two modules above are re-exported here, where other code imports them (and
patches them: callers look them up as `gfmd_contact.app.io.<name>`).
"""

from __future__ import annotations

import collections
import csv
import dataclasses
import io
import json
import shutil
from pathlib import Path

import numpy as np

from gfmd_contact.core.result import CURVE_COLUMNS, FIELD_NAMES
from gfmd_contact.core.scene import load_scene, scene_to_toml

from .averages import ensemble_average
from .checkpoints import (PARTIAL, _atomic_write, _file_mode, _fmt, _npz_bytes, checkpointing,  # noqa: F401
                          consistent_rows, load_part, save_realization, save_step, start_part)
from .cycles import has_path, mean_columns, meta_cycles, realization_cycles, step_loads
from .run_dir import (RUN_ENTRIES, RunDirError, _meta_base, code_version, prepare_run_dir,  # noqa: F401
                      remove_temporaries, run_complete, started_stickiness, stored_scene_differences)


def _far_field_shifts(results):
    """{"far_field_shift": {"r<i>": {step: s}}} of free-boundary results (Result.diagnostics), else {}."""
    shifts = {f"r{r.realization}": {str(k): float(v) for k, v in sorted(r.diagnostics["far_field_shift"].items())}
              for r in results if "far_field_shift" in r.diagnostics}
    return {"far_field_shift": shifts} if shifts else {}


def _user_law_notes(scene):
    """The note of a user-law run (gfmd_contact.run(law=...)): scene.toml alone cannot reproduce it."""
    if scene.user_law is None:
        return []
    return [f"interface.law = \"user\" ({scene.user_law.name}): the law's Python callables are not in scene.toml, "
            "so this run cannot be reproduced from scene.toml alone (nor with the gfmd command)"]


def write_run(out_dir, scene, results, timings=None, command=None, resume=None):
    """Write the final files of a run (module docstring) for `results` (list of Result) and
    remove partial/; returns the directory.

    resume: the reuse counts of `gfmd run --resume` (default none reused).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    results = sorted(results, key=lambda r: r.realization)
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    labelled = any("algorithms" in r.diagnostics for r in results)  # an extra text column: old readers skip it
    cycled = has_path(scene)  # a load path: branch, cycle, event columns (gfmd_contact.app.cycles)
    writer.writerow(("realization", "seed") + CURVE_COLUMNS + (("algorithm",) if labelled else ())
                    + (("branch", "cycle", "event") if cycled else ())
                    + (("load",) if cycled and scene.loading.control == "force" else ()))
    # each realization's cycles once: their per-step columns go into curve.csv, their observables into meta.json
    cycles = {r.realization: realization_cycles(scene, r.curve, r.diagnostics.get("instabilities"))
              for r in results} if cycled else {}
    for r in results:
        extra = cycles[r.realization][1] if cycled else {}
        for k in range(len(r.curve["step"])):
            writer.writerow([r.realization, r.seed] + [_fmt(r.curve[c][k]) for c in CURVE_COLUMNS]
                            + ([step_algorithm(r, k)] if labelled else []) + [extra[c][k] for c in extra])
    _atomic_write(out / "curve.csv", buf.getvalue())
    cols = ensemble_average(results, step_loads(scene))
    if cycled:
        cols.update(mean_columns(scene, cols["step"]))
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(list(cols))
    for k in range(cols["step"].size):
        writer.writerow([_fmt(v[k]) for v in cols.values()])
    _atomic_write(out / "mean_curve.csv", buf.getvalue())
    arrays = {"x": results[0].x, **({"y": results[0].y} if getattr(results[0], "y", None) is not None else {})}
    for r in results:
        arrays[f"h_r{r.realization}"] = r.h
        for step, fields in r.fields.items():
            for name in FIELD_NAMES:
                arrays[f"r{r.realization}_s{step}_{name}"] = fields[name]
    _atomic_write(out / "fields.npz", _npz_bytes(arrays), binary=True)
    _atomic_write(out / "scene.toml", scene_to_toml(scene))
    meta = _meta_base(scene, results[0].method, command, started_stickiness(out))
    meta.update({
        "complete": True,
        "model": results[0].model,
        "model_reasons": list(results[0].reasons),
        "realizations": [r.realization for r in results],
        "seeds": [r.seed for r in results],
        "steps_run": [len(r.curve["step"]) for r in results],
        "all_converged": all(r.all_converged for r in results),
        "notes": [n for r in results for n in r.notes] + _user_law_notes(scene),
        **({"algorithms": algorithm_counts(results)} if labelled else {}),
        **_far_field_shifts(results),
        **(meta_cycles(results, {k: rows for k, (rows, _) in cycles.items()}) if cycled else {}),
        "messages": [m for r in results for m in r.messages],
        "resume": resume or {"realizations_reused": 0, "steps_reused": 0},
        "timings": {**(timings or {}),
                    "solve_s_per_realization": [float(np.sum(r.curve["wall_s"])) for r in results]},
    })
    _atomic_write(out / "meta.json", json.dumps(meta, indent=2))
    shutil.rmtree(out / PARTIAL, ignore_errors=True)
    return out


def step_algorithm(result, k):
    """The algorithm label of row k of `result` (Result.diagnostics["algorithms"]; "" where unknown)."""
    labels = result.diagnostics.get("algorithms", [])
    return labels[k] if k < len(labels) else ""


def algorithm_counts(results):
    """{algorithm label: load steps it relaxed} over `results`, most steps first ("" where unknown)."""
    counts = collections.Counter(step_algorithm(r, k) for r in results for k in range(len(r.curve["step"])))
    return dict(counts.most_common())


def read_run(out_dir):
    """Read a run directory: (scene, curves, fields, meta).

    curves: {realization: {column: array}} (CURVE_COLUMNS, the realization's "seed" and, for an
    unfinished GFMD run, "algorithm");
    fields: the npz as a dict of arrays. An
    unfinished run (meta "complete": false) is read from its partial/ files: the steps
    done so far.
    """
    out = Path(out_dir)
    for name in ("scene.toml", "meta.json"):
        if not (out / name).is_file():
            raise FileNotFoundError(f"{out}: missing {name}; is this a `gfmd run` output directory?")
    scene = load_scene(out / "scene.toml")
    meta = json.loads((out / "meta.json").read_text())
    scene = dataclasses.replace(scene, name=meta.get("scene_name", scene.name))
    if not (out / "curve.csv").is_file():
        parts = [load_part(out, scene, i) for i in range(scene.surface.realizations)]
        results = [p[0].finalize() for p in parts if p is not None and p[0].curve["step"]]
        if not results:
            raise FileNotFoundError(f"{out}: an unfinished run with no completed load step yet")
        curves = {r.realization: {**{c: np.asarray(r.curve[c], float) for c in CURVE_COLUMNS},
                                  "seed": np.full(len(r.curve["step"]), float(r.seed))} for r in results}
        if any("algorithms" in r.diagnostics for r in results):  # as curve.csv's `algorithm` column
            for r in results:
                curves[r.realization]["algorithm"] = np.array([step_algorithm(r, k)
                                                               for k in range(len(r.curve["step"]))])
        fields = {"x": results[0].x, **({"y": results[0].y} if getattr(results[0], "y", None) is not None else {})}
        for r in results:
            fields[f"h_r{r.realization}"] = r.h
            for k, f in r.fields.items():
                fields.update({f"r{r.realization}_s{k}_{name}": f[name] for name in FIELD_NAMES})
        return scene, curves, fields, meta
    with open(out / "curve.csv") as fh:
        rows = list(csv.DictReader(fh))
    columns = CURVE_COLUMNS + (("seed",) if rows and "seed" in rows[0] else ())  # runs before the seed column
    curves = {}
    for row in rows:
        r = int(row["realization"])
        c = curves.setdefault(r, {k: [] for k in columns})
        for k in columns:
            c[k].append(float(row[k]))
    curves = {r: {k: np.asarray(v) for k, v in c.items()} for r, c in curves.items()}
    fields = dict(np.load(out / "fields.npz")) if (out / "fields.npz").is_file() else {}
    return scene, curves, fields, meta
