"""Tests of gfmd_contact.core.scene: TOML scenes, validation messages, round trip, Scene.replace."""

import dataclasses
import math
import tempfile
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from gfmd_contact.core.scene import (Interface, Material, Scene, SceneError, Surface, default_scene, example_scene_text,
                        load_scene, scene_from_dict, scene_to_dict, scene_to_toml)
from gfmd_contact.core.topography_keys import FILE_KEYS


def _round_trip(scene, directory):
    path = Path(directory) / f"{scene.name}.toml"  # load_scene names the scene after the file
    path.write_text(scene_to_toml(scene))
    return load_scene(path)


# ---------------------------------------------------------------- defaults, examples, round trip

def test_default_scene_is_valid_and_round_trips(tmp_path):
    scene = default_scene()
    assert isinstance(scene, Scene) and scene.name == "default"
    assert scene.surface.kind == "self-affine" and scene.material.half_plane
    # the work of separation is derived: φn = φn* δn E (the interface stores φn* only)
    i = scene.interface
    assert scene.work_normal == i.phi_n_star * i.length_normal * scene.material.youngs_modulus
    assert not hasattr(i, "work_normal")
    assert _round_trip(scene, tmp_path) == scene


def test_example_scene_loads(tmp_path):
    path = Path(resources.files("gfmd_contact.core").joinpath("example_scene.toml"))
    scene = load_scene(path)
    assert scene.name == "example_scene"
    assert scene.surface.kind == "self-affine" and scene.surface.nodes >= 8
    assert example_scene_text() == path.read_text()
    assert _round_trip(scene, tmp_path) == scene


def test_dataclass_defaults_are_a_valid_scene(tmp_path):
    scene = scene_from_dict({})
    assert scene.surface == Surface() and scene.material == Material()
    assert scene.interface == Interface() and scene.work_normal == 0.15 * 1e-9 * 70e9
    assert _round_trip(scene, tmp_path) == scene


positive = st.floats(1e-3, 1e3)


@st.composite
def scene_dicts(draw):
    kind = draw(st.sampled_from(["self-affine", "sinusoid", "cylinder", "flat"]))
    nodes = draw(st.integers(8, 2**17))
    length = draw(st.floats(1e-8, 1e-2))
    surface = {"kind": kind, "nodes": nodes, "length": length, "seed": draw(st.integers(0, 2**31))}
    if kind == "self-affine":
        spacing = length / nodes
        lsh = spacing * draw(st.floats(1.001, 4.0))
        lr = min(length, lsh * draw(st.floats(1.001, 1e3)))
        surface.update(hurst=draw(st.floats(0.01, 0.99)), h_rms=length * draw(st.floats(1e-6, 1e-1)),
                       rolloff_wavelength=lr, rollon_wavelength=lsh, realizations=draw(st.integers(1, 50)))
    elif kind == "sinusoid":
        surface["amplitude"] = length * draw(st.floats(1e-6, 1.0))
    elif kind == "cylinder":
        surface["radius"] = length * draw(positive)
    nu = draw(st.floats(-0.999, 0.5))
    material = {"youngs_modulus": draw(st.floats(1e3, 1e12)), "poisson_ratio": nu}
    if nu < 0.5 and draw(st.booleans()):
        material["thickness"] = length * draw(positive)
    dn = draw(st.floats(1e-12, 1e-6))
    interface = {"law": draw(st.sampled_from(["hard-wall", "cohesive"])), "length_normal": dn,
                 "tangential_ratio": draw(st.floats(0.0, 2.0)), "length_tangential": draw(st.floats(1e-12, 1e-6)),
                 "contact_tolerance": draw(st.floats(1e-9, 0.36))}
    if draw(st.booleans()):
        interface["work_normal"] = draw(st.floats(1e-6, 1e3))  # φn* is then derived: w/(δn E)
    else:
        interface["phi_n_star"] = draw(st.floats(1e-6, 1.0))
    d0 = draw(st.floats(0.0, 1e-6))
    loading = {"initial_separation": d0, "final_penetration": -d0 + draw(st.floats(0.01, 100.0)) * (d0 + 1e-9),
               "steps": draw(st.integers(1, 10**4))}
    solver = {"method": draw(st.sampled_from(["fire", "verlet"])), "tolerance": draw(st.floats(1e-15, 0.5)),
              "max_iterations": draw(st.integers(1, 10**7))}
    output = {"field_steps": draw(st.integers(0, 100)), "workers": draw(st.integers(0, 64))}
    return {"surface": surface, "material": material, "interface": interface, "loading": loading,
            "solver": solver, "output": output}


