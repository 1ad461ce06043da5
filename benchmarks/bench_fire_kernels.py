"""FIRE's per-iteration spectral algebra fused (`gfmd.fire_kernels`) against numpy's passes, on whole coupled ramps.

Usage: python benchmarks/bench_fire_kernels.py [--sizes 13 15] [--realization 2] [--nu 0.45] [--repeats 2]
                                               [--out FILE]

The coupled class of benchmarks/bench_adhesion_scaling.py (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, the
default chain; `--nu` sets material.poisson_ratio), whose event steps run FIRE to the handover residual: one ramp per
N and `gfmd.fire_kernels.FUSED` (False, then True), alternating `--repeats` times in one process (the same load on
both), reusing freed arrays as a study worker does: CPU s per ramp and on its event steps (not "newton"), FIRE's
share of the FFT pairs, and the largest differences of p̄ and a_rel and the steps whose chain label differs, against
numpy. Writes benchmarks/results/bench_fire_kernels.md (or --out).
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
from benchmarks.report import header, ramp_row, write  # noqa: E402
from gfmd import fire_kernels  # noqa: E402
from gfmd_contact.app.study_task import reuse_freed_arrays  # noqa: E402

VARIANTS = {"numpy": False, "fused": True}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[13, 15])
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.45)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_fire_kernels.md"))
    args = ap.parse_args(argv)
    reuse_freed_arrays()
    lines = header("FIRE's spectral algebra fused (`gfmd.fire_kernels`) against numpy's passes", "bench_fire_kernels.py",
                   argv, f"2-core machine; ν = {args.nu:g}, realization {args.realization}; CPU s alternate the "
                   "variants in one process")
    lines += ["| N | FIRE algebra | CPU s per ramp (each repeat) | median | on event steps (median) | FFT pairs | "
              "event steps | max |Δp̄|/max|p̄| | max |Δa_rel| | labels differ |", "|---|---|---|---|---|---|---|---|---|---|"]
    for size in args.sizes:
        runs = {v: [] for v in VARIANTS}
        for _ in range(args.repeats):
            for variant, fused in VARIANTS.items():
                fire_kernels.FUSED = fused
                t0 = time.process_time()
                rows = ramp(2**size, "coupled", realization=args.realization, a_rel_stop=2.0,
                            scene_keys={"material.poisson_ratio": args.nu})
                runs[variant].append((time.process_time() - t0, rows))
        fire_kernels.FUSED = True
        for variant, got in runs.items():
            events = np.median([sum(r["cpu"] for r in x if r["method"] != "newton") for _, x in got])
            lines.append(ramp_row(size, variant, [c for c, _ in got], got[0][1], runs["numpy"][0][1],
                                  (f"{events:.2f}",)))
            print(lines[-1], flush=True)
    write(lines, args.out)


if __name__ == "__main__":
    main()
