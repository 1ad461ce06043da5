"""Checkpoints every CHECKPOINT_SECONDS, not every step (`gfmd_contact.app.checkpoints.save_step`, `checkpointing`).

A realization's rows and warm start go to disk at its first step, at its saved steps and once CHECKPOINT_SECONDS
have passed; the steps in between are written when the ramp stops however it stops but a kill: at its end, at an
interrupt (KeyboardInterrupt, SIGINT), at an error. The run's files equal an uninterrupted run's that checkpointed
every step, bit for bit; a resumed run after an interrupt reuses every completed step, after a kill (no chance to
write) the steps up to the last write.
"""

import json

import pytest

import gfmd_contact.app.io
from gfmd_contact.app import checkpoints
from gfmd_contact.cli import main
from tests.test_run_dir import assert_same_run, scene, write_scene


def _steps_on_disk(out, sc, realization):
    part = gfmd_contact.app.io.load_part(out, sc, realization)
    return -1 if part is None else len(part[0].curve["step"]) - 1


@pytest.fixture
def reference(tmp_path, monkeypatch):
    """The scene (2 realizations, 8 steps, fields saved at steps 4 and 8) run with a checkpoint at every step."""
    sc = scene(**{"surface.realizations": 2})
    path = write_scene(tmp_path, sc)
    monkeypatch.setattr(checkpoints, "CHECKPOINT_SECONDS", 0.0)
    assert main(["run", str(path), "--out", str(tmp_path / "ref"), "--quiet", "--no-plot"]) == 0
    monkeypatch.setattr(checkpoints, "CHECKPOINT_SECONDS", 1e9)  # no step is due by time in the tests below
    return sc, path, tmp_path / "ref"


def _run_watched(monkeypatch, path, out, stop=None, kill=False):
    """Run into `out`, recording the steps on disk at every checkpoint call; stop = (realization, step): a
    KeyboardInterrupt there (an interrupt; kill=True: no deferred step written, as SIGKILL)."""
    seen, original = [], gfmd_contact.app.io.save_step

    def spy(out_dir, result, state):
        original(out_dir, result, state)
        seen.append((result.realization, state.step, _steps_on_disk(out_dir, result.scene, result.realization)))
        if (result.realization, state.step) == stop:
            raise KeyboardInterrupt

    monkeypatch.setattr(gfmd_contact.app.io, "save_step", spy)
    if kill:
        monkeypatch.setattr(checkpoints, "flush_steps", lambda outs: None)
    code = main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"])
    monkeypatch.undo()
    return code, seen


def test_steps_between_writes_wait_for_the_next(reference, tmp_path, monkeypatch):
    sc, path, ref = reference
    code, seen = _run_watched(monkeypatch, path, tmp_path / "out")
    assert code == 0
    # written at the first step and the saved steps (4, 8); in between the disk holds the last written step
    assert [on_disk for r, k, on_disk in seen if r == 0] == [0, 0, 0, 0, 4, 4, 4, 4, 8]
    assert_same_run(ref, tmp_path / "out")


def test_a_checkpoint_is_due_after_checkpoint_seconds(reference, tmp_path, monkeypatch):
    sc, path, ref = reference
    clock = iter(range(1000))  # one second per reading: a write every other step at 1.5 s
    monkeypatch.setattr(checkpoints, "_clock", lambda: float(next(clock)))
    monkeypatch.setattr(checkpoints, "CHECKPOINT_SECONDS", 1.5)
    code, seen = _run_watched(monkeypatch, path, tmp_path / "out")
    assert code == 0
    on_disk = [d for r, k, d in seen if r == 0]
    assert on_disk[:2] == [0, 0] and on_disk[2] == 2 and on_disk == sorted(on_disk) and on_disk[-1] == 8
    assert_same_run(ref, tmp_path / "out")


@pytest.mark.parametrize("stop", [(0, 6), (1, 2)])
def test_an_interrupt_writes_every_completed_step(reference, tmp_path, monkeypatch, stop):
    sc, path, ref = reference
    out = tmp_path / "out"
    code, _ = _run_watched(monkeypatch, path, out, stop=stop)
    assert code == 130
    assert _steps_on_disk(out, sc, stop[0]) == stop[1]
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0
    assert json.loads((out / "meta.json").read_text())["resume"] == {"realizations_reused": stop[0],
                                                                      "steps_reused": stop[1] + 1}
    assert_same_run(ref, out)


def test_a_kill_loses_only_the_steps_since_the_last_write(reference, tmp_path, monkeypatch):
    sc, path, ref = reference
    out = tmp_path / "out"
    code, _ = _run_watched(monkeypatch, path, out, stop=(0, 7), kill=True)
    assert code == 130
    assert _steps_on_disk(out, sc, 0) == 4  # the saved step 4 was the last write
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0
    assert json.loads((out / "meta.json").read_text())["resume"]["steps_reused"] == 5
    assert_same_run(ref, out)


@pytest.mark.parametrize("value", ["-1", "soon", "nan", "inf"])
def test_a_bad_checkpoint_interval_is_refused_before_any_compute(reference, tmp_path, monkeypatch, capsys, value):
    sc, path, ref = reference
    monkeypatch.setenv("GFMD_CHECKPOINT_SECONDS", value)
    assert main(["run", str(path), "--out", str(tmp_path / "bad"), "--quiet", "--no-plot"]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith(f"gfmd: error: GFMD_CHECKPOINT_SECONDS = {value!r}: expected the seconds")
    assert not (tmp_path / "bad").exists()


def test_the_interval_from_the_environment(reference, tmp_path, monkeypatch):
    sc, path, ref = reference
    monkeypatch.setenv("GFMD_CHECKPOINT_SECONDS", "0")
    monkeypatch.setattr(checkpoints, "CHECKPOINT_SECONDS", 1e9)
    assert checkpoints.checkpoint_seconds() == 0
    seen, original = [], gfmd_contact.app.io.save_step

    def spy(out_dir, result, state):
        original(out_dir, result, state)
        seen.append(_steps_on_disk(out_dir, result.scene, result.realization))

    monkeypatch.setattr(gfmd_contact.app.io, "save_step", spy)
    assert main(["run", str(path), "--out", str(tmp_path / "out"), "--quiet", "--no-plot"]) == 0
    assert seen == list(range(9)) * 2  # every step on disk as it is computed
    assert_same_run(ref, tmp_path / "out")
