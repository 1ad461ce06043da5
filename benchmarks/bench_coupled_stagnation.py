"""The continuation Newton's stagnation test: FFT pairs and CPU with and without it (issue 24).

Usage: python benchmarks/bench_coupled_stagnation.py [--sizes 13 14] [--realizations 0 1] [--max-steps K]
                                                     [--replay TASK_DIR STEP COUNT]

The coupled chain's first link, the continuation Newton, gives a step up once two iterations in a row each left more
than `gfmd.chains.COUPLED_CONTINUATION_STAGNATION` of the residual before them (`Settings.coupled_continuation_
stagnation`, BROKE_OFF): without it a Newton crawling along a near-singular tangent went on to its iteration cap or a
line search stall before the chain's FIRE took the step from the guess. Two variants, "off" (0, the chain before)
and "on" (the default), each on its own ramp in one run:

* ramps: the coupled ramps of bench_coupled_handover (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, until
  a_rel ≥ 0.5; realization i = profile seed 1 + i); p, a_rel and (N ≤ 2^14) the nodal states compared with "off"'s;
* --replay: a full-scale study task (`gfmd study run` output, its fields.npz holding the state of STEP), steps
  STEP+1 … STEP+COUNT each relaxed from the same start by both (bench_coupled_forcing.replay_variants).

Under "off", every continuation's residuals r_0 … r_k are recorded: for those that converged, the worst pair of
consecutive contraction ratios, max_j min(r_j/r_j−1, r_j+1/r_j) (the test breaks off where both exceed the threshold:
below it on every converged continuation, no kept state changes), and for those that did not, the iterations the test
would have left out. Writes benchmarks/results/bench_coupled_stagnation_<tag>.md.
"""

from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

# E402 below on purpose: the sibling benchmarks are importable only once benchmarks/ is on sys.path (above), and
# bench_coupled_handover must load before numpy (it sets one BLAS thread, as every timing here assumes)
import bench_coupled_forcing as bcf  # noqa: E402
import bench_coupled_handover as bch  # noqa: E402

from gfmd import chains  # noqa: E402
from gfmd.algorithms import coupled_newton  # noqa: E402

KEY = "coupled_continuation_stagnation"
_histories = []  # per continuation Newton run under "off": (residuals r_0 … r_k, converged, iterations)


@contextmanager
def stagnation(value):
    """The default coupled chain with its continuation link's stagnation threshold set to `value` (0: off); under
    0, every continuation's residual history is recorded in _histories."""
    chain_key = ("coupled", "handover-near")
    chain = chains.CHAINS[chain_key]
    first = chain[0]
    options = tuple((k, value if k == KEY else v) for k, v in first.options)
    chains.CHAINS[chain_key] = (replace(first, options=options),) + chain[1:]
    inner_forcing, inner_solve = coupled_newton.forcing, chains.ALGORITHMS["coupled_newton"]
    seen = []

    def forcing(tolerance, residual, eta=0.0):  # called once per iteration with the residual before it
        seen.append(residual)
        return inner_forcing(tolerance, residual, eta)

    def solve(problem, start, settings):
        seen.clear()
        r = inner_solve(problem, start, settings)
        if settings.coupled_continuation_jump > 0:  # the chain's continuation link (not a resumed run)
            ended = [r.residual] if seen and r.residual != seen[-1] else []  # not where the last iteration failed
            _histories.append((list(seen) + ended, r.converged, r.iterations))
        return r

    if value == 0:
        coupled_newton.forcing, chains.ALGORITHMS["coupled_newton"] = forcing, solve
    try:
        yield
    finally:
        chains.CHAINS[chain_key] = chain
        coupled_newton.forcing, chains.ALGORITHMS["coupled_newton"] = inner_forcing, inner_solve


def history_summary(threshold):
    """Lines on the recorded continuations: converged ones' worst consecutive contraction pair, and the iterations
    the test at `threshold` leaves out of the others."""
    worst, saved, broken, kept_cut, cut = 0.0, 0, 0, 0, []
    converged = [h for h in _histories if h[1]]
    for residuals, ok, iterations in _histories:
        ratios = [b / a for a, b in zip(residuals, residuals[1:]) if a > 0]
        pairs = [min(a, b) for a, b in zip(ratios, ratios[1:])]
        if ok:  # the last pair ends below the tolerance, where the test is not taken
            worst = max([worst] + pairs[:-1])
            if any(p > threshold for p in pairs[:-1]):
                kept_cut += 1
                cut.append(", ".join(f"{x:.2g}" for x in residuals))
            continue
        first = next((j + 2 for j, p in enumerate(pairs) if p > threshold), None)  # the iteration the test stops at
        if first is not None and first < iterations:
            broken += 1
            saved += iterations - first
    head = (f"Continuations under \"off\": {len(_histories)}, converged {len(converged)}; the worst pair of "
            f"consecutive contraction ratios a converged one was tested on: {worst:.3g} (threshold {threshold:g}; "
            f"converged ones the test would have broken off: {kept_cut}). Unconverged ones the test stops earlier: "
            f"{broken}, {saved} Newton iterations fewer.")
    return [head] + [f"- converged, broken off by the test: residuals {c} p_ref" for c in cut]


def main(argv=None):
    ap = bch.parser(__doc__.splitlines()[0])
    ap.add_argument("--replay", nargs=3, metavar=("TASK_DIR", "STEP", "COUNT"), default=None)
    args = ap.parse_args(argv)
    threshold = chains.COUPLED_CONTINUATION_STAGNATION
    variants = [("off", lambda: stagnation(0.0)), (f"on ({threshold:g})", lambda: stagnation(threshold))]
    command = f"python benchmarks/bench_coupled_stagnation.py {' '.join(argv or sys.argv[1:])}"
    head = [f"`{command}`; {bch.code_version()}; COUPLED_CONTINUATION_STAGNATION {threshold:g}; load average at "
            f"start {os.getloadavg()[0]:.2f} (2-core machine: CPU s may be under load; FFT pairs deterministic)", ""]
    _histories.clear()
    lines = head + bcf.measure(args, variants)
    lines += [""] + history_summary(threshold)
    bch.write(args, "bench_coupled_stagnation", lines + ["", f"Load average at end: {os.getloadavg()[0]:.2f}."])


if __name__ == "__main__":
    main()
