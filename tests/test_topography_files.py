"""Measured topographies through SurfaceTopography, the optional extra (gfmd_contact.core.topography_files).

The files are written by SurfaceTopography itself (netCDF, its container format, round-trips heights, unit
and physical size exactly) and read back through a scene; tests that need the package skip without it,
the missing-package refusal runs everywhere. These check the heights as read, so their scenes say
surface.facing = "valleys" (the file's heights are the indenter's lower surface as they are).
"""

import sys

import numpy as np
import pytest

from gfmd_contact.core import topography_files
from gfmd_contact.core.scene import SceneError, load_scene, scene_from_dict
from gfmd_contact.core.surfaces import profile

# heights converted by one product with the unit's factor: equal to value × factor up to one rounding
ONE_ROUNDING = 2.0**-52


@pytest.fixture
def st():
    return pytest.importorskip("SurfaceTopography")


def _line_scan(st, path, heights, size, unit):
    st.UniformLineScan(heights, size, unit=unit).to_netcdf(str(path))
    return path


def _map(st, path, heights, sizes, unit):
    st.Topography(heights, sizes, unit=unit).to_netcdf(str(path))
    return path


def _surface(path, nodes, length, **extra):
    return {"surface": {"kind": "file", "path": str(path), "nodes": nodes, "length": length, "facing": "valleys",
                        **extra}}


def test_line_scan_in_micrometres_is_a_profile_in_metres(st, tmp_path):
    h_um = np.random.default_rng(1).uniform(-0.05, 0.05, 64)
    _line_scan(st, tmp_path / "scan.nc", h_um, 2.0, "µm")
    (tmp_path / "s.toml").write_text('[surface]\nkind = "file"\nnodes = 64\nlength = 2e-6\npath = "scan.nc"\n'
                                      'facing = "valleys"\n')
    h = profile(load_scene(tmp_path / "s.toml").surface)  # relative path, the scene's validation, the profile
    assert h.shape == (64,)
    np.testing.assert_allclose(h, h_um * 1e-6, rtol=ONE_ROUNDING, atol=0)


@pytest.mark.parametrize("unit, factor", [("nm", 1e-9), ("mm", 1e-3), ("m", 1.0), ("Å", 1e-10)])
def test_map_is_a_surface_in_metres_axis_0_x(st, tmp_path, unit, factor):
    nx, ny = 16, 8  # not square: axis 0 of the file is x, as in the .npy maps
    h_file = np.random.default_rng(2).uniform(-1, 1, (nx, ny))
    lx, ly = 4e-7, 2e-7
    _map(st, tmp_path / "map.nc", h_file, (lx / factor, ly / factor), unit)
    scene = scene_from_dict(_surface(tmp_path / "map.nc", nx, lx, nodes_y=ny, length_y=ly))
    h = profile(scene.surface)
    assert h.shape == (nx, ny)
    np.testing.assert_allclose(h, h_file * factor, rtol=ONE_ROUNDING, atol=0)


def test_wrong_grid_names_the_keys_and_what_the_file_holds(st, tmp_path):
    scan = _line_scan(st, tmp_path / "scan.nc", np.zeros(32), 1.0, "µm")
    with pytest.raises(SceneError, match=r"surface\.path.*32 points.*\(surface\.nodes\) = \(16\)"):
        scene_from_dict(_surface(scan, 16, 1e-6))
    surface = _map(st, tmp_path / "map.nc", np.zeros((16, 8)), (1.0, 0.5), "µm")
    with pytest.raises(SceneError, match=r"16 × 8 points.*\(surface\.nodes, surface\.nodes_y\) = \(16, 16\)"):
        scene_from_dict(_surface(surface, 16, 1e-6, nodes_y=16, length_y=0.5e-6))
    with pytest.raises(SceneError, match=r"surface\.path.*2-D topography.*needs a line scan"):
        scene_from_dict(_surface(surface, 16, 1e-6))
    with pytest.raises(SceneError, match=r"surface\.path.*1-D topography.*needs a 2-D topography map"):
        scene_from_dict(_surface(scan, 32, 1e-6, nodes_y=32, length_y=1e-6))


def test_physical_size_must_be_the_cell(st, tmp_path):
    scan = _line_scan(st, tmp_path / "scan.nc", np.zeros(16), 5.0, "µm")
    scene_from_dict(_surface(scan, 16, 5e-6))  # 5 µm × 1e-6 is 5e-6 m up to round-off
    with pytest.raises(SceneError, match=r"physical size is 5e-06 m \(5 µm\), but surface\.length = 5\.1e-06"):
        scene_from_dict(_surface(scan, 16, 5.1e-6))
    inside = 5e-6 * (1 + topography_files.SIZE_RTOL / 2)
    scene_from_dict(_surface(scan, 16, inside))
    outside = 5e-6 * (1 + 2 * topography_files.SIZE_RTOL)
    with pytest.raises(SceneError, match=r"surface\.length ="):
        scene_from_dict(_surface(scan, 16, outside))
    surface = _map(st, tmp_path / "map.nc", np.zeros((8, 8)), (1.0, 2.0), "nm")
    with pytest.raises(SceneError, match=r"physical size is 2e-09 m \(2 nm\), but surface\.length_y = 1e-09"):
        scene_from_dict(_surface(surface, 8, 1e-9, nodes_y=8, length_y=1e-9))


def test_unknown_unit_masked_and_unreadable_files_are_refused(st, tmp_path):
    furlongs = _line_scan(st, tmp_path / "f.nc", np.zeros(16), 1.0, "furlong")
    with pytest.raises(SceneError, match=r"surface\.path = .*f\.nc.*unit 'furlong', not a known length "
                                         r"unit.*surface\.height_unit supplies it"):
        scene_from_dict(_surface(furlongs, 16, 201.168))
    h = np.ma.masked_array(np.zeros((8, 8)), mask=np.zeros((8, 8), bool))
    h.mask[3, 4] = True
    masked = _map(st, tmp_path / "m.nc", h, (1.0, 1.0), "nm")
    with pytest.raises(SceneError, match=r"surface\.path.*undefined \(masked or non-finite\) heights \(1 of "
                                         r"64\).*surface\.undefined"):
        scene_from_dict(_surface(masked, 8, 1e-9, nodes_y=8, length_y=1e-9))
    garbage = tmp_path / "scan.sur"
    garbage.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(SceneError, match=r"surface\.path = .*scan\.sur.*binary content.*SurfaceTopography "
                                         r"cannot read it"):
        scene_from_dict(_surface(garbage, 16, 1e-6))


def test_without_the_extra_the_refusal_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "SurfaceTopography", None)  # `import SurfaceTopography` raises ImportError
    monkeypatch.setitem(sys.modules, "SurfaceTopography.Support.UnitConversion", None)
    path = tmp_path / "scan.x3p"
    path.write_bytes(b"PK\x03\x04")
    for dims in ({}, {"nodes_y": 16, "length_y": 1e-6}):
        with pytest.raises(SceneError, match=r"surface\.path = .*scan\.x3p.*"
                                             r"pip install \"gfmd-contact\[topography\]\""):
            scene_from_dict(_surface(path, 16, 1e-6, **dims))
    text = tmp_path / "h.txt"  # .npy and text need no extra
    text.write_text("\n".join(["1e-9"] * 16))
    assert np.array_equal(profile(scene_from_dict(_surface(text, 16, 1e-6)).surface), np.full(16, 1e-9))
