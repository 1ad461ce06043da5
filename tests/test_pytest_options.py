"""The repository's pytest options (conftest.py): what `--full` and `-m slow` select."""

from types import SimpleNamespace

import pytest

import conftest


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
    conftest.pytest_collection_modifyitems(config(full, markexpr), collected)
    assert bool(collected[0].markers) is skipped  # the slow item
    assert collected[1].markers == []  # other items are never skipped
