"""3-D FE reference (reference.fem3d): hard wall, normal cohesive zone, observables, VTU, bad input.

Flat punch / uniform compression against M/D (exact for Q1), the hard-wall sinusoid (1-D embedded and
egg-box) in full contact against the layer formula with the FE's measured mode-stiffness error
(verification/data/mesh/fem3d_stiffness.json, the same mesh family), the flat cohesive layer against the scalar
equilibrium (M/D) u = T_n(z − u), and the law's own consistency T_n = dV/dΔn (= −∂V/∂u_z).
"""

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from gfmd_contact.core.kernels import layer_normal
from reference.fem3d import export_vtu, solve_cell
from reference.fem3d.law import NormalCohesiveZone
from reference.fem3d.observables import contact_mask, gradient_squared

DATA = json.loads((Path(__file__).resolve().parent.parent / "verification" / "data" / "mesh" / "fem3d_stiffness.json")
                  .read_text())
E, NU, L = 1.0, 0.3, 1.0
E_STAR = E / (1 - NU**2)
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
GROWTH = 8.0


def family(n):
    """(layers, top) of the mesh family of tests/test_fem3d_stiffness.py."""
    layers = n // 2
    ratio = GROWTH ** (1 / layers)
    return dict(layers=layers, top=L * (ratio - 1) / (GROWTH - 1))


def test_flat_punch_compresses_the_layer_by_m_over_d():
    """Flat rigid punch, hard wall: full contact, uniaxial strain, p = M U/D to round-off, u_z = −U."""
    d = 0.8 * L
    out = solve_cell(np.zeros((8, 6)), L, 1.2 * L, E, NU, d, [0.0, 1e-3, 2e-3], law="hard-wall", layers=5)
    assert np.allclose(out.curve["p"], M * np.array([0.0, 1e-3, 2e-3]) / d, rtol=1e-10, atol=1e-16)
    assert list(out.curve["a_rel"][1:]) == [1.0, 1.0] and out.curve["converged"].all()
    assert np.allclose(out.fields[2]["u_z"], -2e-3, rtol=1e-10)
    assert np.allclose(out.curve["reaction_p"], out.curve["p"], rtol=1e-10, atol=1e-16)


@pytest.mark.parametrize("n, mode", [(16, (1, 0)), (16, (1, 1)), (32, (1, 1)),
                                     pytest.param(64, (1, 1), marks=pytest.mark.slow)])
def test_hard_wall_sinusoid_in_full_contact(n, mode):
    """h = A cos(2πx/L) (the 1-D sinusoid embedded) or A cos(2πx/L) cos(2πy/L) (egg-box, a sum of the
    (±1, ±1) modes) pressed into full contact: u_z = z_ind = h + A − U, so t_z = −(M/D)(U − A) + k h
    (z_ind is higher, the contact lighter, where h is higher: reference-formulas §0), with the FE's k
    equal to the layer formula's up to the measured mode error at this mesh (data file)."""
    amp = 1e-3
    i = np.arange(n) / n
    shape = np.cos(2 * np.pi * i)[:, None] * (np.cos(2 * np.pi * i)[None, :] if mode == (1, 1) else np.ones(n))
    h = amp * shape
    q = 2 * np.pi * np.hypot(*mode) / L
    k = layer_normal(np.array([q]), E, NU, L)[0]
    u_full = amp * (1 + 1.5 * k * L / M)  # beyond the full-contact threshold A(1 + k D/M)
    u_partial = amp * 0.5
    out = solve_cell(h, L, L, E, NU, L, [u_partial, u_full], law="hard-wall", **family(n))
    assert out.curve["converged"].all()
    assert 0 < out.curve["a_rel"][0] < 1 and out.curve["a_rel"][1] == 1.0
    p_mean = M * (u_full - amp) / L  # z_ind = h − min h − U: mean u_z = A − U
    assert out.curve["p"][1] == pytest.approx(p_mean, rel=1e-10)
    wave = out.fields[1]["t_n"] + p_mean  # = k_FE A shape
    k_fe = np.sum(wave * shape) / np.sum(shape * shape) / amp
    measured = DATA["relative_error_vs_layer"][str(n)][f"{mode[0]},{mode[1]}"]
    assert k_fe / k - 1 == pytest.approx(measured, rel=1e-6)
    assert np.max(np.abs(wave - k_fe * amp * shape)) <= 1e-9 * k * amp  # a single mode, no other
    assert np.allclose(out.fields[1]["gap"], 0.0, atol=1e-12 * amp)


