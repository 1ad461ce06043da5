"""The Python API in Python terms: its errors name the keywords (resume=True, overwrite=True), not the command
line's flags, which `gfmd run` keeps; `run(plot=True)` writes the figures; a run without `out` leaves nothing
behind in the system's temporary folder once its result is gone."""

import gc as garbage
import re
from pathlib import Path

import pytest

import gfmd_contact as gc
from gfmd_contact.cli import main
from gfmd_contact.core.scene import scene_to_toml

FLAG = re.compile(r"--\w")


def _scene():
    return gc.default_scene().replace(**{
        "surface.nodes": 256, "surface.length": 320e-9, "surface.rolloff_wavelength": 160e-9,
        "surface.rollon_wavelength": 10e-9, "surface.realizations": 1, "interface.length_normal": 2.5e-9,
        "loading.steps": 4, "loading.final_penetration": 4e-9, "loading.initial_separation": 20e-9,
        "output.field_steps": 2})


def test_a_non_empty_out_is_refused_in_keywords_from_python_and_in_flags_from_the_command_line(tmp_path, capsys):
    out = tmp_path / "busy"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    with pytest.raises(gc.RunDirError) as exc:
        gc.run(_scene(), out=out, progress=False)
    text = str(exc.value)
    assert "add resume=True to continue a run there, overwrite=True to replace it, or choose another out" in text
    assert not FLAG.search(text), text
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(scene_to_toml(_scene()))
    assert main(["run", str(scene_file), "--out", str(out), "--quiet", "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert "add --resume to continue a run there, --overwrite to replace it, or choose another --out" in err


def test_resume_of_another_scene_and_overwrite_of_foreign_files_name_the_keywords(tmp_path):
    out = tmp_path / "run"
    gc.run(_scene(), out=out, progress=False)
    with pytest.raises(gc.RunDirError, match=r"^resume=True: .* holds a run of another scene \(surface\.realizations: "
                                             r"1 there, 2 now\); resume with the same scene \(gfmd_contact\.open_run"):
        gc.run(_scene(), out=out, realizations=2, resume=True, progress=False)
    (out / "notes.txt").write_text("mine")
    with pytest.raises(gc.RunDirError, match=r"^overwrite=True: .* holds files a run does not write \(notes\.txt\)"):
        gc.run(_scene(), out=out, overwrite=True, progress=False)


def test_plot_true_writes_the_figures(tmp_path):
    plain = gc.run(_scene(), out=tmp_path / "plain", progress=False)
    assert not (plain.dir / "plots").exists()
    drawn = gc.run(_scene(), out=tmp_path / "drawn", progress=False, plot=True)
    pngs = sorted(p.name for p in (drawn.dir / "plots").glob("*.png"))
    assert {"pressure_vs_delta.png", "area_vs_delta.png", "area_vs_reduced_pressure.png"} <= set(pngs), pngs
    assert all((drawn.dir / "plots" / p).stat().st_size > 1000 for p in pngs)


def test_a_run_without_out_goes_with_its_result(tmp_path):
    """No `out`: the run lives in a temporary directory while its result does, can be saved, and is gone after."""
    res = gc.run(_scene(), progress=False)
    where = Path(res.dir)
    assert where.is_dir() and (where / "curve.csv").is_file() and len(res.curve) == 5
    kept = res.save(tmp_path / "kept")
    assert kept.curve.equals(res.curve) and (tmp_path / "kept" / "meta.json").is_file()
    with pytest.raises(FileExistsError, match="not an empty directory"):
        res.save(tmp_path / "kept")
    del res
    garbage.collect()
    assert not where.exists()
    assert (tmp_path / "kept" / "curve.csv").is_file()


def test_resume_without_out_is_refused_by_keyword():
    with pytest.raises(ValueError, match=r"^resume=True needs out"):
        gc.run(_scene(), resume=True, progress=False)


def test_a_study_directory_that_cannot_take_the_study_is_named_by_keyword(tmp_path, capsys):
    out = tmp_path / "busy"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    study = gc.make_study(_scene(), axes={"interface.phi_n_star": [0.01, 0.15]})
    with pytest.raises(gc.RunDirError, match=r"^out .* is not empty and holds no study \(notes\.txt\): choose another "
                                             r"out$"):
        gc.run_study(study, out=out, workers=1, progress=False)
    study_file = tmp_path / "study.toml"
    study_file.write_text(study.text)
    assert main(["study", "run", str(study_file), "--out", str(out), "--workers", "1", "--quiet"]) == 2
    assert "holds no study (notes.txt): choose another --out" in capsys.readouterr().err


def test_a_relative_surface_path_given_in_python_runs_into_any_out(tmp_path, monkeypatch):
    """A scene made in Python with a relative surface.path (the working directory's) runs into a run directory
    elsewhere: the path is the file read at validation, not a path relative to DIR/scene.toml."""
    import numpy as np

    import gfmd_contact as gc

    monkeypatch.chdir(tmp_path)
    np.savetxt("h.txt", 1e-9 * np.sin(2 * np.pi * np.arange(1024) / 1024))
    scene = gc.change(gc.default_scene(), {"surface.kind": "file", "surface.path": "h.txt", "surface.nodes": 1024,
                                           "interface.law": "hard-wall", "loading.steps": 2})
    assert scene.surface.path == str(tmp_path / "h.txt")
    res = gc.run(scene, out=tmp_path / "runs" / "a", workers=1, progress=False)
    assert res.meta["complete"] and len(res.curve) >= 1
