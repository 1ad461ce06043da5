"""The FFT backends of `gfmd.fft` per rfft/irfft pair and on whole ramps, in one run (issue 24).

Usage: python benchmarks/bench_fft.py [--quick] [--sizes 12 14 16 17 18 20] [--ramp-size 17]
       [--classes cohesive hard-wall coupled] [--out FILE] [--data FILE]

1. One rfft/irfft pair through `gfmd.fft.Fft` per N and shape ((N,): the normal laws; (2, N): the coupled law's
   u_x, u_z) and backend: scipy.fft, ducc0, FFTW planned FFTW_ESTIMATE and FFTW planned FFTW_MEASURE (the default
   from `FFTW_MEASURE_FROM` points, its plans kept as wisdom); the backends alternate in rounds and each time is
   the median round, so a drift of the machine's speed falls on all alike. The FFTW_MEASURE plan's first making
   (cold, an empty wisdom file) and its making again from wisdom (what every later process pays) are timed too.
2. Whole ramps (`benchmarks.bench_adhesion_scaling.ramp`, seed base scene, realization 2, to a_rel = 0.5) of each
   class at N = 2^ramp-size with GFMD_FFT = ducc0 (the default before) and fftw (now), as two simultaneous processes
   pinned to one core each, twice, the cores swapped: the CPU ratio is the geometric mean of the two runs' ratios
   (the cores' difference cancels), half their difference the noise left (CPU time on this 2-core machine moves
   by up to 25 % with what runs on the other core). The plans are made (from wisdom) before the timed ramp. Per
   ramp: CPU s, iterations, FFT pairs and the states against ducc0's (max |Δp̄| / max |p̄|, max |Δa_rel|).

Writes benchmarks/results/bench_fft{,_quick,_<classes>}.md and the ratios to bench_fft.json, which
tests/test_fftw_plans.py reads (the default backend must be the one measured fastest on the ramps).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks import report  # noqa: E402
from benchmarks.report import header, ramp_differences, write  # noqa: E402
from gfmd import fft as gfft  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
VARIANTS = ("scipy", "ducc0", "fftw estimate", "fftw measure")
#: the ramps' scene keys per class (on bench_adhesion_scaling's "cohesive" class: φn* = 0.15, c = 0); "coupled"
#: (Fig. 8's c = 0.5, δt = 1 nm: spectra of shape (2, N)) runs with --classes coupled, its rows added to the data file
RAMP_KEYS = {"cohesive": {}, "hard-wall": {"interface.law": "hard-wall"},
             "coupled": {"interface.tangential_ratio": 0.5, "interface.length_tangential": 1e-9}}


def _pair_seconds(fft, x, reps):
    t = time.perf_counter()
    for _ in range(reps):
        fft.irfft(fft.rfft(x))
    return (time.perf_counter() - t) / reps


def pair_table(sizes, rounds):
    """Section 1's rows: per (N, shape) the median seconds per pair of every variant and the plan times."""
    rows, measure_from = [], gfft.FFTW_MEASURE_FROM
    for size in sizes:
        n = 2**size
        for lead in ((), (2,)):
            x = np.random.default_rng(size).standard_normal(lead + (n,))
            reps = max(3, int(2**22 / (n * max(len(lead) * 2, 1))))
            ffts, plans, plan_s = {}, {}, {}
            for v in VARIANTS:
                if v.startswith("fftw"):
                    if gfft._pyfftw is None:
                        continue
                    plans[v] = {}
                    gfft._FFTW_LOCAL.plans = plans[v]
                    gfft.FFTW_MEASURE_FROM = 1 if v == "fftw measure" else 2**62
                    t = time.perf_counter()
                    gfft.Fft(n, "fftw").rfft(x)
                    plan_s[v] = time.perf_counter() - t
                    if v == "fftw measure":  # again from the wisdom just written, as a later process does
                        gfft._FFTW_LOCAL.plans = {}
                        t = time.perf_counter()
                        gfft.Fft(n, "fftw").rfft(x)
                        plan_s["fftw from wisdom"] = time.perf_counter() - t
                        gfft._FFTW_LOCAL.plans = plans[v]
                elif v == "ducc0" and gfft._ducc_fft is None:
                    continue
                ffts[v] = gfft.Fft(n, v.split()[0])
            times = {v: [] for v in ffts}
            for _ in range(rounds):
                for v, fft in ffts.items():
                    if v in plans:
                        gfft._FFTW_LOCAL.plans = plans[v]
                    fft.irfft(fft.rfft(x))
                    times[v].append(_pair_seconds(fft, x, reps))
            rows.append({"size": size, "shape": "(2, N)" if lead else "(N,)",
                         "pair_ms": {v: 1e3 * float(np.median(t)) for v, t in times.items()},
                         "plan_s": plan_s})
    gfft._FFTW_LOCAL.plans, gfft.FFTW_MEASURE_FROM = {}, measure_from
    return rows


