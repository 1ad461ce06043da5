"""Result files of a run directory: written as the run goes, assembled at its end.

Units: SI (see `contact.conventions`). A finished run directory holds
  curve.csv       one row per (realization, step): realization, seed + CURVE_COLUMNS (SI) and, for
                  GFMD, `algorithm`: what relaxed the step ("ncg", "ncg→fire", "cg-dual", ...)
  mean_curve.csv  per step: δ, U and, for each of workbench.averages.AVERAGED, the mean over
                  realizations, its standard error and the count n of realizations with a value
  fields.npz      x, h_r<i> and, for the saved steps, r<i>_s<k>_<field> (FIELD_NAMES); a 2+1-D surface
                  adds y, and h and the fields are (Nx, Ny) arrays (axis 0 x, axis 1 y)
  scene.toml      the fully resolved scene
  meta.json       "complete", code version, method (GFMD: "gfmd-" and its algorithm chain's key, e.g.
                  "gfmd-ncg"), "algorithms" (GFMD: load steps per algorithm label, all realizations),
                  model solved and why, notes, messages,
                  timings, "resume" {"realizations_reused", "steps_reused"}, platform, "stickiness"
                  (the scene's diagnostics before any run, `contact.stickiness.as_dict`: per key
                  value (null where not defined), unit, formula, reading or reason)
ḡ_r is written as "nan" at steps without contact (undefined, seed Eq. 5).

While a run goes, scene.toml and meta.json ("complete": false) are written before any
compute, and every realization writes into partial/ after each load step
(`save_step`): realization<i>.csv (its rows, appended), realization<i>_step<k>.npz
(saved fields, and the warm start after that step) and realization<i>.state.npz (the `contact.loading.RampState` warm start,
messages, reasons, notes; "done" once the realization ends). `load_part` reads them
back to continue an interrupted run (`gfmd run --resume`); `write_run` assembles the
final files and removes partial/. Every file is written to a temporary name and
renamed (a CSV row is appended and flushed), so an interrupt never leaves a
half-written result; files get the permissions of the process umask.
"""

from __future__ import annotations

import collections
import csv
import dataclasses
import functools
import io
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from contact import stickiness, surfaces
from contact.laws import law_from_scene
from contact.ramp import y_positions
from contact.result import CURVE_COLUMNS, FIELD_NAMES, Result
from contact.scene import load_scene, scene_to_dict, scene_to_toml

from . import safe_files
from .averages import ensemble_average
from .cycles import has_path, mean_columns, meta_cycles, realization_cycles, step_loads

#: files and folders a run directory may hold (what --overwrite removes)
RUN_ENTRIES = ("curve.csv", "mean_curve.csv", "fields.npz", "scene.toml", "meta.json", "plots", "vtu", "partial")
PARTIAL = "partial"


class RunDirError(ValueError):
    """An output directory that cannot take this run: the message says why and what to do."""


@functools.cache
def code_version():
    """Package version plus the git commit of the source tree when available.

    Computed once per process, when first asked (a run asks before its first step): a long-lived
    process (a study worker) keeps reporting the version of the code it started with, not that of
    a later checkout of the tree.
    """
    from importlib.metadata import PackageNotFoundError, version

    try:
        v = version("gfmd-contact")
    except PackageNotFoundError:
        v = "unknown"
    try:
        root = Path(__file__).resolve().parent.parent
        sha = subprocess.run(["git", "describe", "--always", "--dirty"], cwd=root, capture_output=True,
                             text=True, timeout=5).stdout.strip()
        if sha:
            v += f"+git.{sha}"
    except (OSError, subprocess.SubprocessError):
        pass
    return v


def _file_mode():
    return safe_files.file_mode()


def _atomic_write(path, data, binary=False):
    safe_files.atomic_write(path, data, binary=binary)


def _npz_bytes(arrays, compress=True):
    """The .npz file of `arrays` as bytes. compress=False for the per-step warm-start state:
    float spectra hardly compress, and zlib cost 24 % of a hard-wall study task at N = 2^17."""
    buf = io.BytesIO()
    (np.savez_compressed if compress else np.savez)(buf, **arrays)
    return buf.getvalue()


