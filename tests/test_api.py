"""The Python API (gfmd_contact) gives what the command line gives, read as pandas, numpy and xarray.

One small scene (the 320 nm, N = 256 cell of tests/test_run_dir.py: no check warning,
3 realizations, run with realizations=2 and --realizations 2; 6 steps). Every comparison is exact: the API and `gfmd run` share one
path (`gfmd_contact.runs.compute`), the solver is deterministic, and the DataFrames
are the CSV files read back (wall_s aside, which is a timing).
"""

import json
import re
import warnings

import numpy as np
import pandas as pd
import pytest

import gfmd_contact as gc
from gfmd_contact.app import io
from gfmd_contact.app.averages import AVERAGED
from gfmd_contact.cli import main

SMALL = {"surface.length": 320e-9, "surface.nodes": 256, "surface.rolloff_wavelength": 160e-9,
         "surface.rollon_wavelength": 10e-9, "surface.realizations": 3, "loading.steps": 6,
         "loading.final_penetration": 8e-9, "output.field_steps": 2, "output.workers": 1,
         "interface.length_normal": 2.5e-9, "loading.initial_separation": 20e-9}


@pytest.fixture(scope="module")
def scene():
    return gc.change(gc.default_scene(), SMALL, name="api")


@pytest.fixture(scope="module")
def result(scene, tmp_path_factory):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # this scene passes every check: no warning may be issued
        return gc.run(scene, out=tmp_path_factory.mktemp("api") / "run", realizations=2, progress=False)


# ---------------------------------------------------------------- scenes

def test_load_scene_reads_a_file_text_a_dict_and_a_scene_alike(scene, tmp_path):
    path = gc.save_scene(scene, tmp_path / "api.toml")
    text = gc.scene_toml(scene)
    for source in (path, str(path), text, gc.scene_dict(scene), scene):
        assert gc.scene_dict(gc.load_scene(source)) == gc.scene_dict(scene), source
    assert gc.load_scene(path).name == "api" and gc.load_scene(text, name="x").name == "x"


def test_change_returns_a_new_validated_scene(scene):
    new = gc.change(scene, {"interface.phi_n_star": 0.05}, surface={"nodes": 512})
    assert (new.interface.phi_n_star, new.surface.nodes) == (0.05, 512)
    assert (scene.interface.phi_n_star, scene.surface.nodes) == (0.15, 256)  # the old one is untouched
    assert gc.change(scene, name="renamed").name == "renamed"


@pytest.mark.parametrize("call, key", [
    (lambda s: gc.change(s, {"interface.phi_nn_star": 0.1}), "phi_nn_star"),
    (lambda s: gc.change(s, {"surface.nodes": -4}), "surface.nodes"),
    (lambda s: gc.change(s, {"nodes": 4}), "nodes"),
    (lambda s: gc.change(s, surface=1024), "surface"),
    (lambda s: gc.load_scene({"surfac": {}}), "surfac"),
    (lambda s: gc.load_scene("[surface]\nnodes = 'many'\n"), "surface.nodes"),
    (lambda s: gc.run(s, method="fe"), "method.name"),  # the FE refuses a half-plane, before any work
    (lambda s: gc.run(s, method="bem"), "method"),
])
def test_bad_input_is_refused_naming_the_key(scene, call, key):
    with pytest.raises(gc.SceneError, match=key.replace(".", r"\.")):
        call(scene)


def test_check_is_what_gfmd_scene_check_reports(scene):
    under = gc.change(scene, {"interface.length_normal": 0.5e-9})  # δn < 2 l: a resolution warning
    assert gc.check(scene) == ([], [])
    found, _ = gc.check(under)
    assert len(found) == 1 and "under-resolved" in found[0]


# ---------------------------------------------------------------- runs

def test_run_equals_gfmd_run(scene, result, tmp_path):
    """The API's run directory and the command line's hold the same results."""
    path = gc.save_scene(scene, tmp_path / "api.toml")
    assert main(["run", str(path), "--out", str(tmp_path / "cli"), "--realizations", "2", "--no-plot",
                 "--quiet"]) == 0
    cli = gc.open_run(tmp_path / "cli")
    pd.testing.assert_frame_equal(result.curve.drop(columns="wall_s"), cli.curve.drop(columns="wall_s"))
    pd.testing.assert_frame_equal(result.mean_curve, cli.mean_curve)
    for k in ("method", "model", "realizations", "seeds", "steps_run", "all_converged"):
        assert result.meta[k] == cli.meta[k], k


