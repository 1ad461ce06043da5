"""Repository-wide pytest options: `--full` runs the studies marked `slow`; `--report-dir DIR`.

CI runs the representative subset (`pytest`); `pytest --full` adds the
expensive resolutions and sweeps. The options and the skipping live in `verification.plugin`
(what an installed package registers through its pytest11 entry point); this file registers
them for a checkout whose installed metadata lacks that entry point, and does nothing when
pytest has loaded the plugin already.
"""

from verification import plugin as _plugin


def _loaded(pluginmanager):
    return pluginmanager.is_registered(_plugin)


def pytest_addoption(parser, pluginmanager):
    if not _loaded(pluginmanager):
        _plugin.pytest_addoption(parser)


def pytest_collection_modifyitems(config, items):
    if not _loaded(config.pluginmanager):
        _plugin.pytest_collection_modifyitems(config, items)


def pytest_configure(config):
    if not _loaded(config.pluginmanager):
        _plugin.pytest_configure(config)
