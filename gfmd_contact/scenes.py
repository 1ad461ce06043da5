"""Scenes from Python: load, build, change by dotted key, check, write.

Units: SI throughout (m, Pa, J/m²; `gfmd_contact.core.conventions`). A scene is the frozen,
validated `gfmd_contact.core.scene.Scene`; every function here returns a new one and raises
`SceneError` naming the key, the value and what is allowed.
"""

from __future__ import annotations

import dataclasses
import tomllib
from pathlib import Path

from gfmd_contact.core.scene import (Scene, SceneError, default_scene as _default_scene, example_scene_text, load_scene as
                           _load_scene, scene_from_dict, scene_to_dict, scene_to_toml)

#: `run(method=...)` and `gfmd run --method`: the scene keys each choice sets
METHOD_CHOICES = {"gfmd": {"method.name": "gfmd"}, "fe": {"method.name": "fe"},
                  "fire": {"method.name": "gfmd", "solver.method": "fire"},
                  "verlet": {"method.name": "gfmd", "solver.method": "verlet"}}


def default_scene():
    """The built-in default scene: a small version of the seed's Fig. 3/4 case.

    Self-affine profile (H = 0.8, h_rms = 10 nm, L = 1.28 µm, N = 4096, 4 realizations)
    on an elastic half-plane (E = 70 GPa, ν = 0.45), cohesive law φn* = 0.15, δn = 1 nm,
    δ from −8 nm to 20 nm in 100 steps; what `gfmd run` runs without a scene file.

    Returns
    -------
    gfmd_contact.core.scene.Scene
    """
    return _default_scene()


def example_scene():
    """The seed's production case (N = 2^17, 10 realizations, 200 steps), as `gfmd scene --example` prints it.

    Returns
    -------
    gfmd_contact.core.scene.Scene
        Named "example"; large: reduce surface.nodes and surface.realizations with `change` to try it.
    """
    return scene_from_dict(tomllib.loads(example_scene_text()), name="example")


def load_scene(source, name=None):
    """A validated scene from a TOML file, TOML text, a nested dict or a Scene.

    Parameters
    ----------
    source : str, pathlib.Path, dict or Scene
        A path to a TOML scene file (a relative surface.path is taken relative to the
        file); a string holding TOML (any string with a newline or "=") whose relative
        surface.path is taken relative to the working directory; a dict of sections
        ({"surface": {"nodes": 1024}, ...}; missing keys take the defaults of
        `gfmd_contact.core.scene`); or a Scene (returned re-validated). Values in SI units.
    name : str, optional
        The scene's name (default: the file's stem, "scene" for text and dicts).

    Returns
    -------
    gfmd_contact.core.scene.Scene

    Raises
    ------
    SceneError
        Naming the key, the value and what is allowed (or the file that is missing).
    """
    if isinstance(source, Scene):
        scene = scene_from_dict(scene_to_dict(source), name=source.name)
    elif isinstance(source, dict):
        scene = scene_from_dict(source, name=name or "scene")
    elif isinstance(source, str) and ("\n" in source or "=" in source):
        try:
            d = tomllib.loads(source)
        except tomllib.TOMLDecodeError as exc:
            raise SceneError(f"scene text is not valid TOML: {exc}") from None
        scene = scene_from_dict(d, name=name or "scene")
    elif isinstance(source, (str, Path)):
        if Path(source).is_dir():
            raise SceneError(f"scene {str(source)!r} is a directory, not a TOML scene file "
                             "(a run directory is read with open_run)")
        scene = _load_scene(source)
    else:
        raise SceneError(f"load_scene: cannot read a scene from {type(source).__name__} (give a path, TOML "
                         "text, a dict of sections or a Scene)")
    return dataclasses.replace(scene, name=name) if name else scene


