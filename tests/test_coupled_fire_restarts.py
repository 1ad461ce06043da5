"""The coupled law's FIRE restarts (`Settings.coupled_f_dec`, `coupled_n_min`, `gfmd.algorithms.dynamics`).

* the default is the other laws' f_dec and n_min: the best pair of the sweeps of
  benchmarks/bench_coupled_fire_restarts.py (its JSON; every swept pair reached the same states) needs fewer FFT pairs
  on the event steps in every sweep (2^13, 2^15) but more iterations on the fig8_small ramp (2^12);
* the coupled FIRE runs with them, a normal-only law's FIRE with Settings.f_dec and n_min;
* a value out of range is refused, naming the key.
"""

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from gfmd import integrators
from gfmd.loading import run_realization, settings_of
from gfmd.settings import Settings
from tests.test_fire_dt_cap import SAME_BRANCH, _fig8_small, _one_step

SWEEPS = Path(__file__).resolve().parents[1] / "benchmarks" / "results" / "bench_coupled_fire_restarts.json"


def test_milder_restarts_save_on_the_sweeps_but_not_on_fig8_small():
    """Why the default keeps the other laws' f_dec and n_min: the sweeps' best pair saves event FFT pairs on every swept
    ramp (2^13, 2^15), but on fig8_small (2^12, ν = 0.1, seed 2) it makes one event step run FIRE's whole budget."""
    sweeps = json.loads(SWEEPS.read_text())
    assert len(sweeps) >= 4, "sweeps at two sizes and two Poisson ratios"
    default = (Settings().coupled_f_dec, Settings().coupled_n_min)
    assert default == (Settings().f_dec, Settings().n_min)
    ratios = {}
    for key, rows in sweeps.items():
        assert all(r["converged"] == r["steps"] for r in rows), key
        assert all(r["dp_rel"] < SAME_BRANCH and r["da_rel"] == 0 for r in rows), key
        ref, = (r for r in rows if (r["f_dec"], r["n_min"]) == default)
        for r in rows:
            ratios.setdefault((r["f_dec"], r["n_min"]), []).append(r["event_fft_pairs"] / ref["event_fft_pairs"])
    complete = {k: v for k, v in ratios.items() if len(v) == len(sweeps)}
    best = min(complete, key=lambda k: sum(complete[k]))
    assert max(complete[best]) < 1.0
    scene = _fig8_small()
    curves = {pair: run_realization(scene, 0, replace(settings_of(scene), coupled_f_dec=pair[0],
                                                      coupled_n_min=pair[1])).curve for pair in (default, best)}
    assert all(all(c["converged"]) for c in curves.values())
    assert np.sum(curves[best]["iterations"]) > np.sum(curves[default]["iterations"])


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
