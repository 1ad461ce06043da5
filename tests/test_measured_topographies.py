"""Real instrument files (tests/data/topographies: AFM, interferometer, ISO x3p, stylus; maps and line scans, none
made for this project) read, prepared and solved through scene keys (gfmd_contact.core.topography_files,
topography_prep, topography_keys).

Every file is read with the grid, size and unit its README table states, or refused with a message that names
the key that supplies what is missing; the measured summits touch first; levelling, resampling, cropping and a
line taken from a map do what they say on planted data; one real map and one real line scan run end to end.
"""

from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.core.scene import SceneError, scene_from_dict
from gfmd_contact.core.surfaces import profile
from gfmd_contact.core.topography_prep import prepare, surface_lengths

pytest.importorskip("SurfaceTopography")

DATA = Path(__file__).parent / "data" / "topographies"
EPS = np.finfo(float).eps

#: file → (grid, physical size in m as the README table states it (4 significant digits), keys it needs to read)
FILES = {
    "di-1.di": ((512, 512), (500e-9, 500e-9), {}),
    "mi-1.mi": ((256, 256), (20e-6, 20e-6), {}),
    "nid-1.nid": ((256, 256), (20e-6, 20e-6), {}),
    "x3p-2.x3p": ((650, 650), (8.298e-5, 2.045e-4), {}),
    "opd-1.opd": ((640, 480), (0.1259e-3, 0.09443e-3), {"undefined": "harmonic"}),
    "sur-2.sur": ((563, 484), (1.961e-3, 1.686e-3), {"undefined": "harmonic"}),
    "dektak-1.csv": ((9600,), (1499.8e-6,), {}),
    "xy-4.txt": ((10001,), (0.9957e-6,), {"height_unit": "µm"}),  # the file states no unit: µm assumed here
}
#: the README's sizes are rounded to 4 significant digits
README_RTOL = 5e-4
#: small prepared grids: a map 32 × 32, a line scan 256 nodes
SMALL = {1: {"nodes": 256}, 2: {"nodes": 32, "nodes_y": 32}}


def _surface(name, **keys):
    grid, _, needs = FILES[name]
    return {"kind": "file", "path": str(DATA / name), **SMALL[len(grid)], "resample": "linear", **needs, **keys}


def _scene(surface, **tables):
    return scene_from_dict({"surface": surface, **tables})


@pytest.mark.parametrize("name", FILES)
def test_every_file_reads_on_its_own_grid_with_its_size_in_metres(name):
    grid, size, needs = FILES[name]
    nodes = {"nodes": grid[0], **({"nodes_y": grid[1]} if len(grid) == 2 else {})}
    surface = _scene({"kind": "file", "path": str(DATA / name), **nodes, **needs}).surface
    assert surface.shape == grid
    np.testing.assert_allclose(surface_lengths(surface), size, rtol=README_RTOL)
    h = profile(surface)
    assert h.shape == grid and np.all(np.isfinite(h)) and np.ptp(h) > 0


@pytest.mark.parametrize("name", ["opd-1.opd", "sur-2.sur"])
def test_masked_maps_are_refused_by_default_and_read_with_an_explicit_fill(name):
    surface = _surface(name)
    del surface["undefined"]
    with pytest.raises(SceneError, match=r"surface\.path = .*undefined \(masked or non-finite\) heights \(\d+ of "
                                         r"\d+\).*surface\.undefined = \"harmonic\" or \"mean\""):
        _scene(surface)
    for fill in ("harmonic", "mean"):
        assert np.all(np.isfinite(profile(_scene({**surface, "undefined": fill}).surface)))


def test_a_file_without_a_unit_is_refused_naming_surface_height_unit():
    surface = _surface("xy-4.txt")
    del surface["height_unit"]
    with pytest.raises(SceneError, match=r"xy-4\.txt.*states no unit.*surface\.height_unit supplies it"):
        _scene(surface)
    in_nm = _scene({**surface, "height_unit": "nm"}).surface  # the unit scales the size the file states, too
    np.testing.assert_allclose(in_nm.length, 0.9957e-9, rtol=README_RTOL)


def test_a_file_without_a_size_is_refused_naming_surface_length(tmp_path):
    """None of the eight states no size (the README's "0 × 0" for nid-1.nid is not what SurfaceTopography 1.27
    reads: 20 µm from its Dim0Range); a text matrix (SurfaceTopography's ASCII reader) states none."""
    h = np.random.default_rng(3).standard_normal((16, 8))  # rows: lines along x, so the map is 8 × 16
    np.savetxt(tmp_path / "matrix.asc", h)
    surface = {"kind": "file", "path": str(tmp_path / "matrix.asc"), "nodes": 8, "nodes_y": 16, "height_unit": "nm"}
    with pytest.raises(SceneError, match=r"matrix\.asc.*states no physical size; surface\.length and "
                                         r"surface\.length_y supply it"):
        _scene(surface)
    given = _scene({**surface, "length": 2e-6, "length_y": 4e-6, "facing": "valleys"}).surface
    assert (given.length, given.length_y) == (2e-6, 4e-6)
    np.testing.assert_allclose(profile(given), h.T * 1e-9, rtol=4 * EPS)
    with pytest.raises(SceneError, match=r"surface\.region = .*states no size"):
        _scene({**surface, "length": 2e-6, "length_y": 4e-6, "region": [0, 1e-6, 0, 1e-6]})