def _ramp_worker(args):
    """One ramp with GFMD_FFT = args.worker on core args.cpu: its rows as JSON to args.dump."""
    from benchmarks.bench_adhesion_scaling import ramp
    from gfmd_contact.app.study_task import reuse_freed_arrays

    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {args.cpu})
    os.environ["GFMD_FFT"] = args.worker
    reuse_freed_arrays()
    ramp(2**12, "cohesive", max_steps=3)  # numba's compilation and the caches outside the measured ramp
    n = 2**args.ramp_size
    for lead in ((), (2,)):  # this size's plans (from wisdom) outside the measured ramp
        gfft.Fft(n).irfft(gfft.Fft(n).rfft(np.zeros(lead + (n,))))
    steps = ramp(n, "cohesive", realization=2, scene_keys=RAMP_KEYS[args.cls])
    Path(args.dump).write_text(json.dumps([{k: s[k] for k in ("it", "pairs", "cpu", "a_rel", "p", "converged",
                                                               "method")} for s in steps]))


def _simultaneous(args, cls, backends):
    return report.simultaneous([[sys.executable, __file__, "--ramp-size", str(args.ramp_size), "--worker", backend,
                                 "--cls", cls] for backend in backends])


def ramp_rows(args):
    """Section 2: per class, ducc0 and fftw beside each other twice (cores swapped): rows and the CPU ratios."""
    n = 2**args.ramp_size
    for lead in ((), (2,)):  # the measured plans into the wisdom file before any timed ramp
        gfft.Fft(n, "fftw").rfft(np.zeros(lead + (n,)))
    rows, ratios = [], {}
    for cls in args.classes:
        ref0, new1 = _simultaneous(args, cls, ["ducc0", "fftw"])
        new0, ref1 = _simultaneous(args, cls, ["fftw", "ducc0"])
        entry = []
        for label, steps in (("ducc0, core 0", ref0), ("fftw, core 1", new1), ("fftw, core 0", new0),
                             ("ducc0, core 1", ref1)):
            dp, da, _ = ramp_differences(steps, ref0)
            entry.append({"class": cls, "run": label, "steps": len(steps), "cpu_s": sum(s["cpu"] for s in steps),
                          "iterations": sum(s["it"] for s in steps), "fft_pairs": sum(s["pairs"] for s in steps),
                          "converged": sum(s["converged"] for s in steps), "dp_rel": dp, "da_rel": da})
        rows += entry
        r1, r2 = entry[1]["cpu_s"] / entry[0]["cpu_s"], entry[2]["cpu_s"] / entry[3]["cpu_s"]
        ratios[cls] = {"fftw_over_ducc0": float(np.sqrt(r1 * r2)), "noise": abs(r1 - r2) / 2.0,
                       "size": args.ramp_size}
    return rows, ratios


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 2^12, 2^14 pairs; ramps at 2^14")
    ap.add_argument("--sizes", type=int, nargs="*", help="section 1's N = 2^size (none: section 2 alone)")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--ramp-size", type=int)
    ap.add_argument("--classes", nargs="+", default=["cohesive", "hard-wall"], choices=list(RAMP_KEYS))
    ap.add_argument("--out")
    ap.add_argument("--data", default=str(RESULTS / "bench_fft.json"))
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--cls", help=argparse.SUPPRESS)
    ap.add_argument("--dump", help=argparse.SUPPRESS)
    ap.add_argument("--cpu", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        return _ramp_worker(args)
    if gfft._pyfftw is None:
        raise SystemExit("pyfftw is not installed: nothing to compare (pip install pyfftw)")
    sizes = args.sizes if args.sizes is not None else ([12, 14] if args.quick else [12, 14, 15, 16, 17, 18, 20])
    args.ramp_size = args.ramp_size or (14 if args.quick else 17)
    with tempfile.TemporaryDirectory() as cold:
        os.environ["GFMD_FFTW_WISDOM"] = cold  # section 1's plan times from an empty wisdom file
        pairs = pair_table(sizes, args.rounds)
    del os.environ["GFMD_FFTW_WISDOM"]
    ramps, ratios = ramp_rows(args)
    lines = header("FFT backends per rfft/irfft pair and on whole ramps", "bench_fft.py", argv,
                   note="2-core machine; ramps: two simultaneous processes per pair")
    lines += [] if not pairs else ["## 1. One rfft/irfft pair (ms, median of the rounds) and FFTW's plan times", "",
              "| N | shape | scipy | ducc0 | FFTW estimate | FFTW measure | ducc0 / FFTW measure "
              "| measure plan, cold s | from wisdom s |", "|" + "---|" * 9]
    for r in pairs:
        t = r["pair_ms"]
        cells = [f"2^{r['size']}", r["shape"], *(f"{t[v]:.3f}" if v in t else "–" for v in VARIANTS),
                 f"{t['ducc0'] / t['fftw measure']:.2f}" if "ducc0" in t else "–",
                 f"{r['plan_s'].get('fftw measure', float('nan')):.2f}",
                 f"{r['plan_s'].get('fftw from wisdom', float('nan')):.3f}"]
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", f"## 2. Whole ramps at N = 2^{args.ramp_size} (realization 2, to a_rel = 0.5): GFMD_FFT = ducc0 and "
              "fftw side by side", "",
              "| class | run | steps | CPU s | iterations | FFT pairs | converged | max Δp̄ / max p̄ "
              "| max Δa_rel |",
              "|" + "---|" * 9]
    for r in ramps:
        lines.append(f"| {r['class']} | {r['run']} | {r['steps']} | {r['cpu_s']:.1f} | {r['iterations']} | "
                     f"{r['fft_pairs']:.0f} | {r['converged']}/{r['steps']} | {r['dp_rel']:.1e} | {r['da_rel']:.1e} |")
    lines += ["", "CPU ratio fftw / ducc0 (geometric mean of the two core placements ± half their difference): " +
              "; ".join(f"{c} {v['fftw_over_ducc0']:.3f} ± {v['noise']:.3f}" for c, v in ratios.items()) + "."]
    default = set(args.classes) == {"cohesive", "hard-wall"}
    suffix = "_quick" if args.quick else "" if default else "_" + "_".join(args.classes)
    out = args.out or RESULTS / f"bench_fft{suffix}.md"
    write(lines, out)
    if not args.quick:  # merged into what other runs measured (--classes, --sizes)
        data = json.loads(Path(args.data).read_text()) if Path(args.data).exists() else {}
        data["pairs"] = pairs or data.get("pairs", [])
        data["ramps"] = {**data.get("ramps", {}), **ratios}
        data["rows"] = [r for r in data.get("rows", []) if r["class"] not in ratios] + ramps
        Path(args.data).write_text(json.dumps(data, indent=1) + "\n")


if __name__ == "__main__":
    main()
