"""The coupled law's FIRE time-step cap `Settings.coupled_dt_max`, swept on whole ramps (issue 24).

Usage: python benchmarks/bench_coupled_dt_max.py [--size 15] [--realization 2] [--nu 0.1] [--values 1 0.6 0.5 0.4 0.3 0.2]
       [--out FILE] [--data FILE]

Writes benchmarks/results/bench_coupled_dt_max_e<size>_nu<ν>_r<realization>.md (or --out).

The coupled class of benchmarks/bench_adhesion_scaling.py (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, the
default chain; `--nu` sets material.poisson_ratio), one whole ramp per cap, one after the other in one process. Per cap:
CPU s, FFT pairs and iterations of the ramp and of its event steps (those the continuation Newton gave up, where FIRE
ran), and the states against the first value's (1.0: FIRE's `Settings.dt_max`, the coupled FIRE before session 35):
max |Δp̄| / max |p̄|, max |Δa_rel|, steps whose chain label differs. The rows also go to a JSON file (--data, default
benchmarks/results/bench_coupled_dt_max.json, keyed by size, ν and realization) that tests/test_fire_dt_cap.py reads.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from benchmarks.report import event_sweep_arguments, event_sweep_row, write_event_sweep  # noqa: E402
from gfmd_contact.app.study_task import reuse_freed_arrays  # noqa: E402



def sweep(size, realization, nu, values):
    """One row per cap: the ramp's and its event steps' cost, and its states against the first cap's."""
    rows, reference = [], None
    for cap in values:
        steps = ramp(2**size, "coupled", {"coupled_dt_max": cap}, realization=realization, a_rel_stop=2.0,
                     scene_keys={"material.poisson_ratio": nu})
        reference = reference or steps
        rows.append(event_sweep_row(steps, reference, dt_max=cap))
    return rows


def main(argv=None):
    args = event_sweep_arguments(__doc__, "bench_coupled_dt_max", [1.0, 0.6, 0.5, 0.4, 0.3, 0.2], float, argv=argv)
    reuse_freed_arrays()
    ramp(2**12, "coupled", max_steps=3)  # numba's compilation and the caches outside the measured ramps
    rows = sweep(args.size, args.realization, args.nu, args.values)
    write_event_sweep(rows, args.data, f"size {args.size}, nu {args.nu:g}, realization {args.realization}", args.out,
                      f"The coupled FIRE's time-step cap, N = 2^{args.size}, ν = {args.nu:g}, realization "
                      f"{args.realization}", "bench_coupled_dt_max.py", argv, "coupled_dt_max", lambda r: f"{r['dt_max']:g}")


if __name__ == "__main__":
    main()
