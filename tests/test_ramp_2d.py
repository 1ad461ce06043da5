"""A 2+1-D scene through the one ramp, the run directory and the plots, method-neutral.

GFMD's 2+1-D cell is built elsewhere (gfmd/); here a tiny local method stands in for it: a Winkler bed of
independent springs t_n = k u_z under a hard wall (u_z = min(z_ind, 0), gap = max(z_ind, 0)), whose step
solution is exact and known in closed form. It exercises what every method shares: gfmd_contact.core.ramp on
(Nx, Ny) fields, gfmd_contact.app.io (fields.npz, curve.csv, interrupt and resume), the plots and `gfmd run`.
"""

import csv
import json
from types import SimpleNamespace

import numpy as np
import pytest

import gfmd_contact.app.io
import gfmd_contact.app.methods
from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import field_step_indices, indenter_surface
from gfmd_contact.core.model import build_model
from gfmd_contact.core.ramp import StepSolution, run_ramp
from gfmd_contact.core.result import CURVE_COLUMNS, FIELD_NAMES
from gfmd_contact.core.scene import SceneError, scene_from_dict, scene_to_toml
from gfmd_contact.cli import main

#: Winkler bed stiffness (Pa/m)
K_BED = 1e16


def scene(**surface):
    s = {"kind": "self-affine", "nodes": 16, "nodes_y": 12, "length": 1.6e-7, "length_y": 1.2e-7,
         "rolloff_wavelength": 8e-8, "rollon_wavelength": 2.5e-8, "h_rms": 2e-9, "realizations": 2, **surface}
    return scene_from_dict({"surface": s, "interface": {"law": "hard-wall"},
                            "loading": {"initial_separation": 1e-9, "final_penetration": 3e-9, "steps": 6},
                            "output": {"field_steps": 3, "workers": 1}}, name="winkler2d")


def winkler_cell(sc, h, realization):
    d0 = sc.loading.initial_separation

    def solve(displacement, guess, fallback):
        z = indenter_surface(h, d0, displacement)
        u = np.minimum(z, 0.0)
        gap, t_n = z - u, K_BED * u

        def fields():
            return {"u_z": u, "u_x": np.zeros_like(u), "gap": gap, "t_n": t_n, "t_t": np.zeros_like(u)}

        return StepSolution(state=u.copy(), converged=True, iterations=1, residual=0.0, gap=gap, t_n=t_n,
                            fields=fields)

    return SimpleNamespace(method="winkler", model="Winkler bed, hard wall", reasons=("test stand-in",),
                           physics=build_model(sc, h), extrapolate=True, diagnostics={},
                           initial_state=lambda: np.zeros(h.shape), solve=solve)


def _run(sc, realization=0, progress=None, checkpoint=None, resume=None):
    return run_ramp(sc, realization, winkler_cell, progress=progress, checkpoint=checkpoint, resume=resume)


@pytest.fixture
def winkler(monkeypatch):
    spec = gfmd_contact.app.methods.MethodSpec("gfmd", _run, lambda sc: None)
    monkeypatch.setitem(gfmd_contact.app.methods.METHODS, "gfmd", spec)


def test_build_model_2d():
    sc = scene()
    h = surfaces.profile(sc.surface)
    m = build_model(sc, h)
    assert m.shape == (16, 12) and m.grid == (16, 12) and m.nodes == 192 and m.length_y == 1.2e-7
    assert m.q.shape == m.k_zz.shape == m.spectrum_shape == (16, 7)
    assert not m.tangential and m.k_xx is None and m.k_xz is None
    assert m.node_area == pytest.approx(1.6e-7 * 1.2e-7 / 192, rel=1e-15)
    # K_zz = E*|q|/2 on the half-space (reference-formulas §1.1 with q → |q|), q = 0 clamped
    assert np.allclose(m.k_zz, sc.material.contact_modulus * m.q / 2, rtol=1e-14, atol=0)
    layer = build_model(sc.replace(**{"material.thickness": 1e-7}), h)
    assert layer.k_zz[0, 0] > 0 and layer.shape == (16, 12)


def test_resolution_check_uses_the_coarser_axis():
    """δn = 2 lx resolves x but not y (ly = 4 lx): warned, naming surface.nodes_y; the same scene with Ny
    doubled twice is resolved along both axes."""
    d = {"surface": {"kind": "flat", "nodes": 64, "length": 64e-9, "nodes_y": 16, "length_y": 64e-9},
         "interface": {"law": "cohesive", "length_normal": 2e-9}, "loading": {"initial_separation": 20e-9}}
    coarse = build_model(scene_from_dict(d))
    assert [w.split(":")[0] for w in coarse.warnings] == ["under-resolved δn"]
    assert "surface.nodes_y = 64" in coarse.warnings[0]
    d["surface"]["nodes_y"] = 64
    assert build_model(scene_from_dict(d)).warnings == ()


def test_ramp_carries_2d_fields():
    sc = scene()
    r = _run(sc)
    h = surfaces.profile(sc.surface)
    assert r.h.shape == (16, 12) and r.x.shape == (16,) and r.y.shape == (12,)
    assert np.array_equal(r.y, surfaces.grid(12, 1.2e-7))
    assert sorted(r.fields) == sorted(field_step_indices(sc.loading, 3)) and all(f[n].shape == (16, 12) for f in r.fields.values() for n in FIELD_NAMES)
    # the observables of the closed-form Winkler solution: p = −⟨t_n⟩ = k⟨max(−z, 0)⟩
    z = indenter_surface(h, 1e-9, r.curve["U"][-1])
    assert r.curve["p"][-1] == pytest.approx(K_BED * np.mean(np.maximum(-z, 0)), rel=1e-14)
    assert r.curve["a_rel"][-1] == np.mean(z < 0) > 0
    assert r.curve["a_rel"][0] == 0


