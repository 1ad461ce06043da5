"""GFMD 2+1-D hard wall on the egg-box vs Johnson–Greenwood–Higginson (1985) (`reference.analytic.jgh_wavy`):
a_rel(p̄) at small loads and near full contact, and the full-contact pressure p*, errors vs N.

Scene: `verification.scenes.egg_box`, h = Δ cos(2πx/λ) cos(2πy/λ), Δ = 10 nm, square cell λ = L = 1 µm of N × N
nodes, default half-space (E = 70 GPa, ν = 0.45), frictionless hard wall. Displacement control along
`loading.path` = [0, 0.2, 0.9, 0.99, 0.999] Δ in 10, 7, 9, 9 steps (p̄/p* ≈ 3e-4 … 0.85; the ramp stops at its
full-contact limit δ ≈ 0.998 Δ, where p̄ → p* steeply). Only the scene is shared with the reference.

Errors (signed, relative), each measured per N:
* small: mean over the steps with 0 < p̄/p* ≤ SMALL of (a_rel − a_JGH2)/a_JGH2, a_JGH2 the Hertz-at-each-peak
  asymptote with the neighbours' curvature (`contact_fraction_small_load_interacting`); a_rel the run's own
  contact fraction (first order in l/a: the contact line cuts the node lattice);
* small a(P): a second scene, δ from 0 to 0.05 Δ in 5 steps with the fields saved (SMALL_PATH): the radius of each of the
  two contacts from its pressure's second moment, a = √(5⟨r²⟩_p/2) (exact for the Hertz pressure; r from the
  contact's trough node, periodic), mean of (a − a_JGH2)/a_JGH2 over both contacts and the steps (p̄/p* ≤ SMALL), a_JGH2 =
  √(a_rel,JGH2 λ²/(2π)) — second order, free of the node-count quantisation of a_rel;
* near-full: mean over the steps with p̄/p* ≥ NEAR of ((1 − a_rel) − s(1 − p̄/p*))/(s(1 − p̄/p*)), s = 3/(2π) (JGH3);
* p*: the intercept at a_rel = 1 of the least-squares line p̄(1 − a_rel) through the steps with p̄/p* ≥ NEAR,
  (p*_fit − p*)/p*, p* = √2πE*Δ/λ (JGH1).
All three hold a model part (the asymptotes are asymptotes: O(p̄/p*) at small loads, O(1 − p̄/p*) near full contact,
and the line's curvature for p*) that does not vanish with N, and the discretisation part; the successive
differences |e(N) − e(2N)| measure the latter, their least-squares log2 slope is the observed order, the Richardson
limit e_∞ the model part.

    python -m verification.studies.jgh_2d [--write]

N = 64 … 512; `--write` stores them in verification/data/jgh_2d.json (entry "ci"), which verification/test_jgh_2d.py
reads (it re-runs CI_NODES).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from reference.analytic import jgh_wavy as J
from verification import analytic_cases as ac
from verification import measured
from verification.scenes import egg_box
from verification.studies.md_pulloff import orders

NAME = "jgh_2d"
AMPLITUDE = 10e-9
LENGTH = 1e-6
PATH = tuple(f * AMPLITUDE for f in (0.0, 0.2, 0.9, 0.99, 0.999))
STEPS = (10, 7, 9, 9)
SMALL = 0.01
NEAR = 0.7
METRICS = ("small", "small a(P)", "near-full", "p*")
#: the small-load scene of "small a(P)": δ from 0 to 0.05 Δ (p̄/p* ≲ 1e-3, a ≲ 0.03 λ) in 5 steps, fields at every step
SMALL_PATH, SMALL_STEPS = (0.0, 0.05 * AMPLITUDE), 5
NODES = (64, 128, 256, 512)
CI_NODES = 256


def scene(nodes):
    s = egg_box(nodes, AMPLITUDE, LENGTH)
    return s.replace(**{"loading.path": list(PATH), "loading.steps": list(STEPS), "output.field_steps": 0})


def small_scene(nodes):
    s = egg_box(nodes, AMPLITUDE, LENGTH)
    return s.replace(**{"loading.path": list(SMALL_PATH), "loading.steps": [SMALL_STEPS],
                        "output.field_steps": SMALL_STEPS})


def small_radius_error(nodes):
    """(mean signed relative error of the second-moment contact radii vs JGH2 over the steps with p̄/p* ≤ SMALL,
    wall s) at N × N nodes (module doc)."""
    sc = small_scene(nodes)
    result, wall = ac.run(sc)
    e_star, ps = sc.material.contact_modulus, full_contact_pressure()
    x, y = np.asarray(result.x), np.asarray(result.y)
    # the troughs (first contact): nodes (Nx/2, 0) and (0, Ny/2), i.e. the centred positions (0, −L/2), (−L/2, 0)
    errors = []
    for k in sorted(result.fields):
        p = -np.asarray(result.fields[k]["t_n"], float)
        pbar = float(np.mean(p))
        if not 0 < pbar / ps <= SMALL:
            continue
        a_ref = np.sqrt(float(J.contact_fraction_small_load_interacting(pbar, AMPLITUDE, LENGTH, e_star))
                        * LENGTH**2 / (2 * np.pi))
        for x0, y0 in ((x[nodes // 2], y[0]), (x[0], y[nodes // 2])):
            dx = (x - x0 + LENGTH / 2) % LENGTH - LENGTH / 2
            dy = (y - y0 + LENGTH / 2) % LENGTH - LENGTH / 2
            r2 = dx[:, None] ** 2 + dy[None, :] ** 2
            near = (r2 < (0.3 * LENGTH) ** 2) & (p > 0)
            a = float(np.sqrt(2.5 * np.sum(r2[near] * p[near]) / np.sum(p[near])))
            errors.append((a - a_ref) / a_ref)
    return float(np.mean(errors)), wall


def full_contact_pressure():
    return float(J.full_contact_pressure(AMPLITUDE, LENGTH, scene(8).material.contact_modulus))


def measure(nodes):
    """{"errors" {metric: signed relative error}, "p_star_fit" (Pa), "steps" {small, near}, "wall_s"} at N × N."""
    sc = scene(nodes)
    result, wall = ac.run(sc)
    e_star = sc.material.contact_modulus
    ps = full_contact_pressure()
    p, a = np.asarray(result.curve["p"], float), np.asarray(result.curve["a_rel"], float)
    small = (p > 0) & (p / ps <= SMALL)
    near = (p / ps >= NEAR) & (a < 1)
    a_small = np.array([J.contact_fraction_small_load_interacting(x, AMPLITUDE, LENGTH, e_star) for x in p[small]])
    hole = J.NEAR_FULL_SLOPE * (1 - p[near] / ps)
    c1, c0 = np.polyfit(1 - a[near], p[near], 1)
    small_radius, wall_small = small_radius_error(nodes)
    wall += wall_small
    errors = {"small": float(np.mean((a[small] - a_small) / a_small)), "small a(P)": small_radius,
              "near-full": float(np.mean(((1 - a[near]) - hole) / hole)), "p*": float((c0 - ps) / ps)}
    return {"errors": errors, "p_star_fit": float(c0), "steps": {"small": int(small.sum()), "near": int(near.sum())},
            "p_over_p_star": list(p / ps), "a_rel": list(a), "wall_s": wall}


def study(nodes=NODES):
    t0 = time.perf_counter()
    data = [measure(n) for n in nodes]
    out = {"N": list(nodes), "data": data, "wall_s": time.perf_counter() - t0, "metrics": {}}
    for m in METRICS:
        errors = [x["errors"][m] for x in data]
        diffs, order, limit = orders(errors)
        out["metrics"][m] = {"errors": errors, "differences": list(diffs), "order": order, "limit": limit}
    return out


def stored(metric):
    """The stored study values of `metric` (verification/data/jgh_2d.json, entry "ci")."""
    v = measured.entry(NAME, "ci")["values"]
    return {"N": v["N"], "ci_nodes": v["ci_nodes"], **v["metrics"][metric]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/jgh_2d.json")
    args = ap.parse_args(argv)
    st = study()
    for m, v in st["metrics"].items():
        print(f"{m}: N {st['N']} error {[f'{e:.5f}' for e in v['errors']]} |Δe| {[f'{d:.2e}' for d in v['differences']]} "
              f"order {v['order']:.2f} limit {v['limit']:.5f}")
    print(f"steps used {st['data'][0]['steps']}, walls {[round(x['wall_s'], 1) for x in st['data']]}")
    if args.write:
        values = {"N": st["N"], "ci_nodes": CI_NODES, "p_star_Pa": full_contact_pressure(), "small_max": SMALL,
                  "near_min": NEAR, "metrics": st["metrics"], "steps_used": st["data"][0]["steps"],
                  "p_star_fit_Pa": [x["p_star_fit"] for x in st["data"]],
                  "wall_s_per_N": [x["wall_s"] for x in st["data"]]}
        ent = measured.make_entry(values, scene=(f"verification.studies.jgh_2d.scene(N): egg-box Δ = 10 nm, λ = L = 1 µm, "
                                                 f"N × N, hard wall, path {[round(x, 12) for x in PATH]} m, steps "
                                                 f"{list(STEPS)}"), wall_s=st["wall_s"])
        print(measured.write(NAME, {"ci": ent}, description=(
            "GFMD hard-wall egg-box (2+1-D) vs JGH (1985): signed relative errors of a_rel at small loads (Hertz at each "
            "peak), 1 − a_rel near full contact, and the fitted full-contact pressure p*, vs N; successive differences, "
            "observed order, Richardson limit (the asymptotes' model part)")))


if __name__ == "__main__":
    main()