@settings(max_examples=80, derandomize=True, deadline=None)
@given(scene_dicts())
def test_round_trip_is_exact(d):
    # scene_to_toml → load_scene must reproduce the scene bit for bit (repr of floats is exact);
    # this includes scenes given by work_normal, stored (and written) as φn* = w/(δn E)
    scene = scene_from_dict(d, name="rt")
    with tempfile.TemporaryDirectory() as directory:
        back = _round_trip(scene, directory)
    assert back == scene
    if "work_normal" in d["interface"]:
        w = d["interface"]["work_normal"]
        e = scene.material.youngs_modulus
        assert scene.interface.phi_n_star == w / (scene.interface.length_normal * e)
        # φn derived back from φn* is w up to the roundings of w/(δn E) and φn* δn E: |Δ| ≤ 4 ε w
        # (gfmd_contact.core.scene docstring; the bound is the rounding analysis, not a fit)
        assert abs(scene.work_normal - w) <= 4 * 2**-53 * w * (1 + 1e-12)
    else:
        assert scene.interface.phi_n_star == d["interface"]["phi_n_star"]


def test_round_trip_of_a_file_profile(tmp_path):
    heights = tmp_path / "heights.npy"
    np.save(heights, np.linspace(0, 1e-9, 16))
    (tmp_path / "s.toml").write_text('[surface]\nkind = "file"\nnodes = 16\nlength = 1e-6\npath = "heights.npy"\n')
    scene = load_scene(tmp_path / "s.toml")
    assert scene.surface.path == str(heights.resolve())  # relative to the scene file
    assert scene.surface.realizations == 1
    (tmp_path / "rt").mkdir()
    assert _round_trip(scene, tmp_path / "rt") == scene  # now an absolute path


def test_thickness_spellings():
    for spelling in ("inf", "Infinite", "half-plane", " INF "):
        assert scene_from_dict({"material": {"thickness": spelling}}).material.half_plane
    assert scene_from_dict({"material": {"thickness": math.inf}}).material.half_plane  # TOML's inf
    layer = scene_from_dict({"material": {"thickness": 2e-6, "poisson_ratio": 0.3}}).material
    assert layer.thickness == 2e-6 and not layer.half_plane
    assert layer.contact_modulus == pytest.approx(70e9 / (1 - 0.09), rel=1e-15)


def test_loads_toml_inf_and_integers_as_floats(tmp_path):
    path = tmp_path / "x.toml"
    path.write_text("[material]\nthickness = inf\nyoungs_modulus = 70_000_000_000\n"
                    "[surface]\nnodes = 4096.0\nkind = \"flat\"\n")
    scene = load_scene(path)
    assert scene.material.half_plane and scene.material.youngs_modulus == 70e9
    assert scene.surface.nodes == 4096 and isinstance(scene.surface.nodes, int)


# ---------------------------------------------------------------- bad input → SceneError naming key and value

def _forms(value):
    forms = {repr(value)}
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        forms |= {repr(float(value)), f"{value:g}", repr(int(value)) if math.isfinite(value) else "nan"}
    return forms


def _expect(d, key, value):
    with pytest.raises(SceneError) as info:
        scene_from_dict(d)
    message = str(info.value)
    assert key in message, message
    if value is not None:
        assert any(form in message for form in _forms(value)), message
    return message


SA = {"kind": "self-affine"}

