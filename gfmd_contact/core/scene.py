"""Scenes: what the user describes, as one frozen dataclass read from TOML.

Units: SI (see `gfmd_contact.core.conventions`). `load_scene(path)` reads and validates a TOML
file; `scene_from_dict` does the same for a dict; `scene_to_toml` writes the
fully resolved scene back (`gfmd_contact.core.scene_toml`). A `Scene` holds one dataclass per section
(`gfmd_contact.core.scene_sections`: the defaults); each table is checked by `gfmd_contact.core.scene_validation`
(every error names the key, the value and the allowed range), the whole scene here.
`example_scene_text()` is a fully commented example (`gfmd scene --example`).

2+1-D surfaces: [surface] nodes_y ≥ 2 (0, the default and omitted: a 1+1-D profile) and length_y;
their validation and what a 2+1-D scene refuses live in `gfmd_contact.core.scene2d`.

φ state: [interface] stores φn* (phi_n_star) only; φn = φn* δn E is derived
(`Scene.work_normal`). A scene may give interface.work_normal instead: it is converted
on reading to φn* = φn/(δn E), so the φn derived back equals the given value or
differs from it in the last bits (at most 4 ulp: two roundings each way; measured on
random inputs: 65 % equal, the rest 1–2 ulp). scene_to_toml writes φn*, so the round
trip of any scene is exact.

The names of the three modules above are re-exported here, where other code imports them.
"""

from __future__ import annotations

import dataclasses
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from . import law_registry, scene2d
from .errors import SceneError
from .scene_sections import _SECTIONS, Interface, Loading, Material, Method, Output, Solver, Surface
from .scene_toml import scene_to_dict, scene_to_toml  # noqa: F401
from .scene_validation import (_KIND_KEYS, _RULE_KEYS, MAX_NODES, MAX_REALIZATIONS, MAX_SCALE,  # noqa: F401
                               MAX_STEPS, METHOD_KEYS, MIN_SCALE, _fail, _interface, _loading, _material,
                               _method, _output, _solver, _surface)


@dataclass(frozen=True)
class Scene:
    surface: Surface = field(default_factory=Surface)
    material: Material = field(default_factory=Material)
    interface: Interface = field(default_factory=Interface)
    loading: Loading = field(default_factory=Loading)
    solver: Solver = field(default_factory=Solver)
    output: Output = field(default_factory=Output)
    method: Method = field(default_factory=Method)
    name: str = "scene"
    #: interface.law = "user": the `gfmd_contact.core.user_law.UserLaw` (Python callables; not in the TOML, kept by replace)
    user_law: object = field(default=None, repr=False)

    @property
    def work_normal(self):
        """φn = φn* δn E (J/m²)."""
        i = self.interface
        return i.phi_n_star * i.length_normal * self.material.youngs_modulus

    @property
    def work_tangential(self):
        """φt = c φn* δt E (J/m²), c = φt*/φn*."""
        i = self.interface
        return i.tangential_ratio * i.phi_n_star * i.length_tangential * self.material.youngs_modulus

    def replace(self, **sections):
        """Copy with dotted keys ("section.key") replaced and re-validated.

        Example: scene.replace(**{"surface.nodes": 1024, "interface.law": "hard-wall"}).
        A new surface.kind drops the old kind's own keys (e.g. surface.hurst when a self-affine
        scene becomes a sinusoid; give the new kind's keys, e.g. surface.amplitude, with it), and a
        deterministic kind gets surface.realizations = 1 unless that is given too. A new
        interface.contact_rule likewise drops the old rule's own key (contact_tolerance, contact_gap).
        """
        d = scene_to_dict(self)
        if sections.get("method.name", self.method.name) != self.method.name:  # the old method's options go
            d["method"] = {k: v for k, v in d["method"].items() if f"method.{k}" in sections}
        for key, value in sections.items():
            section, _, name = key.partition(".")
            if not name:
                raise SceneError(f"replace() takes dotted keys like 'surface.nodes', got {key!r}")
            d.setdefault(section, {})[name] = value
        kind = sections.get("surface.kind", self.surface.kind)
        if kind != self.surface.kind and isinstance(d.get("surface"), dict):
            # a new kind: the old kind's own keys go (unless given again, which is then an error naming
            # them), and a deterministic kind gets its single realization unless one is given
            for name in _KIND_KEYS.get(self.surface.kind, ()):
                if f"surface.{name}" not in sections:
                    d["surface"].pop(name, None)
            if (isinstance(kind, str) and kind in _KIND_KEYS and kind != "self-affine"
                    and "surface.realizations" not in sections):
                d["surface"]["realizations"] = 1
        if sections.get("surface.nodes_y", self.surface.nodes_y) == 0 and isinstance(d.get("surface"), dict) \
                and "surface.length_y" not in sections:
            d["surface"].pop("length_y", None)  # back to a profile: Ly goes with Ny
        rule = sections.get("interface.contact_rule", self.interface.contact_rule)
        if rule != self.interface.contact_rule and isinstance(d.get("interface"), dict):
            for name in _RULE_KEYS.get(self.interface.contact_rule, ()):  # the old rule's own keys go
                if f"interface.{name}" not in sections:
                    d["interface"].pop(name, None)
        if "loading.path" in sections and isinstance(d.get("loading"), dict):
            force = sections.get("loading.control", self.loading.control) == "force"
            for name in ("final_penetration",) if force else ("initial_separation", "final_penetration"):
                if f"loading.{name}" not in sections:  # a path replaces the ramp's keys
                    d["loading"].pop(name, None)
        elif any(k in sections for k in ("loading.initial_separation", "loading.final_penetration")) \
                and isinstance(d.get("loading"), dict) and "loading.path" not in sections:
            if self.loading.path:  # back to a ramp: the path's keys go
                d["loading"].pop("path", None)
                d["loading"].pop("control", None)
                if isinstance(d["loading"].get("steps"), list) and "loading.steps" not in sections:
                    d["loading"]["steps"] = self.loading.steps
        if "interface.work_normal" in sections and "interface.phi_n_star" not in sections:
            d["interface"].pop("phi_n_star", None)  # φn given for the stored φn*: rederived from it
        new = scene_from_dict(d, name=self.name)
        # a law not in the file (the user law's callables) goes with interface.law (`law_registry.SceneLaw.in_file`)
        keep = self.user_law is not None and not law_registry.entry(new.interface.law).in_file
        return dataclasses.replace(new, user_law=self.user_law) if keep else new


