"""GFMD hard wall on a free half-plane (`surface.boundary = "free"`) vs the Hertz cylinder without images: errors vs N.

Scene: `verification.scenes.cylinder` with surface.boundary = "free": h = x²/(2R), R = 1 µm, region L = 1 µm of
N nodes (padded to 2N), half-plane E = 70 GPa, ν = 0.45, frictionless hard wall, force control in 4 equal load
steps to the line load of the Hertz half-width a_max = L/8 (p̄ = F/L over the region). The reference is the
exact free-surface Hertz solution (`reference.analytic.hertz`) at the load the run carried (F = p̄ L), with no
periodic images: the padded cell is exact for the free body, so the errors are discretisation only.

Errors (max over the four loads):
* p(x): rms over the region of (p − p_H)/p0 (p0 the Hertz peak pressure);
* a(P): |a − a_H|/a_H, a = 2√(Σx²p/Σp) the pressure's second moment (exact for the elliptic pressure);
* a_count(P): |a_n − a_H|/a_H, a_n = (nodes in compression)·l/2 (first order: the edge cuts the lattice).

    python -m verification.studies.free_hertz_cylinder [--full] [--write]

N = 64 … 512 ("ci"), … 2048 ("full"); `--write` stores errors and observed orders in
verification/data/free_hertz_cylinder.json, which verification/test_free_boundary_hertz.py reads.
"""

from __future__ import annotations

import sys

import numpy as np

from reference.analytic import hertz as H
from verification import analytic_cases as ac
from verification.scenes import cylinder

NAME = "free_hertz_cylinder"
RADIUS = 1e-6
LENGTH = 1e-6
STEPS = 4
A_MAX = LENGTH / 8
SCENE = ("verification.scenes.cylinder(N, 1e-6, 1e-6, steps=4, initial=1e-9, surface.boundary='free', "
         "loading.control='force', "
         "loading.path=[0, F(L/8)/L])")
DESCRIPTION = ("GFMD hard wall on a free half-plane vs the Hertz cylinder without images (1+1-D, force control): "
               "max errors over 4 loads of p(x) (rms / p0), a(P) (second moment), a_count(P) vs N, observed orders")
METRICS = ("p(x)", "a(P)", "a_count(P)")
NODES = {"ci": (64, 128, 256, 512), "full": (64, 128, 256, 512, 1024, 2048)}


def scene(nodes, e_star=None):
    base = cylinder(nodes, RADIUS, LENGTH, steps=STEPS, initial=1e-9, **{"surface.boundary": "free"})
    load = H.load(A_MAX, RADIUS, base.material.contact_modulus) / LENGTH
    return base.replace(**{"loading.control": "force", "loading.path": [0.0, load]})


def measure(nodes):
    """(errors {metric: max over loads}, per-load rows, last-load profile, wall s) at N nodes."""
    sc = scene(nodes)
    result, wall = ac.run(sc)
    e_star = sc.material.contact_modulus
    spacing = LENGTH / nodes
    rows, errs = [], {m: [] for m in METRICS}
    for k in range(1, STEPS + 1):
        x, p, _, p_mean, _ = ac.step_fields(result, k)
        load = p_mean * LENGTH
        a_h = float(H.half_width(load, RADIUS, e_star))
        p0 = float(H.peak_pressure(load, RADIUS, e_star))
        ph = np.asarray(H.pressure(x, load, RADIUS, e_star))
        e = {"p(x)": float(np.sqrt(np.mean((p - ph) ** 2))) / p0,
             "a(P)": abs(ac.half_width_second_moment(x, p) - a_h) / a_h,
             "a_count(P)": abs(ac.half_width_compressive(p, spacing) - a_h) / a_h}
        for m in METRICS:
            errs[m].append(e[m])
        rows.append([k, load, a_h / LENGTH, a_h / spacing, *e.values()])
    x, p, _, p_mean, _ = ac.step_fields(result, STEPS)
    load = p_mean * LENGTH
    a_h = float(H.half_width(load, RADIUS, e_star))
    ph = np.asarray(H.pressure(x, load, RADIUS, e_star))
    near = np.abs(x) <= 1.5 * a_h
    fields = {"x": x[near] / a_h, "p": p[near] / ph.max(), "ph": ph[near] / ph.max()}
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
