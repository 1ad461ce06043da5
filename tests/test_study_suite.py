"""Suites (gfmd_contact.app.study_suite, `gfmd study run A.toml B.toml --out DIR`): two tiny studies sharing
their hard-wall set run as one suite; the shared tasks are computed once and hard-linked into the other
study; each study directory's tables equal a single-file run's; a rerun reuses everything; two studies
of one name are refused; a study run alone first, or a task interrupted in the second study's
directory, is linked or continued, not recomputed; and the longest-first order (task_cost).

The tiny studies: N = 256, 24 load steps, 2 realizations; "a": hard wall and φn* = 0.01, "b": hard
wall and φn* = 0.15 (4 tasks each, 6 distinct).
"""

import csv
import json
import os

import pytest

from gfmd_contact.app import io
from gfmd_contact.cli import main
from gfmd_contact.app.study import load_study, run_study
from gfmd_contact.app.study_file import longest_first, task_cost
from gfmd_contact.app.study_task import run_task

from test_study import BASE as STUDY_BASE

# test_study's tiny study scene at half its nodes and 24 steps: the suite runs several studies
BASE = STUDY_BASE.replace("nodes = 512", "nodes = 256").replace("steps = 40", "steps = 24")

STUDY = """
name = "{name}"
base = "base.toml"
[zip]
"interface.law" = ["hard-wall", "cohesive"]
"interface.phi_n_star" = [0.15, {phi}]
"""


