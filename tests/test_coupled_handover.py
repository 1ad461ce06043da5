"""The coupled chain's FIRE→Newton handover (Settings.coupled = "handover-near", `gfmd.chains`) against FIRE's own
equilibrium (Settings.coupled = "fire": FIRE relaxes every step).

The ramp is the coupled benchmark class at N = 2^12 (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, λs,H = 10 nm,
realization seed 1) through its first event steps, 46 and 47, where the continuation Newton gives the step up and
FIRE hands over to Newton. Step 47 is an event from the guess extrapolated through step 46's snap only: the ramps
start every step from the guess (`gfmd.chains.COUPLED_BETTER_START` off; from the last state, step 47 is a
continuation).
"""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from gfmd import chains
from gfmd.loading import prepare, run_realization, settings_of
from gfmd.problem import Problem

SEED = Path(__file__).resolve().parents[1] / "studies" / "seed" / "seed_base.toml"
EVENT, STOP = 46, 47  # the ramp's first event step at 2^12; the ramp runs to the second


class _Stop(Exception):
    pass


def _scene():
    from gfmd_contact.core.scene import load_scene
    return load_scene(SEED).replace(**{"surface.nodes": 4096, "surface.rollon_wavelength": 10e-9,
                                       "surface.realizations": 1, "interface.law": "cohesive",
                                       "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.5,
                                       "interface.length_tangential": 1e-9})


def _ramp(scene, settings):
    """Curve (p, a_rel) and labels of steps 0..STOP, the states after steps EVENT − 2 and EVENT − 1 and STOP."""
    seen = {}

    def checkpoint(result, state):
        if state.step == EVENT - 1:
            seen.update(previous=state.previous.copy(), current=state.current.copy())
        if state.step == STOP:
            assert all(result.curve["converged"]), "a step of the ramp failed"
            seen.update(p=np.array(result.curve["p"]), a_rel=np.array(result.curve["a_rel"]),
                        labels=list(result.diagnostics["algorithms"]), last=state.current.copy())
            raise _Stop

    with pytest.raises(_Stop), pytest.MonkeyPatch.context() as m:
        m.setattr(chains, "COUPLED_BETTER_START", False)
        run_realization(scene, 0, settings=settings, checkpoint=checkpoint)
    return seen


@pytest.fixture(scope="module")
def ramps():
    scene = _scene()
    base = replace(settings_of(scene), coupled="fire")
    from gfmd_contact.core import surfaces
    cell = prepare(scene, surfaces.profile(scene.surface, 0), 0)
    return cell, _ramp(scene, base), _ramp(scene, replace(base, coupled="handover-near"))


def bound(cell):
    """Two states with max nodal residual < tol·p_ref differ by less than this (test_coupled_ptc's bound)."""
    m = cell.physics
    k1 = min(abs(m.k_xx[1]), abs(m.k_zz[1])) - abs(m.k_xz[1])
    return 10 * 2 * cell.settings.tolerance * m.reference_traction * np.sqrt(m.nodes) / k1 + \
        1e-6 * cell.scene.interface.length_normal


def _event_step(cell, ramp):
    from gfmd_contact.core.loading import indenter_surface, realization_steps
    from gfmd_contact.core import surfaces
    h = surfaces.profile(cell.scene.surface, 0)
    steps, _ = realization_steps(cell.scene, h, 0)
    z = indenter_surface(h, cell.scene.loading.initial_separation, steps[EVENT])
    return z, 2 * ramp["current"] - ramp["previous"]


def _nodal(cell, u_hat):
    return np.fft.irfft(u_hat, cell.physics.nodes)


def test_handover_ramp_has_fires_states_and_its_label(ramps):
    cell, default, handover = ramps
    for k in (EVENT, STOP):
        assert default["labels"][k] == "fire"  # the event steps: FIRE relaxed them to the tolerance
        assert handover["labels"][k] == "newton→fire→newton"  # FIRE handed over, Newton finished
    assert set(handover["labels"][:EVENT]) == {"newton"}  # the continuation steps
    assert np.array_equal(handover["a_rel"], default["a_rel"])
    # the mean traction of two states within the nodal bound: p = mean(t), t Lipschitz in u with the law's
    # largest slope (k_int_z), plus the two residuals' means
    p_bound = cell.law.k_int_z * bound(cell) + 2 * cell.settings.tolerance * cell.physics.reference_traction
    assert np.max(np.abs(handover["p"] - default["p"])) < p_bound
    assert np.max(np.abs(_nodal(cell, handover["last"] - default["last"]))) < bound(cell)


def test_event_step_handover_is_near_fires_state_and_cheaper(ramps):
    cell, default, _ = ramps
    z, guess = _event_step(cell, default)
    base = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="fire"))
    near = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="handover-near"))
    assert base.method == "fire" and near.method == "newton→fire→newton", (base.method, near.method)
    assert near.converged and near.residual < cell.settings.tolerance
    assert "handed over at residual" in near.message
    assert np.max(np.abs(near.u_z - base.u_z)) < bound(cell) and np.max(np.abs(near.u_x - base.u_x)) < bound(cell)
    assert near.fft_pairs < base.fft_pairs


def test_rejected_newton_hands_back_to_fire(ramps, monkeypatch):
    """A Newton state that fails the acceptance test (moved too far) goes back to FIRE, which goes on from its
    handover state with the budget it has left."""
    cell, default, _ = ramps
    z, guess = _event_step(cell, default)
    base = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="fire"))
    monkeypatch.setattr(chains, "COUPLED_HANDOVER_MOVE", 0.0)  # every Newton state "moved too far"
    far = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="handover-near"))
    assert far.converged and far.method == "newton→fire→newton→fire", far.method
    assert "from FIRE's handover state" in far.message and "rejected" in far.message
    assert np.max(np.abs(far.u_z - base.u_z)) < bound(cell)


def test_bad_settings_name_the_key(ramps):
    cell, default, _ = ramps
    z, _ = _event_step(cell, default)
    problem = Problem(cell.physics, cell.law, z)
    with pytest.raises(ValueError, match="Settings.coupled = 'handoff'"):
        chains.chain_key(problem, replace(cell.settings, coupled="handoff"))
    for bad in (1e-12, 2.0, "1e-4"):
        with pytest.raises(ValueError, match="Settings.coupled_handover"):
            chains.chain_key(problem, replace(cell.settings, coupled="handover-near", coupled_handover=bad))
    assert chains.chain_key(problem, replace(cell.settings, coupled="handover-near")) == ("coupled", "handover-near")
