"""Runs from Python: run a scene into a run directory, read one back as pandas and numpy.

Units: SI throughout (m, Pa; `gfmd_contact.core.conventions`). A run is what `gfmd run` does:
every realization in a process pool, every load step written to the run directory
as it is computed (so an interrupted run continues with ``resume=True``), then
curve.csv, mean_curve.csv, fields.npz, scene.toml and meta.json (`gfmd_contact.app.io`).
"""

from __future__ import annotations

import dataclasses
import functools
import json
import shutil
import tempfile
import time
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from gfmd_contact.core.result import CURVE_COLUMNS, FIELD_NAMES
from gfmd_contact.core.errors import SceneError
from gfmd_contact.core.scene import Scene, load_scene as read_scene

from .scenes import change, check, load_scene, method_changes


class RunResult:
    """A run directory read back: curves as pandas DataFrames, fields as numpy arrays.

    Attributes are read from disk when first used. An unfinished run (interrupted, or
    still running) is read from the load steps saved so far (``complete`` is False).

    Attributes
    ----------
    dir : pathlib.Path
        The run directory.
    scene : gfmd_contact.core.scene.Scene
        The resolved scene of the run (its scene.toml).
    meta : dict
        meta.json: "complete", "method" (what ran), "model", "messages" (non-converged
        steps), "notes", "timings" (s; with the preflight's "estimated_peak_memory_bytes" and
        "estimated_s", `gfmd_contact.core.cost`), "code_version", ...
    """

    def __init__(self, directory):
        self.dir = Path(directory)
        self._curves = None  # {realization: {column: array}} of an unfinished run
        if (self.dir / "curve.csv").is_file():  # finished: nothing else is read until asked for
            self.meta = json.loads((self.dir / "meta.json").read_text())
            scene = read_scene(self.dir / "scene.toml")
            self.scene = dataclasses.replace(scene, name=self.meta.get("scene_name", scene.name))
        else:
            from gfmd_contact.app.io import read_run

            self.scene, self._curves, _, self.meta = read_run(self.dir)

    def __repr__(self):
        state = "complete" if self.complete else "unfinished"
        count = len(self._curves) if self._curves is not None else len(self.meta.get("realizations", []))
        return (f"RunResult({str(self.dir)!r}: scene {self.scene.name!r}, {count} realization(s), "
                f"{self.meta.get('method', '?')}, {state})")

    @property
    def complete(self):
        """True once every realization finished and the final files are written."""
        return self.meta.get("complete") is True

    @property
    def converged(self):
        """True if every load step of every realization converged."""
        return bool(self.curve["converged"].all())

    @functools.cached_property
    def curve(self):
        """curve.csv as a DataFrame: one row per (realization, step).

        Columns: realization, seed, step, U (m, imposed displacement), delta (m, penetration
        δ), p (Pa, mean pressure, > 0 compressive), a_rel (relative contact area), g_r and g
        (rms gradients of the contact nodes and of the whole profile; g_r NaN without
        contact), iterations, residual (relative), converged (0/1), wall_s (s) and, for GFMD, algorithm (what relaxed the step);
        a run with a load path adds branch ("loading"/"unloading"), cycle (0, 1, …), event ("jump-in"/"jump-out"
        or empty) and, under force control, load (Pa, the prescribed p̄).
        """
        import pandas as pd

        path = self.dir / "curve.csv"
        if path.is_file():
            return pd.read_csv(path)
        frames = [pd.DataFrame({"realization": r, **c}) for r, c in sorted(self._curves.items())]
        table = pd.concat(frames, ignore_index=True)
        for col in ("realization", "seed", "step", "iterations", "converged"):
            if col in table:
                table[col] = table[col].astype(int)
        return table[["realization", "seed"] + list(CURVE_COLUMNS) + [c for c in ("algorithm",) if c in table]]

    @functools.cached_property
    def mean_curve(self):
        """mean_curve.csv as a DataFrame: one row per load step.

        Columns: step, delta (m), U (m) and, for each of p (Pa), a_rel, g_r, g, the mean over
        the realizations, ``<name>_se`` (its standard error, 0 for one value) and ``<name>_n``
        (how many realizations have a value at that step). Under force control delta and U are means over
        the realizations too (they share the loads, not δ) and load (Pa) is added; with a load path, branch
        and cycle.
        """
        import pandas as pd

        path = self.dir / "mean_curve.csv"
        if path.is_file():
            return pd.read_csv(path)
        from gfmd_contact.app.averages import ensemble_average

        runs = [SimpleNamespace(realization=r, curve=c) for r, c in sorted(self._curves.items())]
        from gfmd_contact.app.cycles import step_loads

        return pd.DataFrame(ensemble_average(runs, step_loads(self.scene)))

    @functools.cached_property
    def cycles(self):
        """meta.json "cycles" as a DataFrame: one row per (realization, cycle) of a run whose loading has a path.

        Columns: realization, seed, cycle, pull_off_pressure (Pa, the most tensile p̄ on unloading, < 0
        tensile), pull_off_delta (m, its δ), snap_off_delta (m), snap_off_step and snap_off_rule (which
        definition gave it: jump-out, contact lost, load released), hysteresis (J/m², W = ∮ p̄ dδ
        per unit area, > 0 dissipated), closed (the cycle ends at the δ it began), delta_start, delta_end (m),
        jump_in, jump_out (numbers of events), under force control pull_off_load (Pa, the load at which
        contact was lost; NaN where none), and events (the list of the cycle's jump events: kind, step,
        branch, δ (m), p̄ (Pa), a_rel before and after). Definitions: meta["cycle_definitions"]
        (`gfmd_contact.core.cycle`). Empty (these columns, no rows) for a ramp, and for an unfinished run.
        """
        import pandas as pd

        rows = []
        for entry in self.meta.get("cycles") or []:
            for c in entry["cycles"]:
                kinds = [e["kind"] for e in c.get("events", [])]
                rows.append({"realization": entry["realization"], "seed": entry["seed"], **c,
                             "jump_in": kinds.count("jump-in"), "jump_out": kinds.count("jump-out")})
        columns = ["realization", "seed", "cycle", "pull_off_pressure", "pull_off_delta", "snap_off_delta",
                   "snap_off_step", "hysteresis", "closed", "delta_start", "delta_end", "jump_in", "jump_out"]
        table = pd.DataFrame(rows)
        columns += [c for c in table.columns if c not in columns and c != "events"] + ["events"]
        return table.reindex(columns=columns)

    @functools.cached_property
    def _npz(self):
        path = self.dir / "fields.npz"
        if path.is_file():
            return np.load(path)
        from gfmd_contact.app.io import read_run

        return read_run(self.dir)[2]

    def saved_steps(self, realization=0):
        """The load steps (indices into `curve`'s step column) whose fields were saved for `realization`."""
        prefix = f"r{realization}_s"
        return sorted({int(k[len(prefix):].split("_")[0]) for k in self._npz if k.startswith(prefix)})

    def fields(self, realization=0, step=None):
        """The surface fields of one realization at one saved load step.

        Parameters
        ----------
        realization : int
            Realization index (the ``realization`` column of `curve`).
        step : int, optional
            A saved load step (see `saved_steps`; output.field_steps chooses them);
            default: the last saved one.

        Returns
        -------
        dict of numpy.ndarray
            x (m, node positions), h (m, indenter profile), u_z and u_x (m, surface
            displacements), gap (m, normal gap Δn), t_n and t_t (Pa, interface tractions
            t_z and t_x), each of length surface.nodes; and step, delta (m) of that step.
            A 2+1-D surface adds y (m, positions along y); h and the fields are then (Nx, Ny) arrays.
        """
        steps = self.saved_steps(realization)
        if not steps:
            have = sorted({int(k[1:].split("_")[0]) for k in self._npz if k.startswith("r") and "_s" in k})
            raise KeyError(f"realization {realization}: no saved fields in {self.dir} (realizations with "
                           f"fields: {have or 'none'}; output.field_steps chooses how many steps are saved)")
        step = steps[-1] if step is None else int(step)
        if step not in steps:
            raise KeyError(f"step {step}: no saved fields for realization {realization}; saved steps: {steps}")
        out = {"x": np.asarray(self._npz["x"]), "h": np.asarray(self._npz[f"h_r{realization}"])}
        if "y" in self._npz:  # a 2+1-D surface
            out["y"] = np.asarray(self._npz["y"])
        out.update({name: np.asarray(self._npz[f"r{realization}_s{step}_{name}"]) for name in FIELD_NAMES})
        row = self.curve[(self.curve["realization"] == realization) & (self.curve["step"] == step)]
        out.update(step=step, delta=float(row["delta"].iloc[0]))
        return out

    def save(self, directory):
        """Copy this run into `directory` (new or empty) and return it read from there: how a run made without
        `out`, whose temporary directory goes with this object, is kept."""
        from gfmd_contact.app.safe_files import LOCK_NAME

        target = Path(directory)
        if target.exists() and (not target.is_dir() or any(target.iterdir())):
            raise FileExistsError(f"{target} exists and is not an empty directory: choose another directory")
        shutil.copytree(self.dir, target, dirs_exist_ok=True, ignore=shutil.ignore_patterns(LOCK_NAME))
        return open_run(target)

    def figures(self, delta=None, realization=None):
        """The seed-style figures of this run as {name: matplotlib Figure}.

        Parameters
        ----------
        delta : float, optional
            Penetration δ (m) of the interface snapshot (nearest saved step; default the last).
        realization : int, optional
            Realization of the snapshot (default: the first with saved fields).
        """
        from .figures import run_figures

        return run_figures(self, delta=delta, realization=realization)


