"""Node counts in verification/data are stored as integers.

A bound "stored + k nodes" (verification/test_fe_selfaffine.py, test_reduced_models.py,
test_contact_rules.py) needs the stored difference as the whole count it is: |Δa_rel| = 1/256 rounded
to four digits is 0.003906, and 0.003906 + 1/256 is 2.4e-7 below 2/256, so a measured difference of
exactly one more node would fail the bound it should meet.
"""

import json

import pytest

from verification import measured
from verification.studies import fe_selfaffine as fs

COUNT_KEYS = ("nodes",)  # keys holding counts of nodes; and every key ending in "node_count"


def counts(obj, path=""):
    """(path, value) of every leaf under a node-count key."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            if k in COUNT_KEYS or k.endswith("node_count"):
                yield from ((f"{path}/{k}", x) for x in _leaves(v))
            else:
                yield from counts(v, f"{path}/{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from counts(v, f"{path}[{i}]")


def _leaves(v):
    if isinstance(v, dict):
        for x in v.values():
            yield from _leaves(x)
    elif isinstance(v, list):
        for x in v:
            yield from _leaves(x)
    else:
        yield v


def test_stored_node_counts_are_integers():
    found = []
    for f in sorted(measured.DATA_DIR.glob("*.json")):
        for path, value in counts(json.loads(f.read_text())):
            found.append(path)
            assert isinstance(value, int) and not isinstance(value, bool), f"{f.name}{path}: {value!r} is not an int"
    assert len(found) >= 3  # contact_rules, fe_selfaffine, reduced_models


def test_a_rounded_float_would_fail_the_bound_and_the_count_keeps_it():
    n = 256
    rounded = float(f"{1 / n:.{measured.SIGNIFICANT_DIGITS}g}")  # what a float |Δa_rel| is stored as
    assert rounded + 1 / n < 2 / n  # the margin the old storage lost
    one = measured.node_count(1 / n, n)
    assert one == 1 and (one + 1) / n >= 2 / n
    assert measured.node_count(2 / n * (1 + 1e-12), n) == 2  # round-off is not a node
    assert measured.node_count(0.0, n) == 0 and measured.node_count(1.5 / n, n) == 2  # a non-count rounds up


@pytest.mark.parametrize("hurst", fs.HURSTS)
def test_fe_selfaffine_bound_admits_exactly_one_more_node(hurst):
    for n in fs.NODES:
        k = fs.stored_node_count(n, hurst)
        assert isinstance(k, int) and fs.stored("a", n, hurst) == k / n
