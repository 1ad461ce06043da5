"""Observation-only variants share a solve (gfmd_contact.core.observation, gfmd_contact.core.ramp variants,
gfmd_contact.app.study_task.run_shared): tasks that differ only in interface.contact_rule / contact_tolerance /
contact_gap are solved once, and each task directory gets what a separate run writes (wall times aside);
any other difference keeps tasks apart; an interrupted group resumes to the same files; a study and a
suite with a contact-rule axis run one solve per group, counted from their outcome records.

Tiny scenes: test_study's at N = 256, 24 load steps.
"""

import csv
import json
import tomllib

import numpy as np
import pytest

from gfmd_contact.core.observation import HARD_WALL_OBSERVATION_KEYS, OBSERVATION_KEYS
from gfmd_contact.core.scene import scene_from_dict
from gfmd_contact.app import io
from gfmd_contact.app.methods import solve_key
from gfmd_contact.app.study import load_study, run_study
from gfmd_contact.app.study_file import solve_address, solve_groups, task_scene
from gfmd_contact.app.study_suite import run_suite
from gfmd_contact.app.study_task import run_shared, run_task

from test_study import BASE as STUDY_BASE

BASE = STUDY_BASE.replace("nodes = 512", "nodes = 256").replace("steps = 40", "steps = 24")
RULES = ({"contact_rule": "traction-tolerance"}, {"contact_rule": "compressive"},
         {"contact_rule": "gap", "contact_gap": 2.0}, {"contact_rule": "traction-tolerance", "contact_tolerance": 0.01})


def scene(phi=0.01, **interface):
    d = tomllib.loads(BASE)
    d["interface"].update(phi_n_star=phi, **interface)
    return task_scene(scene_from_dict(d), 0)