def open_run(directory):
    """Read a run directory (`gfmd run --out DIR`, `run(..., out=DIR)`, a study's task).

    Parameters
    ----------
    directory : str or pathlib.Path

    Returns
    -------
    RunResult

    Raises
    ------
    FileNotFoundError
        If the directory holds no run (no scene.toml / meta.json) or no finished load step yet.
    """
    directory = Path(directory)
    for name in ("scene.toml", "meta.json"):
        if not (directory / name).is_file():
            raise FileNotFoundError(f"{directory}: missing {name}; is this a `gfmd run` output directory?")
    return RunResult(directory)


def compute(scene, out, workers=None, progress=True, note=None):
    """Run every realization into the prepared run directory `out` and write its final files.

    The one path of `run` and `gfmd run` (after the checks and `gfmd_contact.app.io.prepare_run_dir`).

    Parameters
    ----------
    scene : Scene
    out : pathlib.Path
        The prepared run directory; realizations already done there are reused.
    workers : int, optional
        Worker processes (None: the scene's output.workers; 0: all cores).
    progress : bool
        A tqdm progress bar over load steps.
    note : callable, optional
        Called with one line per repair of damaged partial files (`gfmd_contact.app.io.load_part`).

    Returns
    -------
    (list of gfmd_contact.core.result.Result, dict, float)
        The results, the reuse counts {"realizations_reused", "steps_reused"} and the wall time (s).
    """
    from gfmd_contact.app import io
    from gfmd_contact.app.ensemble import run_to_directory
    from gfmd_contact.core.cost import estimate_peak_memory, estimate_seconds

    seconds = estimate_seconds(scene, workers)  # before any compute (its FFT pair timed on an idle process)
    start = time.perf_counter()
    results, resume = run_to_directory(scene, out, workers=workers, progress=progress, note=note)
    elapsed = time.perf_counter() - start
    io.write_run(out, scene, results, resume=resume, timings={
        "total_s": elapsed, "workers": workers,
        "estimated_peak_memory_bytes": estimate_peak_memory(scene, workers),
        "estimated_s": seconds})  # gfmd_contact.core.cost
    return results, resume, elapsed


