"""GFMD hard wall vs Hertz line contact (reference-formulas §2) in a large periodic cell: convergence in N.

Study, scene and metrics: `verification.studies.hertz`; its measured errors and observed orders are in
verification/data/hertz.json (regenerate: `python -m verification.studies.hertz --write`, with `--full`
for N up to 65536).

Tolerances:
* observed orders a(F) ≥ 1.2, p(x) ≥ 0.6: the expected orders 2 (1.5 once the periodic-image floor
  ≈ 2e-5 is met) and 1, minus the scatter of the contact edge moving across nodes;
* finest-N errors, CI (N = 2048…16384): 3× the stored N = 16384 errors (entry "ci"); slow (…65536):
  6× (a(F), at the periodic-image floor) and 5.5× (p(x)) the stored N = 65536 errors (entry "full").
  A wrong modulus or radius (factor 2 in E*) would give an a(F) error of 30%.
"""

from __future__ import annotations

import numpy as np
import pytest

from verification import analytic_cases as ac
from verification import measured
from verification.plots import profile_plot, table_plot
from verification.studies import hertz as hz

METHODS = ("gfmd-fire", "analytic-hertz")
CASE = "analytic/hertz-hard-wall-cylinder"
MIN_ORDER = {"a(F)": 1.2, "p(x)": 0.6}
FACTOR = {"ci": {"a(F)": 3.0, "p(x)": 3.0}, "full": {"a(F)": 6.0, "p(x)": 5.5}}  # × the stored finest-N error
LABELS = {"a(F)": "max |a − a_Hertz(F)| / a_Hertz", "p(x)": "max rel. L2 of p(x) in contact"}


def bounds(subset):
    """{metric: FACTOR × the stored finest-N error} (verification/data/hertz.json, entry `subset`)."""
    errors, nodes = hz.measured_errors(subset)
    return {m: FACTOR[subset][m] * errors[m][-1] for m in MIN_ORDER}


def tolerance_source(subset):
    e = measured.entry(hz.NAME, subset)
    f = FACTOR[subset]
    return (f"{f['a(F)']:g}× / {f['p(x)']:g}× the N = {hz.NODES[subset][-1]} errors measured by "
            f"verification.studies.hertz (verification/data/hertz.json entry {subset!r}, {e['code_version']}, "
            f"{e['date']}); orders ≥ 1.2 / 0.6")


def _study(subset, verification_record, tag):
    nodes = np.array(hz.NODES[subset])
    st = hz.study(nodes)
    ac.print_orders(tag, "N", nodes, st["errors"], st["orders"])
    rows, fields = st["data"][-1][1], st["data"][-1][2]
    plots = [profile_plot(fields["x"], {"GFMD": fields["p"], "Hertz": fields["ph"]}, xlabel="x / a_Hertz",
                          ylabel="p / p0", title=f"pressure at the last load, N = {nodes[-1]}"),
             table_plot(["step", "F (N/m)", "a_H/L", "a_GFMD/L", "a_H/l", "err a", "err p L2"], rows,
                        title=f"per load, N = {nodes[-1]}")]
    ac.record_n_study(verification_record, case=CASE, methods=METHODS, nodes=nodes, length=hz.LENGTH,
                      errors=st["errors"], orders=st["orders"], labels=LABELS, bounds=bounds(subset),
                      min_order=MIN_ORDER, tolerance_source=tolerance_source(subset), wall=st["wall_s"],
                      plots=plots, resolution={"L/a": 200}, notes="R = L = 1 µm, a ≤ L/200, 4 loads")


def test_hertz_convergence(verification_record):
    _study("ci", verification_record, "CI")


@pytest.mark.slow
def test_hertz_convergence_fine(verification_record):
    _study("full", verification_record, "slow")
