"""Scene checks of gfmd_contact.core.model / gfmd_contact.core.loading: under-resolved δn, unstable start, forced full model.

Flat-surface tests are exact (a flat indenter only moves the uniform mode of a layer,
stiffness M/D, so the jump-in separation of `jump_in_separation` is the true one).
"""

from __future__ import annotations

import numpy as np
import pytest

from gfmd_contact.core import kernels, laws
from gfmd.loading import run_realization
from gfmd_contact.core.loading import start_warning
from gfmd_contact.core.model import (MIN_LENGTH_NORMAL_NODES, ModelCheckError, build_model, jump_in_separation,
                        softest_normal_stiffness, warnings_in)
from gfmd_contact.core.scene import Scene, SceneError, default_scene

E, NU, DN, PHI = 70e9, 0.3, 1e-9, 0.15


def flat_layer(thickness, d0, **extra):
    """Flat indenter on a layer: N = 16, L = 8 nm (δn = 2 l); steps at U = 0 and U = 1e-3 δn (saved)."""
    kw = {"surface.kind": "flat", "surface.nodes": 16, "surface.length": 8e-9, "surface.realizations": 1,
          "material.youngs_modulus": E, "material.poisson_ratio": NU, "material.thickness": thickness,
          "interface.law": "cohesive", "interface.phi_n_star": PHI, "interface.length_normal": DN,
          "loading.initial_separation": d0, "loading.final_penetration": 1e-3 * DN - d0, "loading.steps": 1,
          "output.field_steps": 1}
    kw.update(extra)
    return Scene().replace(**kw)


def test_jump_in_separation_root_and_limits():
    phi_n = PHI * DN * E
    steepest = np.exp(-2) * phi_n / DN**2
    assert jump_in_separation(steepest, phi_n, DN) == 0.0  # stiff enough: nothing jumps
    assert jump_in_separation(2 * steepest, phi_n, DN) == 0.0
    assert jump_in_separation(0.999999 * steepest, phi_n, DN) == pytest.approx(4 * DN, rel=1e-2)  # s* → 2
    previous = 0.0
    for fraction in (0.5, 0.1, 1e-2, 1e-3):
        k = fraction * steepest
        d = jump_in_separation(k, phi_n, DN)
        s = np.roots([1, -d / DN, d / DN])  # d/δn = s²/(s − 1)  ⇔  s² − (d/δn)s + d/δn = 0
        s = float(np.max(s.real))
        assert s > 2
        assert (s - 1) * np.exp(-s) == pytest.approx(k * DN**2 / phi_n, rel=1e-10)  # tangent point
        assert d > previous  # softer surface: jumps from farther away
        previous = d


@pytest.mark.parametrize("factor, jumps", [(1.03, False), (0.97, True)])
def test_flat_layer_jumps_exactly_inside_the_predicted_separation(factor, jumps):
    """Thin enough layer that M/D < e^{-2}φn/δn²: starting just outside δ_jump the first step stays out
    of contact, just inside it the surface jumps, and the run says so."""
    thickness = 200e-9
    m_over_d = kernels.constrained_modulus(E, NU) / thickness
    phi_n = PHI * DN * E
    assert m_over_d < np.exp(-2) * phi_n / DN**2
    d_jump = jump_in_separation(m_over_d, phi_n, DN)
    sc = flat_layer(thickness, factor * d_jump)
    model = build_model(sc)
    assert softest_normal_stiffness(model) == pytest.approx(m_over_d, rel=1e-12)
    predicted = [w for w in model.warnings if w.startswith("unstable start")]
    assert bool(predicted) == jumps
    result = run_realization(sc)
    assert result.all_converged, result.messages
    gap = result.fields[1]["gap"]  # U = 1e-3 δn: the state of step 0, moved by 1e-3 δn
    found = [w for w in warnings_in(result.reasons) if w.startswith("jump at start")]
    assert bool(found) == jumps, result.reasons
    if jumps:
        assert "raise loading.initial_separation" in found[0] and np.max(gap) < DN
    else:  # on the stable branch, beyond the tangent point s* > 2
        assert np.min(gap) > 2 * DN


def test_unstable_start_is_predicted_and_refused_on_request():
    thickness = 200e-9
    phi_n = PHI * DN * E
    d_jump = jump_in_separation(kernels.constrained_modulus(E, NU) / thickness, phi_n, DN)
    sc = flat_layer(thickness, 0.5 * d_jump)
    model = build_model(sc)
    (msg,) = [w for w in model.warnings if w.startswith("unstable start")]
    assert f"Pick δ0 ≥ {d_jump / DN:.3g} δn" in msg and "uniform mode M/D" in msg
    assert "unstable start" in model.description
    with pytest.raises(ModelCheckError, match="unstable start"):
        build_model(sc.replace(**{"solver.checks": "error"}))


def test_start_in_contact_is_reported():
    sc = flat_layer(200e-9, 0.5 * DN)
    model = build_model(sc)
    msg = start_warning(sc, model, min_gap=0.5 * DN)
    assert msg.startswith("start in contact") and "δ0 = 0.5 δn" in msg


