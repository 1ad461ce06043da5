"""The continuation Newton's break-off where an iterate jumps, with and without the FIRE→Newton handover (issue 24).

Usage: python benchmarks/bench_coupled_continuation.py [--sizes 13 14] [--realizations 0 1] [--max-steps K]
                                                       [--handover 1e-4]

The coupled ramps of bench_coupled_handover (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, until a_rel ≥ 0.5,
realization i = profile seed 1 + i), four chains each on its own ramp in the same run:
  newton, no break-off        the coupled "newton" chain before the break-off (its continuation link without
                              the options BREAK_OFF: Newton runs until it converges or stalls, or 60 iterations)
  newton                      the "newton" chain: the continuation gives up once an iterate moved COUPLED_JUMP
                              law lengths and after COUPLED_CONTINUATION_ITERATIONS (`gfmd.chains._CONTINUATION`)
  handover-near, no break-off / handover-near   the same pair for the handover chain (FIRE to
                              Settings.coupled_handover, Newton from there kept where near FIRE's state)
FFT pairs per step include the stability test's (column "stab" of bench_coupled_handover); p, a_rel and (N ≤ 2^14)
the nodal states are compared with the first chain's. Writes benchmarks/results/bench_coupled_continuation_<tag>.md.
"""

from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import bench_coupled_handover as bch  # noqa: E402  (sets one BLAS thread before numpy, counts the stability test)
from gfmd import chains  # noqa: E402


#: the continuation link's options sessions 26–29 added (the break-off at a jump, the iteration cap, the GMRES cycles,
#: the stagnation test)
BREAK_OFF = ("coupled_continuation_jump", "coupled_continuation_iterations", "coupled_continuation_gmres_cycles",
             "coupled_continuation_stagnation")


@contextmanager
def without_break_off(key):
    """CHAINS[("coupled", key)] with its continuation link's break-off off (no jump test, 60 iterations, 5 GMRES
    cycles)."""
    chain = chains.CHAINS[("coupled", key)]
    off = tuple(replace(link, options=tuple((k, v) for k, v in link.options if k not in BREAK_OFF))
                for link in chain)
    chains.CHAINS[("coupled", key)] = off
    try:
        yield
    finally:
        chains.CHAINS[("coupled", key)] = chain


def main(argv=None):
    args = bch.parser(__doc__.splitlines()[0]).parse_args(argv)
    head = [f"`python benchmarks/bench_coupled_continuation.py {' '.join(argv or sys.argv[1:])}`; {bch.code_version()}; "
            f"COUPLED_JUMP = {chains.COUPLED_JUMP}, handover residual {args.handover:g} p_ref; load average at start "
            f"{os.getloadavg()[0]:.2f} (2-core machine: CPU s may be under load; FFT pairs deterministic up to ARPACK's "
            "random start in the stability test)", ""]
    table = list(bch.TABLE)
    variants = [("newton, no break-off", "newton", False), ("newton", "newton", True),
                ("handover-near, no break-off", "handover-near", False), ("handover-near", "handover-near", True)]
    for e in args.sizes:
        n = 2**e
        for real in args.realizations:
            results, bound = {}, bch.tolerance_bound(n, real)
            for name, key, break_off in variants:
                options = {"coupled": key, "coupled_handover": args.handover}
                if break_off:
                    rows, cpu = bch.run(n, real, options, args.max_steps)
                else:
                    with without_break_off(key):
                        rows, cpu = bch.run(n, real, options, args.max_steps)
                results[name] = rows
                line = bch.table_row(e, real, name, rows, cpu, results[variants[0][0]], bound)
                table.append(line)
                print(line, flush=True)
    bch.write(args, "bench_coupled_continuation", head + table + ["", f"Load average at end: {os.getloadavg()[0]:.2f}."])


if __name__ == "__main__":
    main()
