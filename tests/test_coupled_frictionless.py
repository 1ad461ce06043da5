"""The coupled chain's frictionless predictor (Settings.coupled = "frictionless-first", the "auto" choice on a body that
barely couples u_x and u_z; `gfmd.problem.frictionless`, `gfmd.chains`).

Kernels: the reduction's normal stiffness, condensed from the model's coupled 2×2 K(q), is the frictionless normal
kernel of `gfmd_contact.core.kernels` (half-plane and layer: independent formulas). Chain: test_coupled_handover's ramp
(bench_adhesion_scaling's coupled class at N = 2^12, ν = 0.45, realization seed 1) at its first event step.
"""

from dataclasses import replace

import numpy as np
import pytest

from gfmd_contact.core import kernels, surfaces
from gfmd_contact.core.model import build_model
from gfmd import chains
from gfmd.algorithms import ncg
from gfmd.problem import InterfaceLaw, Problem, elastic_coupling, frictionless
from gfmd.settings import Settings

from test_coupled_handover import _event_step, _scene, bound, ramps  # noqa: F401  (ramps: the module fixture)


def _model(nu, thickness, nodes=256):
    scene = _scene().replace(**{"surface.nodes": nodes, "surface.rollon_wavelength": 4 * 10.24e-6 / nodes,
                                "material.poisson_ratio": nu, "material.thickness": thickness})
    return build_model(scene, surfaces.profile(scene.surface, 0))


@pytest.mark.parametrize("thickness", ["inf", 2e-6])
@pytest.mark.parametrize("nu", [0.1, 0.3, 0.45])
def test_reduced_stiffness_is_the_frictionless_kernel(nu, thickness):
    model = _model(nu, thickness)
    assert model.tangential
    problem = _problem(model)
    reduced = frictionless(problem)
    coupled_law, normal_law = model.law, reduced.model.law
    assert type(normal_law).__name__ == "NormalCohesive"
    assert ((normal_law.work_normal, normal_law.length_normal, normal_law.contact_rule)
            == (coupled_law.work_normal, coupled_law.length_normal, coupled_law.contact_rule))
    assert not reduced.model.tangential and reduced.kind == "cohesive"
    youngs = _scene().material.youngs_modulus
    expected = (kernels.halfplane_normal(model.q, youngs, nu) if thickness == "inf"
                else kernels.layer_normal(model.q, youngs, nu, thickness))
    # the coupled kernels zero K_xz at the Nyquist mode (`gfmd_contact.core.kernels`): the model's own frictionless
    # stiffness there is its k_zz, nothing to condense
    free = np.abs(model.k_xz) > 0
    assert np.count_nonzero(~free) <= 2
    scale = np.max(np.abs(expected))
    assert np.max(np.abs(reduced.model.k_zz - expected)[free]) < 1e-12 * scale
    np.testing.assert_array_equal(reduced.model.k_zz[~free], np.real(model.k_zz[~free]))


def _problem(model):
    return Problem(model, InterfaceLaw(model), np.zeros(model.nodes))


def test_elastic_coupling_is_the_half_planes_beta():
    for nu in (0.1, 0.3, 0.45):
        assert elastic_coupling(_model(nu, "inf")) == pytest.approx((1 - 2 * nu) / (2 * (1 - nu)), rel=1e-12)
    assert elastic_coupling(frictionless(_problem(_model(0.45, "inf"))).model) == 0.0


def test_auto_chooses_the_predictor_on_weakly_coupled_bodies_only():
    for nu, key in ((0.45, "frictionless-first"), (0.3, "handover-near"), (0.1, "handover-near")):
        problem = _problem(_model(nu, "inf"))
        assert chains.chain_key(problem, Settings()) == ("coupled", key), nu
    with pytest.raises(ValueError, match="Settings.coupled = 'frictionless'.*auto"):
        chains.chain_key(problem, Settings(coupled="frictionless"))


def test_event_step_prediction_is_fires_state_in_fewer_pairs(ramps):
    cell, default, _ = ramps
    z, guess = _event_step(cell, default)
    near = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="handover-near"))
    pred = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="frictionless-first"))
    assert near.method == "newton→fire→newton" and pred.method == "newton→ncg-frictionless→newton", pred.method
    assert pred.converged and pred.residual < cell.settings.tolerance
    assert np.max(np.abs(pred.u_z - near.u_z)) < bound(cell) and np.max(np.abs(pred.u_x - near.u_x)) < bound(cell)
    assert pred.fft_pairs < near.fft_pairs
    auto = chains.relax(cell.physics, cell.law, z, guess, cell.settings)  # ν = 0.45: "auto" is the predictor
    assert auto.method == pred.method and np.array_equal(auto.u_hat, pred.u_hat)


def test_a_rejected_or_missing_prediction_goes_on_as_handover_near(ramps, monkeypatch):
    """Newton's state moved too far from the prediction (rejected), or the NCG did not reach the handover residual
    (no prediction): FIRE from the guess, as "handover-near", to its state."""
    cell, default, _ = ramps
    z, guess = _event_step(cell, default)
    near = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="handover-near"))
    monkeypatch.setattr(chains, "COUPLED_PREDICTION_MOVE", 0.0)  # every Newton state "moved too far"
    far = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="frictionless-first"))
    assert far.method == "newton→ncg-frictionless→newton→fire→newton", far.method
    assert "from the frictionless prediction" in far.message and "rejected" in far.message
    assert far.converged and np.max(np.abs(far.u_z - near.u_z)) < bound(cell)
    monkeypatch.setattr(chains, "COUPLED_PREDICTION_MOVE", 1.0)
    monkeypatch.setattr(ncg, "NCG_BUDGET", 2)  # the NCG stalls before the handover residual
    none = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="frictionless-first"))
    assert none.method == "newton→ncg-frictionless→fire→newton", none.method
    assert none.converged and np.max(np.abs(none.u_z - near.u_z)) < bound(cell)


def test_a_handover_link_that_hands_nothing_over_leaves_no_stale_state(ramps, monkeypatch):
    """The prediction rejected and FIRE's handover link short of its residual (budget 30 of 60 iterations): the Newton
    that starts from FIRE's handover state is skipped, not run again from the prediction the chain already rejected."""
    cell, default, _ = ramps
    z, guess = _event_step(cell, default)
    monkeypatch.setattr(chains, "COUPLED_PREDICTION_MOVE", 0.0)
    r = chains.relax(cell.physics, cell.law, z, guess,
                     replace(cell.settings, coupled="frictionless-first", max_iterations=60))
    assert "NCG on the frictionless reduction handed over" in r.message
    assert r.message.count("Newton–Krylov from the frictionless prediction stopped") == 1, r.message
    assert "FIRE's handover state" not in r.message and "FIRE handed over" not in r.message, r.message
