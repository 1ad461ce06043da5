"""The cohesive NCG's preconditioners compared along one ramp (issue 24, `gfmd.cohesive_preconditioner`).

Usage: python benchmarks/bench_cohesive_preconditioner.py [--size 14] [--realization 2] [--length-normal 0.25e-9]
                                                         [--preconditioners stiffness two-level two-level:F]
                                                         [--max-steps M]
                                                         [--a-rel-stop 0.5] [--out FILE] [--dump FILE]
       python benchmarks/bench_cohesive_preconditioner.py --merge DUMP1 DUMP2 [--out FILE]

The cohesive class of benchmarks/bench_adhesion_scaling.py (seed base scene, φn* = 0.15, c = 0) on the given
realization (surface seed) and δn, relaxed once per `Settings.cohesive_preconditioner` in the same process,
the first one the reference. Per a_rel bin (of the reference's accepted states): steps, iterations, FFT pairs
(deterministic) and CPU s per step (time.process_time, MEASURED UNDER LOAD: the load average is printed); and
the largest per-step differences of p̄ (relative to the ramp's largest |p̄|), a_rel and the gap against the
reference (each step converged to Settings.tolerance; a different branch of a jump-in shows as a gap
difference of the order of δn). --dump saves a run (rows and float32 gaps, pickle) instead of the table, so
that two preconditioners run as two simultaneous processes; --merge tabulates such dumps, the first the reference.
"two-level:F" runs the two-level preconditioner with `gfmd.cohesive_preconditioner.STIFF_FRACTION` = F (the share of
φn/δn² above which a node's max(k_loc, 0) puts it in the coarse space).
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_adhesion_scaling import A_REL_STOP, ramp  # noqa: E402
from gfmd import cohesive_preconditioner  # noqa: E402

STIFF_FRACTION = cohesive_preconditioner.STIFF_FRACTION  # the module's value, restored after each run

BINS = (0.0, 0.02, 0.05, 0.1, 0.2, np.inf)


def binned(rows, ref_rows):
    """Per a_rel bin (by the reference's a_rel): (label, steps, it/step, pairs/step, CPU s/step)."""
    a = np.array([r["a_rel"] for r in ref_rows])
    out = []
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        sel = [i for i in range(min(len(rows), len(a))) if lo <= a[i] < hi and (lo > 0 or a[i] > 0)]
        if not sel:
            continue
        label = f"{lo:g}–{hi:g}" if np.isfinite(hi) else f"> {lo:g}"
        if lo == 0:
            label = f"(0, {hi:g})"
        out.append((label, len(sel), np.mean([rows[i]["it"] for i in sel]), np.mean([rows[i]["pairs"] for i in sel]),
                    np.mean([rows[i]["cpu"] for i in sel])))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=14, help="exponent e of N = 2^e")
    ap.add_argument("--realization", type=int, default=2, help="surface seed (seed_base.toml: 1)")
    ap.add_argument("--length-normal", type=float, default=0.25e-9, help="interface.length_normal δn (m)")
    ap.add_argument("--preconditioners", nargs="+", default=["stiffness", "two-level"])
    ap.add_argument("--max-steps", type=int, default=None)
    ap.add_argument("--a-rel-stop", type=float, default=A_REL_STOP)
    ap.add_argument("--out", default=None)
    ap.add_argument("--dump", default=None)
    ap.add_argument("--merge", nargs="+", default=None)
    args = ap.parse_args(argv)
    if args.merge:
        runs, meta = {}, None
        for path in args.merge:
            with open(path, "rb") as fh:
                d = pickle.load(fh)
            runs.update(d["runs"])
            meta = meta or d["meta"]
        return report(runs, meta, argv, args.out)
    n = 2**args.size
    keys = {"interface.length_normal": args.length_normal}
    load0 = os.getloadavg()[0]
    runs = {}
    for name in args.preconditioners:
        setting, _, fraction = name.partition(":")  # "two-level:F": with cohesive_preconditioner.STIFF_FRACTION = F
        cohesive_preconditioner.STIFF_FRACTION = float(fraction) if fraction else STIFF_FRACTION
        ramp(min(n, 2**12), "cohesive", {"cohesive_preconditioner": setting}, max_steps=3)  # numba / plans untimed
        states = []
        t0 = time.process_time()
        rows = ramp(n, "cohesive", {"cohesive_preconditioner": setting}, args.max_steps, args.realization, keys,
                    args.a_rel_stop, states)
        cohesive_preconditioner.STIFF_FRACTION = STIFF_FRACTION
        runs[name] = rows, [s.astype(np.float32) for s in states] if args.dump else states
        print(f"{name}: {len(rows)} steps, {time.process_time() - t0:.1f} CPU s, "
              f"{sum(r['pairs'] for r in rows):.0f} pairs", flush=True)
    meta = {"size": args.size, "realization": args.realization, "length_normal": args.length_normal, "load0": load0}
    if args.dump:
        with open(args.dump, "wb") as fh:
            pickle.dump({"runs": runs, "meta": meta}, fh)
        return None
    return report(runs, meta, argv, args.out)


