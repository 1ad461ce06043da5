"""`gfmd scene --check` on a measured file: the prepared topography's statistics (gfmd_contact.core.topography_stats)
and its figure (gfmd_contact.app.topography_plots), and the statistics on planted heights where they are exact."""

import contextlib
import io
from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.cli import main
from gfmd_contact.core.scene import load_scene, scene_to_toml
from gfmd_contact.core.topography_stats import statistics

DATA = Path(__file__).parent / "data" / "topographies"
EPS = np.finfo(float).eps


def test_a_ramp_has_its_slope_and_no_curvature():
    length, n, slope = 2e-6, 64, 0.03
    z = slope * np.arange(n) * length / n
    st = statistics(z, (length,))
    assert abs(st["rms_slope"] - slope) <= 4 * EPS * slope and st["rms_curvature"] <= 4 * n * EPS * slope / (
        length / n)
    assert st["wavelengths"] == (2 * length / n, length) and st["spacings"] == (length / n,)


def test_a_paraboloid_has_its_curvature_exactly():
    """z = c(x² + y²)/2: the mean curvature ½∇²z = c at every node; central differences are exact on it."""
    (nx, lx), (ny, ly), c = (32, 1e-6), (16, 0.5e-6), 3e4
    x, y = np.meshgrid(np.arange(nx) * lx / nx, np.arange(ny) * ly / ny, indexing="ij")
    st = statistics(c * (x**2 + y**2) / 2, (lx, ly))
    bound = 64 * EPS * c * (lx**2 + ly**2) / (lx / nx) ** 2  # round-off of a second difference of values ≤ c L²
    assert abs(st["rms_curvature"] - c) <= bound
    assert st["h_rms"] == pytest.approx(np.std(c * (x**2 + y**2) / 2), rel=EPS)


def test_scene_check_prints_the_prepared_statistics_and_writes_the_figure(tmp_path):
    pytest.importorskip("SurfaceTopography")
    scene = tmp_path / "scan.toml"
    scene.write_text(f'[surface]\nkind = "file"\npath = "{DATA / "dektak-1.csv"}"\nnodes = 256\n'
                     'levelling = "slope"\nresample = "cubic"\n\n[interface]\nlaw = "cohesive"\n')
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        assert main(["scene", "--check", str(scene)]) == 0
    lines = [line for line in out.getvalue().splitlines() if line.startswith("topography: ")]
    text = "\n".join(lines)
    for words in ("9600 points over 0.0014998 m, heights in µm", "levelling slope, resample cubic, facing summits",
                  "h_rms = ", "rms slope = ", "rms curvature = ", "PSD wavelengths from 1.17172e-05 m (2l) to "
                  "0.0014998 m (L)", "against the process zone l_pz", "scan_topography.png"):
        assert words in text, text
    assert (tmp_path / "scan_topography.png").stat().st_size > 0
    written = load_scene(scene)
    assert 'levelling = "slope"' in scene_to_toml(written) and 'facing = "summits"' in scene_to_toml(written)