BAD = [
    # (dict, key named in the message, value named in the message)
    ({"material": {"youngs_modulus": 0}}, "material.youngs_modulus", 0),
    ({"material": {"youngs_modulus": -70e9}}, "material.youngs_modulus", -70e9),
    ({"material": {"youngs_modulus": math.inf}}, "material.youngs_modulus", math.inf),
    ({"material": {"poisson_ratio": -1.0}}, "material.poisson_ratio", -1.0),
    ({"material": {"poisson_ratio": -1.5}}, "material.poisson_ratio", -1.5),
    ({"material": {"poisson_ratio": 0.5000001}}, "material.poisson_ratio", 0.5000001),
    ({"material": {"poisson_ratio": 0.7}}, "material.poisson_ratio", 0.7),
    ({"material": {"poisson_ratio": 0.5, "thickness": 1e-6}}, "material.poisson_ratio", 0.5),
    ({"material": {"poisson_ratio": 0.5, "thickness": 1e-6}}, "material.thickness", 1e-6),
    ({"material": {"thickness": 0.0}}, "material.thickness", 0.0),
    ({"material": {"thickness": -1e-6}}, "material.thickness", -1e-6),
    ({"material": {"thickness": "deep"}}, "material.thickness", "deep"),
    ({"interface": {"length_normal": 0.0}}, "interface.length_normal", 0.0),
    ({"interface": {"length_normal": -1e-9}}, "interface.length_normal", -1e-9),
    ({"interface": {"length_tangential": 0}}, "interface.length_tangential", 0),
    ({"interface": {"phi_n_star": 0.0}}, "interface.phi_n_star", 0.0),
    ({"interface": {"work_normal": -1.0}}, "interface.work_normal", -1.0),
    ({"interface": {"phi_n_star": 0.1, "work_normal": 1.0}}, "interface.phi_n_star", 0.1),
    ({"interface": {"phi_n_star": 0.1, "work_normal": 1.0}}, "interface.work_normal", 1.0),
    ({"interface": {"contact_tolerance": 0.0}}, "interface.contact_tolerance", 0.0),
    ({"interface": {"contact_tolerance": -1e-3}}, "interface.contact_tolerance", -1e-3),
    ({"interface": {"contact_tolerance": math.exp(-1)}}, "interface.contact_tolerance", math.exp(-1)),
    ({"interface": {"contact_tolerance": 0.5}}, "interface.contact_tolerance", 0.5),
    ({"interface": {"tangential_ratio": -0.5}}, "interface.tangential_ratio", -0.5),
    ({"interface": {"law": "sticky"}}, "interface.law", "sticky"),
    ({"surface": {**SA, "nodes": 7}}, "surface.nodes", 7),
    ({"surface": {**SA, "nodes": 0}}, "surface.nodes", 0),
    ({"surface": {**SA, "nodes": -8}}, "surface.nodes", -8),
    ({"surface": {**SA, "nodes": 100.5}}, "surface.nodes", 100.5),
    ({"surface": {**SA, "nodes": math.inf}}, "surface.nodes", math.inf),
    ({"surface": {**SA, "nodes": math.nan}}, "surface.nodes", math.nan),
    ({"surface": {"kind": "fractal"}}, "surface.kind", "fractal"),
    ({"surface": {**SA, "hurst": 1.0}}, "surface.hurst", 1.0),
    ({"surface": {**SA, "hurst": 0.0}}, "surface.hurst", 0.0),
    ({"surface": {**SA, "h_rms": 0.0}}, "surface.h_rms", 0.0),
    ({"surface": {**SA, "length": -1.0}}, "surface.length", -1.0),
    ({"surface": {**SA, "seed": -1}}, "surface.seed", -1),
    ({"surface": {**SA, "realizations": 0}}, "surface.realizations", 0),
    # wavelengths out of order: need L ≥ λr > λs,H > L/N (default L = 10.24e-6, N = 131072)
    ({"surface": {**SA, "rolloff_wavelength": 2e-5}}, "surface.rolloff_wavelength", 2e-5),
    ({"surface": {**SA, "rollon_wavelength": 1.28e-6}}, "surface.rollon_wavelength", 1.28e-6),
    ({"surface": {**SA, "rollon_wavelength": 2e-6}}, "surface.rollon_wavelength", 2e-6),
    ({"surface": {**SA, "rollon_wavelength": 10.24e-6 / 131072}}, "surface.rollon_wavelength", 10.24e-6 / 131072),
    ({"surface": {**SA, "nodes": 8, "length": 1e-6, "rolloff_wavelength": 1e-6, "rollon_wavelength": 1e-7}},
     "surface.rollon_wavelength", 1e-7),
    # deterministic kinds
    ({"surface": {"kind": "sinusoid", "amplitude": 1e-9, "realizations": 2}}, "surface.realizations", 2),
    ({"surface": {"kind": "flat", "realizations": 10}}, "surface.realizations", 10),
    ({"surface": {"kind": "sinusoid"}}, "surface.amplitude", 0.0),
    ({"surface": {"kind": "cylinder", "radius": -1.0}}, "surface.radius", -1.0),
    ({"surface": {"kind": "file"}}, "surface.path", ""),
    ({"surface": {"kind": "file", "path": "/nonexistent/heights.npy"}}, "surface.path", "/nonexistent/heights.npy"),
    # non-numeric and bool values
    ({"surface": {**SA, "length": "1e-6"}}, "surface.length", "1e-6"),
    ({"surface": {**SA, "nodes": "many"}}, "surface.nodes", "many"),
    ({"material": {"poisson_ratio": [0.3]}}, "material.poisson_ratio", [0.3]),
    ({"surface": {**SA, "nodes": True}}, "surface.nodes", True),
    ({"material": {"youngs_modulus": True}}, "material.youngs_modulus", True),
    ({"interface": {"phi_n_star": False}}, "interface.phi_n_star", False),
    ({"material": {"youngs_modulus": math.nan}}, "material.youngs_modulus", math.nan),
    # loading, solver, output
    ({"loading": {"initial_separation": -1e-9}}, "loading.initial_separation", -1e-9),
    ({"loading": {"initial_separation": 1e-9, "final_penetration": -1e-9}}, "loading.final_penetration", -1e-9),
    ({"loading": {"steps": 0}}, "loading.steps", 0),
    ({"solver": {"method": "cg"}}, "solver.method", "cg"),
    ({"solver": {"tolerance": 0.0}}, "solver.tolerance", 0.0),
    ({"solver": {"tolerance": 1.0}}, "solver.tolerance", 1.0),
    ({"solver": {"max_iterations": 0}}, "solver.max_iterations", 0),
    ({"output": {"field_steps": -1}}, "output.field_steps", -1),
    ({"output": {"workers": -2}}, "output.workers", -2),
    ({"output": 5}, "output", 5),
]


