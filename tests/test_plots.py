"""Figures of a run directory (gfmd_contact.app.plots, `gfmd plot`): what is drawn, not only that files exist.

The run directories are synthetic (hand-made `Result`s written by gfmd_contact.app.io.write_run), so
negative mean pressures, non-converged steps and ragged curves are exactly known.
The figures are captured as plot_run saves them (Figure.savefig is wrapped) and their
artists are checked against values computed here.
"""

import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from matplotlib.figure import Figure

from gfmd_contact.app import plots
from gfmd_contact.cli import main
from gfmd_contact.app.io import read_run, write_run
from gfmd_contact.core.result import Result
from gfmd_contact.core.scene import default_scene

DELTA = np.linspace(-8e-9, 12e-9, 6)  # six load steps
NAN = float("nan")
# (p (Pa), a_rel, ḡ_r, converged) per realization; r0 and r2 run all six steps, r1 stops after four
CURVES = {
    0: ([0.0, -2e6, -1e6, 5e6, 2e7, 5e7], [0, .01, .03, .08, .15, .25], [NAN, .20, .25, .30, .30, .30], [1] * 6),
    1: ([0.0, -3e6, -5e5, 8e6], [0, .02, .04, .09], [NAN, .22, .26, .31], [1, 1, 0, 1]),
    2: ([0.0, -1e6, -2e5, 6e6, 3e7, 6e7], [0, .01, .05, .10, .18, .28], [NAN, .18, .24, .29, .31, .32], [1] * 6),
}
G = 0.35


def _scene(realizations, **extra):
    d = {"surface.nodes": 256, "surface.rollon_wavelength": 20e-9, "surface.realizations": realizations,
         "loading.steps": 5, "loading.final_penetration": 12e-9, "output.field_steps": 2, "output.workers": 1}
    d.update(extra)
    return default_scene().replace(**d)


E_STAR = _scene(1).material.contact_modulus

