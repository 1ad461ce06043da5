"""Sphinx configuration of the documentation site: `python -m sphinx -W -b html docs docs/_build/html`.

Pages are reStructuredText, the design notes under docs/design/ Markdown (MyST). The tutorials are a
sphinx-gallery built from examples/, each script executed at its small size (GFMD_EXAMPLE_SIZE=small, its
files in a temporary directory) with its figure shown. The CLI reference is generated from the argparse
parser (`gfmd_contact.cli.build_parser`), the API reference from the docstrings (autodoc, numpy style).
tests/test_docs.py builds the site with warnings as errors.
"""

import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the checkout's packages, installed or not

project = "gfmd-contact"
author = "gfmd-contact developers"
copyright = "gfmd-contact developers"
try:
    import tomllib

    release = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
except (OSError, KeyError):
    release = ""
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "myst_parser",
    "sphinxarg.ext",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3
napoleon_google_docstring = False
napoleon_numpy_docstring = True
autodoc_member_order = "bysource"
autodoc_typehints = "none"
default_role = "code"  # `name` in a docstring is code, as in the source
exclude_patterns = ["_build", "auto_examples/*.ipynb", "auto_examples/*.py", "auto_examples/*.zip",
                    "auto_examples/*.md5", "auto_examples/*.json"]
suppress_warnings = ["config.cache"]  # the gallery's reset_argv is a function: no config cache
math_numfig = True
numfig = True

# the tutorials: every script of examples/, run at its small size; its files go to a temporary directory
os.environ.setdefault("GFMD_EXAMPLE_SIZE", "small")
os.environ.setdefault("MPLBACKEND", "Agg")
_EXAMPLE_OUT = Path(tempfile.mkdtemp(prefix="gfmd-docs-examples-"))


def _example_argv(gallery_conf, script_vars):
    """The command-line arguments each example runs with in the build: its output in a temporary directory."""
    return ["--out", str(_EXAMPLE_OUT / Path(script_vars["src_file"]).stem)]


sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py$",
    "ignore_pattern": r"(^|/)_",
    "reset_argv": _example_argv,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "plot_gallery": "True",
    "abort_on_example_error": True,
    "run_stale_examples": True,  # every build runs every example, so a build that passes proves they run
    "show_memory": False,
    "line_numbers": False,
    "min_reported_time": 1000,
}

# the latest verification report (reports/index.html, written by `pytest verification`), where there is one,
# is published beside the site as verification_report/index.html; the pages link it only then
_REPORT = ROOT / "reports" / "index.html"
html_extra_path = []
if _REPORT.is_file():
    import shutil

    _extra = Path(tempfile.mkdtemp(prefix="gfmd-docs-report-"))
    (_extra / "verification_report").mkdir()
    shutil.copy2(_REPORT, _extra / "verification_report" / "index.html")
    html_extra_path.append(str(_extra))
    tags.add("verification_report")  # noqa: F821 (Sphinx provides `tags` to conf.py)

html_theme = "furo"
html_title = f"gfmd-contact {release}"
html_static_path = []


# the verification checks: one section per case module of verification/, its docstring (reference, scene,
# tolerances and where they come from), so that the page lists every check there is and cannot drift
from docutils.parsers.rst import Directive  # noqa: E402
from docutils.statemachine import StringList  # noqa: E402
from docutils import nodes  # noqa: E402
from sphinx.util.nodes import nested_parse_with_titles  # noqa: E402
import ast  # noqa: E402
import inspect  # noqa: E402


class VerificationChecks(Directive):
    """``.. verification-checks::``: every verification/test_*.py (but the machinery's own tests), its docstring."""

    def run(self):
        lines = []
        for path in sorted((ROOT / "verification").glob("test_*.py")):
            if path.stem == "test_reporting":
                continue
            doc = inspect.cleandoc(ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or "")
            title = f"``{path.name}``"
            lines += [title, "~" * len(title), ""]
            lines += [f".. code-block:: text", ""] + ["   " + line for line in doc.splitlines()] + [""]
        container = nodes.section()
        nested_parse_with_titles(self.state, StringList(lines, source="verification/"), container)
        return container.children


def setup(app):
    app.add_directive("verification-checks", VerificationChecks)