def test_cohesive_law_is_consistent():
    """T_n = dV/dΔn and dT_n/dΔn by central differences (error ≤ (δ²/6)|f'''| + round-off), V(0) = −φn,
    peak φn/(e δn) at Δn = δn, ∫₀^∞ T_n dΔn = φn, T_n(Δtol) = tolerance·φn/δn past the peak."""
    law = NormalCohesiveZone.from_dimensionless(0.05, 1e-3, 2.0)
    assert law.phi_n == pytest.approx(0.05 * 1e-3 * 2.0, rel=1e-15)
    gap = np.linspace(-2e-3, 8e-3, 41)
    step = 1e-7
    fd = (law.potential(gap + step) - law.potential(gap - step)) / (2 * step)
    scale = law.phi_n / law.delta_n * np.exp(2.0)  # |T| bound on the range (Δn ≥ −2 δn)
    bound = step**2 / law.delta_n**2 * scale + 1e-16 * law.phi_n * np.exp(2.0) / step
    assert np.max(np.abs(fd - law.traction(gap))) <= bound
    fd2 = (law.traction(gap + step) - law.traction(gap - step)) / (2 * step)
    assert np.max(np.abs(fd2 - law.slope(gap))) <= bound / law.delta_n
    assert law.potential(0.0) == pytest.approx(-law.phi_n, rel=1e-15)
    assert law.traction(law.delta_n) == pytest.approx(law.phi_n / (np.e * law.delta_n), rel=1e-15)
    assert law.slope(law.delta_n) == 0.0
    s = np.linspace(0, 60, 200001) * law.delta_n
    assert np.trapezoid(law.traction(s), s) == pytest.approx(law.phi_n, rel=1e-8)
    tol_gap = law.contact_gap(1e-3)
    assert tol_gap > law.delta_n
    assert law.traction(tol_gap) == pytest.approx(1e-3 * law.phi_n / law.delta_n, rel=1e-12)


def test_flat_cohesive_layer_matches_the_scalar_equilibrium():
    """Flat surface: every node alike, (M/D) u = T_n(δ0 − U − u); the ramp out and back with warm starts."""
    d, dn = L, 1e-3
    steps = [-3e-3, -1e-3, 0.0, 1e-3, 0.0, -3e-3]
    out = solve_cell(np.zeros((4, 4)), L, L, E, NU, d, steps, law="cohesive", phi_n_star=1e-3, length_normal=dn,
                     initial_separation=1e-3, layers=3)
    law = NormalCohesiveZone.from_dimensionless(1e-3, dn, E)
    assert out.curve["converged"].all()
    for k, U in enumerate(steps):
        z = 1e-3 - U
        # the stable root: M/D > max |dT/dΔn| = φn/δn² here, so the equation has one root
        u = brentq(lambda v: M / d * v - law.traction(z - v), -10 * dn, 10 * dn, xtol=1e-18)
        assert out.curve["p"][k] == pytest.approx(-law.traction(z - u), rel=1e-9, abs=1e-12 * law.phi_n / dn)
        assert np.allclose(out.fields[k]["u_z"], u, rtol=1e-9, atol=1e-15)
    assert M / d > law.phi_n / dn**2


def test_cohesive_rough_ramp_is_in_equilibrium():
    """An egg-box with adhesion, loading and unloading: converged steps; the nodal reaction pressure
    −Σ(S u)/A equals p = −⟨T_n⟩ to the solver tolerance; hysteresis-free steps repeat."""
    n, amp = 16, 2e-3
    i = np.arange(n) / n
    h = amp * np.cos(2 * np.pi * i)[:, None] * np.cos(2 * np.pi * i)[None, :]
    steps = [0.0, 1e-3, 2e-3, 4e-3, 2e-3, 1e-3, 0.0, -1e-3]
    out = solve_cell(h, L, L, E, NU, L, steps, law="cohesive", phi_n_star=0.01, length_normal=2e-4)
    c = out.curve
    assert c["converged"].all() and (c["residual"] <= 1e-10).all()
    p_ref = E_STAR * c["g"][0]
    assert np.allclose(c["reaction_p"], c["p"], rtol=0, atol=2e-10 * p_ref)
    assert np.all(np.diff(c["p"][:4]) > 0) and c["a_rel"][3] > c["a_rel"][0]


def test_observables_by_hand():
    """g_i² of a single bump: (1/lx² + 1/ly²) at the bump, ½/lx² at its x neighbours, ½/ly² at its y ones."""
    h = np.zeros((5, 4))
    h[0, 0] = 1.0
    lx, ly = 0.5, 2.0
    g2 = gradient_squared(h, (lx, ly))
    assert g2[0, 0] == pytest.approx(1 / lx**2 + 1 / ly**2)
    assert g2[1, 0] == g2[-1, 0] == pytest.approx(0.5 / lx**2)
    assert g2[0, 1] == g2[0, -1] == pytest.approx(0.5 / ly**2)
    assert np.count_nonzero(g2) == 5
    gap, t_z = np.array([0.0, 1.0, 3.0]), np.array([-1.0, 0.5, 0.0])
    assert list(contact_mask("traction-tolerance", gap, t_z)) == [True, False, False]
    assert list(contact_mask("traction-tolerance", gap, t_z, tolerance_gap=2.0)) == [True, True, False]
    assert list(contact_mask("gap", gap, t_z, rule_gap=1.0)) == [True, True, False]
    with pytest.raises(ValueError, match="contact_rule"):
        contact_mask("nearby", gap, t_z)


