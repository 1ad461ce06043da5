"""GFMD cohesive cylinder vs Maugis–Dugdale (Baney & Hui 1997; reference-formulas §4.2): signed error vs N.

Scene: `verification.scenes.cylinder`, parabolic cylinder R = 1 µm in a periodic cell L = 1 µm,
half-plane E = 70 GPa, ν = 0.45, exponential CZ law (normal only), w = φn = 1 J/m²; δn set so that
the mapped Maugis parameter (w = φn, σ0 = φn/(e δn)) is λ = 3 or λ = 1. Scales:
ℓ = 2(wR²/(πE*))^{1/3} ≈ 31 nm (L/ℓ ≈ 32), F_u = (πE*w²R)^{1/3}. Displacement control, 8 steps from
first touch to δ = 3 nm (loading only: a/ℓ ≈ 1.1…2.3, F/F_u ≈ −0.2…2.4); pull-off is not measured.

Which a: MD has a contact edge a (gap 0) and a cohesive-zone edge c where the gap is w/σ0 = e δn.
The exponential law has no gap-0 edge, but "gap = e δn" means the same in both, so
c_GFMD = (nodes with Δn ≤ e δn)·l/2 and a_MD is the root of c_MD(a) = c_GFMD. Error: the worst
(largest in magnitude) signed (F_GFMD − F_MD(a_MD))/F_u over the loads, F = p̄ L. (Using a from
Δn ≤ δn instead gives errors ≈ 1 F_u at λ = 1: the definition matters as much as the law.)
The MD curve is a guide, not an exact reference: the exponential law's pull-off is −1% (λ = 3) and
−7% (λ = 1) off its Dugdale map (reference-formulas §4.2 table), so at λ = 1 the error converges in
N to a law-shape offset, not to zero.

    python -m verification.studies.maugis_dugdale [--full] [--write]

N = 2048, 4096 (`--full`: … 8192; ℓ/l = 63, 126, 252); `--write` stores the signed errors per λ in
verification/data/maugis_dugdale.json (entry "ci" or "full"), which test_analytic_maugis_dugdale.py reads.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.optimize import brentq

from reference.analytic import jkr_cylinder as JC
from reference.analytic import maugis_dugdale as MD
from verification import analytic_cases as ac
from verification import measured
from verification.metrics import worst_signed
from verification.scenes import cylinder

NAME = "maugis_dugdale"
RADIUS = 1e-6
LENGTH = 1e-6
WORK = 1.0
STEPS = 8
FINAL = 3e-9
LAMBDAS = (3.0, 1.0)
NODES = {"ci": (2048, 4096), "full": (2048, 4096, 8192)}


def e_star():
    return cylinder(64, RADIUS, LENGTH).material.contact_modulus


def measure(nodes, lam):
    """(worst signed error / F_u, per-load rows, δn, wall s) at N = nodes, Maugis parameter lam."""
    es = e_star()
    dn = 1e-9 * MD.maugis_parameter_from_cohesive_law(WORK, 1e-9, RADIUS, es) / lam  # λ ∝ 1/δn
    w, s0 = MD.dugdale_from_cohesive_law(WORK, dn)
    scene = cylinder(nodes, RADIUS, LENGTH, law="cohesive", steps=STEPS, final=FINAL,
                     **{"interface.work_normal": WORK, "interface.length_normal": dn})
    result, wall = ac.run(scene)
    ell, f_u, _ = MD.units(RADIUS, es, w)
    rows = []
    for k in range(1, STEPS + 1):
        _, _, gap, pbar, _ = ac.step_fields(result, k)
        c = ac.half_width_gap(gap, np.e * dn, LENGTH / nodes)
        a = brentq(lambda a: MD.cohesive_zone_edge(a, RADIUS, es, w, s0) - c, 1e-3 * c, c * (1 - 1e-12))
        load = pbar * LENGTH
        f_md, f_jkr = MD.load(a, RADIUS, es, w, s0), JC.load(a, RADIUS, es, w)
        rows.append([k, a / ell, c / ell, load / f_u, f_md / f_u, (load - f_md) / f_u, (load - f_jkr) / f_u])
    return worst_signed(r[5] for r in rows), rows, dn, wall


def study(lam, nodes):
    """{"lambda", "nodes", "data" (measure's output per N), "errors" [signed, per N], "wall_s"}."""
    t0 = time.perf_counter()
    data = [measure(n, lam) for n in nodes]
    return {"lambda": lam, "nodes": list(nodes), "data": data, "errors": [d[0] for d in data],
            "wall_s": time.perf_counter() - t0}


def entry(studies, subset):
    return measured.make_entry({"N": studies[0]["nodes"],
                                "errors": {f"lambda={st['lambda']:g}": list(st["errors"]) for st in studies},
                                "delta_n_m": {f"lambda={st['lambda']:g}": st["data"][-1][2] for st in studies}},
                               scene=("verification.scenes.cylinder(N, 1e-6, 1e-6, law='cohesive', steps=8, "
                                      "final=3e-9, w = 1 J/m², δn: λ = 3 or 1)"),
                               subset=subset, wall_s=sum(st["wall_s"] for st in studies))


def measured_errors(lam, subset="ci"):
    """[signed worst error / F_u per N] at Maugis parameter lam and the N list (verification/data/maugis_dugdale.json)."""
    values = measured.entry(NAME, subset)["values"]
    return values["errors"][f"lambda={lam:g}"], values["N"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="N up to 8192 (entry 'full'); default N up to 4096 ('ci')")
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/maugis_dugdale.json")
    args = ap.parse_args(argv)
    subset = "full" if args.full else "ci"
    studies = [study(lam, NODES[subset]) for lam in LAMBDAS]
    for st in studies:
        print(f"λ = {st['lambda']}: N {st['nodes']} worst signed error / F_u {[f'{e:.4f}' for e in st['errors']]}")
    print(f"{sum(st['wall_s'] for st in studies):.1f} s")
    if args.write:
        print(measured.write(NAME, {subset: entry(studies, subset)},
                             description="GFMD cohesive cylinder vs Maugis-Dugdale: worst signed (F − F_MD(a))/F_u "
                                         "over 8 loads vs N, at λ = 3 and λ = 1"))


if __name__ == "__main__":
    main()
