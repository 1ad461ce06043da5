"""`gfmd run SCENE --method fe` end to end, for both FE interface laws (hard wall, cohesive).

The real command line (`gfmd_contact.cli.main`) on small finite-layer scenes: a sinusoid
(h0 = 10 nm, L = 1 µm, N = 32) and a self-affine profile (H = 0.8, h_rms = 5 nm,
λr = 250 nm, λs = L/16 = 4 l, seed 3, N = 64: verification/test_fe_selfaffine.py's
parameters, cut at λs = 4 l), layer D = L on a rigid base, E = 70 GPa,
ν = 0.3, δ0 = 2 nm, δ from −2 nm to 8 nm in 4 steps, fields saved at 2 steps.
Hard wall: frictionless; cohesive: normal-only CZ, φn* = 0.01, δn = 1 nm.

Each run must return 0 and write:

* curve.csv: one row per load step 0…steps (realization 0), U and δ the ramp of
  `gfmd_contact.core.loading.displacement_steps`, every step converged, contact reached;
* fields.npz: r0_s<k>_<field> for exactly the saved steps
  (`gfmd_contact.core.loading.field_step_indices`);
* vtu/realization0/fe.pvd listing fe_step<k>.vtu for every saved step, in
  order, with δ_k as the time value, and each of those files;
* each fe_step<k>.vtu, read back with meshio: the displacement at the mesh's
  surface nodes x_j (z = 0) equals u_z and u_x of fields.npz at step k.
  Measured difference: 0 (bit-identical, both are the same FE solution vector
  written as float64), so the comparison is exact.

Before the fix (hard-wall FE stored a dict per step, the export needs the
surface unknowns vector) the hard-wall runs raised TypeError in the VTU export.
"""

from __future__ import annotations

import csv
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from gfmd_contact.cli import main
from gfmd_contact.core.loading import displacement_steps, field_step_indices
from gfmd_contact.core.result import FIELD_NAMES
from gfmd_contact.core.scene import default_scene, scene_to_toml

LENGTH = 1e-6  # m
COMMON = {
    "surface.length": LENGTH, "surface.realizations": 1,
    "material.youngs_modulus": 70e9, "material.poisson_ratio": 0.3, "material.thickness": LENGTH,
    "interface.phi_n_star": 0.01, "interface.length_normal": 1e-9, "interface.tangential_ratio": 0.0,
    "loading.initial_separation": 2e-9, "loading.final_penetration": 10e-9, "loading.steps": 4,
    "output.field_steps": 2, "output.workers": 1,
}
PROFILES = {
    "sinusoid": {"surface.kind": "sinusoid", "surface.nodes": 32, "surface.amplitude": 10e-9},
    "self-affine": {"surface.kind": "self-affine", "surface.nodes": 64, "surface.hurst": 0.8,
                    "surface.h_rms": 5e-9, "surface.rolloff_wavelength": 250e-9,
                    "surface.rollon_wavelength": LENGTH / 16, "surface.seed": 3},
}
CASES = [(law, profile) for law in ("hard-wall", "cohesive") for profile in PROFILES]


def fe_scene(law, profile):
    return default_scene().replace(**{**COMMON, **PROFILES[profile], "interface.law": law})


def run_cli(tmp_path, scene):
    scene_file = tmp_path / "scene.toml"
    scene_file.write_text(scene_to_toml(scene))
    out = tmp_path / "out"
    rc = main(["run", str(scene_file), "--method", "fe", "--out", str(out), "--quiet", "--no-plot"])
    return rc, out


def read_curve(out):
    with open(out / "curve.csv") as fh:
        rows = list(csv.DictReader(fh))
    return {name: np.array([float(r[name]) for r in rows]) for name in rows[0]}


def read_series(pvd):
    root = ET.parse(pvd).getroot()
    assert root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def surface_nodes(mesh, x):
    """Indices of the mesh points at (x_j, 0), one per GFMD node x_j."""
    top = np.flatnonzero(mesh.points[:, 1] == 0.0)
    distance = np.abs(mesh.points[top, 0][None, :] - x[:, None])  # (N, top points)
    assert np.max(np.min(distance, axis=1)) < 1e-12 * LENGTH, "no mesh node at some x_j"
    return top[np.argmin(distance, axis=1)]


@pytest.mark.parametrize("law,profile", CASES, ids=[f"{law}-{profile}" for law, profile in CASES])
def test_cli_fe_run_writes_curve_fields_and_matching_vtu(tmp_path, capsys, law, profile):
    scene = fe_scene(law, profile)
    rc, out = run_cli(tmp_path, scene)
    err = capsys.readouterr().err
    assert rc == 0, err
    assert "model solved: FE P2" in err
    assert ("hard wall" in err) == (law == "hard-wall")

    # curve.csv: every load step of realization 0, the scene's ramp, converged, with contact
    curve = read_curve(out)
    steps = scene.loading.steps
    np.testing.assert_array_equal(curve["realization"], np.zeros(steps + 1))
    np.testing.assert_array_equal(curve["step"], np.arange(steps + 1))
    ramp = displacement_steps(scene.loading)
    np.testing.assert_allclose(curve["U"], ramp, rtol=0, atol=1e-15 * np.max(np.abs(ramp)))
    np.testing.assert_allclose(curve["delta"], ramp - scene.loading.initial_separation,
                               rtol=0, atol=1e-15 * np.max(np.abs(ramp)))
    assert np.all(curve["converged"] == 1)
    assert curve["a_rel"][-1] > 0 and np.all(np.isfinite(curve["p"]))

    # fields.npz: exactly the saved steps
    saved = sorted(field_step_indices(scene.loading, scene.output.field_steps))
    assert len(saved) == scene.output.field_steps
    with np.load(out / "fields.npz") as npz:
        fields = dict(npz)
    assert {key for key in fields if key.startswith("r0_s")} == {
        f"r0_s{k}_{name}" for k in saved for name in FIELD_NAMES}
    x = fields["x"]

    # fe.pvd lists every saved step, in order, with δ_k as time
    vtu_dir = out / "vtu" / "realization0"
    series = read_series(vtu_dir / "fe.pvd")
    assert [name for _, name in series] == [f"fe_step{k}.vtu" for k in saved]
    np.testing.assert_array_equal([t for t, _ in series], curve["delta"][saved])
    assert sorted(p.name for p in vtu_dir.glob("*.vtu")) == sorted(f"fe_step{k}.vtu" for k in saved)

    # each VTU: surface displacement at the nodes = the saved fields (same solution vector: exact)
    for k in saved:
        mesh = meshio.read(vtu_dir / f"fe_step{k}.vtu")
        disp = mesh.point_data["displacement"]
        assert disp.shape == (mesh.points.shape[0], 3) and np.all(np.isfinite(disp))
        assert np.all(np.isfinite(mesh.point_data["stress"]))
        idx = surface_nodes(mesh, x)
        u_z = fields[f"r0_s{k}_u_z"]
        assert np.max(np.abs(u_z)) > 0, f"step {k}: the surface did not move; the comparison is vacuous"
        np.testing.assert_array_equal(disp[idx, 1], u_z, err_msg=f"step {k}: VTU u_z ≠ fields.npz u_z")
        np.testing.assert_array_equal(disp[idx, 0], fields[f"r0_s{k}_u_x"],
                                      err_msg=f"step {k}: VTU u_x ≠ fields.npz u_x")