@pytest.mark.parametrize("d, key, value", BAD, ids=[f"{k}={v!r}" for _, k, v in BAD])
def test_bad_input_names_key_and_value(d, key, value):
    _expect(d, key, value)


def test_unknown_key_lists_valid_keys():
    message = _expect({"surface": {"nodez": 1024}}, "nodez", None)
    for valid in ("kind", "length", "nodes", "hurst", "h_rms", "rolloff_wavelength", "rollon_wavelength"):
        assert valid in message
    message = _expect({"interface": {"phi_n": 0.1}}, "phi_n", None)
    assert "phi_n_star" in message and "work_normal" in message


def test_unknown_section_lists_sections():
    message = _expect({"surfaces": {}}, "surfaces", None)
    for valid in ("surface", "material", "interface", "loading", "solver", "output"):
        assert valid in message
    with pytest.raises(SceneError):
        scene_from_dict([("surface", {})])


@pytest.mark.parametrize("count", [15, 17])
def test_file_profile_with_wrong_length(tmp_path, count):
    np.save(tmp_path / "h.npy", np.zeros(count))
    path = tmp_path / "s.toml"
    path.write_text('[surface]\nkind = "file"\nnodes = 16\nlength = 1e-6\npath = "h.npy"\n')
    with pytest.raises(SceneError) as info:
        load_scene(path)
    message = str(info.value)
    assert "surface.path" in message and "h.npy" in message
    assert f"{count} heights" in message and "surface.nodes = 16" in message


def test_load_scene_file_errors(tmp_path):
    with pytest.raises(SceneError, match="not found"):
        load_scene(tmp_path / "absent.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[surface\nnodes = 8\n")
    with pytest.raises(SceneError, match="not valid TOML"):
        load_scene(bad)


# ---------------------------------------------------------------- Scene.replace

