"""Every accepted scene ends the documented way, property-based.

Scenes are drawn over the ranges the scene check accepts (log-uniform lengths, moduli, φn*,
δn; every surface kind and law; 1–12 load steps; small N so that an example is fast) and run
through the CLI entry point (`gfmd_contact.cli.main`, in this process) into a temporary
directory. The only outcomes allowed are the documented ones:

* exit 2, refused before any compute: one line naming a scene key, and nothing written;
* exit 0 or 1 with the complete result files: curve.csv with one row per load step run, no
  sentinel number (every number finite, or NaN where nothing was computed, and then only on a
  step marked not converged), mean_curve.csv, fields.npz with N values per saved field,
  meta.json "complete": true; exit 1 exactly when a step is not converged, each such step
  named in a message ("step k");
* never a traceback (an exception out of `main`).

GFMD on every kind and law; the FE reference (finite layers, 16–64 nodes) on the laws it
models. The ground beyond a ramp has its own draws (GROUND_EXAMPLES each in CI, SLOW_FACTOR × with `--full`):
load paths with several reversals under displacement and force control (loads beyond pull-off and beyond full
contact), 2+1-D grids (odd, tiny, non-square), hostile surface files (refused naming surface.path) and user laws
that raise or return NaN (a `UserLawError` naming the law, or every non-converged step named). CI runs `max_examples` = GFMD_EXAMPLES and FE_EXAMPLES (measured 40 + 12 examples in 37 s on 2 shared cores);
the `slow` variants draw more.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, currently_in_test_context, event, given, settings, strategies as st

from gfmd_contact.core.result import CURVE_COLUMNS, FIELD_NAMES
from gfmd_contact.cli import main

GFMD_EXAMPLES, FE_EXAMPLES = 60, 12
SLOW_FACTOR = 8
KINDS = ("self-affine", "sinusoid", "cylinder", "flat", "file")
#: "section.key" as the scene names its keys (gfmd_contact.core.scene): a refusal must name one
SECTIONS = ("surface", "material", "interface", "loading", "solver", "output", "method")
KEY = re.compile(r"\b(" + "|".join(SECTIONS) + r")\.[a-z_]+")


def log_uniform(lo, hi):
    return st.floats(math.log(lo), math.log(hi)).map(math.exp)


@st.composite
def scenes(draw, method="gfmd"):
    """A scene dict (TOML tables) and, for kind "file", the heights to write next to it."""
    fe = method == "fe"
    kind = draw(st.sampled_from(KINDS))
    nodes = draw(st.sampled_from((16, 32, 64) if fe else (16, 32, 64, 128, 256)))
    length = draw(log_uniform(1e-8, 1e-3))
    spacing = length / nodes
    surface = {"kind": kind, "length": length, "nodes": nodes}
    heights = None
    scale = draw(log_uniform(1e-4, 0.3)) * length  # height scale of the profile (m)
    if kind == "self-affine":
        rollon = draw(st.floats(2.0, 8.0)) * spacing
        surface.update(hurst=draw(st.floats(0.1, 0.95)), h_rms=scale,
                       rolloff_wavelength=draw(st.floats(1.5, 10.0)) * rollon if rollon * 10 < length else length,
                       rollon_wavelength=rollon, seed=draw(st.integers(0, 1000)),
                       realizations=draw(st.integers(1, 2)))
        surface["rolloff_wavelength"] = min(surface["rolloff_wavelength"], length)
    elif kind == "sinusoid":
        surface["amplitude"] = scale
    elif kind == "cylinder":
        surface["radius"] = draw(log_uniform(0.05, 1e3)) * length  # sharp to blunt
    elif kind == "file":
        x = np.arange(nodes) / nodes
        rng = np.random.default_rng(draw(st.integers(0, 1000)))
        heights = scale * (np.cos(2 * np.pi * x) + 0.3 * rng.standard_normal(nodes))
        surface["path"] = "heights.npy"
    ptp = {"self-affine": 6 * scale, "sinusoid": 2 * scale, "flat": 0.0, "file": 3 * scale,
           "cylinder": length**2 / (8 * surface.get("radius", 1.0))}[kind]
    youngs = draw(log_uniform(1e6, 1e12))
    nu = draw(st.floats(-0.5, 0.5))
    thick = draw(log_uniform(0.05, 20.0)) * length if fe or draw(st.booleans()) else "inf"
    if isinstance(thick, float) and nu == 0.5:
        nu = 0.49
    laws = ("hard-wall", "cohesive") if fe else ("hard-wall", "cohesive", "cohesive-wall")
    law = draw(st.sampled_from(laws))
    dn = draw(log_uniform(1e-5, 1e2)) * spacing  # far below the spacing too (δn/l = 0.0024 once crashed)
    interface = {"law": law, "phi_n_star": draw(log_uniform(1e-3, 2.0)), "length_normal": dn}
    if law == "cohesive" and draw(st.booleans()):  # the coupled law
        interface.update(tangential_ratio=draw(log_uniform(0.05, 3.0)),
                         length_tangential=draw(log_uniform(0.1, 10.0)) * dn)
    rule = draw(st.sampled_from(("traction-tolerance", "compressive", "gap")))
    interface["contact_rule"] = rule
    if rule == "traction-tolerance":
        interface["contact_tolerance"] = draw(log_uniform(1e-5, 0.3))
    elif rule == "gap":
        interface["contact_gap"] = draw(log_uniform(0.1, 10.0))
    d0 = draw(log_uniform(0.1, 30.0)) * (dn if law != "hard-wall" else max(ptp, spacing))
    final = draw(st.floats(-0.5, 0.9)) * max(ptp, dn)
    if final <= -d0:
        final = 0.5 * d0
    loading = {"initial_separation": d0, "final_penetration": final, "steps": draw(st.integers(1, 12))}
    solver = {"method": draw(st.sampled_from(("fire", "verlet"))), "max_iterations": draw(st.integers(50, 3000)),
              "tolerance": draw(log_uniform(1e-10, 1e-5))}
    scene = {"surface": surface, "material": {"youngs_modulus": youngs, "poisson_ratio": nu, "thickness": thick},
             "interface": interface, "loading": loading, "solver": solver,
             "output": {"field_steps": draw(st.integers(0, 12)), "workers": 1}}
    if fe:
        scene["method"] = {"name": "fe", "order": draw(st.sampled_from((1, 2)))}
    return scene, heights


def _toml(scene):
    def value(v):
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, bool):
            return "true" if v else "false"
        return repr(v)

    return "\n".join(f"[{section}]\n" + "\n".join(f"{k} = {value(v)}" for k, v in table.items()) + "\n"
                     for section, table in scene.items())


def run_cli(scene, heights, tmp):
    """(exit code, stderr) of `gfmd run scene.toml --out tmp/out` in this process."""
    tmp.mkdir(parents=True)
    (tmp / "scene.toml").write_text(_toml(scene))
    if heights is not None:
        np.save(tmp / "heights.npy", heights)
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(["run", str(tmp / "scene.toml"), "--out", str(tmp / "out"), "--quiet", "--no-plot"])
    return code, err.getvalue()


def assert_documented_end(code, err, out, scene):
    """The documented outcomes (module docstring); `out` is the run directory."""
    assert code in (0, 1, 2), (code, err)
    if currently_in_test_context():  # hypothesis' statistics: how often each outcome came up
        event(f"exit {code}" + (f": {KEY.search(err).group(0)}" if code == 2 and KEY.search(err) else ""))
    if code == 2:
        lines = [ln for ln in err.splitlines() if ln.startswith("gfmd: error:")]
        assert lines, err
        assert KEY.search(lines[0]), f"a refusal must name the scene key: {lines[0]}"
        # the one refusal while running (README, force control): a load the ramp finds beyond full contact
        running = scene["loading"].get("control") == "force" and lines[0].startswith("gfmd: error: loading.path: "
                                                                                     "the load p̄ = ")
        assert running or not out.exists() or not any(out.iterdir()), f"refused after writing: {sorted(out.iterdir())}"
        return
    meta = json.loads((out / "meta.json").read_text())
    assert meta["complete"] is True
    curve = pd.read_csv(out / "curve.csv")
    gfmd = scene.get("method", {}).get("name", "gfmd") == "gfmd"  # GFMD labels each step's algorithm
    path = "path" in scene["loading"]  # a load path adds branch, cycle, event (and force control: load)
    force = scene["loading"].get("control") == "force"
    assert list(curve.columns) == ["realization", "seed", *CURVE_COLUMNS, *(["algorithm"] if gfmd else []),
                                   *(["branch", "cycle", "event"] if path else []), *(["load"] if path and force else [])]
    realizations = scene["surface"].get("realizations", 1)
    assert sorted(curve["realization"].unique()) == list(range(realizations))
    numbers = curve.drop(columns=["realization", "seed", "algorithm", "branch", "event"], errors="ignore").to_numpy(float)
    assert not np.isinf(numbers).any(), "an infinite number in curve.csv"
    assert not (np.abs(numbers) >= 1e300).any(), "a sentinel number (1e300) in curve.csv"
    steps = scene["loading"]["steps"]
    steps = sum(steps) if isinstance(steps, list) else steps  # a load path: steps per segment
    bad = curve["converged"] == 0
    for r, rows in curve.groupby("realization"):
        assert list(rows["step"]) == list(range(len(rows))) and 1 <= len(rows) <= steps + 1
    # NaN where nothing was computed: only on a step marked not converged (g_r is NaN out of contact)
    missing = curve[["p", "a_rel", "residual"]].isna().any(axis=1)
    assert not (missing & ~bad).any(), curve[missing & ~bad]
    assert (curve["p"].isna() == curve["a_rel"].isna()).all(), "p and a_rel: both observed or neither"
    assert (code == 1) == bool(bad.any()), (code, curve[bad])
    for _, row in curve[bad].iterrows():
        assert f"step {int(row['step'])} " in err, f"non-converged step {int(row['step'])} not named:\n{err}"
    fields = np.load(out / "fields.npz")
    n = (scene["surface"]["nodes"],) + ((scene["surface"]["nodes_y"],) if scene["surface"].get("nodes_y") else ())
    for key in fields.files:
        if key[0] == "r" and key.split("_", 2)[-1] in FIELD_NAMES:
            assert fields[key].shape == n, (key, fields[key].shape)
    assert (out / "mean_curve.csv").is_file()


@settings(max_examples=GFMD_EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
@given(drawn=scenes("gfmd"))
def test_every_gfmd_scene_ends_the_documented_way(drawn, tmp_path_factory):
    scene, heights = drawn
    tmp = tmp_path_factory.mktemp("scene")
    code, err = run_cli(scene, heights, tmp / "s")
    assert_documented_end(code, err, tmp / "s" / "out", scene)


@settings(max_examples=FE_EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
@given(drawn=scenes("fe"))
def test_every_fe_scene_ends_the_documented_way(drawn, tmp_path_factory):
    scene, heights = drawn
    tmp = tmp_path_factory.mktemp("scene")
    code, err = run_cli(scene, heights, tmp / "s")
    assert_documented_end(code, err, tmp / "s" / "out", scene)


@pytest.mark.slow
@settings(max_examples=GFMD_EXAMPLES * SLOW_FACTOR, deadline=None, suppress_health_check=list(HealthCheck))
@given(drawn=scenes("gfmd"))
def test_every_gfmd_scene_ends_the_documented_way_many(drawn, tmp_path_factory):
    test_every_gfmd_scene_ends_the_documented_way.hypothesis.inner_test(drawn, tmp_path_factory)


@pytest.mark.slow
@settings(max_examples=FE_EXAMPLES * SLOW_FACTOR, deadline=None, suppress_health_check=list(HealthCheck))
@given(drawn=scenes("fe"))
def test_every_fe_scene_ends_the_documented_way_many(drawn, tmp_path_factory):
    test_every_fe_scene_ends_the_documented_way.hypothesis.inner_test(drawn, tmp_path_factory)


# -- the ground beyond a ramp: load paths, force control, 2+1-D grids, hostile files, user laws ----------------
#: draws per test in CI (each a small run); `--full` runs SLOW_FACTOR × as many
GROUND_EXAMPLES = 6


@st.composite
def path_scenes(draw):
    """Load paths with several reversals under displacement or force control (targets beyond pull-off and
    beyond full contact included), on 1+1-D profiles and on 2+1-D grids (odd, tiny, non-square)."""
    two_d = draw(st.booleans())
    nodes = draw(st.sampled_from((8, 9, 12, 16) if two_d else (16, 33, 64)))
    length = draw(log_uniform(1e-8, 1e-5))
    surface = {"length": length, "nodes": nodes, "realizations": 1}
    if two_d:
        surface.update(nodes_y=draw(st.sampled_from((2, 3, 4, 7, 16))),
                       length_y=draw(log_uniform(0.3, 3.0)) * length)
    kind = draw(st.sampled_from(("sinusoid", "egg-box", "sphere", "flat") if two_d else ("sinusoid", "cylinder", "flat")))
    surface["kind"] = kind
    scale = draw(log_uniform(1e-3, 0.1)) * length
    if kind in ("sinusoid", "egg-box"):
        surface["amplitude"] = scale
    elif kind in ("sphere", "cylinder"):
        surface["radius"] = draw(log_uniform(0.5, 50.0)) * length
    youngs = draw(log_uniform(1e7, 1e11))
    law = draw(st.sampled_from(("hard-wall", "cohesive")))
    dn = draw(log_uniform(0.3, 10.0)) * length / nodes
    force = draw(st.booleans())
    corners = draw(st.integers(3, 5))  # two reversals or more
    if force:  # p̄ corners (Pa): 0, then alternating compressive and tensile loads over decades of E* slope
        p_scale = youngs * scale / length
        path = [0.0] + [(1 if i % 2 == 0 else -1) * draw(log_uniform(1e-4, 3.0)) * p_scale for i in range(corners - 1)]
    else:  # δ corners (m), starting out of contact
        d0 = draw(log_uniform(0.5, 5.0)) * dn
        path = [-d0] + [(1 if i % 2 == 0 else -0.5) * draw(log_uniform(0.1, 3.0)) * max(scale, dn)
                        for i in range(corners - 1)]
    loading = {"path": path, "steps": [draw(st.integers(1, 3)) for _ in range(corners - 1)]}
    if force:
        loading.update(control="force", initial_separation=draw(log_uniform(0.5, 5.0)) * dn)
    scene = {"surface": surface,
             "material": {"youngs_modulus": youngs, "poisson_ratio": draw(st.floats(0.0, 0.49)),
                          "thickness": draw(st.sampled_from(("inf", 2 * length)))},
             "interface": {"law": law, "phi_n_star": draw(log_uniform(1e-3, 0.3)), "length_normal": dn},
             "loading": loading, "solver": {"max_iterations": 3000},
             "output": {"field_steps": draw(st.integers(0, 3)), "workers": 1}}
    return scene, None


@settings(max_examples=GROUND_EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
@given(drawn=path_scenes())
def test_every_path_scene_ends_the_documented_way(drawn, tmp_path_factory):
    scene, heights = drawn
    tmp = tmp_path_factory.mktemp("path")
    code, err = run_cli(scene, heights, tmp / "s")
    assert_documented_end(code, err, tmp / "s" / "out", scene)


@pytest.mark.slow
@settings(max_examples=GROUND_EXAMPLES * SLOW_FACTOR, deadline=None, suppress_health_check=list(HealthCheck))
@given(drawn=path_scenes())
def test_every_path_scene_ends_the_documented_way_many(drawn, tmp_path_factory):
    test_every_path_scene_ends_the_documented_way.hypothesis.inner_test(drawn, tmp_path_factory)


def _hostile(kind, nodes, data, tmp):
    """Write a hostile surface file of `kind` in tmp; returns its name."""
    if kind == "lying header":
        with open(tmp / "h.npy", "wb") as f:
            np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": False,
                                                     "shape": (data.draw(st.integers(nodes + 1, 10**15)),)})
        return "h.npy"
    if kind == "random bytes":
        (tmp / "h.npy").write_bytes(data.draw(st.binary(min_size=0, max_size=256)))
        return "h.npy"
    if kind == "nul text":
        with open(tmp / "h.txt", "wb") as f:
            f.truncate(data.draw(st.integers(1, 2**24)))
        return "h.txt"
    if kind == "junk text":
        (tmp / "h.txt").write_text(data.draw(st.text(max_size=200)))
        return "h.txt"
    (tmp / "h.npy").symlink_to("/dev/zero")
    return "h.npy"


@settings(max_examples=GROUND_EXAMPLES * 2, deadline=None, suppress_health_check=list(HealthCheck))
@given(kind=st.sampled_from(("lying header", "random bytes", "nul text", "junk text", "device")),
       nodes=st.sampled_from((8, 16, 64)), data=st.data())
def test_every_hostile_surface_file_is_refused_naming_surface_path(kind, nodes, data, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("hostile")
    name = _hostile(kind, nodes, data, tmp)
    scene = {"surface": {"kind": "file", "path": name, "nodes": nodes, "length": 1e-7, "realizations": 1},
             "interface": {"law": "hard-wall"}, "loading": {"initial_separation": 1e-9, "final_penetration": 1e-9,
                                                            "steps": 1}, "output": {"workers": 1}}
    (tmp / "s").mkdir()
    (tmp / "s" / "scene.toml").write_text(_toml(scene))
    code, err = run_cli_file(tmp / "s" / "scene.toml", tmp / "s" / "out")
    if currently_in_test_context():
        event(f"{kind}: exit {code}")
    if code == 2:
        assert err.startswith("gfmd: error: surface.path"), err
    else:  # junk text that happens to be `nodes` numbers is a profile
        assert_documented_end(code, err, tmp / "s" / "out", scene)


@pytest.mark.slow
@settings(max_examples=GROUND_EXAMPLES * 2 * SLOW_FACTOR, deadline=None, suppress_health_check=list(HealthCheck))
@given(kind=st.sampled_from(("lying header", "random bytes", "nul text", "junk text", "device")),
       nodes=st.sampled_from((8, 16, 64)), data=st.data())
def test_every_hostile_surface_file_is_refused_naming_surface_path_many(kind, nodes, data, tmp_path_factory):
    test_every_hostile_surface_file_is_refused_naming_surface_path.hypothesis.inner_test(kind, nodes, data,
                                                                                         tmp_path_factory)


@settings(max_examples=GROUND_EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
@given(mode=st.sampled_from(("raise", "nan")), after=st.integers(0, 400), steps=st.integers(1, 4))
def test_every_user_law_that_fails_ends_the_documented_way(mode, after, steps, tmp_path_factory):
    """A user law that raises after `after` calls ends in gc.UserLawError naming the law and the step; one that
    returns NaN ends with its non-converged steps named (or converged where the NaN never mattered)."""
    import warnings

    import gfmd_contact as gc

    dn, phi = 1e-9, 0.05
    calls = [0]

    def broken(f):
        def g(x):
            calls[0] += 1
            if calls[0] > after and armed[0]:
                if mode == "raise":
                    raise ArithmeticError("broken on purpose")
                return np.full(np.shape(x), np.nan)
            return f(x)
        return g

    armed = [False]
    law = gc.user_law(broken(lambda g: -phi * (1 + g / dn) * np.exp(-g / dn)),
                      broken(lambda g: phi / dn * (g / dn) * np.exp(-g / dn)),
                      broken(lambda g: phi / dn**2 * (1 - g / dn) * np.exp(-g / dn)), dn, name="broken")
    armed[0] = True
    scene = gc.change(gc.default_scene(), {"surface.kind": "sinusoid", "surface.amplitude": 2e-9,
                                           "surface.nodes": 32, "surface.length": 1.28e-7, "surface.realizations": 1,
                                           "loading.steps": steps, "output.workers": 1})
    try:
        with warnings.catch_warnings(record=True):
            warnings.simplefilter("always")
            res = gc.run(scene, out=tmp_path_factory.mktemp("law") / "run", law=law, progress=False)
    except gc.UserLawError as exc:
        event(f"{mode}: UserLawError")
        # in a load step: which realization and step; before one (the cell's set-up, the check): the law alone
        assert mode == "raise" and re.match(r"(realization 0\b.*, step \d+ \(U = .*\): )?user law 'broken': "
                                            r"(energy|traction|tangent)\(Δn\) raised ArithmeticError", str(exc)), exc
        return
    event(f"{mode}: {'converged' if res.converged else 'not converged'}")
    for k in res.curve.loc[res.curve["converged"] == 0, "step"]:
        assert any(f"step {k} " in m for m in res.meta["messages"]), (k, res.meta["messages"])


@pytest.mark.slow
@settings(max_examples=GROUND_EXAMPLES * SLOW_FACTOR, deadline=None, suppress_health_check=list(HealthCheck))
@given(mode=st.sampled_from(("raise", "nan")), after=st.integers(0, 400), steps=st.integers(1, 4))
def test_every_user_law_that_fails_ends_the_documented_way_many(mode, after, steps, tmp_path_factory):
    test_every_user_law_that_fails_ends_the_documented_way.hypothesis.inner_test(mode, after, steps, tmp_path_factory)


# -- the reproductions, deterministic ------------------------------------------------------


def _example_scene(tmp, **changes):
    """`gfmd scene --example` at 1,024 nodes (λs,H above the spacing), 1 realization, with `changes`."""
    from gfmd_contact.core.scene import example_scene_text

    text = example_scene_text()
    for old, new in {"nodes = 131072": "nodes = 1024", "rollon_wavelength = 2.5e-9": "rollon_wavelength = 4e-8",
                     "realizations = 10": "realizations = 1", "workers = 0": "workers = 1", **changes}.items():
        assert old in text, old
        text = text.replace(old, new)
    tmp.mkdir(parents=True, exist_ok=True)
    (tmp / "scene.toml").write_text(text)
    return tmp / "scene.toml"


@pytest.mark.parametrize("steps", ["200", "5"])
def test_tiny_length_normal_is_refused_before_compute(tmp_path, steps):
    """δn = 1e-15 m in the example scene at 1,024 nodes ended in `KeyError: 'u_z is not a file
    in the archive'`. Every load step presses past the law's range there: refused, naming the key."""
    path = _example_scene(tmp_path, **{"length_normal = 1e-9": "length_normal = 1e-15",
                                       "steps = 200 ": f"steps = {steps} "})
    for argv in (["scene", "--check", str(path)], ["run", str(path), "--out", str(tmp_path / "out"), "--quiet"]):
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            assert main(argv) == 2
        assert "gfmd: error: loading.steps" in err.getvalue() and "−600 δn" in err.getvalue(), err.getvalue()
    assert not (tmp_path / "out").exists()


