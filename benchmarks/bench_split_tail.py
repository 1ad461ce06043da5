"""How often the cohesive NCG folds û's coarse tail into its spectrum (`gfmd.algorithms.ncg.FOLD_EVERY`), swept on a
whole ramp (issue 24).

Usage: python benchmarks/bench_split_tail.py [--size 17] [--realization 2] [--nu 0.45] [--phi 0.15]
       [--values 1 4 8 16 1000000] [--out FILE]

Writes benchmarks/results/bench_split_tail_e<size>_phi<φ>_nu<ν>_r<realization>.md (or --out).

Under the two-level preconditioner the NCG keeps û as a spectral part and a coarse tail, û = û_s + rfft(Π Z e_u)
(`gfmd.cohesive_preconditioner.TwoLevel.apply_split`), and takes its dot products from the parts
(`split_products`); their round-off grows with the tail against the force. A fold (one rfft) empties the tail: at
every force residual test (every `Settings.check_every` iterations at least), where the coarse space changes, where
the near set is rebuilt, and at least every FOLD_EVERY iterations. FOLD_EVERY = 1 folds before every application:
û_s is û, the products' tails are zero. The cohesive class of benchmarks/bench_adhesion_scaling.py (seed base scene,
δn = 1 nm; `--phi`, `--nu`), one whole ramp per value, one after the other in one process: iterations, FFT pairs per
step and CPU s, and the states against the first value's (max |Δû| / max |û| over the steps, max |Δp̄| / max |p̄|).
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

import numpy as np  # noqa: E402

from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from benchmarks.report import header  # noqa: E402
from gfmd.algorithms import ncg  # noqa: E402


def sweep(size, realization, nu, phi, values):
    """One row per FOLD_EVERY value: the ramp's cost, and its states against the first value's."""
    rows, reference, kept = [], None, ncg.FOLD_EVERY
    keys = {"material.poisson_ratio": nu, "interface.phi_n_star": phi}
    ramp(2**12, "cohesive", max_steps=3, scene_keys=keys)  # the process's one-time costs (kernels, plans) first
    try:
        for value in values:
            ncg.FOLD_EVERY = value
            t0 = time.process_time()
            steps = ramp(2**size, "cohesive", realization=realization, a_rel_stop=2.0, scene_keys=keys,
                         keep_u_hat=True)
            cpu = time.process_time() - t0
            reference = reference or steps
            du = max(float(np.max(np.abs(s["u_hat"] - r["u_hat"])) / np.max(np.abs(r["u_hat"])))
                     for s, r in zip(steps, reference))
            p_ref = max(abs(r["p"]) for r in reference)
            dp = max(abs(s["p"] - r["p"]) for s, r in zip(steps, reference)) / p_ref
            rows.append({"value": value, "steps": len(steps), "it": sum(s["it"] for s in steps),
                         "pairs": sum(s["pairs"] for s in steps) / len(steps), "cpu": cpu, "du": du, "dp": dp,
                         "converged": sum(s["converged"] for s in steps)})
            print(rows[-1], flush=True)
    finally:
        ncg.FOLD_EVERY = kept
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=17)
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.45)
    ap.add_argument("--phi", type=float, default=0.15)
    ap.add_argument("--values", type=int, nargs="+", default=[1, 4, 8, 16, 1_000_000])
    ap.add_argument("--out", type=Path)
    a = ap.parse_args(argv)
    rows = sweep(a.size, a.realization, a.nu, a.phi, a.values)
    name = f"bench_split_tail_e{a.size}_phi{a.phi:g}_nu{a.nu:g}_r{a.realization}.md"
    out = a.out or ROOT / "benchmarks" / "results" / name
    lines = header(f"The NCG's coarse tail: FOLD_EVERY swept, N = 2^{a.size}, φn* = {a.phi:g}, ν = {a.nu:g}, "
                   f"realization {a.realization}", "bench_split_tail.py", argv) + [
             "One process, one ramp after the other (a short ramp first: the process's one-time costs); CPU s on a "
             "shared 2-core machine. States against the first row's.", "",
             "| FOLD_EVERY | steps | converged | iterations | FFT pairs / step | CPU s | max |Δû| / max |û| | "
             "max |Δp̄| / max |p̄| |", "|---|---|---|---|---|---|---|---|"]
    lines += [f"| {r['value']} | {r['steps']} | {r['converged']} | {r['it']} | {r['pairs']:.2f} | {r['cpu']:.1f} | "
              f"{r['du']:.1e} | {r['dp']:.1e} |" for r in rows]
    text = "\n".join(lines) + "\n"
    out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