def scene_from_dict(d, name="scene"):
    """Validated `Scene` from a nested dict (TOML tables); raises SceneError."""
    if not isinstance(d, dict):
        raise SceneError("a scene must be a table of sections")
    for section in d:
        if section not in _SECTIONS:
            raise SceneError(f"unknown section [{section}]; valid sections: {', '.join(_SECTIONS)}")
    material = _material(d.get("material", {}))
    interface = _interface(d.get("interface", {}), material)
    solver = _solver(d.get("solver", {}))
    if solver.unknowns == "coupled" and law_registry.entry(interface.law).normal_only:
        _fail("solver.unknowns", solver.unknowns, f"needs interface.law = \"cohesive\" (got {interface.law!r}, "
              "a normal-only law); use \"auto\"")
    scene = Scene(surface=_surface(d.get("surface", {})), material=material, interface=interface,
                  loading=_loading(d.get("loading", {})), solver=solver, output=_output(d.get("output", {})),
                  method=_method(d.get("method", {})), name=name)
    scene2d.check_scene(scene)  # 2+1-D is normal-only (and what else it refuses)
    return scene


def load_scene(path):
    """Read and validate a TOML scene file; a relative surface.path is taken relative to the file.

    Parameters
    ----------
    path : str or Path
        TOML scene file (`gfmd scene --example` prints a commented one).

    Returns
    -------
    Scene
        Named after the file's stem. Raises SceneError naming the key, the value and
        what is allowed.
    """
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            d = tomllib.load(fh)
    except FileNotFoundError:
        raise SceneError(f"scene file {str(path)!r} not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene file {str(path)!r} is not valid TOML: {exc}") from None
    surface = d.get("surface", {})
    if isinstance(surface, dict) and surface.get("kind") == "file" and isinstance(surface.get("path"), str):
        p = Path(surface["path"])
        if not p.is_absolute():
            surface["path"] = str((path.parent / p).resolve())
    return scene_from_dict(d, name=path.stem)


def default_scene():
    """The built-in default scene (a small version of the seed's Fig. 3/4 case)."""
    text = resources.files("gfmd_contact.core").joinpath("default_scene.toml").read_text()
    return scene_from_dict(tomllib.loads(text), name="default")


def example_scene_text():
    """Fully commented example scene (TOML text)."""
    return resources.files("gfmd_contact.core").joinpath("example_scene.toml").read_text()
