"""Pseudo-transient continuation on the coupled law (`gfmd.algorithms.coupled_ptc`, the coupled chains' last resort).

The steps are test_solver_coupled's fig8_small steps (ν = 0.1, c = 0.5, seed 2, N = 4096): step 99 from step
98's state (FIRE's ramp converged it) and the last step, 100, from the extrapolated guess, an event step where
the default chain's FIRE stalls and Newton from the guess finishes it.
"""

from dataclasses import replace

import numpy as np
import pytest

from gfmd import solver as gs
from gfmd.algorithms import coupled_newton, coupled_ptc
from gfmd.problem import Problem
from gfmd.stopping import finish
from test_solver_coupled import fig8_step  # noqa: F401  (the module-scoped fixture)


def bound(cell):
    """Two states with max nodal residual < tol·p_ref differ by less than this (test_solver_coupled's bound)."""
    m = cell.physics
    k1 = min(abs(m.k_xx[1]), abs(m.k_zz[1])) - abs(m.k_xz[1])
    return 10 * 2 * cell.settings.tolerance * m.reference_traction * np.sqrt(m.nodes) / k1 + \
        1e-6 * cell.scene.interface.length_normal


def test_ptc_reaches_fires_state(fig8_step):
    cell, previous, current, (z99, _) = fig8_step
    r = coupled_ptc.solve(Problem(cell.physics, cell.law, z99), previous, cell.settings)
    assert r.converged and r.method == "ptc" and r.stalled == "", r.message
    assert r.residual < cell.settings.tolerance
    fire = finish(Problem(cell.physics, cell.law, z99), current, 0, 0.0, True, "")
    for a, b in ((r.u_z, fire.u_z), (r.u_x, fire.u_x)):
        assert np.max(np.abs(a - b)) < bound(cell)


def test_ptc_on_an_event_step_reaches_newtons_state_and_counts_pairs(fig8_step):
    cell, previous, current, (_, z100) = fig8_step
    problem, guess = Problem(cell.physics, cell.law, z100), 2 * current - previous
    r = coupled_ptc.solve(problem, guess, cell.settings)
    assert r.converged and r.iterations > 1, r.message
    eq = coupled_newton.solve(problem, guess, cell.settings)
    assert eq.converged, eq.message
    for a, b in ((r.u_z, eq.u_z), (r.u_x, eq.u_x)):
        assert np.max(np.abs(a - b)) < bound(cell)
    # every iteration: one force (3 transforms) and GMRES's products (≥ 1 pair), plus the start's force
    assert r.fft_pairs >= 1.5 + 2.5 * r.iterations
    again = coupled_ptc.solve(problem, r.u_hat, cell.settings)  # a converged start: no iteration, one force
    newton_again = coupled_newton.solve(problem, r.u_hat, cell.settings)  # its force on the nodes: u and K u
    assert again.converged and again.iterations == 0 and again.fft_pairs == 2.0
    assert newton_again.converged and newton_again.iterations == 0 and newton_again.fft_pairs == 1.5


def test_ptc_stalls_cleanly(fig8_step, monkeypatch):
    cell, previous, current, (_, z100) = fig8_step
    problem = Problem(cell.physics, cell.law, z100)
    crushed = np.array(current, copy=True)  # u_z plus a cosine of amplitude 1e3 δn: Δn < −600 δn somewhere
    crushed[-1, 1] += 1e3 * cell.scene.interface.length_normal * cell.physics.nodes / 2
    bad = coupled_ptc.solve(problem, crushed, cell.settings)  # in the law's overflow range
    assert not bad.converged and bad.iterations == 0 and "diverged" in bad.stalled, bad.message
    monkeypatch.setattr(coupled_ptc, "PTC_ITERATIONS", 2)
    short = coupled_ptc.solve(problem, 2 * current - previous, cell.settings)
    assert not short.converged and short.iterations == 2 and "not converged after 2" in short.stalled
    assert short.residual > cell.settings.tolerance and np.all(np.isfinite(short.u_hat)) and short.fft_pairs > 2


@pytest.mark.parametrize("value", ["PTC", "psi", "ptc", "newton", "handover", "ncg-first"])
def test_unknown_coupled_setting_is_refused_by_name(fig8_step, value):
    cell, _previous, current, (_, z100) = fig8_step
    with pytest.raises(ValueError, match="Settings.coupled"):
        gs.relax(cell.physics, cell.law, z100, current, replace(cell.settings, coupled=value))
