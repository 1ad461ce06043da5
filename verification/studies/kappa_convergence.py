"""κ (seed Eq. 1, a_rel = κ p/(ḡ_r E*)) vs N for the hard-wall self-affine default geometry.

Scene: `gfmd_contact/core/default_scene.toml` (L = 1.28 µm, λr = 160 nm, H = 0.8, h_rms = 10 nm, ν = 0.45, half-plane)
with interface.law = "hard-wall", δ from first contact (initial_separation 0) to 30 nm in STEPS steps.
N = 1024 … 8192 at fixed L and λr, two ways:

* "hard-wall" — fixed physical lengths: λs = 8 L/1024 = 10 nm at every N (the default's λs/l = 8 at
  N = 1024): the same surface, resolved with 8 … 64 nodes per λs; κ(N) is a discretisation convergence;
* "hard-wall-lambda-s-following" — λs = 8 L/N follows the grid: finer N adds the shorter wavelengths of
  the same spectrum (the shared modes keep their phases: one random stream per realization; h_rms is
  renormalised), so κ(N) changes with the surface, not only with the discretisation.

κ per realization: `gfmd_contact.core.observables.fit_kappa` (least squares through the origin over the steps with
0 < a_rel ≤ 0.1).

Per N: κ of each realization, their mean and spread (max − min). Between neighbouring N: the differences
of the mean, the observed order p = log2(|d_i|/|d_{i+1}|), and the Richardson limit
κ∞ = κ_finest + d_last / (2^p − 1) with its error estimate |d_last| (the last difference).

    python -m verification.studies.kappa_convergence [--write]

`--write` stores both in verification/data/kappa_convergence.json, which test_kappa_convergence.py reads.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import gfmd.loading as gl
from gfmd_contact.core.observables import fit_kappa, reduced_pressure
from gfmd_contact.core.scene import default_scene
from verification import measured

NAME = "kappa_convergence"
KEY = "hard-wall"  # fixed λs
FOLLOWING = "hard-wall-lambda-s-following"
NODES = (1024, 2048, 4096, 8192)
REALIZATIONS = (0, 1, 2, 3)
STEPS = 120
FINAL = 30e-9
LAMBDA_S_OVER_L = 8  # λs / (L/N), the default scene's
_CACHE = {}


def scene(n, variant=KEY):
    """The default scene as a hard wall at N = n; λs fixed at 8 L/1024 (KEY) or 8 L/n (FOLLOWING)."""
    base = default_scene()
    lambda_s = LAMBDA_S_OVER_L * base.surface.length / (n if variant == FOLLOWING else NODES[0])
    return base.replace(**{"surface.nodes": n, "surface.rollon_wavelength": lambda_s,
                           "interface.law": "hard-wall", "loading.initial_separation": 0.0,
                           "loading.final_penetration": FINAL, "loading.steps": STEPS, "output.field_steps": 0})


def kappa(n, realization, variant=KEY):
    """(κ, points fitted, wall s) of one realization at N = n, once per process."""
    key = (n, realization, variant)
    if key not in _CACHE:
        sc = scene(n, variant)
        t0 = time.perf_counter()
        r = gl.run_realization(sc, realization)
        wall = time.perf_counter() - t0
        assert r.all_converged, r.messages
        pr = reduced_pressure(r.curve["p"], r.curve["g_r"], sc.material.contact_modulus)
        k, used = fit_kappa(pr, r.curve["a_rel"])
        _CACHE[key] = (k, used, wall)
    return _CACHE[key]


def richardson(nodes, means):
    """{"differences", "orders", "limit", "limit_error"} of a sequence κ(N) at N doubling."""
    d = [b - a for a, b in zip(means, means[1:])]
    orders = [math.log2(abs(a) / abs(b)) if a and b else float("nan") for a, b in zip(d, d[1:])]
    p = orders[-1] if orders else float("nan")
    limit = means[-1] + d[-1] / (2**p - 1) if math.isfinite(p) and p > 0 else float("nan")
    return {"differences": d, "orders": orders, "limit": limit, "limit_error": abs(d[-1])}


def study(nodes=NODES, realizations=REALIZATIONS, variant=KEY):
    t0 = time.perf_counter()
    per = {n: [kappa(n, r, variant) for r in realizations] for n in nodes}
    k = {n: [v[0] for v in per[n]] for n in nodes}
    means = [float(np.mean(k[n])) for n in nodes]
    values = {"N": list(nodes), "realizations": list(realizations), "kappa": [k[n] for n in nodes],
              "mean": means, "spread": [float(np.max(k[n]) - np.min(k[n])) for n in nodes],
              "points": [[v[1] for v in per[n]] for n in nodes], **richardson(nodes, means)}
    return values, {n: [v[2] for v in per[n]] for n in nodes}, time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store κ(N) in verification/data/kappa_convergence.json")
    args = ap.parse_args(argv)
    entries = {}
    for variant, lam in ((KEY, f"{LAMBDA_S_OVER_L} L/{NODES[0]}"), (FOLLOWING, f"{LAMBDA_S_OVER_L} L/N")):
        values, walls, wall = study(variant=variant)
        print(variant)
        for key, v in values.items():
            print(" ", key, v)
        print(f"  {wall:.1f} s")
        entries[variant] = measured.make_entry(
            values, scene=f"gfmd_contact/core/default_scene.toml, hard wall, λs = {lam}, δ 0 … 30 nm in {STEPS} steps",
            wall_s={str(n): w for n, w in walls.items()})
    if args.write:
        print(measured.write(NAME, entries,
            description="κ vs N (λs following the grid) for the hard-wall self-affine default geometry: per realization, "
                        "mean, spread, differences, observed order, Richardson limit"))


if __name__ == "__main__":
    main()