def test_gfmd_step_without_state_is_marked_not_a_crash(tmp_path, monkeypatch):
    """A GFMD step whose iterate leaves the law's range (CompressionOverflowError) used to be recorded as
    residual = 1e300, p = -0.0 beside a_rel > 0, with empty field files that the assembly then crashed on.
    Now: exit 1, the step named, NaN observables and residual, N NaN values per saved field."""
    import gfmd.loading
    from gfmd_contact.core.laws import CompressionOverflowError

    relax, calls = gfmd.loading.relax, []

    def overflow_from_step_3(physics, law, z_ind, guess, settings, wall_tolerance, previous=None):
        calls.append(1)
        if len(calls) > 3:  # steps 0-2 relax, every later solve fails
            raise CompressionOverflowError("normal gap Δn = -1e6 δn is beyond the law's range (injected)")
        return relax(physics, law, z_ind, guess, settings, wall_tolerance, previous=previous)

    monkeypatch.setattr(gfmd.loading, "relax", overflow_from_step_3)
    path = _example_scene(tmp_path, **{"steps = 200 ": "steps = 5 ", "field_steps = 5 ": "field_steps = 6 "})
    scene = tomllib_load(path)
    code, err = run_cli_file(path, tmp_path / "out")
    assert_documented_end(code, err, tmp_path / "out", scene)
    curve = pd.read_csv(tmp_path / "out" / "curve.csv")
    lost = curve["converged"] == 0
    assert code == 1 and lost.sum() >= 1 and curve.loc[lost, ["p", "a_rel", "residual"]].isna().all().all()
    fields = np.load(tmp_path / "out" / "fields.npz")
    for k in curve.loc[lost, "step"]:
        assert np.isnan(fields[f"r0_s{k}_u_z"]).all() and fields[f"r0_s{k}_u_z"].shape == (1024,)


