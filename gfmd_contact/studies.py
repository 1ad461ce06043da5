"""Studies from Python: a grid of scenes × realizations on Dask, read back with xarray and pandas.

Units: SI throughout (`gfmd_contact.core.conventions`). A study is a base scene and axes over
scene keys by their dotted names (the grid is their product; zipped keys vary
together); each (parameter set, realization) is one content-addressed, resumable
task (`gfmd_contact.app.study`, the same as `gfmd study run`).
"""

from __future__ import annotations

import functools
import json
import math
import tomllib
from pathlib import Path

from gfmd_contact.core.scene import Scene, scene_to_dict

from .runs import open_run


def _toml(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and math.isinf(value):
        return '"inf"'
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)  # a TOML basic string
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} to a study file (numbers, strings, booleans)")


def study_text(scene, axes=None, zip=None, name=None):
    """The study file (TOML) of a base scene and its axes, as `gfmd study run` reads it.

    Parameters
    ----------
    scene : Scene
        The base scene (written inline as [scene.<section>] tables).
    axes : dict, optional
        {"section.key": [values]}: the grid is the product of these lists (SI units).
    zip : dict, optional
        {"section.key": [values]}: keys that vary together (lists of equal length).
    name : str, optional
        The study's name (default: the scene's).

    Returns
    -------
    str
    """
    lines = [f"name = {_toml(name or scene.name)}"]
    for section, values in scene_to_dict(scene).items():
        lines.append(f"\n[scene.{section}]")
        lines += [f"{k} = {_toml(v)}" for k, v in values.items()]
    for table, entries in (("axes", axes), ("zip", zip)):
        if entries:
            lines.append(f"\n[{table}]")
            lines += [f"{json.dumps(k)} = {_toml(list(v))}" for k, v in entries.items()]
    return "\n".join(lines) + "\n"


def make_study(scene, axes=None, zip=None, name=None, *, yes=False):
    """A validated study: `scene` varied over `axes` (a product) and `zip` (together).

    Parameters
    ----------
    scene : Scene
        The base scene.
    axes, zip : dict, optional
        {"section.key": [values]} (see `study_text`); e.g.
        ``axes={"interface.phi_n_star": [0.01, 0.05, 0.15]}``.
    name : str, optional
        The study's name (default: the scene's).
    yes : bool
        Accept more than ``gfmd_contact.app.study_file.MAX_TASKS`` tasks (refused otherwise, naming the count).

    Returns
    -------
    gfmd_contact.app.study.Study
        ``.sets`` (the parameters of each set), ``.scenes``, ``.tasks``.

    Raises
    ------
    gfmd_contact.app.study.StudyError
        Naming the key and value of a bad axis (every set is checked as `run` checks a scene), or a
        scene with a user law (`user_law`): a study's tasks run from scene files, which cannot hold
        its functions; loop over `run` instead.
    """
    from gfmd_contact.app.study import StudyError, study_from_dict

    if getattr(scene, "user_law", None) is not None:
        raise StudyError("interface.law = \"user\": a study runs its tasks from scene files, which cannot hold the "
                         "user law's Python functions; run each scene with gfmd_contact.run(scene, law=...) instead")
    text = study_text(scene, axes, zip, name)
    return study_from_dict(tomllib.loads(text), text=text, name=name or scene.name, yes=yes)


def load_study(source, *, yes=False):
    """A validated study from a study TOML file.

    Parameters
    ----------
    source : str, pathlib.Path or gfmd_contact.app.study.Study
        A study file (``gfmd study run`` reads the same; base scene and [axes], optional
        [zip]), or a `make_study` result (returned as it is).
    yes : bool
        Accept more than ``gfmd_contact.app.study_file.MAX_TASKS`` tasks (refused otherwise, naming the count).

    Returns
    -------
    gfmd_contact.app.study.Study
    """
    from gfmd_contact.app.study import Study, load_study as read

    return source if isinstance(source, Study) else read(source, yes=yes)


