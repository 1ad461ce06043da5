"""GFMD vs FE through a jump into contact: t_n, p(δ), a_rel differences vs N (64 … 512).

Scene: `verification.scenes.jump_in_sinusoid` (the cohesive sinusoid at φn* = 0.15, δ0 = 10 nm ≥ 8 δn,
δ from −10 nm to 40 nm in 25 steps). The FE Newton solve fails at the jump and falls back to
its trust-region energy descent (`SurfaceProblem.descend`); GFMD (FIRE) relaxes dynamically. Differences as in
`verification.runs.fe_vs_gfmd` (t_n relative L2 max over the field steps, p(δ) max |Δp|/max |p|,
max |Δa_rel|), and the FE steps that needed the fallback.

    python -m verification.studies.fe_jump [--write]

`--write` stores them per N in verification/data/fe_jump.json (entry "convergence"), which
test_fe_jump.py reads (its bounds: a small factor over the stored difference at the same N; its
convergence check: the worst stored ratio between neighbouring N).
"""

from __future__ import annotations

import argparse
import time

from verification import measured
from verification.runs import fe_vs_gfmd
from verification.scenes import jump_in_sinusoid

NAME = "fe_jump"
KEY = "convergence"
NODES = (64, 128, 256, 512)
N = 128  # the CI resolution of the single-N test
_CACHE = {}


def study(n=N):
    """{"scene", "out" (fe_vs_gfmd), "values" {tn, p, a, fe_fallback_steps}, "wall_s"}, once per process and N."""
    if n not in _CACHE:
        sc = jump_in_sinusoid(n)
        t0 = time.perf_counter()
        out = fe_vs_gfmd(sc)
        vals = {"N": n, "tn": float(out["tn"]), "p": float(out["p"]), "a": float(out["a"]),
                "fe_fallback_steps": [int(k) for k in out["rf"].diagnostics["fallback_steps"]]}
        _CACHE[n] = {"scene": sc, "out": out, "values": vals, "wall_s": time.perf_counter() - t0}
    return _CACHE[n]


def stored(metric, n):
    """The stored difference `metric` ("tn", "p", "a") at N = n (verification/data/fe_jump.json)."""
    nodes = measured.value(NAME, KEY, "N")
    return measured.value(NAME, KEY, metric)[nodes.index(n)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the differences in verification/data/fe_jump.json")
    args = ap.parse_args(argv)
    sts = [study(n) for n in NODES]
    for st in sts:
        print(st["values"], f"{st['wall_s']:.1f} s")
    values = {"N": list(NODES)}
    for k in ("tn", "p", "a", "fe_fallback_steps"):
        values[k] = [st["values"][k] for st in sts]
    if args.write:
        print(measured.write(NAME, {KEY: measured.make_entry(values, scene="verification.scenes.jump_in_sinusoid(N)",
                                                             wall_s=[st["wall_s"] for st in sts])},
                             description="GFMD vs FE P2 through a jump into contact (φn* = 0.15), N = 64 … 512: "
                                         "t_n, p(δ), a_rel differences and the FE steps that needed the fallback"))


if __name__ == "__main__":
    main()
