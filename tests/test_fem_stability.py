"""Local stability test of FE equilibria (`reference.fem.solver.locally_stable`).

Units: the tangents J are in Pa (N/m of nodal force per m of displacement), the
weights W in m; the tests use dimensionless numbers, the criterion is scale free.

Normal law: J symmetric, stable ⇔ positive definite. Coupled law (no potential):
stable ⇔ the overdamped dynamics W u̇ = −J u decays ⇔ every eigenvalue of W⁻¹J has
Re λ > 0. The decay is checked independently with a matrix exponential.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from reference.fem.solver import locally_stable


def decays(jacobian, weights, squarings=60):
    """True if the overdamped dynamics W u̇ = −J u decays: the growth rate of ‖exp(−W⁻¹J t)‖,
    from E = exp(−W⁻¹J τ) (scipy's Padé matrix exponential, τ = 1/‖W⁻¹J‖) squared 2^60 times
    with renormalisation (log ρ(E) = lim 2^−k log‖E^(2^k)‖), is negative. No eigenvalues used."""
    a = jacobian / weights[:, None]
    e = scipy.linalg.expm(-a / np.linalg.norm(a, 2))
    log_norm = 0.0  # log of the factored-out scale of E^(2^k)
    for k in range(squarings):
        e = e @ e
        scale = np.linalg.norm(e, 2)
        e /= scale
        log_norm = 2 * log_norm + np.log(scale)
    return log_norm / 2.0**squarings < 0


def test_nonsymmetric_stable_with_indefinite_symmetric_part():
    # eigenvalues 1, 1; sym(J) = [[1, 2], [2, 1]] has eigenvalue −1 (the old Cholesky-of-sym(J) check said unstable)
    jacobian = np.array([[1.0, 4.0], [0.0, 1.0]])
    assert np.linalg.eigvalsh(0.5 * (jacobian + jacobian.T)).min() < 0
    assert locally_stable(jacobian, np.ones(2), symmetric=False)
    assert decays(jacobian, np.ones(2))


def test_nonsymmetric_unstable_spiral():
    jacobian = np.array([[-0.1, 1.0], [-1.0, -0.1]])  # λ = −0.1 ± i: growing oscillation
    assert not locally_stable(jacobian, np.ones(2), symmetric=False)
    assert not decays(jacobian, np.ones(2))


def test_damping_weights_enter_as_inverse():
    # stable with W = I (trace 0.5, det 0.5) but not with W = diag(1, 0.1): trace(W⁻¹J) = 1 − 5 < 0.
    # (Using W J instead of W⁻¹J would give trace 0.95 > 0 and call it stable.)
    jacobian = np.array([[1.0, 1.0], [-1.0, -0.5]])
    assert locally_stable(jacobian, np.ones(2), symmetric=False)
    weights = np.array([1.0, 0.1])
    assert not locally_stable(jacobian, weights, symmetric=False)
    assert not decays(jacobian, weights)


def test_symmetric_needs_positive_definite():
    assert locally_stable(np.array([[2.0, 1.0], [1.0, 2.0]]), np.ones(2), symmetric=True)
    assert not locally_stable(np.array([[1.0, 2.0], [2.0, 1.0]]), np.ones(2), symmetric=True)


@pytest.mark.parametrize("seed", range(16))
def test_agrees_with_overdamped_dynamics(seed):
    """Random SPD 'elastic' part + non-symmetric 2×2 nodal blocks like the coupled law's tangent
    (diagonal stiffness of either sign, skew-dominated coupling). With these seeds 11 draws are
    stable with an indefinite sym(J) and 5 are unstable: the old sym(J) test fails the 11."""
    rng = np.random.default_rng(seed)
    nodes = 6
    b = rng.normal(size=(2 * nodes, 2 * nodes))
    jacobian = b @ b.T / (2 * nodes) + 0.2 * np.eye(2 * nodes)
    idx = np.arange(nodes)
    coupling = rng.normal(scale=2.5, size=nodes)
    jacobian[idx, idx] += rng.uniform(-1.2, 1.0, nodes)  # ∂Tt/∂Δt
    jacobian[idx, nodes + idx] += coupling  # ∂Tt/∂Δn
    jacobian[nodes + idx, idx] += -coupling * rng.uniform(0.0, 2.0, nodes)  # ∂Tn/∂Δt
    jacobian[nodes + idx, nodes + idx] += rng.uniform(-1.2, 1.0, nodes)  # ∂Tn/∂Δn
    weights = np.tile(rng.uniform(0.3, 1.0, nodes), 2)
    assert locally_stable(jacobian, weights, symmetric=False) == decays(jacobian, weights)


def test_coupled_fe_equilibria_accepted_without_fallback():
    """Coupled-law FE ramp (ν = 0.3, N = 64, δ to 30 nm): from δ ≈ 23 nm sym(J) is indefinite at the
    Newton roots, yet they are stable (min Re λ(W⁻¹J) ≈ 7e16 Pa/m > 0, measured); the old check sent
    those steps to pseudo-transient continuation. Newton's roots must now be accepted."""
    from gfmd_contact.core.loading import displacement_steps, indenter_surface
    from reference import fem
    from verification.scenes import cohesive_sinusoid as scene

    sc = scene(64).replace(**{"interface.tangential_ratio": 0.5, "loading.final_penetration": 30e-9,
                              "loading.steps": 16, "output.field_steps": 1})
    result = fem.run_realization(sc, order=2)
    assert result.all_converged, result.messages
    assert result.diagnostics["fallback_steps"] == [], result.messages
    prob, k = result.diagnostics["problem"], max(result.diagnostics["solutions"])
    z_ind = indenter_surface(prob.h_surface, sc.loading.initial_separation, displacement_steps(sc.loading)[k])
    z_ind = z_ind + (np.min(prob.h_surface) - np.min(result.h))
    jacobian = prob.jacobian(result.diagnostics["solutions"][k], z_ind)
    assert np.linalg.eigvalsh(0.5 * (jacobian + jacobian.T)).min() < 0, "the case no longer exercises the eigenvalue path"
    assert decays(jacobian, prob.wt)


def test_fe_refuses_a_poisson_ratio_its_stiffness_cannot_resolve():
    """Near ν = 1/2 a displacement FE's condensed stiffness loses its Cholesky factorisation (ν = 0.5 − 1e−16 on a
    16-node P2 cell once crashed the CLI with a traceback): both FE references refuse such a scene naming
    material.poisson_ratio, and solve every ν up to the documented bound."""
    import scipy.linalg

    from gfmd_contact.core.scene import scene_from_dict
    from reference._material import MAX_POISSON_RATIO as bound
    from reference._material import near_incompressible
    from reference.fem.assembly import build_cell
    from reference.fem.run import refusal

    def scene(nu):
        return scene_from_dict({"surface": {"kind": "cylinder", "radius": 1e-6, "nodes": 16, "length": 1e-6},
                                "material": {"poisson_ratio": nu, "thickness": 1e-6},
                                "interface": {"law": "hard-wall"}, "method": {"name": "fe"}})

    too_close = 0.49999999999999994
    assert refusal(scene(too_close)).startswith("material.poisson_ratio = 0.49999999999999994")
    assert near_incompressible(scene(bound)) is None and refusal(scene(0.45)) is None
    for order in (1, 2):  # at the bound the stiffness still factorises
        stiffness, _ = build_cell(16, 1e-6, 1e-6, 70e9, bound, order=order).schur(("z",))
        scipy.linalg.cho_factor(stiffness)
