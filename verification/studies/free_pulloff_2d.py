"""GFMD pull-off of a cohesive sphere on a free half-space (`surface.boundary = "free"`) vs Maugis–Dugdale: e vs N.

The scene of `verification.studies.md_pulloff_2d` (R = 1 µm, region L = 0.5 µm of N × N nodes, exponential CZ
w = 1 J/m², δn from the mapped Maugis parameter λ, displacement path [−1, 2, 0.5, −3] nm) with surface.boundary =
"free" (padded to 2N × 2N): no periodic images. Pull-off P = the run's most tensile p̄ on unloading × L² (the
region's total force: the load-controlled pull-off, which the displacement-controlled branch passes before it snaps
off; the padded cell's δ reference does not enter it). e = (P − P_MD)/|P_MD| holds the law-shape difference between
Eq. 3 and the Dugdale map (fixed by λ) and the discretisation error (successive differences, observed order,
Richardson limit e_∞ as in `md_pulloff_2d`).

    python -m verification.studies.free_pulloff_2d [--write]

`--write` stores them in verification/data/free_pulloff_2d.json (entry "ci"), which
verification/test_free_boundary_hertz.py reads.
"""

from __future__ import annotations

import argparse
import time

from verification import measured
from verification.studies import md_pulloff_2d as mp
from verification.studies.md_pulloff import orders

NAME = "free_pulloff_2d"
LAMBDA = 0.3
NODES = (32, 64, 128)
#: the N the CI test re-runs
CI_NODES = 32


def scene(nodes):
    return mp.scene(nodes, LAMBDA).replace(**{"surface.boundary": "free"})


def measure(nodes):
    """`md_pulloff_2d.measure` of the free scene at N × N nodes."""
    return mp.measure(nodes, LAMBDA, boundary="free")


def study(nodes=NODES):
    t0 = time.perf_counter()
    data = [measure(n) for n in nodes]
    errors = [x["error"] for x in data]
    diffs, order, limit = orders(errors)
    return {"nodes": list(nodes), "errors": errors, "differences": list(diffs), "order": order, "limit": limit,
            "P_over_P_u": [x["P"] / x["P_u"] for x in data], "wall_s": time.perf_counter() - t0}


def stored():
    """The stored study (verification/data/free_pulloff_2d.json, entry "ci")."""
    return measured.entry(NAME, "ci")["values"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/free_pulloff_2d.json")
    args = ap.parse_args(argv)
    st = study()
    print(f"λ = {LAMBDA}: N {st['nodes']} error {[f'{e:.5f}' for e in st['errors']]} |Δe| "
          f"{[f'{v:.2e}' for v in st['differences']]} order {st['order']:.2f} limit {st['limit']:.5f} "
          f"({st['wall_s']:.0f} s)")
    if args.write:
        values = {k: st[k] for k in ("nodes", "errors", "differences", "order", "limit", "P_over_P_u")}
        values.update(lam=LAMBDA, ci_nodes=CI_NODES)
        print(measured.write(NAME, {"ci": measured.make_entry(
            values, scene=f"verification.studies.free_pulloff_2d.scene(N): md_pulloff_2d.scene(N, {LAMBDA}) with "
                          "surface.boundary = free", wall_s=st["wall_s"])},
            description="GFMD cohesive sphere pull-off on a free half-space (2+1-D, Hockney padding) vs Maugis–Dugdale "
                        f"at λ = {LAMBDA}: signed relative error vs N, successive differences, order, "
                        "Richardson limit"))


if __name__ == "__main__":
    main()