def _meta_base(scene, method, command):
    return {
        "complete": False,
        "code_version": code_version(),
        "scene_name": scene.name,
        "method": method,
        "platform": {"python": sys.version.split()[0], "machine": platform.machine(),
                     "system": platform.platform(), "cpus": os.cpu_count()},
        "numpy": np.__version__,
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": command or " ".join(sys.argv),
        "units": "SI: m, Pa, J/m^2; see contact/conventions.py",
        "stickiness": stickiness.as_dict(scene),  # before any run: contact.stickiness (value null = n/a, reason)
        **({"user_law": law_from_scene(scene).summary()} if scene.user_law is not None else {}),
    }


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
    cycled = has_path(scene)  # a load path: branch, cycle, event columns (workbench.cycles)
    writer.writerow(("realization", "seed") + CURVE_COLUMNS + (("algorithm",) if labelled else ())
                    + (("branch", "cycle", "event") if cycled else ())
                    + (("load",) if cycled and scene.loading.control == "force" else ()))
    for r in results:
        extra = realization_cycles(scene, r.curve, r.diagnostics.get("instabilities"))[1] if cycled else {}
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
    meta = _meta_base(scene, results[0].method, command)
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
        **(meta_cycles(scene, results) if cycled else {}),
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


def _fmt(v):
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    return str(int(v)) if isinstance(v, (bool, np.bool_, int, np.integer)) else str(v)


# ---------------------------------------------------------------- the run directory before and while a run goes

def _differences(a, b, prefix=""):
    keys = sorted(set(a) | set(b))
    out = []
    for k in keys:
        va, vb = a.get(k), b.get(k)
        if isinstance(va, dict) and isinstance(vb, dict):
            out += _differences(va, vb, f"{prefix}{k}.")
        elif va != vb:
            out.append(f"{prefix}{k}: {va!r} there, {vb!r} now")
    return out


def stored_scene_differences(out, scene):
    """The keys in which DIR/scene.toml differs from `scene` ("key: there, now"; output.workers ignored)."""
    a, b = scene_to_dict(load_scene(Path(out) / "scene.toml")), scene_to_dict(scene)
    for d in (a, b):
        d["output"].pop("workers", None)
    return _differences(a, b)


