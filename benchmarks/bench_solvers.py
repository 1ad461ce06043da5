"""One load step of each production solver, the FFT floor and Tamaas on the same load.

The scene is the seed study's (studies/seed/seed_base.toml: L = 10.24 µm, H = 0.8, h_rms = 10 nm, ν = 0.45, the
200-step ramp to δ = 20 nm, realization 0) at N = 2^e, its short cut-off raised to 4 node spacings where the grid is
coarser than the seed's. A case relaxes, untimed, a few steps of the ramp up to step STEP (near the ramp's end, the
deepest contact: a_rel in the table's note), then the timed call relaxes STEP from the ramp's warm start (the
extrapolation 2u_k − u_{k−1}, `previous` the last state), as a study task does, with the scene's solver settings
(the default chain of each law): the hard wall's dual CG, the cohesive law's NCG, the coupled law's chain.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest

from gfmd.loading import prepare, wall_tolerance_of
from gfmd.solver import relax
from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import indenter_surface, realization_steps
from gfmd_contact.core.scene import load_scene

SEED_BASE = Path(__file__).resolve().parents[1] / "studies" / "seed" / "seed_base.toml"
#: the timed step, as a fraction of the ramp; the untimed approach relaxes APPROACH steps before it
STEP, APPROACH = 0.99, 6
#: the laws (scene keys): Fig. 3's hard wall and strong adhesion (φn* = 0.15), Fig. 8's coupled law (c = 0.5)
LAWS = {
    "hard wall": {"interface.law": "hard-wall"},
    "cohesive": {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.0},
    "coupled": {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.5,
                "interface.length_tangential": 1e-9},
}


def seed_scene(nodes, law, nodes_y=0):
    """The seed base scene with `nodes` (× `nodes_y` on a 2+1-D surface) and the law's keys."""
    base = load_scene(SEED_BASE)
    rollon = max(base.surface.rollon_wavelength, 4 * base.surface.length / nodes)
    keys = {"surface.nodes": nodes, "surface.rollon_wavelength": rollon, **LAWS[law]}
    if nodes_y:
        keys.update({"surface.nodes_y": nodes_y, "surface.length_y": base.surface.length})
    return base.replace(**keys)


class StepCase:
    """One load step of a scene, ready to relax: the cell, the indenter, the warm start and the last state."""

    def __init__(self, scene):
        self.scene = scene
        self.h = surfaces.profile(scene.surface, 0)
        self.cell = prepare(scene, self.h)
        self.wall_tolerance = wall_tolerance_of(scene, self.h)
        steps, _ = realization_steps(scene, self.h, 0)
        k = int(STEP * len(steps))
        state = self.cell.initial_state()
        for j in np.linspace(0, k - 2, APPROACH).round().astype(int):
            state = self._converged(steps[j], state)
        previous = state
        current = self._converged(steps[k - 1], previous)
        self.z, self.z_previous = self._z(steps[k]), self._z(steps[k - 1])
        self.guess, self.previous = 2 * current - previous, current

    def _z(self, displacement):
        return indenter_surface(self.h, self.scene.loading.initial_separation, displacement)

    def _converged(self, displacement, guess):
        r = relax(self.cell.physics, self.cell.law, self._z(displacement), guess, self.cell.settings,
                  self.wall_tolerance)
        if not r.converged:
            raise RuntimeError(f"approach step did not converge ({r.method}): {r.message}")
        return r.u_hat

    def args(self):
        """The timed call's arguments, fresh arrays each round."""
        return (self.cell.physics, self.cell.law, self.z, self.guess.copy(), self.cell.settings,
                self.wall_tolerance), {"previous": self.previous.copy()}


@cache
def step_case(law, nodes, nodes_y=0):
    return StepCase(seed_scene(nodes, law, nodes_y))


def _time_step(benchmark, sizes, table, case, name, label, pair_s):
    result = benchmark.pedantic(relax, setup=case.args, rounds=sizes["rounds"], iterations=1, warmup_rounds=1)
    assert result.converged, f"{name} at {label}: {result.message}"
    a_rel = float(np.mean(result.gap <= case.wall_tolerance)) if name.startswith("hard") else \
        float(np.mean(result.t_z < 0))
    table.add(benchmark, name, label, pairs=float(result.fft_pairs), pair_s=pair_s,
              note=f"{result.method}, {result.iterations} it, a_rel {a_rel:.3f}")


def test_fft_pair(benchmark, sizes, table, exponent):
    """The floor every step is measured against: one rfft + irfft pair of N nodes (the default FFT backend)."""
    from gfmd.fft import Fft

    n = 2**exponent
    fft = Fft(n)
    x = fft.empty_nodes()
    x[:] = np.random.default_rng(0).standard_normal(n)
    benchmark.pedantic(lambda: fft.irfft(fft.rfft(x)), rounds=max(50, int(4e6 // n)), iterations=1, warmup_rounds=3)
    table.add(benchmark, "FFT pair", f"2^{exponent}", pairs=1.0, pair_s=table.pair(f"2^{exponent}", n),
              note=f"backend {fft.backend}")


@pytest.mark.parametrize("law", list(LAWS))
def test_load_step(benchmark, sizes, table, exponent, law):
    """One load step of the law at N = 2^exponent."""
    n = 2**exponent
    label = f"2^{exponent}"
    case = step_case(law, n)
    _time_step(benchmark, sizes, table, case, law, label, table.pair(label, n))


def test_load_step_2d(benchmark, sizes, table):
    """One hard-wall load step on a 2+1-D surface of side × side nodes (the dual CG on the flat view)."""
    side = sizes["side"]
    label = f"{side}²"
    case = step_case("hard wall", side, side)
    _time_step(benchmark, sizes, table, case, "hard wall 2+1-D", label, table.pair(label, side * side, (side, side)))


def test_tamaas_hard_wall(benchmark, sizes, table, exponent):
    """Tamaas' PolonskyKeerRey on the hard wall's step (the mean pressure GFMD finds there), warm-started by a solve
    at the previous step's mean pressure as GFMD is from its states; skipped where tamaas is not installed (the `bench`
    extra)."""
    tm = pytest.importorskip("tamaas", reason="tamaas is not installed (pip install '.[bench]'): no Tamaas column")
    n = 2**exponent
    case = step_case("hard wall", n)
    args, kw = case.args()
    p = -float(np.mean(relax(*args, **kw).t_z))
    previous = relax(case.cell.physics, case.cell.law, case.z_previous, case.previous.copy(), case.cell.settings,
                     case.wall_tolerance)
    p_previous = -float(np.mean(previous.t_z))
    s, m = case.scene.surface, case.scene.material

    solvers = {}

    def setup():  # a fresh solver with its warm start: the field of the previous step's load
        model = tm.ModelFactory.createModel(tm.model_type.basic_1d, [s.length], [n])
        model.E, model.nu = m.youngs_modulus, m.poisson_ratio
        tolerance = case.cell.settings.tolerance  # GFMD's, as the comparisons always ran them
        solvers["pkr"] = tm.PolonskyKeerRey(model, np.ascontiguousarray(-case.h), tolerance)
        solvers["pkr"].solve(p_previous)
        return (p,), {}

    benchmark.pedantic(lambda load: solvers["pkr"].solve(load), setup=setup, rounds=sizes["rounds"], iterations=1)
    table.add(benchmark, "Tamaas hard wall", f"2^{exponent}", pair_s=table.pair(f"2^{exponent}", n),
              note="PolonskyKeerRey, same mean pressure")
    table.tamaas[f"2^{exponent}"] = benchmark.stats.stats.min if benchmark.stats else None
