"""Figures of a study directory (gfmd_contact.app.study_plots, `gfmd study plot`): a tiny study run once through
`gfmd_contact.app.study.run_study` (N = 512, 24 load steps, h_rms = 10, 15 nm × hard wall / φn* = 0.15,
2 realizations: 4 sets, 8 tasks on 2 workers); every figure is written, holds one curve per set with
the hard walls as references, labels its error bars, the κ fit per hard-wall set; a partial study
(one task gone, still "running") is drawn with a note; refusals name the problem (exit 2)."""

import json
import shutil

import pytest

from gfmd_contact.cli import main
from gfmd_contact.app.study import run_study, study_from_dict
from gfmd_contact.app.study_plots import FIGURES, make_study_figures, plot_study

BASE = {
    "surface": {"kind": "self-affine", "length": 320e-9, "nodes": 512, "hurst": 0.8, "h_rms": 10e-9,
                "rolloff_wavelength": 160e-9, "rollon_wavelength": 10e-9, "seed": 1, "realizations": 2},
    "interface": {"law": "cohesive", "phi_n_star": 0.15, "length_normal": 2.5e-9},
    "loading": {"initial_separation": 20e-9, "final_penetration": 8e-9, "steps": 24},
    "output": {"field_steps": 4},
}


@pytest.fixture(scope="module")
def study_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("study")
    study = study_from_dict({"name": "tiny", "scene": BASE, "axes": {"surface.h_rms": [10e-9, 15e-9]},
                             "zip": {"interface.law": ["hard-wall", "cohesive"],
                                     "interface.phi_n_star": [0.15, 0.15]}})
    record = run_study(study, out, workers=2, progress=False)
    assert record["tasks_failed"] == 0
    return out


def _lines(ax, gid):
    return [ln for ln in ax.get_lines() if ln.get_gid() == gid]


def test_every_figure_is_written(study_dir):
    paths = plot_study(study_dir, fmt="svg")
    assert [p.stem for p in paths] == list(FIGURES)
    assert all(p.parent == study_dir / "figures" and p.stat().st_size > 1000 for p in paths)


def test_overlay_one_curve_per_set_with_references_and_error_bar_label(study_dir):
    figs = make_study_figures(study_dir)
    ax = figs["area_vs_reduced_pressure"].axes[0]
    mean, ref = _lines(ax, "mean"), _lines(ax, "reference")
    assert len(mean) == 2 and len(ref) == 2  # the cohesive sets, and the two hard walls dashed
    assert all(ln.get_linestyle() == "--" for ln in ref)
    legend = ax.get_legend()
    labels = [t.get_text() for t in legend.get_texts()]
    assert "error bars: ± 1 standard error over n = 2 realizations" in labels
    assert {"h_rms = 10 nm", "h_rms = 15 nm"} <= set(labels)
    assert any("hard wall, h_rms = 15 nm" in x and "reference" in x for x in labels)
    assert "h_rms" in legend.get_title().get_text()
    assert figs["area_vs_reduced_pressure"]._suptitle is None  # complete study: no partial note
    for name in ("pressure_vs_delta", "area_vs_delta", "gr_over_g_vs_delta", "area_vs_pressure"):
        assert len(_lines(figs[name].axes[0], "mean")) == 2, name


def test_kappa_fit_per_hard_wall_set_and_snapshot(study_dir):
    figs = make_study_figures(study_dir)
    ax = figs["kappa_fit"].axes[0]
    assert len(_lines(ax, "kappa-fit")) == 2 and len(_lines(ax, "mean")) == 2
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert sum("κ = " in x and "± " in x and "(n = 2)" in x for x in labels) == 2
    assert any("fit range 0 < a_rel ≤ 0.1" in x for x in labels)
    snap = figs["interface_snapshot"].axes[0]
    colors = sorted(ln.get_color() for ln in _lines(snap, "surface"))
    assert colors == ["tab:green", "tab:red"]
    assert "realization 0" in snap.get_title()


def test_over_axis_panels_and_unknown_axis(study_dir):
    figs = make_study_figures(study_dir, over="interface.law")
    panels = [ax for ax in figs["area_vs_delta"].axes if ax.get_visible()]
    assert [ax.get_title().split("\n")[1] for ax in panels] == ["h_rms = 10 nm", "h_rms = 15 nm"]
    for ax in panels:  # the law is the overlay axis: hard wall and cohesive are curves, no reference
        assert len(_lines(ax, "mean")) == 2 and not _lines(ax, "reference")
        assert "interface.law" in ax.get_legend().get_title().get_text()
    with pytest.raises(ValueError, match="--over 'surface.nodes'"):
        make_study_figures(study_dir, over="surface.nodes")


def test_partial_study_is_drawn_with_a_note(study_dir, tmp_path):
    part = tmp_path / "part"
    shutil.copytree(study_dir, part, ignore=shutil.ignore_patterns("figures", "report.html"))
    record = json.loads((part / "study.json").read_text())
    record["complete"] = False
    (part / "study.json").write_text(json.dumps(record))
    (part / "study.csv").unlink()
    shutil.rmtree(part / "tasks" / record["tasks"][-1]["key"])  # the last set loses a realization
    figs = make_study_figures(part)
    note = figs["area_vs_delta"]._suptitle.get_text()
    assert note.startswith("PARTIAL STUDY: 7 of 8 tasks finished") and "fewer realizations in set 3" in note
    assert _lines(figs["area_vs_delta"].axes[0], "mean")


def test_cli_refuses_what_is_no_study(tmp_path, capsys, study_dir):
    assert main(["study", "plot", str(tmp_path)]) == 2
    assert "is not a study directory" in capsys.readouterr().err
    empty = tmp_path / "empty"
    shutil.copytree(study_dir, empty, ignore=shutil.ignore_patterns("tasks", "study.csv", "figures"))
    record = json.loads((empty / "study.json").read_text())
    record["complete"] = False
    (empty / "study.json").write_text(json.dumps(record))
    assert main(["study", "plot", str(empty)]) == 2
    assert "no finished task" in capsys.readouterr().err
    assert main(["study", "plot", str(study_dir), "--format", "png"]) == 0
    assert (study_dir / "figures" / "kappa_fit.png").is_file()
