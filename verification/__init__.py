"""Cross-method verification: cases, harness (records, provenance), HTML report.

`pytest verification` runs the representative subset and writes `reports/`;
`pytest verification --full` adds the studies marked slow.
"""
