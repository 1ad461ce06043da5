"""gfmd.coupled_preconditioner: the coupled Newton's two-level right preconditioner M⁻¹ = Q + K⁻¹(I − A Q).

Checked against dense matrices built here from the model's kernels (numpy's FFT, A = Π (K + D) Π on a clamped
half-plane, K + D on a layer) and a nodal tangent D made up for the test (stiff patches, non-symmetric, a few
negative entries):

* the coarse modes are solved exactly: M⁻¹ A Π Z c = Π Z c (fails on any wrong block of E = Zᵀ A Z: a kernel,
  the x–z transposition, the mean-removal terms);
* a product is A M⁻¹ y, one FFT pair (K K⁻¹ = Π, not a second pair);
* `gfmd.coupled_krylov.newton_step` solves (K + D) δu = f to its tolerance with either choice (K⁻¹ alone:
  `spectral_step`, also where no node is stiff); fewer products: tests/test_solver_coupled.py.
"""

from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.core import surfaces
from gfmd_contact.core.scene import load_scene
from gfmd import coupled_krylov, coupled_preconditioner, kernels
from gfmd.coupled_preconditioner import coarse_space, operators
from gfmd.fft import Fft
from gfmd.loading import prepare
from gfmd.problem import Elastic

BASE = Path(__file__).resolve().parents[1] / "studies" / "seed" / "seed_base.toml"
N = 256
BACKENDS = ["numpy"] + (["numba"] if kernels.numba is not None else [])  # the nodal passes (`coarse_passes`)


def coupled_cell(thickness="inf", nodes=N):
    scene = load_scene(BASE).replace(**{
        "surface.nodes": nodes, "surface.length": nodes * 2.5e-9, "surface.rollon_wavelength": 8 * 2.5e-9,
        "surface.rolloff_wavelength": nodes * 2.5e-9 / 4, "material.poisson_ratio": 0.1,
        "material.thickness": thickness, "interface.tangential_ratio": 0.5, "surface.realizations": 1})
    h = surfaces.profile(scene.surface, 0)
    return prepare(scene, h, 0), h, scene


