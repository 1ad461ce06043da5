"""FE boundary quadrature: nodal (lumped, default) vs Gauss–Legendre vs GFMD, differences vs N.

Scene: `verification.scenes.cohesive_sinusoid` with every step's fields kept (a = 50 nm,
L = D = 1 µm, E = 70 GPa, ν = 0.3, normal CZ, φn* = 0.01, δn = 1 nm, δ0 = 2 nm,
δ from −2 nm to 60 nm in 20 steps). FE P2 (`method.name = "fe"`, gfmd_contact.app.methods)
with quadrature="nodal" (f_i = W_i T(Δ_i), Simpson weights) and "gauss"
(f = Bᵀ(w_g T(Δ_g)), 4 Gauss points per facet, z_ind from the Fourier
interpolant of h; `reference.fem.quadrature`); GFMD (FIRE, nodal forces l T_i).
Outputs are nodal for every method: t_n is T at the GFMD nodes' gaps, p =
−⟨t_z⟩ over the nodes.

Metrics (pairs nodal–Gauss, nodal–GFMD, Gauss–GFMD): t_n = max over the field steps 4, 8, …, 20 of
‖t_n^a − t_n^b‖₂/‖t_n^b‖₂; p = max_k |p_a − p_b| / max_k |p_GFMD|; p_force: the same with the FE
pressure taken from its own equilibrium total boundary force, −Σ_i f_z,i / L = −Σ (S u)_z / L
(GFMD's p is its total nodal force already), at all steps 1–20.

    python -m verification.studies.fe_quadrature [--write]

N = 64, 128, 256, 512; `--write` stores the differences per N in verification/data/fe_quadrature.json
(entry "convergence"), which test_fe_quadrature.py reads.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gfmd_contact.core.loading import field_step_indices
from verification import measured
from verification.metrics import field_difference
from verification.runs import run_method, with_method
from verification.scenes import cohesive_sinusoid

NAME = "fe_quadrature"
KEY = "convergence"
NODES = (64, 128, 256, 512)
QUANTITIES = ("tn", "p", "p_force")
PAIRS = ("nodal-gauss", "nodal-gfmd", "gauss-gfmd")
_CACHE = {}


def scene(n):
    """The cohesive sinusoid with the fields of every step kept (for p_force)."""
    return cohesive_sinusoid(n).replace(**{"output.field_steps": 20})


def field_steps(result):
    """The steps compared in test_fe_cohesive (4, 8, …, 20), for comparable t_n numbers."""
    return field_step_indices(result.scene.loading, 5)


def t_n_difference(a, b):
    """max over the field steps of ‖t_n^a − t_n^b‖₂ / ‖t_n^b‖₂."""
    return field_difference(a, b, "t_n", steps=field_steps(b))


def force_pressure(result):
    """(steps, p (Pa)) from the FE equilibrium total boundary force −Σ (S u)_z / L at the stored steps."""
    steps = np.array(sorted(result.diagnostics["solutions"]))
    length = result.scene.surface.length
    return steps, np.array([-float(np.sum(result.diagnostics["problem"].S @ result.diagnostics["solutions"][k]))
                            / length for k in steps])


def compare(n):
    """{"runs", "wall", "tn"|"p"|"p_force": {pair: difference}}, once per process and N."""
    if n in _CACHE:
        return _CACHE[n]
    sc = scene(n)
    runs, wall = {}, {}
    for name, run in (("nodal", lambda: run_method(with_method(sc, "fe", order=2))),
                      ("gauss", lambda: run_method(with_method(sc, "fe", order=2, quadrature="gauss",
                                                               linear="dense"))),
                      ("gfmd", lambda: run_method(with_method(sc, "gfmd")))):
        t0 = time.perf_counter()
        runs[name] = run()
        wall[name] = time.perf_counter() - t0
        assert runs[name].all_converged, (name, runs[name].messages)
    rn, rq, rg = runs["nodal"], runs["gauss"], runs["gfmd"]
    p_scale = np.max(np.abs(rg.curve["p"]))
    steps, pf_n = force_pressure(rn)
    _, pf_q = force_pressure(rq)

    def p_diff(a, b):
        return float(np.max(np.abs(a - b)) / p_scale)

    out = {"runs": runs, "wall": wall,
           "tn": {"nodal-gauss": t_n_difference(rq, rn), "nodal-gfmd": t_n_difference(rn, rg),
                  "gauss-gfmd": t_n_difference(rq, rg)},
           "p": {"nodal-gauss": p_diff(rq.curve["p"], rn.curve["p"]),
                 "nodal-gfmd": p_diff(rn.curve["p"], rg.curve["p"]),
                 "gauss-gfmd": p_diff(rq.curve["p"], rg.curve["p"])},
           "p_force": {"nodal-gauss": p_diff(pf_n, pf_q), "nodal-gfmd": p_diff(pf_n, rg.curve["p"][steps]),
                       "gauss-gfmd": p_diff(pf_q, rg.curve["p"][steps])}}
    print(f"N={n}: " + "; ".join(f"{m} " + ", ".join(f"{k} {v:.3g}" for k, v in out[m].items())
                                 for m in QUANTITIES)
          + "; wall " + ", ".join(f"{k} {v:.2f} s" for k, v in wall.items()))
    _CACHE[n] = out
    return out


def stored(quantity, pair, n):
    """The stored difference of `quantity` between `pair` at N = n (verification/data/fe_quadrature.json)."""
    nodes = measured.value(NAME, KEY, "N")
    return measured.value(NAME, KEY, quantity)[pair][nodes.index(n)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the differences in verification/data/fe_quadrature.json")
    args = ap.parse_args(argv)
    outs = [compare(n) for n in NODES]
    values = {"N": list(NODES)}
    for q in QUANTITIES:
        values[q] = {pair: [o[q][pair] for o in outs] for pair in PAIRS}
    if args.write:
        print(measured.write(NAME, {KEY: measured.make_entry(
            values, scene="verification.scenes.cohesive_sinusoid(N) with output.field_steps = 20",
            wall_s=[sum(o["wall"].values()) for o in outs])},
            description="FE P2 nodal vs Gauss boundary quadrature vs GFMD, cohesive sinusoid φn* = 0.01: t_n, p "
                        "and p from the FE total boundary force, differences per N"))


if __name__ == "__main__":
    main()