def with_law(scene, law):
    """The scene with a user-defined interface law (interface.law = "user"; `user_law` builds `law`).

    The law's Python callables travel with the Scene object, not in its TOML: scene.toml records
    interface.law = "user" only, and meta.json the law's name, numbers and that the run cannot be
    reproduced from scene.toml alone.

    Parameters
    ----------
    scene : Scene, str, pathlib.Path or dict
        The scene, or anything `load_scene` reads. interface.tangential_ratio must be 0 (a user law
        is normal-only).
    law : gfmd_contact.core.user_law.UserLaw
        From `user_law`.

    Returns
    -------
    Scene
    """
    from gfmd_contact.core.user_law import UserLaw

    if not isinstance(law, UserLaw):
        raise SceneError(f"law = {law!r}: expected a user law from gfmd_contact.user_law(energy=..., traction=..., "
                         "tangent=..., length=...)")
    scene = load_scene(scene) if not isinstance(scene, Scene) else scene
    return dataclasses.replace(change(scene, {"interface.law": "user"}), user_law=law)


def run(scene, out=None, *, method=None, realizations=None, workers=1, progress=True, resume=False,
        overwrite=False, wait=0, law=None, plot=False):
    """Run a scene (every realization) into a run directory and return its result.

    Parameters
    ----------
    scene : Scene, str, pathlib.Path or dict
        The scene, or anything `load_scene` reads (a TOML file, TOML text, a dict).
    out : str or pathlib.Path, optional
        The run directory (created; a non-empty one is refused unless resume or overwrite).
        Default: none of yours: the run goes to a temporary directory that lives as long as the returned
        result (``result.dir``) and is removed with it, or when Python exits; ``result.save(DIR)`` keeps it.
    method : {"gfmd", "fe", "fire", "verlet"}, optional
        "fe": the finite-element reference (finite layer only); "fire"/"verlet": GFMD
        with solver.method "fire" (the law's production chain: NCG, CG, Newton or FIRE, `gfmd.chains`) or
        "verlet" (damped Verlet throughout); default: the scene's [method] and [solver] keys.
    realizations : int, optional
        Number of random realizations (surface.realizations; seeds surface.seed + i).
    workers : int, optional
        Worker processes (one realization each): 1 runs in this process, 0 uses all cores,
        None the scene's output.workers.
    progress : bool
        A tqdm progress bar over load steps.
    resume : bool
        Continue an interrupted run in `out` (finished realizations are reused).
    overwrite : bool
        Replace an earlier run in `out` (only the files a run writes are removed).
    wait : float
        Seconds to wait for another process that writes `out` (0: refuse at once, None: for ever).
    law : gfmd_contact.core.user_law.UserLaw, optional
        A user-defined interface law (`user_law`; sets interface.law = "user", `with_law`), solved by
        GFMD and the FE. With workers other than 1 its callables must be picklable (module-level functions).
    plot : bool
        Also write the run's figures into ``out/plots/`` (what `gfmd run` draws; `plot_run`).

    Returns
    -------
    RunResult

    Raises
    ------
    SceneError
        A key out of range or a scene the method cannot solve, before any work.
    gfmd_contact.app.io.RunDirError
        An `out` that cannot take the run (the message says why, naming resume=True, overwrite=True).
    ValueError
        resume=True without `out`.

    Warns
    -----
    UserWarning
        The scene's resolution/stability warnings, and non-converged load steps
        (listed in ``result.meta["messages"]``).
    """
    from gfmd_contact.app import io, safe_files

    scene = load_scene(scene) if not isinstance(scene, Scene) else scene
    if law is not None:
        scene = with_law(scene, law)
    if scene.user_law is not None and workers != 1:
        import pickle

        try:
            pickle.dumps(scene.user_law)
        except Exception as exc:  # noqa: BLE001 - lambdas, closures: say why and what to do
            raise SceneError(f"workers = {workers!r} with a user law whose callables cannot be sent to worker processes "
                             f"({type(exc).__name__}: {exc}): define them as module-level functions, or use workers=1"
                             ) from None
    keys = method_changes(method)
    if realizations is not None:
        keys["surface.realizations"] = realizations
    if keys:
        scene = change(scene, keys)
    found, _notes = check(scene)  # refusals happen here, before any file is touched
    from gfmd_contact.core.cost import check_memory

    check_memory(scene, workers)  # the worker processes this run starts
    if out is None and resume:
        raise ValueError("resume=True needs out: the run directory to continue")
    temporary = tempfile.TemporaryDirectory(prefix=f"gfmd-{scene.name}-") if out is None else None
    out = Path(temporary.name if temporary else out)
    with safe_files.locked(out, wait=wait, what="run directory", command=f"gfmd_contact.run(out={str(out)!r})",
                           advice="wait for it to end (wait=seconds), or choose another out",
                           note=lambda line: warnings.warn(line, stacklevel=4)):
        try:
            out = io.prepare_run_dir(out, scene, resume=resume, overwrite=overwrite,
                                     command=f"gfmd_contact.run(out={out})")
        except io.RunDirError as exc:
            raise exc.in_python() from None
        if resume and io.run_complete(out):
            return _finished(out, temporary, plot)
        for w in found:
            warnings.warn(w, stacklevel=2)
        results, _, _ = compute(scene, out, workers=workers, progress=progress,
                                note=lambda line: warnings.warn(line, stacklevel=4))
    bad = [m for r in results for m in r.messages]
    if bad:
        warnings.warn(f"{len(bad)} non-converged load step(s): {'; '.join(bad[:3])}", stacklevel=2)
    return _finished(out, temporary, plot)


def _finished(out, temporary, plot):
    """The run's result (its figures written first if `plot`); a temporary directory goes with it."""
    if plot:
        from gfmd_contact.app.plots import plot_run as write_plots

        write_plots(out)
    result = open_run(out)
    result._temporary = temporary  # removed with the result (tempfile's finalizer), or when Python exits
    return result