def test_replace_with_dotted_keys():
    base = default_scene()
    new = base.replace(**{"surface.nodes": 1024, "interface.law": "hard-wall", "solver.method": "verlet"})
    assert new.surface.nodes == 1024 and new.interface.law == "hard-wall" and new.solver.method == "verlet"
    assert base.surface.nodes != 1024  # frozen original untouched
    assert new.name == base.name
    # everything not named is unchanged
    assert dataclasses.replace(new.surface, nodes=base.surface.nodes) == base.surface
    assert new.material == base.material and new.loading == base.loading and new.output == base.output
    assert new.replace(**{"surface.nodes": base.surface.nodes, "interface.law": base.interface.law,
                          "solver.method": base.solver.method}) == base


def test_replace_rederives_work_of_separation():
    base = default_scene()
    e, dn = base.material.youngs_modulus, base.interface.length_normal
    # φn* is primary: changing E or δn changes φn = φn* δn E
    stiffer = base.replace(**{"material.youngs_modulus": 2 * e})
    assert stiffer.interface.phi_n_star == base.interface.phi_n_star
    assert stiffer.work_normal == base.interface.phi_n_star * dn * (2 * e)
    # giving φn instead rederives φn* = φn/(δn E)
    by_work = base.replace(**{"interface.work_normal": 1.0})
    assert by_work.work_normal == 1.0
    assert by_work.interface.phi_n_star == 1.0 / (dn * e)
    by_phi = by_work.replace(**{"interface.phi_n_star": 0.01})
    assert by_phi.interface.phi_n_star == 0.01 and by_phi.work_normal == 0.01 * dn * e
    # φt = c φn* δt E
    c = base.replace(**{"interface.tangential_ratio": 0.5})
    assert c.work_tangential == 0.5 * c.interface.phi_n_star * c.interface.length_tangential * e


def test_one_phi_state_work_normal_is_an_input_key_only(tmp_path):
    # φn* is the stored state: a scene given φn = 0.7 J/m² (δn = 1 nm, E = 70 GPa) stores
    # φn* = 0.7/70 and writes it back; φn* δn E is then 0.7 + 1 ulp: the documented last-bit change
    scene = scene_from_dict({"interface": {"work_normal": 0.7}})
    assert scene.interface.phi_n_star == 0.7 / (1e-9 * 70e9)
    assert scene.work_normal == math.nextafter(0.7, 1.0)
    text = scene_to_toml(scene)
    assert "work_normal" not in text and f"phi_n_star = {scene.interface.phi_n_star!r}" in text
    assert "work_normal" not in scene_to_dict(scene)["interface"]
    assert _round_trip(scene, tmp_path) == scene
    # φn* stays primary: a new E rederives φn, as for a scene given φn*
    stiffer = scene.replace(**{"material.youngs_modulus": 140e9})
    assert stiffer.interface.phi_n_star == scene.interface.phi_n_star
    assert stiffer.work_normal == scene.interface.phi_n_star * 1e-9 * 140e9
    # replace() takes either key, never both (as a scene file)
    assert scene.replace(**{"interface.work_normal": 1.4}).interface.phi_n_star == 1.4 / (1e-9 * 70e9)
    with pytest.raises(SceneError, match="either"):
        scene.replace(**{"interface.work_normal": 1.4, "interface.phi_n_star": 0.02})
    # a φn whose φn* would leave [1e-30, 1e30] is refused, naming the key given (its φn* could not be read back)
    with pytest.raises(SceneError, match="interface.work_normal"):
        scene_from_dict({"interface": {"work_normal": 1e25, "length_normal": 1e-12},
                         "material": {"youngs_modulus": 1e3}})


def test_replace_rejects_bad_keys_and_values():
    base = default_scene()
    with pytest.raises(SceneError, match="dotted"):
        base.replace(nodes=1024)
    with pytest.raises(SceneError, match="nodez"):
        base.replace(**{"surface.nodez": 1024})
    with pytest.raises(SceneError, match="unknown section"):
        base.replace(**{"surfaces.nodes": 1024})
    with pytest.raises(SceneError, match="surface.nodes"):
        base.replace(**{"surface.nodes": 4})
    with pytest.raises(SceneError, match="surface.realizations"):
        base.replace(**{"surface.kind": "flat", "surface.realizations": 4})  # given explicitly: refused
    flat = base.replace(**{"surface.kind": "flat"})  # a deterministic kind gets realizations = 1
    assert flat.surface.kind == "flat" and flat.surface.realizations == 1


