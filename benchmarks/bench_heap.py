"""The allocator's share of a ramp: glibc's defaults against the heap `gfmd.heap` keeps (issue 24).

Usage: python benchmarks/bench_heap.py [--size 17] [--realization 2] [--nu 0.45] [--repeats 1] [--out FILE]

Whole 201-step ramps of bench_adhesion_scaling's seed base scene (φn* = 0.15) for the normal law (c = 0, the NCG)
and the coupled law (c = 0.5, the Newton–Krylov chain), each in a fresh process under three allocator settings:
"dask" (MALLOC_TRIM_THRESHOLD_=65536, what Dask's nannies give their workers by default, and so the study's workers
had before session 50; `gfmd.heap` leaves it alone), "glibc" (GFMD_KEEP_HEAP=0: glibc's defaults) and "kept"
(`gfmd.heap.keep_heap`, the default), one after the other: user and system CPU s and the page faults of the ramp
(getrusage), FFT pairs per step; then the coupled / normal CPU ratio per setting (issue 24's 2× target). --repeats
runs the six processes that many times, alternating. Writes
benchmarks/results/bench_heap_e<size>_nu<nu>_r<realization>.md (or --out).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.report import header, write  # noqa: E402

WORKER = """
import json, resource, sys, time
from benchmarks.bench_adhesion_scaling import ramp
import gfmd.heap
n, cls, realization, nu = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
before = resource.getrusage(resource.RUSAGE_SELF)
rows = ramp(n, cls, realization=realization, scene_keys={"material.poisson_ratio": nu}, a_rel_stop=1.0)
after = resource.getrusage(resource.RUSAGE_SELF)
print(json.dumps({"user": after.ru_utime - before.ru_utime, "sys": after.ru_stime - before.ru_stime,
                  "faults": after.ru_minflt - before.ru_minflt, "steps": len(rows),
                  "converged": sum(bool(r["converged"]) for r in rows),
                  "pairs": sum(r["pairs"] for r in rows) / len(rows), "heap": gfmd.heap.STATE}))
"""


#: the settings: their environment
SETTINGS = {"dask": {"MALLOC_TRIM_THRESHOLD_": "65536"}, "glibc": {"GFMD_KEEP_HEAP": "0"},
            "kept": {"GFMD_KEEP_HEAP": "1"}}


def run(n, cls, realization, nu, setting):
    env = {k: v for k, v in os.environ.items() if not k.startswith("MALLOC_") and k != "GFMD_KEEP_HEAP"}
    env.update(SETTINGS[setting], OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", WORKER, str(n), cls, str(realization), str(nu)], cwd=ROOT, env=env,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=17)
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.45)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--out")
    args = ap.parse_args(argv)
    n = 2 ** args.size
    runs = {}
    for _ in range(args.repeats):
        for setting in SETTINGS:
            for cls in ("cohesive", "coupled"):
                runs.setdefault((setting, cls), []).append(run(n, cls, args.realization, args.nu, setting))
    lines = header(f"The allocator's share of a ramp, N = 2^{args.size}, ν = {args.nu}, realization {args.realization}",
                   "bench_heap.py", argv)
    lines += ["Each row a whole 201-step ramp in a fresh process (getrusage over the ramp); the allocator as "
              "`gfmd.heap.STATE` says: " + "; ".join(f"{k}: {runs[(k, 'coupled')][0]['heap']} ({v})"
                                                    for k, v in SETTINGS.items()) + ".",
              "", "| law | heap | run | steps converged | FFT pairs / step | user CPU s | system CPU s | page faults |",
              "|---|---|---|---|---|---|---|---|"]
    for (setting, cls), rows in runs.items():
        for i, r in enumerate(rows):
            lines.append(f"| {cls} | {setting} | {i + 1} | {r['converged']}/{r['steps']} | {r['pairs']:.2f} | "
                         f"{r['user']:.1f} | {r['sys']:.2f} | {r['faults']:,} |")
    lines += ["", "| heap | normal CPU s | coupled CPU s | coupled / normal |", "|---|---|---|---|"]
    for setting in SETTINGS:
        cpu = {cls: min(r["user"] + r["sys"] for r in runs[(setting, cls)]) for cls in ("cohesive", "coupled")}
        lines.append(f"| {setting} | {cpu['cohesive']:.1f} | "
                     f"{cpu['coupled']:.1f} | **{cpu['coupled'] / cpu['cohesive']:.2f}** |")
    lines += ["", "CPU s: user + system, the fastest of the repeats."]
    out = args.out or ROOT / "benchmarks" / "results" / f"bench_heap_e{args.size}_nu{args.nu}_r{args.realization}.md"
    write(lines, out)


if __name__ == "__main__":
    main()
