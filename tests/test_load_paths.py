"""Load paths and cycle observables: scene keys, steps, warm starts, run files."""

import json

import numpy as np
import pytest

import gfmd_contact as gc
from gfmd_contact.core import cycle as cyc
from gfmd_contact.core import loading as L
from gfmd_contact.core.scene import SceneError, default_scene, load_scene, scene_to_toml

NM = 1e-9


def path_scene(path=(-8 * NM, 4 * NM, -8 * NM), steps=(6, 6), **extra):
    d = {"surface.kind": "sinusoid", "surface.amplitude": 5 * NM, "surface.nodes": 128, "surface.length": 1e-6,
         "surface.realizations": 1, "loading.path": list(path), "loading.steps": list(steps),
         "output.field_steps": 2, "output.workers": 1}
    d.update(extra)
    return default_scene().replace(**d)


def test_path_steps_branches_and_round_trip(tmp_path):
    s = path_scene(path=(-8 * NM, 4 * NM, -2 * NM, 6 * NM, -8 * NM), steps=(6, 3, 4, 7))
    lo = s.loading
    assert lo.initial_separation == 8 * NM and lo.final_penetration == 6 * NM and lo.steps == 20
    U = L.displacement_steps(lo)
    assert U.size == 21 and U[0] == 0.0
    corners = np.cumsum([0, 6, 3, 4, 7])
    assert np.allclose(U[corners] - lo.initial_separation, lo.path, atol=1e-20)
    branch, cycle = L.step_branches(lo)
    assert list(branch[1:7]) == ["loading"] * 6 and list(branch[7:10]) == ["unloading"] * 3
    assert list(cycle) == [0] * 10 + [1] * 11
    # no extrapolation from a step across a corner: the first two steps after each corner start from the last state
    allowed = [L.extrapolation_allowed(lo, k) for k in range(21)]
    assert [k for k in range(2, 21) if not allowed[k]] == [7, 8, 10, 11, 14, 15]
    (tmp_path / "s.toml").write_text(scene_to_toml(s))
    assert load_scene(tmp_path / "s.toml").loading == s.loading


def test_ramp_unchanged():
    s = default_scene()
    assert s.loading.path == () and "path" not in scene_to_toml(s)
    assert np.array_equal(L.displacement_steps(s.loading),
                          np.linspace(0, s.loading.initial_separation + s.loading.final_penetration, s.loading.steps + 1))
    assert all(L.extrapolation_allowed(s.loading, k) for k in range(2, s.loading.steps + 1))


@pytest.mark.parametrize("change, key", [
    ({"loading.steps": [6, 0]}, "loading.steps"),
    ({"loading.steps": [6]}, "loading.steps"),
    ({"loading.path": [-8 * NM, float("inf")]}, "loading.path[1]"),
    ({"loading.path": [-8 * NM, float("nan"), 1 * NM]}, "loading.path[1]"),
    ({"loading.path": [2 * NM, 4 * NM]}, "loading.path[0]"),
    ({"loading.path": [-8 * NM, -8 * NM]}, "loading.path[1]"),
    ({"loading.path": [-8 * NM]}, "loading.path"),
    ({"loading.final_penetration": 3 * NM, "loading.path": [-8 * NM, 4 * NM]}, "loading.final_penetration"),
    ({"loading.control": "force"}, "loading.path[0]"),  # a force path starts unloaded at p̄ = 0
    ({"loading.control": "push"}, "loading.control"),
])
def test_bad_path_names_the_key(change, key):
    with pytest.raises(SceneError, match=key.replace("[", r"\[").replace("]", r"\]")):
        path_scene(**change)


