"""Code, docstrings, comments and docs say what and why, not when: no history references.

History lives in git; a measurement that chose a design is kept, condensed, in docs/design/. Scanned: every .py
file under gfmd/, gfmd_contact/, reference/ and verification/, plus every .rst and .md page of docs/ (not what a
build generates there) and the study definitions and scripts under studies/ (.toml, .py); not the verification
data files. The result records under studies/results/ have a test of their own (`RECORDS`).
A hit fails the test with its file:line. False positives are kept out by the patterns, not by exempting files.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("gfmd", "gfmd_contact", "reference", "verification")
DOCS = ("docs/**/*.rst", "docs/**/*.md")
#: the study definitions and their scripts (a result folder's study.toml is a copy of its definition)
STUDIES = ("studies/**/*.toml", "studies/**/*.py")
#: what a docs build writes under docs/ (the gallery's pages are generated from examples/)
GENERATED = ("_build", "auto_examples")

#: a commit hash: 7–40 hex digits with at least one digit and one letter a–f, a token of its own (not part of a word,
#: a path, a hex colour "#rrggbb" or a "0x" literal)
_HASH = r"(?<![\w#./-])(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}(?![\w/-]|\.\w)"
#: name → pattern of one kind of history reference
PATTERNS = {
    "issue number": re.compile(r"\bissues?\s*#?\d+", re.IGNORECASE),
    "session number": re.compile(r"\bsessions?\s*#?\d+", re.IGNORECASE),
    "work-log entry": re.compile(r"\b(?:work[- ]?log|log entry)\s*(?:entry\s*)?#?\d+"
                                 r"|(?<![A-Za-z0-9])s\d{2,3}(?![A-Za-z0-9])", re.IGNORECASE),
    "GitHub reference": re.compile(r"(?:(?<=\s)|(?<=\())#\d+\b|\b(?:PR|pull request)\s*#?\d+", re.IGNORECASE),
    "dated entry": re.compile(r"\b(?:19|20)\d{2}-[01]\d-[0-3]\d\b"),
    "commit hash": re.compile(_HASH),
}
#: tokens the hash pattern matches that are numbers, not hashes: a float's mantissa and exponent (1e1000)
_NUMBER = re.compile(r"\d+e\d+")


def scanned_files(root=ROOT):
    """The files under the rule: every .py of the packages and the docs' pages (.rst, .md) but generated ones."""
    files = [p for pkg in PACKAGES for p in sorted((root / pkg).rglob("*.py"))]
    files += [p for pattern in DOCS for p in sorted(root.glob(pattern))
              if not set(p.relative_to(root / "docs").parts) & set(GENERATED) and p.name != "sg_execution_times.rst"]
    files += [p for pattern in STUDIES for p in sorted(root.glob(pattern))]
    return files


#: the result records: every Markdown file under studies/results/ (what was run, the numbers, the figure, how to
#: reproduce; a run's code version stays in its study.json or meta.json, written as "0.1.0+git.<hash>", which the
#: hash pattern leaves alone)
RECORDS = ("studies/results/**/*.md",)


def record_files(root=ROOT):
    """The result records under the rule (`RECORDS`)."""
    return sorted({p for pattern in RECORDS for p in root.glob(pattern)})


def references(line):
    """The history references in one line of text: [(kind, matched text)]."""
    found = []
    for kind, pattern in PATTERNS.items():
        for m in pattern.finditer(line):
            if kind == "commit hash" and _NUMBER.fullmatch(m.group(0)):
                continue
            found.append((kind, m.group(0)))
    return found


def violations(files, root=ROOT):
    """'file:line: kind "text"' for every history reference in `files`."""
    out = []
    for path in files:
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
        for number, line in enumerate(lines, 1):
            for kind, text in references(line):
                out.append(f"{path.relative_to(root)}:{number}: {kind} {text!r}")
    return out