def prepare_run_dir(out, scene, *, resume=False, overwrite=False, command=None):
    """Check `out` before any compute and start the run there; returns the directory (Path).

    Refused (RunDirError): `out` is a file; without resume, a non-empty `out` (overwrite
    clears the entries a run writes, RUN_ENTRIES, and refuses if anything else is there);
    with resume, a directory holding another scene (the differing keys named, the method
    included; output.workers may differ). Then scene.toml and meta.json ("complete": false) are
    written, so an interrupted run is recognisable and resumable.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise RunDirError(f"--out {str(out)!r} is an existing file, not a directory: choose another --out")
    existing = sorted(p.name for p in out.iterdir() if p.name != safe_files.LOCK_NAME) if out.is_dir() else []
    if existing and resume and (out / "scene.toml").is_file():
        diff = stored_scene_differences(out, scene)
        if diff:
            raise RunDirError(f"--resume: {out} holds a run of another scene ({'; '.join(diff)}); resume with "
                              "the same scene (or omit the scene file to take it from the directory), or choose "
                              "another --out")
        remove_temporaries(out)
        if run_complete(out):  # partial/ outlives a kill between the final meta.json and its removal
            shutil.rmtree(out / PARTIAL, ignore_errors=True)
            return out
        (out / PARTIAL).mkdir(exist_ok=True)
        if not (out / "meta.json").is_file():  # a start cut short after scene.toml
            _atomic_write(out / "meta.json", json.dumps(_meta_base(scene, scene.method.name, command), indent=2))
        return out
    if existing and resume:
        raise RunDirError(f"--resume: {out} is not empty but holds no scene.toml ({', '.join(existing)}): it is not a "
                          "gfmd run directory; choose another --out")
    if existing and not overwrite:
        what = "an unfinished run" if (out / PARTIAL).is_dir() else "files"
        raise RunDirError(f"--out {out} is not empty (it holds {what}: {', '.join(existing[:6])}"
                          f"{', …' if len(existing) > 6 else ''}): add --resume to continue a run there, "
                          "--overwrite to replace it, or choose another --out")
    if existing:
        foreign = [n for n in existing if n not in RUN_ENTRIES and not n.startswith(".")]
        if foreign:
            raise RunDirError(f"--overwrite: {out} holds files a run does not write ({', '.join(foreign)}); "
                              "not removing them: choose another --out or remove them yourself")
        for name in existing:
            path = out / name
            shutil.rmtree(path) if path.is_dir() else path.unlink()
    out.mkdir(parents=True, exist_ok=True)
    _atomic_write(out / "scene.toml", scene_to_toml(scene))
    meta = _meta_base(scene, scene.method.name, command)
    _atomic_write(out / "meta.json", json.dumps(meta, indent=2))
    (out / PARTIAL).mkdir(exist_ok=True)
    return out


def remove_temporaries(out):
    """Remove the temporary files (.NAME.*.tmp) a killed writer left in `out`, partial/ and plots/
    (call only while holding the directory's lock: nobody else is writing them)."""
    for d in (Path(out), Path(out) / PARTIAL, Path(out) / "plots"):
        for p in d.glob(".*.tmp") if d.is_dir() else []:
            p.unlink(missing_ok=True)


def run_complete(out):
    """True if `out` holds a finished run (meta.json "complete": true)."""
    meta = Path(out) / "meta.json"
    return meta.is_file() and json.loads(meta.read_text()).get("complete") is True


def _part(out, realization, suffix):
    return Path(out) / PARTIAL / f"realization{realization}{suffix}"


def _save_state(out, result, state, done):
    arrays = {"step": np.int64(state.step), "done": np.bool_(done), "slip_warned": np.bool_(state.slip_warned),
              "text": np.array(json.dumps({"method": result.method, "model": result.model,
                                           "reasons": list(result.reasons), "messages": list(result.messages),
                                           "notes": list(result.notes),
                                           "fallback_steps": list(result.diagnostics.get("fallback_steps", [])),
                                           "algorithms": list(result.diagnostics.get("algorithms", [])),
                                           "instabilities": list(result.diagnostics.get("instabilities", []))}))}
    if not done:
        arrays.update(current=state.current, previous=state.previous)
    _atomic_write(_part(out, result.realization, ".state.npz"), _npz_bytes(arrays, compress=False),
                  binary=True)


def _save_fields(out, result, k, state=None):
    """Step k's saved fields, and the method's per-step diagnostics of that step (diag_<name>); with the
    ramp's `state` after step k, also its warm start (ramp_current, ramp_previous, ramp_slip_warned) and
    the counts of messages, reasons and notes then (ramp_counts): what `load_part` continues from when
    the CSV's consistent rows end before the saved step."""
    arrays = dict(result.fields[k])
    arrays.update({f"diag_{name}": per_step[k] for name, per_step in result.diagnostics.items()
                   if isinstance(per_step, dict) and k in per_step})
    if state is not None and state.current is not None:
        arrays.update(ramp_current=state.current, ramp_previous=state.previous,
                      ramp_slip_warned=np.bool_(state.slip_warned),
                      ramp_counts=np.array([len(result.messages), len(result.reasons), len(result.notes)]))
    _atomic_write(_part(out, result.realization, f"_step{k}.npz"), _npz_bytes(arrays), binary=True)


def save_step(out, result, state):
    """Checkpoint (gfmd.loading.run_realization): put step state.step of `result` on disk.

    Order: the curve row (appended, flushed), the step's fields if saved, then the state;
    `load_part` trusts a row only up to the state's step, so a kill between any two writes
    loses at most that one step. A saved step's fields file also keeps the warm start after it,
    so rows lost before the state's step cost only the steps after the last saved one (a second,
    rotating state file instead would write the state twice every step: +66 kB a step at
    N = 4096, against +64 kB per saved step here, measured).
    """
    k = state.step
    row = [_fmt(result.curve[c][-1]) for c in CURVE_COLUMNS]
    safe_files.append_line(_part(out, result.realization, ".csv"), ",".join(row), header=",".join(CURVE_COLUMNS))
    if k in result.fields:
        _save_fields(out, result, k, state)
    _save_state(out, result, state, done=False)


def start_part(out, realization, result=None):
    """Before a realization (re)starts: its CSV holds exactly the rows of `result` (a
    `load_part` result to continue) or none, dropping a row cut short by a kill, and the saved
    fields of steps after them (dropped by a cut-back) are removed."""
    path = _part(out, realization, ".csv")
    last = len(result.curve["step"]) - 1 if result is not None else -1
    for f in Path(out, PARTIAL).glob(f"realization{realization}_step*.npz"):  # fields of dropped steps
        k = f.name[len(f"realization{realization}_step"):-4]
        if k.isdigit() and int(k) > last:
            with safe_files.writing(f):
                f.unlink(missing_ok=True)
    if result is None:  # a fresh start: no state (it may be one that could not be continued), no rows
        with safe_files.writing(path):
            _part(out, realization, ".state.npz").unlink(missing_ok=True)
            path.unlink(missing_ok=True)
        return
    buf = io.StringIO()
    buf.write(",".join(CURVE_COLUMNS) + "\n")
    for k in range(len(result.curve["step"])):
        buf.write(",".join(_fmt(result.curve[c][k]) for c in CURVE_COLUMNS) + "\n")
    _atomic_write(path, buf.getvalue())


def save_realization(out, result):
    """Mark a finished realization done; one that was not checkpointed step by step (a run
    without the checkpoint hook) is first put on disk at once."""
    from contact.loading import RampState

    rows = len(result.curve["step"])
    if not _part(out, result.realization, ".csv").is_file():
        start_part(out, result.realization, result)
        for k in result.fields:
            _save_fields(out, result, k)
    last = int(result.curve["step"][-1]) if rows else -1
    _save_state(out, result, RampState(step=last, current=None, previous=None), done=True)


def consistent_rows(path, last_step):
    """The longest prefix of a partial CSV that a checkpoint can trust: complete rows (newline-ended,
    every column a number) numbered 0, 1, 2, … up to `last_step`; (rows as dicts, rows in the file)."""
    try:
        lines = Path(path).read_text().split("\n")
    except FileNotFoundError:
        return [], 0
    total = sum(1 for line in lines[1:] if line)
    if lines[0] != ",".join(CURVE_COLUMNS):
        return [], total
    rows = []
    for i, line in enumerate(lines[1:-1]):  # the text after the last newline is a row cut short
        values = line.split(",")
        if i > last_step or len(values) != len(CURVE_COLUMNS):
            break
        try:
            row = {c: (int(float(v)) if c in ("step", "iterations", "converged") else float(v))
                   for c, v in zip(CURVE_COLUMNS, values)}
        except ValueError:
            break
        if row["step"] != i:
            break
        rows.append(row)
    return rows, total


def load_part(out, scene, realization, notes=None):
    """(result, state, done) of a realization found in out/partial, or None if it has no usable state.

    result holds the steps up to state.step (lists, ready to be continued), its saved
    fields, messages, reasons and notes; state is the `contact.loading.RampState` to
    resume from (its arrays None when done). Damage is repaired, not refused: rows after
    the saved step (a kill between a row and its state, a second writer) are dropped; a CSV
    whose consistent prefix (`consistent_rows`) ends at a step m before the saved step is cut
    back to the last step j ≤ m whose saved fields carry the ramp's warm start (`_save_fields`:
    current, previous, slip_warned and the message counts after step j, exactly as the ramp had
    them, so the continuation equals an uninterrupted run's), messages and reasons of later steps
    dropped, not done; with no such j, or an unreadable state, None (the realization restarts).
    Each repair appends one line to `notes` (a list) if given.
    """
    from contact.loading import RampState

    path = _part(out, realization, ".state.npz")
    if not path.is_file():
        return None
    csv_path = _part(out, realization, ".csv")
    try:
        with np.load(path) as z:
            step, done, slip = int(z["step"]), bool(z["done"]), bool(z["slip_warned"])
            text = json.loads(str(z["text"]))
            current = z["current"] if "current" in z else None
            previous = z["previous"] if "previous" in z else None
    except (OSError, ValueError, KeyError, EOFError) as exc:
        if notes is not None:
            notes.append(f"{path}: unreadable ({exc}): realization {realization} restarts from step 0")
        return None
    rows, total = consistent_rows(csv_path, step)
    if len(rows) < step + 1:
        where = (f"{csv_path}: {total} rows for {step + 1} saved steps, consistent only up to step {len(rows) - 1} "
                 "(rows missing, cut or out of order: written by another process?)")
        earlier = _saved_warm_start(out, realization, len(rows) - 1)
        if earlier is None:
            if notes is not None:
                notes.append(f"{where}; no warm start of a step up to {len(rows) - 1} is on disk (one is kept with "
                             f"the fields of each saved step, output.field_steps): realization {realization} "
                             f"restarts from step 0 ({step + 1} saved steps dropped)")
            return None
        if notes is not None:
            notes.append(f"{where}; kept steps 0–{earlier[0]} (the last of them whose warm start is on disk, with "
                         f"its saved fields), dropped {step - earlier[0]} saved step(s): realization {realization} "
                         f"continues from step {earlier[0] + 1}")
        step, current, previous, slip, (n_messages, n_reasons, n_notes) = earlier
        done, rows = False, rows[:step + 1]
        text.update(messages=text["messages"][:n_messages], reasons=text["reasons"][:n_reasons],
                    notes=text["notes"][:n_notes])
    elif total > len(rows) and notes is not None:
        notes.append(f"{csv_path}: {total} rows for {step + 1} saved steps: kept steps 0–{step}, dropped "
                     f"{total - len(rows)} row(s) written after the last saved step (a process killed between a row "
                     f"and its checkpoint, or a second writer); realization {realization} continues from step "
                     f"{step + 1}")
    h = surfaces.profile(scene.surface, realization)
    result = Result(scene=scene, method=text["method"], model=text["model"], realization=realization,
                    x=surfaces.grid(scene.surface.nodes, scene.surface.length), y=y_positions(scene.surface), h=h,
                    reasons=tuple(text["reasons"]), messages=text["messages"], notes=text["notes"])
    if text.get("fallback_steps"):
        result.diagnostics["fallback_steps"] = [k for k in text["fallback_steps"] if k <= step]
    if text.get("algorithms"):
        result.diagnostics["algorithms"] = text["algorithms"][:step + 1]
    if text.get("instabilities"):  # force control's events (contact.force)
        result.diagnostics["instabilities"] = [e for e in text["instabilities"] if e["step"] <= step]
    for row in rows:
        result.append_step(**row)
    for k in range(step + 1):
        f = _part(out, realization, f"_step{k}.npz")
        if f.is_file():
            with np.load(f) as z:
                result.fields[k] = {name: z[name] for name in FIELD_NAMES}
                for name in z.files:
                    if name.startswith("diag_"):
                        result.diagnostics.setdefault(name[5:], {})[k] = z[name]
    return result, RampState(step=step, current=current, previous=previous, slip_warned=slip), done


def _saved_warm_start(out, realization, last):
    """(step, current, previous, slip_warned, (messages, reasons, notes) counts) of the highest step ≤ `last`
    whose saved fields carry the ramp's warm start (`_save_fields`), or None if none does."""
    found = []
    for f in Path(out, PARTIAL).glob(f"realization{realization}_step*.npz"):
        k = f.name[len(f"realization{realization}_step"):-4]
        if k.isdigit() and int(k) <= last:
            found.append((int(k), f))
    for k, f in sorted(found, reverse=True):
        try:
            with np.load(f) as z:
                if "ramp_current" in z:
                    return (k, z["ramp_current"], z["ramp_previous"], bool(z["ramp_slip_warned"]),
                            [int(c) for c in z["ramp_counts"]])
        except (OSError, ValueError, KeyError, EOFError):  # damaged: try an earlier one
            continue
    return None


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
