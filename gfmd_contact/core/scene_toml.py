"""A scene written back: the plain nested dict and the TOML text of a resolved `gfmd_contact.core.scene.Scene`.

Only the keys that apply are written ([surface]: those of its kind; [interface]: those of its
contact rule; [loading]: the ramp's or the path's; [method]: the method's options), so
`gfmd_contact.core.scene.scene_from_dict` reads the result back to an equal Scene: the round trip of any
scene is exact (φn* is written, the stored state, also for a scene given work_normal).
"""

from __future__ import annotations

import dataclasses

from . import scene2d
from .scene_sections import _SECTIONS
from .scene_validation import _COMMON_KEYS, _KIND_KEYS, _RULE_KEYS, METHOD_KEYS


def scene_to_dict(scene):
    """Plain nested dict of the resolved scene (thickness inf written as "inf").

    [surface] holds only the keys that apply to its kind, [interface] only those of its contact_rule
    (contact_tolerance: "traction-tolerance", contact_gap: "gap"); `scene_from_dict` refuses the others.
    """
    d = {}
    for section in _SECTIONS:
        values = dataclasses.asdict(getattr(scene, section))
        d[section] = values
    kind = scene.surface.kind
    if kind in _KIND_KEYS:
        d["surface"] = {k: v for k, v in d["surface"].items() if k in _COMMON_KEYS + _KIND_KEYS[kind]}
    if not scene.surface.two_d:  # a 1+1-D profile: its TOML as before 2+1-D existed
        for k in scene2d.KEYS_2D:
            d["surface"].pop(k, None)
    d["material"]["thickness"] = "inf" if scene.material.half_plane else scene.material.thickness
    d["method"] = {k: v for k, v in d["method"].items() if k == "name" or k in METHOD_KEYS[scene.method.name]}
    if scene.loading.path:  # a path: the TOML keys path and steps (list); the rest is derived from them
        d["loading"] = {"path": list(scene.loading.path), "steps": list(scene.loading.segment_steps),
                        "control": scene.loading.control,
                        **({"initial_separation": scene.loading.initial_separation}
                           if scene.loading.control == "force" else {})}
    else:  # the seed's ramp: its keys only, as before paths existed
        d["loading"] = {k: d["loading"][k] for k in ("initial_separation", "final_penetration", "steps")}
    rule = scene.interface.contact_rule
    d["interface"] = {k: v for k, v in d["interface"].items()
                      if k == "contact_rule" or not any(k in keys for keys in _RULE_KEYS.values())
                      or k in _RULE_KEYS.get(rule, ())}
    d["interface"].update(d["interface"].pop("parameters"))  # the law's own keys, as keys of [interface]
    return d


def _toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {v!r} to TOML")


def scene_to_toml(scene):
    """TOML text of the fully resolved scene; `load_scene` reads it back to an equal Scene.

    [interface] holds φn* (phi_n_star), the stored state, also for a scene given work_normal.
    """
    d = scene_to_dict(scene)
    lines = [f"# resolved scene {scene.name!r}; SI units (m, Pa, J/m^2)"]
    for section, values in d.items():
        lines.append(f"\n[{section}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in values.items()]
    return "\n".join(lines) + "\n"
