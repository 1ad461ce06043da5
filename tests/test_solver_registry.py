"""The solver-adapter registry and protocol helpers, and the cross-code page built from several solvers' files."""

from __future__ import annotations

import numpy as np
import pytest

from verification.cross_code import outcomes
from verification.report_cross_code import section
from verification.solvers import registry
from verification.solvers.protocol import Interface, Problem, Solver, not_applicable


def _problem(**kw):
    base = {"heights": np.zeros(8), "lengths": (1e-6,), "contact_modulus": 1e9, "interface": Interface("hard-wall"),
                "boundary": "periodic", "control": "pressure", "path": (1e6,), "name": "t"}
    base.update(kw)
    return Problem(**base)


def test_unknown_name_lists_the_known_ones():
    with pytest.raises(registry.SolverUnavailable, match="known: .*fe.*gfmd"):
        registry.get("no-such-code")


def test_entry_point_registers_a_third_party_code(monkeypatch):
    class EP:
        name, value = "thirdparty", "pkg.mod:Factory"

        def load(self):
            return lambda: "the third party's solver"
    monkeypatch.setattr(registry, "entry_points", lambda group: [EP()] if group == registry.GROUP else [])
    assert registry.get("thirdparty") == "the third party's solver"
    assert "gfmd" in registry.solvers()


def test_missing_package_gives_the_install_hint(monkeypatch, tmp_path):
    (tmp_path / "ghost_adapter_xyz.py").write_text("import no_such_peer_code_xyz\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(registry.BUILTINS, "ghost", ("ghost_adapter_xyz", "Ghost", "gfmd-contact[ghost]"))
    with pytest.raises(registry.SolverUnavailable, match=r"no_such_peer_code_xyz.*pip install 'gfmd-contact\[ghost\]'"):
        registry.get("ghost")
    monkeypatch.setitem(registry.BUILTINS, "lost", ("no_such_adapter_xyz", "Lost", "gfmd-contact[lost]"))
    with pytest.raises(registry.SolverUnavailable, match="adapter module no_such_adapter_xyz is missing"):
        registry.get("lost")


def test_our_adapters_follow_the_protocol_and_give_reasons():
    gfmd, fe = registry.get("gfmd"), registry.get("fe")
    assert isinstance(gfmd, Solver) and isinstance(fe, Solver)
    assert not_applicable(gfmd, _problem()) is None
    assert "layer" in not_applicable(fe, _problem(control="penetration"))
    assert not_applicable(fe, _problem(heights=np.zeros((4, 4)), lengths=(1e-6, 1e-6))).startswith("2:")
    with pytest.raises(ValueError, match="unknown value 'sticky'"):
        not_applicable(gfmd, _problem(interface=Interface("sticky")))


def test_the_refuses_hook_is_consulted_after_the_capabilities():
    """`not_applicable` asks an adapter's optional `refuses(problem)` only where the capability sets allow every
    value; an adapter without the hook (a third party's written before it) refuses nothing more."""
    gfmd = registry.get("gfmd")

    class Picky:
        name, capabilities = "picky", gfmd.capabilities

        def refuses(self, problem):
            return "no pressure on a profile" if problem.control == "pressure" and problem.dimension == 1 else None

    class Plain:
        name, capabilities = "plain", gfmd.capabilities

    assert not_applicable(Picky(), _problem()) == "no pressure on a profile"
    assert not_applicable(Picky(), _problem(control="penetration")) is None
    assert not_applicable(Plain(), _problem()) is None
    assert not_applicable(Picky(), _problem(interface=Interface("hard-wall+exponential"))).startswith(
        "hard-wall+exponential: GFMD")


def _rec(solver, case, error, passed, reason=""):
    return {"case": case, "solver": solver, "reference": "ref", "metric": "m" if reason == "" else "",
            "error": error, "tolerance": 1.0 if error is not None else None, "lower_bound": False, "passed": passed,
            "reason": reason, "wall_s": 0.5 if error is not None else None, "iterations": 3, "resolution": "8",
            "ran": "x", "tolerance_source": "s"}


def test_page_combines_every_solver_in_the_report_dir(tmp_path):
    outcomes.store(tmp_path, "gfmd", [_rec("gfmd", "a", 0.1, True), _rec("gfmd", "b", 2.0, False)])
    outcomes.store(tmp_path, "fe", [_rec("fe", "a", 0.05, True), _rec("fe", "b", None, None, "no 2+1-D here")])
    outcomes.store(tmp_path, "gfmd", [_rec("gfmd", "a", 0.2, True)])  # a rerun replaces its case, keeps the others
    html = "".join(section(tmp_path))
    assert "<th>fe</th>" in html and "<th>gfmd</th>" in html
    assert "n/a: no 2+1-D here" in html and "(fail)" in html and "<svg" in html
    assert "a (m): most accurate fe;" in html
    assert [r["error"] for r in outcomes.load_all(tmp_path)["gfmd"]] == [2.0, 0.2]
    assert section(tmp_path / "empty") == []


def test_an_unknown_solver_is_a_usage_error():
    """`pytest verification --solver NAME` with a name no adapter has stops before any test, naming the known ones."""
    import subprocess
    import sys
    from pathlib import Path
    run = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "--collect-only", "-q",
                          "--solver", "no-such-code", "verification/test_cross_code.py"],
                         cwd=Path(__file__).resolve().parent.parent, capture_output=True, text=True, timeout=300,
                         check=False)
    assert run.returncode == 4, run.stdout[-2000:] + run.stderr[-2000:]
    assert "--solver 'no-such-code': unknown; known: contactmechanics, fe, gfmd, tamaas" in run.stdout + run.stderr


def test_a_solver_not_installed_is_a_usage_error(monkeypatch, tmp_path):
    """`--solver NAME` of a code whose package is missing stops before any test with the install hint (the
    cross-code cases would otherwise all be skipped, and a run asked for that code would pass on nothing)."""
    from verification import plugin

    (tmp_path / "ghost_adapter_xyz.py").write_text("import no_such_peer_code_xyz\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(registry.BUILTINS, "ghost", ("ghost_adapter_xyz", "Ghost", "gfmd-contact[ghost]"))

    class Config:
        def addinivalue_line(self, *args):
            pass

        def getoption(self, name, default=None):
            return "ghost" if name == "--solver" else default

    with pytest.raises(pytest.UsageError, match=r"--solver 'ghost': .*pip install 'gfmd-contact\[ghost\]'"):
        plugin.pytest_configure(Config())
