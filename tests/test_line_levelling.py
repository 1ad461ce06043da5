"""Scan-line levelling of a measured map (surface.line_levelling, surface.scan_axis;
gfmd_contact.core.topography_prep.level_lines): planted per-line offsets and tilts removed exactly, the key
validated, written to scene.toml, shown by `gfmd scene --check`, refused by a profile, and on the real AFM map
di-1.di the scan lines' excess slope across them removed."""

import contextlib
import io
from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.cli import main
from gfmd_contact.core.scene import (
    SceneError,
    load_scene,
    scene_from_dict,
    scene_to_toml,
)
from gfmd_contact.core.topography_prep import level_lines, prepare, surface_lengths
from gfmd_contact.core.topography_stats import statistics

DATA = Path(__file__).parent / "data" / "topographies"
EPS = np.finfo(float).eps
NX, NY, LX, LY = 24, 16, 2.4e-6, 1.6e-6


def _base():
    rng = np.random.default_rng(7)
    return 1e-8 * rng.standard_normal((NX, NY))


def _planted(z, axis):
    """z plus an offset and a tilt of its own on every line along `axis` (0: x)."""
    rng = np.random.default_rng(11)
    n, m = z.shape[axis], z.shape[1 - axis]
    offsets, tilts = 5e-8 * rng.standard_normal(m), 1e-8 * rng.standard_normal(m)
    plant = offsets[None, :] + np.arange(n)[:, None] * tilts[None, :]  # (along, lines)
    return z + (plant if axis == 0 else plant.T)


def _reference(z, axis, degree):
    """Each line along `axis` less its own least-squares polynomial of `degree` (numpy.polyfit, line by line)."""
    lines = z if axis == 0 else z.T
    x = np.arange(lines.shape[0])
    out = np.stack([line - np.polyval(np.polyfit(x, line, degree), x) for line in lines.T], axis=1)
    return out if axis == 0 else out.T


@pytest.mark.parametrize("axis", [0, 1])
def test_planted_per_line_offsets_and_tilts_are_removed_exactly(axis):
    z = _base()
    h = _planted(z, axis)
    scan_axis = "xy"[axis]
    bound = 64 * EPS * np.max(np.abs(h)) * max(NX, NY)
    assert np.max(np.abs(level_lines(h, scan_axis, "slope") - level_lines(z, scan_axis, "slope"))) <= bound
    assert np.max(np.abs(level_lines(h, scan_axis, "slope") - _reference(z, axis, 1))) <= bound
    offsets_only = z + (np.take(h - z, [0], axis=axis))  # the planted offsets, no tilt
    assert np.max(np.abs(level_lines(offsets_only, scan_axis, "height") - _reference(z, axis, 0))) <= bound
    # the other axis's lines do not hold the plant: levelling them leaves it
    assert np.max(np.abs(level_lines(h, "xy"[1 - axis], "slope") - level_lines(z, "xy"[1 - axis], "slope"))) > 1e3 * bound
    assert level_lines(h, scan_axis, "none") is h


def _npy_scene(tmp_path, heights, **keys):
    np.save(tmp_path / "map.npy", heights)
    surface = {"kind": "file", "path": str(tmp_path / "map.npy"), "nodes": NX, "nodes_y": NY, "length": LX,
               "length_y": LY, **keys}
    return scene_from_dict({"surface": surface})


def test_a_scene_levels_the_lines_before_the_whole_map(tmp_path):
    """Steps in order: height_scale, line_levelling along scan_axis, then levelling (the documented order)."""
    z = _base()
    scene = _npy_scene(tmp_path, _planted(z, 1), scan_axis="y", line_levelling="slope", levelling="curvature",
                       height_scale=2.0)
    s = scene.surface
    got = prepare(s, surface_lengths(s)).heights
    import SurfaceTopography

    want = SurfaceTopography.Topography(_reference(2 * z, 1, 1), (LX, LY), periodic=False).detrend("curvature")
    assert np.max(np.abs(got - want.heights())) <= 256 * EPS * np.max(np.abs(2 * z))