def test_channels_are_chosen_by_name_or_index_and_refusals_list_them():
    first = profile(_scene(_surface("di-1.di")).surface)
    assert np.array_equal(first, profile(_scene(_surface("di-1.di", channel=0)).surface))
    assert not np.array_equal(first, profile(_scene(_surface("di-1.di", channel=1)).surface))
    for channel, words in [("Height", "names 2 channels"), ("Torsion", "names no channel"),
                           (7, "channels 0 to 3"), ("Phase", "holds no heights")]:
        with pytest.raises(SceneError, match=rf"surface\.channel|channel 2.*{words}") as info:
            _scene(_surface("di-1.di", channel=channel))
        assert words in str(info.value) and "'AmplitudeError'" in str(info.value), str(info.value)


@pytest.mark.parametrize("name", FILES)
def test_the_highest_measured_point_is_where_the_indenter_is_lowest(name):
    surface = _scene(_surface(name, levelling="slope")).surface
    z = prepare(surface, surface_lengths(surface)).heights  # the measured surface, z out of its material
    h = profile(surface)
    assert np.unravel_index(np.argmin(h), h.shape) == np.unravel_index(np.argmax(z), z.shape)
    assert np.array_equal(h, -z)
    turned = _scene({**_surface(name, levelling="slope"), "facing": "valleys"}).surface
    assert np.array_equal(profile(turned), z)


def _first_contact_run(surface, tmp_path):
    """A hard-wall run into a penetration of 1 % of the prepared h_rms: (the run's fields, the measured z)."""
    import gfmd_contact as gc

    scene = _scene(surface)
    z = prepare(scene.surface, surface_lengths(scene.surface)).heights
    tables = {"surface": surface, "interface": {"law": "hard-wall"}, "output": {"field_steps": 3, "workers": 1},
              "loading": {"initial_separation": 0.01 * z.std(), "final_penetration": 0.01 * z.std(), "steps": 3}}
    res = gc.run(scene_from_dict(tables), out=tmp_path / "run", workers=1, progress=False)
    assert res.meta["complete"] and res.converged
    return res, z


@pytest.mark.parametrize("name", FILES)
def test_every_real_map_and_line_scan_runs_end_to_end_summits_first(name, tmp_path):
    """Resampled (32² / 256 nodes), levelled, 3 load steps: at the first step in contact the measured summit
    carries load, and the measured valley (what touched first before the surface faced the body) does not."""
    res, z = _first_contact_run(_surface(name, levelling="slope"), tmp_path)
    fields = res.fields(step=res.saved_steps()[-1])
    pressure = -fields["t_n"]
    summit, valley = np.unravel_index(np.argmax(z), z.shape), np.unravel_index(np.argmin(z), z.shape)
    assert pressure[summit] > 0 and pressure[valley] == 0
    assert np.count_nonzero(pressure > 0) < pressure.size // 10  # first contact: a few summits


def test_levelling_removes_a_planted_tilt_exactly(tmp_path):
    rng = np.random.default_rng(5)
    base = rng.standard_normal((24, 16)) * 1e-9
    x, y = np.meshgrid(np.arange(24) / 24 * 3e-6, np.arange(16) / 16 * 2e-6, indexing="ij")
    tilt = 4e-9 + 0.02 * x - 0.01 * y  # a mean, and slopes far above the roughness
    np.save(tmp_path / "base.npy", base)
    np.save(tmp_path / "tilted.npy", base + tilt)
    common = {"kind": "file", "nodes": 24, "nodes_y": 16, "length": 3e-6, "length_y": 2e-6, "facing": "valleys"}
    level = {m: [profile(_scene({**common, "path": str(tmp_path / f), "levelling": m}).surface)
                 for f in ("base.npy", "tilted.npy")] for m in ("slope", "curvature")}
    bound = base.size * EPS * np.abs(base + tilt).max()  # a least-squares fit over N points: N roundings at most
    for levelled, tilted in level.values():
        assert np.abs(levelled - tilted).max() <= bound
        assert abs(levelled.mean()) <= bound
    unlevelled = profile(_scene({**common, "path": str(tmp_path / "tilted.npy")}).surface)
    assert np.abs(unlevelled - level["slope"][1]).max() > 1e3 * bound  # "none" keeps it


