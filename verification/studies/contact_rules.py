"""Contact rules (interface.contact_rule) computed by GFMD and by the FE reference, each with its own code.

Scene: `verification.scenes.cohesive_sinusoid` (a = 50 nm, L = D = 1 µm, ν = 0.3, δ from −2 nm to
60 nm in 20 steps) with the normal CZ law (φn* = 0.01, δn = 1 nm) and with the hard wall, each under
the three rules: "traction-tolerance" (the seed's), "compressive", and "gap" with contact_gap = 1
(Δn ≤ δn). Every (law, rule) is run by both methods through the method registry
(`verification.runs.run_fe_and_gfmd`: FE P2 and GFMD FIRE); a_rel is each method's own:
`gfmd_contact.core.observables` (the law object's `in_contact`) for GFMD, `reference.fem.observables.contact_set`
for the FE (the FE cell's `observe`).

Measured per N: max over the load steps of |a_rel^FE − a_rel^GFMD|, in nodes (× N). a_rel counts
nodes, so the difference is quantised by 1/N; a node at a contact edge whose gap or traction
lies within the two discretisations' difference of the rule's threshold flips. The data show
how many nodes that is, and whether it grows with N.

    python -m verification.studies.contact_rules [--full] [--write]

N = 64, 128 (entry "ci"); `--full`: 64 … 512 (entry "full"). `--write` stores them in
verification/data/contact_rules.json, which verification/test_contact_rules.py reads.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from verification import measured
from verification.runs import run_fe_and_gfmd
from verification.scenes import cohesive_sinusoid

NAME = "contact_rules"
NODES = {"ci": (64, 128), "full": (64, 128, 256, 512)}
LAWS = ("cohesive", "hard-wall")
#: rule name in the data → the [interface] keys that select it
RULES = {"traction-tolerance": {"interface.contact_rule": "traction-tolerance"},
         "compressive": {"interface.contact_rule": "compressive"},
         "gap": {"interface.contact_rule": "gap", "interface.contact_gap": 1.0}}
_CACHE = {}


def scene(n, law, rule):
    """`cohesive_sinusoid(n)` with interface.law `law` and the contact rule `rule` (a key of RULES)."""
    return cohesive_sinusoid(n).replace(**{"interface.law": law, **RULES[rule]})


def compare(n, law, rule):
    """{"a_fe", "a_gfmd" (a_rel per step), "nodes" (max |Δa_rel|·N), "wall_s"}; computed once per process."""
    key = (n, law, rule)
    if key not in _CACHE:
        t0 = time.perf_counter()
        fe, gfmd, _, _ = run_fe_and_gfmd(scene(n, law, rule))
        assert fe.all_converged, f"FE {key}: {fe.messages[:3]}"
        assert gfmd.all_converged, f"GFMD {key}: {gfmd.messages[:3]}"
        a_fe, a_gfmd = np.asarray(fe.curve["a_rel"], float), np.asarray(gfmd.curve["a_rel"], float)
        _CACHE[key] = {"a_fe": a_fe, "a_gfmd": a_gfmd, "nodes": float(np.max(np.abs(a_fe - a_gfmd)) * n),
                       "wall_s": time.perf_counter() - t0}
        print(f"N={n} {law:9s} {rule:18s}: max |Δa_rel| = {_CACHE[key]['nodes']:.0f} nodes "
              f"(a_rel up to {a_gfmd.max():.3f}), {_CACHE[key]['wall_s']:.1f} s")
    return _CACHE[key]


def study(nodes):
    """{"N": [...], "nodes": {law: {rule: [max |Δa_rel|·N per N]}}, "a_max": {law: {rule: [...]}}, "wall_s"}."""
    t0 = time.perf_counter()
    out = {"N": list(nodes), "nodes": {}, "a_max": {}}
    for law in LAWS:
        out["nodes"][law], out["a_max"][law] = {}, {}
        for rule in RULES:
            runs = [compare(n, law, rule) for n in nodes]
            out["nodes"][law][rule] = [measured.node_count(r["nodes"] / n, n) for r, n in zip(runs, nodes)]
            out["a_max"][law][rule] = [float(r["a_gfmd"].max()) for r in runs]
    out["wall_s"] = time.perf_counter() - t0
    return out


def entry(st, subset):
    return measured.make_entry({k: st[k] for k in ("N", "nodes", "a_max")},
                               scene="verification.studies.contact_rules.scene(N, law, rule)", subset=subset,
                               wall_s=st["wall_s"])


def measured_nodes(subset="full"):
    """({law: {rule: [max |Δa_rel|·N per N]}}, [N]) from verification/data/contact_rules.json."""
    values = measured.entry(NAME, subset)["values"]
    return values["nodes"], values["N"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="N up to 512 (entry 'full'); default N = 64, 128 ('ci')")
    ap.add_argument("--write", action="store_true", help="store the numbers in verification/data/contact_rules.json")
    args = ap.parse_args(argv)
    subset = "full" if args.full else "ci"
    st = study(NODES[subset])
    print(f"{st['wall_s']:.1f} s")
    if args.write:
        print(measured.write(NAME, {subset: entry(st, subset)},
                             description="GFMD vs FE P2 a_rel by each contact rule, each method's own contact-set "
                                         "code; max |Δa_rel| over the steps in nodes (× N), cohesive (φn* = 0.01) "
                                         "and hard-wall sinusoid on a layer, vs N"))


if __name__ == "__main__":
    main()
