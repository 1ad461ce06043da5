"""Which interface laws a scene may name: interface.law → the module that builds the law object.

A law lives in its own module, which declares what the scene needs of it in ``SCENE_LAWS``, a dict
{interface.law: `SceneLaw`}; this registry only maps the name to that module, so a new law is its own
file plus one line in `MODULES`. The scene validation (`gfmd_contact.core.scene_validation`) reads the
names and each law's own [interface] keys from here, and `gfmd_contact.core.laws.law_from_scene` builds
the object through it. Modules are imported on first use: importing the registry imports no law.

The object a builder returns answers the law protocol (`gfmd_contact.core.law_protocol`).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Callable

#: interface.law → the module that declares it (its ``SCENE_LAWS``)
MODULES = {
    "hard-wall": "gfmd_contact.core.laws",
    "cohesive": "gfmd_contact.core.laws",
    "cohesive-wall": "gfmd_contact.core.laws",
    "user": "gfmd_contact.core.user_law",
    "lj93": "gfmd_contact.core.law_lj93",
}


@dataclass(frozen=True)
class LawKey:
    """One [interface] key of a law's own: name, unit (SI) and meaning; a positive finite number."""

    name: str
    unit: str
    meaning: str


@dataclass(frozen=True)
class SceneLaw:
    """What the scene needs of a law.

    build(interface, work_normal, work_tangential, tangential, scene) → the law object; work_normal and
    work_tangential are the scene's φn, φt (NaN where no elastic modulus is at hand, `law_from_interface`),
    tangential as `law_from_scene`'s, scene None where only the Interface is given.
    keys: the law's own [interface] keys (`LawKey`), stored in `Interface.parameters`.
    normal_only: the scene refuses solver.unknowns = "coupled" for it, and interface.tangential_ratio ≠ 0
    unless unused_friction (the hard wall, whose cohesive-zone keys are not used).
    in_file: False where the law cannot be written to scene.toml (the user law's Python callables).
    """

    build: Callable
    keys: tuple = ()
    normal_only: bool = True
    unused_friction: bool = False
    in_file: bool = True


def names():
    """The values interface.law may take."""
    return tuple(MODULES)


def entry(name):
    """The `SceneLaw` of interface.law = name (KeyError for an unknown name)."""
    return importlib.import_module(MODULES[name]).SCENE_LAWS[name]
