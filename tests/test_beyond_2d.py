"""studies/beyond/fig3_2d*.toml: the seed's Fig. 3 study in 2+1-D loads and validates,
varies what studies/seed/fig3.toml varies, and the committed 1+1-D vs 2+1-D claims table is what
studies/beyond/compare_dims.py makes of the committed study tables."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from gfmd_contact.app.study import load_study

ROOT = Path(__file__).resolve().parents[1]
BEYOND = ROOT / "studies" / "beyond"
RESULTS = ROOT / "studies" / "results" / "beyond_2d_small"


def _compare():
    spec = importlib.util.spec_from_file_location("compare_dims", BEYOND / "compare_dims.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("name, nodes, realizations", [("fig3_2d", 512, 10), ("fig3_2d_small", 256, 3)])
def test_2d_fig3_study_files(name, nodes, realizations):
    study = load_study(BEYOND / f"{name}.toml")  # every set built and preflighted
    seed = load_study(ROOT / "studies" / "seed" / ("fig3.toml" if name == "fig3_2d" else "fig3_small.toml"))
    assert list(study.zipped) == list(seed.zipped) and study.zipped == seed.zipped
    for scene in study.scenes:
        s = scene.surface
        assert (s.nodes, s.nodes_y, s.realizations) == (nodes, nodes, realizations)
        assert s.rolloff_wavelength == pytest.approx(s.length / 8)  # the seed's ε_t
        assert s.rollon_wavelength / (s.length / s.nodes) == pytest.approx(8)  # λsH/l of the small 1+1-D files
        assert scene.interface.length_normal == pytest.approx(s.h_rms / 10)  # the seed's h_rms/δn
        assert scene.loading.final_penetration == pytest.approx(2 * s.h_rms)


@pytest.mark.skipif(not (RESULTS / "claims_1d_vs_2d.md").is_file(), reason="no committed beyond_2d_small results")
def test_compare_reproduces_the_committed_table():
    md, tab = _compare().render(RESULTS / "fig3_small_1d", RESULTS / "fig3_2d_small")
    assert md == (RESULTS / "claims_1d_vs_2d.md").read_text()
    assert tab == (RESULTS / "claims_1d_vs_2d.csv").read_text()
    assert "N = 256 × 256" in md and "N = 4096," in md
