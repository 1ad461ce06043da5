"""Gauss–Legendre boundary quadrature of the FE reference (`reference.fem.quadrature`).

Units: x, L, gaps in m; weights in m; tractions Pa; nodal forces N/m; tangents Pa.
Exactness checks are at round-off (rtol 1e-12 relative to the values' scale).
The Jacobian checks compare the assembled tangent with central finite
differences of the residual (step 1e-6 δn, truncation O(step²) ≈ 1e-12
relative; round-off ≈ 1e-16·‖R‖/step ≈ 1e-9 relative): bound 1e-6 relative to
max |J|.
"""

from __future__ import annotations

import numpy as np
import pytest

from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import indenter_surface
from gfmd_contact.core.scene import Scene
from reference import fem
from reference.fem.assembly import build_cell
from reference.fem.quadrature import fourier_evaluate, gauss_surface_quadrature, shape_functions
from reference.fem.solver import SurfaceProblem, fourier_interpolate

LENGTH = 1e-6


def surface_points(nodes, order, length=LENGTH):
    """Uniform surface points of an FE cell: x_k = −L/2 + k l/order (P2: midpoints at odd k)."""
    return -0.5 * length + np.arange(nodes * order) * length / (nodes * order)


def facet_columns(nodes, order, facet):
    """Surface-point indices of a facet and their x, unwrapped (last facet ends at x_0 + L)."""
    cols = np.arange(facet * order, facet * order + order + 1)
    x = -0.5 * LENGTH + cols * LENGTH / (nodes * order)
    return cols % (nodes * order), x


@pytest.mark.parametrize("order", [1, 2])
def test_trace_reproduces_polynomials_of_element_degree(order):
    nodes = 6
    quad = gauss_surface_quadrature(surface_points(nodes, order), LENGTH, order)
    b = quad.interpolation.toarray()
    n_g = quad.x.size // nodes
    rng = np.random.default_rng(0)
    for facet in range(nodes):  # includes the wrap-around facet
        cols, x = facet_columns(nodes, order, facet)
        rows = slice(facet * n_g, (facet + 1) * n_g)
        others = np.ones(nodes * order, bool)
        others[cols] = False
        assert np.all(b[rows][:, others] == 0), "a Gauss point sees a point outside its facet"
        xg = quad.x[rows]  # in [x_first vertex, x_first + l): the last facet ends at L/2 = x_0 + L
        for degree in range(order + 1):
            coef = rng.normal(size=degree + 1)
            poly = np.polynomial.Polynomial(coef, domain=[x[0], x[-1]], window=[0, 1])
            assert np.allclose(b[rows][:, cols] @ poly(x), poly(xg), rtol=0, atol=1e-12 * np.abs(coef).sum())
        # one degree higher is not reproduced (the test can fail)
        bad = np.polynomial.Polynomial([0] * (order + 1) + [1.0], domain=[x[0], x[-1]], window=[0, 1])
        assert np.max(np.abs(b[rows][:, cols] @ bad(x) - bad(xg))) > 1e-3


@pytest.mark.parametrize("order,points", [(1, 1), (1, 3), (2, 3), (2, 4)])
def test_rule_integrates_polynomials_of_degree_2n_minus_1(order, points):
    nodes = 5
    quad = gauss_surface_quadrature(surface_points(nodes, order), LENGTH, order, points_per_facet=points)
    assert np.isclose(quad.weights.sum(), LENGTH, rtol=1e-14, atol=0)
    l = LENGTH / nodes
    xi = (quad.x + 0.5 * LENGTH) / l % 1.0  # local facet coordinate of each Gauss point
    for degree in range(2 * points):
        assert np.isclose(quad.integrate(xi**degree), LENGTH / (degree + 1), rtol=1e-12, atol=0), degree
    assert not np.isclose(quad.integrate(xi ** (2 * points)), LENGTH / (2 * points + 1), rtol=1e-6, atol=0)


