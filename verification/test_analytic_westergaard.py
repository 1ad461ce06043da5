"""GFMD hard wall vs Westergaard's periodic sinusoid (reference-formulas §3): convergence in N.

Study, scene and metrics: `verification.studies.westergaard`; its measured errors are in
verification/data/westergaard.json (regenerate: `python -m verification.studies.westergaard --write`,
with `--full` for N up to 8192).

Tolerances:
* observed orders p̄(ḡ) ≥ 1.5, a ≥ 0.7, p(x) ≥ 0.7: the expected orders 2 (√-singular edge
  integrated), 1 (node-count edge), ~1 (pointwise edge error) minus the scatter of the contact
  edge crossing grid nodes (neighbouring N differ by up to 4× at a fixed order);
* finest-N errors (CI, N = 1024): 3× the stored N = 1024 errors; --full (N = 8192): those bounds
  divided by the gain expected over 8× in N with room for the edge scatter (2nd order /15, 1st
  order /4 and /6). An O(1)-wrong solution (e.g. a factor 2 in E*) exceeds them by orders of magnitude.
"""

from __future__ import annotations

import numpy as np
import pytest

from verification import analytic_cases as ac
from verification import measured
from verification.plots import profile_plot, table_plot
from verification.studies import westergaard as wg

METHODS = ("gfmd-fire", "analytic-westergaard")
CASE = "analytic/westergaard-hard-wall-sinusoid"
MIN_ORDER = {"p̄(ḡ)": 1.5, "a": 0.7, "p(x)": 0.7}
FACTOR = 3.0  # finest-N bound = FACTOR × the error measured at N = 1024
FINE_GAIN = {"p̄(ḡ)": 15.0, "a": 4.0, "p(x)": 6.0}  # expected error gain N = 1024 → 8192, with scatter room
LABELS = {"p̄(ḡ)": "max |p̄ − p̄_W(ḡ)| / p*", "a": "max |a − a_W(p̄)| / λ", "p(x)": "max rel. L2 of p(x) in contact"}


def bounds_1024():
    """{metric: FACTOR × the stored N = 1024 error} (verification/data/westergaard.json, entry "ci")."""
    errors, nodes = wg.measured_errors("ci")
    i = nodes.index(1024)
    return {m: FACTOR * errors[m][i] for m in MIN_ORDER}


def tolerance_source():
    e = measured.entry(wg.NAME, "ci")
    return (f"{FACTOR:g}× the N = 1024 errors measured by verification.studies.westergaard "
            f"(verification/data/westergaard.json, {e['code_version']}, {e['date']}); --full: divided by "
            f"{FINE_GAIN['p̄(ḡ)']:g} / {FINE_GAIN['a']:g} / {FINE_GAIN['p(x)']:g} for N = 8192; "
            "orders ≥ 1.5 / 0.7 / 0.7")


def _study(nodes, verification_record, bounds, tag):
    st = wg.study(nodes)
    ac.print_orders(tag, "N", nodes, st["errors"], st["orders"])
    rows, fields = st["data"][-1][1], st["data"][-1][2]
    plots = [profile_plot(fields["x"] * 1e6, {"GFMD": fields["p"] / fields["ps"],
                                              "Westergaard": fields["pw"] / fields["ps"]}, xlabel="x (µm)",
                          ylabel="p / p*", title=f"pressure at p̄/p* = {fields['P']:.3f}, N = {nodes[-1]}"),
             table_plot(["step", "p̄/p*", "ḡ/h0", "a/λ GFMD", "a/λ Westergaard", "err p̄(ḡ)/p*", "err a/λ",
                         "p(x) rel. L2"], rows, title=f"per load, N = {nodes[-1]}")]
    ac.record_n_study(verification_record, case=CASE, methods=METHODS, nodes=nodes, length=wg.LENGTH,
                      errors=st["errors"], orders=st["orders"], labels=LABELS, bounds=bounds, min_order=MIN_ORDER,
                      tolerance_source=tolerance_source(), wall=st["wall_s"], plots=plots,
                      notes=f"h0 = 10 nm, λ = 1 µm, hard wall, 6 loads to δ = 0.995 h0 (P up to {rows[-1][1]:.2f})")


def test_westergaard_convergence(verification_record):
    _study(np.array(wg.NODES["ci"]), verification_record, bounds_1024(), "CI")


@pytest.mark.slow
def test_westergaard_convergence_fine(verification_record):
    _study(np.array(wg.NODES["full"]), verification_record,
           {m: b / FINE_GAIN[m] for m, b in bounds_1024().items()}, "slow")
