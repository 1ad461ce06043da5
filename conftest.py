"""Repository-wide pytest options: `--full` runs the studies marked `slow`.

CI runs the representative subset (`pytest`); `pytest --full` adds the
expensive resolutions and sweeps.
"""

import pytest


def pytest_addoption(parser):
    parser.addoption("--full", action="store_true", default=False,
                     help="also run the expensive studies marked @pytest.mark.slow")
    parser.addoption("--report-dir", default=None,
                     help="where the verification report goes (default reports/; also $GFMD_REPORT_DIR)")


def pytest_collection_modifyitems(config, items):
    if config.getoption("--full") or "slow" in (config.getoption("markexpr") or ""):
        return  # `pytest -m slow` asks for the slow studies: run them (skipping them all would exit 0 on nothing)
    skip = pytest.mark.skip(reason="expensive study: run with --full")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)