def test_cycle_observables_on_a_known_loop():
    # a loop: load at p = 0 from δ = −2 to −1, jump to p = −1 at δ = 0, follow p = −1 + δ/5 up to δ = 1, back
    # down to −1 and jump out to p = 0 on the way to −1.5
    d = np.array([-2, -1, 0, 0.5, 1, 0.5, 0, -0.5, -1, -1.5, -2], float)
    p = np.array([0, 0, -1, -0.9, -0.8, -0.9, -1, -1.1, -1.2, 0, 0], float)
    a = np.array([0, 0, 0.3, 0.35, 0.4, 0.35, 0.3, 0.25, 0.2, 0, 0], float)
    branch = np.array(["loading"] * 5 + ["unloading"] * 6, object)
    rows = cyc.cycle_observables(d, p, a, branch, np.zeros(11, int))
    (r,) = rows
    # trapezoid along the steps: the branch in contact cancels between loading and unloading except on
    # δ ∈ [−1, 0] (unloading only: +1.1) and the two sloped jump segments (−0.5 on loading, +0.3 on unloading)
    assert r["hysteresis"] == pytest.approx(1.1 - 0.5 + 0.3, rel=1e-12) and r["closed"]
    assert r["pull_off_pressure"] == -1.2 and r["pull_off_delta"] == -1
    kinds = [(e["kind"], e["step"]) for e in r["events"]]
    assert kinds == [("jump-in", 2), ("jump-out", 9)]
    assert r["snap_off_delta"] == -1 and r["snap_off_step"] == 9


def test_smooth_curve_has_no_jumps():
    d = np.linspace(0, 1, 41)
    p = np.concatenate([d[:21] ** 1.5, (d[:20] ** 1.5)[::-1]])
    branch = np.array(["loading"] * 21 + ["unloading"] * 20, object)
    assert cyc.jump_events(np.r_[d[:21], d[:20][::-1]], p, np.zeros(41), branch, np.zeros(41, int)) == []


@pytest.fixture(scope="module")
def cycle_run(tmp_path_factory):
    s = path_scene(**{"interface.law": "cohesive"})
    return s, gc.run(s, tmp_path_factory.mktemp("cyc") / "run", progress=False)


def test_path_run_files(cycle_run):
    s, res = cycle_run
    curve, mean = res.curve, res.mean_curve
    assert list(curve.columns[-3:]) == ["branch", "cycle", "event"]
    assert list(curve["branch"]) == ["loading"] * 7 + ["unloading"] * 6
    assert list(mean["branch"]) == list(curve["branch"]) and set(mean["cycle"]) == {0}
    assert np.allclose(curve["delta"].iloc[[0, 6, 12]], s.loading.path, rtol=0, atol=1e-18)
    meta = json.loads((res.dir / "meta.json").read_text())
    (entry,) = meta["cycles"]
    (c,) = entry["cycles"]
    # the file's numbers are those of gfmd_contact.core.cycle on the file's own curve
    ref = cyc.cycle_observables(curve["delta"], curve["p"], curve["a_rel"], curve["branch"], curve["cycle"])[0]
    assert c["hysteresis"] == ref["hysteresis"] and c["pull_off_pressure"] == ref["pull_off_pressure"]
    assert c["pull_off_pressure"] == curve["p"][curve["branch"] == "unloading"].min() < 0
    assert "hysteresis" in meta["cycle_units"] and meta["cycle_definitions"]


def test_study_cycles_table(tmp_path):
    """A study of path scenes writes cycles.csv: pull-off and W per task, equal to each task's meta.json."""
    from gfmd_contact.cli import main

    base = tmp_path / "base.toml"
    base.write_text(scene_to_toml(path_scene(**{"interface.law": "cohesive", "surface.nodes": 64})))
    (tmp_path / "study.toml").write_text('base = "base.toml"\n[axes]\n"interface.phi_n_star" = [0.05, 0.15]\n')
    assert main(["study", "run", str(tmp_path / "study.toml"), "--out", str(tmp_path / "out"), "--workers", "1",
                 "--quiet"]) == 0
    import csv
    with open(tmp_path / "out" / "cycles.csv") as fh:
        table = list(csv.DictReader(fh))
    assert [r["interface.phi_n_star"] for r in table] == ["0.05", "0.15"]
    for r in table:
        meta = json.loads((tmp_path / "out" / "tasks" / r["task"] / "meta.json").read_text())
        c = meta["cycles"][0]["cycles"][0]
        assert float(r["hysteresis"]) == c["hysteresis"] and float(r["pull_off_pressure"]) == c["pull_off_pressure"]
        assert r["snap_off_rule"] == (c["snap_off_rule"] or "")
    # more adhesion, more tensile pull-off
    assert float(table[1]["pull_off_pressure"]) < float(table[0]["pull_off_pressure"]) < 0


