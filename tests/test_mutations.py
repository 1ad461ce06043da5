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
