"""The documentation site (docs/, Sphinx) builds without a warning, runs its tutorials and links only to what exists.

`python -m sphinx -W -b html docs DIR` must exit 0: a malformed docstring, a missing page, a :doc: or :ref:
that does not resolve, an example that fails, or an object autodoc cannot import is a warning, and -W makes it
an error. The build executes every script of examples/ (sphinx-gallery, at its small size) and shows its figure;
every relative link and image of every built page must name a file of the build (and an anchor on it, where it
names one), so no page links to a missing file — checked offline. Every name of `gfmd_contact.__all__` must
appear in docs/api.rst, every argument of every public function and method must be described in its docstring
(with its unit where it has one), and the CLI reference must hold every subcommand of the parser.
"""

import argparse
import inspect
import re
import subprocess
import sys
import time
from html.parser import HTMLParser
from urllib.parse import unquote, urlsplit
from pathlib import Path

import pytest

import gfmd_contact

ROOT = Path(__file__).resolve().parent.parent


EXAMPLES = sorted(p.stem for p in (ROOT / "examples").glob("*.py") if not p.name.startswith("_"))


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site built once, with warnings as errors: its html directory and the build's wall time (s)."""
    out = tmp_path_factory.mktemp("docs") / "html"
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html", str(ROOT / "docs"), str(out)],
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, ("the docs extra is in the test extra: pip install \".[test]\"\n"
                                  + done.stdout[-3000:] + done.stderr[-3000:])
    return out, time.perf_counter() - start


def test_docs_build_without_warnings(site):
    html, _ = site
    page = (html / "api.html").read_text()
    assert "gfmd_contact.run" in page and "Parameters" in page


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_tutorial_is_executed_with_its_figure(site, name):
    html, _ = site
    page = (html / "auto_examples" / f"{name}.html").read_text()
    figure = html / "_images" / f"sphx_glr_{name}_001.png"
    assert figure.is_file() and figure.stat().st_size > 10_000, f"{name}: no figure from the executed example"
    assert f"sphx_glr_{name}_001.png" in page


def test_cli_reference_has_every_subcommand_and_option(site):
    from gfmd_contact.cli import build_parser

    html, _ = site
    page = (html / "cli.html").read_text()
    headings = {re.sub(r"<[^>]+>|¶", "", h).strip() for h in re.findall(r"<h[1-6][^>]*>(.*?)</h[1-6]>", page)}
    missing = []
    for name, sub in _subcommands(build_parser()):
        missing += [name] if name.split()[-1] not in headings else []
        missing += [f"{name} {o}" for a in sub._actions for o in a.option_strings if o not in page]
    assert not missing, f"not in the CLI reference: {missing}"


def _subcommands(parser, prefix=""):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield f"{prefix}{name}", sub
                yield from _subcommands(sub, prefix=f"{prefix}{name} ")


class _Links(HTMLParser):
    """The href/src of every tag and the ids of an html page."""

    def __init__(self):
        super().__init__()
        self.links, self.ids = [], set()

    def handle_starttag(self, tag, attrs):
        for key, value in attrs:
            if key in ("href", "src") and value:
                self.links.append(value)
            elif key in ("id", "name") and value:
                self.ids.add(value)


def broken_links(html):
    """'page: link' for every relative link of the built site whose file (or anchor on it) does not exist."""
    parsed = {}
    for page in html.rglob("*.html"):
        parsed[page] = _Links()
        parsed[page].feed(page.read_text(encoding="utf-8"))
    broken = []
    for page, found in parsed.items():
        for link in found.links:
            parts = urlsplit(link)
            if parts.scheme or parts.netloc or link.startswith(("mailto:", "data:", "javascript:")):
                continue  # external: not checked offline
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{page.relative_to(html)}: {link}")
            elif parts.fragment and target.suffix == ".html" and target in parsed \
                    and unquote(parts.fragment) not in parsed[target].ids:
                broken.append(f"{page.relative_to(html)}: {link} (no such anchor)")
    return broken


def test_no_page_links_to_a_missing_file(site):
    html, _ = site
    assert len(list(html.rglob("*.html"))) > 20, "the site has too few pages: did the build run?"
    broken = broken_links(html)
    assert not broken, "links to missing files:\n" + "\n".join(broken[:50])


def test_the_link_check_finds_a_broken_link(tmp_path):
    (tmp_path / "a.html").write_text('<a href="b.html#x">b</a> <img src="_images/gone.png"> '
                                     '<a href="https://example.org/none">web</a> <a href="#top" id="top">t</a>')
    (tmp_path / "b.html").write_text('<p id="y">b</p>')
    assert sorted(broken_links(tmp_path)) == ["a.html: _images/gone.png", "a.html: b.html#x (no such anchor)"]


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