def test_cycle_figures(cycle_run):
    from gfmd_contact.app import plots
    from gfmd_contact.app.cycle_plots import CYCLE_FIGURES

    s, res = cycle_run
    figs = plots.make_figures(res.dir)
    assert set(CYCLE_FIGURES) <= set(figs)
    ax = figs["cycle_pressure_vs_delta"].axes[0]
    gids = [a.get_gid() for a in ax.get_children()]
    assert "loading" in gids and "unloading" in gids and "pull-off" in gids
    assert gids.count("direction") == 2  # one arrow per segment of the path
    meta = json.loads((res.dir / "meta.json").read_text())
    events = [e["kind"] for c in meta["cycles"][0]["cycles"] for e in c["events"]]
    assert sorted(g for g in gids if g in ("jump-in", "jump-out")) == sorted(events)
    paths = plots.plot_run(res.dir)
    assert {p.stem for p in paths} >= set(CYCLE_FIGURES)


@pytest.mark.parametrize("method, stop", [("gfmd", 8), ("fe", 3)])
def test_path_run_resumes_past_the_turning_point(tmp_path, monkeypatch, method, stop):
    """Interrupted after an unloading step and resumed: the files equal an uninterrupted run's (GFMD and the FE,
    through the one ramp)."""
    from test_cli_fe import fe_scene
    from test_run_dir import assert_same_run, interrupted_and_resumed

    if method == "fe":
        sc = fe_scene("cohesive", "sinusoid").replace(**{"method.name": "fe", "loading.path": [-2 * NM, 6 * NM, -2 * NM],
                                                         "loading.steps": [3, 3]})
    else:
        sc = path_scene(**{"interface.law": "cohesive"})
    ref, out = interrupted_and_resumed(tmp_path, monkeypatch, sc, (0, stop))
    assert_same_run(ref, out)
    meta = json.loads((ref / "meta.json").read_text())
    assert meta["cycles"][0]["cycles"][0]["closed"] and meta["method"].startswith(method)


# ----------------------------------------------------------------------------- force control (gfmd_contact.core.force)
P_STAR = np.pi * 70e9 / (1 - 0.45**2) * 5 * NM / 1e-6  # Westergaard p* of the 5 nm sinusoid (Pa)


def force_scene(top=0.3, **extra):
    return path_scene(**{"interface.law": "cohesive", "interface.phi_n_star": 0.01, "loading.control": "force",
                         "loading.initial_separation": 8 * NM, "loading.path": [0.0, top * P_STAR, -0.2 * P_STAR],
                         "loading.steps": [4, 8], **extra})


@pytest.fixture(scope="module")
def force_run(tmp_path_factory):
    s = force_scene()
    return s, gc.run(s, tmp_path_factory.mktemp("force") / "run", progress=False)


def test_force_control_follows_the_loads_and_records_the_jumps(force_run):
    from gfmd_contact.core import force

    s, res = force_run
    curve = res.curve
    meta = json.loads((res.dir / "meta.json").read_text())
    (c,) = meta["cycles"][0]["cycles"]
    kinds = [(e["kind"], e["branch"], e["detached"]) for e in c["events"]]
    assert kinds == [("jump-in", "loading", False), ("jump-out", "unloading", True)]  # one each, not per step
    out = c["events"][1]["step"]
    assert bool(curve["converged"].all())
    tol = force.tolerance(s.loading)
    carried = (curve["step"] < out) & (curve["step"] > 0)  # step 0: the start, δ = −δ0 (p̄ ≈ 0, the law's tail)
    assert np.all(np.abs(curve["p"][carried] - curve["load"][carried]) <= tol)  # the load is carried ...
    detached = curve["step"] >= out
    assert np.all(curve["delta"][detached] == -s.loading.initial_separation)  # ... until the body detaches
    assert np.all(curve["load"][detached] < curve["p"][detached])
    assert c["pull_off_load"] == curve["load"][out] and c["pull_off_pressure"] == curve["p"][out - 1]
    assert list(curve["event"].fillna("")) == [""] + ["jump-in"] + [""] * (out - 2) + ["jump-out"] + [""] * (12 - out)
    assert any("detached" in n for n in meta["notes"])


