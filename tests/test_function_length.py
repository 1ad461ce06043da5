"""Functions stay short: no function in the methods (gfmd/) or the neutral core (gfmd_contact/core/) over LIMIT lines.

A function's length is its code lines: from its `def` line to its last line (nested functions, comments and blank
lines included), less its docstring. A long solver becomes a small explicit state plus init and step functions
(e.g. `gfmd.dual_cg`, `gfmd.algorithms.dynamics`). STILL_LONG lists the functions that were over the limit when
the rule came, each allowed only up to its recorded length, so that the list can only shrink: a function that
grows fails, and one now within the limit (or gone) must leave the list.
"""

from __future__ import annotations

import ast
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCANNED = ("gfmd", "gfmd_contact/core")
LIMIT = 80

#: "path:qualified name" → its code lines when the rule came (being refactored; the bound can only go down)
STILL_LONG = {}


def code_lines(node):
    """Lines of a function from its `def` to its end, less its docstring's."""
    lines = node.end_lineno - node.lineno + 1
    first = node.body[0] if node.body else None
    if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
        lines -= first.end_lineno - first.lineno + 1
    return lines


def function_lengths(source, module):
    """{"module:qualified name": code lines} of every function and method in `source`, nested ones included."""
    out = {}

    def visit(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                name = prefix + child.name
                out[f"{module}:{name}"] = code_lines(child)
                visit(child, name + ".")
            elif isinstance(child, ast.ClassDef):
                visit(child, prefix + child.name + ".")
            else:
                visit(child, prefix)

    visit(ast.parse(source), "")
    return out


def scanned_lengths(root=ROOT):
    """Every function of the scanned packages with its code lines."""
    out = {}
    for package in SCANNED:
        for path in sorted((root / package).rglob("*.py")):
            out.update(function_lengths(path.read_text(encoding="utf-8"), path.relative_to(root).as_posix()))
    return out


def violations(lengths, limit=LIMIT, still_long=None):
    """'name: lines' for every function over `limit` beyond its STILL_LONG bound, and every stale STILL_LONG entry."""
    still_long = STILL_LONG if still_long is None else still_long
    out = [f"{name}: {lines} code lines (limit {limit}{f', recorded {still_long[name]}' if name in still_long else ''})"
           for name, lines in sorted(lengths.items(), key=lambda item: -item[1])
           if lines > max(limit, still_long.get(name, 0))]
    out += [f"{name}: in STILL_LONG but now {lengths[name]} code lines: remove it from STILL_LONG"
            if name in lengths else f"{name}: in STILL_LONG but no longer exists: remove it from STILL_LONG"
            for name in sorted(still_long) if lengths.get(name, 0) <= limit]
    return out


def test_no_function_over_the_limit():
    found = violations(scanned_lengths())
    assert not found, "functions too long (split into a state plus init/step, or helpers):\n" + "\n".join(found)


def test_the_scan_covers_the_packages():
    """The scan reads the packages' functions (a wrong path would pass the rule by finding nothing)."""
    lengths = scanned_lengths()
    assert "gfmd/dual_cg.py:solve_dual" in lengths and "gfmd_contact/core/ramp.py:run_ramp" in lengths
    assert len(lengths) > 500


def _function(name, statements, docstring_lines=0):
    """A function's text: `docstring_lines` of docstring, `statements` assignments and a return."""
    doc = ['"""' + "\n".join(["A docstring line."] * docstring_lines) + '"""'] if docstring_lines else []
    body = "\n".join(doc + [f"x{i} = {i}" for i in range(statements)] + ["return x0"])
    return f"def {name}():\n{textwrap.indent(body, '    ')}\n"


def test_the_scanner_catches_a_planted_long_function():
    """A function of 82 code lines nested in a method is caught, and the method holding it, by qualified names;
    one of 78 code lines under a 40-line docstring is not; a STILL_LONG bound allows only up to itself and must
    leave the list once its function is short or gone."""
    inner = _function("inner", 80, docstring_lines=3)
    method = f"def method(self):\n{textwrap.indent(inner, '    ')}    return inner()\n"
    module = (f"class Planted:\n{textwrap.indent(method, '    ')}\n\n{_function('short', 1)}\n\n"
              f"{_function('documented', 76, docstring_lines=40)}")
    lengths = function_lengths(module, "planted.py")
    assert lengths == {"planted.py:Planted.method": 1 + 85 + 1, "planted.py:Planted.method.inner": 1 + 80 + 1,
                       "planted.py:short": 3, "planted.py:documented": 1 + 76 + 1}
    assert violations(lengths, still_long={}) == [
        "planted.py:Planted.method: 87 code lines (limit 80)",
        "planted.py:Planted.method.inner: 82 code lines (limit 80)"]
    bounds = {"planted.py:Planted.method": 87, "planted.py:Planted.method.inner": 82}
    assert violations(lengths, still_long=bounds) == []
    grown = violations(lengths, still_long={**bounds, "planted.py:Planted.method.inner": 81})
    assert grown == ["planted.py:Planted.method.inner: 82 code lines (limit 80, recorded 81)"]
    stale = violations(lengths, still_long={**bounds, "planted.py:documented": 90, "planted.py:gone": 90})
    assert stale == ["planted.py:documented: in STILL_LONG but now 78 code lines: remove it from STILL_LONG",
                     "planted.py:gone: in STILL_LONG but no longer exists: remove it from STILL_LONG"]