def test_scene_to_dict_and_properties():
    scene = scene_from_dict({"material": {"thickness": 3e-6, "poisson_ratio": 0.25},
                             "surface": {"kind": "flat", "nodes": 64, "length": 1e-6}})
    d = scene_to_dict(scene)
    assert set(d) == {"surface", "material", "interface", "loading", "solver", "output", "method"}
    assert d["material"]["thickness"] == 3e-6
    assert scene_to_dict(default_scene())["material"]["thickness"] == "inf"
    assert scene.surface.spacing == 1e-6 / 64
    assert scene.interface.law == "cohesive" and scene.replace(**{"interface.law": "hard-wall"}).interface.law == "hard-wall"


# ---------------------------------------------------------------- keys that belong to another surface kind

COMMON = {"kind", "length", "nodes", "seed", "realizations", "boundary"}
OWN = {"self-affine": {"hurst", "h_rms", "rolloff_wavelength", "rollon_wavelength"}, "sinusoid": {"amplitude"},
       "cylinder": {"radius"}, "flat": set(), "file": set(FILE_KEYS)}
SIN = {"kind": "sinusoid", "amplitude": 5e-9}
CYL = {"kind": "cylinder", "radius": 1e-6}
FLAT = {"kind": "flat"}
FILE = "<heights.npy>"  # replaced by a real 64-node profile file in the test

FOREIGN = [
    # (surface table, foreign key, its value): each used to be ignored silently
    ({**SIN, "hurst": 0.5}, "hurst", 0.5),
    ({**SIN, "radius": 1e-6}, "radius", 1e-6),
    ({**SIN, "h_rms": 1e-9}, "h_rms", 1e-9),
    ({**SIN, "path": "h.npy"}, "path", "h.npy"),
    ({**SA, "amplitude": 5e-9}, "amplitude", 5e-9),
    ({**SA, "radius": 1e-6}, "radius", 1e-6),
    ({**SA, "path": "h.npy"}, "path", "h.npy"),
    ({**CYL, "rolloff_wavelength": 1e-7}, "rolloff_wavelength", 1e-7),
    ({**CYL, "amplitude": 5e-9}, "amplitude", 5e-9),
    ({**FLAT, "hurst": 0.8}, "hurst", 0.8),
    ({**FLAT, "amplitude": 1e-9}, "amplitude", 1e-9),
    ({**FLAT, "path": "h.npy"}, "path", "h.npy"),
    ({"kind": "file", "path": FILE, "nodes": 64, "amplitude": 5e-9}, "amplitude", 5e-9),
    ({"kind": "file", "path": FILE, "nodes": 64, "rollon_wavelength": 1e-9}, "rollon_wavelength", 1e-9),
]


@pytest.mark.parametrize("surface, key, value", FOREIGN, ids=[f"{s['kind']}+{k}" for s, k, _ in FOREIGN])
def test_key_of_another_kind_is_an_error(tmp_path, surface, key, value):
    if surface.get("path") == FILE:
        np.save(tmp_path / "h.npy", np.zeros(64))
        surface = {**surface, "path": str(tmp_path / "h.npy")}
    message = _expect({"surface": surface}, f"surface.{key}", value)
    kind = surface["kind"]
    assert f"surface.kind = {kind!r}" in message, message
    for allowed in COMMON | OWN[kind]:  # what is allowed is listed
        assert allowed in message, message


@pytest.mark.parametrize("kind, extra", [("self-affine", {}), ("sinusoid", {"amplitude": 5e-9}),
                                         ("cylinder", {"radius": 1e-6}), ("flat", {}), ("file", None)])
