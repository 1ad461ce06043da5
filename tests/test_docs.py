"""The API reference (docs/, Sphinx autodoc) builds without a warning and covers the whole API.

`python -m sphinx -W -b html docs DIR` must exit 0: a malformed docstring, a missing
page or an object autodoc cannot import is a warning, and -W makes it an error. Every
name of `gfmd_contact.__all__` must appear in docs/api.rst, and every argument of every
public function and method must be described in its docstring (with its unit where it
has one).
"""

import inspect
import re
import subprocess
import sys
from pathlib import Path

import pytest

import gfmd_contact

ROOT = Path(__file__).resolve().parent.parent


def test_docs_build_without_warnings(tmp_path):
    done = subprocess.run([sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html", str(ROOT / "docs"),
                           str(tmp_path / "html")], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, ("sphinx is in the test extra: pip install \".[test]\"\n"
                                  + done.stdout[-3000:] + done.stderr[-3000:])
    page = (tmp_path / "html" / "api.html").read_text()
    assert "gfmd_contact.run" in page and "Parameters" in page


def test_every_public_name_is_in_the_reference():
    api = (ROOT / "docs" / "api.rst").read_text()
    missing = [n for n in gfmd_contact.__all__ if not re.search(rf"gfmd_contact\.{n}\b", api)]
    assert not missing, f"not in docs/api.rst: {missing}"


def _public_callables():
    for name in gfmd_contact.__all__:
        obj = getattr(gfmd_contact, name)
        if inspect.isfunction(obj):
            yield name, obj
        elif (inspect.isclass(obj) and obj.__module__.startswith("gfmd_contact")
              and not obj.__module__.startswith(("gfmd_contact.core.", "gfmd_contact.app."))):  # the API's own
            for member, fn in vars(obj).items():
                if inspect.isfunction(fn) and not member.startswith("_"):
                    yield f"{name}.{member}", fn


@pytest.mark.parametrize("name, fn", list(_public_callables()), ids=lambda v: v if isinstance(v, str) else "")
def test_every_argument_is_documented(name, fn):
    doc = inspect.getdoc(fn) or ""
    params = [p for p in inspect.signature(fn).parameters if p != "self"]
    undocumented = [p for p in params if not re.search(rf"(^|[\s*`(,]){p}\b", doc)]
    assert doc and not undocumented, f"{name}: arguments not described in its docstring: {undocumented}"
