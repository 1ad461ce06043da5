"""One writer per directory, and damage repaired instead of thrown away (gfmd_contact.app.safe_files, .io).

The three reproductions of the issue as they were measured (two `gfmd run` at once, two
`gfmd study run` at once, kill -9 of a pooled `gfmd run` then --resume at once) run real
processes; the lock's refusals, take-over and --wait, and the repair of partial files
that hold more or fewer rows than their saved steps, run in-process.
"""

import json
import os
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

import gfmd_contact.app.checkpoints
import gfmd_contact.app.io
from gfmd_contact.app import safe_files
from gfmd_contact.cli import main

from test_run_dir import assert_same_run, rows, scene, write_scene

LONG = {"surface.nodes": 4096, "surface.rollon_wavelength": 2.5e-9, "surface.realizations": 2,
        "loading.steps": 600,  # a few seconds on 2 cores: long enough to be met by a second process
        "loading.final_penetration": 15e-9, "interface.length_normal": 1e-9,
        "loading.initial_separation": 8e-9, "output.field_steps": 3}


def gfmd(*args):
    return [sys.executable, "-m", "gfmd", *map(str, args)]


def saved_step(out, realization=None):
    """The highest saved step in out/partial (-1 if none yet)."""
    best = -1
    for p in (out / "partial").glob("*.state.npz") if (out / "partial").is_dir() else []:
        try:
            best = max(best, int(np.load(p)["step"]))
        except (OSError, ValueError, KeyError, EOFError):  # being replaced right now
            pass
    return best


def wait_until_saved(out, proc, step, timeout=120):
    deadline = time.monotonic() + timeout
    while saved_step(out) < step:
        assert proc.poll() is None, "the run ended before the second process could meet it"
        assert time.monotonic() < deadline
        time.sleep(0.01)


def test_second_run_is_refused_at_once_naming_the_first(tmp_path):
    """Reproduced: `gfmd run` and four seconds later the same with --resume. Before:
    both ended exit 2, "partial files are damaged". Now the second is refused at once, exit 2, one
    line naming the first (host, pid, start, command); the first ends 0; --wait waits for it."""
    path = write_scene(tmp_path, scene(**LONG))
    out = tmp_path / "o"
    first = subprocess.Popen(gfmd("run", path, "--out", out, "--quiet", "--no-plot", "--workers", "1"),
                             stderr=subprocess.PIPE, text=True)
    wait_until_saved(out, first, 5)
    t0 = time.monotonic()
    second = subprocess.run(gfmd("run", path, "--out", out, "--resume", "--quiet", "--no-plot"),
                            capture_output=True, text=True, timeout=120)
    assert second.returncode == 2, second.stderr
    err = second.stderr.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("gfmd: error: "), second.stderr
    assert f"pid {first.pid} on host {socket.gethostname()}" in err[0] and "started 20" in err[0]
    assert "command 'gfmd run" in err[0] and "--wait" in err[0] and "being written by" in err[0]
    assert first.poll() is None, "the first run must be left running"
    waited = subprocess.run(gfmd("run", path, "--out", out, "--resume", "--quiet", "--no-plot", "--wait"),
                            capture_output=True, text=True, timeout=300)
    _, first_err = first.communicate(timeout=300)
    assert first.returncode == 0, first_err
    assert waited.returncode == 0 and "complete; nothing to resume" in waited.stderr, waited.stderr
    assert json.loads((out / "meta.json").read_text())["complete"] is True
    assert len(rows(out / "curve.csv")) == 2 * (LONG["loading.steps"] + 1)
    assert not (out / safe_files.LOCK_NAME).exists()  # released and removed


STUDY = """
name = "two"
[scene]
surface = {{ length = 320e-9, nodes = 512, rolloff_wavelength = 160e-9, rollon_wavelength = 10e-9, realizations = 1 }}
loading = {{ steps = {steps}, final_penetration = 8e-9, initial_separation = 20e-9 }}
interface = {{ length_normal = 2.5e-9 }}
output = {{ field_steps = 1 }}
[axes]
"interface.phi_n_star" = [0.1, 0.2]
"""


