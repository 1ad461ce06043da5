"""GFMD cohesive sinusoid vs Johnson's (1995) JKR-wavy solution (reference-formulas §4.3).

Scene: h = −h0 cos(2πx/λ), h0 = 10 nm, λ = L = 1 µm, E = 70 GPa, ν = 0.45
half-plane; exponential CZ law (normal only) with φn = w fixed so that Johnson's
α = √(2wλ/(π²h0²E*)) = 0.3. δn is lowered at fixed w: the cohesive-zone length
d = (πe²/4) E* δn²/w (reference-formulas §4.2) takes d/λ = 0.04, 0.02, 0.01, 0.005
(δn = 0.55, 0.39, 0.28, 0.20 nm). Displacement control, 8 steps from first touch
to δ = 0.6 h0 (loading only: a/λ ≈ 0.13…0.24, p̄/p* ≈ −0.04…0.17).

The ramp only loads, so pull-off (the minimum of p̄ under unloading) is NOT
tested; the loading branch p̄(a) and ḡ(a) are. Contact half-width from the gap,
a = (nodes with Δn ≤ δn)·l/2 (the compressive region is much smaller, §4.3).

Metrics (max over the 8 loads): |p̄ − p̄_J(a)|/p* and |ḡ − ḡ_J(a)|/h0.

Convergence study in δn (measured when the tolerances were set):

    d/λ                0.04     0.02     0.01     0.005
    N = 2048 (CI) p̄   3.3e-3   2.7e-3   2.1e-3   1.2e-3
                  ḡ   1.5e-2   1.1e-2   7.5e-3   4.1e-3
    N = 8192      p̄   3.3e-3   2.6e-3   1.7e-3   8.8e-4
                  ḡ   1.5e-2   1.1e-2   6.5e-3   3.6e-3

The N = 2048 and 8192 rows agree to ≲ 30%: the error is the finite-δn
(cohesive-zone) error, not discretisation. Observed rate vs δn: ḡ ≈ δn^1.25,
p̄ ≈ δn^1.0 (≈ d^0.6 and d^0.5).

Tolerances: rate vs δn ≥ 0.8 (ḡ) and ≥ 0.6 (p̄) (measured 1.25 / 0.97, minus
margin for the a quantisation by l); smallest-δn errors ≤ 2× the N = 2048 values
(8e-3 h0, 2.5e-3 p*). Failure of w = φn as the JKR input (e.g. a factor 2 in w)
would change p̄ by ≈ α√tan(πa/λ) ~ 0.1 p*, 40× the bound.

GFMD PROBLEM found (reported, not tested): at d/λ = 0.0025 (δn = 0.14 nm) and
N = 8192 the FIRE cohesive solver diverges at step 6 (Δn → −4e40 δn,
"repulsive branch would overflow"); so δn is not taken lower here.
"""

from __future__ import annotations


import numpy as np
import pytest

from reference.analytic import jkr_sinusoid as J
from reference.analytic import westergaard as W
from verification import analytic_cases as ac
from verification.plots import convergence_plot, curve_plot, table_plot
from verification.scenes import sinusoid

H0 = 10e-9
LENGTH = 1e-6
ALPHA = 0.3
STEPS = 8
FINAL = 0.6 * H0
D_REL = (0.04, 0.02, 0.01, 0.005)
METHODS = ("gfmd-fire", "analytic-jkr-sinusoid")
CASE = "analytic/jkr-wavy-cohesive-sinusoid"
TOL_SOURCE = ("δn-convergence study in verification/test_analytic_jkr_sinusoid.py docstring: ḡ error ∝ δn^1.25, "
              "p̄ error ∝ δn^1.0; bound = 2× the error at the smallest δn (d/λ = 0.005), N = 2048")
MIN_RATE = {"p̄(a)": 0.6, "ḡ(a)": 0.8}
LABELS = {"p̄(a)": "max |p̄ − p̄_Johnson(a)| / p*", "ḡ(a)": "max |ḡ − ḡ_Johnson(a)| / h0"}


def _e_star():
    return sinusoid(64, H0, LENGTH).material.contact_modulus


def work():
    return ALPHA**2 * np.pi**2 * _e_star() * H0**2 / (2 * LENGTH)


def delta_n(d_rel):
    """δn giving a cohesive-zone length d = d_rel·λ at the fixed w (m)."""
    return float(np.sqrt(d_rel * LENGTH * work() / ((np.pi * np.e**2 / 4) * _e_star())))


def measure(nodes, d_rel):
    w, dn, e_star = work(), delta_n(d_rel), _e_star()
    scene = sinusoid(nodes, H0, LENGTH, law="cohesive", steps=STEPS, final=FINAL,
                              **{"interface.work_normal": w, "interface.length_normal": dn})
    result, wall = ac.run(scene)
    ps = W.full_contact_pressure(H0, LENGTH, e_star)
    rows, curve = [], []
    for k in range(1, STEPS + 1):
        x, p, gap, pbar, gbar = ac.step_fields(result, k)
        a = ac.half_width_gap(gap, dn, LENGTH / nodes)
        pj, gj = J.mean_pressure(a, H0, LENGTH, e_star, w), J.mean_gap(a, H0, LENGTH, e_star, w)
        rows.append([k, a / LENGTH, pbar / ps, pj / ps, gbar / H0, gj / H0, abs(pbar - pj) / ps, abs(gbar - gj) / H0])
        curve.append((a / LENGTH, pbar / ps))
    errs = {"p̄(a)": max(r[6] for r in rows), "ḡ(a)": max(r[7] for r in rows)}
    return errs, rows, curve, dn, wall


def _study(nodes, verification_record, bound, tag):
    data, errors, wall = ac.convergence_study(lambda d: measure(nodes, d), D_REL, MIN_RATE)
    dns = np.array([d[3] for d in data])
    rates = ac.orders_in(dns, errors)
    ac.print_orders(tag, "δn", dns, errors, rates)
    e_star, w = _e_star(), work()
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
            methods=METHODS, tolerance_source=TOL_SOURCE,
            resolution={"N": int(nodes), "delta_n_m": [float(v) for v in dns], "d_over_lambda": list(D_REL),
                        "rate_in_delta_n": rates[m], "min_rate": MIN_RATE[m]},
            wall_s=wall, plots=plots,
            notes=(f"α = {ALPHA}, loading branch only (no pull-off: the ramp only loads); a from Δn ≤ δn; "
                   f"error rate vs δn {rates[m]:.2f} (asserted ≥ {MIN_RATE[m]})"))
        records.append((m, rec))
    ac.assert_study(records, rates, MIN_RATE, errors)


def test_jkr_wavy_delta_n_convergence(verification_record):
    _study(2048, verification_record, {"p̄(a)": 2.5e-3, "ḡ(a)": 8e-3}, "CI")


@pytest.mark.slow
def test_jkr_wavy_delta_n_convergence_fine(verification_record):
    # N = 8192 measured 8.8e-4 p* / 3.6e-3 h0 at d/λ = 0.005; bounds 2×
    _study(8192, verification_record, {"p̄(a)": 1.8e-3, "ḡ(a)": 7.2e-3}, "slow")