def test_scene_to_dict_writes_only_the_keys_of_the_kind(tmp_path, kind, extra):
    if extra is None:
        np.save(tmp_path / "h.npy", np.linspace(0, 1e-9, 64))
        extra = {"path": str(tmp_path / "h.npy")}
    surface = {"kind": kind, "nodes": 64, "length": 1e-6, **extra}
    if kind == "self-affine":
        surface.update(rolloff_wavelength=5e-7, rollon_wavelength=1e-7, realizations=3)
    scene = scene_from_dict({"surface": surface})
    assert set(scene_to_dict(scene)["surface"]) == COMMON | OWN[kind]
    (tmp_path / "rt").mkdir()
    assert _round_trip(scene, tmp_path / "rt") == scene


def test_replace_changes_the_kind(tmp_path):
    base = default_scene()  # self-affine, 4 realizations
    sin = base.replace(**{"surface.kind": "sinusoid", "surface.amplitude": 5e-9})
    assert sin.surface.kind == "sinusoid" and sin.surface.amplitude == 5e-9
    assert sin.surface.realizations == 1  # deterministic: one realization
    assert (sin.surface.length, sin.surface.nodes, sin.surface.seed) == (
        base.surface.length, base.surface.nodes, base.surface.seed)  # the common keys are kept
    assert sin.material == base.material and sin.interface == base.interface and sin.loading == base.loading
    assert _round_trip(sin, tmp_path) == sin
    # sinusoid → cylinder → flat → self-affine: each step drops the old kind's own key
    cyl = sin.replace(**{"surface.kind": "cylinder", "surface.radius": 1e-6})
    assert cyl.surface.kind == "cylinder" and cyl.surface.radius == 1e-6 and cyl.surface.amplitude == 0.0
    flat = cyl.replace(**{"surface.kind": "flat"})
    assert flat.surface == Surface(kind="flat", length=base.surface.length, nodes=base.surface.nodes,
                                   seed=base.surface.seed, realizations=1)
    back = flat.replace(**{"surface.kind": "self-affine", "surface.realizations": 4,
                           **{f"surface.{k}": getattr(base.surface, k) for k in OWN["self-affine"]}})
    assert back == base
    # the new kind's keys are needed (sinusoid: amplitude), and a key of another kind stays an error
    with pytest.raises(SceneError, match="surface.amplitude"):
        base.replace(**{"surface.kind": "sinusoid"})
    with pytest.raises(SceneError, match="surface.hurst"):
        base.replace(**{"surface.kind": "sinusoid", "surface.amplitude": 5e-9, "surface.hurst": 0.5})
    with pytest.raises(SceneError, match="surface.amplitude"):
        base.replace(**{"surface.amplitude": 5e-9})  # no kind change: amplitude does not apply
    # the same kind given again changes nothing
    assert base.replace(**{"surface.kind": "self-affine"}) == base


# ---------------------------------------------------------------- profile files through the scene

def _bad_profile(directory, what):
    """A profile file that is not one column of 256 heights; returns its path."""
    if what == "2-D npy":
        np.save(directory / "h.npy", np.zeros((16, 16)))  # 256 values, but a 16×16 map
        return directory / "h.npy"
    if what == "corrupt npy":
        (directory / "h.npy").write_bytes(b"\x93NUMPY\x01\x00garbage")
        return directory / "h.npy"
    if what == "comma-separated":
        (directory / "h.csv").write_text(",".join(["1e-9"] * 256) + "\n")
        return directory / "h.csv"
    if what == "empty text":
        (directory / "h.txt").write_text("")
        return directory / "h.txt"
    if what == "two columns":
        np.savetxt(directory / "h.txt", np.zeros((128, 2)))  # x, h pairs: 256 numbers
        return directory / "h.txt"
    raise AssertionError(what)


BAD_PROFILE_WORDS = {  # what each message says is wrong, and the key that would fix it where one does
    "2-D npy": ["shape (16, 16)", "surface.nodes", "surface.resample"], "corrupt npy": ["not a valid .npy file"],
    "comma-separated": ["not one column of heights", "SurfaceTopography cannot read"], "empty text": ["empty"],
    "two columns": ["states no unit", "surface.height_unit"]}  # x–z columns: an instrument export without a unit


