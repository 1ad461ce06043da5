"""GFMD 2+1-D hard wall vs the periodic Hertz sphere (`reference.analytic.hertz_sphere`): convergence in N.

Study, scene and metrics: `verification.studies.hertz_sphere_2d` (R = L = 1 µm, a ≤ L/20, 4 loads; P(δ) against
approach_periodic, a(P) from the pressure's second moment, a_rel(P) the run's own contact fraction); its errors
and orders are in verification/data/hertz_sphere_2d.json (regenerate: `python -m verification.studies.
hertz_sphere_2d --write`, `--full` for N up to 1024).

Tolerances (the rule; the numbers are the stored study's):
* observed orders: P(δ), a(P) ≥ 1.5 (expected 2: second-order kernel and moment, until the image remainder
  O((a/L)³) ≈ 1e-4 of the reference is met), a_rel ≥ 0.7 (expected 1: the contact line cuts the node lattice);
* finest-N error ≤ stored finest-N error + the stored last successive difference |e(N/2) − e(N)| (one N-doubling of
  discretization error at that level: the re-run of the same N may differ by round-off only, so this is generous
  by ≥ 10× against round-off and ≥ 10× tighter than a factor 2 in E* or R, which moves P(δ) by 50%).
"""

from __future__ import annotations

import numpy as np
import pytest

from verification import analytic_cases as ac
from verification import measured
from verification.plots import profile_plot, table_plot
from verification.studies import hertz_sphere_2d as hs

METHODS = ("gfmd", "analytic-hertz-sphere")
CASE = "analytic/hertz-hard-wall-sphere-2d"
MIN_ORDER = {"P(δ)": 1.5, "a(P)": 1.5, "a_rel(P)": 0.7}
LABELS = {"P(δ)": "max |P − P_ref(δ)|/P_ref (periodic Hertz)", "a(P)": "max |a − a_H(P)|/a_H (second moment)",
          "a_rel(P)": "max |a_rel − πa_H²/L²|/(πa_H²/L²)"}


def bounds(subset):
    """{metric: stored finest-N error + stored last successive difference}."""
    errors, _ = hs.measured_errors(subset)
    return {m: errors[m][-1] + abs(errors[m][-2] - errors[m][-1]) for m in MIN_ORDER}


def tolerance_source(subset):
    e = measured.entry(hs.NAME, subset)
    return (f"verification/data/hertz_sphere_2d.json entry {subset!r} ({e['code_version']}, {e['date']}): stored "
            f"N = {hs.NODES[subset][-1]} error + its last successive difference; orders ≥ 1.5 / 1.5 / 0.7")


def _study(subset, verification_record, tag):
    nodes = np.array(hs.NODES[subset])
    st = hs.study(nodes)
    ac.print_orders(tag, "N", nodes, st["errors"], st["orders"])
    rows, fields = st["data"][-1][1], st["data"][-1][2]
    plots = [profile_plot(fields["x"], {"GFMD (nodes)": fields["p"], "Hertz": fields["ph"]}, xlabel="r / a_Hertz",
                          ylabel="p / p0", title=f"pressure vs r at the last load, N = {nodes[-1]}²"),
             table_plot(["step", "δ (m)", "P (N)", "P_ref(δ) (N)", "a_H/L", "a/L", "a_H/l", "err P", "err a",
                         "err a_rel"], rows, title=f"per load, N = {nodes[-1]}²")]
    ac.record_n_study(verification_record, case=CASE, methods=METHODS, nodes=nodes, length=hs.LENGTH,
                      errors=st["errors"], orders=st["orders"], labels=LABELS, bounds=bounds(subset),
                      min_order=MIN_ORDER, tolerance_source=tolerance_source(subset), wall=st["wall_s"],
                      plots=plots, resolution={"L/a": 20, "dimension": "2+1-D"},
                      notes="R = L = 1 µm, a ≤ L/20, 4 loads, N × N nodes")


def test_hertz_sphere_convergence(verification_record):
    _study("ci", verification_record, "CI")


@pytest.mark.slow
def test_hertz_sphere_convergence_fine(verification_record):
    _study("full", verification_record, "slow")
