"""Studies (gfmd_contact.app.study, `gfmd study run`): grid/zip expansion, refusals naming the key, a tiny
study on a local Dask cluster killed part-way with a real SIGINT and resumed (reuse counts, the
same study.csv/summary.csv as an uninterrupted run but wall_s), a failing task that does not stop
the others, and the netCDF summary read back with xarray.

The tiny study: N = 512, 40 load steps, axis material.poisson_ratio × a zip of interface.law and
interface.phi_n_star (hard wall / cohesive), 2 realizations: 4 sets, 8 tasks, about 1 s each.
"""

import csv
import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from gfmd_contact.core import stickiness
from gfmd_contact.app import io
from gfmd_contact.cli import main
from gfmd_contact.app.study import load_study, stickiness_columns, study_from_dict

BASE = """
[surface]
kind = "self-affine"
length = 320e-9
nodes = 512
hurst = 0.8
h_rms = 10e-9
rolloff_wavelength = 160e-9
rollon_wavelength = 10e-9
seed = 1
realizations = 2

[interface]
law = "cohesive"
phi_n_star = 0.15
length_normal = 2.5e-9

[loading]
initial_separation = 20e-9
final_penetration = 8e-9
steps = 40

[output]
field_steps = 2
"""

STUDY = """
base = "base.toml"
[axes]
"material.poisson_ratio" = [0.3, 0.45]
[zip]
"interface.law" = ["hard-wall", "cohesive"]
"interface.phi_n_star" = [0.15, 0.01]
"""


def write_study(folder, study=STUDY, base=BASE):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "base.toml").write_text(base)
    (folder / "study.toml").write_text(study)
    return folder / "study.toml"


def rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def without_wall(table):
    return [{k: v for k, v in r.items() if k != "wall_s"} for r in table]