@pytest.mark.parametrize("method", ["linear", "cubic", "fourier"])
def test_resampling_keeps_a_planted_sinusoid(tmp_path, method):
    n, m, length, waves, amplitude = 100, 64, 1e-6, 3, 2e-9
    k = 2 * np.pi * waves / length
    np.save(tmp_path / "s.npy", amplitude * np.cos(k * np.arange(n) * length / n))
    surface = {"kind": "file", "path": str(tmp_path / "s.npy"), "nodes": m, "length": length, "resample": method,
               "facing": "valleys"}
    h = profile(_scene(surface).surface)
    error = np.abs(h - amplitude * np.cos(k * np.arange(m) * length / m)).max()
    spacing = length / n
    bound = {"linear": spacing**2 / 8 * amplitude * k**2,  # |f − I₁f| ≤ l²/8 max|f''|
             "cubic": 5 / 384 * spacing**4 * amplitude * k**4,  # periodic cubic spline (Hall 1968)
             "fourier": 8 * n * EPS * amplitude}[method]  # band-limited and periodic: exact to round-off
    assert error <= bound
    with pytest.raises(SceneError, match=r"100 heights, but surface\.nodes = 64.*surface\.resample"):
        _scene({**surface, "resample": "none"})


def test_a_region_crops_the_map_and_sets_the_cell():
    full = _scene(_surface("mi-1.mi", nodes=256, nodes_y=256, resample="none")).surface
    spacing = full.length / 256  # 20 µm / 256
    crop = _scene(_surface("mi-1.mi", nodes=128, nodes_y=64, resample="none",
                           region=[0.0, 128 * spacing, 64 * spacing, 128 * spacing])).surface
    assert np.array_equal(profile(crop), profile(full)[0:128, 64:128])
    np.testing.assert_allclose((crop.length, crop.length_y), (128 * spacing, 64 * spacing), rtol=4 * EPS)
    with pytest.raises(SceneError, match=r"surface\.region = .*beyond the file's size"):
        _scene(_surface("mi-1.mi", region=[0.0, 30e-6, 0.0, 10e-6]))
    with pytest.raises(SceneError, match=r"surface\.region = .*\[x0, x1, y0, y1\]"):
        _scene(_surface("mi-1.mi", region=[0.0, 10e-6]))
    line = _scene(_surface("mi-1.mi", nodes=256, nodes_y=0, resample="none", line="x:17")).surface
    assert np.array_equal(profile(line), profile(full)[:, 17]) and line.length == full.length
    with pytest.raises(SceneError, match=r"surface\.line = 'y:300'.*outside"):
        _scene(_surface("mi-1.mi", nodes=256, nodes_y=0, line="y:300"))
    with pytest.raises(SceneError, match=r"surface\.line = 'x:3'.*1\+1-D profile.*surface\.nodes_y = 32"):
        _scene(_surface("mi-1.mi", line="x:3"))
    with pytest.raises(SceneError, match=r"surface\.line = 'x:3'.*a line of a map.*holds a line scan"):
        _scene(_surface("dektak-1.csv", line="x:3"))


def test_the_cell_size_agrees_with_the_file_or_is_refused():
    size = _scene(_surface("dektak-1.csv")).surface.length
    assert _scene(_surface("dektak-1.csv", length=size)).surface.length == size
    with pytest.raises(SceneError, match=r"physical size is 0\.0014998 m.*surface\.length = 0\.0015 m.*leave "
                                         r"surface\.length out"):
        _scene(_surface("dektak-1.csv", length=1.5e-3))


@pytest.mark.parametrize("key, value", [
    ("facing", "up"), ("channel", -1), ("channel", 1.5), ("region", [1e-6, 0.0]), ("region", [0, 1e-6, 0]),
    ("undefined", "zero"), ("line", "row:3"), ("height_unit", "furlong"), ("height_scale", 0.0),
    ("levelling", "plane"), ("resample", "nearest")])
def test_every_bad_value_names_its_key(key, value):
    with pytest.raises(SceneError, match=rf"surface\.{key} = "):
        _scene(_surface("mi-1.mi", **{key: value}))


def test_the_example_scene_of_a_real_map_loads_with_its_keys_recorded(tmp_path):
    from gfmd_contact.core.scene import load_scene, scene_to_toml

    scene = load_scene(DATA / "afm_map.toml")  # its path is relative to the scene file
    s = scene.surface
    assert (s.shape, s.levelling, s.resample, s.facing, s.channel) == ((64, 64), "slope", "fourier", "summits",
                                                                        "Topography")
    np.testing.assert_allclose((s.length, s.length_y), FILES["mi-1.mi"][1], rtol=README_RTOL)
    (tmp_path / "written.toml").write_text(scene_to_toml(scene))
    assert load_scene(tmp_path / "written.toml").surface == s
