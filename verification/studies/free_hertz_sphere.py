"""GFMD hard wall on a free half-space (`surface.boundary = "free"`) vs the Hertz sphere without images: errors vs N.

Scene: `verification.scenes.sphere` with surface.boundary = "free": paraboloid h = (x² + y²)/(2R), R = 1 µm, square
region L = 1 µm of N × N nodes (padded to 2N × 2N), half-space E = 70 GPa, ν = 0.45, frictionless hard wall,
displacement control in 4 equal steps to δ = a_max²/R, a_max = L/8. The reference is the exact free Hertz solution
(`reference.analytic.hertz_sphere`, no images) at the load the run carried (P = p̄ L²).

Errors (max over the four loads):
* P(δ): |P − P_H(δ − s)|/P_H, δ − s the approach from the far field (s: the padded cell's far-field shift,
  Result.diagnostics["far_field_shift"], `gfmd_contact.core.free_boundary`): checks the shift too;
* a(P): |a − a_H|/a_H, a = √(5⟨r²⟩_p/2), the pressure's second moment;
* a_count(P): |a_n − a_H|/a_H, a_n = √(n l²/π) from the n nodes in compression (first order).

    python -m verification.studies.free_hertz_sphere [--full] [--write]

N = 16 … 128 ("ci"), … 256 ("full"); `--write` stores errors and observed orders in
verification/data/free_hertz_sphere.json, which verification/test_free_boundary_hertz.py reads.
"""

from __future__ import annotations

import sys

import numpy as np

from reference.analytic import hertz_sphere as HS
from verification import analytic_cases as ac
from verification.scenes import sphere

NAME = "free_hertz_sphere"
RADIUS = 1e-6
LENGTH = 1e-6
STEPS = 4
A_MAX = LENGTH / 8
FINAL = A_MAX**2 / RADIUS
SCENE = "verification.scenes.sphere(N, 1e-6, 1e-6, steps=4, final=(L/8)²/R, surface.boundary='free')"
DESCRIPTION = ("GFMD hard wall on a free half-space vs the Hertz sphere without images (2+1-D): max errors over 4 "
               "loads of P(δ − s) (far-field approach), a(P) (second moment), a_count(P) vs N, observed orders")
METRICS = ("P(δ)", "a(P)", "a_count(P)")
NODES = {"ci": (16, 32, 64, 128), "full": (16, 32, 64, 128, 256)}


def scene(nodes):
    return sphere(nodes, RADIUS, LENGTH, steps=STEPS, final=FINAL, **{"surface.boundary": "free"})


def measure(nodes):
    """(errors {metric: max over loads}, per-load rows, last-load radial profile, wall s) at N × N nodes."""
    sc = scene(nodes)
    result, wall = ac.run(sc)
    e_star = sc.material.contact_modulus
    x, y = np.asarray(result.x), np.asarray(result.y)
    r2 = x[:, None] ** 2 + y[None, :] ** 2
    cell = (LENGTH / nodes) ** 2
    rows, errs = [], {m: [] for m in METRICS}
    for k in range(1, STEPS + 1):
        p = -np.asarray(result.fields[k]["t_n"], float)
        load = float(np.sum(p)) * cell
        delta = float(result.curve["delta"][k]) - float(result.diagnostics["far_field_shift"][k])
        p_ref = float(HS.load_from_approach(delta, RADIUS, e_star))
        a_h = float(HS.contact_radius(load, RADIUS, e_star))
        a = float(np.sqrt(2.5 * np.sum(r2 * p) / np.sum(p)))
        a_n = float(np.sqrt(np.count_nonzero(p > 0) * cell / np.pi))
        e = {"P(δ)": abs(load - p_ref) / p_ref, "a(P)": abs(a - a_h) / a_h, "a_count(P)": abs(a_n - a_h) / a_h}
        for m in METRICS:
            errs[m].append(e[m])
        rows.append([k, delta, load, p_ref, a_h / LENGTH, a_h * nodes / LENGTH, *e.values()])
    p = -np.asarray(result.fields[STEPS]["t_n"], float)
    load = float(np.sum(p)) * cell
    a_h = float(HS.contact_radius(load, RADIUS, e_star))
    r = np.sqrt(r2).ravel()
    near = r <= 1.5 * a_h
    order = np.argsort(r[near])
    ph = np.asarray(HS.pressure(r[near][order], load, RADIUS, e_star))
    fields = {"x": r[near][order] / a_h, "p": p.ravel()[near][order] / ph.max(), "ph": ph / ph.max()}
    return {m: max(v) for m, v in errs.items()}, rows, fields, wall


def study(nodes):
    """{"nodes", "data", "errors" {metric: array over N}, "orders", "wall_s"}."""
    return ac.n_study(sys.modules[__name__], nodes)


def measured_errors(subset="ci"):
    """{metric: [error per N]} and the N list of the stored study."""
    return ac.stored_errors(NAME, subset)


def main(argv=None):
    ac.n_study_main(sys.modules[__name__], argv)


if __name__ == "__main__":
    main()
