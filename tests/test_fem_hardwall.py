"""FE hard wall (reference/fem/hardwall.py): KKT, Westergaard (deep layer), GFMD.

Scenes (SI): sinusoid h = −h0 cos(2πx/L), h0 = 10 nm, L = 1 µm, E = 70 GPa,
ν = 0.45 (default scene), frictionless hard wall, δ0 = 0, six steps to
δ = 0.9 h0; KKT test on a self-affine profile (H = 0.8, h_rms = 10 nm, L = 1.28 µm,
λr = 320 nm, λs = 80 nm, N = 64, layer D = L).

1. KKT: every step satisfies S u + μ = 0, μ ≥ 0, u ≤ z_ind, μ·Δn = 0 to round-off,
   and the primal–dual active set (PDAS) agrees with an independent solver, the
   dual NNLS (Lawson–Hanson), to 1e-9 relative. PDAS iterations per step: ≤ 7
   measured (N ≤ 512): bound 15.
2. Westergaard on a deep layer D = 2L (the q = 2π/L mode's compliance is the
   half-plane's to ~1e-9): p̄ and ḡ are the node means of the Result's −t_n and
   Δn (the observable of tests/test_gfmd_westergaard.py: no contact-edge
   detection), error = max over the six loads of |p̄ − p̄_exact(ḡ)|/p*.
3. GFMD hard wall (FIRE, tolerance 1e-10, layer kernel) vs FE on the same
   sinusoid with D = L, all steps: max |Δp| / max p, max |Δu_z| / h0, t_n rel. L2.

The errors of 2 and 3 are measured by `verification.studies.fe_hardwall` and stored in
verification/data/fe_hardwall.json (regenerate: `python -m verification.studies.fe_hardwall --write`);
the tests read them. Bounds: SAFETY × the stored value at each N; P2 Westergaard: fitted order over the
N run ≥ the stored fitted order over the same N − ORDER_MARGIN; the GFMD differences of P2 in Δu_z and
t_n must decrease from N = 64 to 128. P1 (its nodal pressures oscillate node to node, ±20 %: the
alternating diagonals of the top row give neighbouring vertices different stiffness, and its Westergaard
error has a mesh floor) is held to SAFETY × stored in Δp and the Westergaard error only.
"""

import numpy as np
import pytest

from gfmd_contact.core.scene import default_scene
from reference import fem
from reference.fem.hardwall import HardWallProblem
from verification.studies import fe_hardwall as fh

H0, LENGTH, STEPS = fh.H0, fh.LENGTH, fh.STEPS
sinusoid_scene, westergaard_error, gfmd_differences = fh.sinusoid_scene, fh.westergaard_error, fh.gfmd_differences
SAFETY = 1.5  # × the stored error at the same N
ORDER_MARGIN = 0.2  # the fitted P2 Westergaard order may fall this far below the stored one


def test_half_plane_is_refused():
    sc = sinusoid_scene(16, 1e-6).replace(**{"material.thickness": "inf"})
    with pytest.raises(ValueError, match="finite layer"):
        fem.run_realization(sc)