def test_fe_diverged_iterate_is_a_non_converged_step(tmp_path, monkeypatch):
    """`[method] name = "fe"` with coupled cohesive laws ended in a traceback
    `reference.fem.law.LawRangeError: normal gap down to -984.4 δn … the iterate diverged`. A diverged
    Newton iterate (here: injected from step 3 on, 1,000 δn deep) is a non-converged step: exit 1."""
    from test_cli_fe import fe_scene

    import reference.fem.solver as fem_solver
    from gfmd_contact.core.scene import scene_to_toml

    solve_step, calls = fem_solver.SurfaceProblem.solve_step, []

    def diverging(self, u0, z_ind, tol, fallback_from=None):
        u, res, it, ok, how = solve_step(self, u0, z_ind, tol, fallback_from=fallback_from)
        calls.append(1)
        if len(calls) > 3:
            return u + 1e3 * self.dn, res, it, False, how
        return u, res, it, ok, how

    monkeypatch.setattr(fem_solver.SurfaceProblem, "solve_step", diverging)
    sc = fe_scene("cohesive", "self-affine").replace(**{"method.name": "fe", "loading.steps": 5,
                                                        "interface.tangential_ratio": 0.5})
    (tmp_path / "scene.toml").write_text(scene_to_toml(sc))
    code, err = run_cli_file(tmp_path / "scene.toml", tmp_path / "out")
    assert_documented_end(code, err, tmp_path / "out", tomllib_load(tmp_path / "scene.toml"))
    curve = pd.read_csv(tmp_path / "out" / "curve.csv")
    assert code == 1 and (curve["converged"] == 0).any() and "outside the law's range" in err


