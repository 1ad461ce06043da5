"""BLAS threads under `gfmd run`: OpenBLAS's own count against `gfmd.blas`'s one thread per relaxation (issue 24).

Usage: python benchmarks/bench_blas_threads.py [--size 15] [--realizations 2] [--repeats 2] [--out FILE]

`gfmd run` as a user runs it (the console script, a fresh process, --no-plot --quiet) on bench_adhesion_scaling's seed
base scene at N = 2^size (λs,H at 4 node spacings), realizations 2..: the hard wall, the normal cohesive law (φn* =
0.15) and the coupled law (c = 0.5, δt = 1 nm, ν = 0.1), each with --workers 1 and 2, under two environments:
"threaded" (OPENBLAS_NUM_THREADS = the core count: what numpy's and scipy's OpenBLAS start by default, and what
every GFMD step ran with outside Dask and the benchmarks before `gfmd.blas`; set, so `gfmd.blas` leaves it) and
"one" (no thread variable: `gfmd.blas.one_thread` around each step, the default). Wall s and CPU s (user + system of
the run's processes, getrusage) per run; --repeats alternates the two. Writes benchmarks/results/bench_blas_threads.md
(or --out).
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.report import header, write  # noqa: E402
from gfmd.blas import THREAD_VARIABLES  # noqa: E402

#: the scenes: seed_base.toml's keys per law
LAWS = {"hard wall": {"law": "hard-wall", "tangential_ratio": 0.0, "poisson_ratio": 0.45},
        "normal cohesive": {"law": "cohesive", "tangential_ratio": 0.0, "poisson_ratio": 0.45},
        "coupled, ν = 0.1": {"law": "cohesive", "tangential_ratio": 0.5, "poisson_ratio": 0.1}}
SETTINGS = ("threaded", "one")


def scene_text(size, realizations, law):
    """seed_base.toml at N = 2^size with the law's keys and `realizations` realizations (seeds 2..)."""
    n = 2 ** size
    keys = {"nodes": str(n), "rollon_wavelength": repr(max(2.5e-9, 4 * 10.24e-6 / n)), "seed": "2",
            "realizations": str(realizations), "law": f'"{law["law"]}"',
            "tangential_ratio": repr(law["tangential_ratio"]), "poisson_ratio": repr(law["poisson_ratio"])}
    lines = []
    for line in (ROOT / "studies" / "seed" / "seed_base.toml").read_text().splitlines():
        key = line.split("=")[0].strip()
        lines.append(f"{key} = {keys[key]}" if key in keys and "=" in line else line)
    return "\n".join(lines) + "\n"


def run(scene, workers, setting, tmp):
    """(wall s, CPU s) of one `gfmd run`."""
    env = {k: v for k, v in os.environ.items() if k not in THREAD_VARIABLES}
    if setting == "threaded":
        env["OPENBLAS_NUM_THREADS"] = str(os.cpu_count())
    out = Path(tmp) / "out"
    shutil.rmtree(out, ignore_errors=True)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run([shutil.which("gfmd") or "gfmd", "run", str(scene), "--out", str(out), "--workers", str(workers),
                    "--no-plot", "--quiet"], env=env, check=True, capture_output=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=15)
    ap.add_argument("--realizations", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--out", default=ROOT / "benchmarks" / "results" / "bench_blas_threads.md")
    args = ap.parse_args(argv)
    lines = header(f"BLAS threads under `gfmd run`, N = 2^{args.size}, {args.realizations} realizations",
                   "bench_blas_threads.py", argv, note=f"{os.cpu_count()}-core machine")
    runs = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, law in LAWS.items():
            scene = Path(tmp) / "scene.toml"
            scene.write_text(scene_text(args.size, args.realizations, law))
            for _ in range(args.repeats):
                for workers in (1, 2):
                    for setting in SETTINGS:
                        runs.setdefault((name, workers, setting), []).append(run(scene, workers, setting, tmp))
                        print(name, workers, setting, runs[(name, workers, setting)][-1], flush=True)
    lines += ["`gfmd run SCENE --workers W --no-plot --quiet` in a fresh process; threaded: OPENBLAS_NUM_THREADS = "
              f"{os.cpu_count()} (OpenBLAS's default here, what GFMD ran with before gfmd.blas); one: gfmd.blas's one "
              "thread per relaxation (the default). Wall s and CPU s per repeat.", "",
              "| law | workers | threaded wall s | one wall s | threaded / one (wall, best) | threaded CPU s "
              "| one CPU s |",
              "|---|---|---|---|---|---|---|"]
    for name in LAWS:
        for workers in (1, 2):
            th, one = runs[(name, workers, "threaded")], runs[(name, workers, "one")]
            ratio = min(w for w, _ in th) / min(w for w, _ in one)
            lines.append(f"| {name} | {workers} | {', '.join(f'{w:.1f}' for w, _ in th)} | "
                         f"{', '.join(f'{w:.1f}' for w, _ in one)} | **{ratio:.2f}** | "
                         f"{', '.join(f'{c:.1f}' for _, c in th)} | {', '.join(f'{c:.1f}' for _, c in one)} |")
    write(lines, args.out)


if __name__ == "__main__":
    main()