def curve(task_dir):
    with open(task_dir / "curve.csv") as fh:
        return [{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(fh)]


def assert_same_task(a, b):
    """Two task directories hold the same run: curve.csv (all but wall_s), fields.npz, scene.toml, meta.json
    (all but its wall times, date, command and resume counts)."""
    assert curve(a) == curve(b)
    fa, fb = np.load(a / "fields.npz"), np.load(b / "fields.npz")
    assert sorted(fa.files) == sorted(fb.files)
    for name in fa.files:
        np.testing.assert_array_equal(fa[name], fb[name], err_msg=name)
    assert (a / "scene.toml").read_text() == (b / "scene.toml").read_text()
    ma, mb = (json.loads((d / "meta.json").read_text()) for d in (a, b))
    for m in (ma, mb):
        m["timings"].pop("total_s"), m.pop("date"), m.pop("command"), m.pop("resume")
        m["timings"].pop("solve_s_per_realization")
    assert ma == mb


@pytest.fixture(scope="module")
def separate(tmp_path_factory):
    """Each rule's task run alone (run_task): {index: task dir}."""
    root = tmp_path_factory.mktemp("separate")
    dirs = {}
    for i, rule in enumerate(RULES):
        dirs[i] = root / f"t{i}"
        assert run_task(scene(**rule), dirs[i])["status"] == "run"
    return dirs


def test_the_shared_solve_writes_each_variant_what_a_separate_run_writes(separate, tmp_path):
    members = [(scene(**rule), tmp_path / f"t{i}") for i, rule in enumerate(RULES)]
    outcomes = run_shared(members)
    assert [o["status"] for o in outcomes] == ["run"] * len(RULES)
    assert ["solved_with" in o for o in outcomes] == [False] + [True] * (len(RULES) - 1)
    assert {o.get("solved_with") for o in outcomes[1:]} == {"t0"}
    for i in separate:
        assert_same_task(separate[i], tmp_path / f"t{i}")
    a_rel = [[float(r["a_rel"]) for r in curve(separate[i])] for i in separate]
    assert len({tuple(a) for a in a_rel}) == len(RULES), "the rules observe different contact sets"
    p = [[r["p"] for r in curve(separate[i])] for i in separate]
    assert all(q == p[0] for q in p), "one solve: the same p"
    again = run_shared(members)  # complete: reused
    assert [o["status"] for o in again] == ["reused"] * len(RULES)


@pytest.mark.parametrize("other", [{"interface.phi_n_star": 0.02}, {"interface.law": "cohesive"},
                                   {"surface.seed": 2}, {"loading.steps": 30}, {"method.name": "fe"}])
def test_only_observation_keys_share_a_solve(other):
    base = scene(law="hard-wall", phi=0.15)
    assert all(solve_address(scene(law="hard-wall", phi=0.15, **rule)) == solve_address(base) for rule in RULES)
    assert set(OBSERVATION_KEYS) == {"interface.contact_rule", "interface.contact_tolerance", "interface.contact_gap"}
    assert set(HARD_WALL_OBSERVATION_KEYS) == {"interface.length_normal"}
    changed = base.replace(**({"material.thickness": 640e-9} if "method.name" in other else {}), **other)
    assert solve_address(changed) != solve_address(base)
    if "method.name" in other:  # the FE reference shares no solve, not even between its own rule variants
        assert solve_key(changed) is None
        rule = changed.replace(**{"interface.contact_rule": "compressive"})
        assert solve_address(rule) != solve_address(changed)
    jobs = [("a", base), ("b", base.replace(**{"interface.contact_rule": "compressive"})), ("c", changed)]
    assert [[j[0] for j in g] for g in solve_groups(jobs)] == [["a", "b"], ["c"]]


def test_hard_wall_tasks_differing_in_length_normal_share_a_solve(tmp_path):
    """δn enters a hard-wall step only through the "gap" rule's threshold contact_gap·δn: tasks that differ in δn and
    the rule share one solve, each directory what a separate run writes; for a cohesive law δn keeps them apart."""
    variants = [dict(law="hard-wall", phi=0.15, length_normal=dn, **rule) for dn in (0.25e-9, 1e-9)
                for rule in ({"contact_rule": "traction-tolerance"}, {"contact_rule": "gap", "contact_gap": 2.0})]
    scenes = [scene(**v) for v in variants]
    assert len({solve_address(s) for s in scenes}) == 1
    cohesive = [scene(phi=0.15, length_normal=dn) for dn in (0.25e-9, 1e-9)]
    assert solve_address(cohesive[0]) != solve_address(cohesive[1])
    members = [(s, tmp_path / "shared" / f"t{i}") for i, s in enumerate(scenes)]
    outcomes = run_shared(members)
    assert [o["status"] for o in outcomes] == ["run"] * len(scenes)
    assert {o.get("solved_with") for o in outcomes[1:]} == {"t0"}
    for i, s in enumerate(scenes):
        assert run_task(s, tmp_path / "alone" / f"t{i}")["status"] == "run"
        assert_same_task(tmp_path / "alone" / f"t{i}", tmp_path / "shared" / f"t{i}")
    a_rel = [tuple(float(r["a_rel"]) for r in curve(tmp_path / "alone" / f"t{i}")) for i in range(len(scenes))]
    assert a_rel[1] != a_rel[3], "the gap rule's threshold scales with δn"


def test_an_interrupted_group_resumes_to_the_separate_runs(separate, tmp_path, monkeypatch):
    """Killed after 40 checkpoints (the members stop at different steps), run again: every directory
    equals the separate run's; the steps each member had saved are reused."""
    members = [(scene(**rule), tmp_path / f"t{i}") for i, rule in enumerate(RULES)]
    save, calls = io.save_step, [0]

    def killed(out, result, state):
        calls[0] += 1
        if calls[0] > 40:
            raise KeyboardInterrupt
        save(out, result, state)

    monkeypatch.setattr(io, "save_step", killed)
    with pytest.raises(KeyboardInterrupt):
        run_shared(members)
    monkeypatch.setattr(io, "save_step", save)
    saved = [len(io.load_part(d, s, 0)[0].curve["step"]) for s, d in members]
    assert saved == [10, 10, 10, 10]
    # a member further ahead: the ramp restarts from the one behind, the one ahead keeps its steps
    monkeypatch.setattr(io, "save_step", killed)
    calls[0] = 35
    with pytest.raises(KeyboardInterrupt):
        run_shared(members[:1])
    monkeypatch.setattr(io, "save_step", save)
    saved = [len(io.load_part(d, s, 0)[0].curve["step"]) for s, d in members]
    assert saved == [15, 10, 10, 10]
    outcomes = run_shared(members)
    assert [o["steps_reused"] for o in outcomes] == saved
    for i in separate:
        assert_same_task(separate[i], tmp_path / f"t{i}")


RULE_STUDY = """
name = "{name}"
base = "base.toml"
[axes]
"interface.contact_rule" = {rules}
[zip]
"interface.law" = ["hard-wall", "cohesive"]
"interface.phi_n_star" = [0.15, 0.01]
"""


def test_a_study_with_a_rule_axis_runs_one_solve_per_group(tmp_path):
    (tmp_path / "base.toml").write_text(BASE)
    (tmp_path / "s.toml").write_text(RULE_STUDY.format(name="s", rules='["traction-tolerance", "compressive", "gap"]'))
    study = load_study(tmp_path / "s.toml")
    assert len(study.sets) == 6 and len(study.tasks) == 12
    record = run_study(study, tmp_path / "out", workers=2, progress=False)
    solved = [t for t in record["tasks"] if t["status"] == "run" and "solved_with" not in t]
    assert len(solved) == 4 == len(study.sets) // 3 * 2  # 2 laws × 2 realizations
    assert record["tasks_solved_with"] == 8 and record["tasks_run"] == 12
    by_key = {t["key"]: t for t in record["tasks"]}
    for t in study.tasks:  # each task directory equals its own run (one per group checked against run_task)
        if by_key[t.key].get("solved_with") and t.realization == 1:
            alone = tmp_path / "alone" / t.key
            run_task(t.scene, alone)
            assert_same_task(alone, tmp_path / "out" / "tasks" / t.key)
            assert solve_address(t.scene) == solve_address(
                next(u.scene for u in study.tasks if u.key == by_key[t.key]["solved_with"]))
    rerun = run_study(study, tmp_path / "out", workers=2, progress=False)
    assert rerun["tasks_reused"] == 12 and rerun["tasks_solved_with"] == 0


def test_a_suite_shares_solves_after_its_identical_task_dedup(tmp_path):
    (tmp_path / "base.toml").write_text(BASE)
    paths = []
    for name, rules in (("a", '["traction-tolerance", "compressive"]'), ("b", '["compressive", "gap"]')):
        paths.append(tmp_path / f"{name}.toml")
        paths[-1].write_text(RULE_STUDY.format(name=name, rules=rules))
    studies = [load_study(p) for p in paths]
    suite = run_suite(studies, tmp_path / "out", workers=2, progress=False)
    assert suite["distinct_tasks"] == 12  # 3 rules × 2 laws × 2 realizations
    assert suite["tasks_linked"] == 4  # the compressive tasks of b
    assert suite["tasks_solved_with"] == 8  # 4 solves for 12 distinct tasks
    assert suite["tasks_run"] == 12  # a: 8 run; b: 4 linked (compressive), 4 run (gap)
    for s in studies:
        for t in s.tasks:
            if t.realization == 0 and t.scene.interface.law == "cohesive":
                alone = tmp_path / "alone" / t.key
                if not alone.exists():
                    run_task(t.scene, alone)
                assert_same_task(alone, tmp_path / "out" / s.name / "tasks" / t.key)
