"""Result files of a run directory, written atomically.

Units: SI (see `gfmd.conventions`). A run directory holds
  curve.csv   one row per (realization, step): realization + CURVE_COLUMNS (SI)
  fields.npz  x, h_r<i> and, for the saved steps, r<i>_s<k>_<field> (FIELD_NAMES)
  scene.toml  the fully resolved scene
  meta.json   code version, method, model solved and why, timings, platform, messages
ḡ_r is written as "nan" at steps without contact (undefined, seed Eq. 5).
Every file is written to a temporary name and renamed, so an interrupt never
leaves a half-written result.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .result import CURVE_COLUMNS, FIELD_NAMES
from .scene import load_scene, scene_to_toml


def code_version():
    """Package version plus the git commit of the source tree when available."""
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


def _atomic_write(path, data, binary=False):
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb" if binary else "w") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_run(out_dir, scene, results, timings=None, command=None):
    """Write curve.csv, fields.npz, scene.toml and meta.json for `results` (list of Result)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(("realization",) + CURVE_COLUMNS)
    for r in results:
        for k in range(len(r.curve["step"])):
            writer.writerow([r.realization] + [_fmt(r.curve[c][k]) for c in CURVE_COLUMNS])
    _atomic_write(out / "curve.csv", buf.getvalue())
    arrays = {"x": results[0].x}
    for r in results:
        arrays[f"h_r{r.realization}"] = r.h
        for step, fields in r.fields.items():
            for name in FIELD_NAMES:
                arrays[f"r{r.realization}_s{step}_{name}"] = fields[name]
    npz = io.BytesIO()
    np.savez_compressed(npz, **arrays)
    _atomic_write(out / "fields.npz", npz.getvalue(), binary=True)
    _atomic_write(out / "scene.toml", scene_to_toml(scene))
    messages = [m for r in results for m in r.messages]
    meta = {
        "code_version": code_version(),
        "scene_name": scene.name,
        "method": results[0].method,
        "model": results[0].model,
        "model_reasons": list(results[0].reasons),
        "realizations": [r.realization for r in results],
        "all_converged": all(r.all_converged for r in results),
        "messages": messages,
        "timings": {**(timings or {}),
                    "solve_s_per_realization": [float(np.sum(r.curve["wall_s"])) for r in results]},
        "platform": {"python": sys.version.split()[0], "machine": platform.machine(),
                     "system": platform.platform(), "cpus": os.cpu_count()},
        "numpy": np.__version__,
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": command or " ".join(sys.argv),
        "units": "SI: m, Pa, J/m^2; see gfmd/conventions.py",
    }
    _atomic_write(out / "meta.json", json.dumps(meta, indent=2))
    return out


def _fmt(v):
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    return str(int(v)) if isinstance(v, (bool, np.bool_, int, np.integer)) else str(v)


def read_run(out_dir):
    """Read a run directory: (scene, curves, fields, meta).

    curves: {realization: {column: array}}; fields: the npz as a dict of arrays.
    """
    out = Path(out_dir)
    for name in ("curve.csv", "scene.toml", "meta.json"):
        if not (out / name).is_file():
            raise FileNotFoundError(f"{out}: missing {name}; is this a `gfmd run` output directory?")
    scene = load_scene(out / "scene.toml")
    with open(out / "curve.csv") as fh:
        rows = list(csv.DictReader(fh))
    curves = {}
    for row in rows:
        r = int(row["realization"])
        c = curves.setdefault(r, {k: [] for k in CURVE_COLUMNS})
        for k in CURVE_COLUMNS:
            c[k].append(float(row[k]))
    curves = {r: {k: np.asarray(v) for k, v in c.items()} for r, c in curves.items()}
    fields = dict(np.load(out / "fields.npz")) if (out / "fields.npz").is_file() else {}
    meta = json.loads((out / "meta.json").read_text())
    scene = dataclasses.replace(scene, name=meta.get("scene_name", scene.name))
    return scene, curves, fields, meta
