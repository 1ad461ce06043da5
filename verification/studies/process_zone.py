"""Process-zone resolution: the grid error of an adhesive sinusoid vs l_pz/Δx (gfmd_contact.core.stickiness).

Scene: `verification.scenes.sinusoid`, h = −h0 cos(2πx/λ), h0 = 10 nm, λ = L = 1 µm, half-plane
E = 70 GPa, ν = 0.45, exponential CZ law (normal only) at fixed work of adhesion w = φn = 7 J/m²
(Johnson α = 0.40: partial contact, no spontaneous full contact) and three cohesive lengths
δn = 1, 0.3, 0.1 nm, i.e. process-zone sizes l_pz = E* w/σ_max² = e² E* δn²/w = 92.7, 8.3, 0.93 nm
(σ_max = φn/(e δn), l_pz/δn = 93, 28, 9.3). Displacement control from δ0 = 0 to δ = 0.6 h0 in 8
steps (loading, a/λ ≈ 0.1 … 0.3). Each case runs on N = 256 … 4096 nodes (ten grids) and on N_ref = 8192;
error at N = max over the 8 steps of |p̄_N − p̄_ref|/max|p̄_ref| and |a_rel,N − a_rel,ref|.

The measured limit (`min_process_zone_nodes`): the smallest l_pz/Δx sampled from which on (every
finer grid of every case) both errors stay ≤ 1 % (`ERROR_LIMIT`). The δn/Δx of each point is stored
too: the limit is read against the separate δn check (gfmd_contact.core.model.MIN_LENGTH_NORMAL_NODES).

    python -m verification.studies.process_zone [--write]

`--write` stores the numbers in verification/data/process_zone.json, which
`gfmd_contact.core.stickiness.measured_process_zone_limit` (the check) and tests/test_stickiness.py read.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from verification import measured
from verification.runs import run_gfmd
from verification.scenes import sinusoid

NAME = "process_zone"
H0 = 10e-9
LENGTH = 1e-6
WORK = 7.0  # J/m²
STEPS = 8
FINAL = 0.6 * H0
DELTA_N = (1e-9, 0.3e-9, 0.1e-9)
NODES = (256, 320, 384, 512, 768, 1024, 1536, 2048, 3072, 4096)
REFERENCE_NODES = 8192
ERROR_LIMIT = 0.01  # the error the limit is defined by (1 %)


def scene(nodes, delta_n):
    return sinusoid(nodes, H0, LENGTH, law="cohesive", steps=STEPS, final=FINAL,
                    **{"interface.work_normal": WORK, "interface.length_normal": delta_n,
                       "interface.tangential_ratio": 0.0, "output.field_steps": 1})


def process_zone(delta_n):
    """l_pz = E* w/σ_max² with σ_max = w/(e δn) (m), written out here (independent of gfmd_contact.core.stickiness)."""
    e_star = scene(256, delta_n).material.contact_modulus
    return e_star * WORK / (WORK / (math.e * delta_n)) ** 2


def curve(nodes, delta_n):
    result, _ = run_gfmd(scene(nodes, delta_n))
    return np.asarray(result.curve["p"], float), np.asarray(result.curve["a_rel"], float)


def study(nodes=NODES, delta_ns=DELTA_N):
    t0 = time.perf_counter()
    cases = []
    for dn in delta_ns:
        p_ref, a_ref = curve(REFERENCE_NODES, dn)
        lpz = process_zone(dn)
        rows = []
        for n in nodes:
            p, a = curve(n, dn)
            k = min(p.size, p_ref.size)
            ep = float(np.max(np.abs(p[:k] - p_ref[:k])) / np.max(np.abs(p_ref[:k])))
            ea = float(np.max(np.abs(a[:k] - a_ref[:k])))
            spacing = LENGTH / n
            rows.append({"N": n, "lpz_nodes": lpz / spacing, "delta_n_nodes": dn / spacing,
                         "p_error": ep, "a_rel_error": ea})
            print(f"δn = {dn:.3g} m, l_pz = {lpz:.3g} m, N = {n}: l_pz/Δx = {lpz / spacing:.4g}, "
                  f"δn/Δx = {dn / spacing:.3g}, |Δp̄|/max p̄ = {ep:.3g}, |Δa_rel| = {ea:.3g}", flush=True)
        cases.append({"delta_n_m": dn, "lpz_m": lpz, "rows": rows})
    return cases, time.perf_counter() - t0


def limit(cases, error=ERROR_LIMIT):
    """Smallest sampled l_pz/Δx from which on every point (every case) has both errors ≤ `error`."""
    points = sorted((r["lpz_nodes"], max(r["p_error"], r["a_rel_error"])) for c in cases for r in c["rows"])
    bad = [x for x, e in points if e > error]
    good = [x for x, e in points if e <= error and (not bad or x > max(bad))]
    return min(good) if good else None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the numbers in verification/data/process_zone.json")
    args = ap.parse_args(argv)
    cases, wall = study()
    lim = limit(cases)
    print(f"min_process_zone_nodes = {lim}  ({wall:.1f} s)")
    if args.write:
        values = {"min_process_zone_nodes": lim, "error_limit": ERROR_LIMIT, "reference_nodes": REFERENCE_NODES,
                  "work_normal": WORK, "cases": cases}
        print(measured.write(NAME, {"ci": measured.make_entry(
            values, scene=(f"verification.scenes.sinusoid(N, 10e-9, 1e-6, law='cohesive', steps=8, final=6e-9, "
                           f"w = {WORK} J/m², δn ∈ {DELTA_N})"), wall_s=wall)},
            description="grid error of an adhesive sinusoid vs process-zone size l_pz/Δx; the limit below which "
                        "the error exceeds 1 % (read by gfmd_contact.core.stickiness)"))


if __name__ == "__main__":
    main()
