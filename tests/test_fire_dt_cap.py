"""The coupled law's FIRE time-step cap (`gfmd.settings.Settings.coupled_dt_max`, `gfmd.algorithms.dynamics`).

(The default is the cap that needed the fewest FFT pairs on the event steps of whole ramps at 2^13 and 2^15, every
cap reaching the same states: docs/design/performance.md.)

* on the fig8_small ramp (N = 4096, ν = 0.1, c = 0.5, seed 2) the capped FIRE needs fewer iterations than FIRE with
  the other laws' Δt_max, on the same branch at every step;
* FIRE's steps on the coupled law never exceed the cap; the other laws keep Settings.dt_max;
* a cap that is not a positive time step is refused, naming the key.
"""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import indenter_surface, realization_steps
from gfmd_contact.core.scene import load_scene
from gfmd import integrators, solver as gs
from gfmd.loading import prepare, run_realization, settings_of
from gfmd.settings import Settings

ROOT = Path(__file__).resolve().parents[1]
#: another branch at a jump-in step moves p̄ by ≥ 0.75 % of its maximum; the same branch differs by the solver's
#: tolerance (measured on whole ramps with every cap swept: ≤ 6e-8 of max p̄)
SAME_BRANCH = 1e-5


def _fig8_small():
    return load_scene(ROOT / "studies" / "seed" / "fig3_small_base.toml").replace(**{
        "material.poisson_ratio": 0.1, "interface.tangential_ratio": 0.5, "interface.length_tangential": 1e-9,
        "interface.phi_n_star": 0.15, "surface.seed": 2, "surface.realizations": 1})


@pytest.fixture(scope="module")
def ramps():
    """The fig8_small ramp with the default cap and with Settings.dt_max (1.0): {cap: curve}."""
    scene = _fig8_small()
    return {cap: run_realization(scene, 0, replace(settings_of(scene), coupled_dt_max=cap)).curve
            for cap in (Settings().coupled_dt_max, Settings().dt_max)}


def test_capped_fire_needs_fewer_iterations_on_the_same_branch(ramps):
    capped, uncapped = (ramps[c] for c in (Settings().coupled_dt_max, Settings().dt_max))
    assert all(capped["converged"]) and all(uncapped["converged"])
    assert np.sum(capped["iterations"]) < np.sum(uncapped["iterations"])
    p, p_old = np.asarray(capped["p"]), np.asarray(uncapped["p"])
    assert np.max(np.abs(p - p_old)) < SAME_BRANCH * np.max(np.abs(p_old))
    assert np.array_equal(capped["a_rel"], uncapped["a_rel"])


def _one_step(scene, settings, k=40):
    """Relax load step k of `scene` from the undeformed state (a step FIRE runs long enough to reach its largest Δt)."""
    h = surfaces.profile(scene.surface, 0)
    cell = prepare(scene, h, 0)
    steps, _ = realization_steps(scene, h, 0)
    z = indenter_surface(h, scene.loading.initial_separation, steps[k])
    return gs.relax(cell.physics, cell.law, z, cell.initial_state(), settings)


def test_fire_steps_stay_under_the_cap(monkeypatch):
    """FIRE's Δt never exceeds the cap on the coupled law, and reaches it; a normal-only law's FIRE goes past it."""
    seen = []
    adapt = integrators.Fire.adapt

    def record(self, power):
        restart = adapt(self, power)
        seen.append(self.dt)
        return restart

    monkeypatch.setattr(integrators.Fire, "adapt", record)
    cap = 0.35
    scene = _fig8_small()
    r = _one_step(scene, replace(settings_of(scene), coupled_dt_max=cap, coupled="fire"))
    assert r.method.startswith("fire") and seen
    assert max(seen) <= cap and max(seen) > 0.9 * cap
    seen.clear()
    normal = scene.replace(**{"interface.tangential_ratio": 0.0})
    r = _one_step(normal, replace(settings_of(normal), cohesive="fire", coupled_dt_max=cap))
    assert r.method == "fire" and max(seen) > cap


@pytest.mark.parametrize("cap", [0.0, -0.4, float("nan")])
def test_a_cap_that_is_not_a_time_step_is_refused(cap):
    scene = _fig8_small()
    with pytest.raises(ValueError, match="coupled_dt_max"):
        _one_step(scene, replace(settings_of(scene), coupled_dt_max=cap, coupled="fire"))
