"""Tests of 2+1-D surfaces: gfmd_contact.core.surfaces_2d and the [surface] nodes_y / length_y keys.

The isotropic spectrum in seed Eq. 4's bands, C^iso(|q|) ∝ |q|^−2(1+H), is transcribed here independently
(`_eq4_radial`); the PSD checks compare the rfft2 of a surface with it mode by mode, to an FFT round-off
bound. tests/test_hurst_measured.py measures H from the heights.
"""

import math
import tomllib

import numpy as np
import pytest
import scipy.fft
from hypothesis import given, settings, strategies as st

from gfmd_contact.core import surfaces, surfaces_2d
from gfmd_contact.core.scene import SceneError, default_scene, load_scene, scene_from_dict, scene_to_toml

EPS = np.finfo(float).eps


def _eq4_radial(qx, qy, hurst, lr, ls, longest):
    """Seed Eq. 4's bands / C(q_r) at |q| = √(qx² + qy²): 1 on the plateau 2π/longest ≤ |q| < q_r,
    (|q|/q_r)^−2(1+H) up to q_s = 2π/λs, 0 above and at q = 0."""
    q = np.hypot(qx[:, None], qy[None, :])
    qr, qs, ql = 2 * np.pi / lr, 2 * np.pi / ls, 2 * np.pi / longest
    out = np.where((q >= ql * (1 - 1e-12)) & (q < qr), 1.0, 0.0)
    power = (q >= qr) & (q <= qs * (1 + 1e-12))
    out[power] = (q[power] / qr) ** (-2 * (1 + hurst))
    return out


def _surface(nx=64, ny=48, lx=1e-6, ly=0.75e-6, hurst=0.8, h_rms=1e-8, seed=3):
    return surfaces_2d.self_affine(nx, lx, ny, ly, hurst, h_rms, lx / 4, 4 * max(lx / nx, ly / ny), seed)


# ---------------------------------------------------------------- self-affine, radial Eq. 4

dims = st.sampled_from([(64, 64), (64, 48), (33, 40), (16, 128)])


@settings(max_examples=25, derandomize=True, deadline=None)
@given(st.floats(0.05, 0.95), st.floats(1e-10, 1e-6), st.integers(0, 2**32 - 1), dims)
def test_exact_rms_and_zero_mean(hurst, h_rms, seed, shape):
    nx, ny = shape
    h = _surface(nx, ny, hurst=hurst, h_rms=h_rms, seed=seed)
    assert h.shape == (nx, ny) and np.all(np.isfinite(h))
    # rescaled to h_rms over the surface: round-off of a mean of squares and a sqrt
    assert math.sqrt(np.mean(h**2)) == pytest.approx(h_rms, rel=1e-12)
    assert abs(np.mean(h)) <= 1e-12 * h_rms  # q = 0 carries nothing: the mean is round-off


