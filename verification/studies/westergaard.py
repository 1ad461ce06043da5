"""GFMD hard wall vs Westergaard's periodic sinusoid (reference-formulas §3): errors vs N.

Scene: `verification.scenes.sinusoid`, h0 = 10 nm, λ = L = 1 µm, half-plane E = 70 GPa, ν = 0.45,
hard wall, solver tolerance 1e-10; 6 steps from first touch to δ = 0.995 h0 (P = p̄/p* ≈ 0.04 … 0.85).

Errors (max over the six loads): |p̄ − p̄_W(ḡ)|/p* (p̄_W the exact inverse of ḡ = h0[1 − P + P ln P]);
|a − a_W(p̄)|/λ (a = compressive nodes·l/2); ‖p − p_W‖₂/‖p_W‖₂ over the nodes inside the exact contact.

    python -m verification.studies.westergaard [--full] [--write]

prints the errors and observed orders at N = 64 … 1024 (`--full`: … 8192); `--write` stores them in
verification/data/westergaard.json (entry "ci" or "full"), which test_analytic_westergaard.py reads.
"""

from __future__ import annotations

import sys

from scipy.optimize import brentq

from reference.analytic import westergaard as W
from verification import analytic_cases as ac
from verification.metrics import relative_l2, worst
from verification.scenes import sinusoid

NAME = "westergaard"
SCENE = "verification.scenes.sinusoid(N, 10e-9, 1e-6, steps=6, final=0.995 * 10e-9)"
DESCRIPTION = ("GFMD hard wall vs Westergaard: max errors over 6 loads vs N, observed orders "
               "(least squares over the N of the entry)")
H0 = 10e-9
LENGTH = 1e-6
STEPS = 6
FINAL = 0.995 * H0
METRICS = ("p̄(ḡ)", "a", "p(x)")
NODES = {"ci": (64, 128, 256, 512, 1024), "full": (64, 128, 256, 512, 1024, 2048, 4096, 8192)}


def scene(nodes):
    return sinusoid(nodes, H0, LENGTH, steps=STEPS, final=FINAL)


def _pressure_at_mean_gap(gbar, ps, e_star):
    return ps * brentq(lambda P: W.mean_gap(P * ps, H0, LENGTH, e_star) - gbar, 1e-300, 1 - 1e-15,
                       xtol=1e-300, rtol=1e-15)


def measure(nodes):
    """(errors {metric: max over loads}, per-load table rows, mid-ramp fields, wall s) at N = nodes."""
    sc = scene(nodes)
    result, wall = ac.run(sc)
    e_star = sc.material.contact_modulus
    ps = W.full_contact_pressure(H0, LENGTH, e_star)
    spacing = LENGTH / nodes
    rows, errs = [], {m: [] for m in METRICS}
    for k in range(1, STEPS + 1):
        x, p, gap, pbar, gbar = ac.step_fields(result, k)
        pw = W.pressure(x, pbar, H0, LENGTH, e_star)
        inside = pw > 0
        e_p = abs(pbar - _pressure_at_mean_gap(gbar, ps, e_star)) / ps
        a = ac.half_width_compressive(p, spacing)
        a_w = W.half_width(pbar, H0, LENGTH, e_star)
        e_a = abs(a - a_w) / LENGTH
        e_l2 = relative_l2(pw[inside], p[inside])
        for m, e in zip(METRICS, (e_p, e_a, e_l2)):
            errs[m].append(e)
        rows.append([k, pbar / ps, gbar / H0, a / LENGTH, a_w / LENGTH, e_p, e_a, e_l2])
    x, p, gap, pbar, gbar = ac.step_fields(result, STEPS // 2)
    fields = dict(x=x, p=p, pw=W.pressure(x, pbar, H0, LENGTH, e_star), ps=ps, P=pbar / ps)
    return {m: worst(v) for m, v in errs.items()}, rows, fields, wall


def study(nodes):
    """{"nodes", "data" (measure's output per N), "errors" {metric: array over N}, "orders", "wall_s"}."""
    return ac.n_study(sys.modules[__name__], nodes)


def measured_errors(subset="ci"):
    """{metric: [error per N]} and the N list of the stored study (verification/data/westergaard.json)."""
    return ac.stored_errors(NAME, subset)


def main(argv=None):
    ac.n_study_main(sys.modules[__name__], argv)


if __name__ == "__main__":
    main()
