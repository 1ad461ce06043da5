"""GFMD hard wall vs the Hertz sphere in a periodic square cell (2+1-D, `reference.analytic.hertz_sphere`): errors vs N.

Scene: `verification.scenes.sphere`, paraboloid h = (x² + y²)/(2R), R = 1 µm, square cell L = 1 µm of N × N nodes,
half-space E = 70 GPa, ν = 0.45, frictionless hard wall, FIRE/CG to 1e-10 × p_ref. Displacement control in 4 equal
steps to δ = a_max²/R with a_max = L/20 (a/L ≈ 0.025 … 0.05); δ is the tip penetration relative to the mean surface
(the half-space's q = 0 mode is clamped), which `hertz_sphere.approach_periodic` gives with the periodic
images (Epstein-zeta correction; the load P = p̄ L², one sphere per cell). Only the scene is shared.

Errors (max over the four loads):
* P(δ): |P_GFMD − P_ref(δ)|/P_ref(δ), P_ref the root of approach_periodic(P) = δ;
* a(P): |a_GFMD − a_H(P)|/a_H, a_GFMD = √(5⟨r²⟩_p/2), the pressure's second moment (exact for the Hertz
  p ∝ √(1 − r²/a²): ∫r²p dA/∫p dA = 2a²/5), free of the node-count quantisation;
* a_rel(P): |a_rel − πa_H²/L²|/(πa_H²/L²), a_rel the run's own contact fraction (nodes in contact / N²: first
  order in l/a, the contact line cuts the node lattice).

    python -m verification.studies.hertz_sphere_2d [--full] [--write]

N = 64 … 512 ("ci"), … 1024 ("full"); `--write` stores errors and observed orders in
verification/data/hertz_sphere_2d.json, which verification/test_analytic_hertz_sphere_2d.py reads.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy.optimize import brentq

from reference.analytic import hertz_sphere as HS
from verification import analytic_cases as ac
from verification.scenes import sphere

NAME = "hertz_sphere_2d"
RADIUS = 1e-6
LENGTH = 1e-6
STEPS = 4
A_MAX = LENGTH / 20
FINAL = A_MAX**2 / RADIUS
SCENE = "verification.scenes.sphere(N, 1e-6, 1e-6, steps=4, final=(L/20)²/R)"
DESCRIPTION = ("GFMD hard wall vs the periodic Hertz sphere (2+1-D): max errors over 4 loads of P(δ), a(P) (second "
               "moment) and a_rel(P) vs N, observed orders (least squares over the N of the entry)")
METRICS = ("P(δ)", "a(P)", "a_rel(P)")
NODES = {"ci": (64, 128, 256, 512), "full": (64, 128, 256, 512, 1024)}


def scene(nodes):
    return sphere(nodes, RADIUS, LENGTH, steps=STEPS, final=FINAL)


def reference_load(delta, e_star):
    """P (N) with approach_periodic(P) = δ (the periodic Hertz sphere, δ relative to the mean surface)."""
    hi = HS.load_from_approach(delta, RADIUS, e_star) * 2.0
    return brentq(lambda P: float(HS.approach_periodic(P, RADIUS, e_star, LENGTH)) - delta, 0.0, hi,
                  xtol=1e-30, rtol=1e-14)


def measure(nodes):
    """(errors {metric: max over loads}, per-load rows, last-load radial profile, wall s) at N × N nodes."""
    sc = scene(nodes)
    result, wall = ac.run(sc)
    e_star = sc.material.contact_modulus
    x, y = np.asarray(result.x), np.asarray(result.y)
    r2 = x[:, None] ** 2 + y[None, :] ** 2
    rows, errs = [], {m: [] for m in METRICS}
    for k in range(1, STEPS + 1):
        p = -np.asarray(result.fields[k]["t_n"], float)
        load = float(np.mean(p)) * LENGTH**2
        delta = float(result.curve["delta"][k])
        p_ref = reference_load(delta, e_star)
        a_h = float(HS.contact_radius(load, RADIUS, e_star))
        a = float(np.sqrt(2.5 * np.sum(r2 * p) / np.sum(p)))
        a_rel, a_rel_h = float(result.curve["a_rel"][k]), float(HS.contact_fraction(load, RADIUS, e_star, LENGTH, LENGTH))
        e = {"P(δ)": abs(load - p_ref) / p_ref, "a(P)": abs(a - a_h) / a_h, "a_rel(P)": abs(a_rel - a_rel_h) / a_rel_h}
        for m in METRICS:
            errs[m].append(e[m])
        rows.append([k, delta, load, p_ref, a_h / LENGTH, a / LENGTH, a_h * nodes / LENGTH, *e.values()])
    p = -np.asarray(result.fields[STEPS]["t_n"], float)
    load = float(np.mean(p)) * LENGTH**2
    a_h = float(HS.contact_radius(load, RADIUS, e_star))
    r = np.sqrt(r2).ravel()
    near = r <= 1.5 * a_h
    order = np.argsort(r[near])
    ph = np.asarray(HS.pressure(r[near][order], load, RADIUS, e_star))
    fields = dict(x=r[near][order] / a_h, p=p.ravel()[near][order] / ph.max(), ph=ph / ph.max())
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