@pytest.mark.parametrize("order", [1, 2])
def test_consistent_forms_match_the_cells_nodal_weights_and_mass(order):
    """Bᵀw_g = the FacetBasis load vector W (Cell.weights); Bᵀdiag(w_g)B = the exact facet mass matrix."""
    nodes = 8
    cell = build_cell(nodes, LENGTH, LENGTH, 70e9, 0.3, order=order)
    quad = gauss_surface_quadrature(cell.surface_x, LENGTH, order)
    b = quad.interpolation
    assert np.allclose(b.T @ quad.weights, cell.weights, rtol=1e-12, atol=0)
    mass = b.T @ (quad.weights[:, None] * b.toarray())
    l = LENGTH / nodes
    cols, _ = facet_columns(nodes, order, 2)  # an interior facet: its points' couplings come from it alone
    if order == 1:  # exact P1 facet mass l/6 [[2, 1], [1, 2]]; a vertex has two facets
        assert np.isclose(mass[cols[0], cols[1]], l / 6, rtol=1e-12, atol=0)
        assert np.isclose(mass[cols[0], cols[0]], 2 * 2 * l / 6, rtol=1e-12, atol=0)
    else:  # exact P2 facet mass l/30 [[4, 2, −1], [2, 16, 2], [−1, 2, 4]] (vertex, midpoint, vertex)
        assert np.isclose(mass[cols[1], cols[1]], 16 * l / 30, rtol=1e-12, atol=0)
        assert np.isclose(mass[cols[0], cols[1]], 2 * l / 30, rtol=1e-12, atol=0)
        assert np.isclose(mass[cols[0], cols[2]], -l / 30, rtol=1e-12, atol=0)
        assert np.isclose(mass[cols[0], cols[0]], 2 * 4 * l / 30, rtol=1e-12, atol=0)


def test_linear_law_identities_nodal_vs_gauss():
    """For T = kΔ: the total force Σf agrees exactly for any FE gap field (W is exact for the trace's
    degree); for a constant gap every nodal force agrees; elsewhere lumped ≠ consistent (the test can fail)."""
    order, nodes, k = 2, 8, 3.0e18
    quad = gauss_surface_quadrature(surface_points(nodes, order), LENGTH, order)
    b, w = quad.interpolation, quad.weights
    lumped = b.T @ w
    gap = np.random.default_rng(1).normal(size=nodes * order) * 1e-9
    f_gauss, f_nodal = b.T @ (w * k * (b @ gap)), lumped * k * gap
    assert np.isclose(f_gauss.sum(), f_nodal.sum(), rtol=1e-12, atol=0)
    assert not np.allclose(f_gauss, f_nodal, rtol=1e-3)
    const = np.full(nodes * order, 1e-9)
    assert np.allclose(b.T @ (w * k * (b @ const)), lumped * k * const, rtol=1e-12, atol=0)


