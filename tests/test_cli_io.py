"""Result files, ensembles and the command line (gfmd_contact.app.io, gfmd_contact.app.ensemble, gfmd_contact.cli)."""

import json
import tomllib

import numpy as np
import pytest

from gfmd_contact.cli import main
from gfmd_contact.app.averages import ensemble_average, mean_standard_error
from gfmd_contact.app.ensemble import run_ensemble
from gfmd_contact.app.io import read_run, write_run
from gfmd_contact.core.result import CURVE_COLUMNS, FIELD_NAMES
from gfmd_contact.core.scene import default_scene, scene_from_dict, scene_to_toml


def small_scene(**extra):
    """Default geometry shrunk to N = 256 (λs,H = 4 l), 2 realizations, 6 steps: ~1 s."""
    d = {"surface.nodes": 256, "surface.rollon_wavelength": 20e-9, "surface.realizations": 2,
         "loading.steps": 6, "loading.final_penetration": 8e-9, "output.field_steps": 2, "output.workers": 1}
    d.update(extra)
    return default_scene().replace(**d)


@pytest.fixture(scope="module")
def ensemble():
    scene = small_scene()
    return scene, run_ensemble(scene, progress=False)


def test_run_directory_round_trip(tmp_path, ensemble):
    scene, results = ensemble
    write_run(tmp_path, scene, results, timings={"total_s": 1.0})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["curve.csv", "fields.npz", "mean_curve.csv", "meta.json",
                                                          "scene.toml"]
    scene2, curves, fields, meta = read_run(tmp_path)
    assert scene2 == scene
    assert sorted(curves) == [0, 1]
    for r in results:
        for c in CURVE_COLUMNS:  # written with repr(): exact round trip, NaN (no contact) included
            np.testing.assert_array_equal(curves[r.realization][c], np.asarray(r.curve[c], float))
        np.testing.assert_array_equal(fields[f"h_r{r.realization}"], r.h)
        for step, f in r.fields.items():
            for name in FIELD_NAMES:
                np.testing.assert_array_equal(fields[f"r{r.realization}_s{step}_{name}"], f[name])
    assert set(results[0].fields) == {3, 6}  # field_steps = 2: evenly spaced, last included
    assert meta["model"] == results[0].model and meta["model_reasons"]
    assert meta["all_converged"] is True and meta["messages"] == []
    assert meta["code_version"] and "platform" in meta and meta["timings"]["total_s"] == 1.0


def test_realizations_use_consecutive_seeds(ensemble):
    scene, results = ensemble
    assert [r.realization for r in results] == [0, 1]
    assert not np.array_equal(results[0].h, results[1].h)
    again = run_ensemble(scene.replace(**{"surface.seed": scene.surface.seed + 1, "surface.realizations": 1}),
                         progress=False)
    np.testing.assert_array_equal(again[0].h, results[1].h)


def test_ensemble_average_matches_numpy(ensemble):
    _, results = ensemble
    avg = ensemble_average(results)
    p = np.array([r.curve["p"] for r in results])
    np.testing.assert_allclose(avg["p"], p.mean(axis=0), rtol=1e-14, atol=0)
    np.testing.assert_allclose(avg["p_se"], p.std(axis=0, ddof=1) / np.sqrt(len(results)), rtol=1e-12, atol=0)


def test_mean_standard_error_skips_undefined_values():
    values = np.array([[1.0, np.nan, np.nan], [3.0, 5.0, np.nan]])
    mean, se, count = mean_standard_error(values)
    np.testing.assert_array_equal(count, [2, 1, 0])
    assert mean[0] == 2.0 and mean[1] == 5.0 and np.isnan(mean[2])
    assert se[0] == pytest.approx(1.0) and se[1] == 0.0 and se[2] == 0.0


def test_cli_run_writes_results_and_plots(tmp_path, capsys):
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(scene_to_toml(small_scene(**{"surface.realizations": 1})))
    out = tmp_path / "out"
    assert main(["run", str(scene_file), "--out", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "model solved: normal-only CZ, half-plane, 256 nodes" in err
    pngs = sorted(p.name for p in (out / "plots").iterdir())
    assert pngs == ["area_vs_delta.png", "area_vs_reduced_pressure.png", "gr_over_g_vs_delta.png",
                    "interface_snapshot.png", "pressure_vs_delta.png"]
    assert all((out / "plots" / p).stat().st_size > 1000 for p in pngs)
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]  # atomic writes leave no temporaries


def test_cli_reports_unconverged_steps(tmp_path, capsys):
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(scene_to_toml(small_scene(**{"surface.realizations": 1, "solver.max_iterations": 2})))
    out = tmp_path / "out"
    assert main(["run", str(scene_file), "--out", str(out), "--quiet", "--no-plot"]) == 1
    assert "WARNING: realization 0 (seed 1), step" in capsys.readouterr().err
    meta = json.loads((out / "meta.json").read_text())
    assert meta["all_converged"] is False and meta["messages"]


def test_cli_rejects_bad_scene(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('[material]\nyoungs_modulus = -1.0\n')
    assert main(["run", str(bad), "--out", str(tmp_path / "o")]) == 2
    assert "material.youngs_modulus = -1.0" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()  # refused before any work


def test_cli_example_scene_is_valid(capsys):
    assert main(["scene", "--example"]) == 0
    text = capsys.readouterr().out
    scene = scene_from_dict(tomllib.loads(text))
    assert scene.surface.nodes == 131072 and scene.interface.law == "cohesive"


def test_scene_check(tmp_path, capsys):
    f = tmp_path / "s.toml"
    f.write_text(scene_to_toml(small_scene()))
    assert main(["scene", "--check", str(f)]) == 0
    assert "valid scene" in capsys.readouterr().out


def test_cli_fe_method_writes_results_and_vtu_series(tmp_path, capsys):
    import meshio
    scene = small_scene(**{"surface.nodes": 64, "surface.rollon_wavelength": 80e-9, "surface.realizations": 1,
                           "material.thickness": 1.28e-6, "interface.length_normal": 40e-9,
                           "loading.initial_separation": 80e-9, "loading.steps": 4})
    scene_file = tmp_path / "fe.toml"
    scene_file.write_text(scene_to_toml(scene))
    out = tmp_path / "out"
    assert main(["run", str(scene_file), "--method", "fe", "--out", str(out), "--quiet", "--no-plot"]) == 0
    assert "model solved: FE P2" in capsys.readouterr().err
    _, curves, _, meta = read_run(out)
    vtu = out / "vtu" / "realization0"
    files = sorted(p.name for p in vtu.iterdir())
    steps = [f for f in files if f.endswith(".vtu")]
    assert "fe.pvd" in files and len(steps) == scene.output.field_steps
    mesh = meshio.read(vtu / steps[-1])
    assert mesh.point_data["displacement"].shape[1] == 3 and np.all(np.isfinite(mesh.point_data["displacement"]))
    assert meta["all_converged"] is True and np.all(np.isfinite(curves[0]["p"]))
