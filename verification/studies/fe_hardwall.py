"""FE hard wall (reference/fem/hardwall.py) against Westergaard on a deep layer and against GFMD: errors vs N.

Scenes (SI): sinusoid h = −h0 cos(2πx/L), h0 = 10 nm, L = 1 µm, E = 70 GPa, ν = 0.45 (default scene),
frictionless hard wall, δ0 = 0, six steps to δ = 0.9 h0.

* Westergaard on a deep layer D = 2L (the q = 2π/L mode's compliance is the half-plane's to ~1e-9):
  p̄ and ḡ are the node means of the Result's −t_n and Δn, error = max over the six loads of
  |p̄ − p̄_exact(ḡ)|/p*; P2 at N = 32 … 512, P1 at N = 32 … 128 (P1 has a mesh floor: the graded mesh
  keeps ≥ 32 segments of L/32 in the bulk, not refined with N).
* GFMD hard wall (FIRE, tolerance 1e-10, layer kernel) vs FE on the same sinusoid with D = L, all steps:
  max |Δp| / max p, max |Δu_z| / h0, t_n rel. L2 (max over steps); P2 and P1 at N = 64, 128, 256.

    python -m verification.studies.fe_hardwall [--write]

`--write` stores them in verification/data/fe_hardwall.json (entry "convergence"), which
tests/test_fem_hardwall.py reads.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.optimize import brentq

import gfmd.loading as gl
from gfmd_contact.core.scene import default_scene
from gfmd.solver import Settings
from reference import fem
from reference.analytic.westergaard import full_contact_pressure, mean_gap
from verification import measured

NAME = "fe_hardwall"
KEY = "convergence"
H0 = 10e-9  # m
LENGTH = 1e-6  # m
STEPS = 6
WESTERGAARD_NODES = {2: (32, 64, 128, 256, 512), 1: (32, 64, 128)}
GFMD_NODES = (64, 128, 256)
GFMD_METRICS = ("dp", "du", "tn")
_CACHE = {}


def sinusoid_scene(nodes, depth):
    return default_scene().replace(**{
        "surface.kind": "sinusoid", "surface.nodes": nodes, "surface.length": LENGTH, "surface.amplitude": H0,
        "surface.realizations": 1, "interface.law": "hard-wall", "material.thickness": depth,
        "loading.initial_separation": 0.0, "loading.final_penetration": 0.9 * H0, "loading.steps": STEPS,
        "solver.tolerance": 1e-10, "output.field_steps": STEPS})


def westergaard_error(nodes, order):
    """max over the loaded steps of |p̄ − p̄_exact(ḡ)|/p* on the D = 2L layer, p̄ and ḡ the node means
    of the Result's fields (−t_n and Δn, as tests/test_gfmd_westergaard.py)."""
    key = ("w", nodes, order)
    if key not in _CACHE:
        sc = sinusoid_scene(nodes, 2 * LENGTH)
        r = fem.run_realization(sc, order=order)
        assert r.all_converged, r.messages
        e_star = sc.material.contact_modulus
        ps = full_contact_pressure(H0, LENGTH, e_star)
        errors = []
        for k, f in r.fields.items():
            if k == 0:
                continue
            gbar, pbar = np.mean(f["gap"]), -np.mean(f["t_n"])
            exact = ps * brentq(lambda P: mean_gap(P * ps, H0, LENGTH, e_star) - gbar, 1e-300, 1.0,
                                xtol=1e-300, rtol=1e-15)
            errors.append(abs(pbar - exact) / ps)
        _CACHE[key] = max(errors)
    return _CACHE[key]


def gfmd_differences(nodes, order):
    """{"dp": Δp/max p, "du": max Δu_z/h0, "tn": t_n rel. L2} between FE P<order> and GFMD FIRE, D = L."""
    key = ("g", nodes, order)
    if key not in _CACHE:
        sc = sinusoid_scene(nodes, LENGTH)
        rg = gl.run_realization(sc, settings=Settings(method="fire", tolerance=1e-10, max_iterations=20_000))
        rf = fem.run_realization(sc, order=order)
        assert rg.all_converged and rf.all_converged, (rg.messages, rf.messages)
        steps = [k for k in rf.fields if k > 0]
        dp = np.max(np.abs(rf.curve["p"] - rg.curve["p"])) / np.max(np.abs(rg.curve["p"]))
        du = max(np.max(np.abs(rf.fields[k]["u_z"] - rg.fields[k]["u_z"])) for k in steps) / H0
        tn = max(np.linalg.norm(rf.fields[k]["t_n"] - rg.fields[k]["t_n"]) / np.linalg.norm(rg.fields[k]["t_n"])
                 for k in steps)
        _CACHE[key] = {"dp": float(dp), "du": float(du), "tn": float(tn)}
    return _CACHE[key]


def stored_westergaard(order, nodes):
    v = measured.value(NAME, KEY, "westergaard")[f"P{order}"]
    return v["error"][v["N"].index(nodes)]


def stored_gfmd(order, nodes):
    v = measured.value(NAME, KEY, "gfmd")[f"P{order}"]
    i = v["N"].index(nodes)
    return {m: v[m][i] for m in GFMD_METRICS}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/fe_hardwall.json")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    values = {"westergaard": {}, "gfmd": {}}
    for order, ns in WESTERGAARD_NODES.items():
        values["westergaard"][f"P{order}"] = {"N": list(ns), "error": [westergaard_error(n, order) for n in ns]}
        print(f"P{order} Westergaard", values["westergaard"][f"P{order}"], flush=True)
    for order in (2, 1):
        rows = [gfmd_differences(n, order) for n in GFMD_NODES]
        values["gfmd"][f"P{order}"] = {"N": list(GFMD_NODES), **{m: [r[m] for r in rows] for m in GFMD_METRICS}}
        print(f"P{order} vs GFMD", values["gfmd"][f"P{order}"], flush=True)
    if args.write:
        print(measured.write(NAME, {KEY: measured.make_entry(values, scene="tests/test_fem_hardwall.py sinusoid_scene "
                                                             "(h0 = 10 nm, L = 1 µm; D = 2L Westergaard, D = L GFMD)",
                                                             wall_s=time.perf_counter() - t0)},
                             description="FE hard wall: Westergaard error on a deep layer (P2, P1) and the GFMD–FE "
                                         "differences (Δp, Δu_z, t_n) vs N"))


if __name__ == "__main__":
    main()