def test_second_study_run_is_refused_at_once(tmp_path):
    """Reproduced: the same `gfmd study run` twice at once. Before: both exit 1 with
    every task damaged. Now the second is refused at once (exit 2, the holder named) and the first
    completes; the study then reruns as all-reused."""
    study = tmp_path / "s.toml"
    study.write_text(STUDY.format(steps=1500))
    out = tmp_path / "o"
    first = subprocess.Popen(gfmd("study", "run", study, "--out", out, "--workers", "2", "--quiet"),
                             stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list((out / "tasks").glob("*/partial/*.state.npz")) if (out / "tasks").is_dir() else True:
        assert first.poll() is None, first.communicate()[1]
        assert time.monotonic() < deadline
        time.sleep(0.05)
    second = subprocess.run(gfmd("study", "run", study, "--out", out, "--workers", "2", "--quiet"),
                            capture_output=True, text=True, timeout=120)
    assert second.returncode == 2, second.stderr
    err = second.stderr.strip().splitlines()[-1]
    assert err.startswith("gfmd: error: ") and f"pid {first.pid} on host" in err and "study directory" in err
    assert "command 'gfmd study run" in err and "--wait" in err
    _, first_err = first.communicate(timeout=600)
    assert first.returncode == 0, first_err
    again = subprocess.run(gfmd("study", "run", study, "--out", out, "--workers", "1", "--quiet"),
                           capture_output=True, text=True, timeout=300)
    assert again.returncode == 0 and "2 reused, 0 run" in again.stderr, again.stderr


def test_kill_9_of_a_pooled_run_then_resume_at_once(tmp_path):
    """Reproduced: kill -9 of `gfmd run --workers 2`, then --resume at once. Before:
    the pool's workers outlived the main process and went on appending rows, and the resume failed
    at its end ("realization 0 has N rows for M saved steps"). Now the workers die with it (or the
    resume waits for the lock they inherited), twice in a row, and the result equals an
    uninterrupted run's."""
    sc = scene(**LONG)
    path = write_scene(tmp_path, sc)
    out = tmp_path / "o"
    cmd = gfmd("run", path, "--out", out, "--workers", "2", "--no-plot", "--quiet")
    proc = subprocess.Popen(cmd, stderr=subprocess.DEVNULL)
    for k, at in enumerate((30, 200)):  # two kills: the second one of a resumed run
        wait_until_saved(out, proc, at)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        proc = subprocess.Popen(cmd + ["--resume"], stderr=subprocess.PIPE, text=True)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err
    ref = tmp_path / "ref"
    assert main(["run", str(path), "--out", str(ref), "--quiet", "--no-plot", "--workers", "1"]) == 0
    assert_same_run(ref, out)


# ---------------------------------------------------------------- the lock, in-process

def test_lock_refuses_waits_and_is_removed(tmp_path, capsys):
    sc = scene(**{"surface.realizations": 1})
    path = write_scene(tmp_path, sc)
    out = tmp_path / "o"
    holder = safe_files.DirLock(out, command="someone else").acquire()
    try:
        assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 2
        err = capsys.readouterr().err
        assert f"the run directory is being written by pid {os.getpid()} on host {socket.gethostname()}" in err
        assert "command 'someone else'" in err and err.count("\n") == 1
        t0 = time.monotonic()
        assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot", "--wait", "0.5"]) == 2
        assert time.monotonic() - t0 >= 0.5 and "(waited 0.5 s)" in capsys.readouterr().err
        assert sorted(p.name for p in out.iterdir()) == [safe_files.LOCK_NAME]  # nothing written by the refused
    finally:
        holder.release()
    assert not out.exists() or not any(out.iterdir())
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 0
    assert not (out / safe_files.LOCK_NAME).exists()


def test_lock_of_a_dead_process_is_taken_over_and_said_so(tmp_path, capsys):
    """kill -9 leaves the lock file (its flock died with the process): the next run takes it over."""
    sc = scene(**{"surface.realizations": 1})
    path = write_scene(tmp_path, sc)
    out = tmp_path / "o"
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    out.mkdir()
    (out / safe_files.LOCK_NAME).write_text(json.dumps({"host": socket.gethostname(), "pid": dead.pid,
                                                         "started": "2026-01-01T00:00:00+0000",
                                                         "command": "gfmd run old"}))
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 0
    err = capsys.readouterr().err
    assert (f"note: {out}: took over the lock of pid {dead.pid} on host {socket.gethostname()}, started "
            "2026-01-01T00:00:00+0000, command 'gfmd run old', which ended without releasing it") in err


def test_a_task_run_twice_at_once_leaves_one_result(tmp_path):
    """Dask may run a task twice at once: the second waits for the first's lock and returns its
    published result; the directory holds one complete result equal to a single execution's."""
    import threading

    from gfmd_contact.app.study import run_task, task_scene

    sc = task_scene(scene(**{"loading.steps": 30}), 0)
    one, two = tmp_path / "one", tmp_path / "two"
    assert run_task(sc, str(one), progress=None)["status"] == "run"
    outcomes = []
    threads = [threading.Thread(target=lambda: outcomes.append(run_task(sc, str(two), progress=None)))
               for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(o["status"] for o in outcomes) == ["reused", "run"]
    assert_same_run(one, two)
    assert sorted(p.name for p in two.iterdir()) == ["curve.csv", "fields.npz", "mean_curve.csv", "meta.json",
                                                     "scene.toml"]
    assert run_task(sc, str(two), progress=None)["status"] == "reused"  # one after the other


# ---------------------------------------------------------------- damage repaired

def interrupted(tmp_path, monkeypatch, sc, stop):
    """ref/ uninterrupted and out/ interrupted after step `stop` of realization 0 (KeyboardInterrupt)."""
    path = write_scene(tmp_path, sc)
    ref, out = tmp_path / "ref", tmp_path / "out"
    assert main(["run", str(path), "--out", str(ref), "--quiet", "--no-plot"]) == 0
    original = gfmd_contact.app.io.save_step

    def interrupt(out_dir, result, state):
        original(out_dir, result, state)
        if state.step == stop:
            raise KeyboardInterrupt

    monkeypatch.setattr(gfmd_contact.app.io, "save_step", interrupt)
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 130
    monkeypatch.setattr(gfmd_contact.app.io, "save_step", original)
    return ref, out


def test_rows_after_the_saved_step_are_dropped_and_said(tmp_path, monkeypatch, capsys):
    """More rows than saved steps (a second writer appended its own): keep steps 0..k, say how many
    rows were dropped, continue from k+1. Before: "the partial files are damaged: rerun with --overwrite"."""
    sc = scene(**{"surface.realizations": 1})
    ref, out = interrupted(tmp_path, monkeypatch, sc, 4)
    csv_path = out / "partial" / "realization0.csv"
    lines = csv_path.read_text().splitlines(keepends=True)
    csv_path.write_text("".join(lines + lines[2:5] + ["5,1.2e-08,3"]))  # a foreign writer's rows, one cut short
    capsys.readouterr()
    assert main(["run", "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0
    err = capsys.readouterr().err
    assert (f"note: {csv_path}: 9 rows for 5 saved steps: kept steps 0–4, dropped 4 row(s) written after the "
            "last saved step") in err
    assert_same_run(ref, out)
    assert json.loads((out / "meta.json").read_text())["resume"]["steps_reused"] == 5


def test_fewer_rows_than_saved_steps_restart_the_realization(tmp_path, monkeypatch, capsys):
    """Consistent rows that end before the first saved step (saved: 4, 8) leave no warm start on disk:
    the realization restarts from step 0, and says so."""
    sc = scene(**{"surface.realizations": 1})
    ref, out = interrupted(tmp_path, monkeypatch, sc, 4)
    csv_path = out / "partial" / "realization0.csv"
    lines = csv_path.read_text().splitlines(keepends=True)
    csv_path.write_text("".join(lines[:3]))  # steps 0, 1 only
    capsys.readouterr()
    assert main(["run", "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0
    err = capsys.readouterr().err
    assert (f"note: {csv_path}: 2 rows for 5 saved steps, consistent only up to step 1") in err
    assert ("no warm start of a step up to 1 is on disk (one is kept with the fields of each saved step, "
            "output.field_steps): realization 0 restarts from step 0 (5 saved steps dropped)") in err
    assert_same_run(ref, out)


def _fe_scene(law):
    from test_cli_fe import fe_scene

    return fe_scene(law, "self-affine").replace(**{"method.name": "fe", "surface.realizations": 2, "loading.steps": 6,
                                                   "output.field_steps": 3})


# (scene, realization 1 interrupted after step `stop`, rows of each realization's CSV kept (a row out of order
# follows them), the step each continues after): the saved steps are 2, 4, 6, 8 (GFMD) and 2, 4, 6 (the FE);
# realization 0 was done, realization 1 interrupted
CUT_BACK = {
    "gfmd": (lambda: scene(**{"surface.realizations": 2, "output.field_steps": 4}), 5, (5, 4), (4, 2)),
    "fe-cohesive": (lambda: _fe_scene("cohesive"), 4, (4, 3), (2, 2)),
    "fe-hard-wall": (lambda: _fe_scene("hard-wall"), 4, (5, 3), (4, 2)),
}


@pytest.mark.parametrize("case", list(CUT_BACK))
def test_fewer_rows_than_saved_steps_continue_from_the_last_saved_warm_start(tmp_path, monkeypatch, capsys, case):
    """Fewer consistent rows than saved steps (rows lost or reordered by a foreign writer): each realization is cut
    back to the last step j within its consistent rows whose saved fields carry the warm start, says how many
    saved steps it dropped and continues from j + 1, to a result bit-equal to an uninterrupted run's (the saved
    warm start is the ramp's own state after step j). Before: every such realization restarted from step 0."""
    make, stop, kept, cont = CUT_BACK[case]
    sc = make()
    path = write_scene(tmp_path, sc)
    ref, out = tmp_path / "ref", tmp_path / "out"
    assert main(["run", str(path), "--out", str(ref), "--quiet", "--no-plot"]) == 0
    original = gfmd_contact.app.io.save_step

    def interrupt(out_dir, result, state):
        original(out_dir, result, state)
        if result.realization == 1 and state.step == stop:
            raise KeyboardInterrupt

    monkeypatch.setattr(gfmd_contact.app.io, "save_step", interrupt)
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 130
    last = [sc.loading.steps, stop]  # the saved step of each realization
    for i, n in enumerate(kept):
        csv_path = out / "partial" / f"realization{i}.csv"
        lines = csv_path.read_text().splitlines(keepends=True)
        csv_path.write_text("".join(lines[:1 + n] + lines[-1:]))  # steps 0..n-1, then the last one: out of order
    ran = []

    def count(out_dir, result, state):
        ran.append((result.realization, state.step))
        original(out_dir, result, state)

    monkeypatch.setattr(gfmd_contact.app.io, "save_step", count)
    capsys.readouterr()
    assert main(["run", "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0
    err = capsys.readouterr().err
    for i, (n, j) in enumerate(zip(kept, cont)):
        csv_path = out / "partial" / f"realization{i}.csv"
        assert (f"note: {csv_path}: {n + 1} rows for {last[i] + 1} saved steps, consistent only up to step {n - 1} "
                f"(rows missing, cut or out of order: written by another process?); kept steps 0–{j} (the last of "
                f"them whose warm start is on disk, with its saved fields), dropped {last[i] - j} saved step(s): "
                f"realization {i} continues from step {j + 1}") in err
    steps = sc.loading.steps
    assert sorted(ran) == [(i, k) for i, j in enumerate(cont) for k in range(j + 1, steps + 1)]
    assert json.loads((out / "meta.json").read_text())["resume"]["steps_reused"] == sum(j + 1 for j in cont)
    assert_same_run(ref, out)


def test_cut_back_drops_the_messages_of_the_dropped_steps(tmp_path, monkeypatch):
    """A realization cut back to step j keeps exactly the messages, reasons and notes it had after step j
    (every step checkpointed, CHECKPOINT_SECONDS = 0: the hook below writes without `checkpointing`)."""
    from gfmd.loading import run_realization

    monkeypatch.setattr(gfmd_contact.app.checkpoints, "CHECKPOINT_SECONDS", 0.0)

    sc = scene(**{"surface.realizations": 1, "output.field_steps": 4})
    out = tmp_path / "out"
    (out / "partial").mkdir(parents=True)

    def checkpoint(result, state):
        result.messages.append(f"message of step {state.step}")
        result.reasons = tuple(result.reasons) + (f"reason of step {state.step}",)
        gfmd_contact.app.io.save_step(out, result, state)
        if state.step == 7:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_realization(sc, 0, checkpoint=checkpoint)
    csv_path = out / "partial" / "realization0.csv"
    csv_path.write_text("".join(csv_path.read_text().splitlines(keepends=True)[:6]))  # steps 0..4
    notes = []
    result, state, done = gfmd_contact.app.io.load_part(out, sc, 0, notes=notes)
    assert (state.step, done, len(result.curve["step"]), sorted(result.fields)) == (4, False, 5, [2, 4])
    assert result.messages == [f"message of step {k}" for k in range(5)]
    assert [r for r in result.reasons if r.startswith("reason")] == [f"reason of step {k}" for k in range(5)]
    assert "dropped 3 saved step(s): realization 0 continues from step 5" in notes[0]
    gfmd_contact.app.io.start_part(out, 0, result)  # the stale fields of the dropped step 6 go with the rows
    assert sorted(p.name for p in (out / "partial").glob("*_step*.npz")) == ["realization0_step2.npz",
                                                                           "realization0_step4.npz"]


def test_verify_is_one_writer_of_its_reports(tmp_path, monkeypatch, capsys):
    import gfmd_contact.cli

    monkeypatch.setenv("GFMD_REPORT_DIR", str(tmp_path / "reports"))
    calls = []
    monkeypatch.setattr(gfmd_contact.cli.subprocess, "call", lambda cmd, cwd=None: calls.append(cmd) or 0)
    with safe_files.DirLock(tmp_path / "reports", command="gfmd verify"):
        assert main(["verify"]) == 2
        line = capsys.readouterr().err.strip().splitlines()[-1]
        assert line.startswith(f"gfmd: error: {tmp_path / 'reports'}: the report folder is being written by pid "
                               f"{os.getpid()}") and "command 'gfmd verify'" in line and "--wait" in line
        assert not calls
    assert main(["verify"]) == 0 and len(calls) == 1
    assert not (tmp_path / "reports" / safe_files.LOCK_NAME).exists()
