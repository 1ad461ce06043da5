"""`gfmd run SCENE2D --method fe`: the 3-D FE (reference.fem3d) through the one ramp, end to end.

A 12 × 10 egg-box on a bonded layer (Lx = 120 nm, Ly = 100 nm, D = Lx, E = 70 GPa, ν = 0.3,
A = 2 nm, δ0 = 1 nm, δ from −1 nm to 3 nm in 4 steps, 2 saved steps), hard wall and normal CZ
(φn* = 0.01, δn = 1 nm). The run must return 0 and write curve.csv (every step converged, the
scene's ramp), fields.npz with (Nx, Ny) fields of the saved steps, meta.json naming the 3-D FE,
and one VTU per saved step whose surface u_z equals fields.npz's (the same vector through the
FFT of `Cell3D.displacement_field`: round-off, measured ≤ 2e-25 m on 1e-10 m). The
ramp's curve must equal `reference.fem3d.solve_cell` on the same inputs (the plain-input entry the
fem3d tests check) to the solver tolerance. Refusals exit 2 naming the key: a half-space
(material.thickness) and a surface over 64² (surface.nodes).
"""

from __future__ import annotations

import csv
import json

import meshio
import numpy as np
import pytest

from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import displacement_steps, field_step_indices
from gfmd_contact.core.scene import scene_from_dict, scene_to_toml
from reference.fem3d import solve_cell
from gfmd_contact.cli import main

LX = 1.2e-7


def scene(law, **surface):
    s = {"kind": "egg-box", "nodes": 12, "nodes_y": 10, "length": LX, "length_y": 1e-7, "amplitude": 2e-9,
         "realizations": 1, **surface}
    return scene_from_dict({"surface": s, "material": {"youngs_modulus": 70e9, "poisson_ratio": 0.3,
                                                       "thickness": LX},
                            "interface": {"law": law, "phi_n_star": 0.01, "length_normal": 1e-9},
                            "loading": {"initial_separation": 1e-9, "final_penetration": 3e-9, "steps": 4},
                            "output": {"field_steps": 2, "workers": 1}, "method": {"name": "fe"}}, name="eggbox2d")


def _curve(out):
    with open(out / "curve.csv") as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in ("U", "p", "a_rel", "g_r", "converged")}


@pytest.mark.parametrize("law", ["hard-wall", "cohesive"])
def test_fe_on_a_surface_writes_the_run_directory(tmp_path, capsys, law):
    sc = scene(law)
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(sc))
    out = tmp_path / "r"
    assert main(["run", str(path), "--method", "fe", "--out", str(out), "--quiet", "--no-plot"]) == 0, \
        capsys.readouterr().err
    curve = _curve(out)
    ramp = displacement_steps(sc.loading)
    np.testing.assert_allclose(curve["U"], ramp, rtol=0, atol=1e-15 * np.max(np.abs(ramp)))
    assert np.all(curve["converged"] == 1) and curve["a_rel"][-1] > 0
    meta = json.loads((out / "meta.json").read_text())
    assert "fe3d-q1" in json.dumps(meta) and "Q1 hexahedra" in json.dumps(meta)

    # the same numbers as the plain-input entry on the same heights and displacements
    h = surfaces.profile(sc.surface, 0)
    ref = solve_cell(h, LX, 1e-7, 70e9, 0.3, LX, ramp, law=law, phi_n_star=0.01, length_normal=1e-9,
                     initial_separation=1e-9)
    scale = 70e9 / (1 - 0.09) * ref.curve["g"][0]  # p_ref = E* ḡ: the residual's scale
    np.testing.assert_allclose(curve["p"], ref.curve["p"], rtol=0, atol=1e-8 * scale)
    np.testing.assert_array_equal(curve["a_rel"], ref.curve["a_rel"])

    saved = sorted(field_step_indices(sc.loading, sc.output.field_steps))
    with np.load(out / "fields.npz") as npz:
        f = dict(npz)
    for k in saved:
        u_z = f[f"r0_s{k}_u_z"]
        assert u_z.shape == (12, 10) and np.max(np.abs(u_z)) > 0
        np.testing.assert_allclose(u_z, ref.fields[k]["u_z"], rtol=0, atol=1e-8 * np.max(np.abs(u_z)))
        mesh = meshio.read(out / "vtu" / "realization0" / f"fe3d_step{k}.vtu")
        top = mesh.points[:, 2] == 0.0
        i = np.rint(mesh.points[top, 0] / (LX / 12)).astype(int) % 12
        j = np.rint(mesh.points[top, 1] / (1e-7 / 10)).astype(int) % 10
        np.testing.assert_allclose(mesh.point_data["displacement"][top, 2], u_z[i, j], rtol=0,
                                   atol=1e-13 * np.max(np.abs(u_z)))  # u_z through the FFT of the interior field


@pytest.mark.parametrize("change, key", [({"material": {"thickness": "inf"}}, "material.thickness"),
                                         ({"surface": {"nodes": 72, "nodes_y": 64}}, "surface.nodes")])
def test_what_the_3d_fe_cannot_do_is_refused(tmp_path, capsys, change, key):
    from gfmd_contact.core.scene import scene_to_dict

    d = scene_to_dict(scene("hard-wall"))
    for section, values in change.items():
        d[section].update(values)
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(scene_from_dict(d)))
    assert main(["run", str(path), "--method", "fe", "--out", str(tmp_path / "r"), "--quiet", "--no-plot"]) == 2
    assert key in capsys.readouterr().err
