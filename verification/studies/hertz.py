"""GFMD hard wall vs Hertz line contact (reference-formulas §2) in a large periodic cell: errors vs N.

Scene: `verification.scenes.cylinder`, parabolic cylinder h = x²/(2R), R = 1 µm, cell L = 1 µm,
half-plane E = 70 GPa, ν = 0.45, frictionless hard wall, solver tolerance 1e-10. Displacement control
in 4 steps to the tip penetration δ of §2.2 for a = L/200, so a/L ≈ 0.0023, 0.0034, 0.0043, 0.0050
(L ≥ 200a: the periodic images change a(F) by ≈ 0.8 (a/L)² ≤ 2e-5).

Errors (max over the four loads), F = p̄ L:
* a(F): |a_GFMD − a_H(F)|/a_H, a_GFMD = 2√(Σx²p/Σp) (second moment of the pressure; exact for the
  elliptic Hertz pressure, no node-count quantisation);
* p(x): ‖p − p_H‖₂/‖p_H‖₂ over the nodes inside the Hertz contact.

    python -m verification.studies.hertz [--full] [--write]

prints the errors and observed orders at N = 2048 … 16384 (`--full`: … 65536); `--write` stores them
in verification/data/hertz.json (entry "ci" or "full"), which test_analytic_hertz.py reads.
"""

from __future__ import annotations

import sys

import numpy as np

from reference.analytic import hertz as H
from verification import analytic_cases as ac
from verification.metrics import relative_l2, worst
from verification.scenes import cylinder

NAME = "hertz"
SCENE = "verification.scenes.cylinder(N, 1e-6, 1e-6, steps=4, final=δ(a = L/200))"
DESCRIPTION = ("GFMD hard wall vs Hertz line contact: max errors over 4 loads vs N, observed orders "
               "(least squares over the N of the entry)")
RADIUS = 1e-6
LENGTH = 1e-6
STEPS = 4
A_MAX = LENGTH / 200
FINAL = A_MAX**2 / (4 * RADIUS) * (2 * np.log(LENGTH / (np.pi * A_MAX)) + 1)  # §2.2 δ_rel at a = A_MAX
METRICS = ("a(F)", "p(x)")
NODES = {"ci": (2048, 4096, 8192, 16384), "full": (2048, 4096, 8192, 16384, 32768, 65536)}


def scene(nodes):
    return cylinder(nodes, RADIUS, LENGTH, steps=STEPS, final=FINAL)


def measure(nodes):
    """(errors {metric: max over loads}, per-load table rows, last-load fields, wall s) at N = nodes."""
    sc = scene(nodes)
    result, wall = ac.run(sc)
    e_star = sc.material.contact_modulus
    rows, errs = [], {m: [] for m in METRICS}
    for k in range(1, STEPS + 1):
        x, p, gap, pbar, gbar = ac.step_fields(result, k)
        load = pbar * LENGTH
        a_h = H.half_width(load, RADIUS, e_star)
        a = ac.half_width_second_moment(x, p)
        ph = H.pressure(x, load, RADIUS, e_star)
        inside = ph > 0
        e_a, e_p = abs(a - a_h) / a_h, relative_l2(ph[inside], p[inside])
        errs["a(F)"].append(e_a)
        errs["p(x)"].append(e_p)
        rows.append([k, load, a_h / LENGTH, a / LENGTH, a_h / (LENGTH / nodes), e_a, e_p])
    x, p, gap, pbar, gbar = ac.step_fields(result, STEPS)
    ph = H.pressure(x, pbar * LENGTH, RADIUS, e_star)
    a_h = H.half_width(pbar * LENGTH, RADIUS, e_star)
    near = np.abs(x) <= 1.5 * a_h
    fields = dict(x=x[near] / a_h, p=p[near] / ph.max(), ph=ph[near] / ph.max())
    return {m: worst(v) for m, v in errs.items()}, rows, fields, wall


def study(nodes):
    """{"nodes", "data" (measure's output per N), "errors" {metric: array over N}, "orders", "wall_s"}."""
    return ac.n_study(sys.modules[__name__], nodes)


def measured_errors(subset="ci"):
    """{metric: [error per N]} and the N list of the stored study (verification/data/hertz.json)."""
    return ac.stored_errors(NAME, subset)


def main(argv=None):
    ac.n_study_main(sys.modules[__name__], argv)


if __name__ == "__main__":
    main()
