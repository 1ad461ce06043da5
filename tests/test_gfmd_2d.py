"""GFMD on 2+1-D surfaces (the 2+1-D contract): Model.shape = (Nx, Ny),
û of shape (1, Nx, Ny//2 + 1), real fields (Nx, Ny), normal-only.

The 2-D models are built by hand here (`surface_model`: `gfmd_contact.core.kernels.wavevector_magnitudes` and
`halfplane_normal`), so these tests do not depend on the scene layer's 2-D branch.

* (a) a 1-D sinusoid embedded in 2-D (constant along y) relaxes to the 1+1-D result: u, t_z, p̄, a_rel and
  the FFT pairs per step, hard wall (dual CG → primal CG, projected FIRE and Verlet), normal CZ (NCG, FIRE,
  Verlet) and the cohesive wall (projected FIRE);
* (b) a single mode (plane wave, egg-box, the q_y = 0 and Nyquist columns of the half-spectrum):
  `Problem.energy` = A (E*|q|/4) ⟨u²⟩, `Problem.force` = −(E*|q|/2) u, `tangent_times` = K u and
  `dual_gap` = z_ind + G P, |q| and E* written here;
* (c) a self-affine surface: the hard-wall KKT conditions, recomputed with numpy's FFT and a kernel
  written here, hold to the solver's tolerance; dual and primal CG agree; the NCG's force balance;
* (d) FFT pairs per step are counted on the 2-D transforms, and the rfft2 half-spectrum's Parseval
  weights; a tangential 2+1-D model is refused naming the keys.

Tolerances: a converged step has max|f| < τ p_ref (τ = Settings.tolerance); two such states of the same
problem differ by at most |Δu| ≤ 2 τ p_ref √N / k_min in displacement (K ≥ k_min = πE*/L on the
clamped half-plane, ‖·‖_max ≤ ‖·‖_2 ≤ √N ‖·‖_max), and their tractions by K_max |Δu| + 2 τ p_ref. Pure
linear algebra (b) is exact up to round-off: relative 4 N ε (an N-term sum, two FFTs).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gfmd_contact.core.kernels import halfplane_normal, wavevector_magnitudes
from gfmd_contact.core.loading import indenter_surface
from gfmd_contact.core.model import build_model
from gfmd_contact.core.observables import contact_mask
from gfmd_contact.core.scene import default_scene
from gfmd import fft as gfft
from gfmd.chains import SURFACE_NORMAL_ONLY, relax
from gfmd.links import Link
from gfmd.loading import GfmdCell
from gfmd.problem import InterfaceLaw, Problem
from gfmd.settings import Settings

EPS = np.finfo(float).eps
LENGTH = 1.0e-6
NODES = 64
AMPLITUDE = 10e-9
TOLERANCE = 1e-10


def surface_model(profile_model, nodes_y, length_y, youngs_modulus, poisson_ratio):
    """The 2+1-D model of a profile model's law and body on an Nx × Ny grid (Nx, Lx of the profile)."""
    q = wavevector_magnitudes(profile_model.nodes, profile_model.length, nodes_y, length_y)
    return dataclasses.replace(profile_model, nodes=profile_model.nodes * nodes_y, q=q,
                               k_zz=np.asarray(halfplane_normal(q, youngs_modulus, poisson_ratio)),
                               shape=(profile_model.nodes, nodes_y), length_y=length_y)


def sinusoid_scene(law):
    return default_scene().replace(**{"surface.kind": "sinusoid", "surface.amplitude": AMPLITUDE,
                                      "surface.nodes": NODES, "surface.length": LENGTH, "interface.law": law,
                                      "interface.length_normal": 2e-9})


@pytest.fixture(scope="module", params=["hard-wall", "cohesive"])
def embedded(request):
    """(scene, 1-D model, 2-D model, h (N,), h2 (N, Ny)): the sinusoid and the same sinusoid constant along y."""
    sc = sinusoid_scene(request.param)
    x = np.arange(NODES) * LENGTH / NODES
    h = AMPLITUDE * np.cos(2 * np.pi * x / LENGTH)
    m1 = build_model(sc, h)
    ny = 8
    m2 = surface_model(m1, ny, LENGTH / 4, sc.material.youngs_modulus, sc.material.poisson_ratio)
    return sc, m1, m2, h, np.repeat(h[:, None], ny, axis=1)


