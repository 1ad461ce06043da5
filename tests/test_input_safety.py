"""Every input ends the documented way: 2+1-D force control, hostile surface files, grids too big for the
machine, a force-control step the search gave up on, huge studies, and the right words for odd paths and
user laws that raise. Each test reproduces one case that used to end in a traceback or the wrong words."""

from __future__ import annotations

import contextlib
import io
import subprocess
import sys

import numpy as np
import pytest

import gfmd_contact as gc
from gfmd_contact.cli import main
from gfmd_contact.core.scene import scene_to_toml

GRID_2D = {"surface.kind": "self-affine", "surface.nodes": 32, "surface.nodes_y": 32, "surface.length": 1.28e-7,
           "surface.length_y": 1.28e-7, "surface.h_rms": 1e-9, "surface.rolloff_wavelength": 6.4e-8,
           "surface.rollon_wavelength": 1.6e-8, "surface.realizations": 1, "material.thickness": "inf",
           "interface.law": "hard-wall", "output.workers": 1, "output.field_steps": 1}


def cli(argv):
    """(exit code, stderr) of `gfmd ARGV` in this process."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(argv)
    return code, err.getvalue()


def write_scene(tmp_path, scene, name="scene.toml"):
    path = tmp_path / name
    path.write_text(scene_to_toml(scene))
    return path


def force_2d(top):
    return gc.change(gc.default_scene(), {**GRID_2D, "loading.control": "force", "loading.initial_separation": 1e-9,
                                          "loading.path": [0.0, top, 0.0], "loading.steps": 5})


# -- 1. 2+1-D force control on a half-space -------------------------------------------------------------------


def test_full_contact_pressure_of_an_egg_box_is_the_kernel_times_the_amplitude():
    """On a half-space, h = a cos(2πx/Lx) cos(2πy/Ly) has one wavevector |q0|: F⁻¹[k ĥ] = E*|q0|/2 · h, so
    p̄_fc = E*|q0| a/2 (the 2+1-D bound; the 1-D one broadcast a (Ny//2+1)-column spectrum against Nx)."""
    from gfmd_contact.core.loading import full_contact_pressure
    from gfmd_contact.core.surfaces_2d import egg_box

    a, lx, ly, e, nu = 2e-9, 1e-7, 0.5e-7, 1e9, 0.3
    h = egg_box(32, lx, 16, ly, a)
    q0 = 2 * np.pi * np.hypot(1 / lx, 1 / ly)
    assert full_contact_pressure(h, lx, e, nu, ly) == pytest.approx(e / (1 - nu**2) * q0 * a / 2, rel=1e-12)


@pytest.mark.parametrize("top, code", [(100e6, 0), (1e12, 2)])
def test_2d_force_control_on_a_half_space_is_checked_naming_the_path(tmp_path, top, code):
    """The issue's recipe (32 × 32 self-affine, hard wall, force path [0, top, 0]): a leaked numpy broadcast
    error naming no key, exit 2; now checked, and a load beyond full contact refused naming loading.path."""
    got, err = cli(["scene", "--check", str(write_scene(tmp_path, force_2d(top)))])
    assert "broadcast" not in err
    assert got == code, err
    assert ("gfmd: error: loading.path" in err) == (code == 2), err


# -- 3. memory preflight --------------------------------------------------------------------------------------


def big_scene(nodes=2**24):
    return gc.change(gc.default_scene(), {"surface.kind": "flat", "surface.nodes": nodes, "surface.length": 1e-3,
                                          "surface.realizations": 1, "output.workers": 1})


def test_a_grid_beyond_the_address_space_limit_is_refused_before_allocating(tmp_path):
    """surface.nodes = 2^24 under `ulimit -v` 2 GB ended in `_ArrayMemoryError` with a traceback; now exit 2,
    naming surface.nodes, the estimate, the room `ulimit -v` leaves and the keys that reduce it."""
    import resource

    path = write_scene(tmp_path, big_scene())
    limit = 2 * 10**9

    def limited():
        resource.setrlimit(resource.RLIMIT_AS, (limit, resource.getrlimit(resource.RLIMIT_AS)[1]))

    code = f"import sys; from gfmd_contact.cli import main; sys.exit(main(['scene', '--check', {str(path)!r}]))"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                          preexec_fn=limited)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    line = proc.stderr.strip().splitlines()[-1]
    assert line.startswith("gfmd: error: surface.nodes = 16777216"), line
    assert "ulimit -v" in line and "estimated" in line and "output.workers" in line, line


def test_memory_refusal_gives_both_numbers_and_the_estimate_grows_with_the_grid(monkeypatch):
    from gfmd_contact.core import cost
    from gfmd_contact.core.errors import SceneError

    small, large = big_scene(2**12), big_scene(2**16)
    assert cost.estimate_peak_memory(large) - cost.IMPORTS == pytest.approx(
        16 * (cost.estimate_peak_memory(small) - cost.IMPORTS))
    monkeypatch.setattr(cost, "memory_allowed", lambda: (10 * 2**20, "test room"))
    cost.check_memory(small)  # 4,096 nodes: a few MiB
    with pytest.raises(SceneError, match=r"^surface\.nodes = 65536: .*estimated .* MiB.* 10 MiB more \(test room\)"):
        gc.check(large)


def test_the_run_checks_the_memory_of_its_worker_processes(tmp_path, monkeypatch):
    """The scene check counts one process; `gfmd run --workers 2` (and gc.run(workers=2)) counts two."""
    from gfmd_contact.core import cost
    from gfmd_contact.core.errors import SceneError

    scene = gc.change(gc.default_scene(), {"surface.nodes": 2**16, "surface.length": 2.048e-5, "output.workers": 1,
                                           "surface.realizations": 2, "output.field_steps": 0, "loading.steps": 1})
    one = cost.estimate_peak_memory(scene, 1) - cost.IMPORTS
    monkeypatch.setattr(cost, "memory_allowed", lambda: (int(1.5 * one), "test room"))
    gc.check(scene)
    code, err = cli(["run", str(write_scene(tmp_path, scene)), "--out", str(tmp_path / "out"), "--workers", "2",
                     "--quiet", "--no-plot"])
    assert code == 2 and "2 process(es)" in err and "output.workers" in err, err
    assert not (tmp_path / "out").exists()
    with pytest.raises(SceneError, match="2 process"):
        gc.run(scene, tmp_path / "api", workers=2, progress=False)


def test_the_estimate_is_on_the_progress_line_and_in_meta_json(tmp_path):
    import json

    from gfmd_contact.core import cost

    scene = big_scene(64).replace(**{"loading.steps": 1})
    code, err = cli(["run", str(write_scene(tmp_path, scene)), "--out", str(tmp_path / "out"), "--quiet", "--no-plot"])
    assert code == 0, err
    meta = json.loads((tmp_path / "out" / "meta.json").read_text())
    need = cost.estimate_peak_memory(scene, None)
    assert meta["timings"]["estimated_peak_memory_bytes"] == need
    assert cost.describe(need, meta["timings"]["estimated_s"]) + ";" in err, err


# -- 2. hostile surface files ---------------------------------------------------------------------------------


def file_scene(tmp_path, path, nodes=16, nodes_y=0):
    """A scene reading surface.path = `path`, as TOML next to it (the file is checked when the scene loads)."""
    text = scene_to_toml(gc.change(gc.default_scene(), {"surface.kind": "flat", "surface.nodes": nodes,
                                                        "surface.realizations": 1, "output.workers": 1,
                                                        **({"surface.nodes_y": nodes_y} if nodes_y else {})}))
    text = text.replace('kind = "flat"', f'kind = "file"\npath = "{path}"')
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    return scene


def lying_npy(path, shape):
    """A .npy file of a few bytes whose header claims `shape` of float64."""
    with open(path, "wb") as f:
        np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": False, "shape": shape})
        f.write(b"\0" * 8)


@pytest.mark.parametrize("shape, nodes_y", [((10**12,), 0), ((10**6, 10**6), 16)])
def test_a_npy_header_claiming_a_huge_shape_is_refused_by_its_header(tmp_path, shape, nodes_y):
    """A tiny .npy whose header claims 10^12 values ended in `_ArrayMemoryError: Unable to allocate 7.28 TiB`
    (1+1-D and 2+1-D loaders); now refused from the header, naming surface.path and the scene's grid."""
    lying_npy(tmp_path / "h.npy", shape)
    for argv in (["scene", "--check", str(file_scene(tmp_path, "h.npy", nodes_y=nodes_y))],
                 ["run", str(tmp_path / "scene.toml"), "--out", str(tmp_path / "out"), "--quiet", "--no-plot"]):
        code, err = cli(argv)
        assert code == 2, err
        assert "gfmd: error: surface.path" in err and str(shape) in err.replace(".0", "") or str(shape[0]) in err, err
        assert "surface.nodes" in err and "Unable to allocate" not in err, err
    assert not (tmp_path / "out").exists()


def test_a_truncated_npy_is_refused_by_name(tmp_path):
    lying_npy(tmp_path / "h.npy", (16,))
    code, err = cli(["scene", "--check", str(file_scene(tmp_path, "h.npy"))])
    assert code == 2 and "surface.path" in err and "truncated" in err, err


def test_a_big_file_of_nul_bytes_named_txt_is_refused_before_it_is_read(tmp_path):
    """2 GiB of NUL bytes named heights.txt was read whole (10.5 GB resident, then MemoryError); now refused by
    its size: a height file of any format (binary content goes to SurfaceTopography, whatever its suffix) takes at
    most MAX_FILE_BYTES (sparse here, one byte more)."""
    from gfmd_contact.core.topography_files import MAX_FILE_BYTES

    with open(tmp_path / "heights.txt", "wb") as f:
        f.truncate(MAX_FILE_BYTES + 1)
    code, err = cli(["scene", "--check", str(file_scene(tmp_path, "heights.txt"))])
    assert code == 2, err
    assert "gfmd: error: surface.path" in err and f"{MAX_FILE_BYTES + 1} bytes, more than" in err, err


def test_binary_junk_under_a_text_suffix_is_refused_by_name(tmp_path):
    (tmp_path / "heights.txt").write_bytes(b"1e-9\n\0\0\0\0\n" * 4)
    code, err = cli(["scene", "--check", str(file_scene(tmp_path, "heights.txt"))])
    assert code == 2 and "surface.path" in err and "binary content" in err, err


# -- 6. the right words ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["/dev/zero", "zero.npy"])
def test_a_device_as_surface_file_is_named_a_device(tmp_path, name):
    """surface.path = "/dev/zero" was refused as "no such file"."""
    (tmp_path / "zero.npy").symlink_to("/dev/zero")
    code, err = cli(["scene", "--check", str(file_scene(tmp_path, name))])
    assert code == 2 and "surface.path" in err and "character device" in err and "no such file" not in err, err



# -- 4. a force-control step the outer search gave up on ------------------------------------------------------


def test_a_force_step_the_search_gave_up_on_is_named_with_the_load_reached(tmp_path, monkeypatch):
    """A step with converged = 0 whose inner solves converged (the outer search ran out of trials) was named in
    no message; now exit 1, and the step's message says the search gave up, the load and the p̄ reached."""
    from gfmd_contact.core import force
    from test_load_paths import force_scene

    monkeypatch.setattr(force, "MAX_TRIALS", 2)  # the search gives up where the full budget would succeed
    code, err = cli(["run", str(write_scene(tmp_path, force_scene(**{"output.workers": 1}))), "--out",
                     str(tmp_path / "out"), "--quiet", "--no-plot"])
    import pandas as pd

    curve = pd.read_csv(tmp_path / "out" / "curve.csv")
    bad = curve[curve["converged"] == 0]
    assert code == 1 and len(bad), err
    for k in bad["step"]:
        lines = [ln for ln in err.splitlines() if f"step {k} " in ln]
        assert any("outer search on U gave up" in ln and "the step records p̄ =" in ln for ln in lines), err


def test_a_force_step_whose_solve_failed_says_so():
    """solve_load on a model p̄(U) = U whose solves fail beyond U = 1: the message blames the solve, not the search."""
    from types import SimpleNamespace

    from gfmd_contact.core import force

    import dataclasses

    @dataclasses.dataclass
    class Sol:
        state: float
        converged: bool
        iterations: int
        messages: tuple = ()

    loaded = force.solve_load(lambda U, g, f: Sol(U, U <= 1.0, 1), lambda sol: {"p": sol.state, "a_rel": 0.0},
                              5.0, (0.0, 0.0, {"p": 0.0, "a_rel": 0.0}, None), step=1.0, tolerance=1e-6,
                              u_max=np.inf)
    assert not loaded.converged
    assert "a displacement solve did not converge" in loaded.solved.messages[-1]
    assert "P = 5 Pa" in loaded.solved.messages[-1]


# -- 6. the right words ---------------------------------------------------------------------------------------


def test_a_dangling_symlink_as_out_is_named_a_dangling_link(tmp_path):
    """`--out` as a symbolic link to a missing directory said `cannot write …/.gfmd.lock: File exists (EEXIST);
    … free space or fix the permissions`; now exit 2 naming the link and its missing target."""
    scene = write_scene(tmp_path, gc.change(gc.default_scene(), {"surface.kind": "flat", "surface.nodes": 16,
                                                                 "surface.realizations": 1, "loading.steps": 1}))
    (tmp_path / "out").symlink_to(tmp_path / "missing")
    code, err = cli(["run", str(scene), "--out", str(tmp_path / "out"), "--quiet", "--no-plot"])
    assert code == 2 and "symbolic link to" in err and "missing" in err and "EEXIST" not in err, err
    assert not (tmp_path / "missing").exists()


def test_a_user_law_that_raises_is_named_with_its_gap_and_step(tmp_path):
    """A user law that raises let the user's ZeroDivisionError out of gc.run with no word of which law, gap or
    step; now a UserLawError naming the law, the callable, the gaps, the realization and the step."""
    from test_user_law import SCENE, eq3

    good = eq3(SCENE.work_normal, SCENE.interface.length_normal, name="fragile")
    armed = [False]

    def traction(g):
        if armed[0]:
            raise ZeroDivisionError("division by zero")
        return good.traction(g)

    law = gc.user_law(good.energy, traction, good.tangent_fn, good.length, name="fragile")
    armed[0] = True  # passes the construction check, raises in the run
    with pytest.raises(gc.UserLawError, match=r"^realization 0 \(seed \d+\), step 0 \(U = 0 m\): user law 'fragile': "
                                              r"traction\(Δn\) raised ZeroDivisionError: division by zero on \d+ "
                                              r"gap\(s\) Δn in \[.*\] m$"):
        gc.run(SCENE, out=tmp_path / "u", law=law, progress=False)


# -- 5. a huge study ------------------------------------------------------------------------------------------


def study_file(tmp_path, n_phi, n_dn):
    """A study of n_phi × n_dn parameter sets over a tiny flat cohesive scene (one realization each)."""
    phis = ", ".join(f"{0.01 + 1e-6 * i:.8g}" for i in range(n_phi))
    dns = ", ".join(f"{1e-9 + 1e-15 * i:.8g}" for i in range(n_dn))
    (tmp_path / "study.toml").write_text(
        'name = "huge"\n[scene.surface]\nkind = "flat"\nnodes = 16\nlength = 1.6e-7\nrealizations = 1\n'
        '[scene.loading]\nsteps = 2\n[scene.output]\nworkers = 1\n'
        f'[axes]\n"interface.phi_n_star" = [{phis}]\n"interface.length_normal" = [{dns}]\n')
    return tmp_path / "study.toml"


def test_a_study_of_a_million_tasks_is_refused_at_once_with_its_size(tmp_path):
    """10^6 tasks: nothing written and nothing printed for about 20 min (loading validated every set); now
    exit 2 within seconds, naming the task count, its estimated cost and --yes."""
    path = study_file(tmp_path, 1000, 1000)
    code = (f"import sys; from gfmd_contact.cli import main; "
            f"sys.exit(main(['study', 'run', {str(path)!r}, '--out', {str(tmp_path / 'out')!r}]))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert "1000000 task(s)" in proc.stderr and "node-steps" in proc.stderr and "--yes" in proc.stderr, proc.stderr
    assert not (tmp_path / "out").exists()


def test_a_study_above_the_limit_runs_when_told_yes_and_says_its_size_first(tmp_path, monkeypatch):
    from gfmd_contact.app import study_file as sf

    monkeypatch.setattr(sf, "MAX_TASKS", 3)
    path = study_file(tmp_path, 2, 2)
    with pytest.raises(gc.StudyError, match=r"4 task\(s\).*MAX_TASKS = 3.*yes=True"):
        gc.load_study(path)
    lines = []
    study = sf.load_study(path, yes=True, note=lines.append)
    assert len(study.tasks) == 4 and lines and "4 task(s)" in lines[0] and "node-steps" in lines[0]
    assert len(gc.load_study(path, yes=True).tasks) == 4


# -- plausibility warnings: unit slips, named by key, never a refusal ----------------------------------------


@pytest.mark.parametrize("changes, key", [
    ({"surface.length": 2e-3, "surface.nodes": 64, "surface.rolloff_wavelength": 1e-3,
      "surface.rollon_wavelength": 1e-4}, "surface.length"),
    ({"surface.rollon_wavelength": 2e-8, "material.youngs_modulus": 5e5}, "material.youngs_modulus"),
    ({"surface.rollon_wavelength": 2e-8, "surface.h_rms": 0.2e-6}, "surface.h_rms"),
    ({"surface.kind": "sinusoid", "surface.amplitude": 0.2e-6}, "surface.amplitude"),
])
def test_a_likely_unit_slip_is_warned_by_key_and_not_refused(tmp_path, changes, key):
    scene = gc.change(gc.default_scene(), {"surface.nodes": 256, "surface.realizations": 1, "output.workers": 1,
                                           **changes})
    found, _ = gc.check(scene)
    slips = [w for w in found if w.startswith(key + " = ")]
    assert len(slips) == 1, found
    code, err = cli(["scene", "--check", str(write_scene(tmp_path, scene))])
    assert code == 0 and f"WARNING: {slips[0]}" in err, err


def test_the_default_and_example_scenes_have_no_unit_slip_warning():
    from gfmd_contact.core.plausibility import unit_slip_warnings

    for scene in (gc.default_scene(), gc.example_scene()):
        assert unit_slip_warnings(scene) == []


def test_the_scene_check_says_the_estimate(tmp_path):
    from gfmd_contact.core import cost

    scene = big_scene(256)
    err = io.StringIO()
    out = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        assert main(["scene", "--check", str(write_scene(tmp_path, scene))]) == 0
    assert cost.describe(cost.estimate_peak_memory(scene)) in out.getvalue().splitlines()[-1], out.getvalue()
