"""FFT pairs per load step over the seed's Fig. 3 strong-adhesion tasks (issue 24's target: mean ≤ 40 at φn* = 0.15).

Usage: python benchmarks/bench_fig3_pairs.py [--size 17] [--phi 0.15] [--realizations 1 2 ... 10] [--out FILE]

Writes benchmarks/results/bench_fig3_pairs_e<size>_phi<φ>.md (or --out).

The cohesive class of benchmarks/bench_adhesion_scaling.py is Fig. 3's task (seed base scene: H = 0.8, ν = 0.45,
δn = 1 nm, φn* = `--phi`); realization r is the surface seed r, so realizations 1–10 are the study's ten
(studies/seed/fig3.toml: seeds surface.seed + 0 … 9, surface.seed = 1). Each whole 201-step ramp at N = 2^size runs as
the study runs it (the default solver and its warm start); per realization: steps, converged steps, iterations,
FFT pairs (every algorithm that ran, `Relaxed.fft_pairs`), pairs per step and CPU s; then the mean pairs per step
over every step of every realization. Pair counts are deterministic; CPU s are one run on a shared machine.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from benchmarks.report import header  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=17)
    ap.add_argument("--phi", type=float, default=0.15)
    ap.add_argument("--realizations", type=int, nargs="+", default=list(range(1, 11)))
    ap.add_argument("--out", type=Path)
    a = ap.parse_args(argv)
    keys = {"material.poisson_ratio": 0.45, "interface.phi_n_star": a.phi}
    rows = []
    for r in a.realizations:
        t0 = time.process_time()
        steps = ramp(2**a.size, "cohesive", realization=r, a_rel_stop=2.0, scene_keys=keys)
        rows.append({"r": r, "steps": len(steps), "converged": sum(s["converged"] for s in steps),
                     "it": sum(s["it"] for s in steps), "pairs": sum(s["pairs"] for s in steps),
                     "cpu": time.process_time() - t0})
        print(rows[-1], flush=True)
    steps, pairs = sum(r["steps"] for r in rows), sum(r["pairs"] for r in rows)
    lines = header(f"FFT pairs per step, Fig. 3's φn* = {a.phi:g} tasks at N = 2^{a.size}", "bench_fig3_pairs.py",
                   argv) + [
             "| realization | steps | converged | iterations | FFT pairs | pairs / step | CPU s |",
             "|---|---|---|---|---|---|---|"]
    lines += [f"| {r['r']} | {r['steps']} | {r['converged']} | {r['it']} | {r['pairs']:.1f} | "
              f"{r['pairs'] / r['steps']:.2f} | {r['cpu']:.1f} |" for r in rows]
    lines += ["", f"**Mean over {steps} steps: {pairs / steps:.2f} FFT pairs per step** "
              f"({sum(r['converged'] for r in rows)} converged; {sum(r['it'] for r in rows) / steps:.2f} iterations "
              "per step)."]
    text = "\n".join(lines) + "\n"
    out = a.out or ROOT / "benchmarks" / "results" / f"bench_fig3_pairs_e{a.size}_phi{a.phi:g}.md"
    out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