def bounds(model, tolerance):
    """(|Δu|_max, |Δt|_max) between two converged states of the same problem (module docstring)."""
    e_star = model.contact_modulus
    k_min = np.pi * e_star / model.length
    k_max = float(np.max(np.real(model.k_zz)))
    du = 2 * tolerance * model.reference_traction * np.sqrt(model.nodes) / k_min
    return du, k_max * du + 2 * tolerance * model.reference_traction


def test_embedded_sinusoid_equals_profile(embedded):
    """(a) u, t_z, p̄, a_rel and FFT pairs of the sinusoid constant along y = the 1+1-D step's, at loads from a
    small contact to near full contact (hard wall: the dual CG, then its hand-over to the primal)."""
    sc, m1, m2, h, h2 = embedded
    settings = Settings(tolerance=TOLERANCE)
    d0 = sc.loading.initial_separation
    wall_tolerance = 1e-12 * 2 * AMPLITUDE
    du, dt = bounds(m2, TOLERANCE)
    methods = set()
    for push in (3e-9, 8e-9, 9.9e-9):
        z1, z2 = indenter_surface(h, d0, d0 + push), indenter_surface(h2, d0, d0 + push)
        # the profile with the algorithms a surface runs (the dual CG's band preconditioner, the NCG's K⁻¹: a
        # surface has no two-level CG and no two-level NCG preconditioner)
        r1 = relax(m1, InterfaceLaw(m1), z1, np.zeros((1, NODES // 2 + 1), complex),
                   dataclasses.replace(settings, dual_coarse_block=0, cohesive_preconditioner="stiffness"),
                   wall_tolerance)
        r2 = relax(m2, InterfaceLaw(m2), z2, np.zeros((1,) + m2.spectrum_shape, complex), settings, wall_tolerance)
        assert r1.converged and r2.converged, (r1.message, r2.message)
        assert r2.u_hat.shape == (1, NODES, 8 // 2 + 1) and r2.u_z.shape == r2.t_z.shape == r2.gap.shape == (NODES, 8)
        assert r2.method == r1.method
        methods.add(r2.method)
        assert np.max(np.abs(r2.u_z - r1.u_z[:, None])) <= du
        assert np.max(np.abs(r2.t_z - r1.t_z[:, None])) <= dt
        assert abs(np.mean(r2.t_z) - np.mean(r1.t_z)) <= dt
        a1 = np.mean(contact_mask(m1.law, r1.gap, r1.t_z))
        a2 = np.mean(contact_mask(m2.law, r2.gap, r2.t_z))
        assert abs(a2 - a1) <= 2.0 / NODES  # at most one column flips at each contact edge
        if r1.method != "cg-dual":  # the same iterates (the dual CG's 2-D window preconditioner is not the band)
            # one rfft2/irfft2 pair counted as one pair: the same cost per iteration. The 1+1-D and 2+1-D transforms
            # sum in different orders, so the iterates agree to round-off, not bit for bit, and a branch near its
            # threshold (the stop, a line-search bracket) may go the other way: measured 53 vs 55 iterations and
            # 5.0 vs 5.5 extra pairs (scipy.fft + numpy kernels, the fresh venv without the `fast` extra), 0 and 1
            # with ducc0 + numba; allowed: 10 % of the iterations (at least one) and the same pairs per iteration
            # to 10 %
            assert abs(r2.iterations - r1.iterations) <= max(1, 0.1 * r1.iterations)
            assert r2.fft_pairs / r2.iterations == pytest.approx(r1.fft_pairs / r1.iterations, rel=0.1)
    if m1.law.constraint:
        assert methods == {"cg-dual", "cg-dual→cg"}
    else:
        assert methods == {"ncg"}


@pytest.mark.parametrize("law, options, label", [
    ("hard-wall", {"hard_wall": "fire"}, "fire"), ("hard-wall", {"method": "verlet"}, "verlet"),
    ("cohesive", {"cohesive": "fire"}, "fire"), ("cohesive", {"method": "verlet"}, "verlet")])
def test_embedded_sinusoid_dynamics(law, options, label):
    """(a) the damped dynamics (projected FIRE / Verlet on the hard wall, FIRE / Verlet on the CZ) on the embedded
    sinusoid: the profile's state within the bounds, one mid-contact step."""
    sc = sinusoid_scene(law)
    x = np.arange(NODES) * LENGTH / NODES
    h = AMPLITUDE * np.cos(2 * np.pi * x / LENGTH)
    m1 = build_model(sc, h)
    m2 = surface_model(m1, 4, LENGTH / 8, sc.material.youngs_modulus, sc.material.poisson_ratio)
    d0 = sc.loading.initial_separation
    settings = Settings(tolerance=1e-9, **options)
    du, dt = bounds(m2, 1e-9)
    push = 8e-9
    r1 = relax(m1, InterfaceLaw(m1), indenter_surface(h, d0, d0 + push), np.zeros((1, NODES // 2 + 1), complex),
               settings, 1e-12 * 2 * AMPLITUDE)
    r2 = relax(m2, InterfaceLaw(m2), indenter_surface(np.repeat(h[:, None], 4, axis=1), d0, d0 + push),
               np.zeros((1,) + m2.spectrum_shape, complex), settings, 1e-12 * 2 * AMPLITUDE)
    assert r1.converged and r2.converged and r1.method == r2.method == label
    assert np.max(np.abs(r2.u_z - r1.u_z[:, None])) <= du
    assert np.max(np.abs(r2.t_z - r1.t_z[:, None])) <= dt


def test_embedded_sinusoid_cohesive_wall():
    """(a) the cohesive wall's projected FIRE on the embedded sinusoid: the profile's state within the bounds."""
    sc = sinusoid_scene("cohesive-wall")
    x = np.arange(NODES) * LENGTH / NODES
    h = AMPLITUDE * np.cos(2 * np.pi * x / LENGTH)
    m1 = build_model(sc, h)
    m2 = surface_model(m1, 4, LENGTH / 8, sc.material.youngs_modulus, sc.material.poisson_ratio)
    h2 = np.repeat(h[:, None], 4, axis=1)
    d0 = sc.loading.initial_separation
    settings = Settings(tolerance=TOLERANCE)
    du, dt = bounds(m2, TOLERANCE)
    for push in (3e-9, 9.9e-9):
        r1 = relax(m1, InterfaceLaw(m1), indenter_surface(h, d0, d0 + push), np.zeros((1, NODES // 2 + 1), complex),
                   settings, 1e-12 * 2 * AMPLITUDE)
        r2 = relax(m2, InterfaceLaw(m2), indenter_surface(h2, d0, d0 + push),
                   np.zeros((1,) + m2.spectrum_shape, complex), settings, 1e-12 * 2 * AMPLITUDE)
        assert r1.converged and r2.converged
        assert np.max(np.abs(r2.u_z - r1.u_z[:, None])) <= du
        assert np.max(np.abs(r2.t_z - r1.t_z[:, None])) <= dt


@pytest.fixture(scope="module")
def free_surface():
    """A hard-wall problem on a 48 × 36 grid, non-square cell, with the wall far away (energy purely elastic)."""
    sc = default_scene().replace(**{"surface.nodes": 48, "surface.length": LENGTH, "interface.law": "hard-wall",
                                    "surface.rollon_wavelength": 4 * LENGTH / 48})
    m1 = build_model(sc)
    ly = 0.6 * LENGTH
    m2 = surface_model(m1, 36, ly, sc.material.youngs_modulus, sc.material.poisson_ratio)
    problem = Problem(m2, InterfaceLaw(m2), np.ones(m2.grid))
    e_star = sc.material.youngs_modulus / (1 - sc.material.poisson_ratio**2)
    return problem, e_star, LENGTH, ly


@pytest.mark.parametrize("modes", [[(3, 2)], [(0, 5)], [(5, 0)], [(24, 18)], [(2, 3), (2, -3)], [(7, -4)]],
                         ids=["plane-wave", "qx=0", "qy=0-column", "nyquist-corner", "egg-box", "negative-qy"])
def test_single_mode_energy_and_force(free_surface, modes):
    """(b) u = a Σ cos(q·x) over modes of one |q|: E = ½ A ⟨u K u⟩ = A (E*|q|/4) ⟨u²⟩ (J; a plane wave:
    A (E*|q|/4) Σ_±q |û_q|² with û_±q = a/2) and f = −(E*|q|/2) u (Pa),
    with |q| = 2π |(m_x/L_x, m_y/L_y)| and E* = E/(1 − ν²) computed here."""
    problem, e_star, lx, ly = free_surface
    nx, ny = problem.model.grid
    x = (np.arange(nx) * lx / nx)[:, None]
    y = (np.arange(ny) * ly / ny)[None, :]
    a = 1e-9
    u = sum(a * np.cos(2 * np.pi * (mx * x / lx + my * y / ly)) for mx, my in modes)
    if len(modes) == 2:  # the egg-box: 2 a cos(q_x x) cos(q_y y) → a cos(q_x x) cos(q_y y)
        u = u / 2
    q = {float(np.hypot(2 * np.pi * mx / lx, 2 * np.pi * my / ly)) for mx, my in modes}
    assert len(q) == 1
    q = q.pop()
    u_hat = np.fft.rfft2(u)[None]  # numpy's, not gfmd.fft's
    area = lx * ly
    energy = problem.energy(u_hat)
    expected = area * (e_star * q / 4) * np.mean(u**2)
    n = problem.model.nodes
    assert energy == pytest.approx(expected, rel=4 * n * EPS, abs=0)
    force = problem.force(u_hat)
    assert force.shape == (1, nx, ny)
    assert np.max(np.abs(force[0] + e_star * q / 2 * u)) <= 4 * n * EPS * e_star * q / 2 * a
    assert np.allclose(problem.displacements(u_hat)[0], u, rtol=0, atol=4 * n * EPS * a)
    # the Hessian product (hard wall: K v) and the dual's gap z_ind + G P for a pressure of the same mode
    stiffness = e_star * q / 2
    kv = problem.tangent_times(u_hat, u[None])
    assert np.max(np.abs(kv[0] - stiffness * u)) <= 4 * n * EPS * stiffness * a
    pressure = stiffness * u  # G P = u
    on_plane = dataclasses.replace(problem, z_ind=np.zeros(problem.model.grid))
    assert np.max(np.abs(on_plane.dual_gap(pressure) - u)) <= 4 * n * EPS * a


def self_affine(grid, lengths, hurst, h_rms, seed):
    """An isotropic self-affine height map (m), C(q) ∝ |q|^(−2−2H) between 2π/(L_x/4) and 2π/(4 l), random phases
    (written here: the scene layer's generator is another helper's)."""
    nx, ny = grid
    qx = 2 * np.pi * np.fft.fftfreq(nx, lengths[0] / nx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, lengths[1] / ny)
    q = np.hypot(qx[:, None], qy[None, :])
    q_r, q_s = 2 * np.pi / (lengths[0] / 4), 2 * np.pi / (4 * lengths[0] / nx)
    amp = np.where((q > 0) & (q <= q_s), np.maximum(q, q_r) ** (-1 - hurst), 0.0)
    rng = np.random.default_rng(seed)
    h = np.real(np.fft.ifft2(amp * np.exp(2j * np.pi * rng.random(grid))))
    return h * h_rms / np.std(h)


@pytest.fixture(scope="module")
def rough():
    """The hard wall on a 64 × 64 self-affine surface (H = 0.8, h_rms = 2 nm), and its pressing solved."""
    sc = default_scene().replace(**{"surface.nodes": 64, "surface.length": LENGTH, "interface.law": "hard-wall",
                                    "surface.rollon_wavelength": 4 * LENGTH / 64})
    h = self_affine((64, 64), (LENGTH, LENGTH), 0.8, 2e-9, 7)
    m1 = build_model(sc, h[:, 0])
    m2 = surface_model(m1, 64, LENGTH, sc.material.youngs_modulus, sc.material.poisson_ratio)
    e_star = sc.material.youngs_modulus / (1 - sc.material.poisson_ratio**2)
    return sc, m2, h, e_star


def kkt_residuals(model, h_z, z_ind, u, e_star):
    """(max |f| off the wall, min reaction on the wall, max penetration, p_far) of a hard-wall state u (Nx, Ny),
    from numpy's FFT and K = E*|q|/2 written here; f = p_far − K u, p_far = ⟨K u⟩ over the free nodes."""
    nx, ny = model.grid
    qx = 2 * np.pi * np.fft.fftfreq(nx, model.length / nx)
    qy = 2 * np.pi * np.fft.rfftfreq(ny, model.length_y / ny)
    k = e_star / 2 * np.hypot(qx[:, None], qy[None, :])
    ku = np.fft.irfft2(k * np.fft.rfft2(u), s=(nx, ny))
    on_wall = z_ind - u <= 1e-12 * float(np.ptp(h_z))
    p_far = float(np.mean(ku[~on_wall]))
    f = p_far - ku
    reaction = float(np.min(f[on_wall])) if on_wall.any() else np.inf
    return float(np.max(np.abs(f[~on_wall]))), reaction, float(np.max(u - z_ind)), p_far, ku


@pytest.mark.parametrize("solver", ["dual", "primal"], ids=["dual-cg", "primal-cg"])
def test_hard_wall_kkt_self_affine(rough, solver):
    """(c) KKT on a self-affine surface at a_rel ≈ 1–40 %: zero force off the wall, compressive reaction on it,
    no penetration (all to τ p_ref plus the FFT round-off ε log2 N K_max max|u|), mean pressure = far-field
    load; dual and primal CG agree within the bounds."""
    sc, model, h, e_star = rough
    settings = Settings(tolerance=1e-9)
    chain = (Link("hard_wall_primal_cg"),) if solver == "primal" else None  # `relax`'s own chain: the primal alone
    d0 = sc.loading.initial_separation
    guess = np.zeros((1,) + model.spectrum_shape, complex)
    states = []
    for rigid in (0.02, 0.05, 0.1):  # the fraction of the nodes a rigid pressing (u = 0) would overlap
        push = float(np.quantile(h, rigid) - np.min(h))
        z = indenter_surface(h, d0, d0 + push)
        r = relax(model, InterfaceLaw(model), z, guess, settings, 1e-12 * float(np.ptp(h)), chain=chain)
        assert r.converged, r.message
        guess = r.u_hat
        a_rel = float(np.mean(contact_mask(model.law, r.gap, r.t_z)))
        assert 0.005 < a_rel < 0.5
        test_hard_wall_kkt_self_affine.a_rel.append(a_rel)
        k_max = float(np.max(np.real(model.k_zz)))
        roundoff = EPS * np.log2(model.nodes) * k_max * float(np.max(np.abs(r.u_z))) * 10
        tol = settings.tolerance * model.reference_traction + roundoff
        off, reaction, penetration, p_far, _ = kkt_residuals(model, h, z, r.u_z, e_star)
        assert off <= tol
        assert reaction >= -tol
        assert penetration <= 1e-12 * float(np.ptp(h))
        assert -float(np.mean(r.t_z)) == pytest.approx(p_far, rel=0, abs=tol)
        assert r.fft_pairs > r.iterations  # (d) counted: at least one pair per CG iteration
        states.append(r.u_z)
    test_hard_wall_kkt_self_affine.states[solver] = states


test_hard_wall_kkt_self_affine.states = {}
test_hard_wall_kkt_self_affine.a_rel = []


def test_dual_and_primal_agree(rough):
    """(c) the dual and the primal CG reach the same states (run after the KKT tests; within the bounds)."""
    states = test_hard_wall_kkt_self_affine.states
    if len(states) < 2:
        pytest.skip("needs both KKT tests of this module")
    du, _ = bounds(rough[1], 1e-9)
    for a, b in zip(states["dual"], states["primal"]):
        assert np.max(np.abs(a - b)) <= du


def test_cohesive_ncg_self_affine(rough):
    """(c) the NCG on the self-affine surface with Eq. 3: the force T_n(Δn) − K u (mean removed), recomputed with
    numpy's FFT, below τ p_ref plus round-off; the initial_state of the cell has the 2-D spectrum shape."""
    sc, model, h, e_star = rough
    sc = sc.replace(**{"interface.law": "cohesive", "interface.length_normal": 0.5e-9})
    m1 = build_model(sc, h[:, 0])
    m2 = surface_model(m1, 64, LENGTH, sc.material.youngs_modulus, sc.material.poisson_ratio)
    cell = GfmdCell(scene=sc, h=h, physics=m2, law=InterfaceLaw(m2), settings=Settings(tolerance=1e-9), method="x")
    guess = cell.initial_state()
    assert guess.shape == (1, 64, 33)
    d0 = sc.loading.initial_separation
    z = indenter_surface(h, d0, d0 + 2e-9)
    r = relax(m2, InterfaceLaw(m2), z, guess, Settings(tolerance=1e-9), 0.0)
    assert r.converged and r.method == "ncg", r.message
    t_n = m2.law.tractions(r.gap)[0]
    _, _, _, _, ku = kkt_residuals(m2, h, np.full(m2.grid, np.inf), r.u_z, e_star)
    f = t_n - np.mean(t_n) - (ku - np.mean(ku))
    roundoff = EPS * np.log2(m2.nodes) * float(np.max(np.real(m2.k_zz))) * float(np.max(np.abs(r.u_z))) * 10
    assert float(np.max(np.abs(f))) <= 1e-9 * m2.reference_traction + roundoff
    assert np.array_equal(r.t_z, t_n)


@pytest.mark.parametrize("grid", [(8, 6), (7, 5), (6, 9)])
def test_half_spectrum_weights_parseval(grid):
    """(d) Σ_j a_j b_j = (1/N) Σ w Re(conj(â) b̂) on the flat rfft2 half-spectrum, even and odd N_y; the NCG's
    fused products the same sums (gfmd.kernels)."""
    from gfmd import kernels
    rng = np.random.default_rng(1)
    n = grid[0] * grid[1]
    a, b, c = (rng.standard_normal(n) for _ in range(3))
    g = rng.random(grid[0] * (grid[1] // 2 + 1))
    fft = gfft.Fft(n, "scipy", grid)
    ah, bh, ch = fft.rfft(a), fft.rfft(b), fft.rfft(c)
    w = gfft.spectral_weights(grid)
    scale = np.sqrt(n) * 8 * n * EPS
    assert np.sum(w * (np.conj(ah) * ch).real) / n == pytest.approx(a @ c, abs=scale)
    s = fft.irfft(g * ah)
    for name in ("numpy", "numba"):
        if name == "numba" and kernels.numba is None:
            continue
        products, _, _ = kernels.ncg_kernels(name, grid)
        got = products(ah, bh, ch, g, n)
        assert got == pytest.approx((a @ s, b @ s, a @ c), abs=scale * float(np.max(g)))
    assert fft.pairs == 2.0  # 3 rfft2 and one irfft2


def test_ffts_agree_on_the_grid():
    """(d) scipy and ducc0 (where installed) 2-D transforms on flat fields: rfft = numpy's rfft2, round trip."""
    grid = (12, 10)
    x = np.random.default_rng(2).standard_normal(grid)
    for backend in ("scipy", "ducc0"):
        if backend == "ducc0" and gfft._ducc_fft is None:
            continue
        fft = gfft.Fft(120, backend, grid)
        spectrum = fft.rfft(x.ravel())
        assert np.allclose(spectrum, np.fft.rfft2(x).ravel(), rtol=0, atol=64 * EPS * np.abs(x).sum())
        assert np.allclose(fft.irfft(spectrum), x.ravel(), rtol=0, atol=64 * EPS * np.abs(x).max())
        out = np.empty(120)
        kernel = np.arange(spectrum.size, dtype=float)
        fft.apply_to(kernel, x.ravel(), out)
        assert np.allclose(out, np.fft.irfft2(kernel.reshape(12, 6) * np.fft.rfft2(x), s=grid).ravel(),
                           rtol=0, atol=64 * EPS * np.abs(x).sum() * kernel.max())
        assert fft.pairs == 2.0


def test_tangential_surface_refused():
    """A 2+1-D model with tangential unknowns is refused, naming the keys and why."""
    sc = sinusoid_scene("cohesive").replace(**{"surface.nodes": 16, "interface.tangential_ratio": 0.5,
                                               "material.poisson_ratio": 0.3})
    m1 = build_model(sc)
    assert m1.tangential
    m2 = dataclasses.replace(m1, shape=(16, 4), nodes=64, length_y=sc.surface.length)
    with pytest.raises(ValueError) as err:
        relax(m2, InterfaceLaw(m2), np.ones((16, 4)), np.zeros((2, 16, 3), complex), Settings())
    assert str(err.value) == SURFACE_NORMAL_ONLY
    assert "interface.tangential_ratio" in SURFACE_NORMAL_ONLY and "normal-only" in SURFACE_NORMAL_ONLY


@pytest.mark.parametrize("push", [2e-9, 4e-9])
def test_hertz_sphere(push):
    """A paraboloid h = r²/(2R) (R = 5 µm) on a 128² cell pressed by the hard wall against Hertz (Johnson 1985,
    §4.2; written here): p_max = p0 = (6 F E*²/(π³ R²))^(1/3) from the total force F, and F = 4E* a³/(3R) with a
    from the contact area. Bounds: the periodic images change the pressure by O((a/L)³) (measured
    p_max/p0 − 1 = 1.3 (a/L)³ for a/L = 0.11–0.26, N = 64–256, the same at every N: allowed 2 (a/L)³, plus
    2 (l/a)² for the peak's sampling on the grid); a counted from whole nodes is uncertain by one ring, |Δa| ≤ l,
    so |ΔF/F| ≤ 3 l/a."""
    n, radius = 128, 5e-6
    sc = sinusoid_scene("hard-wall").replace(**{"surface.nodes": n})
    x = (np.arange(n) - n // 2) * LENGTH / n
    h = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius)
    m1 = build_model(sc, h[:, n // 2])
    model = surface_model(m1, n, LENGTH, sc.material.youngs_modulus, sc.material.poisson_ratio)
    e_star = sc.material.youngs_modulus / (1 - sc.material.poisson_ratio**2)
    d0 = sc.loading.initial_separation
    z = indenter_surface(h, d0, d0 + push)
    r = relax(model, InterfaceLaw(model), z, np.zeros((1,) + model.spectrum_shape, complex), Settings(tolerance=1e-10),
              1e-12 * float(np.ptp(h)))
    assert r.converged, r.message
    pressure = -r.t_z
    force = float(np.sum(pressure)) * model.node_area
    contact = contact_mask(model.law, r.gap, r.t_z)
    a = np.sqrt(np.count_nonzero(contact) * model.node_area / np.pi)
    spacing = LENGTH / n
    assert 10 < a / spacing and a / LENGTH < 0.2  # resolved, and a small contact in its cell
    p0 = (6 * force * e_star**2 / (np.pi**3 * radius**2)) ** (1 / 3)
    assert abs(float(np.max(pressure)) / p0 - 1) <= 2 * (a / LENGTH) ** 3 + 2 * spacing / a * (spacing / a)
    assert abs(force / (4 * e_star * a**3 / (3 * radius)) - 1) <= 3 * spacing / a


def test_surface_shapes_checked(embedded):
    """A height map or a state that does not fit the 2+1-D grid is a clear error naming the array."""
    _, _, m2, _, h2 = embedded
    state = np.zeros((1,) + m2.spectrum_shape, complex)
    with pytest.raises(ValueError, match="z_ind has shape"):
        relax(m2, InterfaceLaw(m2), h2.T, state, Settings())
    with pytest.raises(ValueError, match="u_hat has shape"):
        relax(m2, InterfaceLaw(m2), h2, state[:, :, :-1], Settings())