@pytest.mark.parametrize("what", ["2-D npy", "corrupt npy", "comma-separated", "empty text", "two columns"])
def test_bad_profile_file_names_surface_path(tmp_path, what):
    path = _bad_profile(tmp_path, what)
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(f'[surface]\nkind = "file"\nnodes = 256\nlength = 1e-6\npath = "{path.name}"\n')
    with pytest.raises(SceneError) as info:
        load_scene(scene_file)
    message = str(info.value)
    assert "surface.path" in message and path.name in message, message
    for word in BAD_PROFILE_WORDS[what]:
        assert word in message, message


# ---------------------------------------------------------------- absurd sizes and magnitudes

HUGE = [
    # (dict, key, value): each gave a traceback (MemoryError, ZeroDivisionError, OverflowError), a NaN
    # pressure or a denormal answer on the old code, or an integer TOML cannot hold
    ({"surface": {**SA, "nodes": 2**40}}, "surface.nodes", 2**40),
    ({"surface": {**SA, "nodes": 1e300}}, "surface.nodes", None),
    ({"surface": {**SA, "nodes": 2**24 + 1}}, "surface.nodes", 2**24 + 1),
    ({"surface": {**SA, "realizations": 10**9}}, "surface.realizations", 10**9),
    ({"surface": {**SA, "seed": 2**70}}, "surface.seed", 2**70),
    ({"loading": {"steps": 10**12}}, "loading.steps", 10**12),
    ({"output": {"field_steps": 10**9}}, "output.field_steps", 10**9),
    ({"solver": {"max_iterations": 2**70}}, "solver.max_iterations", 2**70),
    ({"material": {"youngs_modulus": 1e-320}}, "material.youngs_modulus", 1e-320),
    ({"material": {"youngs_modulus": 1e31}}, "material.youngs_modulus", 1e31),
    ({"material": {"thickness": 1e-320}}, "material.thickness", 1e-320),
    ({"interface": {"length_normal": 1e-320}}, "interface.length_normal", 1e-320),
    ({"interface": {"work_normal": 1e-320}}, "interface.work_normal", 1e-320),
    ({"interface": {"phi_n_star": 1e308}}, "interface.phi_n_star", 1e308),
    ({"surface": {**SIN, "amplitude": 1e300}}, "surface.amplitude", 1e300),
    ({"surface": {**CYL, "radius": 1e-300}}, "surface.radius", 1e-300),
    ({"surface": {**SA, "h_rms": 1e-300}}, "surface.h_rms", 1e-300),
    ({"surface": {**FLAT, "length": 1e-300}}, "surface.length", 1e-300),
]


@pytest.mark.parametrize("d, key, value", HUGE, ids=[f"{k}={v!r}" for _, k, v in HUGE])
def test_absurd_sizes_and_magnitudes_are_refused(d, key, value):
    message = _expect(d, key, value)
    assert "must" in message  # says what is allowed


def test_largest_allowed_values_are_valid():
    scene = scene_from_dict({"surface": {**FLAT, "nodes": 2**24, "length": 1e-3, "seed": 2**63 - 1},
                             "loading": {"steps": 10**6}, "output": {"field_steps": 10**6}})
    assert scene.surface.nodes == 2**24 and scene.loading.steps == 10**6


# ---------------------------------------------------------------- the shipped scenes run cleanly

def _shipped(name):
    if name == "default":
        return default_scene()
    return load_scene(Path(resources.files("gfmd_contact.core").joinpath("example_scene.toml")))


@pytest.mark.parametrize("name", ["default", "example"])
def test_shipped_scenes_start_stable_and_stay_below_full_contact(name):
    from gfmd_contact.core import surfaces
    from gfmd_contact.core.model import build_model, jump_in_separation, softest_normal_stiffness

    scene = _shipped(name)
    h0 = surfaces.profile(scene.surface, 0)
    model = build_model(scene, h0)
    assert model.warnings == ()  # neither under-resolved δn nor a start inside the jump-in separation
    gap = jump_in_separation(softest_normal_stiffness(model), scene.work_normal, scene.interface.length_normal)
    assert scene.loading.initial_separation >= 1.2 * gap  # with a margin, as the comments say
    for i in range(scene.surface.realizations):
        h = surfaces.profile(scene.surface, i)
        assert scene.loading.final_penetration < 0.85 * (np.mean(h) - np.min(h)), i  # full contact: mean − min
