"""studies/beyond/: the study files load and validate, and the committed table is what
studies/beyond/report.py makes of the committed csvs."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from gfmd_contact.core.loading import step_branches
from gfmd_contact.app.study import load_study

ROOT = Path(__file__).resolve().parents[1]
BEYOND = ROOT / "studies" / "beyond"
RESULTS = [ROOT / "studies" / "results" / d for d in ("beyond_small", "beyond_full")]
FILES = sorted(p for p in BEYOND.glob("fig*_cycle*.toml"))


def _report():
    spec = importlib.util.spec_from_file_location("beyond_report", BEYOND / "report.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_all_six_study_files_are_there():
    assert {p.stem for p in FILES} == {f"fig{f}_cycle{s}" for f in ("3", "6a", "6b") for s in ("", "_small")}


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_study_file_validates_and_runs_one_load_unload_cycle(path):
    study = load_study(path)  # study_from_dict: every set built and preflighted (gfmd scene --check)
    full = not path.stem.endswith("_small")
    for scene in study.scenes:
        lo = scene.loading
        assert lo.path[0] < 0 and lo.path[-1] == lo.path[0], "starts and ends out of contact"
        assert max(lo.path) == pytest.approx(20e-9), "the seed's final penetration"
        branch, cycle = step_branches(lo)
        assert set(branch) == {"loading", "unloading"} and set(cycle) == {0}
        assert (scene.surface.nodes, scene.surface.realizations) == ((131072, 10) if full else (4096, 3))


def test_full_and_small_vary_the_same_parameters():
    for f in ("3", "6a", "6b"):
        full, small = load_study(BEYOND / f"fig{f}_cycle.toml"), load_study(BEYOND / f"fig{f}_cycle_small.toml")
        assert list(full.axes) == list(small.axes) and list(full.zipped) == list(small.zipped)


@pytest.mark.parametrize("results", RESULTS, ids=lambda p: p.name)
def test_report_reproduces_the_committed_table(results):
    if not (results / "table.md").is_file():
        pytest.skip(f"no committed results in {results.name}")
    md, tab = _report().render(results)
    assert md == (results / "table.md").read_text()
    assert tab == (results / "table.csv").read_text()


def test_nonlinearity_is_zero_for_a_linear_curve_and_positive_for_a_concave_one():
    rep = _report()
    x = [0.0, 0.1, 0.2, 0.3, 0.4]
    lin = {"delta": [1e-9 * i for i in range(5)], "pr": x, "a_rel": [2 * v for v in x]}
    sqrt = dict(lin, a_rel=[v ** 0.5 for v in x])
    assert rep.nonlinearity(lin, 4e-9) == pytest.approx(0.0, abs=1e-12)
    assert rep.nonlinearity(sqrt, 4e-9) == pytest.approx(2 * 0.5 ** 0.5 - 1)
