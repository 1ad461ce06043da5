"""Crash consistency: SIGKILL at many seeded random moments, resume each time, same final files.

tests/crash_driver.py kills `gfmd run` (GFMD and the FE method, figures included) and
`gfmd study run` at random write events: before a write, half-way through one (a temporary
file or a CSV row cut short) and after it, which are all the distinct states a kill during a
load step, a checkpoint or the final table and figure writes can leave. After the last resume
the run's curve.csv (wall_s aside), mean_curve.csv, fields.npz, scene.toml and meta.json
(timings, date, command, resume counts aside), and the study's study.csv (wall_s aside),
summary.csv and summary.nc must equal an uninterrupted run's bit for bit: the methods are
deterministic and the warm start is saved bit for bit, so no tolerance applies. The kill
points are printed (pytest -s) and checked to reach every phase of the run, and no resume may
lose a saved step (the steps on disk never decrease from one kill to the next).
"""

import csv
import io
import json
import os
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest

from gfmd_contact.core.scene import scene_to_toml
from test_run_dir import assert_same_run, scene

DRIVER = Path(__file__).with_name("crash_driver.py")


def drive(kind, ref, out, seed, gap, *args):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(DRIVER.parent.parent)] + sys.path))
    done = subprocess.run([sys.executable, str(DRIVER), kind, str(ref), str(out), str(seed), str(gap),
                           *map(str, args)],
                          capture_output=True, text=True, timeout=600, env=env)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["exit"] == 0, report
    return report


def phase(kill):
    path = kill["path"]
    if "partial" in path:
        return "load steps (row, state, fields)"
    if path.startswith(("plots", "figures")):
        return "figures"
    start = ("scene.toml", "study.toml", "base_scene.toml")
    if Path(path).name in start or "meta.json" in path and "tasks" not in path:
        return "start (scene, meta)"
    return "final tables"


def summarize(name, report, total_steps):
    kills = report["kills"]
    spread = Counter(phase(k) for k in kills)
    stages = Counter(k["stage"] for k in kills)
    fractions = [round(k["steps_on_disk"] / total_steps, 2) for k in kills]
    print(f"\n{name}: {len(kills)} kills; phases {dict(spread)}; stages {dict(stages)}; "
          f"saved steps at the kills, in order (fraction of {total_steps}): {fractions}")
    saved = [k["steps_on_disk"] for k in kills]
    assert saved == sorted(saved), "a resume lost saved load steps"  # nothing finished is lost
    return spread, stages, fractions


def strip_wall(text):
    rows = list(csv.reader(io.StringIO(text)))
    i = rows[0].index("wall_s")
    return [r[:i] + r[i + 1:] for r in rows]


def crash_run(tmp_path, sc, seed, gap, extra=()):
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(sc))
    ref, out = tmp_path / "ref", tmp_path / "out"
    report = drive("run", ref, out, seed, gap, path, *extra)
    assert_same_run(ref, out)
    figures = sorted(p.name for p in (ref / "plots").iterdir())
    assert figures and figures == sorted(p.name for p in (out / "plots").iterdir())
    assert not list(out.rglob("*.tmp")) and not list(out.rglob(".gfmd.lock")) and not list(out.rglob("partial"))
    return report


def test_run_killed_at_random_moments_resumes_bit_equal(tmp_path):
    sc = scene(**{"surface.realizations": 1, "loading.steps": 8})
    report = crash_run(tmp_path, sc, seed=26, gap=5)
    spread, stages, _ = summarize("gfmd run (GFMD)", report, 9)
    assert len(report["kills"]) >= 15
    assert set(spread) >= {"load steps (row, state, fields)", "final tables", "figures"}
    assert set(stages) == {"before", "mid", "after"}


def test_fe_run_killed_at_random_moments_resumes_bit_equal(tmp_path):
    from test_cli_fe import fe_scene

    sc = fe_scene("cohesive", "self-affine").replace(**{"method.name": "fe", "loading.steps": 4})
    report = crash_run(tmp_path, sc, seed=27, gap=12)
    spread, _, _ = summarize("gfmd run (FE)", report, 5 * sc.surface.realizations)
    assert len(report["kills"]) >= 5 and "load steps (row, state, fields)" in spread


STUDY = """
name = "crash"
[scene]
surface = {{ length = 320e-9, nodes = 256, rolloff_wavelength = 160e-9, rollon_wavelength = 10e-9, realizations = {r} }}
loading = {{ steps = {steps}, final_penetration = 8e-9, initial_separation = 20e-9 }}
interface = {{ length_normal = 2.5e-9 }}
output = {{ field_steps = 2 }}
[axes]
"interface.phi_n_star" = [0.1, 0.2]
"""


def crash_study(tmp_path, seed, gap, r, steps):
    study = tmp_path / "study.toml"
    study.write_text(STUDY.format(r=r, steps=steps))
    ref, out = tmp_path / "ref", tmp_path / "out"
    report = drive("study", ref, out, seed, gap, study)
    assert strip_wall((ref / "study.csv").read_text()) == strip_wall((out / "study.csv").read_text())
    assert (ref / "summary.csv").read_text() == (out / "summary.csv").read_text()
    assert (ref / "summary.nc").read_bytes() == (out / "summary.nc").read_bytes()
    for task in (ref / "tasks").iterdir():
        assert_same_run(task, out / "tasks" / task.name)
    assert json.loads((out / "study.json").read_text())["complete"] is True
    assert not list(out.rglob("*.tmp")) and not list(out.rglob(".gfmd.lock")) and not list(out.rglob("partial"))
    return report


def test_study_killed_at_random_moments_resumes_bit_equal(tmp_path):
    report = crash_study(tmp_path, seed=28, gap=14, r=1, steps=6)
    spread, _, _ = summarize("gfmd study run", report, 2 * 7)
    assert len(report["kills"]) >= 5
    assert set(spread) >= {"load steps (row, state, fields)", "final tables"}


@pytest.mark.slow
def test_bigger_crash_campaign(tmp_path):
    """More kills over longer runs: 3 realizations × 30 steps at N = 512, and a 2 × 2 × 20-step study."""
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    sc = scene(**{"surface.nodes": 512, "surface.realizations": 3, "loading.steps": 30})
    report = crash_run(run_dir, sc, seed=126, gap=10)
    summarize("gfmd run (GFMD, slow)", report, 3 * 31)
    assert len(report["kills"]) >= 40
    study_dir = tmp_path / "study"
    study_dir.mkdir()
    report = crash_study(study_dir, seed=128, gap=10, r=2, steps=20)
    summarize("gfmd study run (slow)", report, 4 * 21)
    assert len(report["kills"]) >= 25
