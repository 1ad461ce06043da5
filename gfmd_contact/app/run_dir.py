"""The run directory before a run: refuse what cannot take it, then start it (scene.toml, meta.json).

`prepare_run_dir` checks an output directory before any compute (a file, a non-empty directory
without --resume/--overwrite, a directory of another scene, files a run does not write: each
refused with `RunDirError` saying what to do) and writes scene.toml and meta.json
("complete": false, `_meta_base`: code version, platform, stickiness diagnostics) first, so an
interrupted run is recognisable and resumable; `run_complete` says whether one finished.
"""

from __future__ import annotations

import functools
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from gfmd_contact.core import stickiness
from gfmd_contact.core.laws import law_from_scene
from gfmd_contact.core.scene import load_scene, scene_to_dict, scene_to_toml

from . import safe_files
from .checkpoints import PARTIAL, _atomic_write

#: files and folders a run directory may hold (what --overwrite removes)
RUN_ENTRIES = ("curve.csv", "mean_curve.csv", "fields.npz", "scene.toml", "meta.json", "plots", "vtu", "partial")


#: the run directory's options as the command line names them, and as the Python API's keywords (`RunDirError`)
CLI_WORDS = {"out": "--out", "resume": "--resume", "overwrite": "--overwrite",
             "same_scene": "the same scene (or omit the scene file to take it from the directory)"}
PYTHON_WORDS = {"out": "out", "resume": "resume=True", "overwrite": "overwrite=True",
                "same_scene": "the same scene (gfmd_contact.open_run(out).scene)"}


class RunDirError(ValueError):
    """An output directory that cannot take this run: the message says why and what to do.

    Raised with `options`, the message names the options in command-line words (``str(exc)``: "add --resume");
    `in_python` is the same error in the Python API's keywords ("add resume=True"), what `gfmd_contact.run` raises.
    """

    template = None

    @classmethod
    def options(cls, template, **values):
        """The error of `template`, a str.format text with the option fields of `CLI_WORDS` and `values`."""
        exc = cls(template.format(**CLI_WORDS, **values))
        exc.template, exc.values = template, values
        return exc

    def in_python(self):
        """This error naming the Python keywords (itself where it names no option)."""
        if self.template is None:
            return self
        exc = type(self)(self.template.format(**PYTHON_WORDS, **self.values))
        exc.template, exc.values = self.template, self.values
        return exc


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
        root = Path(__file__).resolve().parent.parent.parent
        sha = subprocess.run(["git", "describe", "--always", "--dirty"], cwd=root, capture_output=True,
                             text=True, timeout=5).stdout.strip()
        if sha:
            v += f"+git.{sha}"
    except (OSError, subprocess.SubprocessError):
        pass
    return v


def _meta_base(scene, method, command, stickiness_entry=None):
    """meta.json's entries known before any step; stickiness_entry: the scene's diagnostics where the run's start
    already computed them (`started_stickiness`), else computed here."""
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
        "units": "SI: m, Pa, J/m^2; see gfmd_contact/core/conventions.py",
        # before any run: gfmd_contact.core.stickiness (value null = n/a, reason)
        "stickiness": stickiness.as_dict(scene) if stickiness_entry is None else stickiness_entry,
        **({"user_law": law_from_scene(scene).summary()} if scene.user_law is not None else {}),
    }


def started_stickiness(out):
    """The stickiness diagnostics the run's start wrote into DIR/meta.json (`prepare_run_dir`), or None."""
    try:
        return json.loads((Path(out) / "meta.json").read_text(encoding="utf-8")).get("stickiness")
    except (OSError, ValueError):
        return None


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
        raise RunDirError.options("{out} {path!r} is an existing file, not a directory: choose another {out}",
                                  path=str(out))
    existing = sorted(p.name for p in out.iterdir() if p.name != safe_files.LOCK_NAME) if out.is_dir() else []
    if existing and resume and (out / "scene.toml").is_file():
        diff = stored_scene_differences(out, scene)
        if diff:
            raise RunDirError.options("{resume}: {path} holds a run of another scene ({diff}); resume with "
                                      "{same_scene}, or choose another {out}", path=out, diff="; ".join(diff))
        remove_temporaries(out)
        if run_complete(out):  # partial/ outlives a kill between the final meta.json and its removal
            shutil.rmtree(out / PARTIAL, ignore_errors=True)
            return out
        (out / PARTIAL).mkdir(exist_ok=True)
        if not (out / "meta.json").is_file():  # a start cut short after scene.toml
            _atomic_write(out / "meta.json", json.dumps(_meta_base(scene, scene.method.name, command), indent=2))
        return out
    if existing and resume:
        raise RunDirError.options("{resume}: {path} is not empty but holds no scene.toml ({entries}): it is not a "
                                  "gfmd run directory; choose another {out}", path=out, entries=", ".join(existing))
    if existing and not overwrite:
        what = "an unfinished run" if (out / PARTIAL).is_dir() else "files"
        raise RunDirError.options("{out} {path} is not empty (it holds {what}: {entries}): add {resume} to continue "
                                  "a run there, {overwrite} to replace it, or choose another {out}", path=out,
                                  what=what, entries=", ".join(existing[:6]) + (", …" if len(existing) > 6 else ""))
    if existing:
        foreign = [n for n in existing if n not in RUN_ENTRIES and not n.startswith(".")]
        if foreign:
            raise RunDirError.options("{overwrite}: {path} holds files a run does not write ({entries}); not "
                                      "removing them: choose another {out} or remove them yourself", path=out,
                                      entries=", ".join(foreign))
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
