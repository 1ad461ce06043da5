"""Comparisons of independently rounded floats that decide a test (issue 26)."""

from verification.measured import SIGNIFICANT_DIGITS, _rounded, node_bound


def test_node_bound_counts_whole_nodes():
    """|Δa_rel| ≤ stored + 1/N, with stored kept to 4 digits, refused the very k + 1 nodes it allows."""
    n = 512
    stored = _rounded(3 / n, SIGNIFICANT_DIGITS)
    assert stored < 3 / n and not 4 / n <= stored + 1 / n  # the old form: fails on the last digit kept
    assert 4 / n <= node_bound(stored, n) and not 5 / n <= node_bound(stored, n)
    assert 3 / n <= node_bound(stored, n, extra=0) < 4 / n