def test_under_resolved_length_normal_warns_with_the_fix():
    sc = flat_layer(200e-9, 10 * DN, **{"surface.nodes": 16, "surface.length": 32e-9})  # δn = 0.5 l
    model = build_model(sc)
    (msg,) = [w for w in model.warnings if w.startswith("under-resolved δn")]
    assert "δn = 0.5 l is under-resolved" in msg and f"refine to δn ≥ {MIN_LENGTH_NORMAL_NODES:g} l" in msg
    assert "surface.nodes = 64" in msg
    with pytest.raises(ModelCheckError, match="under-resolved"):
        build_model(sc.replace(**{"solver.checks": "error"}))
    resolved = build_model(sc.replace(**{"surface.nodes": 64}))
    assert not [w for w in resolved.warnings if w.startswith("under-resolved")]


def test_hard_wall_has_no_cohesive_checks():
    sc = flat_layer(200e-9, 1e-9, **{"interface.law": "hard-wall", "surface.nodes": 16, "surface.length": 1e-6})
    assert build_model(sc).warnings == ()


def test_forced_coupled_unknowns():
    sc = flat_layer(float("inf"), 10 * DN, **{"material.poisson_ratio": 0.5, "interface.tangential_ratio": 0.5})
    assert not build_model(sc).tangential  # ν = 1/2 half-plane: u_x ≡ 0 exact
    full = build_model(sc.replace(**{"solver.unknowns": "coupled"}))
    assert full.tangential and "solver.unknowns = coupled" in full.reasons[1 - 1]
    assert build_model(sc.replace(**{"interface.tangential_ratio": 0.0, "solver.unknowns": "coupled"})).tangential
    with pytest.raises(SceneError, match="solver.unknowns"):
        sc.replace(**{"interface.law": "hard-wall", "solver.unknowns": "coupled"})
    with pytest.raises(SceneError, match="solver.unknowns"):
        sc.replace(**{"solver.unknowns": "everything"})
    with pytest.raises(SceneError, match="solver.checks"):
        sc.replace(**{"solver.checks": "ignore"})


@pytest.mark.parametrize("extra, law, tangential, text", [
    ({"interface.law": "hard-wall"}, laws.HardWall, False, "hard wall, half-plane"),
    ({}, laws.NormalCohesive, False, "normal-only CZ, half-plane"),
    ({"interface.tangential_ratio": 0.5}, laws.CoupledCohesive, True, "coupled CZ, half-plane"),
    ({"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.5}, laws.NormalCohesive, False,
     "normal-only CZ, half-plane"),  # ν = 1/2: Eq. 2 at Δt ≡ 0 is Eq. 3
    ({"solver.unknowns": "coupled"}, laws.CoupledCohesive, True, "coupled CZ, half-plane"),  # Eq. 2, φt = 0
    ({"interface.tangential_ratio": 0.5, "material.thickness": 1e-6}, laws.CoupledCohesive, True,
     "coupled CZ, layer"),
])
def test_model_holds_the_law_object_it_solves(extra, law, tangential, text):
    # Model.law is the law on the chosen unknowns (gfmd_contact.core.laws.law_from_scene(scene, tangential)),
    # and the description names it
    sc = flat_layer(float("inf"), 10 * DN, **extra)
    model = build_model(sc)
    assert type(model.law) is law and model.tangential is tangential
    assert model.law == laws.law_from_scene(sc, tangential=tangential)
    assert model.description.startswith(text) and model.description.startswith(model.law.name)
    p_ref = model.law.reference_traction(sc.material.contact_modulus)  # flat profile: the law's own scale
    assert model.reference_traction == p_ref
    assert p_ref == (sc.material.contact_modulus if law is laws.HardWall else sc.work_normal / (np.e * DN))


def test_start_warning_asks_the_law():
    # a hard wall has nothing to jump to: no start warning however close the start; a cohesive law warns
    wall = flat_layer(200e-9, 0.1 * DN, **{"interface.law": "hard-wall"})
    assert start_warning(wall, build_model(wall), 0.0) is None
    cz = flat_layer(200e-9, 0.1 * DN)
    assert start_warning(cz, build_model(cz), 0.0).startswith("start in contact")


def test_slip_warning_flags_compressed_slipping_nodes_only():
    from gfmd_contact.core.loading import SLIP_LIMIT, slip_warning
    sc = default_scene().replace(**{"interface.tangential_ratio": 0.5})
    dt = sc.interface.length_tangential
    gap = np.array([-1e-9, -1e-9, 2e-9])
    assert slip_warning(sc, 3, 1e-9, gap, np.array([0.5, 2.0, 0.0]) * dt) is None  # below the limit
    assert slip_warning(sc, 3, 1e-9, gap, np.array([0.0, 0.0, 10.0]) * dt) is None  # slipping but open
    msg = slip_warning(sc, 3, 1e-9, gap, np.array([0.0, -(SLIP_LIMIT + 0.5), 0.0]) * dt)
    assert msg and "step 3" in msg and "1 compressed nodes" in msg and f"max {SLIP_LIMIT + 0.5:.3g} δt" in msg
    normal = sc.replace(**{"interface.tangential_ratio": 0.0})
    assert slip_warning(normal, 3, 1e-9, gap, np.array([0.0, 10.0, 0.0]) * dt) is None  # no coupled law
