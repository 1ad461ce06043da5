"""Observation-only scene keys: scenes that differ only in them share one solve.

`OBSERVATION_KEYS` enter only a step's contact set (the law's `in_contact`, `gfmd_contact.core.observables`:
a_rel and ḡ_r), never the equilibrium a method solves: in `gfmd_contact.core.laws` the contact rule, its
tolerance and its gap are read by `in_contact` / `contact_gap` alone, and GFMD (`gfmd/`) calls
neither. So a GFMD load ramp of one scene is the ramp of every scene that differs from it only
in these keys (`gfmd_contact.core.ramp.run_ramp`'s `variants`), step for step.

`solve_key(scene)` is the scene with those keys at their defaults, or None where the scene's own
loading or law may read them: force control (the load search and its instability events read a_rel,
`gfmd_contact.core.force`), a user law (its contact set is the user's code). Which *methods* solve without
reading them is each method's declaration (`gfmd_contact.app.methods.MethodSpec.shares_solve`: GFMD yes; the
FE reference computes its own observables inside its cell, with per-step side effects);
`gfmd_contact.app.methods.solve_key` combines the two. Every other key keeps scenes apart, but for the hard wall
`HARD_WALL_OBSERVATION_KEYS`: its equilibrium has no cohesive length, δn (interface.length_normal) enters only
the "gap" rule's threshold contact_gap·δn (`gfmd_contact.core.laws.HardWall`), and GFMD's wall tolerance reads δn only for
a law with a cohesive zone (`gfmd.loading.wall_tolerance_of`). So the seed's sensitivity study (hard wall at δn =
0.25 and 1 nm, three rules each) solves its hard-wall ramps once per realization, not twice.
"""

from __future__ import annotations

import dataclasses

from .scene_sections import Interface

#: the dotted scene keys that enter only the observables of a step (module docstring)
OBSERVATION_KEYS = ("interface.contact_rule", "interface.contact_tolerance", "interface.contact_gap")
#: ... and those that enter only the observables of a hard-wall step (module docstring)
HARD_WALL_OBSERVATION_KEYS = ("interface.length_normal",)


def solve_key(scene):
    """The scene whose solve `scene` runs: its `OBSERVATION_KEYS` (and for a hard wall its
    `HARD_WALL_OBSERVATION_KEYS`) at their defaults; None where its loading or law may read them (module
    docstring), so that the scene shares no solve. The method's part: `gfmd_contact.app.methods.solve_key`."""
    if scene.loading.control != "displacement" or scene.user_law is not None:
        return None
    default = Interface()
    keys = OBSERVATION_KEYS + (HARD_WALL_OBSERVATION_KEYS if scene.interface.law == "hard-wall" else ())
    values = {key.partition(".")[2]: getattr(default, key.partition(".")[2]) for key in keys}
    return dataclasses.replace(scene, interface=dataclasses.replace(scene.interface, **values))