def test_result_is_the_run_directory_read_back(result):
    d = result.dir
    assert result.complete and result.converged and result.scene.name == "api"
    pd.testing.assert_frame_equal(result.curve, pd.read_csv(d / "curve.csv"))
    assert list(result.curve["realization"].unique()) == [0, 1]
    assert list(result.mean_curve.columns) == (["step", "delta", "U"]
                                               + [f"{n}{s}" for n in AVERAGED for s in ("", "_se", "_n")])
    assert result.meta == json.loads((d / "meta.json").read_text())
    z = np.load(d / "fields.npz")
    steps = result.saved_steps(1)
    assert steps == sorted(int(k.split("_")[1][1:]) for k in z.files if k.startswith("r1_s") and k.endswith("_gap"))
    f = result.fields(1, steps[0])
    np.testing.assert_array_equal(f["gap"], z[f"r1_s{steps[0]}_gap"])
    np.testing.assert_array_equal(f["h"], z["h_r1"])
    assert f["delta"] == result.curve.query(f"realization == 1 and step == {steps[0]}")["delta"].item()
    assert result.fields(1)["step"] == steps[-1]  # default: the last saved step
    with pytest.raises(KeyError, match=re.escape(f"saved steps: {steps}")):
        result.fields(1, steps[0] + 1)


def test_an_unfinished_run_is_read_from_its_saved_steps(scene, result, tmp_path):
    """Every step on disk but no final files (as while a run goes): the same curve and mean curve."""
    from gfmd_contact.app.ensemble import run_to_directory

    two = gc.change(scene, {"surface.realizations": 2})
    out = io.prepare_run_dir(tmp_path / "unfinished", two)
    run_to_directory(two, out, workers=1, progress=False)
    part = gc.open_run(out)
    assert not part.complete and not (out / "curve.csv").exists()
    pd.testing.assert_frame_equal(part.curve.drop(columns="wall_s"), result.curve.drop(columns="wall_s"))
    pd.testing.assert_frame_equal(part.mean_curve, result.mean_curve, check_dtype=False)
    step = result.saved_steps(0)[-1]
    np.testing.assert_array_equal(part.fields(0, step)["t_n"], result.fields(0, step)["t_n"])


def test_run_refuses_a_directory_holding_another_run(scene, result):
    with pytest.raises(gc.RunDirError, match="not empty"):
        gc.run(scene, out=result.dir, progress=False)
    with pytest.raises(gc.RunDirError, match=r"surface\.realizations: 2 there, 3 now"):
        gc.run(scene, out=result.dir, resume=True, progress=False)
    again = gc.run(scene, out=result.dir, resume=True, realizations=2, progress=False)  # complete: read back
    pd.testing.assert_frame_equal(again.curve, result.curve)


def test_open_run_refuses_what_is_no_run(tmp_path):
    with pytest.raises(FileNotFoundError, match="scene.toml"):
        gc.open_run(tmp_path)


def test_figures_of_a_run(result):
    figs = gc.run_figures(result)
    assert {"area_vs_reduced_pressure", "pressure_vs_delta", "interface_snapshot"} <= set(figs)
    paths = gc.plot_run(result, fmt="svg")
    assert paths and all(p.is_file() and p.parent == result.dir / "plots" for p in paths)


# ---------------------------------------------------------------- studies

def test_make_study_is_the_study_file_it_writes(scene, tmp_path):
    """make_study's text, saved and read as `gfmd study run` reads a file, gives the same sets and tasks."""
    axes, zipped = {"interface.length_normal": [2.5e-9, 5e-9]}, {"interface.law": ["hard-wall", "cohesive"],
                                                                 "interface.phi_n_star": [0.15, 0.01]}
    study = gc.make_study(scene, axes=axes, zip=zipped, name="s")
    path = tmp_path / "s.toml"
    path.write_text(gc.study_text(scene, axes=axes, zip=zipped, name="s"))
    read = gc.load_study(path)
    assert read.sets == study.sets and [t.key for t in read.tasks] == [t.key for t in study.tasks]
    assert len(study.sets) == 4 and len(study.tasks) == 4 * 3  # 3 realizations each


def test_make_study_refuses_a_bad_axis_naming_it(scene):
    with pytest.raises(gc.StudyError, match="interface.phi_n_star"):
        gc.make_study(scene, axes={"interface.phi_n_star": [0.1, -1.0]})
    with pytest.raises(gc.StudyError, match="surface.nodez"):
        gc.make_study(scene, axes={"surface.nodez": [64]})


def test_open_study_refuses_what_is_no_study(tmp_path):
    with pytest.raises(FileNotFoundError, match="study.json"):
        gc.open_study(tmp_path)
