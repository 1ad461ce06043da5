"""Cross-method verification: scenes, studies, thin tests, records and the HTML report.

`pytest verification` runs the representative subset and writes `reports/`;
`pytest verification --full` adds the studies marked slow.

* `scenes`: the scene catalogue (tests, studies, unit tests and benchmarks import scenes from it);
* `studies/`: the sweeps that measure what the tests assert on; `python -m verification.studies.<name>
  --write` regenerates their data files in `data/` (`measured`: reading and writing them);
* `test_*.py`: one case per module: a scene from the catalogue, run through `runs`
  (`run_fe_and_gfmd`, `run_methods`, …), reduced with `metrics`, recorded with the
  `verification_record` fixture (`conftest`) and asserted; a bound derived from a measured number
  reads that number from `data/`;
* `records` (Measurement, results.json), `provenance` (code version, platform, Meter), `plots`
  (plot dicts), `report` (the HTML page), `render_check` (headless Chromium check of the page);
* `analytic_cases`: observables and study helpers of the analytic cases.
"""