def write_pair(folder):
    """Study files a (φn* = 0.01) and b (φn* = 0.15), both with the hard-wall set: (path a, path b)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "base.toml").write_text(BASE)
    (folder / "a.toml").write_text(STUDY.format(name="a", phi=0.01))
    (folder / "b.toml").write_text(STUDY.format(name="b", phi=0.15))
    return folder / "a.toml", folder / "b.toml"


def run(*args):
    return main(["study", "run", *map(str, args), "--quiet"])


def record(study_dir):
    return json.loads((study_dir / "study.json").read_text())


def statuses(study_dir):
    return {t["key"]: t["status"] for t in record(study_dir)["tasks"]}


def rows(path):
    with open(path) as fh:
        return [{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(fh)]


def files(task_dir):
    return sorted(p.relative_to(task_dir) for p in task_dir.rglob("*") if p.is_file())


@pytest.fixture(scope="module")
def suite(tmp_path_factory):
    """The suite a, b run from scratch (2 workers), and each study alone: (a, b, out, alone)."""
    folder = tmp_path_factory.mktemp("suite")
    a, b = write_pair(folder)
    out, alone = folder / "out", folder / "alone"
    assert run(a, b, "--out", out, "--workers", "2") == 0
    for path, name in ((a, "a"), (b, "b")):
        assert run(path, "--out", alone / name, "--workers", "2") == 0
    return a, b, out, alone


def test_a_shared_task_is_computed_once_and_hard_linked(suite):
    a, b, out, _ = suite
    shared = {t.key for t in load_study(a).tasks} & {t.key for t in load_study(b).tasks}
    assert len(shared) == 2  # the hard-wall set's two realizations
    sa, sb = statuses(out / "a"), statuses(out / "b")
    assert set(sa.values()) == {"run"}  # a comes first on the command line: everything computed there
    assert {k: s for k, s in sb.items() if k in shared} == {k: "linked" for k in shared}
    assert {s for k, s in sb.items() if k not in shared} == {"run"}
    assert {t["linked_from"] for t in record(out / "b")["tasks"] if t["key"] in shared} == {"a"}
    for key in shared:  # the same inodes: one computation, no copy
        da, db = out / "a" / "tasks" / key, out / "b" / "tasks" / key
        assert files(da) == files(db) and (da / "meta.json") in [da / f for f in files(da)]
        for f in files(da):
            assert os.stat(da / f).st_ino == os.stat(db / f).st_ino, f
        assert os.stat(da).st_ino != os.stat(db).st_ino  # the directories are real
    suite_json = json.loads((out / "suite.json").read_text())
    assert suite_json["complete"] is True
    assert (suite_json["tasks_total"], suite_json["distinct_tasks"]) == (8, 6)
    assert (suite_json["tasks_run"], suite_json["tasks_linked"], suite_json["tasks_failed"]) == (6, 2, 0)
    assert [s["name"] for s in suite_json["studies"]] == ["a", "b"]
    assert suite_json["files"] == [str(a), str(b)]
    assert [(s["tasks_run"], s["tasks_linked"]) for s in suite_json["studies"]] == [(4, 0), (2, 2)]
    assert suite_json["code_version"].startswith("0.")
    rb = record(out / "b")
    assert (rb["complete"], rb["tasks_run"], rb["tasks_linked"], rb["tasks_reused"]) == (True, 2, 2, 0)
    assert rb["suite"]["studies"] == ["a", "b"]
    assert 0 < rb["timings"]["wall_s"] <= rb["timings"]["suite_wall_s"] == suite_json["timings"]["wall_s"]


def test_each_study_directory_equals_a_single_file_run(suite):
    """summary.csv byte for byte, study.csv but wall_s, and the same files as `gfmd study run A --out`."""
    _, _, out, alone = suite
    for name in ("a", "b"):
        assert (out / name / "summary.csv").read_bytes() == (alone / name / "summary.csv").read_bytes()
        assert rows(out / name / "study.csv") == rows(alone / name / "study.csv")
        assert sorted(p.name for p in (out / name).iterdir()) == sorted(p.name for p in (alone / name).iterdir())
        assert (out / name / "study.toml").read_text() == (alone / name / "study.toml").read_text()
    assert sorted(p.name for p in out.iterdir()) == ["a", "b", "suite.json"]  # the locks are gone
    single = record(alone / "a")
    assert "tasks_linked" not in single and "suite" not in single  # a single file's study.json as before


def test_a_rerun_reuses_every_task(suite, tmp_path):
    import shutil

    a, b, out, _ = suite
    again = tmp_path / "again"
    shutil.copytree(out, again)
    before = {n: (again / n / "summary.csv").read_bytes() for n in ("a", "b")}
    assert run(a, b, "--out", again) == 0
    for name in ("a", "b"):
        assert set(statuses(again / name).values()) == {"reused"}
        assert (again / name / "summary.csv").read_bytes() == before[name]
    suite_json = json.loads((again / "suite.json").read_text())
    assert (suite_json["tasks_run"], suite_json["tasks_linked"]) == (0, 0)


def test_two_studies_of_one_name_are_refused_naming_both_files(tmp_path, capsys):
    a, b = write_pair(tmp_path)
    b.write_text(STUDY.format(name="a", phi=0.15))
    out = tmp_path / "out"
    assert run(a, b, "--out", out) == 2
    err = capsys.readouterr().err
    assert "'a'" in err and str(a) in err and str(b) in err and "Traceback" not in err
    assert not out.exists()
    assert run(a, b) == 2 and "--out" in capsys.readouterr().err  # several files need --out


def test_a_study_run_alone_first_is_linked_not_recomputed(suite, tmp_path):
    """b run alone at DIR/b first (as a study directory computed before would be placed there): the suite
    links b's hard-wall tasks into a (the first study) and computes only a's own."""
    a, b = write_pair(tmp_path)
    out = tmp_path / "out"
    run_study(load_study(b), out / "b", workers=1, progress=False)
    assert run(a, b, "--out", out, "--workers", "1") == 0
    shared = {t.key for t in load_study(b).tasks} & {t.key for t in load_study(a).tasks}
    by_key = {t["key"]: t for t in record(out / "a")["tasks"]}
    assert {k: (by_key[k]["status"], by_key[k].get("linked_from")) for k in by_key} == \
        {k: ("linked", "b") if k in shared else ("run", None) for k in by_key}
    assert set(statuses(out / "b").values()) == {"reused"}
    suite_json = json.loads((out / "suite.json").read_text())
    assert (suite_json["tasks_run"], suite_json["tasks_linked"]) == (2, 2)
    assert (out / "a" / "summary.csv").read_bytes() == (suite[3] / "a" / "summary.csv").read_bytes()


def test_an_interrupted_shared_task_continues_where_it_stopped(suite, tmp_path):
    """A hard-wall task stopped after 5 load steps in b's directory (the second study): the suite continues
    it there (5 steps reused, not recomputed in a, the first study) and links it into a."""
    a, b = write_pair(tmp_path)
    out = tmp_path / "out"
    cut = next(t for t in load_study(b).tasks if t.scene.interface.law == "hard-wall")

    class Stop(Exception):
        pass

    def stop_after_5(step, steps):
        if step == 4:
            raise Stop

    with pytest.raises(Stop):
        run_task(cut.scene, out / "b" / "tasks" / cut.key, progress=stop_after_5)
    assert not io.run_complete(out / "b" / "tasks" / cut.key)
    assert run(a, b, "--out", out, "--workers", "2") == 0
    tb = {t["key"]: t for t in record(out / "b")["tasks"]}[cut.key]
    ta = {t["key"]: t for t in record(out / "a")["tasks"]}[cut.key]
    assert (tb["status"], tb["steps_reused"], ta["status"], ta["linked_from"]) == ("run", 5, "linked", "b")
    assert os.stat(out / "a" / "tasks" / cut.key / "curve.csv").st_ino == \
        os.stat(out / "b" / "tasks" / cut.key / "curve.csv").st_ino
    suite_json = json.loads((out / "suite.json").read_text())
    assert (suite_json["tasks_run"], suite_json["tasks_linked"]) == (6, 2)
    for name in ("a", "b"):  # the continued task gives the uninterrupted tables
        assert (out / name / "summary.csv").read_bytes() == (suite[3] / name / "summary.csv").read_bytes()


def test_tasks_run_longest_first(tmp_path):
    """On one worker the tasks finish in the order of decreasing task_cost: φn* = 0.15, hard wall, 0.01."""
    a, b = write_pair(tmp_path)
    out = tmp_path / "out"
    assert run(a, b, "--out", out, "--workers", "1") == 0
    tasks = {t.key: t for path in (a, b) for t in load_study(path).tasks}
    where = {k: out / ("a" if (out / "a" / "tasks" / k).is_dir() else "b") / "tasks" / k for k in tasks}
    finished = sorted(tasks, key=lambda k: os.stat(where[k] / "meta.json").st_mtime_ns)
    laws = [(tasks[k].scene.interface.law, tasks[k].scene.interface.phi_n_star) for k in finished]
    assert laws == [("cohesive", 0.15)] * 2 + [("hard-wall", 0.15)] * 2 + [("cohesive", 0.01)] * 2


def test_task_cost_orders_scenes():
    """Relative costs: coupled ≫ strong cohesive > hard wall > weak cohesive; ∝ steps and N log N;
    less contact (larger h_rms at the same penetration) is cheaper; longest_first sorts stably."""
    from gfmd_contact.core.scene import Scene

    from gfmd_contact.app.study_file import Task

    base = Scene().replace(**{"interface.law": "cohesive", "interface.phi_n_star": 0.001})
    weak = task_cost(base)
    hard = task_cost(base.replace(**{"interface.law": "hard-wall"}))
    strong = task_cost(base.replace(**{"interface.phi_n_star": 0.15}))
    coupled = task_cost(base.replace(**{"interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.5}))
    assert weak < hard < strong < coupled and coupled >= 5 * strong
    assert task_cost(base.replace(**{"loading.steps": 400})) == pytest.approx(2 * weak)
    n = base.surface.nodes
    quarter = base.replace(**{"surface.nodes": n // 4})
    assert task_cost(quarter) == pytest.approx(weak / 4 * (17 - 2) / 17)
    rough = base.replace(**{"surface.h_rms": 30e-9, "loading.final_penetration": 20e-9})
    smooth = base.replace(**{"surface.h_rms": 10e-9, "loading.final_penetration": 20e-9})
    assert task_cost(rough) == pytest.approx(task_cost(smooth) / 3)
    tasks = [Task(str(i), i, 0, 1, s) for i, s in enumerate([base, base.replace(**{"interface.law": "hard-wall"}),
                                                            base, base.replace(**{"interface.phi_n_star": 0.15})])]
    assert [t.key for t in longest_first(tasks)] == ["3", "1", "0", "2"]