def change(scene, changes=None, /, *, name=None, **sections):
    """A copy of `scene` with keys changed by their dotted names, validated again.

    Parameters
    ----------
    scene : Scene
        The scene to start from (not modified: scenes are frozen).
    changes : dict, optional
        {"section.key": value}, e.g. {"interface.phi_n_star": 0.05, "surface.nodes": 1024}.
        Values in SI units (lengths m, moduli and tractions Pa, work of separation J/m²);
        the keys and their ranges are those of `gfmd scene --example`.
    name : str, optional
        A new name for the scene (default: the old one).
    **sections : dict
        The same by section: ``change(scene, interface={"phi_n_star": 0.05})``.

    Returns
    -------
    gfmd_contact.core.scene.Scene
        As `Scene.replace`: a new surface.kind drops the old kind's own keys, a
        deterministic kind gets one realization.

    Raises
    ------
    SceneError
        For an unknown key or a value out of range, naming the key.

    Examples
    --------
    >>> import gfmd_contact as gc
    >>> s = gc.change(gc.default_scene(), {"surface.nodes": 1024, "interface.law": "hard-wall"})
    >>> s.surface.nodes, s.interface.law
    (1024, 'hard-wall')
    """
    flat = dict(changes or {})
    for section, values in sections.items():
        if not isinstance(values, dict):
            raise SceneError(f"change(): {section}={values!r}: give a section as a dict of its keys, "
                             f"e.g. {section}={{'key': value}}")
        for key, value in values.items():
            flat[f"{section}.{key}"] = value
    for key in flat:
        if not isinstance(key, str) or "." not in key:
            raise SceneError(f"change() takes dotted keys like 'surface.nodes', got {key!r}")
    new = scene.replace(**flat) if flat else load_scene(scene)
    return dataclasses.replace(new, name=name) if name else new


def method_changes(method):
    """The scene keys a method choice sets: "gfmd", "fe", "fire" or "verlet" (GFMD with that solver.method).

    Returns
    -------
    dict
        {"section.key": value}; empty for None (keep the scene's method).
    """
    if method is None:
        return {}
    if method not in METHOD_CHOICES:
        raise SceneError(f"method = {method!r}: choose one of {', '.join(map(repr, METHOD_CHOICES))}")
    return dict(METHOD_CHOICES[method])


def check(scene):
    """Every check `gfmd run` makes before compute (the same as `gfmd scene --check`).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    (list of str, list of str)
        Warnings (resolution, stability: the run goes on unless solver.checks = "error")
        and notes (realizations that stop early at their full-contact limit).

    Raises
    ------
    SceneError
        What the scene's method cannot solve, said before any work.
    """
    from gfmd_contact.core.loading import preflight
    from gfmd_contact.app.methods import method_of

    method_of(scene).refuse(scene)
    return preflight(scene)


def stickiness(scene):
    """The stickiness diagnostics of a scene, before any run (what `gfmd scene --check` prints).

    Process zone l_pz = E* w/σ_max² (m, and in nodes, against its measured limit), Johnson α
    (sinusoid), Maugis λ (cylinder), Tabor-like μ_rough and Persson–Tosatti θ (rough profiles);
    Pastewka–Robbins is not defined for line contacts. Formulas and their 1+1-D forms:
    `gfmd_contact.core.stickiness` and docs/stickiness.rst.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    dict
        {key: {"value": float or None, "unit", "formula", "reading" or "reason"}}: value None
        (n/a) where the quantity is not defined for the scene, with the reason.
    """
    from gfmd_contact.core.stickiness import as_dict

    return as_dict(scene)


def save_scene(scene, path):
    """Write the fully resolved scene as TOML to `path`; returns the Path (`load_scene` reads it back equal)."""
    path = Path(path)
    path.write_text(scene_to_toml(scene))
    return path


def scene_dict(scene):
    """The resolved scene as a nested dict of sections (SI units; thickness "inf" for a half-plane)."""
    return scene_to_dict(scene)


def scene_toml(scene):
    """The resolved scene as TOML text (what a run directory's scene.toml holds)."""
    return scene_to_toml(scene)