def test_no_history_references():
    files = scanned_files()
    assert len(files) > 100, "the scan found too few files: is ROOT right?"
    found = violations(files)
    assert not found, ("history references (say what and why; history lives in git, measurements in "
                       "docs/design/):\n" + "\n".join(found))


def test_scan_catches_a_planted_violation(tmp_path):
    """Each kind planted in a copy of the layout is reported with its file:line; a clean line is not."""
    module = tmp_path / "gfmd" / "algorithms" / "planted.py"
    module.parent.mkdir(parents=True)
    planted = [
        '"""Relax a step (issue 24)."""',
        "x = 1  # the default of sessions 26–39",
        "# measured in Session 47, see the work-log entry 12",
        "# recorded in suite_s47/ and (#5)",
        "# Measured (2026-11-25): 3 % faster",
        "# as at b56a595, before e1f001c.",
    ]
    clean = [
        "# Eq. 3 at 2^17: 1e10000 overflows; colour #a1b2c3, 0x1f2e3d4c, tolerance 1e-12",
        "# φn* = 0.15, δn = 0.25 nm, 201 steps, Fig. 8, §4.2, item 4, s = Δn/δn, gh-8400",
        "# decade, facade, 1234567, data/run_3f2a.csv",
    ]
    module.write_text("\n".join(planted + clean) + "\n", encoding="utf-8")
    (tmp_path / "docs" / "design").mkdir(parents=True)
    (tmp_path / "docs" / "design" / "note.md").write_text("Kept since issue #63.\n", encoding="utf-8")
    for pkg in ("gfmd_contact", "reference", "verification"):
        (tmp_path / pkg).mkdir()

    found = violations(scanned_files(tmp_path), root=tmp_path)
    lines = {int(v.split(":")[1]) for v in found if v.startswith("gfmd/algorithms/planted.py:")}
    assert lines == set(range(1, len(planted) + 1)), found
    kinds = {v.split(": ", 1)[1].rsplit(" '", 1)[0] for v in found}
    assert kinds == set(PATTERNS), kinds
    assert any(v.startswith("docs/design/note.md:1: issue number") for v in found), found
    assert "gfmd/algorithms/planted.py:6: commit hash 'b56a595'" in found, found
    assert "gfmd/algorithms/planted.py:6: commit hash 'e1f001c'" in found, found


def test_result_records_have_no_history_references():
    """The README of every studies/results/ folder and the records beside it: no rerun logs, session, issue or
    work-log numbers, commit hashes or dated entries."""
    files = record_files()
    assert {p.relative_to(ROOT).as_posix() for p in files} >= {
        "studies/results/seed_full/README.md", "studies/results/beyond_full/README.md",
        "studies/results/beyond_small/README.md", "studies/results/seed_full/fig8/resolution.md"}, files
    found = violations(files)
    assert not found, ("history references in result records (say what was run, the numbers, the figure and how to "
                       "reproduce; history lives in git):\n" + "\n".join(found))


def test_record_scan_catches_a_planted_rerun_log(tmp_path):
    """A rerun narrative planted in a copy of the layout is reported with its file:line; the package version and a
    run's recorded code version are not."""
    record = tmp_path / "studies" / "results" / "fig9" / "README.md"
    record.parent.mkdir(parents=True)
    record.write_text("# Fig. 9\n\nRerun at 3c95d85 (session 32): 18 min.\ngfmd-contact 0.1.0, code 0.1.0+git.2ce4ea7\n"
                      "Kept in suite_s50/ since issue 24.\n", encoding="utf-8")
    (tmp_path / "studies" / "results" / "notes.md").write_text("Measured 2026-11-25.\n", encoding="utf-8")
    found = violations(record_files(tmp_path), root=tmp_path)
    lines = sorted({v.split(":")[0] + ":" + v.split(":")[1] for v in found})
    assert lines == ["studies/results/fig9/README.md:3", "studies/results/fig9/README.md:5",
                     "studies/results/notes.md:1"], found
