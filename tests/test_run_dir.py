"""Run directories that never lose work: written as the run goes, interrupt, resume, refusals (gfmd_contact.app.io, .cli).

The resumed files must equal an uninterrupted run's: every column of curve.csv but
wall_s, every array of fields.npz, mean_curve.csv and meta.json but timings, date,
command and the resume counts. The tolerance is zero: the warm-start state (the last
two converged displacement spectra) is saved bit for bit and the solver is
deterministic, so a resumed ramp takes exactly the same iterations.
"""

import csv
import json
import os
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest

import gfmd_contact.app.checkpoints
import gfmd_contact.app.io
from gfmd_contact.core import surfaces
from gfmd_contact.cli import main
from gfmd_contact.core.loading import FULL_CONTACT_MARGIN, displacement_steps
from gfmd_contact.core.scene import default_scene, scene_to_toml


def scene(**extra):
    """A 320 nm cell at N = 256 (λs,H = 8 l, δn = 2 l, δ0 = 8 δn: no check warning), 3 realizations, 8 steps."""
    d = {"surface.length": 320e-9, "surface.nodes": 256, "surface.rolloff_wavelength": 160e-9,
         "surface.rollon_wavelength": 10e-9, "surface.realizations": 3, "loading.steps": 8,
         "loading.final_penetration": 8e-9, "output.field_steps": 2, "output.workers": 1,
         "interface.length_normal": 2.5e-9, "loading.initial_separation": 20e-9}
    d.update(extra)
    return default_scene().replace(**d)


def write_scene(tmp_path, sc, name="s.toml"):
    path = tmp_path / name
    path.write_text(scene_to_toml(sc))
    return path


def rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def assert_same_run(a, b):
    """Run directories a and b hold the same results (timings, date, command, resume counts aside)."""
    ra, rb = rows(a / "curve.csv"), rows(b / "curve.csv")
    assert len(ra) == len(rb) and ra[0].keys() == rb[0].keys()
    for x, y in zip(ra, rb):
        assert {k: v for k, v in x.items() if k != "wall_s"} == {k: v for k, v in y.items() if k != "wall_s"}
    assert (a / "mean_curve.csv").read_text() == (b / "mean_curve.csv").read_text()
    fa, fb = np.load(a / "fields.npz"), np.load(b / "fields.npz")
    assert sorted(fa.files) == sorted(fb.files)
    for k in fa.files:
        np.testing.assert_array_equal(fa[k], fb[k])
    assert (a / "scene.toml").read_text() == (b / "scene.toml").read_text()
    ma, mb = (json.loads((d / "meta.json").read_text()) for d in (a, b))
    for m in (ma, mb):
        for k in ("timings", "date", "command", "resume"):
            m.pop(k)
    assert ma == mb


def test_run_writes_every_step_as_it_goes(tmp_path, monkeypatch):
    """While realization 1 runs, realization 0 and the steps of 1 so far are on disk and meta says incomplete
    (a checkpoint every step: CHECKPOINT_SECONDS = 0; the interval: tests/test_checkpoint_interval.py)."""
    monkeypatch.setattr(gfmd_contact.app.checkpoints, "CHECKPOINT_SECONDS", 0.0)
    sc = scene()
    out = tmp_path / "out"
    seen = []
    original = gfmd_contact.app.io.save_step

    def spy(out_dir, result, state):
        original(out_dir, result, state)
        if result.realization == 1 and state.step == 4:
            meta = json.loads((out / "meta.json").read_text())
            seen.append((meta["complete"], gfmd_contact.app.io.load_part(out, sc, 0), gfmd_contact.app.io.load_part(out, sc, 1)))

    monkeypatch.setattr(gfmd_contact.app.io, "save_step", spy)
    assert main(["run", str(write_scene(tmp_path, sc)), "--out", str(out), "--quiet", "--no-plot"]) == 0
    (complete, part0, part1), = seen
    assert complete is False
    assert part0[2] is True and len(part0[0].curve["step"]) == sc.loading.steps + 1  # done
    assert part1[2] is False and part1[0].curve["step"] == [0, 1, 2, 3, 4]  # every step so far
    meta = json.loads((out / "meta.json").read_text())
    assert meta["complete"] is True and meta["resume"] == {"realizations_reused": 0, "steps_reused": 0}
    assert not (out / "partial").exists()


