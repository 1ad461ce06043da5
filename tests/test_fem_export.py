"""VTU/PVD export of FE runs (`reference.fem.export`): files read back with meshio.

Round trip: meshio writes VTU data arrays in binary (base64, float64), so
points, connectivity, point data (displacement, stress) and cell data (stress)
must come back bit-identical to the in-memory `step_mesh` (exact comparison,
no tolerance). Independent checks: the exported displacement at the GFMD nodes
is the run's recorded surface field (bit-identical: the same solution vector);
the P2 "triangle6" nodes 3–5 are the midpoints of the edges 01, 12, 20 (VTK's
quadratic-triangle order; 1e-12 relative to L: coordinates are sums of two
doubles); the dense and sparse runs export the same displacement (1e-8
relative, the bound of tests/test_fem_sparse.py). The PVD collection must list
every exported step, in order, with δ as its time value. Every check runs on
both FE interface paths, cohesive (`reference.fem.solver`) and hard wall
(`reference.fem.hardwall`), P1 and P2: both store `Result.solutions[k]` as the
vector of the problem's surface unknowns that the export extends to every DOF.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

import gfmd.loading as gl
from gfmd_contact.core import surfaces
from reference import fem
from reference.fem.export import SERIES_NAME, step_mesh
from verification.scenes import cohesive_sinusoid as cohesive_scene


def small_scene(steps=4, field_steps=2, law="cohesive"):
    """N = 8 sinusoid of verification.scenes.cohesive_sinusoid (h0 = 50 nm, D = L = 1 µm), a short ramp to
    δ = 58 nm; law "hard-wall" keeps the geometry (contact from the first loaded step)."""
    return cohesive_scene(8).replace(**{"loading.steps": steps, "output.field_steps": field_steps,
                                        "interface.law": law})


_RUNS = [("cohesive", 1), ("cohesive", 2), ("hard-wall", 1), ("hard-wall", 2)]


@pytest.fixture(scope="module", params=_RUNS, ids=[f"{law}-P{order}" for law, order in _RUNS])
def run(request):
    law, order = request.param
    result = fem.run_realization(small_scene(law=law), order=order)
    assert result.all_converged, result.messages
    return result


def _series(directory):
    root = ET.parse(directory / SERIES_NAME).getroot()
    assert root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def test_vtu_round_trip_is_exact(run, tmp_path):
    paths = fem.export_vtu(run, tmp_path)
    assert [p.name for p in paths] == [f"fe_step{k}.vtu" for k in sorted(run.diagnostics["solutions"])]
    for k, path in zip(sorted(run.diagnostics["solutions"]), paths):
        written, back = step_mesh(run, k), meshio.read(path)
        assert np.array_equal(back.points, written.points)
        assert [c.type for c in back.cells] == [c.type for c in written.cells]
        assert all(np.array_equal(b.data, w.data) for b, w in zip(back.cells, written.cells))
        assert set(back.point_data) == {"displacement", "stress"}
        for name in ("displacement", "stress"):
            assert np.array_equal(back.point_data[name], written.point_data[name]), name
        assert np.array_equal(back.cell_data["stress"][0], written.cell_data["stress"][0])
        assert np.all(np.isfinite(back.point_data["stress"]))


def test_exported_surface_displacement_is_the_recorded_field(run, tmp_path):
    paths = fem.export_vtu(run, tmp_path)
    x_nodes = surfaces.grid(run.scene.surface.nodes, run.scene.surface.length)
    for k, path in zip(sorted(run.diagnostics["solutions"]), paths):
        m = meshio.read(path)
        top = np.flatnonzero(m.points[:, 1] == 0.0)
        distance = np.abs(m.points[top, 0][None, :] - x_nodes[:, None])  # (N, top points)
        idx = top[np.argmin(distance, axis=1)]
        assert np.max(np.min(distance, axis=1)) < 1e-12 * run.scene.surface.length  # a mesh node at every x_j
        assert np.array_equal(m.point_data["displacement"][idx, 1], run.fields[k]["u_z"])
        assert np.array_equal(m.point_data["displacement"][idx, 0], run.fields[k]["u_x"])


@pytest.mark.parametrize("run", [("cohesive", 2), ("hard-wall", 2)], ids=["cohesive-P2", "hard-wall-P2"],
                         indirect=True)  # P1 writes linear triangles: no midside nodes
def test_p2_midside_nodes_follow_vtk_order(run):
    assert run.diagnostics["problem"].cell.order == 2
    m = step_mesh(run, max(run.diagnostics["solutions"]))
    (block,) = m.cells
    assert block.type == "triangle6"
    c = m.points[block.data]  # (n_cells, 6, 3)
    length = run.scene.surface.length
    for mid, (a, b) in zip((3, 4, 5), ((0, 1), (1, 2), (2, 0))):
        assert np.max(np.abs(c[:, mid] - 0.5 * (c[:, a] + c[:, b]))) < 1e-12 * length


def test_series_lists_every_step(run, tmp_path):
    fem.export_vtu(run, tmp_path)
    entries = _series(tmp_path)
    steps = sorted(run.diagnostics["solutions"])
    assert [name for _, name in entries] == [f"fe_step{k}.vtu" for k in steps]
    assert all((tmp_path / name).is_file() for _, name in entries)
    assert [t for t, _ in entries] == [float(run.curve["delta"][k]) for k in steps]
    # a subset rewrites the collection with that subset only
    fem.export_vtu(run, tmp_path / "one", steps=[steps[-1]])
    assert [name for _, name in _series(tmp_path / "one")] == [f"fe_step{steps[-1]}.vtu"]


def test_sparse_run_exports_the_same_displacement(tmp_path):
    sc = small_scene()
    dense, sparse = (fem.run_realization(sc, linear=linear) for linear in ("dense", "sparse"))
    a, b = fem.export_vtu(dense, tmp_path / "dense"), fem.export_vtu(sparse, tmp_path / "sparse")
    for pa, pb in zip(a, b):
        ua, ub = meshio.read(pa).point_data["displacement"], meshio.read(pb).point_data["displacement"]
        assert np.max(np.abs(ua - ub)) < 1e-8 * np.max(np.abs(ua))


def test_bad_inputs_raise(run, tmp_path):
    gfmd_result = gl.run_realization(small_scene(steps=2))
    with pytest.raises(ValueError, match="run_realization"):
        fem.export_vtu(gfmd_result, tmp_path)
    with pytest.raises(ValueError, match="no stored FE solution"):
        fem.export_vtu(run, tmp_path, steps=[1])
    with pytest.raises(ValueError, match="nothing to export"):
        fem.export_vtu(fem.run_realization(small_scene(steps=2, field_steps=0)), tmp_path)