def dense_operator(model, d, clamp):
    """A (2N × 2N) on nodal (x, z) columns: Π (K + D) Π (clamp) or K + D, K from the model's kernels by numpy."""
    n = model.nodes
    k = ((model.k_xx, model.k_xz), (np.conj(model.k_xz), model.k_zz))
    d_nn, d_nt, d_tn, d_tt = d
    a = np.zeros((2 * n, 2 * n))
    for col in range(2 * n):
        e = np.zeros((2, n))
        e[col // n, col % n] = 1.0
        spec = np.fft.rfft(e, axis=1)
        ke = np.array([np.fft.irfft(k[r][0] * spec[0] + k[r][1] * spec[1], n) for r in range(2)])
        de = np.array([d_tt * e[0] + d_tn * e[1], d_nt * e[0] + d_nn * e[1]])
        a[:, col] = (ke + de).ravel()
    if clamp:
        pi = np.kron(np.eye(2), np.eye(n) - 1.0 / n)
        a = pi @ a @ pi
    return a


def made_up_tangent(model, law, seed):
    """Stiff patches (D_nn ≈ k_n, D_tt ≈ k_t, non-symmetric D_nt, D_tn), soft elsewhere with some negative D_nn."""
    rng = np.random.default_rng(seed)
    n = model.nodes
    k_t, k_n = law.law.initial_stiffness
    patch = np.zeros(n, bool)
    for start, width in ((10, 30), (80, 5), (150, 60), (240, 25)):  # the last wraps around the cell's end
        patch[np.arange(start, start + width) % n] = True
    d_nn = np.where(patch, k_n * (1 + rng.random(n)), -0.05 * k_n * rng.random(n))
    d_tt = np.where(patch, k_t * (1 + rng.random(n)), 0.001 * k_t * rng.random(n))
    d_nt = np.where(patch, 0.3 * k_n * rng.standard_normal(n), 0.0)
    d_tn = np.where(patch, -0.2 * k_n * rng.standard_normal(n), 0.0)
    return d_nn, d_nt, d_tn, d_tt


def blocks_matrix(coarse, n):
    """Z (2N × 2m) from the blocks' starts and widths, Π applied where clamped."""
    z = np.zeros((n, coarse.m))
    for j, (a, p) in enumerate(zip(coarse.starts, coarse.widths)):
        z[a:a + p, j] = 1.0
    if coarse.clamp:
        z -= z.mean(axis=0)
    return np.kron(np.eye(2), z)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("thickness", ["inf", 2e-7])
def test_coarse_modes_are_solved_exactly(thickness, backend):
    cell, _, _ = coupled_cell(thickness)
    model, law = cell.physics, cell.law
    clamp = model.half_plane
    assert clamp == (thickness == "inf")
    fft, stiff = Fft(N), Elastic(model, 0.0, 0.0)
    d = made_up_tangent(model, law, 1)
    coarse = coarse_space(stiff, fft, d, law.law.initial_stiffness)
    assert coarse is not None and coarse.m >= 8
    a = dense_operator(model, d, clamp)
    inverse, _ = operators(coarse, stiff, fft, d, backend)
    z = blocks_matrix(coarse, N)
    rng = np.random.default_rng(2)
    for _ in range(3):
        zc = z @ rng.standard_normal(2 * coarse.m)
        back = np.fft.irfft(inverse((a @ zc).reshape(2, N)), N, axis=1).ravel()
        assert np.max(np.abs(back - zc)) < 1e-9 * np.max(np.abs(zc))
    # and not for a vector outside the coarse space (the check can fail)
    y = rng.standard_normal(2 * N)
    if clamp:
        y = (np.kron(np.eye(2), np.eye(N) - 1.0 / N) @ y)
    back = np.fft.irfft(inverse((a @ y).reshape(2, N)), N, axis=1).ravel()
    assert np.max(np.abs(back - y)) > 1e-3 * np.max(np.abs(y))


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("thickness", ["inf", 2e-7])
def test_product_is_the_operator_times_the_preconditioner(thickness, backend):
    cell, _, _ = coupled_cell(thickness)
    model, law = cell.physics, cell.law
    fft, stiff = Fft(N), Elastic(model, 0.0, 0.0)
    d = made_up_tangent(model, law, 3)
    coarse = coarse_space(stiff, fft, d, law.law.initial_stiffness)
    a = dense_operator(model, d, model.half_plane)
    inverse, product = operators(coarse, stiff, fft, d, backend)
    y = np.random.default_rng(4).standard_normal((2, N))
    if model.half_plane:
        y -= y.mean(axis=1, keepdims=True)
    before = fft.pairs
    out = product(y)
    assert fft.pairs - before == 1
    s = np.fft.irfft(inverse(y), N, axis=1)
    assert np.max(np.abs(out.ravel() - a @ s.ravel())) < 1e-9 * np.max(np.abs(out))


def test_no_stiff_node_no_coarse_space():
    cell, _, _ = coupled_cell()
    model, law = cell.physics, cell.law
    soft = tuple(np.zeros(N) for _ in range(4))
    assert coarse_space(Elastic(model, 0.0, 0.0), Fft(N), soft, law.law.initial_stiffness) is None


def test_newton_step_solves_to_its_tolerance(monkeypatch):
    """A coupled state with the indenter 2 nm into the profile (u = 0): (K + D) δu = f to rtol with either
    preconditioner (the true residual, by the dense A). Fewer products on real Newton systems:
    tests/test_solver_coupled.py::test_two_level_newton_needs_fewer_products."""
    cell, h, _ = coupled_cell(nodes=1024)
    model, law = cell.physics, cell.law
    n = model.nodes
    z_ind = h - np.min(h) - 2e-9  # the gap Δn = z_ind − u_z: 2 nm of compression at the lowest node, most far
    u = np.zeros((2, n))
    fft, stiff = Fft(n), Elastic(model, 0.0, 0.0)
    f_hat, f, _ = coupled_krylov.balance(law, z_ind, fft, stiff, True)(fft.rfft(u))
    tangent = law.law.tangent(z_ind - u[-1], -u[0])
    assert coupled_preconditioner.coarse_space(stiff, fft, tangent, law.law.initial_stiffness) is not None
    a = dense_operator(model, tuple(np.broadcast_to(x, (n,)) for x in tangent), True)
    for choice in ("two-level", "stiffness"):
        monkeypatch.setattr(coupled_preconditioner, "CHOICE", choice)
        du_hat, info = coupled_krylov.newton_step(model, law, z_ind, u, f_hat, stiff, fft, 1e-6)
        assert info == 0
        du = np.fft.irfft(du_hat, n, axis=1).ravel()
        assert np.linalg.norm(a @ du - f.ravel()) <= 1.01e-6 * np.linalg.norm(f)


def test_unknown_choice_names_the_setting(monkeypatch):
    cell, h, _ = coupled_cell()
    model, law = cell.physics, cell.law
    fft, stiff = Fft(N), Elastic(model, 0.0, 0.0)
    monkeypatch.setattr(coupled_preconditioner, "CHOICE", "multigrid")
    u = np.zeros((2, N))
    with pytest.raises(ValueError, match="coupled_preconditioner.CHOICE"):
        coupled_krylov.newton_step(model, law, h, u, fft.rfft(u), stiff, fft, 1e-3)


def test_stiffness_operator_is_kept_per_model_and_its_kernel_sums_computed_once(monkeypatch):
    """`gfmd.problem.stiffness_operator`: K(q) of a model, one object per model (equal to Elastic(model, 0, 0)), a new
    one for another model, none keeping a model alive; the coarse spaces' kernel sums cached on it are computed once per model
    however many Newton solves use them (K's three blocks: three calls of `kernel_sums`), once more for a new model."""
    import dataclasses
    import gc
    import weakref

    from gfmd import cohesive_preconditioner
    from gfmd.algorithms import coupled_newton
    from gfmd.problem import Problem, stiffness_operator
    from gfmd.solver import Settings

    cell, h, _ = coupled_cell(nodes=1024)
    model, law = cell.physics, cell.law
    op = stiffness_operator(model)
    assert stiffness_operator(model) is op
    plain = Elastic(model, 0.0, 0.0)
    for a, b in zip(op.mass + op.inv_mass, plain.mass + plain.inv_mass):
        np.testing.assert_array_equal(a, b)
    calls = []
    counted = cohesive_preconditioner.kernel_sums
    monkeypatch.setattr(coupled_preconditioner, "kernel_sums", lambda *a: calls.append(1) or counted(*a))
    start = np.zeros((2, model.nodes // 2 + 1), complex)
    for depth in (1e-9, 1.5e-9, 2e-9):  # three steps, each engaging the coarse space
        problem = Problem(model, law, h - np.min(h) - depth, 0.0)
        coupled_newton.solve(problem, start, Settings(tolerance=1e-6))
    assert len(calls) == 3
    other = dataclasses.replace(model)
    assert stiffness_operator(other) is not op
    coupled_newton.solve(Problem(other, law, h - np.min(h) - 1e-9, 0.0), start, Settings(tolerance=1e-6))
    assert len(calls) == 6
    gone = weakref.ref(other)
    del other
    gc.collect()
    assert gone() is None  # nothing holds a model beyond its life
