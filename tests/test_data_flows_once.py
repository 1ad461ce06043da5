"""A check and a run build the law and the model choice once per scene, each profile once per realization,
and the stickiness diagnostics once; every later caller gets what was built (`gfmd_contact.core.memo`).

The counts are of the builders themselves (`laws.build_law`, `model.choose_model`, `surfaces.make_profile`,
`stickiness.diagnostics`), seen through sys.setprofile by code object, so no import alias escapes them.
"""

import collections
import gc as garbage
import sys
import weakref

import numpy as np
import pytest

import gfmd_contact as gc
from gfmd_contact.app.study_task import run_task
from gfmd_contact.cli import main
from gfmd_contact.core import laws, memo, model, stickiness, surfaces


def _builds():
    """{code object: (what, key of one computation from the call's arguments)}."""
    return {laws.build_law.__code__: ("law", lambda f: (id(f["scene"]), f["tangential"])),
            model.choose_model.__code__: ("model choice", lambda f: id(f["scene"])),
            surfaces.make_profile.__code__: ("profile", lambda f: (id(f["surface"]), f["realization"])),
            stickiness.diagnostics.__code__: ("stickiness diagnostics", lambda f: id(f["scene"]))}


def count_builds(fn):
    """Run fn(); {(what, key): times built}."""
    watched, counts = _builds(), collections.Counter()

    def seen(frame, event, arg):
        if event == "call" and frame.f_code in watched:
            what, key = watched[frame.f_code]
            counts[what, key(frame.f_locals)] += 1

    sys.setprofile(seen)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return counts


def repeated(counts):
    """What was built more than once for the same scene (law, model choice, diagnostics) or realization (profile)."""
    return {what: n for (what, _), n in counts.items() if n > 1}


def assert_once(counts, needed):
    assert not repeated(counts), (f"built more than once for the same scene or realization: {repeated(counts)} "
                                  "(the law, the model choice and the stickiness diagnostics are built once per scene, "
                                  "each profile once per realization, then handed on)")
    built = {what for what, _ in counts}
    assert needed <= built, f"not built at all, so not counted: {needed - built} (has a builder been renamed?)"


def small():
    return gc.change(gc.default_scene(), {"surface.nodes": 1024, "surface.realizations": 2, "loading.steps": 3})


@pytest.fixture(autouse=True)
def _quiet(recwarn):
    """The small scene's resolution warning is expected here."""


def test_probe_a_second_build_is_caught():
    scene = small()
    counts = count_builds(lambda: [surfaces.make_profile(scene.surface, 0) for _ in range(2)])
    assert repeated(counts) == {"profile": 2}
    with pytest.raises(AssertionError, match="built more than once"):
        assert_once(counts, {"profile"})


def test_check_builds_once():
    scene = small()
    counts = count_builds(lambda: gc.check(scene))
    assert_once(counts, {"law", "model choice", "profile"})
    assert sum(n for (what, _), n in counts.items() if what == "profile") == 2  # one per realization


def test_scene_check_command_builds_once(tmp_path, capsys):
    path = tmp_path / "scene.toml"
    gc.save_scene(small(), path)
    counts = count_builds(lambda: main(["scene", "--check", str(path)]))
    assert_once(counts, {"law", "model choice", "profile", "stickiness diagnostics"})


def test_run_builds_once(tmp_path):
    scene = small()
    counts = count_builds(lambda: gc.run(scene, out=tmp_path / "run", workers=1, progress=False))
    assert_once(counts, {"law", "model choice", "profile", "stickiness diagnostics"})


def test_study_task_builds_once(tmp_path):
    scene = gc.change(small(), {"surface.realizations": 1})
    counts = count_builds(lambda: run_task(scene, tmp_path / "task", progress=lambda *a: None))
    assert_once(counts, {"law", "model choice", "profile", "stickiness diagnostics"})


def test_memo_keeps_no_scene_alive():
    scene = small()
    laws.law_from_scene(scene)
    model.build_model(scene)
    surfaces.profile(scene.surface, 0)
    gone, key = weakref.ref(scene), id(scene)
    del scene
    garbage.collect()
    assert gone() is None and key not in memo._KEPT


def _morse_scene():
    phi, ell = 0.1, 1e-9
    law = gc.user_law(lambda g: phi * ((1 - np.exp(-g / ell)) ** 2 - 1),
                      lambda g: 2 * phi / ell * (1 - np.exp(-g / ell)) * np.exp(-g / ell),
                      lambda g: 2 * phi / ell**2 * (2 * np.exp(-2 * g / ell) - np.exp(-g / ell)), ell, name="morse")
    return gc.with_law(gc.default_scene(), law)


@pytest.mark.parametrize("make", [
    gc.default_scene, lambda: gc.change(gc.default_scene(), {"interface.tangential_ratio": 0.3}),
    lambda: gc.change(gc.default_scene(), {"interface.law": "hard-wall"}),
    lambda: gc.change(gc.default_scene(), {"interface.law": "cohesive-wall"}),
    lambda: gc.change(gc.default_scene(), {"interface.law": "lj93", "interface.work_of_adhesion": 0.05,
                                           "interface.range_length": 1e-9}),
    _morse_scene], ids=["cohesive", "coupled", "hard-wall", "cohesive-wall", "lj93", "user"])
def test_solved_law_is_the_built_one(make):
    """law_from_scene hands on the described law where the solved unknowns agree: it equals a fresh build."""
    scene = make()
    for tangential in (None, False, True):
        try:
            fresh = laws.build_law(scene, tangential)
        except ValueError:  # a normal-only law refuses tangential unknowns
            with pytest.raises(ValueError):
                laws.law_from_scene(scene, tangential)
            continue
        assert laws.law_from_scene(scene, tangential) == fresh


def test_a_changed_scene_gets_its_own_model():
    a = small()
    b = gc.change(a, {"material.youngs_modulus": 2 * a.material.youngs_modulus})
    assert model.build_model(a).law != model.build_model(b).law
    assert model.build_model(a) is model.build_model(a)