def _rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def test_gfmd_run_interrupt_resume_and_plots(tmp_path, monkeypatch, winkler):
    sc = scene()
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(sc))
    ref = tmp_path / "ref"
    assert main(["run", str(path), "--out", str(ref), "--quiet"]) == 0
    header = _rows(ref / "curve.csv")[0].keys()
    assert list(header) == ["realization", "seed", *CURVE_COLUMNS]  # curve.csv unchanged in 2+1-D
    f = np.load(ref / "fields.npz")
    assert f["x"].shape == (16,) and f["y"].shape == (12,) and f["h_r1"].shape == (16, 12)
    assert f["r0_s6_t_n"].shape == (16, 12)
    plots = sorted(p.name for p in (ref / "plots").iterdir())
    assert "contact_map.png" in plots and "pressure_map.png" in plots and "interface_snapshot.png" not in plots

    original = gfmd_contact.app.io.save_step

    def interrupt(out_dir, result, state):
        original(out_dir, result, state)
        if (result.realization, state.step) == (1, 2):
            raise KeyboardInterrupt

    out = tmp_path / "out"
    monkeypatch.setattr(gfmd_contact.app.io, "save_step", interrupt)
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 130
    monkeypatch.setattr(gfmd_contact.app.io, "save_step", original)
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0
    ra, rb = _rows(ref / "curve.csv"), _rows(out / "curve.csv")
    assert [{k: v for k, v in x.items() if k != "wall_s"} for x in ra] == \
           [{k: v for k, v in x.items() if k != "wall_s"} for x in rb]
    fa, fb = np.load(ref / "fields.npz"), np.load(out / "fields.npz")
    assert sorted(fa.files) == sorted(fb.files)
    for k in fa.files:
        np.testing.assert_array_equal(fa[k], fb[k])
    assert json.loads((out / "meta.json").read_text())["resume"]["realizations_reused"] == 1


def test_contact_map_counts_the_curve_contact(tmp_path, winkler):
    from gfmd_contact.app.plots import make_figures

    sc = scene()
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(sc))
    assert main(["run", str(path), "--out", str(tmp_path / "r"), "--quiet", "--no-plot"]) == 0
    figs = make_figures(tmp_path / "r")
    a_rel = float(_rows(tmp_path / "r" / "curve.csv")[6]["a_rel"])
    drawn = figs["contact_map"].axes[0].get_images()[0].get_array()
    assert drawn.shape == (12, 16) and float(np.mean(drawn)) == pytest.approx(a_rel, abs=0)
    import gfmd_contact as gc

    got = gc.open_run(tmp_path / "r").fields(0)
    assert got["y"].shape == (12,) and got["h"].shape == got["t_n"].shape == (16, 12)


def test_scene_check_of_a_2d_scene(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(scene()))
    assert main(["scene", "--check", str(path)]) == 0
    fe = scene_to_toml(scene()).replace('[method]\nname = "gfmd"', '[method]\nname = "fe"')
    path.write_text(fe)  # the 3-D FE on a half-space: refused, naming the key
    assert main(["scene", "--check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "method.name" in err and "2+1-D" in err and "material.thickness" in err
    path.write_text(fe.replace('thickness = "inf"', "thickness = 1e-7"))  # a finite layer: the 3-D FE takes it
    assert main(["scene", "--check", str(path)]) == 0


def test_bad_2d_scene_exits_2(tmp_path, capsys):
    text = scene_to_toml(scene()).replace("nodes_y = 12", "nodes_y = 1")
    path = tmp_path / "s.toml"
    path.write_text(text)
    assert main(["scene", "--check", str(path)]) == 2
    assert "surface.nodes_y" in capsys.readouterr().err
    with pytest.raises(SceneError, match="interface.tangential_ratio"):
        scene().replace(**{"interface.law": "cohesive", "interface.tangential_ratio": 0.2})


def test_force_control_on_a_surface():
    """loading.control = "force" on (Nx, Ny) fields: gfmd_contact.core.force finds U for every load to its tolerance."""
    from gfmd_contact.core.force import tolerance
    from gfmd_contact.core.loading import path_values
    from gfmd_contact.core.scene import scene_to_dict

    d = scene_to_dict(scene())
    d["loading"] = {"control": "force", "path": [0.0, 5e6, 1e6], "steps": [4, 2], "initial_separation": 1e-9}
    sc = scene_from_dict(d)
    r = _run(sc)
    assert r.all_converged and len(r.curve["p"]) == 7
    assert np.max(np.abs(r.curve["p"] - path_values(sc.loading))) <= tolerance(sc.loading)
    assert r.fields[6]["t_n"].shape == (16, 12)


def test_profile_run_files_have_no_2d_keys(tmp_path, winkler):
    """The same stand-in on a 1+1-D profile: Result.y is None and fields.npz holds no y (files unchanged)."""
    d = {"surface": {"kind": "sinusoid", "nodes": 32, "length": 1.6e-7, "amplitude": 2e-9},
         "interface": {"law": "hard-wall"}, "loading": {"initial_separation": 1e-9, "final_penetration": 1e-9,
                                                        "steps": 3}, "output": {"workers": 1}}
    sc = scene_from_dict(d, name="winkler1d")
    r = _run(sc)
    assert r.y is None and r.h.shape == (32,) and r.fields[3]["t_n"].shape == (32,)
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(sc))
    assert "nodes_y" not in path.read_text()
    assert main(["run", str(path), "--out", str(tmp_path / "r"), "--quiet"]) == 0
    f = np.load(tmp_path / "r" / "fields.npz")
    assert "y" not in f.files and f["h_r0"].shape == (32,)
    assert (tmp_path / "r" / "plots" / "interface_snapshot.png").is_file()