@pytest.mark.parametrize("order", [1, 2])
def test_kkt_and_independent_dual_solver(order):
    sc = default_scene().replace(**{
        "surface.nodes": 64, "surface.length": 1.28e-6, "surface.realizations": 1, "interface.law": "hard-wall",
        "surface.rolloff_wavelength": 320e-9, "surface.rollon_wavelength": 80e-9,
        "material.thickness": 1.28e-6, "loading.initial_separation": 0.0, "loading.final_penetration": 35e-9,
        "loading.steps": 5, "output.field_steps": 5})
    r = fem.run_realization(sc, order=order)
    assert r.all_converged, r.messages
    assert r.diagnostics["fallback_steps"] == [], r.messages
    assert np.max(r.curve["iterations"]) <= 15
    assert 0.05 < r.curve["a_rel"][-1] < 0.9  # partial contact: the test exercises both sets
    prob = r.diagnostics["problem"]
    assert sorted(r.diagnostics["solutions"]) == sorted(r.diagnostics["wall_forces"]) == sorted(r.fields)
    for k, u in r.diagnostics["solutions"].items():
        mu, z = r.diagnostics["wall_forces"][k], prob.indenter(sc.loading.initial_separation, r.curve["U"][k])
        scale = prob.p_ref * prob.w  # N/m, a nodal force at the reference traction
        assert np.max(np.abs(prob.S @ u + mu) / scale) < 1e-10, f"step {k}: equilibrium"
        assert np.min(mu / scale) >= -1e-12, f"step {k}: wall pulls"
        gap = z - u
        assert np.min(gap) >= -1e-12 * H0, f"step {k}: penetration"
        assert np.max(np.minimum(mu / scale, np.abs(gap) / H0)) < 1e-12, f"step {k}: complementarity"
        u2, mu2 = prob.dual_nnls(z)
        assert np.max(np.abs(mu2 - mu)) <= 1e-9 * max(np.max(mu), 1e-300) + 1e-300, f"step {k}: PDAS ≠ NNLS"
        assert np.max(np.abs(u2 - u)) <= 1e-9 * np.max(np.abs(z))


def test_warm_start_needs_no_iterations_when_nothing_changes():
    """Re-solving a converged step from its own (u, μ) takes one PDAS iteration."""
    sc = sinusoid_scene(32, 1e-6)
    r = fem.run_realization(sc, order=1)
    z_ind = r.diagnostics["problem"].indenter(sc.loading.initial_separation, r.curve["U"][STEPS])
    u, mu, its, ok, how = r.diagnostics["problem"].solve_step(z_ind, r.diagnostics["solutions"][STEPS], r.diagnostics["wall_forces"][STEPS], 1e-10)
    assert ok and how == "pdas" and its == 1


@pytest.mark.parametrize("order,ns", [(2, [32, 64, 128]), pytest.param(2, [32, 64, 128, 256, 512],
                                                                        marks=pytest.mark.slow),
                                      (1, [32, 64, 128])])
def test_westergaard_deep_layer(order, ns):
    errors = [westergaard_error(n, order) for n in ns]
    print(f"\nP{order} Westergaard errors", dict(zip(ns, errors)))
    for n, e in zip(ns, errors):
        m = fh.stored_westergaard(order, n)
        assert e <= SAFETY * m, f"P{order} N = {n}: error {e:.3g} > {SAFETY:g}× stored {m:.3g}"
    if order == 2:
        slope = np.polyfit(np.log(ns), np.log(errors), 1)[0]
        stored = -np.polyfit(np.log(ns), np.log([fh.stored_westergaard(order, n) for n in ns]), 1)[0]
        assert -slope >= stored - ORDER_MARGIN, f"P2 Westergaard order {-slope:.2f} < stored {stored:.2f} − {ORDER_MARGIN}"


@pytest.mark.parametrize("nodes,order", [(64, 2), (128, 2), (64, 1), (128, 1),
                                         pytest.param(256, 2, marks=pytest.mark.slow),
                                         pytest.param(256, 1, marks=pytest.mark.slow)])
def test_gfmd_agreement(nodes, order):
    stored = fh.stored_gfmd(order, nodes)
    got = gfmd_differences(nodes, order)
    for name in (fh.GFMD_METRICS if order == 2 else ("dp",)):
        assert got[name] <= SAFETY * stored[name], \
            f"P{order} N = {nodes}: {name} = {got[name]:.3g} > {SAFETY:g}× stored {stored[name]:.2g}"


def test_gfmd_agreement_improves_with_n():
    coarse, fine = gfmd_differences(64, 2), gfmd_differences(128, 2)
    assert fine["du"] < coarse["du"] and fine["tn"] < coarse["tn"], (coarse, fine)


def test_problem_rejects_cohesive_scene():
    sc = sinusoid_scene(16, 1e-6).replace(**{"interface.law": "cohesive"})
    with pytest.raises(ValueError, match="hard-wall"):
        HardWallProblem(sc, np.zeros(16))