def test_the_keys_are_written_to_scene_toml_and_read_back(tmp_path):
    scene = _npy_scene(tmp_path, _base(), line_levelling="height", scan_axis="y")
    text = scene_to_toml(scene)
    assert 'line_levelling = "height"' in text and 'scan_axis = "y"' in text
    (tmp_path / "written.toml").write_text(text)
    assert load_scene(tmp_path / "written.toml").surface == scene.surface
    default = _npy_scene(tmp_path, _base()).surface
    assert (default.line_levelling, default.scan_axis) == ("none", "x")


@pytest.mark.parametrize("key, value", [("line_levelling", "median"), ("line_levelling", "curvature"),
                                        ("line_levelling", 1), ("scan_axis", "z"), ("scan_axis", 0)])
def test_a_bad_value_names_its_key(tmp_path, key, value):
    with pytest.raises(SceneError, match=rf"surface\.{key} = .*must be one of"):
        _npy_scene(tmp_path, _base(), **{key: value})


def test_a_profile_refuses_line_levelling(tmp_path):
    np.save(tmp_path / "line.npy", _base()[:, 0])
    line = {"kind": "file", "path": str(tmp_path / "line.npy"), "nodes": NX, "length": LX}
    scene_from_dict({"surface": {**line, "line_levelling": "none"}})
    pytest.importorskip("SurfaceTopography")
    a_line_of_a_map = {"kind": "file", "path": str(DATA / "di-1.di"), "nodes": 512, "line": "x:3"}
    scene_from_dict({"surface": a_line_of_a_map})
    for surface in ({**line, "line_levelling": "height"}, {**a_line_of_a_map, "line_levelling": "slope"}):
        with pytest.raises(SceneError, match=r"surface\.line_levelling = '(height|slope)': levels each scan line "
                                             r"of a map, but the scene is a 1\+1-D profile"):
            scene_from_dict({"surface": surface})


def _di(region, **keys):
    pytest.importorskip("SurfaceTopography")
    n = 512 if not region else 256
    surface = {"kind": "file", "path": str(DATA / "di-1.di"), "nodes": n, "nodes_y": n, "channel": 0,
               "levelling": "slope", **({"region": region} if region else {}), **keys}
    s = scene_from_dict({"surface": surface}).surface
    p = prepare(s, surface_lengths(s))
    return statistics(p.heights, p.sizes)


@pytest.mark.parametrize("region", [[], [0.0, 250e-9, 0.0, 250e-9]])
def test_di_map_line_levelling_removes_the_scan_lines_excess_slope(region):
    """di-1.di's scan lines run along x (axis 0 of SurfaceTopography's heights: the file stores samps/line points
    per line, read as (lines, samps/line) and transposed). Before: the slope across the lines (y) is over 3× the
    slope along them; after each line's own mean and tilt are removed, under 1.5× (an isotropic surface has 1×;
    measured 1.34 on the whole map, 0.99 on its first quadrant). Levelling the wrong axis (y) leaves the excess."""
    before = _di(region)["rms_slopes"]
    after = _di(region, line_levelling="slope")["rms_slopes"]
    wrong = _di(region, line_levelling="slope", scan_axis="y")["rms_slopes"]
    assert before[1] > 3 * before[0]
    assert after[1] < 1.5 * after[0]
    assert wrong[1] > 3 * wrong[0]


def test_scene_check_shows_line_levelling(tmp_path):
    pytest.importorskip("SurfaceTopography")
    scene = tmp_path / "map.toml"
    scene.write_text(f'[surface]\nkind = "file"\npath = "{DATA / "di-1.di"}"\nnodes = 64\nnodes_y = 64\n'
                     'line_levelling = "slope"\nlevelling = "slope"\nresample = "fourier"\n')
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        assert main(["scene", "--check", str(scene)]) == 0
    prepared = [line for line in out.getvalue().splitlines() if line.startswith("topography: prepared: ")]
    assert len(prepared) == 1 and "line_levelling slope (scan lines along x), levelling slope" in prepared[0]
    assert "rms slope = " in out.getvalue() and "(along x " in out.getvalue()