def test_fourier_evaluate_is_the_solvers_interpolant():
    n = 16
    x = surface_points(n, 1)
    h = np.random.default_rng(2).normal(size=n)
    fine = surface_points(n, 4)
    assert np.allclose(fourier_evaluate(h, LENGTH, fine), fourier_interpolate(h, 4), rtol=0, atol=1e-12)
    assert np.allclose(fourier_evaluate(h, LENGTH, x), h, atol=1e-12)
    xs = np.random.default_rng(3).uniform(-LENGTH / 2, LENGTH / 2, 50)
    for mode in (0, 3, n // 2):  # cos modes incl. Nyquist (cosine, split between ±q)
        q = 2 * np.pi * mode / LENGTH
        assert np.allclose(fourier_evaluate(np.cos(q * x), LENGTH, xs), np.cos(q * xs), atol=1e-12)


def test_shape_functions_partition_of_unity_and_bad_order():
    xi = np.linspace(0, 1, 7)
    for order in (1, 2):
        assert np.allclose(shape_functions(order, xi).sum(axis=1), 1.0)
    with pytest.raises(ValueError, match="order"):
        shape_functions(3, xi)
    with pytest.raises(ValueError, match="midpoints"):
        gauss_surface_quadrature(surface_points(4, 2) + np.tile([0.0, 1e-8], 4), LENGTH, 2)


def small_scene(nodes=16, tangential_ratio=0.0):
    return Scene().replace(**{
        "surface.kind": "sinusoid", "surface.realizations": 1, "surface.nodes": nodes, "surface.length": LENGTH,
        "surface.amplitude": 5e-9, "material.youngs_modulus": 70e9, "material.poisson_ratio": 0.3,
        "material.thickness": LENGTH, "interface.law": "cohesive", "interface.phi_n_star": 0.01,
        "interface.length_normal": 1e-9, "interface.tangential_ratio": tangential_ratio,
        "loading.initial_separation": 2e-9, "loading.final_penetration": 6e-9, "loading.steps": 6,
        "output.field_steps": 2})


def problem(tangential_ratio, quadrature="gauss", nodes=16):
    sc = small_scene(nodes, tangential_ratio)
    h = surfaces.profile(sc.surface, 0)
    prob = SurfaceProblem(sc, h, order=2, quadrature=quadrature)
    z_ind = indenter_surface(prob.h_surface, 2e-9, 3e-9) + (np.min(prob.h_surface) - np.min(h))
    rng = np.random.default_rng(4)
    u = rng.normal(size=prob.S.shape[0]) * 0.3e-9  # gaps spread over the law's range (≈ 0–4 δn)
    return prob, z_ind, u


@pytest.mark.parametrize("tangential_ratio", [0.0, 0.5])
def test_gauss_jacobian_matches_finite_differences(tangential_ratio):
    prob, z_ind, u = problem(tangential_ratio)
    jac = prob.jacobian(u, z_ind)
    assert not np.allclose(jac, prob.S), "law part of the tangent is missing"
    step = 1e-6 * prob.dn
    fd = np.empty_like(jac)
    for j in range(u.size):
        e = np.zeros(u.size)
        e[j] = step
        fd[:, j] = (prob.residual(u + e, z_ind) - prob.residual(u - e, z_ind)) / (2 * step)
    law_fd, law = fd - prob.S, jac - prob.S
    assert np.max(np.abs(law - law_fd)) < 1e-6 * np.max(np.abs(law)), np.max(np.abs(law - law_fd))
    if tangential_ratio > 0:
        assert not np.allclose(law, law.T), "coupled Gauss tangent should be non-symmetric"


def test_gauss_energy_gradient_is_the_residual():
    prob, z_ind, u = problem(0.0)
    step = 1e-6 * prob.dn
    grad = np.array([(prob.energy(u + step * e, z_ind) - prob.energy(u - step * e, z_ind)) / (2 * step)
                     for e in np.eye(u.size)])
    r = prob.residual(u, z_ind)
    assert np.max(np.abs(grad - r)) < 1e-5 * np.max(np.abs(r))


def test_flat_surface_nodal_and_gauss_agree():
    """Uniform gap (flat surface, uniform u): the consistent force equals the lumped one (Bᵀw_g = W)."""
    sc = small_scene()
    h = np.zeros(sc.surface.nodes)  # flat surface (heights passed directly)
    nodal, gauss = (SurfaceProblem(sc, h, order=2, quadrature=q) for q in ("nodal", "gauss"))
    z_ind = indenter_surface(nodal.h_surface, 2e-9, 0.0)
    u = np.full(nodal.S.shape[0], 0.4e-9)
    def law_force(prob, u):  # f = S u − R (N/m)
        return prob.S @ u - prob.residual(u, z_ind)

    assert np.allclose(law_force(gauss, u), law_force(nodal, u), rtol=1e-12, atol=0)
    assert np.isclose(gauss.energy(u, z_ind), nodal.energy(u, z_ind), rtol=1e-12, atol=0)
    # a non-uniform u makes them differ (lumped vs consistent): the comparison can fail
    u2 = u + 0.2e-9 * np.cos(2 * np.pi * 3 * nodal.cell.surface_x / LENGTH)
    assert not np.allclose(law_force(gauss, u2), law_force(nodal, u2), rtol=1e-3)


@pytest.mark.parametrize("tangential_ratio", [0.0, 0.5])
def test_gauss_run_converges_close_to_nodal(tangential_ratio):
    sc = small_scene(32, tangential_ratio)
    gauss = fem.run_realization(sc, quadrature="gauss")
    nodal = fem.run_realization(sc)
    assert gauss.all_converged, gauss.messages
    assert "Gauss" in gauss.model
    # same observables' structure; p differs by a quadrature error (N = 32: < 5 % of max |p|)
    diff = np.max(np.abs(gauss.curve["p"] - nodal.curve["p"])) / np.max(np.abs(nodal.curve["p"]))
    assert 0 < diff < 5e-2, diff


def test_bad_quadrature_choices_raise():
    sc = small_scene()
    with pytest.raises(ValueError, match="quadrature"):
        fem.run_realization(sc, quadrature="simpson")
    with pytest.raises(ValueError, match="linear='dense'"):
        fem.run_realization(sc, quadrature="gauss", linear="sparse")
    with pytest.raises(ValueError, match="hard wall"):
        fem.run_realization(sc.replace(**{"interface.law": "hard-wall"}), quadrature="gauss")