def saved_step(task_dir):
    """The last saved load step of an unfinished task directory (-1: none)."""
    try:
        with np.load(task_dir / "partial" / "realization0.state.npz") as z:
            return -1 if bool(z["done"]) else int(z["step"])
    except (OSError, ValueError, KeyError, EOFError):  # absent, or being replaced right now
        return -1


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The tiny study run uninterrupted in-process (2 workers): (study file, out)."""
    folder = tmp_path_factory.mktemp("ref")
    path = write_study(folder)
    out = folder / "out"
    assert main(["study", "run", str(path), "--out", str(out), "--workers", "2", "--quiet"]) == 0
    return path, out


def test_grid_and_zip_expansion(tmp_path):
    """Product of the axes in file order, the zip index innermost; tasks = sets × realizations, seeds seed + r."""
    path = write_study(tmp_path, STUDY.replace("[0.3, 0.45]", "[0.3, 0.4, 0.45]"))
    study = load_study(path)
    assert study.keys == ["material.poisson_ratio", "interface.law", "interface.phi_n_star"]
    assert study.sets == [{"material.poisson_ratio": nu, "interface.law": law, "interface.phi_n_star": phi}
                          for nu in (0.3, 0.4, 0.45) for law, phi in (("hard-wall", 0.15), ("cohesive", 0.01))]
    assert [s.interface.law for s in study.scenes] == ["hard-wall", "cohesive"] * 3
    assert [s.material.poisson_ratio for s in study.scenes] == [0.3, 0.3, 0.4, 0.4, 0.45, 0.45]
    tasks = study.tasks
    assert len(tasks) == 12 and len({t.key for t in tasks}) == 12
    assert [(t.set, t.realization, t.seed) for t in tasks[:2]] == [(0, 0, 1), (0, 1, 2)]
    assert tasks[1].scene.surface.seed == 2 and tasks[1].scene.surface.realizations == 1
    # two axes, no zip; inline [scene]
    two = study_from_dict({"scene": {"surface": {"nodes": 512, "length": 320e-9, "rolloff_wavelength": 160e-9,
                                                 "rollon_wavelength": 10e-9, "realizations": 3}},
                           "axes": {"interface.phi_n_star": [0.01, 0.05, 0.15], "surface.hurst": [0.3, 0.8]}})
    assert [(p["interface.phi_n_star"], p["surface.hurst"]) for p in two.sets] == \
        [(phi, hurst) for phi in (0.01, 0.05, 0.15) for hurst in (0.3, 0.8)]
    assert len(two.tasks) == 18
    # the key is the task scene's content: the same set in another study has the same key
    again = study_from_dict({"scene": {"surface": {"nodes": 512, "length": 320e-9, "rolloff_wavelength": 160e-9,
                                                   "rollon_wavelength": 10e-9, "realizations": 3}},
                             "axes": {"surface.hurst": [0.8]}, "zip": {"interface.phi_n_star": [0.05]}})
    assert {t.key for t in again.tasks} < {t.key for t in two.tasks}
    # zipped keys may repeat a value; the entries (tuples) differ
    hard = study_from_dict({"scene": {"surface": {"nodes": 512, "length": 320e-9, "rolloff_wavelength": 160e-9,
                                                  "rollon_wavelength": 10e-9}},
                            "zip": {"interface.law": ["hard-wall", "cohesive", "cohesive"],
                                    "interface.phi_n_star": [0.15, 0.001, 0.15]}})
    assert [(s.interface.law, s.interface.phi_n_star) for s in hard.scenes] == \
        [("hard-wall", 0.15), ("cohesive", 0.001), ("cohesive", 0.15)]


@pytest.mark.parametrize("axes, named", [
    ('[axes]\n"interface.bogus" = [1.0]', "bogus"),
    ('[axes]\n"interface.phi_n_star" = [0.01, -1.0]', "interface.phi_n_star"),
    ('[axes]\n"surface.nodes" = [512, 4]', "surface.nodes"),
    ('[axes]\nnodes = [512]', "'nodes'"),
    ('[axes]\n"material.poisson_ratio" = []', "material.poisson_ratio"),
    ('[zip]\n"interface.law" = ["hard-wall", "cohesive"]\n"interface.phi_n_star" = [0.15]', "interface.phi_n_star"),
    ('[axes]\n"interface.law" = ["cohesive"]\n[zip]\n"interface.law" = ["hard-wall"]', "interface.law"),
    ('[axes]\n"surface.rollon_wavelength" = [1e-9, 200e-9]', "surface.rollon_wavelength"),
    ('[axes]\n"surface.hurst" = [0.3, 0.3]', "surface.hurst"),
    ('[zip]\n"interface.law" = ["cohesive", "cohesive"]\n"interface.phi_n_star" = [0.1, 0.1]', "interface.law"),
])
def test_bad_axes_are_refused_naming_the_key(tmp_path, capsys, axes, named):
    path = write_study(tmp_path, 'base = "base.toml"\n' + axes)
    out = tmp_path / "out"
    assert main(["study", "run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert named in err and err.startswith("gfmd: error:") and "Traceback" not in err
    assert not out.exists()  # refused before anything is written or computed


def test_a_set_refused_as_a_whole_names_its_parameters(tmp_path, capsys):
    """Each value passes alone; the combination breaks the wavelength order: the set's keys are named."""
    path = write_study(tmp_path, 'base = "base.toml"\n[zip]\n"surface.rolloff_wavelength" = [160e-9, 20e-9]\n'
                                 '"surface.rollon_wavelength" = [10e-9, 40e-9]')
    assert main(["study", "run", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "parameter set 1" in err and "surface.rolloff_wavelength = 2e-08" in err


def test_killed_study_resumes_to_the_uninterrupted_result(tmp_path):
    """A real SIGINT to `python -m gfmd study run --workers 2` once one task is complete and another has
    saved steps: exit 130, one line; the rerun reuses exactly the complete tasks and continues the saved
    steps; study.csv and summary.csv equal the uninterrupted run's (every column but wall_s)."""
    # tasks long enough to be caught mid-ramp (N = 2048, 400 steps: ≈ 1–2 s each); its own reference
    slow = BASE.replace("nodes = 512", "nodes = 2048").replace("steps = 40", "steps = 400")
    ref_dir = tmp_path / "ref"
    ref_dir.mkdir()
    ref_path = write_study(ref_dir, base=slow)
    ref = ref_dir / "out"
    assert main(["study", "run", str(ref_path), "--out", str(ref), "--workers", "2", "--quiet"]) == 0
    path = write_study(tmp_path, base=slow)
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "gfmd", "study", "run", str(path), "--out", str(out), "--workers", "2", "--quiet"]
    # a checkpoint every step ($GFMD_CHECKPOINT_SECONDS = 0), so that a mid-ramp task is seen on disk
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, env=dict(os.environ, GFMD_CHECKPOINT_SECONDS="0"))
    deadline = time.monotonic() + 600  # a guard against a hang, not a timing: a loaded machine is slow to get there
    tasks = out / "tasks"
    while time.monotonic() < deadline:
        assert proc.poll() is None, "the study ended before it could be interrupted"
        dirs = list(tasks.iterdir()) if tasks.is_dir() else []
        complete = [d for d in dirs if io.run_complete(d)]
        if complete and any(5 <= saved_step(d) <= 30 for d in dirs):  # one task done, one mid-ramp
            break
        time.sleep(0.01)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130, err
    assert time.monotonic() - sent < 10, "the workers were not stopped at once"
    assert "Traceback" not in err
    last = err.strip().splitlines()[-1]
    assert last.startswith("gfmd: interrupted:") and "continue with: gfmd study run" in last
    study = load_study(path)
    complete = {t.key for t in study.tasks if io.run_complete(out / "tasks" / t.key)}
    saved = {}
    for t in study.tasks:
        if t.key not in complete and (out / "tasks" / t.key / "scene.toml").is_file():
            part = io.load_part(out / "tasks" / t.key, t.scene, 0)
            if part is not None:
                saved[t.key] = len(part[0].curve["step"])
    assert 1 <= len(complete) < 8 and sum(saved.values()) >= 1
    print(f"killed with {len(complete)} task(s) complete, saved steps of the others: {sorted(saved.values())}")
    resumed = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert resumed.returncode == 0, resumed.stderr
    record = json.loads((out / "study.json").read_text())
    assert record["complete"] is True
    assert record["tasks_total"] == 8 and record["tasks_failed"] == 0
    assert record["tasks_reused"] == len(complete) and record["tasks_run"] == 8 - len(complete)
    assert record["steps_reused"] == sum(saved.values())
    by_key = {t["key"]: t for t in record["tasks"]}
    assert all(by_key[k]["status"] == "reused" for k in complete)
    assert all(by_key[k]["steps_reused"] == n for k, n in saved.items())
    for t in record["tasks"]:  # the version of the run that computed the task (the tree may move meanwhile)
        meta = json.loads((out / "tasks" / t["key"] / "meta.json").read_text())
        assert t["code_version"] == meta["code_version"] and t["code_version"].startswith("0.")
    assert record["study_text"] == path.read_text()
    for name in ("study.csv", "summary.csv"):
        a, b = rows(ref / name), rows(out / name)
        assert len(a) == len(b) > 0
        assert without_wall(a) == without_wall(b), name
    # a third run reuses everything and writes the same tables
    before = (out / "study.csv").read_text()
    assert main(["study", "run", str(path), "--out", str(out), "--workers", "2", "--quiet"]) == 0
    record = json.loads((out / "study.json").read_text())
    assert (record["tasks_reused"], record["tasks_run"], record["steps_reused"]) == (8, 0, 0)
    assert (out / "study.csv").read_text() == before


