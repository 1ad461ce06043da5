"""Studies of load paths (issue 23 §3, §5): summaries keep the branches apart, cycle figures over an axis."""

import csv
import json
import math

import numpy as np
import pytest

from contact import loading as L
from contact.scene import scene_to_toml
from test_load_paths import path_scene


def rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def path_study(tmp_path_factory):
    """Two adhesion strengths × two realizations of a rough load–unload cycle: (study file, out)."""
    from workbench.cli import main

    folder = tmp_path_factory.mktemp("cycstudy")
    scene = path_scene(**{"interface.law": "cohesive", "surface.nodes": 64}).replace(**{
        "surface.kind": "self-affine", "surface.hurst": 0.8, "surface.h_rms": 3e-9,
        "surface.rolloff_wavelength": 0.5e-6, "surface.rollon_wavelength": 0.05e-6, "surface.realizations": 2})
    (folder / "base.toml").write_text(scene_to_toml(scene))
    (folder / "study.toml").write_text('base = "base.toml"\n[axes]\n"interface.phi_n_star" = [0.05, 0.15]\n')
    out = folder / "out"
    assert main(["study", "run", str(folder / "study.toml"), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    return folder / "study.toml", out


def test_summary_keeps_the_branches_apart(path_study):
    """summary.csv and summary.nc carry per step the branch and cycle of the scene's path (contact.loading)."""
    xr = pytest.importorskip("xarray")
    from workbench.study import load_study

    path, out = path_study
    study = load_study(path)
    summary = rows(out / "summary.csv")
    assert list(summary[0])[:6] == ["set", "interface.phi_n_star", "step", "branch", "cycle", "delta"]
    branch, cycle = L.step_branches(study.scenes[0].loading)
    for s in ("0", "1"):
        mine = [r for r in summary if r["set"] == s]
        assert [r["branch"] for r in mine] == list(branch) and [int(r["cycle"]) for r in mine] == list(cycle)
    assert {r["branch"] for r in summary} == {"loading", "unloading"}
    # a δ visited on both branches keeps two rows with their own means (no mixing)
    twice = [r for r in summary if r["set"] == "1" and math.isclose(float(r["delta"]), -2e-9, abs_tol=1e-18)]
    assert sorted(r["branch"] for r in twice) == ["loading", "unloading"]
    with xr.open_dataset(out / "summary.nc", engine="scipy") as ds:
        ds = ds.load()
    assert ds["branch"].dims == ("interface.phi_n_star", "step")
    for r in summary:
        cell = ds.sel({"interface.phi_n_star": float(r["interface.phi_n_star"]), "step": int(r["step"])})
        assert str(cell["branch"].values) == r["branch"] and int(cell["cycle"]) == int(r["cycle"])
        assert float(cell["p"]) == float(r["p"])


def test_ramp_study_has_no_branch_columns():
    """A ramp study's summary columns are the seed's (no branch/cycle)."""
    from workbench.study import summary_columns

    assert "branch" not in summary_columns() and summary_columns(True)[:3] == ["step", "branch", "cycle"]