def test_vtu_export(tmp_path):
    import meshio

    h = 1e-3 * np.cos(2 * np.pi * np.arange(6) / 6)[:, None] * np.ones((6, 4))
    out = solve_cell(h, L, 0.7 * L, E, NU, 0.5 * L, [1e-3], law="hard-wall", layers=3)
    (path,) = export_vtu(out, tmp_path)
    mesh = meshio.read(path)
    assert mesh.points.shape == (7 * 5 * 4, 3) and mesh.cells[0].type == "hexahedron"
    top = np.abs(mesh.points[:, 2]) < 1e-12
    ix = np.rint(mesh.points[top, 0] / (L / 6)).astype(int) % 6
    iy = np.rint(mesh.points[top, 1] / (0.7 * L / 4)).astype(int) % 4
    assert np.allclose(mesh.point_data["displacement"][top, 2], out.fields[0]["u_z"][ix, iy], rtol=1e-12)
    base = np.abs(mesh.points[:, 2] + 0.5 * L) < 1e-12
    assert np.all(mesh.point_data["displacement"][base] == 0)
    with pytest.raises(ValueError, match="step"):
        export_vtu(out, tmp_path, steps=[3])


@pytest.mark.parametrize("kwargs, key", [(dict(heights=np.zeros(8)), "heights"),
                                         (dict(law="coupled"), "law"),
                                         (dict(poisson_ratio=0.5), "poisson_ratio"),
                                         (dict(thickness=0.0), "thickness"),
                                         (dict(length_y=-1.0), "length_y"),
                                         (dict(displacements=[]), "displacements"),
                                         (dict(law="cohesive"), "phi_n_star")])
def test_bad_input_names_the_key(kwargs, key):
    args = dict(heights=np.zeros((4, 4)), length_x=L, length_y=L, youngs_modulus=E, poisson_ratio=NU,
                thickness=L, displacements=[0.0])
    args.update(kwargs)
    with pytest.raises(ValueError, match=key):
        solve_cell(**args)


def test_from_scene_maps_the_keys():
    """The adapter reads surface.nodes_y/length_y (SPEC2D), material, interface and loading, and refuses a
    1+1-D scene naming surface.nodes_y."""
    from types import SimpleNamespace as NS

    interface = NS(law="hard-wall", phi_n_star=0.1, length_normal=1e-3, contact_rule="traction-tolerance",
                   contact_tolerance=1e-3, contact_gap=1.0)
    material = NS(youngs_modulus=E, poisson_ratio=NU, thickness=L, half_plane=False)
    scene = NS(surface=NS(nodes=4, nodes_y=4, length=L, length_y=L), material=material, interface=interface,
               loading=NS(initial_separation=0.0))
    from reference.fem3d import from_scene

    out = from_scene(scene, np.zeros((4, 4)), [1e-3], layers=3)
    assert out.curve["p"][0] == pytest.approx(M * 1e-3 / L, rel=1e-10)
    with pytest.raises(ValueError, match="nodes_y"):
        from_scene(NS(**{**vars(scene), "surface": NS(nodes=4, length=L)}), np.zeros((4, 4)), [0.0])


def test_cohesive_steps_end_at_stable_minima():
    """A sticky egg-box loaded and unloaded: every converged step is a local minimum of Π (no instability
    message), and the warm starts follow the path: unloading stays on the adhesive branch, a lower (more
    tensile) p than loading at the same U (hysteresis) with at least the loading's contact."""
    n, amp = 8, 2e-3
    i = np.arange(n) / n
    h = amp * np.cos(2 * np.pi * i)[:, None] * np.cos(2 * np.pi * i)[None, :]
    steps = [0.0, 2e-3, 4e-3, 2e-3, 0.0, -0.5e-3]
    out = solve_cell(h, L, L, E, NU, L, steps, law="cohesive", phi_n_star=0.02, length_normal=2e-4)
    assert out.curve["converged"].all()
    assert not [m for m in out.messages if "unstable" in m]
    p, a = out.curve["p"], out.curve["a_rel"]
    assert p[3] < p[1] and p[4] < p[0]
    assert a[3] >= a[1] and a[4] >= a[0]