def test_study_tables(reference):
    """study.csv: one row per (task, step) with the axis columns; summary.csv: the means over realizations."""
    path, out = reference
    table = rows(out / "study.csv")
    assert list(table[0]) == ["set", "material.poisson_ratio", "interface.law", "interface.phi_n_star",
                              "realization", "seed", "task", "step", "U", "delta", "p", "a_rel", "g_r", "g",
                              "iterations", "residual", "converged", "wall_s", "algorithm"] + stickiness_columns()
    # GFMD's per-step label, as each task's curve.csv holds it
    for r in table[::41]:
        with open(out / "tasks" / r["task"] / "curve.csv") as fh:
            assert r["algorithm"] == next(csv.DictReader(fh))["algorithm"] != ""
    assert len(table) == 8 * 41
    assert {(r["set"], r["material.poisson_ratio"], r["interface.law"]) for r in table} == \
        {("0", "0.3", "hard-wall"), ("1", "0.3", "cohesive"), ("2", "0.45", "hard-wall"), ("3", "0.45", "cohesive")}
    assert {(r["realization"], r["seed"]) for r in table} == {("0", "1"), ("1", "2")}
    summary = rows(out / "summary.csv")
    assert len(summary) == 4 * 41
    row = next(r for r in summary if r["set"] == "3" and r["step"] == "40")
    p = [float(r["p"]) for r in table if r["set"] == "3" and r["step"] == "40"]
    assert float(row["p"]) == pytest.approx(np.mean(p), rel=1e-12)
    assert float(row["p_se"]) == pytest.approx(np.std(p, ddof=1) / math.sqrt(2), rel=1e-12)
    assert row["p_n"] == "2"
    hard = next(r for r in summary if r["set"] == "2" and r["step"] == "40")
    assert float(hard["p"]) != float(row["p"])  # the sets really differ
    # the per-set stickiness columns: the set scene's diagnostics before any run, "nan" where not defined
    study = load_study(path)
    for r in table[::41] + summary[::41]:
        expected = stickiness.as_dict(study.scenes[int(r["set"])])
        for key, value in expected.items():
            cell = r[f"stickiness_{key}"]
            assert (cell == "nan") if value["value"] is None else float(cell) == value["value"], (r["set"], key)
    assert {r["stickiness_tabor_rough"] == "nan" for r in summary} == {True, False}  # hard wall n/a, cohesive not


