"""Every repository path the package's code and docstrings name (``docs/…``, ``benchmarks/…``, ``tests/…``,
``verification/data/…``, ``studies/…``) exists: a deleted benchmark, data file or note leaves no dangling pointer
for a reader to follow."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("gfmd", "gfmd_contact", "reference", "verification")
#: a path into the repository: a top folder, then path characters, ending in a file suffix
PATH = re.compile(r"(?<![\w/.~-])((?:docs|benchmarks|tests|studies|verification/data)/[\w./*-]*\.(?:md|py|json|rst|toml))")


def named_paths(text):
    return set(PATH.findall(text))


def dangling(root=ROOT):
    """{file:line: path} for each named path that matches nothing in the tree (a * matches as a glob)."""
    found = {}
    files = [p for pkg in PACKAGES for p in sorted((root / pkg).rglob("*.py"))
             if not p.name.startswith(("test_", "_probe"))] + [root / "pyproject.toml"]  # tests name made-up paths
    for path in files:
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for name in named_paths(line):
                if not (any(root.glob(name)) if "*" in name else (root / name).exists()):
                    found[f"{path.relative_to(root)}:{number}"] = name
    return found


def test_named_paths_exist():
    missing = dangling()
    assert not missing, "paths named but not in the tree:\n" + "\n".join(f"{k}: {v}" for k, v in missing.items())


def test_the_check_sees_a_dangling_path(tmp_path):
    (tmp_path / "gfmd").mkdir()
    (tmp_path / "docs" / "design").mkdir(parents=True)
    (tmp_path / "docs" / "design" / "solvers.md").write_text("")
    (tmp_path / "pyproject.toml").write_text("# measured: docs/design/gone.md\n")
    (tmp_path / "gfmd" / "m.py").write_text('"""See docs/design/solvers.md and studies/old_study.py."""\n')
    assert dangling(tmp_path) == {"pyproject.toml:1": "docs/design/gone.md", "gfmd/m.py:1": "studies/old_study.py"}
