"""Studies of load paths: summaries keep the branches apart, cycle figures over an axis."""

import csv
import json
import math

import numpy as np
import pytest

from gfmd_contact.core import loading as L
from gfmd_contact.core.scene import scene_to_toml
from test_load_paths import path_scene


def rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def path_study(tmp_path_factory):
    """Two adhesion strengths × two realizations of a rough load–unload cycle: (study file, out)."""
    from gfmd_contact.cli import main

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
    """summary.csv and summary.nc carry per step the branch and cycle of the scene's path (gfmd_contact.core.loading)."""
    xr = pytest.importorskip("xarray")
    from gfmd_contact.app.study import load_study

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
    from gfmd_contact.app.study import summary_columns

    assert "branch" not in summary_columns() and summary_columns(True)[:3] == ["step", "branch", "cycle"]


def test_pull_off_and_hysteresis_vs_axis(path_study):
    """gfmd study plot --over AXIS draws pull-off and W vs AXIS: each point the mean ± SE of cycles.csv's rows."""
    from gfmd_contact.cli import main
    from gfmd_contact.app.study_cycle_plots import CYCLE_STUDY_FIGURES, cycle_study_figures

    _, out = path_study
    table = rows(out / "cycles.csv")
    figs = cycle_study_figures(out, over="interface.phi_n_star")
    assert set(figs) == set(CYCLE_STUDY_FIGURES)
    drawn = {}
    for name, column, factor in (("pull_off_vs_axis", "pull_off_pressure", 1e-6), ("hysteresis_vs_axis",
                                                                                   "hysteresis", 1e3)):
        (line,) = [c for c in figs[name].axes[0].containers if c.lines[0].get_gid() == "mean"]
        x, y = (np.asarray(v, float) for v in line.lines[0].get_data())
        assert list(x) == [0.05, 0.15]
        for xi, yi, bar in zip(x, y, line.lines[2][0].get_segments()):
            values = np.array([float(r[column]) for r in table if float(r["interface.phi_n_star"]) == xi])
            assert values.size == 2  # two realizations
            assert yi == pytest.approx(values.mean() * factor, rel=1e-12)
            se = values.std(ddof=1) / np.sqrt(values.size) * factor
            assert bar[1][1] - bar[0][1] == pytest.approx(2 * se, rel=1e-9, abs=1e-12 * abs(yi))
        drawn[column] = y
    assert drawn["pull_off_pressure"][1] < drawn["pull_off_pressure"][0] < 0  # more adhesion: more tensile
    assert main(["study", "plot", str(out), "--over", "interface.phi_n_star"]) == 0
    assert all((out / "figures" / f"{n}.png").is_file() for n in CYCLE_STUDY_FIGURES)
    assert set(cycle_study_figures(out)) == set(CYCLE_STUDY_FIGURES)  # without --over: the one varied axis
    with pytest.raises(ValueError, match="--over 'surface.nodes'"):
        cycle_study_figures(out, over="surface.nodes")


def test_ramp_study_draws_no_cycle_figures(tmp_path):
    from gfmd_contact.app.study_cycle_plots import cycle_study_figures

    assert cycle_study_figures(tmp_path) == {}


def test_api_cycles(path_study):
    """gc.open_study(...).cycles is cycles.csv; gc.open_run(task).cycles is its meta.json "cycles", one row per
    (realization, cycle); a ramp run has none."""
    import gfmd_contact as gc

    _, out = path_study
    study = gc.open_study(out)
    table = study.cycles
    assert len(table) == 4 and list(table.columns[:2]) == ["set", "interface.phi_n_star"]
    assert table["pull_off_pressure"].tolist() == [float(r["pull_off_pressure"]) for r in rows(out / "cycles.csv")]
    assert set(study.summary_table["branch"]) == {"loading", "unloading"}
    res = study.task(set=1, realization=1)
    cyc = res.cycles
    meta = json.loads((res.dir / "meta.json").read_text())["cycles"]
    assert cyc["realization"].tolist() == [e["realization"] for e in meta for _ in e["cycles"]]
    assert cyc["hysteresis"].tolist() == [c["hysteresis"] for e in meta for c in e["cycles"]]
    row = table[(table["set"] == 1) & (table["realization"] == 1)].iloc[0]
    assert row["hysteresis"] == cyc["hysteresis"].iloc[0] and row["jump_out"] == cyc["jump_out"].iloc[0]


def test_api_cycles_of_a_ramp_are_empty(tmp_path):
    import gfmd_contact as gc

    s = gc.default_scene().replace(**{"surface.nodes": 256, "surface.length": 320e-9, "surface.realizations": 1,
                                      "loading.steps": 4, "output.field_steps": 2, "output.workers": 1,
                                      "interface.law": "hard-wall"})
    res = gc.run(s, tmp_path / "run", progress=False)
    assert res.cycles.empty and "hysteresis" in res.cycles.columns


def test_force_control_mean_curve_of_several_realizations(tmp_path):
    """Under force control the realizations share the loads, not δ: mean_curve.csv averages δ and U per step and
    carries the load (before: a ValueError while writing the run)."""
    import gfmd_contact as gc
    from test_load_paths import force_scene

    s = force_scene(top=0.05, **{"surface.nodes": 64}).replace(**{
        "surface.kind": "self-affine", "surface.hurst": 0.8, "surface.h_rms": 3e-9,
        "surface.rolloff_wavelength": 0.5e-6, "surface.rollon_wavelength": 0.05e-6, "surface.realizations": 2})
    with pytest.warns(UserWarning, match="under-resolved"):
        res = gc.run(s, tmp_path / "run", progress=False)
    curve, mean = res.curve, res.mean_curve
    by_step = curve.groupby("step")
    assert not np.array_equal(curve[curve.realization == 0]["delta"], curve[curve.realization == 1]["delta"])
    assert np.allclose(mean["delta"], by_step["delta"].mean(), rtol=1e-15, atol=0)
    assert mean["load"].tolist() == by_step["load"].first().tolist() == list(L.path_values(s.loading))
    assert np.allclose(mean["p"], by_step["p"].mean(), rtol=1e-15, atol=0)


def test_force_control_study_summaries_carry_the_load(tmp_path):
    """A force-controlled study: summary.csv and summary.nc carry each step's prescribed load (Pa) beside the
    mean δ; a displacement-controlled study has no load column."""
    import xarray as xr

    from test_load_paths import force_scene
    from gfmd_contact.cli import main
    from gfmd_contact.app.study import summary_columns

    assert "load" not in summary_columns(True) and "load" in summary_columns(True, True)
    s = force_scene(top=0.05, **{"surface.nodes": 64})
    (tmp_path / "base.toml").write_text(scene_to_toml(s))
    (tmp_path / "study.toml").write_text('base = "base.toml"\n[axes]\n"interface.phi_n_star" = [0.005, 0.01]\n')
    assert main(["study", "run", str(tmp_path / "study.toml"), "--out", str(tmp_path / "out"), "--workers", "1",
                 "--quiet"]) == 0
    summary = rows(tmp_path / "out" / "summary.csv")
    loads = list(L.path_values(s.loading))
    for v in ("0.005", "0.01"):
        assert [float(r["load"]) for r in summary if r["interface.phi_n_star"] == v] == loads
    with xr.open_dataset(tmp_path / "out" / "summary.nc", engine="scipy") as ds:
        assert ds["load"].attrs["units"] == "Pa"
        assert np.array_equal(ds["load"].sel({"interface.phi_n_star": 0.01}).values[:len(loads)], loads)