def interrupted_and_resumed(tmp_path, monkeypatch, sc, stop_after):
    """Run `sc` into ref/ uninterrupted, and into out/ interrupted after step k of realization i
    (stop_after = (i, k); a KeyboardInterrupt from the checkpoint), refused without --resume,
    then resumed; returns (ref, out)."""
    path = write_scene(tmp_path, sc)
    ref = tmp_path / "ref"
    assert main(["run", str(path), "--out", str(ref), "--quiet", "--no-plot"]) == 0
    original = gfmd_contact.app.io.save_step

    def interrupt(out_dir, result, state):
        original(out_dir, result, state)
        if (result.realization, state.step) == stop_after:
            raise KeyboardInterrupt

    out = tmp_path / "out"
    monkeypatch.setattr(gfmd_contact.app.io, "save_step", interrupt)
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 130
    assert json.loads((out / "meta.json").read_text())["complete"] is False
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 2  # not without --resume
    monkeypatch.setattr(gfmd_contact.app.io, "save_step", original)
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0
    return ref, out


@pytest.mark.parametrize("stop_after", [(0, 3), (1, 0), (2, 8)])
def test_resume_equals_uninterrupted_run(tmp_path, monkeypatch, stop_after):
    """Interrupt after step k of realization i (KeyboardInterrupt from the checkpoint), resume: same files."""
    ref, out = interrupted_and_resumed(tmp_path, monkeypatch, scene(), stop_after)
    assert_same_run(ref, out)
    i, k = stop_after
    resume = json.loads((out / "meta.json").read_text())["resume"]
    assert resume == {"realizations_reused": i, "steps_reused": k + 1}