class StudyResult:
    """A study directory read back.

    Attributes
    ----------
    dir : pathlib.Path
    record : dict
        study.json: task counts (tasks_total, tasks_reused, tasks_run, tasks_failed), every
        task (set, parameters, realization, seed, key, status), failures, "complete".
    """

    def __init__(self, directory):
        self.dir = Path(directory)
        path = self.dir / "study.json"
        if not path.is_file():
            raise FileNotFoundError(f"{self.dir}: no study.json; is this a `gfmd study run` directory?")
        self.record = json.loads(path.read_text())

    def __repr__(self):
        r = self.record
        return (f"StudyResult({str(self.dir)!r}: {r.get('tasks_total', '?')} task(s), "
                f"{r.get('tasks_failed', 0)} failed, {'complete' if r.get('complete') else 'unfinished'})")

    @functools.cached_property
    def summary(self):
        """summary.nc as an xarray.Dataset (loaded into memory).

        Dimensions: one per [axes] key (coordinates: its values), "zip" (coordinates: the
        zipped keys) if the study has a [zip], and "step". Variables: delta, U (m), set
        (parameter set index) and, for each of p (Pa), a_rel, g_r, g, the mean over the set's
        realizations, ``<name>_se`` (standard error) and ``<name>_n`` (count); units in attrs. A study of
        load paths adds branch ("loading"/"unloading"; "" where a set has no such step) and cycle (0, 1, …;
        −1 there) per step.
        """
        import xarray as xr

        with xr.open_dataset(self.dir / "summary.nc", engine="scipy") as ds:
            return ds.load()

    @functools.cached_property
    def table(self):
        """study.csv as a DataFrame: one row per (task, step); columns set, the varied keys,
        realization, seed, task, curve.csv's (step, U, delta (m), p (Pa), a_rel, g_r, g, …) and the set's
        stickiness_<key> columns (`gfmd_contact.core.stickiness`; NaN where not defined)."""
        import pandas as pd

        return pd.read_csv(self.dir / "study.csv")

    @functools.cached_property
    def summary_table(self):
        """summary.csv as a DataFrame: per set and step, the means, standard errors and counts, and the set's
        stickiness_<key> columns; with load paths also branch and cycle of each step (after step)."""
        import pandas as pd

        return pd.read_csv(self.dir / "summary.csv")

    @functools.cached_property
    def cycles(self):
        """cycles.csv as a DataFrame: one row per (task, cycle) of a study whose scenes have a load path.

        Columns: set, the varied keys, realization, seed, task, cycle, pull_off_pressure (Pa, the most tensile
        p̄ on unloading, < 0 tensile), pull_off_delta and snap_off_delta (m), hysteresis (J/m², W = ∮ p̄ dδ per
        unit area), closed (True/False), jump_in and jump_out (numbers of events); NaN where a cycle has no
        value (`gfmd_contact.app.cycles.write_study_cycles`). A ramp study has no cycles.csv: an empty DataFrame
        with the columns that do not depend on the axes.
        """
        import pandas as pd
        from gfmd_contact.app.cycles import STUDY_COLUMNS

        path = self.dir / "cycles.csv"
        if not path.is_file():
            return pd.DataFrame(columns=["set", "realization", "seed", "task", *STUDY_COLUMNS])
        return pd.read_csv(path)

    def task(self, set=0, realization=0):
        """The run directory of one task, as a `RunResult` (fields included).

        Parameters
        ----------
        set : int
            Parameter set index (the ``set`` column of `table`, the ``set`` variable of `summary`).
        realization : int
            Realization index within the set (seed surface.seed + realization).
        """
        for t in self.record.get("tasks", []):
            if t["set"] == set and t["realization"] == realization:
                return open_run(self.dir / "tasks" / t["key"])
        raise KeyError(f"no task with set {set} and realization {realization} in {self.dir}")

    def figures(self, over=None):
        """The seed-style figures of this study as {name: matplotlib Figure}.

        Parameters
        ----------
        over : str, optional
            A varied dotted key: one panel per combination of the other keys, one curve per value of it.
        """
        from .figures import study_figures

        return study_figures(self, over=over)


def run_study(study, out, *, workers=None, scheduler=None, progress=True, yes=False):
    """Run (or continue) every task of a study into a study directory.

    Parameters
    ----------
    study : str, pathlib.Path or gfmd_contact.app.study.Study
        A study TOML file, or a `make_study` result.
    out : str or pathlib.Path
        The study directory; rerunning into it reuses every finished task.
    workers : int, optional
        Worker processes of the local Dask cluster (default: all cores).
    scheduler : str, optional
        The address of an existing Dask scheduler (e.g. "tcp://host:8786") instead; `out`
        must then be on a file system every worker sees.
    progress : bool
        A progress bar over tasks.
    yes : bool
        Accept a study file of more than ``gfmd_contact.app.study_file.MAX_TASKS`` tasks (`load_study`).

    Returns
    -------
    StudyResult

    Raises
    ------
    gfmd_contact.app.io.RunDirError
        An `out` that cannot take the study (a file, a non-empty directory holding no study), naming `out`.

    Warns
    -----
    UserWarning
        If a task failed (the tracebacks are in ``result.record["failures"]``).
    """
    import warnings

    from gfmd_contact.app.study import failure_summary, run_study as execute

    from gfmd_contact.app.io import RunDirError

    study = load_study(study, yes=yes)
    try:
        record = execute(study, out, workers=workers, scheduler=scheduler, progress=progress,
                         command=f"gfmd_contact.run_study(out={out})")
    except RunDirError as exc:
        raise exc.in_python() from None
    if record["tasks_failed"]:
        warnings.warn(f"{record['tasks_failed']} task(s) failed: " + "; ".join(failure_summary(record)[:3]),
                      stacklevel=2)
    return StudyResult(out)


def open_study(directory):
    """Read a study directory (`gfmd study run --out DIR` or `run_study`); returns a `StudyResult`."""
    return StudyResult(directory)
