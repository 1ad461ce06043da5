"""GFMD pull-off of a cohesive sphere (2+1-D) on a load–unload cycle vs Maugis–Dugdale (`reference.analytic.
maugis_dugdale_sphere`) at the scene's λ: errors and observed orders in N (the 2+1-D kin of `md_pulloff`).

Scene: `verification.scenes.sphere` (paraboloid R = 1 µm in a square periodic cell L = 0.5 µm of N × N nodes on the
default half-space E = 70 GPa, ν = 0.45), exponential CZ law (seed Eq. 3, normal only), w = φn = 1 J/m², δn set so
that the mapped Maugis parameter of the sphere is λ = 0.1, 0.3, 1 or 3 (σ0 = φn/(eδn), w = φn:
`maugis_parameter_from_cohesive_law`). Scales: ℓ = (πwR²/K)^{1/3} ≈ 30 nm (L/ℓ ≈ 17), P_u = πwR ≈ 3.1 µN.
Displacement control along `loading.path` = [−1, 2, 0.5, −3] nm in 10, 6 and 350 steps (Δδ = 0.01 nm on the
unloading segment that holds the minimum of P, δ ≈ −0.2 nm at λ = 1, and the snap-off).

Pull-off (GFMD): the run's own `gfmd_contact.core.cycle` observable, the most tensile p̄ on unloading, as a load
P = p̄_min L² (N, one sphere per cell). Under displacement control the branch passes the minimum of P(a)
(load-controlled pull-off) before it snaps off, as for the cylinder (`md_pulloff`). Sampling error: the sampled
minimum − the vertex of the parabola through it and its neighbours (stored, / P_u).

Error e = (P_GFMD − P_MD)/|P_MD| (signed). It holds the law-shape difference between Eq. 3 and the Dugdale map,
fixed by λ (it does not vanish as δn → 0 at fixed λ, see `md_pulloff`), and the discretisation error; the
successive differences |e(N) − e(2N)| measure the latter, their least-squares log2 slope is the observed order and
the Richardson limit e_∞ the law-shape error of the sphere. It must vanish at both ends, where the pull-off does not
depend on the law's shape: λ → 0 (DMT/Derjaguin, −2πwR) and λ → ∞ (JKR, −(3/2)πwR). Cell check (entry "cell"):
λ = 0.1, the widest adhesive zone, at L = 2 × 0.5 µm with N doubled (same spacing): the periodic-image part.

    python -m verification.studies.md_pulloff_2d [--write]

N per λ in NODES; `--write` stores them in verification/data/md_pulloff_2d.json (entry "ci"), which
verification/test_md_pulloff_2d.py reads (it re-runs CI_NODES, the second level of each list).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gfmd_contact.core import cycle as cyc
from gfmd_contact.core.loading import step_branches
from reference.analytic import maugis_dugdale_sphere as MDS
from verification import analytic_cases as ac
from verification import measured
from verification.scenes import sphere
from verification.studies.md_pulloff import orders

NAME = "md_pulloff_2d"
RADIUS = 1e-6
LENGTH = 0.5e-6
WORK = 1.0
PATH = (-1e-9, 2e-9, 0.5e-9, -3e-9)
STEPS = (10, 6, 350)
LAMBDAS = (0.1, 0.3, 1.0, 3.0)
#: N per λ (doubling); the process zone shrinks as 1/λ², so the lists start finer as λ grows
NODES = {0.1: (32, 64, 128, 256), 0.3: (32, 64, 128, 256), 1.0: (64, 128, 256, 512), 3.0: (128, 256, 512)}
#: the N the CI test re-runs (the second level of each list)
CI_NODES = {lam: ns[1] for lam, ns in NODES.items()}


def e_star():
    return sphere(8, RADIUS, LENGTH).material.contact_modulus


def delta_n(lam):
    """δn (m) at w = φn = WORK for the sphere's mapped Maugis parameter lam (λ ∝ 1/δn)."""
    return 1e-9 * float(MDS.maugis_parameter_from_cohesive_law(WORK, 1e-9, RADIUS, e_star())) / lam


def scene(nodes, lam, length=LENGTH):
    s = sphere(nodes, RADIUS, length, law="cohesive",
               **{"interface.work_normal": WORK, "interface.length_normal": delta_n(lam)})
    return s.replace(**{"loading.path": list(PATH), "loading.steps": list(STEPS), "output.field_steps": 0})


def analytic(lam):
    """(MD pull-off P_c (N), P_u = πwR (N)) for the Dugdale map of the scene at lam."""
    w, s0 = MDS.dugdale_from_cohesive_law(WORK, delta_n(lam))
    _, p_u, _ = MDS.units(RADIUS, e_star(), w)
    return float(MDS.pull_off_load(RADIUS, e_star(), w, s0)), p_u


