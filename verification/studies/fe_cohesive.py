"""GFMD (finite bonded layer) vs the FE cell on the adhesive sinusoid, normal CZ law: differences vs N.

Scene: `verification.scenes.cohesive_sinusoid` (a = 50 nm, L = D = 1 µm, ν = 0.3, φn* = 0.01, δn = 1 nm,
δ from −2 nm to 60 nm in 20 steps). GFMD: FIRE at the scene's tolerance (1e-8); FE: `reference.fem` P2
(Newton, tolerance 1e-10). Same nodes and profile heights; each method its own z_ind and observables
(`verification.runs.fe_vs_gfmd`).

Differences (GFMD the reference; max over the recorded field steps 4, 8, …, 20, resp. over all steps):
* t_n(x): ‖t_n^FE − t_n^GFMD‖₂ / ‖t_n^GFMD‖₂;  p(δ): max_k |p_FE − p_GFMD| / max_k |p_GFMD|;
* a_rel: max_k |Δa_rel|; and the mean wall time per load step of each method (informational);
* p_reaction: the FE pressure from its own nodal reaction forces (−Σ (S u)_z / L, `reference.fem`
  diagnostics["reaction_pressure"]) against GFMD's p, max_k |Δ| / max_k |p_GFMD|; p_consistency: the same
  between the FE's two pressures (reaction forces vs the node mean of its law tractions).
The difference is discretisation (GFMD: continuum kernel sampled at the nodes; FE: P2 elements +
Simpson nodal quadrature): both converge to the same continuum problem.

    python -m verification.studies.fe_cohesive [--full] [--write]

N = 64, 128 (`--full`: … 512); `--write` stores the differences and the observed t_n orders between
neighbouring N in verification/data/fe_cohesive.json (entry "ci" or "full"); test_fe_cohesive.py reads
"full" (its bounds: a small factor over the stored difference at the same N, and the worst stored ratio
between neighbouring N).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from verification import measured
from verification.runs import fe_vs_gfmd
from verification.scenes import cohesive_sinusoid

NAME = "fe_cohesive"
NODES = {"ci": (64, 128), "full": (64, 128, 256, 512)}
METRICS = ("tn", "p", "a", "p_reaction", "p_consistency")
_CACHE = {}


def compare(n):
    """`verification.runs.fe_vs_gfmd` on cohesive_sinusoid(n), computed once per process."""
    if n not in _CACHE:
        out = _CACHE[n] = fe_vs_gfmd(cohesive_sinusoid(n))
        print(f"N={n}: t_n L2 {out['tn']:.3g}  p {out['p']:.3g}  p_reaction {out['p_reaction']:.3g}  "
              f"p_consistency {out['p_consistency']:.3g}  a_rel {out['a']:.3g}  FE {out['fe_s']:.1f} s "
              f"({out['fe_step']:.3f} s/step)  GFMD {out['gfmd_s']:.1f} s ({out['gfmd_step']:.3f} s/step)")
    return _CACHE[n]


def order(e_coarse, e_fine, ratio=2.0):
    """Observed order between two N a factor `ratio` apart."""
    return float(np.log(e_coarse / e_fine) / np.log(ratio))


def study(nodes):
    """{"nodes", "outs" (compare per N), "errors" {metric: [per N]}, "orders_tn" [per neighbouring pair],
    "step_s" {"fe", "gfmd": [per N]}, "wall_s"}."""
    t0 = time.perf_counter()
    outs = [compare(n) for n in nodes]
    errors = {m: [float(o[m]) for o in outs] for m in METRICS}
    return {"nodes": list(nodes), "outs": outs, "errors": errors,
            "orders_tn": [order(a, b, n1 / n0) for a, b, n0, n1 in
                          zip(errors["tn"], errors["tn"][1:], nodes, nodes[1:])],
            "step_s": {"fe": [o["fe_step"] for o in outs], "gfmd": [o["gfmd_step"] for o in outs]},
            "wall_s": time.perf_counter() - t0}


def entry(st, subset):
    return measured.make_entry({"N": st["nodes"], "errors": st["errors"], "orders_tn": st["orders_tn"]},
                               scene="verification.scenes.cohesive_sinusoid(N)", subset=subset,
                               step_s=st["step_s"], wall_s=st["wall_s"])


def measured_errors(subset="ci"):
    """{metric: [difference per N]} and the N list (verification/data/fe_cohesive.json)."""
    values = measured.entry(NAME, subset)["values"]
    return values["errors"], values["N"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="N up to 512 (entry 'full'); default N = 64, 128 ('ci')")
    ap.add_argument("--write", action="store_true", help="store the differences in verification/data/fe_cohesive.json")
    args = ap.parse_args(argv)
    subset = "full" if args.full else "ci"
    st = study(NODES[subset])
    print(f"t_n orders {[f'{o:.2f}' for o in st['orders_tn']]}; {st['wall_s']:.1f} s")
    if args.write:
        print(measured.write(NAME, {subset: entry(st, subset)},
                             description="GFMD vs FE P2, cohesive sinusoid φn* = 0.01: t_n, p(δ), a_rel differences "
                                         "vs N, t_n orders between neighbouring N"))


if __name__ == "__main__":
    main()
