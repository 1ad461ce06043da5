"""No test, verification case, study script or package module depends on the benchmark directory.

The benchmark suite (its own pytest root, `python -m pytest benchmarks`) measures the code; nothing the code or its
tests need lives there. Two scans, each a failing list of file:line:
* code: in every .py file of the packages, tests and studies, an import of the directory's modules or a string
  literal (docstrings aside) naming it as a path: ``"<dir>/…"``, ``"<dir>\\…"`` or the path part ``"<dir>"``;
* text: tests and the verification suite do not mention a path into it even in a comment or docstring (a test
  documents what it checks where it checks it; measured findings are in docs/design/performance.md).
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: the directory's name, built here so that this file's own probes are no string literal naming it
DIR = "".join(("bench", "marks"))
CODE = ("gfmd", "gfmd_contact", "reference", "verification", "tests", "studies")
TEXT = ("tests", "verification")
#: a path into the directory: its name, a slash and a file or folder name (not the directory named in prose)
_PATH_INTO = re.compile(rf"\b{DIR}/[\w.]")


def _docstrings(tree):
    """The ids of the docstring constants of the module, its classes and functions."""
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                out.add(id(first.value))
    return out


def _names_dir(text):
    return text == DIR or text.startswith((f"{DIR}/", f"{DIR}\\")) or f"/{DIR}/" in text or f"\\{DIR}\\" in text


def code_references(source, name="<source>"):
    """'name:line: what' for each import of the directory's modules and each non-docstring string naming it."""
    tree = ast.parse(source)
    docs = _docstrings(tree)
    out = []
    for node in ast.walk(tree):
        modules = []
        if isinstance(node, ast.Import):
            modules = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            modules = [node.module]
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs \
                and _names_dir(node.value):
            out.append(f"{name}:{node.lineno}: string {node.value!r}")
        out += [f"{name}:{node.lineno}: import {m}" for m in modules if m.split(".")[0] == DIR]
    return out


def text_references(text, name="<text>"):
    """'name:line: text' for each line that names a path into the directory."""
    return [f"{name}:{i}: {line.strip()}" for i, line in enumerate(text.splitlines(), 1) if _PATH_INTO.search(line)]


def _files(dirs):
    return [p for d in dirs for p in sorted((ROOT / d).rglob("*.py"))] + [ROOT / "conftest.py"]


def test_no_code_reads_the_benchmark_directory():
    found = [hit for p in _files(CODE) for hit in code_references(p.read_text(encoding="utf-8"), p.relative_to(ROOT))]
    assert not found, "\n".join(found)


def test_no_test_mentions_a_path_into_it():
    found = [hit for p in _files(TEXT) for hit in text_references(p.read_text(encoding="utf-8"), p.relative_to(ROOT))]
    assert not found, "\n".join(found)


def test_the_scans_catch_a_violation():
    """Probes: each way a test could read the directory is caught; a mention in a docstring or of the bare word in
    prose is not code."""
    probes = {
        f"import {DIR}.iterates_equal": "import",
        f"from {DIR}.report import header": "import",
        f"SWEEPS = ROOT / {DIR!r} / 'results' / 'x.json'": "string",
        f"data = open('{DIR}/results/x.json').read()": "string",
        f"data = Path(__file__).parents[1].joinpath('{DIR}\\\\results')": "string",
        f"x = '/work/main/{DIR}/results/bench.md'": "string",
    }
    for source, what in probes.items():
        hits = code_references(source)
        assert len(hits) == 1 and f": {what} " in hits[0], (source, hits)
    clean = f'def f():\n    """Measured with {DIR}/x.py."""\n    return "the {DIR} suite"\n'
    assert code_references(clean) == []
    assert text_references(clean) == ["<text>:2: " + f'"""Measured with {DIR}/x.py."""']
    assert text_references(f"# the result records under studies/ and {DIR}/).") == []


def test_the_repository_pytest_never_runs_a_benchmark():
    """`pytest` runs testpaths with pytest's default file pattern: the benchmark directory is not among them and holds
    no file that pattern would collect (the directory is its own pytest root, whose pytest.ini collects bench_*.py)."""
    import tomllib

    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["pytest"]["ini_options"]
    assert DIR not in {Path(p).parts[0] for p in config["testpaths"]}
    assert "python_files" not in config
    assert not [p.name for p in (ROOT / DIR).rglob("*.py") if p.name.startswith("test_") or p.stem.endswith("_test")]
    assert "python_files = bench_*.py" in (ROOT / DIR / "pytest.ini").read_text(encoding="utf-8")
