"""The coupled law's FIRE restarts (`Settings.coupled_f_dec`, `coupled_n_min`, `gfmd.algorithms.dynamics`).

* the default is the other laws' f_dec and n_min: MILDER, the pair that needed the fewest FFT pairs on the event steps
  of whole ramps at 2^13 and 2^15 (docs/design/performance.md), needs more iterations on the fig8_small ramp (2^12);
* the coupled FIRE runs with them, a normal-only law's FIRE with Settings.f_dec and n_min;
* a value out of range is refused, naming the key.
"""

from dataclasses import replace

import numpy as np
import pytest

from gfmd import integrators
from gfmd.loading import run_realization, settings_of
from gfmd.settings import Settings
from tests.test_fire_dt_cap import _fig8_small, _one_step

#: (f_dec, n_min) of milder restarts: of the pairs swept on whole coupled ramps (2^13 and 2^15, ν = 0.1 and 0.45,
#: seed 2, every pair reaching the same states) the one with the fewest event-step FFT pairs, 7.8–8.9 % fewer than the
#: default
MILDER = (0.8, 1)


def test_milder_restarts_cost_iterations_on_fig8_small():
    """Why the default keeps the other laws' f_dec and n_min: MILDER saves event FFT pairs on the swept ramps, but on
    fig8_small (2^12, ν = 0.1, seed 2) it makes one event step run FIRE's whole budget."""
    default = (Settings().coupled_f_dec, Settings().coupled_n_min)
    assert default == (Settings().f_dec, Settings().n_min)
    scene = _fig8_small()
    curves = {pair: run_realization(scene, 0, replace(settings_of(scene), coupled_f_dec=pair[0],
                                                      coupled_n_min=pair[1])).curve for pair in (default, MILDER)}
    assert all(all(c["converged"]) for c in curves.values())
    assert np.sum(curves[MILDER]["iterations"]) > np.sum(curves[default]["iterations"])


def test_the_coupled_fire_runs_with_them(monkeypatch):
    seen = []
    init = integrators.Fire.__init__

    def record(self, settings):
        seen.append((settings.f_dec, settings.n_min))
        init(self, settings)

    monkeypatch.setattr(integrators.Fire, "__init__", record)
    scene = _fig8_small()
    settings = replace(settings_of(scene), coupled="fire", coupled_f_dec=0.65, coupled_n_min=3)
    assert _one_step(scene, settings).method.startswith("fire")
    assert seen and set(seen) == {(0.65, 3)}
    seen.clear()
    normal = scene.replace(**{"interface.tangential_ratio": 0.0})
    assert _one_step(normal, replace(settings_of(normal), cohesive="fire", coupled_f_dec=0.65)).method == "fire"
    assert set(seen) == {(Settings().f_dec, Settings().n_min)}


@pytest.mark.parametrize("key, value", [("coupled_f_dec", 0.0), ("coupled_f_dec", 1.0), ("coupled_f_dec", float("nan")),
                                        ("coupled_n_min", -1), ("coupled_n_min", 2.5), ("coupled_n_min", True)])
def test_a_value_out_of_range_is_refused(key, value):
    scene = _fig8_small()
    with pytest.raises(ValueError, match=key):
        _one_step(scene, replace(settings_of(scene), coupled="fire", **{key: value}))