def report(runs, meta, argv, out_path):
    """The markdown table of `runs` {preconditioner: (rows, gaps)}, the first the reference; appended to out_path."""
    ref = next(iter(runs))
    length_normal = meta["length_normal"]
    ref_rows, ref_states = runs[ref]
    commit = os.popen(f"git -C {ROOT} rev-parse --short HEAD").read().strip()
    text = [f"### N = 2^{meta['size']}, realization (seed) {meta['realization']}, δn = {length_normal:g} m, φn* = 0.15",
            "", f"`python benchmarks/bench_cohesive_preconditioner.py {' '.join(argv or sys.argv[1:])}`; git {commit} "
            f"(+ working tree); load average {meta['load0']:.2f} at start, {os.getloadavg()[0]:.2f} at end (CPU s under load).",
            "", "| a_rel bin | steps | " + " | ".join(f"{p}: it/step | pairs/step | CPU s/step" for p in runs) + " |",
            "|---|---|" + "---|---|---|" * len(runs)]
    tables = {p: binned(rows, ref_rows) for p, (rows, _) in runs.items()}
    for i, (label, steps, *_) in enumerate(tables[ref]):
        cells = " | ".join(f"{tables[p][i][2]:.1f} | {tables[p][i][3]:.1f} | {tables[p][i][4]:.3g}" for p in runs)
        text.append(f"| {label} | {steps} | {cells} |")
    totals = " | ".join(f"{sum(r['it'] for r in rows)} | {sum(r['pairs'] for r in rows):.0f} | "
                        f"{sum(r['cpu'] for r in rows):.1f}" for rows, _ in runs.values())
    text.append(f"| whole ramp (sums) | {len(ref_rows)} | {totals} |")
    text.append("")
    p_scale = max(abs(r["p"]) for r in ref_rows)
    for name, (rows, states) in runs.items():
        if name == ref:
            continue
        m = min(len(rows), len(ref_rows))
        dp = max(abs(rows[i]["p"] - ref_rows[i]["p"]) for i in range(m)) / p_scale
        da = max(abs(rows[i]["a_rel"] - ref_rows[i]["a_rel"]) for i in range(m))
        dg = [float(np.max(np.abs(states[i] - ref_states[i]))) for i in range(m)]
        far = sum(g > 0.1 * length_normal for g in dg)
        conv = sum(r["converged"] for r in rows)
        text.append(f"{name} vs {ref}: max |Δp̄| / max|p̄| = {dp:.2e}, max |Δa_rel| = {da:.2e}, max |Δgap| = "
                    f"{max(dg):.2e} m; steps with |Δgap| > 0.1 δn: {far} of {m}; converged {conv}/{len(rows)}; "
                    f"algorithms {'/'.join(sorted({r['method'] for r in rows}))}")
    out = "\n".join(text) + "\n"
    print(out)
    if out_path:
        with open(out_path, "a") as fh:
            fh.write(out + "\n")
    return out


if __name__ == "__main__":
    main()
