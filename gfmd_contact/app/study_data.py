"""A study directory read back for the claims and the study figures: sets, scenes, per-realization curves.

`read_study_dir(path)` reads study.json, base_scene.toml and the curves (study.csv of a complete
study, else every finished task's curve.csv) into a `StudyData` of `SetInfo`s, each with its
realizations stacked by step (`gfmd_contact.app.plots.stack_curves`) and their seeds. Units: SI.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from gfmd_contact.core.laws import law_from_scene
from gfmd_contact.core.scene import load_scene

from .plots import Stacked, stack_curves

#: numeric columns of the per-realization curves
COLUMNS = ("step", "U", "delta", "p", "a_rel", "g_r", "g", "iterations", "residual", "converged", "wall_s")


class StudyDirError(ValueError):
    """A directory that is not a study directory, or has no finished task."""


# ---------------------------------------------------------------- reading a study directory

@dataclass
class SetInfo:
    """One parameter set: index, parameters (study key → value), scene, E* (Pa), law, curves."""

    index: int
    params: dict
    scene: object
    e_star: float
    hard_wall: bool
    adhesive: bool
    realizations: int  # the set's realizations in the study (expected)
    stacked: Stacked | None = None  # realizations × steps (None: no finished task)
    seeds: dict = field(default_factory=dict)  # realization → seed
    tasks: dict = field(default_factory=dict)  # realization → task key

    def value(self, key):
        """The set's value of a dotted scene key (from its scene, so base keys work too)."""
        section, _, name = key.partition(".")
        return getattr(getattr(self.scene, section), name)

    @property
    def signature(self):
        """The set's scene without its adhesion (law, φn*, c, δt): equal for a set and its hard-wall reference."""
        import dataclasses

        i = self.scene.interface
        i = dataclasses.replace(i, law="hard-wall", phi_n_star=0.0, tangential_ratio=0.0, length_tangential=0.0)
        return (self.scene.surface, self.scene.material, self.scene.loading, i)


@dataclass
class StudyData:
    """A study directory read back: its record, base scene, varied keys, sets and counts."""

    path: Path
    name: str
    record: dict
    keys: list
    sets: list  # SetInfo, every set of the study (those without a finished task have stacked None)
    tasks_total: int
    tasks_done: int
    tasks_failed: int
    source: str  # "study.csv" or "tasks" (an unfinished study: the finished tasks' curve.csv)

    @property
    def partial(self):
        return self.tasks_done < self.tasks_total

    def partial_note(self):
        """'' for a complete study, else one line saying what is missing."""
        if not self.partial:
            return ""
        empty = [s.index for s in self.sets if s.stacked is None]
        short = [s.index for s in self.sets if s.stacked is not None and len(s.stacked.realizations) < s.realizations]
        bits = [f"PARTIAL STUDY: {self.tasks_done} of {self.tasks_total} tasks finished"]
        if self.tasks_failed:
            bits.append(f"{self.tasks_failed} failed")
        if empty:
            bits.append(f"no data for set{'s' if len(empty) > 1 else ''} {_ranges(empty)}")
        if short:
            bits.append(f"fewer realizations in set{'s' if len(short) > 1 else ''} {_ranges(short)}")
        return "; ".join(bits)

    @property
    def with_data(self):
        return [s for s in self.sets if s.stacked is not None]


def _ranges(ints):
    return ", ".join(str(i) for i in ints) if len(ints) <= 8 else f"{', '.join(map(str, ints[:8]))}, …"


def _float(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_study_dir(path):
    """Read a study directory (`gfmd_contact.app.study`): study.json, base_scene.toml and the curves.

    The curves come from study.csv when the study completed; otherwise (still running,
    interrupted) from the curve.csv of every finished task. Raises StudyDirError for a
    directory that is not a study directory or has no finished task.
    """
    path = Path(path)
    if not path.is_dir():
        raise StudyDirError(f"{path}: no such directory")
    if not (path / "study.json").is_file() or not (path / "base_scene.toml").is_file():
        raise StudyDirError(f"{path} is not a study directory (no study.json / base_scene.toml; "
                            "make one with gfmd study run STUDY.toml --out DIR)")
    try:
        record = json.loads((path / "study.json").read_text())
        base = load_scene(path / "base_scene.toml")
    except (OSError, ValueError) as exc:
        raise StudyDirError(f"{path}: cannot read the study: {exc}") from None
    keys = list(record.get("axes") or {}) + list(record.get("zip") or {})
    entries = record.get("tasks", [])
    by_set = {}
    for t in entries:
        by_set.setdefault(t["set"], []).append(t)
    sets = []
    for s in sorted(by_set):
        params = by_set[s][0]["parameters"]
        scene = base.replace(**params) if params else base
        law = law_from_scene(scene)
        info = SetInfo(index=s, params=params, scene=scene, e_star=scene.material.contact_modulus,
                       hard_wall=scene.interface.law == "hard-wall", adhesive=bool(law.adhesive),
                       realizations=len(by_set[s]))
        info.seeds = {t["realization"]: t["seed"] for t in by_set[s]}
        info.tasks = {t["realization"]: t["key"] for t in by_set[s]}
        sets.append(info)
    failed = sum(1 for t in entries if t.get("status") == "failed")
    curves = {}  # set → {realization: {column: array}}
    if record.get("complete") and (path / "study.csv").is_file():
        source = "study.csv"
        with open(path / "study.csv") as fh:
            for row in csv.DictReader(fh):
                c = curves.setdefault(int(row["set"]), {}).setdefault(int(row["realization"]),
                                                                       {k: [] for k in COLUMNS})
                for k in COLUMNS:
                    c[k].append(_float(row.get(k)))
    else:
        source = "tasks"
        for t in entries:
            f = path / "tasks" / t["key"] / "curve.csv"
            meta = path / "tasks" / t["key"] / "meta.json"
            if not f.is_file() or not meta.is_file() or not json.loads(meta.read_text()).get("complete"):
                continue
            with open(f) as fh:
                rows = list(csv.DictReader(fh))
            curves.setdefault(t["set"], {})[t["realization"]] = {k: [_float(r.get(k)) for r in rows] for k in COLUMNS}
    done = 0
    for info in sets:
        got = {r: {k: np.asarray(v, float) for k, v in c.items()} for r, c in curves.get(info.index, {}).items()
               if c["step"]}
        if got:
            info.stacked = stack_curves(got)
            done += len(got)
    if done == 0:
        raise StudyDirError(f"{path}: the study has no finished task yet ({len(entries)} task(s), {failed} failed)")
    return StudyData(path=path, name=record.get("study", path.name), record=record, keys=keys, sets=sets,
                     tasks_total=len(entries), tasks_done=done, tasks_failed=failed, source=source)
