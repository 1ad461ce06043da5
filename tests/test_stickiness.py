"""Stickiness diagnostics (gfmd_contact.core.stickiness, docs/stickiness.rst): each formula against a value worked
out by hand or with plain numpy, Johnson α and Maugis λ against the analytic reference modules, the
n/a rules, the lines of `gfmd scene --check`, meta.json's "stickiness", the study-table columns, and
the process-zone warning on both sides of the measured limit (the core's constant, tied to verification/data/process_zone.json here).
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.core import stickiness as st
from gfmd_contact.core import surfaces
from gfmd_contact.core.model import build_model
from gfmd_contact.core.scene import Scene, scene_to_dict, scene_to_toml
from reference.analytic import jkr_sinusoid, maugis_dugdale
from verification.studies import process_zone as pz_study
from gfmd_contact.app import io
from gfmd_contact.cli import main
from gfmd_contact.app.study import stickiness_columns, study_from_dict
from gfmd_contact.app.study_tables import _stickiness_cells

E, NU = 70e9, 0.45
E_STAR = E / (1 - NU**2)
DATA = Path(__file__).resolve().parent.parent / "verification" / "data" / "process_zone.json"


def scene(kind="self-affine", **extra):
    kw = {"surface.kind": kind, "surface.nodes": 1024, "surface.length": 1e-6, "surface.realizations": 1,
          "material.youngs_modulus": E, "material.poisson_ratio": NU, "interface.law": "cohesive",
          "interface.phi_n_star": 0.05, "interface.length_normal": 1e-9}
    kw.update({"sinusoid": {"surface.amplitude": 10e-9}, "cylinder": {"surface.radius": 2e-6}}.get(kind, {}))
    if kind == "self-affine":
        kw.update({"surface.hurst": 0.8, "surface.h_rms": 5e-9, "surface.rolloff_wavelength": 250e-9,
                   "surface.rollon_wavelength": 1e-6 / 64})
    kw.update(extra)
    return Scene().replace(**kw)


def by_key(sc):
    return {d.key: d for d in st.diagnostics(sc)}


# ----------------------------------------------------------------------------- formulas, known answers
def test_process_zone_by_hand():
    sc = scene()
    phi = 0.05 * 1e-9 * E  # φn = φn* δn E
    sigma = phi / (math.e * 1e-9)
    expected = E_STAR * phi / sigma**2  # = e² E* δn²/φn
    assert expected == pytest.approx(math.e**2 * E_STAR * 1e-18 / phi, rel=1e-14)
    d = by_key(sc)
    assert d["process_zone"].value == pytest.approx(expected, rel=1e-14)
    assert d["process_zone_nodes"].value == pytest.approx(expected / (1e-6 / 1024), rel=1e-14)
    assert st.process_zone_size(2.0, 3.0, 4.0) == 2.0 * 3.0 / 16.0


@pytest.mark.parametrize("w, h0, lam, es", [(0.01, 10e-9, 1e-6, 80e9), (7.0, 3e-9, 2e-7, 1e9), (1e-3, 1e-7, 1e-4, 2e11)])
def test_johnson_alpha_equals_the_reference(w, h0, lam, es):
    assert st.johnson_alpha(w, h0, lam, es) == pytest.approx(float(jkr_sinusoid.johnson_alpha(w, h0, lam, es)),
                                                             rel=1e-14)
    assert st.johnson_alpha(w, h0, lam, es) == pytest.approx(math.sqrt(2 * w * lam / (math.pi**2 * h0**2 * es)),
                                                             rel=1e-14)


def test_johnson_thresholds_equal_the_reference():
    assert st.JOHNSON_ALPHA_CRITICAL == pytest.approx(jkr_sinusoid.critical_alpha(), rel=1e-15)
    assert st.JOHNSON_ALPHA_MAX == pytest.approx(jkr_sinusoid.ALPHA_MAX, rel=1e-15)


def test_scene_alpha_and_lambda_equal_the_reference_modules():
    sin = scene("sinusoid")
    w = sin.work_normal
    assert by_key(sin)["johnson_alpha"].value == pytest.approx(
        float(jkr_sinusoid.johnson_alpha(w, 10e-9, 1e-6, E_STAR)), rel=1e-13)
    cyl = scene("cylinder")
    assert by_key(cyl)["maugis_lambda"].value == pytest.approx(
        float(maugis_dugdale.maugis_parameter_from_cohesive_law(w, 1e-9, 2e-6, E_STAR)), rel=1e-13)


def test_moments_and_full_contact_energy_of_a_sinusoid_by_hand():
    n, length, h0 = 256, 1e-6, 10e-9
    x = np.arange(n) * length / n
    h = -h0 * np.cos(2 * np.pi * x / length)
    q = 2 * np.pi / length
    rms, slope, kappa = st.profile_moments(h, length)
    assert (rms, slope, kappa) == pytest.approx((h0 / math.sqrt(2), h0 * q / math.sqrt(2), h0 * q**2 / math.sqrt(2)),
                                                rel=1e-12)
    energy = st.full_contact_energy(h, length, lambda k: E_STAR * k / 2)
    assert energy == pytest.approx(math.pi * E_STAR * h0**2 / (4 * length), rel=1e-12)  # ½⟨p u⟩ of Westergaard
    w = 0.02
    alpha = float(jkr_sinusoid.johnson_alpha(w, h0, length, E_STAR))
    assert st.persson_tosatti_ratio(energy, w) == pytest.approx(1 / (2 * math.pi * alpha**2), rel=1e-12)


def test_tabor_rough_is_the_cylinder_parameter_at_the_rms_radius():
    assert st.tabor_rough(3e8, 2e7, E_STAR, 0.5) == pytest.approx(st.maugis_lambda(3e8, 5e-8, E_STAR, 0.5), rel=1e-15)
    # and 4/π^(2/3) times Tabor's (R w²/(E*² z0³))^(1/3) with z0 = w/σ
    R, w, s = 5e-8, 0.5, 3e8
    assert st.maugis_lambda(s, R, E_STAR, w) == pytest.approx(
        4 / math.pi ** (2 / 3) * (R * w**2 / (E_STAR**2 * (w / s) ** 3)) ** (1 / 3), rel=1e-13)


def test_rough_scene_uses_the_profile_and_the_models_kernel():
    sc = scene()
    h = surfaces.profile(sc.surface, 0)
    c = np.abs(np.fft.fft(h) / h.size) ** 2
    q = np.abs(2 * np.pi * np.fft.fftfreq(h.size, d=sc.surface.spacing))
    energy = 0.5 * np.sum(E_STAR * q / 2 * c)  # plain numpy, half-plane E*|q|/2
    d = by_key(sc)
    assert d["persson_tosatti"].value == pytest.approx(energy / sc.work_normal, rel=1e-12)
    kappa = math.sqrt(np.sum(q**4 * c))
    sigma = sc.work_normal / (math.e * 1e-9)
    expected = 4 * sigma * (1 / (kappa * math.pi**2 * E_STAR**2 * sc.work_normal)) ** (1 / 3)
    assert d["tabor_rough"].value == pytest.approx(expected, rel=1e-12)
    # the phases do not change it: realization 1 (seed + 1) gives the same θ
    other = sc.replace(**{"surface.seed": 7})
    assert by_key(other)["persson_tosatti"].value == pytest.approx(d["persson_tosatti"].value, rel=1e-10)
    # on a layer the layer's stiffer kernel stores more energy; a thick layer approaches the half-plane
    thin = by_key(sc.replace(**{"material.thickness": 20e-9}))["persson_tosatti"].value
    thick = by_key(sc.replace(**{"material.thickness": 1e-3}))["persson_tosatti"].value
    assert thin > 1.1 * d["persson_tosatti"].value
    assert thick == pytest.approx(d["persson_tosatti"].value, rel=1e-6)


# ----------------------------------------------------------------------------- n/a rules
def test_each_quantity_only_for_its_surfaces():
    rough = by_key(scene())
    assert [k for k, d in rough.items() if d.defined] == ["process_zone", "process_zone_nodes", "tabor_rough",
                                                          "persson_tosatti"]
    assert "sinusoid" in rough["johnson_alpha"].reason and "cylinder" in rough["maugis_lambda"].reason
    assert "line contacts" in rough["pastewka_robbins"].reason
    sin = by_key(scene("sinusoid"))
    assert [k for k, d in sin.items() if d.defined] == ["process_zone", "process_zone_nodes", "johnson_alpha"]
    assert "rough profile" in sin["persson_tosatti"].reason
    cyl = by_key(scene("cylinder"))
    assert [k for k, d in cyl.items() if d.defined] == ["process_zone", "process_zone_nodes", "maugis_lambda"]
    flat = by_key(scene("flat"))
    assert [k for k, d in flat.items() if d.defined] == ["process_zone", "process_zone_nodes"]
    layer = by_key(scene("sinusoid", **{"material.thickness": 1e-6}))
    assert layer["johnson_alpha"].value is None and "half-plane" in layer["johnson_alpha"].reason
    hard = by_key(scene("sinusoid", **{"interface.law": "hard-wall"}))
    assert all(d.value is None and "hard-wall" in d.reason for d in hard.values())
    assert list(hard) == list(st.KEYS)


def test_text_says_na_with_the_reason():
    d = by_key(scene())
    assert d["johnson_alpha"].text().startswith("Johnson α (sinusoid) = n/a: defined for a sinusoid")
    assert d["persson_tosatti"].text().startswith(f"Persson–Tosatti θ = {d['persson_tosatti'].value:.4g} ")


# ----------------------------------------------------------------------------- where they are shown
def test_scene_check_prints_the_diagnostics(tmp_path, capsys):
    sc = scene("sinusoid")
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(sc))
    assert main(["scene", "--check", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    lines = [line for line in out if line.startswith("stickiness: ")]
    assert lines == [f"stickiness: {t}" for t in st.lines(sc)]
    alpha = float(jkr_sinusoid.johnson_alpha(sc.work_normal, 10e-9, 1e-6, E_STAR))
    assert f"stickiness: Johnson α (sinusoid) = {alpha:.4g} " in "\n".join(out)
    assert "stickiness: Maugis λ (cylinder) = n/a: defined for a cylinder" in "\n".join(out)
    assert "stickiness: Pastewka–Robbins = n/a: not defined for line contacts" in "\n".join(out)


def test_meta_json_carries_the_diagnostics(tmp_path):
    sc = scene("cylinder")
    out = io.prepare_run_dir(tmp_path / "run", sc)
    meta = json.loads((out / "meta.json").read_text())
    assert list(meta["stickiness"]) == list(st.KEYS)
    assert meta["stickiness"]["maugis_lambda"]["value"] == pytest.approx(by_key(sc)["maugis_lambda"].value, rel=1e-15)
    assert meta["stickiness"]["johnson_alpha"]["value"] is None
    assert "sinusoid" in meta["stickiness"]["johnson_alpha"]["reason"]


def test_study_table_columns_per_set():
    base = scene_to_dict(scene("sinusoid"))
    study = study_from_dict({"scene": base, "axes": {"interface.law": ["hard-wall", "cohesive"],
                                                     "surface.amplitude": [5e-9, 10e-9]}})
    assert stickiness_columns() == [f"stickiness_{k}" for k in st.KEYS]
    cells = _stickiness_cells(study)
    col = stickiness_columns().index("stickiness_johnson_alpha")
    for s, sc in enumerate(study.scenes):
        alpha = cells[s][col]
        if sc.interface.law == "hard-wall":
            assert alpha == "nan"
        else:
            assert float(alpha) == pytest.approx(
                float(jkr_sinusoid.johnson_alpha(sc.work_normal, sc.surface.amplitude, 1e-6, E_STAR)), rel=1e-13)


# ----------------------------------------------------------------------------- the measured resolution limit
def stored():
    return json.loads(DATA.read_text(encoding="utf-8"))["entries"]["ci"]["values"]


def test_the_stored_limit_is_what_its_study_derives_and_it_is_tight():
    values = stored()
    limit = values["min_process_zone_nodes"]
    assert st.measured_process_zone_limit()[0] == limit and st.PROCESS_ZONE_ERROR == values["error_limit"]
    assert pz_study.limit(values["cases"]) == pytest.approx(limit, rel=1e-3)  # stored to 4 digits
    points = [(r["lpz_nodes"], max(r["p_error"], r["a_rel_error"])) for c in values["cases"] for r in c["rows"]]
    assert all(e <= values["error_limit"] for x, e in points if x >= limit)
    below = max((p for p in points if p[0] < limit), key=lambda p: p[0])
    assert below[1] > values["error_limit"]  # the next sampled ratio below the limit does exceed 1 %


@pytest.mark.parametrize("factor, warned", [(0.99, True), (1.01, False)])
def test_process_zone_warning_below_the_measured_limit_only(factor, warned):
    limit = stored()["min_process_zone_nodes"]
    sc = scene("sinusoid", **{"interface.phi_n_star": 0.05})
    lpz = by_key(sc)["process_zone"].value
    n = 1024
    sc = sc.replace(**{"surface.nodes": n, "surface.length": n * lpz / (factor * limit)})  # l_pz/l = factor·limit
    assert by_key(sc)["process_zone_nodes"].value == pytest.approx(factor * limit, rel=1e-12)
    found = [w for w in build_model(sc).warnings if w.startswith("under-resolved process zone")]
    assert bool(found) is warned
    if warned:
        assert f"< {limit:.3g} l" in found[0] and "verification/studies/process_zone.py" in found[0]


def test_no_process_zone_warning_without_adhesion():
    sc = scene("sinusoid", **{"interface.law": "hard-wall", "surface.nodes": 16})
    assert st.resolution_warnings(sc) == []


def test_study_netcdf_carries_the_per_set_diagnostics():
    from gfmd_contact.app.study import summary_dataset

    study = study_from_dict({"scene": scene_to_dict(scene("cylinder")),
                             "axes": {"surface.radius": [1e-6, 4e-6]},
                             "zip": {"interface.law": ["hard-wall", "cohesive"]}})
    ds = summary_dataset(study, {})  # no task finished yet: the diagnostics are there before any run
    lam = ds["stickiness_maugis_lambda"]
    assert lam.dims == ("surface.radius", "zip") and lam.attrs["units"] == "1"
    assert ds["stickiness_process_zone"].attrs["units"] == "m"
    for s, sc in enumerate(study.scenes):
        value = float(lam.values[study.index[s]])
        if sc.interface.law == "hard-wall":
            assert np.isnan(value)
        else:
            assert value == pytest.approx(float(maugis_dugdale.maugis_parameter_from_cohesive_law(
                sc.work_normal, 1e-9, sc.surface.radius, E_STAR)), rel=1e-13)
