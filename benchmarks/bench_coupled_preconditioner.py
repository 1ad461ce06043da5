"""The coupled Newton's two-level preconditioner (`gfmd.coupled_preconditioner`) against K⁻¹ alone, on whole ramps.

Usage: python benchmarks/bench_coupled_preconditioner.py [--sizes 13 15] [--realization 2] [--nu 0.45]
           [--max-steps 201] [--repeats 1] [--variants stiffness two-level] [--rows DIR] [--out FILE]

The coupled class of benchmarks/bench_adhesion_scaling.py (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, the
default chain "handover-near"; `--nu` sets material.poisson_ratio), one ramp per N and
`gfmd.coupled_preconditioner.CHOICE` ("stiffness", then "two-level"), alternating `--repeats` times in one process
(the same load on both): CPU s per ramp (time.process_time), FFT pairs, GMRES products per solve (mean over the
ramp's Newton solves), event steps (not "newton"), the coarse space's own cost (its builds and coarse solves,
time.process_time inside them) and the largest differences of p̄ and a_rel and the steps whose chain label differs,
against "stiffness". The process reuses freed arrays as a study worker does (`gfmd_contact.app.study_task.reuse_freed_arrays`).
At 2^17 run each variant in its own process at once (`--variants stiffness` beside `--variants two-level`, both with
`--rows DIR`: each saves its ramp there), then `--from-rows DIR` writes the table of what DIR holds.
Writes benchmarks/results/bench_coupled_preconditioner.md (or --out).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from benchmarks.report import header, ramp_row, write  # noqa: E402
from gfmd import coupled_krylov, coupled_preconditioner  # noqa: E402
from gfmd_contact.app.study_task import reuse_freed_arrays  # noqa: E402

VARIANTS = ("stiffness", "two-level")


class Meter:
    """Counts GMRES solves and products and the coarse space's CPU time while installed."""

    def __init__(self):
        self.solves = self.products = 0
        self.coarse_s = 0.0
        self._gmres, self._space = coupled_krylov.gfmd_gmres.gmres, coupled_preconditioner.coarse_space
        self._coefficients = coupled_preconditioner.CoarseSpace.coefficients

    def __enter__(self):
        meter = self

        def gmres(matvec, b, *args, **kwargs):
            def counted(x):
                meter.products += 1
                return matvec(x)
            meter.solves += 1
            return meter._gmres(counted, b, *args, **kwargs)

        def timed(function):
            def run(*args):
                t0 = time.process_time()
                try:
                    return function(*args)
                finally:
                    meter.coarse_s += time.process_time() - t0
            return run

        coupled_krylov.gfmd_gmres.gmres = gmres
        coupled_preconditioner.coarse_space = timed(self._space)
        coupled_preconditioner.CoarseSpace.coefficients = timed(self._coefficients)
        return self

    def __exit__(self, *exc):
        coupled_krylov.gfmd_gmres.gmres = self._gmres
        coupled_preconditioner.coarse_space = self._space
        coupled_preconditioner.CoarseSpace.coefficients = self._coefficients


def run(size, variant, args):
    """(CPU s, rows, products per solve, coarse CPU s) of one ramp."""
    coupled_preconditioner.CHOICE = variant
    keys = {"material.poisson_ratio": args.nu}
    with Meter() as meter:
        t0 = time.process_time()
        rows = ramp(2**size, "coupled", realization=args.realization, a_rel_stop=2.0, max_steps=args.max_steps,
                    scene_keys=keys)
        cpu = time.process_time() - t0
    coupled_preconditioner.CHOICE = "two-level"
    return cpu, rows, meter.products / max(meter.solves, 1), meter.coarse_s


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[13, 15])
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.45)
    ap.add_argument("--max-steps", type=int, default=201)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=VARIANTS)
    ap.add_argument("--rows", help="a folder for each ramp's rows (to compare processes run at once)")
    ap.add_argument("--from-rows", help="run nothing: the table of the ramps saved in this folder by --rows")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_coupled_preconditioner.md"))
    args = ap.parse_args(argv)
    reuse_freed_arrays()  # glibc keeps freed arrays, as in a study worker (else page faults blur the comparison)
    lines = header("The coupled Newton's two-level preconditioner (`gfmd.coupled_preconditioner`) against K⁻¹ alone",
                   "bench_coupled_preconditioner.py", argv,
                   f"2-core machine; ν = {args.nu:g}, realization {args.realization}; CPU s alternate the variants "
                   "in one process")
    lines += ["| N | preconditioner | CPU s per ramp (each repeat) | median | of it the coarse space | "
              "GMRES products per solve | FFT pairs | event steps | max |Δp̄|/max|p̄| | max |Δa_rel| | labels differ |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for size in args.sizes:
        got = {v: [] for v in args.variants}
        for _ in range(args.repeats if not args.from_rows else 0):
            for variant in args.variants:
                got[variant].append(run(size, variant, args))
        for variant in args.variants:
            saved = Path(args.from_rows or args.rows or ".") / f"{size}_{variant}.json"
            if args.from_rows and saved.exists():
                got[variant] = [tuple(json.loads(saved.read_text()))]
            elif args.rows and got[variant]:
                saved.parent.mkdir(parents=True, exist_ok=True)
                cpu, rows, products, coarse = got[variant][0]
                keep = [{k: v for k, v in r.items() if k != "u_hat"} for r in rows]
                saved.write_text(json.dumps([cpu, keep, products, coarse]))
        for variant, runs in got.items():
            if not runs:
                continue
            reference = got.get("stiffness") or None
            lines.append(ramp_row(size, variant, [c for c, *_ in runs], runs[0][1], reference and reference[0][1],
                                  (f"{runs[0][3]:.2f}", f"{runs[0][2]:.1f}")))
            print(lines[-1], flush=True)
    write(lines, args.out)


if __name__ == "__main__":
    main()
