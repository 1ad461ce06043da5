"""The GFMD algorithms, one module each: `solve(problem, start, settings) -> Relaxed` (`gfmd.chains` runs them).

No algorithm imports another (tests/test_architecture.py): a fallback is a link of its law's chain.
"""
