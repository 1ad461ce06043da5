"""Fast unit tests of the FE reference: mesh, periodic assembly (manufactured solution), condensation."""

import math

import numpy as np
import pytest
import sympy as sy
from skfem import FacetBasis, LinearForm, asm

from gfmd_contact.core import surfaces
from gfmd_contact.core.scene import Scene
from reference.fem.assembly import build_cell
from reference.fem.mesh import graded_cell
from reference.fem.solver import fourier_interpolate

L, D, E, NU = 1.0, 0.7, 2.0, 0.3


def test_mesh_top_nodes_are_gfmd_nodes_and_area():
    for n in (16, 64):
        p, t, top = graded_cell(n, L, D)
        assert np.allclose(p[0, top], surfaces.grid(n, L)) and np.allclose(p[1, top], 0)
        a, b, c = p[:, t[0]], p[:, t[1]], p[:, t[2]]
        area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        assert np.all(area > 0)
        assert math.isclose(area.sum(), L * D, rel_tol=1e-12)


def test_mesh_grows_linearly():
    counts = [graded_cell(n, L, L)[0].shape[1] for n in (256, 512, 1024, 2048)]
    per_node = np.array(counts) / [256, 512, 1024, 2048]
    assert np.all(np.diff(per_node) < 0) and per_node[-1] < 10  # ~8 N + a fixed coarse part


def _manufactured(order, n):
    """Solve with body force and top traction of a non-x-symmetric periodic exact field; L2 error."""
    x, z = sy.symbols("x z")
    q = 2 * sy.pi / L
    ux = (z + D) * sy.sin(q * x + 0.4) + 0.3 * (z + D) ** 2 * sy.cos(2 * q * x)
    uz = (z + D) ** 2 * sy.cos(q * x - 0.3) / D + 0.2 * (z + D) * sy.sin(3 * q * x + 1.0)
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    exx, ezz, exz = sy.diff(ux, x), sy.diff(uz, z), (sy.diff(ux, z) + sy.diff(uz, x)) / 2
    sxx, szz, sxz = lam * (exx + ezz) + 2 * mu * exx, lam * (exx + ezz) + 2 * mu * ezz, 2 * mu * exz
    fx = -(sy.diff(sxx, x) + sy.diff(sxz, z))
    fz = -(sy.diff(sxz, x) + sy.diff(szz, z))
    num = {k: sy.lambdify((x, z), v, "numpy") for k, v in dict(fx=fx, fz=fz, tx=sxz, tz=szz, ux=ux, uz=uz).items()}
    cell = build_cell(n, L, D, E, NU, order=order)
    b = cell.basis

    @LinearForm
    def body(v, w):
        return num["fx"](*w.x) * v[0] + num["fz"](*w.x) * v[1]

    top = cell.mesh.facets_satisfying(lambda p: np.abs(p[1]) < 1e-12)
    fb = FacetBasis(cell.mesh, b.elem, facets=top)

    @LinearForm
    def trac(v, w):
        return num["tx"](*w.x) * v[0] + num["tz"](*w.x) * v[1]

    f = asm(body, b) + asm(trac, fb)
    kr = cell.reduced_stiffness
    import scipy.sparse.linalg as spla
    u = cell.full(spla.spsolve(kr, cell.P.T @ f))
    # error at the DOF locations (nodal interpolation error is of the same order)
    loc = b.doflocs
    ix, iz = b.split_indices()
    ex = np.concatenate([u[ix] - num["ux"](*loc[:, ix]), u[iz] - num["uz"](*loc[:, iz])])
    return np.max(np.abs(ex))


@pytest.mark.parametrize("order", [1, 2])
def test_periodic_manufactured_solution(order):
    e1, e2 = _manufactured(order, 16), _manufactured(order, 32)
    rate = math.log2(e1 / e2)
    assert rate > (1.5 if order == 1 else 2.8), (e1, e2, rate)
    assert e2 < (2e-2 if order == 1 else 2e-4)


def test_circulant_schur_equals_direct():
    from reference._blas import single_thread
    cell = build_cell(64, L, D, E, NU, order=2)
    assert cell.shifts == 16
    for comps in (("z",), ("x", "z")):
        with single_thread():
            s1, _ = cell.schur(comps)
            s0, _ = cell.schur(comps, circulant=False)
        assert np.max(np.abs(s1 - s0)) < 1e-12 * np.max(np.abs(s0))


@pytest.mark.parametrize("order", [1, 2])
def test_surface_weights(order):
    n = 32
    cell = build_cell(n, L, D, E, NU, order=order)
    assert math.isclose(cell.weights.sum(), L, rel_tol=1e-12)
    l = L / n
    if order == 1:
        assert np.allclose(cell.weights, l)
    else:  # Simpson: l/3 at vertices, 2l/3 at midpoints
        assert np.allclose(cell.weights[0::2], l / 3) and np.allclose(cell.weights[1::2], 2 * l / 3)


def test_uniform_mode_is_layer_mean_compliance():
    """q = 0: uniform pressure p on the periodic bonded layer gives u_z = −p D/M (reference-formulas §1.5)."""
    cell = build_cell(16, L, D, E, NU, order=2)
    s, _ = cell.schur(("x", "z"))
    ns = cell.surface_x.size
    f = np.concatenate([np.zeros(ns), -1.0 * cell.weights])
    u = np.linalg.solve(s, f)
    m = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
    assert np.allclose(u[ns:], -D / m, rtol=1e-10) and np.allclose(u[:ns], 0, atol=1e-12)


def test_fourier_interpolation_keeps_nodes():
    h = surfaces.profile(Scene().surface.__class__(nodes=64, length=1.0, h_rms=0.01, rolloff_wavelength=0.2,
                                                   rollon_wavelength=0.05), 0)
    hi = fourier_interpolate(h, 2)
    assert np.allclose(hi[0::2], h, atol=1e-15)


def test_half_plane_scene_rejected():
    from reference import fem
    scene = Scene().replace(**{"surface.nodes": 64, "surface.length": 1e-6, "surface.rolloff_wavelength": 0.5e-6,
                               "surface.rollon_wavelength": 0.1e-6})
    with pytest.raises(ValueError, match="thickness"):
        fem.run_realization(scene)