def test_netcdf_round_trip_equals_summary_csv(reference):
    xr = pytest.importorskip("xarray")
    path, out = reference
    with xr.open_dataset(out / "summary.nc", engine="scipy") as ds:
        ds = ds.load()
    assert ds["p"].dims == ("material.poisson_ratio", "zip", "step")
    assert list(ds["interface.law"].values) == ["hard-wall", "cohesive"]
    assert ds["p"].attrs["units"] == "Pa"
    summary = rows(out / "summary.csv")
    for r in summary:
        cell = ds.sel({"material.poisson_ratio": float(r["material.poisson_ratio"]), "step": int(r["step"])})
        cell = cell.isel(zip=list(ds["interface.law"].values).index(r["interface.law"]))
        assert int(cell["set"]) == int(r["set"])
        assert float(cell["interface.phi_n_star"]) == float(r["interface.phi_n_star"])
        for c in ("delta", "U", "p", "p_se", "p_n", "a_rel", "a_rel_se", "a_rel_n", "g_r", "g_r_se", "g_r_n",
                  "g", "g_se", "g_n"):
            value, expected = float(cell[c]), float(r[c])
            assert value == expected or (math.isnan(value) and math.isnan(expected)), (r, c)
    assert len(summary) == ds["p"].size


def test_a_failing_task_does_not_stop_the_others(reference, tmp_path, capsys):
    """A task whose directory cannot be written fails; the other 7 finish, exit 1, the failure is named."""
    path = write_study(tmp_path)
    out = tmp_path / "out"
    victim = load_study(path).tasks[3]
    (out / "tasks").mkdir(parents=True)
    (out / "tasks" / victim.key).write_text("in the way")
    assert main(["study", "run", str(path), "--out", str(out), "--workers", "2", "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "1 task(s) failed" in err and victim.key in err and "set 1" in err
    record = json.loads((out / "study.json").read_text())
    assert (record["tasks_failed"], record["tasks_run"]) == (1, 7)
    assert record["failures"][0]["key"] == victim.key and "Traceback" in record["failures"][0]["traceback"]
    summary = rows(out / "summary.csv")
    assert {r["p_n"] for r in summary if r["set"] == "1"} == {"1"}
    assert {r["p_n"] for r in summary if r["set"] != "1"} == {"2"}
    # the others equal the uninterrupted run's rows
    ref_rows = [r for r in without_wall(rows(reference[1] / "study.csv")) if r["task"] != victim.key]
    assert without_wall(rows(out / "study.csv")) == ref_rows


def test_task_address_ignores_keys_at_their_default_and_a_changed_default_is_caught(reference, tmp_path):
    """A key at its default does not enter the address (a version adding a key keeps every task);
    a finished task whose stored scene differs from the current one is refused by name, not reused."""
    from gfmd_contact.core.scene import Scene
    from gfmd_contact.app.study import StudyError, run_task, task_key, task_key_text

    study = load_study(write_study(tmp_path))
    task = study.tasks[0]
    assert task_key(task.scene) == task.key
    text = task_key_text(task.scene)
    assert "interface.contact_tolerance" not in text and "surface.seed" not in text  # both at their defaults
    assert "surface.seed = 2" in task_key_text(study.tasks[1].scene)
    default = Scene().interface.contact_tolerance
    explicit = task.scene.replace(**{"interface.contact_tolerance": default})
    assert task_key(explicit) == task.key
    changed = task.scene.replace(**{"interface.contact_tolerance": 2 * default})
    assert task_key(changed) != task.key

    _, out = reference
    finished = out / "tasks" / task.key
    assert io.run_complete(finished)
    assert run_task(task.scene, finished)["status"] == "reused"
    with pytest.raises(StudyError, match=r"interface\.contact_tolerance: 0\.001 there, 0\.002 now"):
        run_task(changed, finished)


def test_tasks_under_an_older_address_are_moved_and_reused(reference, tmp_path):
    """A study directory written when addresses hashed the whole scene TOML is re-addressed, not recomputed."""
    import hashlib
    import shutil

    from gfmd_contact.core.scene import scene_to_toml
    from gfmd_contact.app.study import readdress_tasks

    path, out = reference
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    study = load_study(path)
    unique = {t.key: t for t in study.tasks}
    for key, task in unique.items():  # the old scheme: sha256 of the whole resolved TOML
        old = hashlib.sha256(scene_to_toml(task.scene).encode()).hexdigest()[:16]
        assert old != key
        (copy / "tasks" / key).rename(copy / "tasks" / old)
    (copy / "tasks" / "not-a-task").mkdir()
    assert readdress_tasks(copy, unique) == len(unique)
    assert sorted(p.name for p in (copy / "tasks").iterdir()) == sorted([*unique, "not-a-task"])
    assert main(["study", "run", str(path), "--out", str(copy), "--quiet"]) == 0
    record = json.loads((copy / "study.json").read_text())
    assert record["tasks_reused"] == len(unique) and record["tasks_run"] == 0


def test_local_cluster_workers_run_without_dasks_diagnostics():
    """Our local cluster's workers get `LOCAL_CLUSTER_CONFIG` (no statistical profiler sampling the solver's stack
    every 10 ms, slower ticks and monitors), and the settings do not leak into the calling process."""
    import dask

    from gfmd_contact.app.study import LOCAL_CLUSTER_CONFIG, _client
    client, cluster = _client(1, None)
    try:
        seen = client.run(lambda keys: {k: dask.config.get(k) for k in keys}, list(LOCAL_CLUSTER_CONFIG))
        assert list(seen.values()) == [LOCAL_CLUSTER_CONFIG]
        profiled = client.run(lambda dask_worker: dask_worker.periodic_callbacks.get("profile"))
        assert list(profiled.values()) == [None]
    finally:
        client.close()
        cluster.close()
    assert dask.config.get("distributed.worker.profile.enabled") is True
