"""Every recipe of the README runs as written, and the README stays short and points only at what exists.

Each recipe is the first fenced code block after its heading under "## Recipes". A python recipe runs as a
script, a bash recipe line by line (bash -e), in a temporary directory with this checkout on PYTHONPATH, so
that the files it writes (results/…) go there; a repository path it names (studies/…, verification) is taken
from the checkout. Only the verification report's recipe runs a subset in the fast test (one case, its report
in the temporary directory); the whole suite is the slow variant. Opening a browser is not run.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
RECIPES = ("Load–unload cycle with pull-off", "A 2+1-D surface", "A measured topography", "A user-defined law",
           "A study on Dask", "The verification report")
MAX_RECIPE_LINES = 15
MAX_README_LINES = 250
MAX_LINE_LENGTH = 120


def recipe(text, heading):
    """(language, code) of the first fenced block after the line '### <heading>' of `text`."""
    found = re.search(rf"^### {re.escape(heading)}\s*$.*?^```(\w+)\n(.*?)^```", text, re.MULTILINE | re.DOTALL)
    assert found, f"README.md: no recipe '### {heading}' with a code block"
    return found.group(1), found.group(2)


def recipe_headings(text):
    """The '### ' headings of the '## Recipes' section, in order."""
    section = text.split("\n## Recipes", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"^### (.+?)\s*$", section, re.MULTILINE)


def _bash_lines(code, tmp_path, fast):
    """The commands of a bash recipe as run here: repository paths from the checkout, no browser; `fast`: the
    verification suite cut to one case with its report in tmp_path."""
    lines = []
    for line in code.splitlines():
        command = line.split("  #", 1)[0].strip()
        if not command or command.startswith("#") or "webbrowser" in command:
            continue
        command = re.sub(r"(?<![\w/])(studies/)", f"{ROOT}/\\1", command)
        command = re.sub(r"(?<![\w/'\"])verification(?=\s|$)", f"{ROOT}/verification", command)
        if "pytest" in command:
            command += f" -p no:cacheprovider --report-dir {tmp_path}/reports" + (" -k westergaard" if fast else "")
        command = re.sub(r"^python ", f"{sys.executable} ", command)
        command = re.sub(r"^gfmd ", f"{sys.executable} -m gfmd ", command)
        lines.append(command)
    return lines


def run_recipe(heading, tmp_path, fast=True, text=None):
    """Run one recipe of the README in tmp_path; the finished process."""
    language, code = recipe(text if text is not None else README.read_text(encoding="utf-8"), heading)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
           "MPLBACKEND": "Agg"}
    if language == "python":
        (tmp_path / "recipe.py").write_text(code, encoding="utf-8")
        argv = [sys.executable, "recipe.py"]
    else:
        assert language == "bash", f"{heading}: a recipe is python or bash, not {language}"
        argv = ["bash", "-e", "-c", "\n".join(_bash_lines(code, tmp_path, fast))]
    return subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)


def test_the_readme_is_short():
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) <= MAX_README_LINES, f"README.md has {len(lines)} lines, at most {MAX_README_LINES}"
    long = [n for n, line in enumerate(lines, 1) if len(line) > MAX_LINE_LENGTH]
    assert not long, f"README.md lines over {MAX_LINE_LENGTH} characters: {long}"


def test_the_readme_has_the_six_recipes_each_short():
    text = README.read_text(encoding="utf-8")
    assert recipe_headings(text) == list(RECIPES)
    for heading in RECIPES:
        _, code = recipe(text, heading)
        assert len(code.splitlines()) <= MAX_RECIPE_LINES, f"recipe '{heading}': over {MAX_RECIPE_LINES} lines"


def test_every_relative_link_of_the_readme_exists():
    text = README.read_text(encoding="utf-8")
    links = [link for link in re.findall(r"\]\(([^)\s]+)\)", text) if "://" not in link and not link.startswith("#")]
    assert links, "README.md links nothing"
    missing = [link for link in links if not (ROOT / link.split("#")[0]).exists()]
    assert not missing, f"README.md links to missing files: {missing}"


def test_the_readme_names_no_history():
    from test_no_history_references import violations

    found = violations([README])
    assert not found, "\n".join(found)


@pytest.mark.parametrize("heading", RECIPES[:-1])
def test_recipe_runs(heading, tmp_path):
    done = run_recipe(heading, tmp_path)
    assert done.returncode == 0, f"recipe '{heading}':\n{done.stdout[-2000:]}\n{done.stderr[-3000:]}"


def test_verification_recipe_writes_the_report(tmp_path):
    done = run_recipe("The verification report", tmp_path, fast=True)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert (tmp_path / "reports" / "index.html").is_file()


@pytest.mark.slow
def test_verification_recipe_whole_suite(tmp_path):
    done = run_recipe("The verification report", tmp_path, fast=False)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert (tmp_path / "reports" / "index.html").is_file()


def test_a_failing_recipe_fails(tmp_path):
    text = "## Recipes\n\n### Broken\n\n```python\nraise SystemExit(3)\n```\n"
    assert run_recipe("Broken", tmp_path, text=text).returncode == 3
    text = "## Recipes\n\n### Broken\n\n```bash\nfalse  # a failing command\necho never\n```\n"
    done = run_recipe("Broken", tmp_path, text=text)
    assert done.returncode != 0 and "never" not in done.stdout