def measure(nodes, lam, length=LENGTH, boundary="periodic"):
    """{"P": GFMD pull-off (N), "P_md", "P_u", "error" (signed, /|P_MD|), "sampling" (/P_u), "wall_s"};
    boundary: surface.boundary of the scene (free: the sphere alone on a half-space)."""
    s = scene(nodes, lam, length).replace(**{"surface.boundary": boundary})
    result, wall = ac.run(s)
    d, p, a = (np.asarray(result.curve[c], float) for c in ("delta", "p", "a_rel"))
    branch, cycle = step_branches(s.loading)
    (row,) = cyc.cycle_observables(d, p, a, branch, cycle)
    load = row["pull_off_pressure"] * length**2
    p_md, p_u = analytic(lam)
    unloading = np.flatnonzero(np.asarray(branch) == "unloading")
    k = int(unloading[np.argmin(p[unloading])])
    if not (k - 1 in unloading and k + 1 in unloading and p[k - 1] > p[k] < p[k + 1]):
        raise AssertionError(f"λ = {lam}, N = {nodes}: the pull-off is at an end of the unloading branch (step {k})")
    y0, y1, y2 = p[k - 1], p[k], p[k + 1]
    vertex = y1 - (y2 - y0) ** 2 / (8.0 * (y0 - 2.0 * y1 + y2))
    return {"P": load, "P_md": p_md, "P_u": p_u, "error": (load - p_md) / abs(p_md),
            "sampling": abs(y1 - vertex) * length**2 / p_u, "wall_s": wall}


def study(lam, nodes=None):
    nodes = NODES[lam] if nodes is None else nodes
    t0 = time.perf_counter()
    data = [measure(n, lam) for n in nodes]
    errors = [x["error"] for x in data]
    diffs, order, limit = orders(errors)
    return {"lambda": lam, "nodes": list(nodes), "data": data, "errors": errors, "differences": list(diffs),
            "order": order, "limit": limit, "wall_s": time.perf_counter() - t0}


#: λ and N of the cell check (L doubled, N doubled)
CELL_LAMBDA = 0.1


def cell_check():
    """e at (L, CI N) and (2L, 2 CI N) for λ = CELL_LAMBDA: the periodic-image part of the error."""
    n = CI_NODES[CELL_LAMBDA]
    errors = [measure(n, CELL_LAMBDA)["error"], measure(2 * n, CELL_LAMBDA, 2 * LENGTH)["error"]]
    return {"lambda": CELL_LAMBDA, "L_m": [LENGTH, 2 * LENGTH], "N": [n, 2 * n], "errors": errors}


def entry(studies):
    values = {}
    for st in studies:
        values[f"lambda={st['lambda']:g}"] = {
            "N": st["nodes"], "ci_nodes": CI_NODES[st["lambda"]], "errors": st["errors"],
            "differences": st["differences"], "order": st["order"], "limit": st["limit"],
            "delta_n_m": delta_n(st["lambda"]), "P_over_P_u": [x["P"] / x["P_u"] for x in st["data"]],
            "P_md_over_P_u": st["data"][0]["P_md"] / st["data"][0]["P_u"],
            "sampling_over_P_u": max(x["sampling"] for x in st["data"]),
            "wall_s_per_N": [x["wall_s"] for x in st["data"]]}
    return measured.make_entry(values, scene=(f"verification.studies.md_pulloff_2d.scene(N, λ): sphere R = 1 µm, "
                                              f"L = 0.5 µm, N × N, w = 1 J/m², δn from λ, path {list(PATH)} m, "
                                              f"steps {list(STEPS)}"),
                               wall_s=sum(st["wall_s"] for st in studies))


def stored(lam):
    """The stored study values at lam (verification/data/md_pulloff_2d.json, entry "ci")."""
    return measured.entry(NAME, "ci")["values"][f"lambda={lam:g}"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/md_pulloff_2d.json")
    args = ap.parse_args(argv)
    studies = []
    for lam in LAMBDAS:
        st = study(lam)
        studies.append(st)
        ratios = [f"{x['P'] / x['P_u']:.5f}" for x in st["data"]]
        print(f"λ = {lam}: N {st['nodes']} P/P_u {ratios} "
              f"MD {st['data'][0]['P_md'] / st['data'][0]['P_u']:.5f} error {[f'{e:.5f}' for e in st['errors']]} "
              f"|Δe| {[f'{v:.2e}' for v in st['differences']]} order {st['order']:.2f} limit {st['limit']:.5f} "
              f"sampling {max(x['sampling'] for x in st['data']):.1e} walls {[round(x['wall_s'], 1) for x in st['data']]}",
              flush=True)
    cell = cell_check()
    print(f"cell check λ = {cell['lambda']}: L {cell['L_m']} N {cell['N']} e {cell['errors']}")
    if args.write:
        print(measured.write(NAME, {"ci": entry(studies), "cell": measured.make_entry(
            cell, scene="verification.studies.md_pulloff_2d.scene(N, λ) at L and 2L (N doubled)")},
                             description="GFMD cohesive sphere (2+1-D) pull-off on a displacement-controlled load–unload "
                                         "path vs Maugis–Dugdale at λ = 0.1, 0.3, 1, 3: signed relative error vs N, successive "
                                         "differences, observed order, Richardson limit (law shape)"))


if __name__ == "__main__":
    main()
