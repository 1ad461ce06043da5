"""The coupled law's FIRE restarts, `Settings.coupled_f_dec` and `coupled_n_min`, swept on whole ramps (issue 24).

Usage: python benchmarks/bench_coupled_fire_restarts.py [--size 15] [--realization 2] [--nu 0.1]
       [--values 0.5/5 0.7/5 0.7/2 0.5/2 0.8/2 0.6/2] [--out FILE] [--data FILE]

Writes benchmarks/results/bench_coupled_fire_restarts_e<size>_nu<ν>_r<realization>.md (or --out).

The coupled class of benchmarks/bench_adhesion_scaling.py (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, the
default chain; `--nu` sets material.poisson_ratio), one whole ramp per value f_dec/n_min (FIRE's factor on Δt at a
restart, P ≤ 0, and the steps it waits before growing Δt again; the coupled FIRE's Δt cap at its default), one after
the other in one process. Per value:
CPU s, FFT pairs and iterations of the ramp and of its event steps (those the continuation Newton gave up, where FIRE
ran), and the states against the first value's (0.5/5: FIRE's f_dec and n_min, the coupled FIRE's default):
max |Δp̄| / max |p̄|, max |Δa_rel|, steps whose chain label differs. The rows also go to a JSON file (--data, default
benchmarks/results/bench_coupled_fire_restarts.json, keyed by size, ν and realization) that
tests/test_coupled_fire_restarts.py reads (a sweep of the same scene adds its values to the earlier rows; run the
first value, 0.5/5, first in each). FFT pairs are deterministic; CPU s are one process's, as the machine gave.
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



def parameters(value):
    """(f_dec, n_min) of a value "f_dec/n_min"."""
    f_dec, _, n_min = value.partition("/")
    return float(f_dec), int(n_min)


def sweep(size, realization, nu, values):
    """One row per value: the ramp's and its event steps' cost, and its states against the first value's."""
    rows, reference = [], None
    for value in values:
        f_dec, n_min = parameters(value)
        steps = ramp(2**size, "coupled", {"coupled_f_dec": f_dec, "coupled_n_min": n_min}, realization=realization,
                     a_rel_stop=2.0,
                     scene_keys={"material.poisson_ratio": nu})
        reference = reference or steps
        rows.append(event_sweep_row(steps, reference, f_dec=f_dec, n_min=n_min))
    return rows


def main(argv=None):
    args = event_sweep_arguments(__doc__, "bench_coupled_fire_restarts", ["0.5/5", "0.7/5", "0.7/2", "0.5/2", "0.8/2", "0.6/2"], argv=argv)
    reuse_freed_arrays()
    ramp(2**12, "coupled", max_steps=3)  # numba's compilation and the caches outside the measured ramps
    rows = sweep(args.size, args.realization, args.nu, args.values)
    write_event_sweep(rows, args.data, f"size {args.size}, nu {args.nu:g}, realization {args.realization}", args.out,
                      f"The coupled FIRE's restarts (f_dec / n_min), N = 2^{args.size}, ν = {args.nu:g}, realization "
                      f"{args.realization}", "bench_coupled_fire_restarts.py", argv, "f_dec / n_min",
                      lambda r: f"{r['f_dec']:g} / {r['n_min']}", same=lambda r: (r["f_dec"], r["n_min"]))


if __name__ == "__main__":
    main()
