"""The mutation score machinery (verification.mutations): snippets still apply, and a
representative few mutations are caught (the whole list: `python -m verification.mutations`)."""

from pathlib import Path

import pytest

from verification import mutations as mu


def test_every_mutation_applies_exactly(tmp_path):
    """Each snippet occurs exactly `count` times in the current tree (a moved source line would
    otherwise silently drop a mutation from the score)."""
    tree = mu.copy_tree(mu.ROOT, tmp_path / "tree")
    for m in mu.MUTATIONS:
        before = [(tree / p).read_text() for p in m.paths]
        mu.apply(m, tree)
        after = [(tree / p).read_text() for p in m.paths]
        assert all(a != b for a, b in zip(after, before)), m.id
        assert sum(a.count(m.new) for a in after) >= m.count, m.id
    with pytest.raises(ValueError, match="occurs 0 times"):
        mu.apply(mu.MUTATIONS[0], tree)  # already applied: the snippet is gone


def test_representative_mutations_are_caught():
    """A 1 % stiffer kernel and Verlet silently running FIRE: caught by the cases that should catch
    them (a narrowed suite, to keep CI short; the full list runs the whole suite)."""
    rows = mu.run(["kernel-scale", "verlet-is-fire"], pytest_args=("-k", "hertz or self_consistency"),
                  progress=lambda line: None)
    assert {r["id"]: r["caught"] for r in rows} == {"kernel-scale": True, "verlet-is-fire": True}, rows
    assert all(Path(r["first_failure"].split("::")[0]).name.startswith("test_") for r in rows)


def test_shared_ramp_mutations_are_caught_by_the_ramp_records_case():
    """Bugs in the code every method shares (the ramp's δ bookkeeping, the whole-profile ḡ, the hysteresis
    sign): the ramp-records case alone fails on each (the shared ramp is checked, not trusted)."""
    ids = ["ramp-delta-off-by-one", "g-spacing", "hysteresis-sign"]
    rows = mu.run(ids, pytest_args=("-k", "ramp_records"), progress=lambda line: None)
    assert {r["id"]: r["caught"] for r in rows} == dict.fromkeys(ids, True), rows
    assert all(r["first_failure"].startswith("verification/test_ramp_records.py::") for r in rows), rows


#: the suite's former blind spots: each mutation's own cross-check (the file its `what` names)
BLIND_SPOTS = {"cycle-start-dropped": "test_second_cycle.py", "snap-off-first-jump": "test_snap_off_patches.py",
               "kernel-ly-is-lx": "test_embedded_sinusoid_y.py", "jkr-sphere-pull-off": "test_sphere_pull_off_references.py",
               "persson-tosatti-half": "test_stickiness_numbers.py",
               "user-law-tolerance-gap": "test_user_law_contact_gap.py"}


def test_blind_spot_mutations_are_caught_by_their_cross_checks():
    """One site per class the suite once missed (a second cycle, a rough snap-off, a non-square 2+1-D cell, a
    sphere reference's pull-off, a stickiness number, a user law's contact gap): its cross-check fails on it."""
    by_id = {m.id: m for m in mu.MUTATIONS}
    assert all(f"verification/{name}" in by_id[i].what for i, name in BLIND_SPOTS.items())
    keywords = " or ".join(name.removesuffix(".py").removeprefix("test_") for name in BLIND_SPOTS.values())
    rows = mu.run(list(BLIND_SPOTS), pytest_args=("-k", keywords), progress=lambda line: None)
    assert {r["id"]: r["caught"] for r in rows} == dict.fromkeys(BLIND_SPOTS, True), rows
    assert all(r["first_failure"].startswith(f"verification/{BLIND_SPOTS[r['id']]}::") for r in rows), rows
