"""Studies on 2+1-D scenes: `gfmd study run` unchanged on a surface of Nx × Ny nodes.

A tiny study (32 × 32 nodes, 8 load steps, hard wall + cohesive, 2 realizations: 4 tasks) on a local
Dask cluster: study.csv / summary.csv / summary.nc with one row per (task, step) and the means over
the realizations, the saved fields as (Nx, Ny) arrays, a rerun that reuses every task and writes the
same tables, the study figures (the 1-D interface snapshot replaced by contact maps) and the claims
computed from the curves (κ of the hard wall equals the fit of its own curves).
"""

import csv
import json
import math

import numpy as np
import pytest

from gfmd_contact.app.claims import evaluate, kappa_per_realization, read_study_dir
from gfmd_contact.cli import main
from gfmd_contact.app.study_plots import FIGURES_2D, make_study_figures

N, STEPS = 32, 8

BASE = f"""
[surface]
kind = "self-affine"
length = 1.28e-6
nodes = {N}
nodes_y = {N}
hurst = 0.8
h_rms = 10e-9
rolloff_wavelength = 160e-9
rollon_wavelength = 80e-9
seed = 1
realizations = 2

[interface]
law = "cohesive"
phi_n_star = 0.15
length_normal = 1e-9

[loading]
initial_separation = 8e-9
final_penetration = 20e-9
steps = {STEPS}

[output]
field_steps = 2
"""

STUDY = """
base = "base.toml"
[zip]
"interface.law" = ["hard-wall", "cohesive"]
"interface.phi_n_star" = [0.15, 0.05]
"""


def rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def study2d(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study2d")
    (folder / "base.toml").write_text(BASE)
    (folder / "study.toml").write_text(STUDY)
    out = folder / "out"
    assert main(["study", "run", str(folder / "study.toml"), "--out", str(out), "--workers", "2", "--quiet"]) == 0
    return folder / "study.toml", out


def test_tables_of_a_2d_study(study2d):
    """One row per (task, step), the sets' parameters, means over the 2 realizations; fields are (Nx, Ny)."""
    _, out = study2d
    table = rows(out / "study.csv")
    assert len(table) == 2 * 2 * (STEPS + 1)
    assert {(r["set"], r["interface.law"]) for r in table} == {("0", "hard-wall"), ("1", "cohesive")}
    assert {(r["realization"], r["seed"]) for r in table} == {("0", "1"), ("1", "2")}
    assert all(r["converged"] == "1" for r in table)
    summary = rows(out / "summary.csv")
    assert len(summary) == 2 * (STEPS + 1)
    last = next(r for r in summary if r["set"] == "1" and r["step"] == str(STEPS))
    p = [float(r["p"]) for r in table if r["set"] == "1" and r["step"] == str(STEPS)]
    assert float(last["p"]) == pytest.approx(np.mean(p), rel=1e-12) and last["p_n"] == "2"
    assert float(last["p_se"]) == pytest.approx(np.std(p, ddof=1) / math.sqrt(2), rel=1e-12)
    # the rough 1+1-D stickiness measures are not extended to surfaces: "nan", not a 1-D number
    assert {r["stickiness_tabor_rough"] for r in summary} == {"nan"}
    task = table[-1]["task"]
    with np.load(out / "tasks" / task / "fields.npz") as f:
        gaps = [k for k in f.files if k.endswith("_gap")]
        assert gaps and all(f[k].shape == (N, N) for k in gaps)
        assert f["x"].shape == (N,) and f["y"].shape == (N,)
    xr = pytest.importorskip("xarray")
    with xr.open_dataset(out / "summary.nc", engine="scipy") as ds:
        assert ds["p"].sizes["step"] == STEPS + 1


def test_a_rerun_reuses_every_task(study2d):
    path, out = study2d
    before = (out / "study.csv").read_text()
    assert main(["study", "run", str(path), "--out", str(out), "--workers", "2", "--quiet"]) == 0
    record = json.loads((out / "study.json").read_text())
    assert (record["tasks_reused"], record["tasks_run"], record["tasks_failed"]) == (4, 0, 0)
    assert (out / "study.csv").read_text() == before


def test_figures_and_claims_of_a_2d_study(study2d):
    """Contact maps instead of the 1-D snapshot; κ from the curves as in 1+1-D (the claim is its fit)."""
    _, out = study2d
    data = read_study_dir(out)
    figs = make_study_figures(out, data=data)
    assert list(figs) == list(FIGURES_2D)  # contact_maps in place of interface_snapshot
    maps = figs["contact_maps"]
    images = [im for ax in maps.axes for im in ax.get_images() if im.get_gid() == "contact"]
    assert len(images) == 2 and all(im.get_array().shape == (N, N) for im in images)
    hard = next(s for s in data.with_data if s.hard_wall)
    kappas = kappa_per_realization(hard)
    assert len(kappas) == 2 and all(np.isfinite(k) and k > 0 for k in kappas.values())
    # the same fit by hand from realization 0's rows of study.csv (0 < a_rel ≤ 0.1, p > 0, p_r* = p/(ḡ_r E*))
    table = [r for r in rows(out / "study.csv") if r["set"] == str(hard.index) and r["realization"] == "0"]
    p, a, g_r = (np.array([float(r[c]) for r in table]) for c in ("p", "a_rel", "g_r"))
    ok = (p > 0) & (a > 0) & (a <= 0.1)
    assert ok.sum() >= 2
    x = p[ok] / (g_r[ok] * hard.scene.material.contact_modulus)
    assert kappas[0] == pytest.approx(float(x @ a[ok] / (x @ x)), rel=1e-9)
    results = {r.id: r for r in evaluate(data)}
    assert results["kappa"].verdict != "not in this study"
    (out / "figures").mkdir(exist_ok=True)
    assert main(["study", "plot", str(out)]) == 0
    assert (out / "figures" / "contact_maps.png").is_file()


def test_an_interrupted_2d_task_continues_from_its_saved_steps(study2d, tmp_path):
    """A task stopped after 4 checkpointed steps (its (Nx, Ny) state saved) continues there on `study run`;
    the tables equal the uninterrupted study's (every column but wall_s)."""
    from gfmd_contact.app.study import load_study, prepare_study_dir, run_task

    ref_path, ref = study2d
    (tmp_path / "base.toml").write_text(BASE)
    path = tmp_path / "study.toml"
    path.write_text(STUDY)
    out = tmp_path / "out"
    study = load_study(path)
    prepare_study_dir(out, study)
    task = study.tasks[2]  # the cohesive set, realization 0

    def stop(step, steps):
        if step >= 4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_task(task.scene, out / "tasks" / task.key, progress=stop)
    assert main(["study", "run", str(path), "--out", str(out), "--workers", "2", "--quiet"]) == 0
    record = json.loads((out / "study.json").read_text())
    assert record["steps_reused"] >= 4 and record["tasks_run"] == 4
    no_wall = lambda t: [{k: v for k, v in r.items() if k != "wall_s"} for r in t]  # noqa: E731
    for name in ("study.csv", "summary.csv"):
        assert no_wall(rows(out / name)) == no_wall(rows(ref / name)), name
