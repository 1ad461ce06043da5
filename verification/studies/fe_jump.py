"""GFMD vs FE through a jump into contact: t_n, p(δ), a_rel differences at N = 128.

Scene: `verification.scenes.jump_in_sinusoid` (the cohesive sinusoid at φn* = 0.15, δ0 = 10 nm ≥ 8 δn,
δ from −10 nm to 40 nm in 25 steps). The FE Newton solve fails at the jump and falls back to
pseudo-transient continuation (energy descent); GFMD (FIRE) relaxes dynamically. Differences as in
`verification.runs.fe_vs_gfmd` (t_n relative L2 max over the field steps, p(δ) max |Δp|/max |p|,
max |Δa_rel|), and the FE steps that needed the fallback.

    python -m verification.studies.fe_jump [--write]

`--write` stores them in verification/data/fe_jump.json (entry "ci"), which test_fe_jump.py reads.
"""

from __future__ import annotations

import argparse
import time

from verification import measured
from verification.runs import fe_vs_gfmd
from verification.scenes import jump_in_sinusoid

NAME = "fe_jump"
N = 128


def study(n=N):
    """{"scene", "out" (fe_vs_gfmd), "values" {tn, p, a, fe_fallback_steps}, "wall_s"}."""
    sc = jump_in_sinusoid(n)
    t0 = time.perf_counter()
    out = fe_vs_gfmd(sc)
    vals = {"N": n, "tn": float(out["tn"]), "p": float(out["p"]), "a": float(out["a"]),
            "fe_fallback_steps": [int(k) for k in out["rf"].diagnostics["fallback_steps"]]}
    return {"scene": sc, "out": out, "values": vals, "wall_s": time.perf_counter() - t0}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the differences in verification/data/fe_jump.json")
    args = ap.parse_args(argv)
    st = study()
    print(st["values"], f"{st['wall_s']:.1f} s")
    if args.write:
        print(measured.write(NAME, {"ci": measured.make_entry(st["values"], scene=f"verification.scenes.jump_in_sinusoid({N})",
                                                              subset="ci", wall_s=st["wall_s"])},
                             description="GFMD vs FE P2 through a jump into contact (φn* = 0.15, N = 128): "
                                         "t_n, p(δ), a_rel differences"))


if __name__ == "__main__":
    main()
