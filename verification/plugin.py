"""The verification suite's pytest options, wherever it runs: `--full` (also the studies marked `slow`),
`--report-dir DIR` (where the report goes) and `--solver NAME` (the contact code the cross-code cases run
against, `verification.solvers.registry`; default gfmd).

Registered by the package's ``pytest11`` entry point under the name ``verification.plugin``, so that
``pytest --pyargs verification --full`` works after ``pip install``; from a source checkout without that
entry point the repository's conftest.py registers the same hooks (once: it defers to this module when
pytest has loaded it).
"""

import pytest

# names only: no adapter is imported here
from verification.solvers.registry import GROUP, SolverUnavailable, get, solvers


def pytest_addoption(parser):
    options = {"--full": dict(action="store_true", default=False,
                              help="also run the expensive studies marked @pytest.mark.slow"),
               "--report-dir": dict(default=None, metavar="DIR",
                                    help="where the verification report (results.json, index.html) goes (default: "
                                         "$GFMD_REPORT_DIR, else reports/ under pytest's rootdir)"),
               "--solver": dict(default="gfmd", metavar="NAME",
                                help="the contact code the cross-code cases (verification/test_cross_code.py) run "
                                     "against: gfmd (default), fe, tamaas, contactmechanics, or one registered in "
                                     "the entry-point group gfmd_contact.solvers")}
    for name, spec in options.items():
        try:
            parser.addoption(name, **spec)
        except ValueError:  # added already (`-p verification.conftest` registers --report-dir too)
            pass


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: expensive resolutions/studies, skipped unless --full or -m slow")
    name = config.getoption("--solver", default="gfmd")
    if name not in solvers():
        raise pytest.UsageError(f"--solver {name!r}: unknown; known: {', '.join(sorted(solvers()))} (register "
                                f"another through the entry-point group {GROUP!r})")
    try:  # a code asked for by name but not installed: one usage error with the install hint, not a skipped suite
        get(name)
    except SolverUnavailable as exc:
        raise pytest.UsageError(f"--solver {name!r}: {exc}") from None


def pytest_collection_modifyitems(config, items):
    if config.getoption("--full") or "slow" in (config.getoption("markexpr") or ""):
        return  # `pytest -m slow` asks for the slow studies: run them (skipping them all would exit 0 on nothing)
    skip = pytest.mark.skip(reason="expensive study: run with --full")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)