@settings(max_examples=15, derandomize=True, deadline=None)
@given(st.floats(0.05, 0.95), st.integers(0, 2**32 - 1), dims)
def test_psd_is_radial_eq4_mode_by_mode(hurst, seed, shape):
    """|ĥ(q)|² ∝ C(|q|) for every mode (deterministic amplitudes, unit-modulus phases): isotropic by
    construction, so modes of equal |q| carry equal power whatever their direction. The Nyquist lines and
    q = 0 are empty. Bound: the FFT's round-off, |δĥ| ≤ c·ε·log2(NxNy)·‖h‖₂ (Higham, Accuracy and Stability,
    §24.1), with c = 5 for the forward and the inverse transform and the rescaling."""
    nx, ny = shape
    lx, ly = 1e-6, 0.75e-6
    h = _surface(nx, ny, lx, ly, hurst=hurst, seed=seed)
    hq = scipy.fft.rfftn(h, axes=(0, 1))
    qx = 2 * np.pi * np.fft.fftfreq(nx, lx / nx)
    qy = 2 * np.pi * np.fft.rfftfreq(ny, ly / ny)
    amplitude = np.sqrt(_eq4_radial(qx, qy, hurst, lx / 4, 4 * max(lx / nx, ly / ny), max(lx, ly)))
    if nx % 2 == 0:
        amplitude[nx // 2, :] = 0
    if ny % 2 == 0:
        amplitude[:, -1] = 0
    scale = np.sum(np.abs(hq) * amplitude) / np.sum(amplitude**2)  # least-squares factor of |ĥ| = s·√C
    bound = 5 * EPS * math.log2(nx * ny) * np.linalg.norm(h) * math.sqrt(nx * ny)
    assert np.max(np.abs(np.abs(hq) - scale * amplitude)) <= bound


def test_isotropy_of_the_radial_average():
    """Power of two rings of modes at equal |q| along x and along y of a square cell is the same (a surface
    built from a 1-D spectrum along x only, or with C(q_x) instead of C(|q|), would fail this)."""
    n, length = 128, 1e-6
    h = surfaces_2d.self_affine(n, length, n, length, 0.7, 1e-8, length / 4, 8 * length / n, 5)
    power = np.abs(scipy.fft.rfftn(h, axes=(0, 1))) ** 2
    for m in (1, 5, 17, 40):
        assert power[m, 0] == pytest.approx(power[0, m], rel=1e-9)  # (m, 0) and (0, m): |q| equal
        assert power[m, 0] > 0


def test_reproducible_from_the_seed_and_different_otherwise():
    a = _surface(seed=11)
    assert np.array_equal(a, _surface(seed=11))  # bit for bit
    b = _surface(seed=12)
    assert not np.array_equal(a, b)
    # independent phases: correlation O(1/√modes), never ≈ 1
    assert abs(np.corrcoef(a.ravel(), b.ravel())[0, 1]) < 0.5


def test_realization_uses_seed_plus_index():
    s = _scene(kind="self-affine", nodes=64, nodes_y=64, rolloff_wavelength=2.5e-7, rollon_wavelength=5e-8,
               seed=4).surface
    assert np.array_equal(surfaces.profile(s, 2),
                          surfaces_2d.self_affine(s.nodes, s.length, s.nodes_y, s.length_y, s.hurst, s.h_rms,
                                                  s.rolloff_wavelength, s.rollon_wavelength, 6))


# ---------------------------------------------------------------- deterministic kinds

def test_sinusoid_is_the_profile_embedded():
    h = surfaces_2d.embedded_sinusoid(64, 1e-6, 8, 2e-8)
    line = surfaces.sinusoid(64, 1e-6, 2e-8)
    assert h.shape == (64, 8)
    assert all(np.array_equal(h[:, j], line) for j in range(8))  # bit for bit, every column


def test_egg_box_and_sphere():
    nx, ny, lx, ly = 32, 16, 1e-6, 0.5e-6
    egg = surfaces_2d.egg_box(nx, lx, ny, ly, 3e-9)
    # the contract: a cos(2πx/Lx) cos(2πy/Ly) at node (i, j) = (i lx, j ly)
    xs, ys = np.arange(nx) * lx / nx, np.arange(ny) * ly / ny
    assert np.allclose(egg, 3e-9 * np.cos(2 * np.pi * xs / lx)[:, None] * np.cos(2 * np.pi * ys / ly)[None, :],
                       rtol=0, atol=8 * EPS * 3e-9)
    assert egg[0, 0] == egg[nx // 2, ny // 2] == 3e-9 == egg.max()
    assert egg[nx // 2, 0] == egg[0, ny // 2] == -3e-9 == egg.min()  # troughs: first contact
    # on the centred positions of a result (even N): the same formula
    x, y = surfaces.grid(nx, lx), surfaces.grid(ny, ly)
    assert np.allclose(egg, 3e-9 * np.cos(2 * np.pi * x / lx)[:, None] * np.cos(2 * np.pi * y / ly)[None, :],
                       rtol=0, atol=8 * EPS * 3e-9)
    sph = surfaces_2d.sphere(nx, lx, ny, ly, 1e-5)
    assert sph[nx // 2, ny // 2] == 0 == sph.min()
    assert sph[nx // 2 + 3, ny // 2] == pytest.approx((3 * lx / nx) ** 2 / 2e-5, rel=4 * EPS)
    # the cylinder of 1+1-D, along each axis through the centre
    assert np.array_equal(sph[:, ny // 2], surfaces.cylinder(nx, lx, 1e-5))


# ---------------------------------------------------------------- scene keys

def _scene(**surface):
    d = {"kind": "flat", "nodes": 32, "nodes_y": 16, "length": 1e-6, **surface}
    return scene_from_dict({"surface": d, "interface": {"law": "hard-wall"}})


def test_defaults_and_properties():
    s = _scene().surface
    assert (s.nodes_y, s.length_y, s.shape, s.two_d) == (16, 1e-6, (32, 16), True)
    assert s.spacings == (1e-6 / 32, 1e-6 / 16)
    d = default_scene().surface
    assert (d.nodes_y, d.two_d, d.shape) == (0, False, (d.nodes,))


@settings(max_examples=30, derandomize=True, deadline=None)
@given(st.sampled_from(["self-affine", "sinusoid", "egg-box", "sphere", "flat"]), st.integers(2, 96),
       st.floats(0.2e-6, 5e-6), st.booleans())
def test_toml_round_trip_is_exact(kind, nodes_y, length_y, give_length_y):
    ly = length_y if give_length_y else 1e-6
    extra = {"self-affine": {"rolloff_wavelength": max(1e-6, ly), "rollon_wavelength": 1.01 * max(1e-6 / 16, ly / nodes_y)},
             "sinusoid": {"amplitude": 1e-9}, "egg-box": {"amplitude": 2e-9}, "sphere": {"radius": 1e-5}}
    surface = {"kind": kind, "nodes": 16, "length": 1e-6, "nodes_y": nodes_y, **extra.get(kind, {})}
    if give_length_y:
        surface["length_y"] = length_y
    sc = scene_from_dict({"surface": surface, "interface": {"law": "hard-wall"}}, name="s")
    text = scene_to_toml(sc)
    assert scene_from_dict(tomllib.loads(text), name="s") == sc
    assert "nodes_y" in text and "length_y" in text
    assert sc.surface.length_y == (length_y if give_length_y else 1e-6)


def test_profile_scene_and_its_toml_unchanged():
    sc = default_scene()
    text = scene_to_toml(sc)
    assert "nodes_y" not in text and "length_y" not in text
    assert sc.replace(**{"surface.nodes": 8192}).surface.nodes_y == 0
    flat2 = _scene()
    back = flat2.replace(**{"surface.nodes_y": 0})  # back to a profile: Ly goes with Ny
    assert (back.surface.nodes_y, back.surface.length_y) == (0, 0.0)
    assert "length_y" not in scene_to_toml(back)


@pytest.mark.parametrize("surface, names", [
    ({"nodes_y": 1}, ["surface.nodes_y", "≥ 2"]),
    ({"nodes_y": -4}, ["surface.nodes_y"]),
    ({"nodes_y": 2.5}, ["surface.nodes_y", "integer"]),
    ({"nodes_y": 0, "length_y": 1e-6}, ["surface.length_y", "nodes_y"]),
    ({"length_y": 0.0}, ["surface.length_y", "> 0"]),
    ({"length_y": -1e-6}, ["surface.length_y"]),
    ({"nodes_y": 2**20}, ["surface.nodes_y", "surface.nodes × surface.nodes_y"]),
    ({"kind": "cylinder", "radius": 1e-6}, ["surface.kind", "'cylinder'", "sphere"]),
    ({"nodes_y": 0, "kind": "egg-box", "amplitude": 1e-9}, ["surface.kind", "'egg-box'", "nodes_y"]),
    ({"nodes_y": 0, "kind": "sphere", "radius": 1e-6}, ["surface.kind", "'sphere'", "nodes_y"]),
    ({"kind": "egg-box", "radius": 1e-6}, ["surface.radius", "egg-box"]),
    ({"kind": "self-affine", "rolloff_wavelength": 2e-6, "rollon_wavelength": 1e-7}, ["rolloff_wavelength"]),
])
def test_bad_2d_keys_name_the_key(surface, names):
    with pytest.raises(SceneError) as err:
        _scene(**surface)
    assert all(n in str(err.value) for n in names), str(err.value)


@pytest.mark.parametrize("section, values, key", [
    ("interface", {"law": "cohesive", "tangential_ratio": 0.3}, "interface.tangential_ratio"),
    ("solver", {"unknowns": "coupled"}, "solver.unknowns"),
])
def test_laws_needing_u_x_are_refused_in_2d(section, values, key):
    d = {"surface": {"kind": "flat", "nodes": 32, "nodes_y": 16}, section: values}
    with pytest.raises(SceneError) as err:
        scene_from_dict(d)
    text = str(err.value)
    assert key in text and "normal-only" in text and "3 × 3" in text
    d["surface"]["nodes_y"] = 0  # the same scene as a profile is fine (its law is built in 1+1-D)
    if section == "interface":
        assert scene_from_dict(d).interface.tangential_ratio == 0.3


def test_file_surface(tmp_path):
    h = np.random.default_rng(0).standard_normal((32, 16)) * 1e-9
    np.save(tmp_path / "h.npy", h)
    sc = _scene(kind="file", path=str(tmp_path / "h.npy"), facing="valleys")  # the heights as they are
    assert np.array_equal(surfaces.profile(sc.surface), h)
    summits = _scene(kind="file", path=str(tmp_path / "h.npy"))  # the default: the measured summits face the body
    assert np.array_equal(surfaces.profile(summits.surface), -h)
    (tmp_path / "s.toml").write_text(scene_to_toml(sc))
    assert load_scene(tmp_path / "s.toml").surface == sc.surface
    np.save(tmp_path / "t.npy", h.T)
    with pytest.raises(SceneError, match=r"surface\.path.*shape \(16, 32\).*\(surface\.nodes, surface\.nodes_y\) = "
                                         r"\(32, 16\)"):
        _scene(kind="file", path=str(tmp_path / "t.npy"))
    np.save(tmp_path / "line.npy", h[:, 0])
    with pytest.raises(SceneError, match=r"surface\.path.*shape \(32,\)"):
        _scene(kind="file", path=str(tmp_path / "line.npy"))
    np.savetxt(tmp_path / "h.txt", h)  # a text matrix goes to SurfaceTopography: no unit, rows are lines along x
    with pytest.raises(SceneError, match=r"surface\.path.*states no unit.*surface\.height_unit"):
        _scene(kind="file", path=str(tmp_path / "h.txt"))
    with pytest.raises(SceneError, match=r"surface\.path.*16 × 32 points.*\(surface\.nodes, surface\.nodes_y\) = "
                                         r"\(32, 16\)"):
        _scene(kind="file", path=str(tmp_path / "h.txt"), height_unit="m")
    np.savetxt(tmp_path / "h.txt", h.T)
    text = _scene(kind="file", path=str(tmp_path / "h.txt"), height_unit="m", facing="valleys")
    np.testing.assert_allclose(surfaces.profile(text.surface), h, rtol=1e-15, atol=0)  # %.18e text: to round-off
    bad = h.copy()
    bad[3, 4] = np.nan
    np.save(tmp_path / "nan.npy", bad)
    with pytest.raises(SceneError, match=r"surface\.path.*non-finite"):
        _scene(kind="file", path=str(tmp_path / "nan.npy"))


def test_example_surface_scene_loads():
    from importlib import resources
    text = resources.files("gfmd_contact.core").joinpath("example_surface_scene.toml").read_text()
    sc = scene_from_dict(tomllib.loads(text), name="example_surface")
    assert sc.surface.shape == (128, 128) and sc.surface.kind == "self-affine"
    assert sc.interface.law == "hard-wall"
    h = surfaces.profile(sc.surface)
    assert h.shape == (128, 128) and math.sqrt(np.mean(h**2)) == pytest.approx(sc.surface.h_rms, rel=1e-12)
