"""Running the methods on a scene, timed: the one place where verification calls a solver,
through the one registry `gfmd_contact.app.methods` (the scene's [method] says which runs).

* `run_fe_and_gfmd(scene, order=2)`: `reference.fem` P<order> and GFMD on one scene.
* `run_methods(scene, names)`: the named methods of `METHODS`, each under a `Meter`.
* `run_gfmd(scene, …)`, `run_fe(scene, order)`: one realization that must converge, with its wall time.
* `fe_vs_gfmd(scene)`: `run_fe_and_gfmd` and the differences every FE case reports.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from gfmd_contact.app.methods import run_realization as run_method

from .provenance import Meter


def with_method(scene, name, **options):
    """`scene` solved by method `name` (gfmd_contact.app.methods registry) with [method] `options`."""
    return scene.replace(**{"method.name": name, **{f"method.{k}": v for k, v in options.items()}})


def run_fe_and_gfmd(scene, order=2):
    """(fe, gfmd, fe_s, gfmd_s): `reference.fem` P<order> and GFMD (scene.solver) on one scene, wall times (s)."""
    t0 = time.perf_counter()
    fe = run_method(with_method(scene, "fe", order=order))
    t1 = time.perf_counter()
    gfmd = run_method(with_method(scene, "gfmd"))
    return fe, gfmd, t1 - t0, time.perf_counter() - t1


def _converged(run, label):
    """(run(), wall s); AssertionError naming `label` if a step did not converge."""
    t0 = time.perf_counter()
    result = run()
    wall = time.perf_counter() - t0
    if not result.all_converged:
        raise AssertionError(f"{label}: not converged: {result.messages[:3]}")
    return result, wall


def run_gfmd(scene, settings=None, method_name=None):
    """(Result, wall s) of realization 0 with `gfmd.solver.Settings` (default: the scene's solver);
    raises AssertionError if a step did not converge."""
    from gfmd.loading import run_realization
    kw = {} if method_name is None else {"method_name": method_name}
    return _converged(lambda: run_realization(scene, settings=settings, **kw), method_name or "gfmd")


def run_fe(scene, order=2):
    """(Result, wall s, mesh and assembly included) of `reference.fem` P<order> on realization 0;
    raises AssertionError if a step did not converge."""
    return _converged(lambda: run_method(with_method(scene, "fe", order=order)), f"fe-p{order}")


def _gfmd(integrator, name=None, **pinned):
    """GFMD with solver.method = integrator; `pinned`: `gfmd.solver.Settings` fields that pin the
    integrator itself (cohesive="fire", hard_wall="fire": FIRE, not the CG / NCG that method "fire"
    runs by default on the hard wall and the normal-only cohesive law)."""
    def run(scene, realization=0):
        scene = with_method(scene, "gfmd").replace(**{"solver.method": integrator})
        if not pinned:
            return run_method(scene, realization)
        from gfmd.loading import run_realization
        from gfmd.solver import Settings
        settings = Settings(method=integrator, tolerance=scene.solver.tolerance,
                            max_iterations=scene.solver.max_iterations, **pinned)
        return run_realization(scene, realization, settings=settings, method_name=name)
    return run


#: method name -> callable(scene, realization=0) -> gfmd_contact.core.result.Result
METHODS: dict[str, Callable] = {"gfmd-fire": _gfmd("fire"), "gfmd-verlet": _gfmd("verlet"),
                                "gfmd-fire-only": _gfmd("fire", "gfmd-fire-only", cohesive="fire", hard_wall="fire",
                                                      coupled="fire")}


@dataclass
class MethodRun:
    result: Any  # gfmd_contact.core.result.Result
    wall_s: float
    peak_memory_bytes: int
    memory_method: str


def run_methods(scene, names, realization=0, memory="rss"):
    """Run the methods `names` (keys of METHODS) on `scene`: {name: MethodRun}."""
    runs = {}
    for name in names:
        if name not in METHODS:
            raise KeyError(f"method {name!r} is not in verification.runs.METHODS: {sorted(METHODS)}")
        with Meter(memory) as m:
            result = METHODS[name](scene, realization)
        runs[name] = MethodRun(result, m.wall_s, m.peak_memory_bytes, m.memory_method)
    return runs


def fe_vs_gfmd(scene, order=2, check=True):
    """FE P<order> and GFMD on one scene, and their differences (GFMD the reference):
    dict(rf, rg, fe_s, gfmd_s, fe_step, gfmd_step (mean s/step), tn (t_n rel. L2, max over field steps),
    p (max |Δp| / max |p|), a (max |Δa_rel|), p_reaction, p_consistency (`reaction_differences`)).
    check: assert that both converged."""
    from .metrics import curve_difference, field_difference, max_abs_difference
    rf, rg, fe_s, gfmd_s = run_fe_and_gfmd(scene, order=order)
    if check:
        assert rf.all_converged, f"FE: {rf.messages}"
        assert rg.all_converged, f"GFMD: {rg.messages}"
    out = dict(rf=rf, rg=rg, fe_s=fe_s, gfmd_s=gfmd_s, fe_step=float(np.mean(rf.curve["wall_s"])),
               gfmd_step=float(np.mean(rg.curve["wall_s"])), tn=field_difference(rf, rg, "t_n"),
               p=curve_difference(rf, rg, "p"), a=max_abs_difference(rf, rg))
    out.update(reaction_differences(rf, rg))
    return out


def reaction_differences(rf, rg):
    """{"p_reaction": max_k |p_FE,reaction − p_GFMD| / max_k |p_GFMD|, "p_consistency": max_k |p_FE,reaction −
    p_FE| / max_k |p_GFMD|}: the FE pressure from its own nodal reaction forces (−Σ (S u)_z / L,
    diagnostics["reaction_pressure"]) against GFMD, and against the FE's traction mean p = −⟨t_z⟩.
    NaN if the FE result holds no reaction pressure for every step (a resumed run)."""
    pr = np.asarray(rf.diagnostics.get("reaction_pressure", []), float)
    scale = float(np.max(np.abs(rg.curve["p"])))
    if pr.size != len(rf.curve["p"]):
        return {"p_reaction": float("nan"), "p_consistency": float("nan")}
    return {"p_reaction": float(np.max(np.abs(pr - rg.curve["p"]))) / scale,
            "p_consistency": float(np.max(np.abs(pr - rf.curve["p"]))) / scale}