def test_resume_restarts_a_row_cut_short(tmp_path, monkeypatch):
    """A kill between the row and the state write leaves an untrusted row: resume drops and recomputes it
    (a checkpoint every step, CHECKPOINT_SECONDS = 0: the kill cuts step 5's)."""
    monkeypatch.setattr(gfmd_contact.app.checkpoints, "CHECKPOINT_SECONDS", 0.0)
    sc = scene(**{"surface.realizations": 1})
    path = write_scene(tmp_path, sc)
    ref = tmp_path / "ref"
    assert main(["run", str(path), "--out", str(ref), "--quiet", "--no-plot"]) == 0
    original = gfmd_contact.app.io.save_step

    def killed(out_dir, result, state):
        if state.step == 5:  # the row is written, then "killed" before the state
            with open(out_dir / "partial" / "realization0.csv", "a") as fh:
                fh.write("5,1.2e-08,3.4")  # half a row
            raise KeyboardInterrupt
        original(out_dir, result, state)

    out = tmp_path / "out"
    monkeypatch.setattr(gfmd_contact.app.io, "save_step", killed)
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 130
    monkeypatch.setattr(gfmd_contact.app.io, "save_step", original)
    assert main(["run", "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0  # scene taken from --out
    assert_same_run(ref, out)
    assert json.loads((out / "meta.json").read_text())["resume"]["steps_reused"] == 5


def test_sigint_to_a_pooled_run_then_resume(tmp_path):
    """A real SIGINT to `gfmd run --workers 2`: exit 130 within seconds, one line, no traceback;
    the resumed files equal an uninterrupted run's."""
    sc = scene(**{"surface.nodes": 4096, "surface.rollon_wavelength": 2.5e-9, "surface.realizations": 4,
                  "loading.steps": 800,  # long enough (≈ 6 s on 2 cores) to be interrupted mid-run
                  "loading.final_penetration": 15e-9, "interface.length_normal": 1e-9,
                  "loading.initial_separation": 8e-9, "output.field_steps": 3})
    path = write_scene(tmp_path, sc)
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "gfmd", "run", str(path), "--out", str(out), "--workers", "2", "--no-plot", "--quiet"]
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:  # interrupt once some steps, but not all realizations, are done
        states = list((out / "partial").glob("*.state.npz")) if (out / "partial").is_dir() else []
        if states and proc.poll() is None:
            try:
                if max(int(np.load(p)["step"]) for p in states) >= 10:
                    break
            except (OSError, ValueError, KeyError, EOFError):  # a state being replaced right now
                pass
        assert proc.poll() is None, "the run ended before it could be interrupted"
        time.sleep(0.01)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    elapsed = time.monotonic() - sent
    assert proc.returncode == 130, err
    assert elapsed < 5, f"took {elapsed:.1f} s to stop"
    assert "Traceback" not in err
    last = err.strip().splitlines()[-1]
    assert last.startswith("gfmd: interrupted:") and "--resume" in last and str(out) in last
    meta = json.loads((out / "meta.json").read_text())
    assert meta["complete"] is False and not (out / "curve.csv").exists()
    parts = [gfmd_contact.app.io.load_part(out, sc, i) for i in range(4)]
    assert any(p is not None for p in parts) and not all(p is not None and p[2] for p in parts)
    saved = sum(len(p[0].curve["step"]) for p in parts if p is not None)
    assert saved >= 11
    resumed = subprocess.run(cmd + ["--resume"], capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    ref = tmp_path / "ref"
    assert main(["run", str(path), "--out", str(ref), "--quiet", "--no-plot", "--workers", "1"]) == 0
    assert_same_run(ref, out)
    reuse = json.loads((out / "meta.json").read_text())["resume"]
    assert reuse["realizations_reused"] * (sc.loading.steps + 1) + reuse["steps_reused"] == saved


def test_out_guards_before_any_compute(tmp_path, capsys, monkeypatch):
    sc = scene(**{"surface.realizations": 1})
    path = write_scene(tmp_path, sc)
    calls = []
    monkeypatch.setattr("gfmd_contact.app.ensemble.run_to_directory", lambda *a, **k: calls.append(1))
    a_file = tmp_path / "file.txt"
    a_file.write_text("x")
    assert main(["run", str(path), "--out", str(a_file)]) == 2
    assert "is an existing file" in capsys.readouterr().err
    full = tmp_path / "full"
    full.mkdir()
    (full / "curve.csv").write_text("old")
    (full / "plots").mkdir()
    assert main(["run", str(path), "--out", str(full)]) == 2
    err = capsys.readouterr().err
    assert "is not empty" in err and "--resume" in err and "--overwrite" in err
    (full / "notes.txt").write_text("mine")
    assert main(["run", str(path), "--out", str(full), "--overwrite"]) == 2  # never deletes what a run did not write
    assert "notes.txt" in capsys.readouterr().err and (full / "notes.txt").exists()
    assert main(["run", str(tmp_path), "--out", str(tmp_path / "o")]) == 2  # a directory as scene
    assert "is a directory" in capsys.readouterr().err
    assert calls == []
    monkeypatch.undo()
    (full / "notes.txt").unlink()
    assert main(["run", str(path), "--out", str(full), "--overwrite", "--quiet", "--no-plot"]) == 0
    assert not (full / "plots").exists() and rows(full / "curve.csv")  # stale plots gone, new results there


def test_resume_refuses_another_scene(tmp_path, capsys):
    sc = scene(**{"surface.realizations": 1})
    out = tmp_path / "out"
    assert main(["run", str(write_scene(tmp_path, sc)), "--out", str(out), "--quiet", "--no-plot"]) == 0
    other = write_scene(tmp_path, sc.replace(**{"interface.phi_n_star": 0.01}), "other.toml")
    assert main(["run", str(other), "--out", str(out), "--resume"]) == 2
    assert "phi_n_star" in capsys.readouterr().err
    before = (out / "meta.json").read_text()
    assert main(["run", str(write_scene(tmp_path, sc)), "--out", str(out), "--resume", "--workers", "2",
                 "--quiet", "--no-plot"]) == 0  # workers may differ
    assert "complete; nothing to resume" in capsys.readouterr().err
    assert (out / "meta.json").read_text() == before


def test_result_files_follow_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        out = tmp_path / "out"
        assert main(["run", str(write_scene(tmp_path, scene(**{"surface.realizations": 1}))), "--out", str(out),
                     "--quiet"]) == 0
    finally:
        os.umask(old)
    files = [p for p in out.rglob("*") if p.is_file()]
    assert len(files) >= 9
    assert {stat.S_IMODE(p.stat().st_mode) for p in files} == {0o644}


def test_realization_stops_below_its_own_full_contact_limit(tmp_path, capsys):
    """final_penetration beyond some realizations' mean(h) − min(h): those stop at (1 − margin) of their
    own limit, the others run to the end; the note is printed and kept in meta.json."""
    sc = scene(**{"surface.realizations": 4, "loading.steps": 20})
    limits = [float(np.mean(h) - np.min(h)) for h in (surfaces.profile(sc.surface, i) for i in range(4))]
    final = float(np.median(limits))  # about half of the realizations reach their limit
    sc = sc.replace(**{"loading.final_penetration": final})
    path = write_scene(tmp_path, sc)
    assert main(["scene", "--check", str(path)]) == 0  # check says the same as run
    check_err = capsys.readouterr().err
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 0
    err = capsys.readouterr().err
    meta = json.loads((out / "meta.json").read_text())
    delta = displacement_steps(sc.loading) - sc.loading.initial_separation
    by_realization = {}
    for row in rows(out / "curve.csv"):
        by_realization.setdefault(int(row["realization"]), []).append(float(row["delta"]))
    stopped = 0
    for i, limit in enumerate(limits):
        stop = (1 - FULL_CONTACT_MARGIN) * limit
        expected = delta[delta <= stop] if final > stop else delta
        np.testing.assert_array_equal(by_realization[i], expected)
        if final > stop:
            stopped += 1
            note = next(n for n in meta["notes"] if n.startswith(f"realization {i} (seed {sc.surface.seed + i})"))
            assert f"stops at step {expected.size - 1}" in note and f"note: {note}" in err and note in check_err
    assert 0 < stopped < 4 and len(meta["notes"]) == stopped
    assert meta["steps_run"] == [len(by_realization[i]) for i in range(4)]
    mean = rows(out / "mean_curve.csv")
    assert len(mean) == delta.size and [int(r["p_n"]) for r in mean][-1] == 4 - stopped


def test_seed_labels_realizations(tmp_path, capsys):
    """A run of one seed at a time is labelled by its seed, not "realization 0" every time."""
    sc = scene(**{"surface.realizations": 1, "surface.seed": 7, "solver.max_iterations": 2})
    out = tmp_path / "out"
    assert main(["run", str(write_scene(tmp_path, sc)), "--out", str(out), "--quiet", "--no-plot"]) == 1
    assert "realization 0 (seed 7), step" in capsys.readouterr().err
    assert {r["seed"] for r in rows(out / "curve.csv")} == {"7"}
    assert json.loads((out / "meta.json").read_text())["seeds"] == [7]


def test_mean_curve_holds_means_and_standard_errors(tmp_path):
    sc = scene()
    out = tmp_path / "out"
    assert main(["run", str(write_scene(tmp_path, sc)), "--out", str(out), "--quiet", "--no-plot"]) == 0
    curve = rows(out / "curve.csv")
    mean = rows(out / "mean_curve.csv")
    for name in ("p", "a_rel", "g"):
        table = np.array([[float(r[name]) for r in curve if int(r["realization"]) == i] for i in range(3)])
        np.testing.assert_array_equal([float(r[name]) for r in mean], table.mean(axis=0))
        np.testing.assert_allclose([float(r[name + "_se"]) for r in mean], table.std(axis=0, ddof=1) / np.sqrt(3),
                                   rtol=1e-12, atol=1e-300)
        assert {r[name + "_n"] for r in mean} == {"3"}


def test_scene_check_makes_the_run_checks(tmp_path, capsys):
    """check refuses what run refuses (exit 2 both), with the same message; warnings are printed by both."""
    unstable = scene(**{"interface.phi_n_star": 1.0, "loading.initial_separation": 5e-9,  # δ_jump = 15 nm
                        "surface.realizations": 1})
    warn = write_scene(tmp_path, unstable, "warn.toml")
    assert main(["scene", "--check", str(warn)]) == 0
    assert "WARNING: unstable start" in capsys.readouterr().err
    strict = write_scene(tmp_path, unstable.replace(**{"solver.checks": "error"}), "strict.toml")
    assert main(["scene", "--check", str(strict)]) == 2
    check_err = capsys.readouterr().err
    assert main(["run", str(strict), "--out", str(tmp_path / "o")]) == 2
    run_err = capsys.readouterr().err
    assert "unstable start" in check_err and check_err == run_err
    assert not (tmp_path / "o").exists()
    half_plane = write_scene(tmp_path, scene(), "hp.toml")
    assert main(["scene", "--check", str(half_plane), "--method", "fe"]) == 2
    assert "finite layer" in capsys.readouterr().err
    empty = tmp_path / "empty.toml"  # the production defaults: 40 nm is past most realizations' full contact
    empty.write_text("")
    assert main(["scene", "--check", str(empty)]) == 0
    check_out = capsys.readouterr()
    assert "note: realization 0 (seed 1) stops at step" in check_out.err and "stop early" in check_out.out


@pytest.mark.parametrize("argv", [["--workers", "-1"], ["--workers", "two"], ["--realizations", "0"]])
def test_bad_flags_name_the_flag(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "--out", "never"] + argv)
    assert exc.value.code == 2
    assert argv[0] in capsys.readouterr().err


def test_verify_runs_from_any_directory(tmp_path, monkeypatch):
    import gfmd_contact.cli

    calls = []
    monkeypatch.setattr(gfmd_contact.cli.subprocess, "call", lambda cmd, cwd=None: calls.append((cmd, cwd)) or 0)
    monkeypatch.chdir(tmp_path)
    assert main(["verify", "--", "-x"]) == 0
    (cmd, cwd), = calls
    assert cmd[-2:] == ["verification", "-x"] and (cwd / "verification" / "conftest.py").is_file()


@pytest.mark.parametrize("law", ["hard-wall", "cohesive"])
def test_fe_run_resumes_step_by_step(tmp_path, monkeypatch, law):
    """The FE reference runs on the same ramp and checkpoints: interrupted after step 2 and
    resumed, its result files and VTU series equal an uninterrupted FE run's."""
    import meshio

    from test_cli_fe import fe_scene

    sc = fe_scene(law, "self-affine").replace(**{"method.name": "fe", "loading.steps": 5})
    ref, out = interrupted_and_resumed(tmp_path, monkeypatch, sc, (0, 2))
    assert_same_run(ref, out)
    assert json.loads((out / "meta.json").read_text())["resume"]["steps_reused"] == 3
    vtu = sorted(p.name for p in (ref / "vtu" / "realization0").iterdir())
    assert vtu == sorted(p.name for p in (out / "vtu" / "realization0").iterdir()) and "fe.pvd" in vtu
    for name in vtu:
        if name.endswith(".vtu"):
            a, b = (meshio.read(d / "vtu" / "realization0" / name) for d in (ref, out))
            np.testing.assert_array_equal(a.point_data["displacement"], b.point_data["displacement"])
            np.testing.assert_array_equal(a.cell_data["stress"][0], b.cell_data["stress"][0])
