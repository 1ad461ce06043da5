"""GFMD cohesive sinusoid vs Johnson's (1995) JKR-wavy solution (reference-formulas §4.3): errors vs δn.

Scene: `verification.scenes.sinusoid`, h = −h0 cos(2πx/λ), h0 = 10 nm, λ = L = 1 µm, half-plane
E = 70 GPa, ν = 0.45; exponential CZ law (normal only) with φn = w fixed so that Johnson's
α = √(2wλ/(π²h0²E*)) = 0.3. δn is lowered at fixed w: the cohesive-zone length
d = (πe²/4) E* δn²/w (reference-formulas §4.2) takes d/λ = 0.04, 0.02, 0.01, 0.005
(δn = 0.55, 0.39, 0.28, 0.20 nm). Displacement control, 8 steps from first touch to δ = 0.6 h0
(loading only: a/λ ≈ 0.13…0.24, p̄/p* ≈ −0.04…0.17), so pull-off is not measured. Contact half-width
from the gap, a = (nodes with Δn ≤ δn)·l/2 (the compressive region is much smaller, §4.3).

Errors (max over the 8 loads): |p̄ − p̄_J(a)|/p* and |ḡ − ḡ_J(a)|/h0; rate = least-squares slope of
log error vs log δn. The error is the finite-δn (cohesive-zone) error, not discretisation: compare
the N = 2048 ("ci") and N = 8192 ("full") entries.

    python -m verification.studies.jkr_sinusoid [--full] [--write]

`--write` stores the errors in verification/data/jkr_sinusoid.json (entry "ci": N = 2048, "full":
N = 8192), which test_analytic_jkr_sinusoid.py reads.

GFMD problem found (not measured here): at d/λ = 0.0025 (δn = 0.14 nm) and N = 8192 the FIRE cohesive
solver diverged at step 6 (Δn → −4e40 δn, "repulsive branch would overflow"), so δn stops at d/λ = 0.005.
"""

from __future__ import annotations

import argparse

import numpy as np

from reference.analytic import jkr_sinusoid as J
from reference.analytic import westergaard as W
from verification import analytic_cases as ac
from verification import measured
from verification.metrics import worst
from verification.scenes import sinusoid

NAME = "jkr_sinusoid"
H0 = 10e-9
LENGTH = 1e-6
ALPHA = 0.3
STEPS = 8
FINAL = 0.6 * H0
D_REL = (0.04, 0.02, 0.01, 0.005)
METRICS = ("p̄(a)", "ḡ(a)")
NODES = {"ci": 2048, "full": 8192}


def e_star():
    return sinusoid(64, H0, LENGTH).material.contact_modulus


def work():
    return ALPHA**2 * np.pi**2 * e_star() * H0**2 / (2 * LENGTH)


def delta_n(d_rel):
    """δn giving a cohesive-zone length d = d_rel·λ at the fixed w (m)."""
    return float(np.sqrt(d_rel * LENGTH * work() / ((np.pi * np.e**2 / 4) * e_star())))


def measure(nodes, d_rel):
    """(errors {metric: max over loads}, per-load rows, (a/λ, p̄/p*) curve, δn, wall s)."""
    w, dn, es = work(), delta_n(d_rel), e_star()
    scene = sinusoid(nodes, H0, LENGTH, law="cohesive", steps=STEPS, final=FINAL,
                     **{"interface.work_normal": w, "interface.length_normal": dn})
    result, wall = ac.run(scene)
    ps = W.full_contact_pressure(H0, LENGTH, es)
    rows, curve = [], []
    for k in range(1, STEPS + 1):
        x, p, gap, pbar, gbar = ac.step_fields(result, k)
        a = ac.half_width_gap(gap, dn, LENGTH / nodes)
        pj, gj = J.mean_pressure(a, H0, LENGTH, es, w), J.mean_gap(a, H0, LENGTH, es, w)
        rows.append([k, a / LENGTH, pbar / ps, pj / ps, gbar / H0, gj / H0, abs(pbar - pj) / ps, abs(gbar - gj) / H0])
        curve.append((a / LENGTH, pbar / ps))
    errs = {"p̄(a)": worst(r[6] for r in rows), "ḡ(a)": worst(r[7] for r in rows)}
    return errs, rows, curve, dn, wall


def study(nodes):
    """{"nodes", "d_rel", "delta_n", "data" (measure's output per d/λ), "errors" {metric: array}, "rates", "wall_s"}."""
    data, errors, wall = ac.convergence_study(lambda d: measure(nodes, d), D_REL, METRICS)
    dns = np.array([d[3] for d in data])
    rates = ac.orders_in(dns, errors)
    return {"nodes": int(nodes), "d_rel": list(D_REL), "delta_n": dns, "data": data, "errors": errors,
            "rates": rates, "wall_s": wall}


def entry(st, subset):
    return measured.make_entry({"N": st["nodes"], "d_over_lambda": st["d_rel"], "delta_n_m": list(st["delta_n"]),
                                "errors": {m: list(e) for m, e in st["errors"].items()}, "rates": st["rates"]},
                               scene=(f"verification.scenes.sinusoid({st['nodes']}, 10e-9, 1e-6, law='cohesive', "
                                      "steps=8, final=0.6 * 10e-9, w: α = 0.3, δn: d/λ)"),
                               subset=subset, wall_s=st["wall_s"])


def measured_errors(subset="ci"):
    """{metric: [error per d/λ]} and the d/λ list of the stored study (verification/data/jkr_sinusoid.json)."""
    values = measured.entry(NAME, subset)["values"]
    return values["errors"], values["d_over_lambda"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="N = 8192 (entry 'full'); default N = 2048 ('ci')")
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/jkr_sinusoid.json")
    args = ap.parse_args(argv)
    subset = "full" if args.full else "ci"
    st = study(NODES[subset])
    ac.print_orders(subset, "δn", st["delta_n"], st["errors"], st["rates"])
    print(f"{st['wall_s']:.1f} s")
    if args.write:
        print(measured.write(NAME, {subset: entry(st, subset)},
                             description="GFMD cohesive sinusoid vs Johnson JKR-wavy: max errors over 8 loads vs δn "
                                         "at fixed w (d/λ = 0.04 … 0.005), rates vs δn (least squares)"))


if __name__ == "__main__":
    main()