def tomllib_load(path):
    import tomllib

    return tomllib.loads(Path(path).read_text())


def run_cli_file(path, out):
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"])
    return code, err.getvalue()


def test_load_step_refusal_rests_on_the_measurement():
    """The refusal of a load step beyond the law's range (gfmd_contact.core.loading.check_step_in_law_range) refuses no
    scene that was measured to run (verification/data/length_normal_limit.json), and the measurement holds
    cells on both sides of it."""
    from gfmd_contact.core.errors import SceneError
    from gfmd_contact.core.laws import MAX_COMPRESSION
    from gfmd_contact.core.loading import preflight
    from gfmd_contact.core.scene import scene_from_dict
    from verification import measured

    cells = measured.load("length_normal_limit")["entries"]
    refused = []
    for key, cell in cells.items():
        v = cell["values"]
        scene = dict(cell["scene"])
        try:
            preflight(scene_from_dict(scene))
        except SceneError as exc:
            assert "loading.steps" in str(exc)
            refused.append(key)
            assert v["steps_converged"] < v["steps_run"], f"{key}: refused, yet measured to converge at every step"
    assert refused and len(refused) < len(cells)
    assert any(v["values"]["steps_converged"] == v["values"]["steps_run"]
               and v["values"]["step_over_delta_n"] > 0.5 * MAX_COMPRESSION for v in cells.values()), "no measured cell near the limit converged: the limit would be untested"