def test_force_path_beyond_full_contact_is_refused_naming_the_key(tmp_path, capsys):
    from gfmd_contact.cli import main

    (tmp_path / "s.toml").write_text(scene_to_toml(force_scene(top=20.0)))
    assert main(["run", str(tmp_path / "s.toml"), "--out", str(tmp_path / "out"), "--quiet", "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert "loading.path" in err and "beyond full contact" in err


@pytest.mark.parametrize("change, key", [
    ({"loading.final_penetration": 1 * NM}, "loading.final_penetration"),
    ({"loading.path": [1e6, 2e6]}, "loading.path[0]"),
    ({"loading.initial_separation": 0.0}, "loading.initial_separation"),
    ({"loading.steps": [4, 0]}, "loading.steps"),
])
def test_bad_force_path_names_the_key(change, key):
    with pytest.raises(SceneError, match=key.replace("[", r"\[").replace("]", r"\]")):
        force_scene(**change)


def test_force_run_resumes_after_the_jump(tmp_path, monkeypatch):
    from test_run_dir import assert_same_run, interrupted_and_resumed

    ref, out = interrupted_and_resumed(tmp_path, monkeypatch, force_scene(), (0, 2))
    assert_same_run(ref, out)


def test_force_cycle_gfmd_and_fe_same_events(tmp_path):
    """GFMD and the FE through the one force-controlled ramp on a cohesive layer: both carry each load,
    jump in and detach at the same steps (their δ agree to 0.2 % here: 3.664 vs 3.671 nm at 100 MPa)."""
    from test_cli_fe import fe_scene

    base = fe_scene("cohesive", "sinusoid").replace(**{
        "loading.control": "force", "loading.path": [0.0, 3e8, -1e8], "loading.steps": [3, 6],
        "loading.initial_separation": 4 * NM})
    runs = {m: gc.run(base.replace(**{"method.name": m}), tmp_path / m, progress=False) for m in ("gfmd", "fe")}
    events = {m: list(r.curve["event"].fillna("")) for m, r in runs.items()}
    assert events["gfmd"] == events["fe"] and events["fe"].count("jump-in") == 1 and events["fe"][-1] == "jump-out"
    assert np.allclose(runs["gfmd"].curve["p"], runs["fe"].curve["p"], rtol=1e-3, atol=1e-4 * 3e8)


def test_snap_off_by_release_where_contact_is_never_lost():
    """No jump-out and a_rel > 0 throughout (a cohesive tail counted in contact): snap-off is the last
    unloading step after the pull-off still carrying ≥ SNAP_OFF_SHARE of it; a jump-out still wins."""
    d = np.array([-1, 0, 1, 0, -1, -2, -3, -4, -5], float)
    p = np.array([0, -0.5, 0.5, -0.8, -1.0, -0.5, -0.02, -0.005, -0.001])
    a = np.full(9, 0.1)
    branch = np.array(["loading"] * 3 + ["unloading"] * 6, object)
    (r,) = cyc.cycle_observables(d, p, a, branch, np.zeros(9, int), events=[])
    assert r["pull_off_pressure"] == -1.0 and r["snap_off_step"] == 7 and r["snap_off_delta"] == -3
    assert r["snap_off_rule"] == "load released"
    # never released within the path: no snap-off
    (r,) = cyc.cycle_observables(d[:7], p[:7], a[:7], branch[:7], np.zeros(7, int), events=[])
    assert r["snap_off_delta"] is None and r["snap_off_rule"] is None


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_snap_off_on_a_rough_cohesive_cycle(tmp_path):
    """A small rough cohesive cycle unloaded to where a_rel (traction-tolerance rule) is still > 0: snap-off
    is found by release, after the pull-off, where the load has fallen below SNAP_OFF_SHARE of it."""
    s = default_scene().replace(**{
        "surface.nodes": 64, "surface.length": 6.4e-7, "surface.rollon_wavelength": 2e-8, "surface.h_rms": 2 * NM,
        "surface.realizations": 1, "interface.law": "cohesive", "loading.path": [-8 * NM, 2 * NM, -9 * NM],
        "loading.steps": [10, 22], "output.field_steps": 2, "output.workers": 1})
    c = gc.run(s, tmp_path / "run", progress=False).curve
    assert (c["a_rel"] > 0).all()
    (r,) = cyc.cycle_observables(c["delta"], c["p"], c["a_rel"], c["branch"], c["cycle"])
    assert r["snap_off_rule"] == "load released", r
    k = r["snap_off_step"]
    assert r["snap_off_delta"] == c["delta"][k - 1] < r["pull_off_delta"]
    assert abs(c["p"][k]) < cyc.SNAP_OFF_SHARE * abs(r["pull_off_pressure"]) <= abs(c["p"][k - 1])
