"""`gfmd verify` after `pip install`: the suite, its data and its pytest options ship with the package, and the
installed suite runs from any directory as `pytest --pyargs verification`; from the checkout `pytest verification`
keeps working, with the options registered once."""

import fnmatch
import json
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
#: what a failed wheel build says when no index can be reached (the build backend is fetched for isolation)
OFFLINE = ("Could not find a version that satisfies", "Failed to establish a new connection", "No matching distribution")


def test_every_data_file_of_the_suite_is_package_data():
    """Each file under verification/data/ matches a package-data pattern (a new folder of data would not ship)."""
    patterns = PYPROJECT["tool"]["setuptools"]["package-data"]["verification"]
    data = [p.relative_to(ROOT / "verification").as_posix() for p in (ROOT / "verification" / "data").rglob("*")
            if p.is_file() and "__pycache__" not in p.parts]
    assert data and not [f for f in data if not any(fnmatch.fnmatch(f, pat) and f.count("/") == pat.count("/")
                                                    for pat in patterns)]


def test_the_plugin_is_an_entry_point_under_its_module_name():
    """pytest11 names the plugin as its module, so `-p verification.plugin` and the entry point load it once."""
    assert PYPROJECT["project"]["entry-points"]["pytest11"] == {"verification.plugin": "verification.plugin"}


@pytest.mark.parametrize("plugin", [[], ["-p", "verification.plugin"]])
def test_checkout_registers_the_options_once(plugin):
    """From the checkout, with or without the plugin loaded first (as the entry point does), --full and
    --report-dir parse (twice registered, pytest would refuse them) and a slow study is skipped without --full."""
    base = [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", *plugin, "-q", "-rs", "--report-dir",
            "/nonexistent/reports", "verification/test_analytic_hertz.py", "-k", "fine"]
    full = subprocess.run(base + ["--full", "--collect-only"], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert full.returncode == 0 and "test_hertz_convergence_fine" in full.stdout, full.stdout[-2000:] + full.stderr
    default = subprocess.run(base, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert default.returncode == 0, default.stdout[-2000:] + default.stderr[-2000:]
    assert "1 skipped" in default.stdout and "expensive study: run with --full" in default.stdout


def _wheel(tmp_path):
    """The wheel, built from a copy of what it packages (a build in the checkout would leave build/ there)."""
    source = tmp_path / "source"
    skip = shutil.ignore_patterns("__pycache__", "*.egg-info")
    for name in ("gfmd", "gfmd_contact", "reference", "verification"):
        shutil.copytree(ROOT / name, source / name, ignore=skip)
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, source / name)
    run = subprocess.run([sys.executable, "-m", "pip", "wheel", str(source), "--no-deps", "-q", "-w",
                          str(tmp_path / "wheel")], capture_output=True, text=True, timeout=600)
    if run.returncode and any(s in run.stdout + run.stderr for s in OFFLINE):
        pytest.skip("building the wheel needs setuptools from a package index, which cannot be reached")
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    wheel, = (tmp_path / "wheel").glob("*.whl")
    return wheel


def test_gfmd_verify_runs_the_installed_suite(tmp_path):
    """The wheel installed into a folder of its own, run from an empty directory with that folder first on the
    path: `gfmd verify` runs `pytest --pyargs verification` there (with --full and --report-dir understood),
    imports the suite from the install, and says where the report is and its file:// URL."""
    site, cwd = tmp_path / "site", tmp_path / "cwd"
    cwd.mkdir()
    wheel = _wheel(tmp_path)
    run = subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(site), str(wheel)],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    env = {**os.environ, "PYTHONPATH": str(site), "MPLBACKEND": "Agg"}
    env.pop("GFMD_REPORT_DIR", None)
    where = subprocess.run([sys.executable, "-c", "import verification, gfmd_contact.cli as c; "
                            "print(verification.__file__); print(c._source_root())"],
                           cwd=cwd, env=env, capture_output=True, text=True, timeout=120)
    assert where.stdout.split() == [str(site / "verification" / "__init__.py"), "None"], where.stdout + where.stderr
    run = subprocess.run([sys.executable, "-m", "gfmd", "verify", "--full", "--", "-p", "no:cacheprovider", "-q", "-k",
                          "data_files_name_their_study or scene_shown_once"],
                         cwd=cwd, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    index = cwd / "reports" / "index.html"
    assert f"--pyargs verification -p no:cacheprovider" in run.stderr and f"in {cwd}" in run.stderr
    assert f"open it in a browser: {index.as_uri()}" in run.stderr
    doc = json.loads((cwd / "reports" / "results.json").read_text())
    assert doc["session"]["subset"] == "full" and doc["session"]["counts"]["passed"] == 2
