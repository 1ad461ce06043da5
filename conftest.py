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
    if config.getoption("--full"):
        return
    skip = pytest.mark.skip(reason="expensive study: run with --full")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)
