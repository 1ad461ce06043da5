"""The repository's pytest options (verification.plugin, applied by conftest.py in a checkout): what `--full` and
`-m slow` select."""

from types import SimpleNamespace

import pytest

import conftest
from verification import plugin


class Item(SimpleNamespace):
    def add_marker(self, marker):
        self.markers.append(marker)


def items():
    return [Item(keywords={"slow": True}, markers=[]), Item(keywords={}, markers=[])]


def config(full=False, markexpr=""):
    return SimpleNamespace(getoption=lambda name: {"--full": full, "markexpr": markexpr}[name])


@pytest.mark.parametrize("full, markexpr, skipped", [(False, "", True), (True, "", False), (False, "slow", False),
                                                     (False, "not slow", False)])
def test_slow_studies_are_skipped_only_by_default(full, markexpr, skipped):
    collected = items()
    plugin.pytest_collection_modifyitems(config(full, markexpr), collected)
    assert bool(collected[0].markers) is skipped  # the slow item
    assert collected[1].markers == []  # other items are never skipped


@pytest.mark.parametrize("plugin_loaded", [False, True])
def test_the_checkout_conftest_skips_once(plugin_loaded):
    """conftest.py applies the plugin's skipping only where pytest has not loaded the plugin itself (else the slow
    item would be marked twice)."""
    collected, cfg = items(), config()
    cfg.pluginmanager = SimpleNamespace(is_registered=lambda module: plugin_loaded and module is plugin)
    conftest.pytest_collection_modifyitems(cfg, collected)
    assert len(collected[0].markers) == (0 if plugin_loaded else 1)
