"""GFMD cohesive sinusoid vs Johnson's (1995) JKR-wavy solution (reference-formulas §4.3): convergence in δn.

Study, scene and metrics: `verification.studies.jkr_sinusoid` (α = 0.3, δn lowered at fixed w so that
d/λ = 0.04 … 0.005; loading branch only, so pull-off is not tested); its measured errors and rates are
in verification/data/jkr_sinusoid.json (regenerate: `python -m verification.studies.jkr_sinusoid --write`
for N = 2048, with `--full` for N = 8192).

Tolerances: rate vs δn ≥ 0.8 (ḡ) and ≥ 0.6 (p̄) (the measured rates minus margin for the a
quantisation by l); smallest-δn errors ≤ 2× the stored smallest-δn errors at the same N (entry "ci"
for N = 2048, "full" for N = 8192). Failure of w = φn as the JKR input (e.g. a factor 2 in w) would
change p̄ by ≈ α√tan(πa/λ) ~ 0.1 p*, tens of times the bound.
"""

from __future__ import annotations

import numpy as np
import pytest

from reference.analytic import jkr_sinusoid as J
from reference.analytic import westergaard as W
from verification import analytic_cases as ac
from verification import measured
from verification.plots import convergence_plot, curve_plot, table_plot
from verification.studies import jkr_sinusoid as js

METHODS = ("gfmd-fire", "analytic-jkr-sinusoid")
CASE = "analytic/jkr-wavy-cohesive-sinusoid"
FACTOR = 2.0  # smallest-δn bound = FACTOR × the stored smallest-δn error at the same N
MIN_RATE = {"p̄(a)": 0.6, "ḡ(a)": 0.8}
LABELS = {"p̄(a)": "max |p̄ − p̄_Johnson(a)| / p*", "ḡ(a)": "max |ḡ − ḡ_Johnson(a)| / h0"}


def bounds(subset):
    """{metric: FACTOR × the stored error at the smallest δn} (verification/data/jkr_sinusoid.json)."""
    errors, d_rel = js.measured_errors(subset)
    return {m: FACTOR * errors[m][-1] for m in MIN_RATE}


def tolerance_source(subset):
    e = measured.entry(js.NAME, subset)
    return (f"{FACTOR:g}× the error at d/λ = {js.D_REL[-1]}, N = {js.NODES[subset]} measured by "
            f"verification.studies.jkr_sinusoid (verification/data/jkr_sinusoid.json entry {subset!r}, "
            f"{e['code_version']}, {e['date']}); rates vs δn ≥ 0.6 (p̄) / 0.8 (ḡ)")


def _study(subset, verification_record, tag):
    nodes, bound = js.NODES[subset], bounds(subset)
    st = js.study(nodes)
    data, errors, dns, rates, wall = st["data"], st["errors"], st["delta_n"], st["rates"], st["wall_s"]
    ac.print_orders(tag, "δn", dns, errors, rates)
    e_star, w, LENGTH, H0, D_REL = js.e_star(), js.work(), js.LENGTH, js.H0, js.D_REL
    a_fine = np.linspace(0.1, 0.3, 81)
    pj_curve = [J.mean_pressure(a * LENGTH, H0, LENGTH, e_star, w) / W.full_contact_pressure(H0, LENGTH, e_star)
                for a in a_fine]
    records = []
    for m in MIN_RATE:
        series = {f"GFMD d/λ = {d}": data[i][2] for i, d in enumerate(D_REL)}
        plots = [
            curve_plot(list(a_fine), {"Johnson (1995)": pj_curve}, xlabel="a / λ", ylabel="p̄ / p*",
                       title="Johnson's p̄(a) (loading branch); GFMD points in the table"),
            table_plot(["d/λ", "a/λ", "p̄/p* GFMD"], [[d, a, p] for d, c in zip(D_REL, series.values()) for a, p in c],
                       title=f"GFMD p̄(a), N = {nodes}"),
            convergence_plot(list(dns), list(errors[m]), order=rates[m], xlabel="δn (m) at fixed w",
                             ylabel=LABELS[m], title=f"{m}: error vs δn (rate {rates[m]:.2f})"),
            table_plot(["step", "a/λ", "p̄/p* GFMD", "p̄/p* Johnson", "ḡ/h0 GFMD", "ḡ/h0 Johnson",
                        "err p̄", "err ḡ"], data[-1][1], title=f"per load, smallest δn, N = {nodes}"),
        ]
        rec = verification_record(
            case=CASE, metric=f"{LABELS[m]} at d/λ = {D_REL[-1]}", value=float(errors[m][-1]), tolerance=bound[m],
            methods=METHODS, tolerance_source=tolerance_source(subset),
            resolution={"N": int(nodes), "delta_n_m": [float(v) for v in dns], "d_over_lambda": list(D_REL),
                        "rate_in_delta_n": rates[m], "min_rate": MIN_RATE[m]},
            wall_s=wall, plots=plots,
            notes=(f"α = {js.ALPHA}, loading branch only (no pull-off: the ramp only loads); a from Δn ≤ δn; "
                   f"error rate vs δn {rates[m]:.2f} (asserted ≥ {MIN_RATE[m]})"))
        records.append((m, rec))
    ac.assert_study(records, rates, MIN_RATE, errors)


def test_jkr_wavy_delta_n_convergence(verification_record):
    _study("ci", verification_record, "CI")


@pytest.mark.slow
def test_jkr_wavy_delta_n_convergence_fine(verification_record):
    _study("full", verification_record, "slow")
