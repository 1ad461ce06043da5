"""studies/measured/: the study files on a real AFM map load and validate (every set preflighted), their base
scenes are the map's four quadrants and nothing else differs, and studies/measured/report.py runs end to end on
a tiny suite of two of the same files (a 32 × 32-node corner of the quadrant)."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import pytest

from gfmd_contact.app.study import load_study
from gfmd_contact.app.study_suite import run_suite
from gfmd_contact.core.scene import load_scene, scene_to_dict
from gfmd_contact.studies import make_study

ROOT = Path(__file__).resolve().parents[1]
MEASURED = ROOT / "studies" / "measured"
FILES = sorted(MEASURED.glob("measured_small_q*.toml"))
QUADRANT = 250e-9


def _script(name):
    spec = importlib.util.spec_from_file_location(f"measured_{name}", MEASURED / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_four_quadrant_studies():
    assert [p.stem for p in FILES] == [f"measured_small_q{i}" for i in range(1, 5)]


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_study_validates_periodic_and_free_hard_wall_and_cycles(path):
    study = load_study(path)  # every set built and checked as `gfmd scene --check` checks it
    sets = {(s.surface.boundary, s.interface.law, s.interface.phi_n_star) for s in study.scenes}
    assert {b for b, _, _ in sets} == {"periodic", "free"}
    assert {(law, phi) for _, law, phi in sets if law == "cohesive"} == {("cohesive", 0.001), ("cohesive", 0.01)}
    for scene in study.scenes:
        s, lo = scene.surface, scene.loading
        assert s.kind == "file" and Path(s.path).name == "di-1.di" and s.resample == "none"
        assert lo.path[0] < 0 and lo.path[-1] == lo.path[0], "starts and ends out of contact"
        assert scene.interface.length_normal >= 2 * s.length / s.nodes, "δn resolved (≥ 2 l)"
        if scene.interface.law == "hard-wall":  # the report recomputes ḡ_r from every step's fields
            assert scene.output.field_steps >= lo.steps


def test_bases_are_the_four_quadrants_and_differ_only_there():
    scenes = [load_scene(MEASURED / f"base_q{i}.toml") for i in range(1, 5)]
    regions = {tuple(round(v / QUADRANT) for v in s.surface.region) for s in scenes}
    assert regions == {(0, 1, 0, 1), (1, 2, 0, 1), (0, 1, 1, 2), (1, 2, 1, 2)}
    same = [scene_to_dict(s.replace(**{"surface.region": list(scenes[0].surface.region)})) for s in scenes]
    assert all(d == same[0] for d in same), "the bases differ in more than surface.region"


@pytest.mark.slow  # ~20 s, most of it the local Dask cluster's start
def test_report_runs_on_a_tiny_suite(tmp_path):
    rep = _script("report")
    tiny = 32 * QUADRANT / 256
    studies = []
    for path in FILES[:2]:
        study = load_study(path)
        x0, _, y0, _ = study.base.surface.region
        base = study.base.replace(**{"surface.nodes": 32, "surface.nodes_y": 32,
                                     "surface.region": [x0, x0 + tiny, y0, y0 + tiny],
                                     "surface.length": tiny, "surface.length_y": tiny,
                                     "loading.path": [-1e-9, 1e-9, -4e-9], "loading.steps": [8, 20]})
        zipped = dict(study.zipped, **{"output.field_steps": [29, 5, 5]})
        studies.append(make_study(base, axes=study.axes, zip=zipped, name=path.stem))
    run_suite(studies, tmp_path, workers=1, progress=False)
    md, tab, data = rep.render(tmp_path)
    assert md.count("\n| ") >= 9 and tab.startswith("quantity,quadrant,periodic,free\n")
    for (q, boundary, law, phi), v in data.items():
        if law == "hard-wall":  # the free run's own ḡ_r is the seam-free one (render checked both against the fields)
            assert (v["kappa"][0] == v["kappa_interior"][0]) == (boundary == "free") and math.isfinite(v["kappa"][0])
        else:
            assert v["pull_off"] < 0 and math.isfinite(v["hysteresis"])


def test_equal_load_delta_is_where_the_loading_branch_reaches_the_load():
    eq = _script("equal_load")
    curve = [{"branch": b, "delta": str(d), "p": str(p)} for b, d, p in
             (("loading", 0.0, 0.0), ("loading", 1e-9, 2.0), ("loading", 2e-9, 6.0), ("unloading", 1.5e-9, 1.0))]
    assert eq.delta_at_load(curve, 4.0) == pytest.approx(1.5e-9)
    with pytest.raises(ValueError, match="does not cross"):
        eq.delta_at_load(curve, 7.0)
