"""surface.boundary = "free": the padded kernel (`gfmd_contact.core.free_kernels`), the region of the padded cell
(`gfmd_contact.core.free_boundary`, `gfmd.free_cell`), the refusals, and the results cropped to the region."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate

from gfmd.chains import relax
from gfmd.loading import prepare, run_realization
from gfmd.problem import InterfaceLaw
from gfmd_contact.core import free_boundary as fb
from gfmd_contact.core import free_kernels as fk
from gfmd_contact.core import surfaces
from gfmd_contact.core.errors import SceneError
from gfmd_contact.core.kernels import wavenumbers, wavevector_magnitudes
from gfmd_contact.core.model import build_model
from gfmd_contact.core.scene import scene_from_dict
from reference.fem import run as fem_run
from reference.fem3d import ramp as fem3d_ramp

E_STAR = 2.0e9


def _scene(law="hard-wall", two_d=False, nodes=32, **sections):
    surface = {"kind": "sphere" if two_d else "cylinder", "nodes": nodes, "length": 1e-6, "radius": 1e-6,
               "boundary": "free", **({"nodes_y": nodes} if two_d else {})}
    interface = {"law": law}
    if law in ("cohesive", "cohesive-wall"):
        interface.update(phi_n_star=1e-3, length_normal=2 * 1e-6 / nodes)
    if law == "lj93":
        interface.update(work_of_adhesion=0.05, range_length=2 * 1e-6 / nodes)
    d = {"surface": surface, "material": {"youngs_modulus": 1.5e9, "poisson_ratio": 0.5}, "interface": interface,
         "loading": {"initial_separation": 4 * 1e-6 / nodes, "final_penetration": 5e-9, "steps": 3},
         "output": {"field_steps": 3}}
    for key, value in sections.items():
        section, name = key.split("__")
        d.setdefault(section, {})[name] = value
    return scene_from_dict(d)


# ----------------------------------------------------------------------------------------------- the kernel
@pytest.mark.parametrize("grid", [(8,), (64,), (1024,), (8, 8), (32, 16)])
def test_padded_compliance_is_positive_at_every_nonzero_mode(grid):
    g = fk.padded_spectrum(grid, (1e-8,) * len(grid), E_STAR)
    assert np.all(g.ravel()[1:] > 0)
    k = fk.padded_stiffness(grid, (1e-8,) * len(grid), E_STAR)
    assert k.ravel()[0] == 0 and np.all(k.ravel()[1:] > 0)


def test_padded_kernel_tends_to_the_periodic_one_at_intermediate_wavelengths():
    """K_c/(E*|q|/2) → 1 between the lowest modes (truncation, ~1/mode) and the Nyquist end (node averaging)."""
    n, l = 1024, 1e-8
    q = wavenumbers(2 * n, 2 * n * l)
    ratio = fk.padded_stiffness((n,), (l,), E_STAR) / (0.5 * E_STAR * np.where(q > 0, q, 1))
    mid = slice(50, 200)
    assert np.max(np.abs(ratio[mid] - 1)) < 0.015, ratio[mid]
    n2 = 64
    q2 = wavevector_magnitudes(2 * n2, 2 * n2 * l, 2 * n2, 2 * n2 * l)
    ratio2 = fk.padded_stiffness((n2, n2), (l, l), E_STAR) / (0.5 * E_STAR * np.where(q2 > 0, q2, 1))
    assert abs(ratio2[10, 0] - 1) < 0.05 and abs(ratio2[0, 10] - 1) < 0.05, (ratio2[10, 0], ratio2[0, 10])


def test_nodal_compliances_match_their_integrals():
    l = 1.0
    for x in (0.0, 0.3, 1.0, 4.5):
        ref = integrate.quad(lambda s, x=x: -2 / (np.pi * E_STAR) * np.log(abs(x - s) / l), -0.5, 0.5,
                             points=[x] if abs(x) < 0.5 else None)[0]
        assert fk.segment_compliance(x, l, E_STAR) == pytest.approx(ref, rel=1e-10)
    for x, y in ((1.0, 0.0), (2.3, 1.7), (0.0, 3.0)):
        ref = integrate.dblquad(lambda yy, xx, x=x, y=y: 1 / np.hypot(x - xx, y - yy), -0.5, 0.5, -0.6, 0.6)[0]
        ref /= np.pi * E_STAR
        assert fk.rectangle_compliance(x, y, 1.0, 1.2, E_STAR) == pytest.approx(ref, rel=1e-8)
    centre = 4 * (0.5 * np.arcsinh(0.6 / 0.5) + 0.6 * np.arcsinh(0.5 / 0.6)) / (np.pi * E_STAR)
    assert fk.rectangle_compliance(0.0, 0.0, 1.0, 1.2, E_STAR) == pytest.approx(centre, rel=1e-14)


def _padded_response(region, spacings, load):
    """u (m) on the padded grid of the clamped padded stiffness under the nodal tractions `load` (Pa)."""
    k = fk.padded_stiffness(region, spacings, E_STAR)
    t = np.zeros(fk.padded_grid(region))
    t[fb.region_slices(region)] = load
    t_hat = np.fft.rfftn(t)
    u_hat = np.where(k > 0, t_hat / np.where(k > 0, k, 1), 0)
    return np.fft.irfftn(u_hat, s=t.shape, axes=tuple(range(t.ndim))), float(np.mean(t))


def test_a_point_load_displaces_the_region_as_the_free_body():
    """One loaded node: u on the region = the closed form at the true distances, up to the far-field shift s."""
    n, l = 64, 1e-8
    load = np.zeros(n)
    load[5] = 1e6
    u, t_mean = _padded_response((n,), (l,), load)
    x = (np.arange(n) - 5) * l
    free = 1e6 * fk.segment_compliance(x, l, E_STAR)
    shift = fk.far_field_shift((n,), (l,), E_STAR, t_mean)
    assert np.max(np.abs(u[:n] + shift - free)) < 1e-12 * np.max(np.abs(free))
    n2 = 16
    load2 = np.zeros((n2, n2))
    load2[0, 0] = 1e6
    u2, t2 = _padded_response((n2, n2), (l, l), load2)
    ix, iy = np.meshgrid(np.arange(n2) * l, np.arange(n2) * l, indexing="ij")
    free2 = 1e6 * fk.rectangle_compliance(ix, iy, l, l, E_STAR)
    shift2 = fk.far_field_shift((n2, n2), (l, l), E_STAR, t2)
    assert np.max(np.abs(u2[:n2, :n2] + shift2 - free2)) < 1e-12 * free2.max()
    far = np.hypot(ix[-1, -1], iy[-1, -1])  # Boussinesq: F/(π E* r) far from the load
    assert free2[-1, -1] == pytest.approx(1e6 * l * l / (np.pi * E_STAR * far), rel=1e-3)


# ------------------------------------------------------------------------------------------- the padded model
def test_free_model_is_the_padded_cell_and_says_so():
    m = build_model(_scene())
    assert m.free and m.region == (32,) and m.grid == (64,) and m.length == pytest.approx(2e-6)
    assert m.node_area == pytest.approx(1e-6 / 32)
    assert "free boundary (Hockney padding to 2N)" in m.description
    m2 = build_model(_scene(two_d=True, nodes=16))
    assert m2.region == (16, 16) and m2.grid == (32, 32) and m2.k_zz.shape == (32, 17)
    periodic = build_model(_scene(surface__boundary="periodic"))
    assert not periodic.free and periodic.grid == (32,)


def test_a_layer_or_an_auxetic_coupled_body_on_a_free_boundary_is_refused():
    with pytest.raises(SceneError, match="surface.boundary"):
        build_model(_scene(material__thickness=1e-6, material__poisson_ratio=0.3))
    with pytest.raises(SceneError, match="material.poisson_ratio"):
        build_model(_scene("cohesive", material__poisson_ratio=-0.3, interface__tangential_ratio=0.5))


def test_tangential_unknowns_get_the_padded_coupled_kernel():
    m = build_model(_scene("cohesive", material__poisson_ratio=0.3, interface__tangential_ratio=0.5))
    assert m.tangential and m.free and m.k_xx.shape == m.k_xz.shape == m.k_zz.shape == (33,)
    assert np.all(np.real(m.k_xz) == 0) and m.k_xz[0] == 0 and m.k_xz[-1] == 0  # imaginary, q = 0 and Nyquist 0
    det = np.real(m.k_xx * m.k_zz) - np.abs(m.k_xz) ** 2
    assert np.all(det[1:] > 0) and np.all(np.real(m.k_xx[1:]) > 0)


def test_the_coupled_padded_kernel_reproduces_the_free_half_plane_point_loads():
    """Johnson §2.2 on the region: a line load moves the surface along the other axis by ∓(β/E*) sgn(x) (node
    integrated), and along its own by the log, up to the uniform shifts of the clamped mean."""
    n, l, nu = 64, 1e-8, 0.3
    beta = (1 - 2 * nu) / (2 * (1 - nu))
    k_xx, k_xz, k_zz = fk.padded_coupled_stiffness(n, l, E_STAR, beta)
    x = (np.arange(n) - 20) * l
    for loaded in (0, 1):  # x, z
        t = np.zeros((2, 2 * n))
        t[loaded, 20] = 1e6
        th = np.fft.rfft(t)
        det = np.real(k_xx * k_zz) - np.abs(k_xz) ** 2
        det[0] = np.inf
        u = np.fft.irfft(np.stack([(k_zz * th[0] - k_xz * th[1]) / det, (-np.conj(k_xz) * th[0] + k_xx * th[1]) / det]),
                         n=2 * n)[:, :n]
        own = 1e6 * fk.segment_compliance(x, l, E_STAR)
        cross = 1e6 * fk.segment_cross_compliance(x, l, E_STAR, beta) * (1 if loaded == 1 else -1)
        other = 1 - loaded
        for got, want in ((u[loaded], own), (u[other], cross)):
            got, want = got - got[0], want - want[0]
            assert np.max(np.abs(got - want)) < 1e-10 * np.max(np.abs(own - own[0]))


def test_the_fe_references_refuse_a_free_boundary():
    assert "surface.boundary" in fem_run.refusal(_scene("cohesive"))
    assert "surface.boundary" in fem3d_ramp.refusal(_scene(two_d=True, nodes=16, material__thickness=1e-6,
                                                                 material__poisson_ratio=0.3))
    with pytest.raises(SceneError, match="surface.boundary"):
        fem_run.run_realization(_scene())
    with pytest.raises(SceneError, match="surface.boundary"):
        fem3d_ramp.run_realization(_scene(two_d=True, nodes=16))


@pytest.mark.parametrize("law", ["hard-wall", "cohesive", "cohesive-wall", "lj93", "coupled"])
def test_no_traction_acts_outside_the_region(law):
    """The padded solve itself (not the cropped fields): zero traction off the region, contact on it."""
    scene = (_scene("cohesive", material__poisson_ratio=0.3, interface__tangential_ratio=0.5) if law == "coupled"
             else _scene(law))
    h = surfaces.profile(scene.surface, 0)
    cell = prepare(scene, h)
    z = cell.indenter(scene.loading.initial_separation + 5e-9)
    assert z.shape == (64,) and np.all(z[32:] > np.max(z[:32]))
    r = relax(cell.physics, InterfaceLaw(cell.physics), z, cell.initial_state(), cell.settings)
    assert r.converged
    assert fb.outside_traction(r.t_z, (32,)) == 0.0
    if law == "coupled":
        assert cell.physics.tangential and fb.outside_traction(r.t_x, (32,)) == 0.0
    assert np.min(r.t_z[:32]) < 0  # the indenter presses on the region


def test_far_gap_is_exact_zero_for_the_laws():
    for law in ("cohesive", "lj93"):
        solved = build_model(_scene(law)).law
        gap = fb.far_gap(solved, 0.0)
        t_n, _ = solved.tractions(np.array([gap, 2 * gap]), np.zeros(2))
        assert np.all(np.asarray(t_n) == 0.0) and np.all(solved.potential(np.array([gap])) == 0.0)
        half = np.array([gap / 2])  # not further out than needed: something is still nonzero half-way
        values = [solved.tractions(half, np.zeros(1))[0], solved.tangent(half, np.zeros(1))[0], solved.potential(half)]
        assert any(np.any(np.asarray(v) != 0.0) for v in values)


def test_results_are_cropped_to_the_region():
    result = run_realization(_scene(two_d=True, nodes=16))
    for fields in result.fields.values():
        assert all(np.shape(v) == (16, 16) for k, v in fields.items() if v is not None and np.ndim(v)), fields.keys()
    assert set(result.diagnostics["far_field_shift"]) == set(result.fields)
    assert np.all(np.asarray(result.curve["converged"]) == 1)
    last = max(result.fields)
    p = -np.asarray(result.fields[last]["t_n"])
    assert result.curve["p"][last] == pytest.approx(np.mean(p), rel=1e-12)  # F / (region area), not the padded cell's


def test_meta_json_keeps_the_far_field_shift_of_a_free_run():
    from gfmd_contact.app.io import _far_field_shifts

    result = run_realization(_scene(two_d=True, nodes=16))
    shifts = _far_field_shifts([result])["far_field_shift"]["r0"]
    assert sorted(shifts) == sorted(str(k) for k in result.fields)
    # 2+1-D compressive loads: s = Ĝ_c(0) t̄ < 0 (Ĝ_c(0) = Σ g_c > 0, the 1/r compliance; 1+1-D: the log's sign)
    assert all(v < 0 for k, v in shifts.items() if result.curve["p"][int(k)] > 0)
    assert _far_field_shifts([run_realization(_scene(surface__boundary="periodic"))]) == {}


def test_the_preflight_estimates_count_the_padded_cell():
    from gfmd_contact.core import cost

    free, periodic = _scene(two_d=True, nodes=256), _scene(two_d=True, nodes=256, surface__boundary="periodic")
    assert cost.solved_grid(free.surface) == (512, 512) and cost.solved_grid(periodic.surface) == (256, 256)
    solver = [cost.estimate_peak_memory(s, workers=1) - cost.IMPORTS for s in (free, periodic)]
    fields = periodic.surface.realizations * 3 * cost.FIELD_ARRAYS * 8 * 256 * 256  # the saved fields: the region's
    assert solver[0] - fields == pytest.approx(4 * (solver[1] - fields))


def test_an_interrupted_free_run_resumes_to_the_same_files(tmp_path, monkeypatch):
    """The padded state checkpoints and resumes as a periodic one (tests/test_run_dir.py's helpers)."""
    import json

    from tests.test_run_dir import assert_same_run, interrupted_and_resumed, scene

    sc = scene(**{"surface.boundary": "free", "surface.realizations": 2})
    ref, out = interrupted_and_resumed(tmp_path, monkeypatch, sc, (1, 3))
    assert_same_run(ref, out)
    shifts = [json.loads((d / "meta.json").read_text())["far_field_shift"] for d in (ref, out)]
    assert shifts[0] == shifts[1] and set(shifts[0]) == {"r0", "r1"}


def test_contact_patches_of_a_free_region_are_not_joined_across_its_edges():
    from gfmd_contact.app.surface_plots import surface_maps

    gap, t_n = np.ones((16, 16)), np.zeros((16, 16))
    t_n[0, 4:8] = t_n[15, 4:8] = -1e6  # pressed on two opposite edges: one patch in a periodic cell, two on a free one
    gap[0, 4:8] = gap[15, 4:8] = 0.0
    fields = {"x": np.arange(16) * 1e-8, "y": np.arange(16) * 1e-8, "r0_s1_gap": gap, "r0_s1_t_n": t_n}
    titles = {b: surface_maps(_scene(two_d=True, nodes=16, surface__boundary=b), fields, 0, 1, 1e-9)["contact_map"]
              .axes[0].get_title() for b in ("periodic", "free")}
    assert "1 patches" in titles["periodic"] and "2 patches" in titles["free"], titles


def test_the_gradients_of_a_free_region_take_no_difference_across_its_edges():
    """ḡ (curve column g, and p_ref) of a free cylinder: Eq. 6 with the edge nodes' inner differences only."""
    scene = _scene()
    h = surfaces.profile(scene.surface, 0)
    d2 = (np.diff(h) / scene.surface.spacing) ** 2
    g2 = 0.5 * (np.concatenate([d2[:1], d2]) + np.concatenate([d2, d2[-1:]]))
    result = run_realization(scene)
    assert np.allclose(result.curve["g"], np.sqrt(np.mean(g2)), rtol=1e-12)
    periodic = run_realization(_scene(surface__boundary="periodic"))
    wrapped = 0.5 * (np.concatenate([[(h[0] - h[-1]) ** 2], d2 * scene.surface.spacing**2])
                     + np.concatenate([d2 * scene.surface.spacing**2, [(h[-1] - h[0]) ** 2]])) / scene.surface.spacing**2
    assert periodic.curve["g"][0] == pytest.approx(np.sqrt(np.mean(wrapped)), rel=1e-12)  # the cell wraps: h[N−1] → h[0]
    assert build_model(scene, h).reference_traction == pytest.approx(build_model(scene).contact_modulus
                                                                      * np.sqrt(np.mean(g2)), rel=1e-12)