def write_synthetic_run(out, curves=CURVES, **scene_extra):
    """A run directory with the given curves; fields saved at steps 3 and 5 (where a curve has them)."""
    scene = _scene(len(curves), **scene_extra)
    n = scene.surface.nodes
    x = (np.arange(n) - n // 2) * scene.surface.spacing
    results = []
    for r, (p, a, g_r, conv) in curves.items():
        h = 5e-9 * np.sin(2 * np.pi * (r + 1) * x / scene.surface.length)
        res = Result(scene=scene, method="gfmd-fire", model="synthetic", realization=r, x=x, h=h)
        for k in range(len(p)):
            res.append_step(step=k, U=DELTA[k] + 8e-9, delta=DELTA[k], p=p[k], a_rel=a[k], g_r=g_r[k], g=G,
                            iterations=10, residual=1e-9, converged=conv[k], wall_s=0.01)
            if k in (3, 5):
                u_z = -1e-9 * (k + r) * np.cos(2 * np.pi * x / scene.surface.length)
                res.fields[k] = {"u_z": u_z, "u_x": 0 * x, "gap": h - h.min() + 1e-9 - u_z, "t_n": 0 * x,
                                 "t_t": 0 * x}
        if not all(conv):
            res.messages.append(f"realization {r}: not converged")
        results.append(res.finalize())
    write_run(out, scene, results, command="synthetic")
    return out


@pytest.fixture
def saved(monkeypatch):
    """{file name: Figure} of every figure saved while the test runs."""
    figs = {}
    original = Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        figs[str(getattr(fname, "name", fname)).rsplit("/", 1)[-1]] = self
        return original(self, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", savefig)
    return figs


def _data_line(fig):
    """The plotted mean: data line of the (only) errorbar container."""
    ax = fig.axes[0]
    assert len(ax.containers) == 1
    return ax.containers[0].lines[0]


def _legend_texts(fig):
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    return [t.get_text() for leg in legends for t in leg.get_texts()]


def _gid(fig, gid):
    return [a for a in fig.axes[0].get_children() if a.get_gid() == gid]


def _expected_mean(values):
    """Step-wise NaN-ignoring mean of ragged per-realization lists (NaN padded to 6 steps)."""
    rows = np.array([list(v) + [NAN] * (6 - len(v)) for v in values], float)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN step: mean is NaN
        return np.nanmean(rows, axis=0)


def test_adhesive_branch_is_plotted(tmp_path, saved):
    """p < 0 points stay on a_rel vs p_r* (the old `mx > 0` filter dropped them), with a line at p = 0."""
    curves = {r: CURVES[r] for r in (0, 2)}  # equal lengths: the old code drew these too, without p < 0
    plots.plot_run(write_synthetic_run(tmp_path / "run", curves=curves))
    fig = saved["area_vs_reduced_pressure.png"]
    line = _data_line(fig)
    p_r = [np.asarray(p) / (np.asarray(g_r) * E_STAR) for p, _, g_r, _ in curves.values()]
    expected_x = _expected_mean(p_r)[1:]  # step 0: no contact, ḡ_r undefined
    expected_y = _expected_mean([a for _, a, _, _ in curves.values()])[1:]
    np.testing.assert_allclose(line.get_xdata(), expected_x, rtol=1e-12)
    np.testing.assert_allclose(line.get_ydata(), expected_y, rtol=1e-12)
    assert (np.asarray(line.get_xdata()) < 0).sum() == 2  # steps 1 and 2: tensile mean pressure
    zero = [a for a in fig.axes[0].lines if a.get_gid() == "p=0"]
    assert len(zero) == 1 and set(zero[0].get_xdata()) == {0.0}
    zoom = fig.axes[1]  # the adhesive branch enlarged: its window holds the tensile points and p = 0
    lo, hi = zoom.get_xlim()
    assert lo < min(expected_x) < 0 < hi


def test_error_bars_are_named_with_the_realization_count(tmp_path, saved):
    plots.plot_run(write_synthetic_run(tmp_path / "run"))
    # ragged: at steps 4–5 only two realizations have values, elsewhere three
    for name in ("pressure_vs_delta.png", "area_vs_delta.png", "area_vs_reduced_pressure.png"):
        texts = _legend_texts(saved[name])
        assert any("mean ± standard error over n = 2–3 realizations (n varies by step)" in t for t in texts), name
    one = write_synthetic_run(tmp_path / "one", curves={0: CURVES[0]}, **{"surface.realizations": 1})
    saved.clear()
    plots.plot_run(one)
    for name in ("pressure_vs_delta.png", "area_vs_reduced_pressure.png"):
        texts = _legend_texts(saved[name])
        assert any("one realization (no error bars)" in t for t in texts)
        assert not any("standard error" in t for t in texts)
    full = {r: CURVES[r] for r in (0, 2)}
    saved.clear()
    plots.plot_run(write_synthetic_run(tmp_path / "two", curves=full))
    assert any("mean ± standard error over n = 2 realizations" in t
               for t in _legend_texts(saved["pressure_vs_delta.png"]))


def test_error_label_uses_the_per_point_count():
    assert plots.error_bar_label([4, 4, 4]) == "mean ± standard error over n = 4 realizations"
    assert plots.error_bar_label([2, 4], [3]) == ("mean ± standard error over n = 2–4 realizations "
                                                  "(n varies by step)")
    assert plots.error_bar_label([1, 1, 0]) == "one realization (no error bars)"


def test_ragged_curves_are_stacked_by_step(tmp_path, saved):
    run = write_synthetic_run(tmp_path / "run")
    _, curves, _, _ = read_run(run)
    st = plots.stack_curves(curves)
    assert st.realizations == [0, 1, 2]
    np.testing.assert_array_equal(st.step, np.arange(6))
    np.testing.assert_allclose(st.delta, DELTA)
    assert np.isnan(st["p"][1, 4:]).all() and st["p"][1, 3] == 8e6
    plots.plot_run(run)
    line = _data_line(saved["pressure_vs_delta.png"])
    np.testing.assert_allclose(line.get_xdata(), DELTA * 1e9)  # δ from the longest curve
    expected = _expected_mean([p for p, _, _, _ in CURVES.values()]) / E_STAR
    np.testing.assert_allclose(line.get_ydata(), expected, rtol=1e-12)
    np.testing.assert_allclose(line.get_ydata()[4], (2e7 + 3e7) / 2 / E_STAR)  # r1 absent: mean of r0, r2
    for name in ("pressure_vs_delta.png", "area_vs_reduced_pressure.png"):  # subset means: open markers
        fig = saved[name]
        (partial,) = _gid(fig, "partial")
        mean = _data_line(fig)
        np.testing.assert_allclose(partial.get_xdata(), mean.get_xdata()[-2:])  # steps 4, 5 (step 0 of p_r: NaN)
        assert "open: mean over n < 3 realizations (the others stopped early or have no value)" in _legend_texts(fig)
    saved.clear()
    plots.plot_run(write_synthetic_run(tmp_path / "full", curves={r: CURVES[r] for r in (0, 2)}))
    assert not _gid(saved["pressure_vs_delta.png"], "partial")


def test_stack_curves_aligns_steps_and_takes_delta_from_the_longest():
    curves = {  # r3: read back from an interrupted run that had only steps 2–3 of a shifted δ column
        0: {"step": np.array([0.0, 1.0]), "delta": np.array([9.0, 9.0]), "p": np.array([1.0, 2.0])},
        3: {"step": np.array([2.0, 3.0, 1.0, 0.0]), "delta": np.array([2.0, 3.0, 1.0, 0.0]),
            "p": np.array([30.0, 40.0, 20.0, 10.0])},
        5: {"step": np.array([4.0]), "delta": np.array([7.0]), "p": np.array([5.0])},
    }
    st = plots.stack_curves(curves)
    np.testing.assert_array_equal(st.step, [0, 1, 2, 3, 4])
    np.testing.assert_array_equal(st.delta, [0, 1, 2, 3, 7])  # longest (r3) first, then the others
    np.testing.assert_array_equal(st["p"][1], [10, 20, 30, 40, NAN])
    np.testing.assert_array_equal(st["p"][2], [NAN, NAN, NAN, NAN, 5])
    with pytest.raises(ValueError, match="repeated step"):
        plots.stack_curves({0: {"step": np.array([0.0, 0.0]), "delta": np.zeros(2)}})


def test_nonconverged_steps_are_marked(tmp_path, saved):
    plots.plot_run(write_synthetic_run(tmp_path / "run"))
    for name in ("pressure_vs_delta.png", "area_vs_delta.png", "gr_over_g_vs_delta.png"):
        fig = saved[name]
        (marks,) = _gid(fig, "nonconverged")
        np.testing.assert_allclose(marks.get_xdata(), [DELTA[2] * 1e9])  # r1, step 2
        assert marks.get_marker() == "x" and marks.get_color() == "red"
        mean = _data_line(fig)
        np.testing.assert_allclose(marks.get_ydata(), mean.get_ydata()[np.isclose(mean.get_xdata(), DELTA[2] * 1e9)])
        assert "not converged: 1 step (realization 1), included in the mean" in _legend_texts(fig)
    (marks,) = _gid(saved["area_vs_reduced_pressure.png"], "nonconverged")
    assert len(marks.get_xdata()) == 1
    saved.clear()
    plots.plot_run(write_synthetic_run(tmp_path / "ok", curves={r: CURVES[r] for r in (0, 2)}))
    for name, fig in saved.items():
        assert not _gid(fig, "nonconverged"), name
        assert not any("not converged" in t for t in _legend_texts(fig)), name


def test_hard_wall_keeps_the_kappa_fit(tmp_path, saved):
    positive = {r: ([abs(v) for v in p], a, g_r, [1] * len(p)) for r, (p, a, g_r, _) in CURVES.items()}
    plots.plot_run(write_synthetic_run(tmp_path / "run", curves=positive, **{"interface.law": "hard-wall"}))
    fig = saved["area_vs_reduced_pressure.png"]
    (fit,) = _gid(fig, "kappa-fit")
    assert len(fig.axes) == 1  # no tensile point: no adhesive-branch panel
    assert any(t.startswith("fit $a_") and "= 0.0" not in t and "(3 points)" in t for t in _legend_texts(fig))
    assert fit.get_xdata()[0] == 0 and np.max(fit.get_xdata()) == pytest.approx(np.max(_data_line(fig).get_xdata()))


def test_formats(tmp_path):
    run = write_synthetic_run(tmp_path / "run")
    svg = plots.plot_run(run, fmt="svg")
    assert [p.name for p in svg] == [f"{n}.svg" for n in plots.FIGURES]
    for p in svg:
        assert ET.parse(p).getroot().tag.endswith("svg")
    pdf = plots.plot_run(run, fmt="pdf")
    assert all(p.suffix == ".pdf" and p.read_bytes().startswith(b"%PDF") for p in pdf)
    png = plots.plot_run(run)
    assert all(p.read_bytes().startswith(b"\x89PNG") for p in png)
    with pytest.raises(ValueError, match="--format"):
        plots.plot_run(run, fmt="jpg")


def test_cli_plot_format_and_realization(tmp_path, capsys, saved):
    run = write_synthetic_run(tmp_path / "run")
    assert main(["plot", str(run), "--format", "svg", "--realization", "2"]) == 0
    out = capsys.readouterr().out
    assert "interface_snapshot.svg" in out
    title = saved["interface_snapshot.svg"].axes[0].get_title()
    assert "realization 2" in title and "δ = 12.00 nm" in title  # last saved step of r2
    assert main(["plot", str(run), "--realization", "1", "--delta", "0"]) == 0
    title = saved["interface_snapshot.png"].axes[0].get_title()
    assert "realization 1" in title and f"δ = {DELTA[3] * 1e9:.2f} nm" in title  # r1 stopped at step 3
    assert main(["plot", str(run), "--realization", "7"]) == 2
    err = capsys.readouterr().err
    assert "gfmd: error:" in err and "--realization 7" in err and "available: 0, 1, 2" in err
    with pytest.raises(SystemExit) as exc:
        main(["plot", str(run), "--format", "jpg"])
    assert exc.value.code == 2
    assert "--format" in capsys.readouterr().err


def test_snapshot_defaults_to_the_first_realization_and_shows_its_seed(tmp_path, saved, monkeypatch):
    run = write_synthetic_run(tmp_path / "run", curves={r: CURVES[r] for r in (1, 2)})
    plots.plot_run(run)
    title = saved["interface_snapshot.png"].axes[0].get_title()
    assert "realization 1" in title and "random seed 2" in title  # read_run passes curve.csv's seed on
    scene, curves, fields, meta = read_run(run)
    for r, c in curves.items():  # a curve.csv with the seed column (surface.seed + realization)
        c["seed"] = np.full(len(c["step"]), scene.surface.seed + r, float)
    monkeypatch.setattr(plots, "read_run", lambda _: (scene, curves, fields, meta))
    saved.clear()
    plots.plot_run(run, realization=2)
    assert f"realization 2, random seed {scene.surface.seed + 2}" in saved["interface_snapshot.png"].axes[0].get_title()


def test_snapshot_needs_saved_fields(tmp_path, saved):
    short = {0: tuple(v[:3] for v in CURVES[0]), 1: CURVES[1]}  # r0 stopped before the first saved step (3)
    run = write_synthetic_run(tmp_path / "run", curves=short)
    plots.plot_run(run)  # default: the first realization that has saved fields
    assert "realization 1" in saved["interface_snapshot.png"].axes[0].get_title()
    with pytest.raises(ValueError, match=r"--realization 0: no saved fields .* with saved fields: 1$"):
        plots.plot_run(run, realization=0)
