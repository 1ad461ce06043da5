"""GFMD (finite bonded layer) vs the FE cell on self-affine adhesive profiles, H = 0.8 and 0.2: differences vs N.

Scene: `verification.scenes.cohesive_self_affine` (L = 1 µm, λs,H = L/64, so every N ≥ 128 samples the same
32 modes: refining N refines the discretisation only; layer D = L, φn* = 0.01, δn = 1 nm). GFMD: FIRE,
tolerance 1e-8; FE: P2, Newton (dense surface solve; sparse at N = 2048), tolerance 1e-10; same nodes, same
profile heights (`verification.runs.fe_vs_gfmd`).

Metrics (max over the field steps 5, 10, 15, resp. over all 16 steps):
* t_n(x): ‖t_n^FE − t_n^GFMD‖₂ / ‖t_n^GFMD‖₂;   p(δ): max_k |p_FE − p_GFMD| / max_k |p_GFMD|;
* ḡ_r: max_k |ḡ_r^FE − ḡ_r^GFMD| / max_k ḡ_r^GFMD (rms gradient in contact, seed Eq. 6);  a_rel: max_k |Δa_rel|.

    python -m verification.studies.fe_selfaffine [--write]

N = 256, 512, 1024, 2048 for each H (a few minutes: the FE at N = 2048 takes over a minute); `--write`
stores them in verification/data/fe_selfaffine.json (entry "convergence"), which test_fe_selfaffine.py reads.
"""

from __future__ import annotations

import argparse
import time

from verification import measured
from verification.metrics import curve_difference
from verification.runs import fe_vs_gfmd
from verification.scenes import cohesive_self_affine

NAME = "fe_selfaffine"
KEY = "convergence"
NODES = (256, 512, 1024, 2048)
HURSTS = (0.8, 0.2)
METRICS = ("tn", "p", "g", "a")
_CACHE = {}


def compare(n, hurst):
    """`fe_vs_gfmd` on cohesive_self_affine(n, hurst) plus the ḡ_r difference "g", once per process."""
    key = (n, hurst)
    if key not in _CACHE:
        out = _CACHE[key] = fe_vs_gfmd(cohesive_self_affine(n, hurst))
        out["g"] = curve_difference(out["rf"], out["rg"], "g_r")
        print(f"H={hurst} N={n}: t_n {out['tn']:.3g}  p {out['p']:.3g}  ḡ_r {out['g']:.3g}  a_rel {out['a']:.3g}  "
              f"FE {out['fe_s']:.1f} s  GFMD {out['gfmd_s']:.1f} s", flush=True)
    return _CACHE[key]


def stored(metric, n, hurst):
    """The stored difference `metric` at N = n for Hurst exponent `hurst` (a_rel: its node count / N)."""
    if metric == "a":
        return stored_node_count(n, hurst) / n
    v = measured.value(NAME, KEY, f"H={hurst:g}")
    return v[metric][v["N"].index(n)]


def stored_node_count(n, hurst):
    """The stored max |Δa_rel| at N = n in nodes, an int (`measured.node_count`)."""
    v = measured.value(NAME, KEY, f"H={hurst:g}")
    return v["a_node_count"][v["N"].index(n)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the differences in verification/data/fe_selfaffine.json")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    values, step_s = {}, {}
    for hurst in HURSTS:
        outs = [compare(n, hurst) for n in NODES]
        values[f"H={hurst:g}"] = {"N": list(NODES), **{m: [float(o[m]) for o in outs] for m in METRICS if m != "a"},
                                  "a_node_count": [measured.node_count(o["a"], n) for o, n in zip(outs, NODES)]}
        step_s[f"H={hurst:g}"] = {"fe": [o["fe_step"] for o in outs], "gfmd": [o["gfmd_step"] for o in outs]}
    if args.write:
        print(measured.write(NAME, {KEY: measured.make_entry(values, scene="verification.scenes.cohesive_self_affine(N, H)",
                                                             step_s=step_s, wall_s=time.perf_counter() - t0)},
                             description="GFMD vs FE P2 on self-affine profiles (H = 0.8, 0.2; λs,H = L/64): t_n, p, ḡ_r, "
                                         "a_rel differences vs N"))


if __name__ == "__main__":
    main()
