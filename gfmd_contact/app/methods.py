"""The one registry of methods: a scene's `method.name` → how one realization is run.

Units: SI (see `gfmd_contact.core.conventions`). Every caller that runs a method (the CLI,
the ensembles, the verification harness, the benchmarks) goes through
`run_realization(scene, realization)`; the scene says which method runs with which
options (`[method]`, gfmd_contact.core.scene.Method), so a run's scene.toml reproduces it.

A `MethodSpec` has
    run(scene, realization, progress=, checkpoint=, resume=)  → gfmd_contact.core.result.Result; a method that
                      `shares_solve` also takes variants= (gfmd_contact.core.ramp.Variant)
    refuse(scene)     raises SceneError if the method cannot solve the scene, saying why
    export(result, directory)   optional: method-specific files of a finished realization
    shares_solve      its solve reads none of `gfmd_contact.core.observation.OBSERVATION_KEYS` (proven by
                      tests/test_observation_variants.py), so scenes differing only in them share it
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from gfmd_contact.core.laws import law_from_scene
from gfmd_contact.core.scene import METHOD_KEYS, SceneError


@dataclass(frozen=True)
class MethodSpec:
    name: str
    run: Callable
    refuse: Callable
    export: Callable | None = None
    shares_solve: bool = False


def _run_gfmd(scene, realization=0, progress=None, checkpoint=None, resume=None, variants=()):
    from gfmd.loading import run_realization

    return run_realization(scene, realization, progress=progress, checkpoint=checkpoint, resume=resume,
                           variants=variants)


def _refuse_nothing(scene):
    return None


def _run_fe(scene, realization=0, progress=None, checkpoint=None, resume=None):
    if scene.surface.two_d:  # the 3-D FE (reference.fem3d) on the same ramp
        from reference.fem3d.ramp import run_realization as run_fe3d

        return run_fe3d(scene, realization, progress=progress, checkpoint=checkpoint, resume=resume)
    from reference.fem import run_realization

    m = scene.method
    return run_realization(scene, realization, order=m.order, linear=m.linear, quadrature=m.quadrature,
                           progress=progress, checkpoint=checkpoint, resume=resume)


def _refuse_fe(scene):
    """What the FE reference cannot mesh or solve, said before any work."""
    if scene.surface.two_d:  # the 3-D FE reference (reference.fem3d): what it cannot model
        from reference.fem3d.ramp import refusal as refusal_3d

        why = refusal_3d(scene)
        if why:
            raise SceneError(f"method.name = \"fe\" (3-D FE, 2+1-D scene): {why}")
        return
    if scene.material.half_plane:
        raise SceneError("method.name = \"fe\": the FE reference models a finite layer only; material.thickness = "
                         "\"inf\" (half-plane) cannot be meshed: give a finite material.thickness (e.g. 2L: the "
                         "fundamental mode then matches the half-plane's compliance to ~1e-9)")
    if scene.surface.nodes % 2:
        raise SceneError(f"method.name = \"fe\": surface.nodes = {scene.surface.nodes}: the FE mesh needs an even "
                         "number of surface nodes")
    from reference.fem.run import refusal
    why = refusal(scene)  # what the FE reference does not model (the cohesive wall)
    if why:
        raise SceneError(f"method.name = \"fe\": {why}")
    if scene.method.quadrature != "nodal" and law_from_scene(scene).constraint:
        raise SceneError(f"method.quadrature = {scene.method.quadrature!r}: the hard wall is a nodal constraint, "
                         "only \"nodal\" applies")


def _export_fe(result, directory):
    """VTU files of the saved steps and the fe.pvd series (reference.fem.export_vtu); [] if none saved."""
    if result.scene.surface.two_d:
        from reference.fem3d.ramp import export_vtu as export_3d

        return export_3d(result, directory)
    from reference.fem import export_vtu

    return export_vtu(result, directory) if result.diagnostics.get("solutions") else []


METHODS = {
    "gfmd": MethodSpec("gfmd", _run_gfmd, _refuse_nothing, shares_solve=True),
    "fe": MethodSpec("fe", _run_fe, _refuse_fe, _export_fe),
}
assert set(METHODS) == set(METHOD_KEYS), "the registry and the scene schema name the same methods"


def method_of(scene):
    """The `MethodSpec` of scene.method.name."""
    return METHODS[scene.method.name]


def solve_key(scene):
    """The scene whose solve `scene` runs (`gfmd_contact.core.observation.solve_key`), or None where it shares no
    solve: its method does not `shares_solve`, or its loading or law reads the observation keys."""
    from gfmd_contact.core import observation

    return observation.solve_key(scene) if method_of(scene).shares_solve else None


def run_realization(scene, realization=0, progress=None, checkpoint=None, resume=None, variants=()):
    """Run one realization of `scene` with the method its [method] section names.

    Parameters
    ----------
    scene : gfmd_contact.core.scene.Scene
        The scene; `scene.method.name` picks the method ("gfmd" or "fe") and its options.
    realization : int
        Realization index i (random profile seed surface.seed + i).
    progress, checkpoint, resume
        The hooks of `gfmd_contact.core.ramp.run_ramp`.
    variants : list of gfmd_contact.core.ramp.Variant
        Scenes of the same `solve_key` sharing this solve (each variant's Result is set on it); only
        for a method that `shares_solve`.

    Returns
    -------
    gfmd_contact.core.result.Result
    """
    if not variants:
        return method_of(scene).run(scene, realization, progress=progress, checkpoint=checkpoint, resume=resume)
    if solve_key(scene) is None or any(solve_key(v.scene) != solve_key(scene) for v in variants):
        raise SceneError(f"method.name = {scene.method.name!r}: these scenes share no solve (gfmd_contact.core.observation)")
    return method_of(scene).run(scene, realization, progress=progress, checkpoint=checkpoint, resume=resume,
                                variants=variants)
