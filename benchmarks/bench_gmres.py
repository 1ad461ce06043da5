"""The coupled Newton's GMRES: `gfmd.gmres` (fused MGS, float32 basis) against scipy's, on whole coupled ramps (issue 24).

Usage: python benchmarks/bench_gmres.py [--sizes 13 15] [--realization 2] [--max-steps 201] [--repeats 2]
                                        [--out FILE]

The coupled class of benchmarks/bench_adhesion_scaling.py (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, the
default chain "handover-near"), one ramp per N and `gfmd.coupled_krylov.GMRES` ("scipy", then "gfmd"), alternating
`--repeats` times in one process (the same load on both): CPU s per ramp (time.process_time), FFT pairs, event steps
(not "newton"), and the largest differences of p̄ and a_rel and the steps whose chain label differs, against "scipy".
The process reuses freed arrays as a study worker does (`gfmd_contact.app.study_task.reuse_freed_arrays`): without it the
page faults of fresh arrays (their pattern differs between the variants) blurred the comparison at 2^17.
A 1-D profile (time.process_time) of where a ramp's time goes is printed for the last "scipy" run: scipy's gmres
own time (its Gram–Schmidt loop) against the FFTs. Writes benchmarks/results/bench_gmres.md (or --out).
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import sys
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")


ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from gfmd import coupled_krylov  # noqa: E402
from benchmarks.report import header, ramp_row, write  # noqa: E402
from gfmd_contact.app.study_task import reuse_freed_arrays  # noqa: E402

VARIANTS = ("scipy", "gfmd")


def profile_shares(size, realization, max_steps):
    """(scipy gmres own s, FFT s, total s) of one "scipy" ramp under cProfile."""
    coupled_krylov.GMRES = "scipy"
    prof = cProfile.Profile()
    prof.enable()
    ramp(2**size, "coupled", realization=realization, a_rel_stop=2.0, max_steps=max_steps)
    prof.disable()
    stats = pstats.Stats(prof).stats
    own = {f"{Path(k[0]).name}:{k[2]}": v[2] for k, v in stats.items()}
    gm = sum(t for name, t in own.items() if name.startswith("iterative.py:gmres"))
    fft = sum(t for name, t in own.items() if "r2c" in name or "c2r" in name)
    return gm, fft, sum(v[2] for v in stats.values())


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[13, 15])
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--max-steps", type=int, default=201)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_gmres.md"))
    args = ap.parse_args(argv)
    reuse_freed_arrays()  # glibc keeps freed arrays, as in a study worker (else page faults blur the comparison)
    lines = header("The coupled Newton's GMRES: fused modified Gram–Schmidt and a float32 basis (`gfmd.gmres`) against "
                   "scipy's", "bench_gmres.py", argv, "2-core machine; CPU s alternate the variants in one process")
    lines += ["| N | GMRES | CPU s per ramp (each repeat) | median | FFT pairs | event steps | max |Δp̄|/max|p̄| | "
              "max |Δa_rel| | labels differ |", "|---|---|---|---|---|---|---|---|---|"]
    profiles = []
    for size in args.sizes:
        runs = {v: [] for v in VARIANTS}
        for _ in range(args.repeats):
            for variant in VARIANTS:
                coupled_krylov.GMRES = variant
                t0 = time.process_time()
                rows = ramp(2**size, "coupled", realization=args.realization, a_rel_stop=2.0, max_steps=args.max_steps)
                runs[variant].append((time.process_time() - t0, rows))
        coupled_krylov.GMRES = "gfmd"
        for variant, got in runs.items():
            lines.append(ramp_row(size, variant, [c for c, _ in got], got[0][1], runs["scipy"][0][1]))
        print("\n".join(lines[-2:]), flush=True)
        profiles.append((size, *profile_shares(size, args.realization, args.max_steps)))
    lines += ["", "Where a \"scipy\" ramp's time goes (cProfile, own time):", "",
              "| N | scipy gmres (its Gram–Schmidt loop) | FFTs | total |", "|---|---|---|---|"]
    for size, gm, fft, total in profiles:
        lines.append(f"| 2^{size} | {gm:.1f} s ({gm / total:.0%}) | {fft:.1f} s ({fft / total:.0%}) | {total:.1f} s |")
    write(lines, args.out)


if __name__ == "__main__":
    main()
