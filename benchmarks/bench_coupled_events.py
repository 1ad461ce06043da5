"""Where FIRE's iterations go on the coupled chain's event steps: iterations per residual decade (issue 24).

Usage: python benchmarks/bench_coupled_events.py [--size 15] [--realization 2] [--nu 0.1] [--out FILE]

The coupled class of benchmarks/bench_adhesion_scaling.py (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, the
default chain; `--nu` sets material.poisson_ratio), one whole ramp. On every event step (the continuation Newton gave
it up, so FIRE ran to the handover residual `Settings.coupled_handover`), FIRE is run again from the same start to
1e-1, 1e-2 and 1e-3 p_ref: FIRE is deterministic, so these are the iterations at which its run first passed each
residual (checked every `check_every` iterations). With them: FIRE's restarts (power f·v ≤ 0, `gfmd.integrators.Fire`)
and the largest nodal move from the start at handover, in law lengths min(δn, δt). A run whose last decade holds most
of its iterations at a move of about a law length crawls through the ghost of a fold (a snap whose equilibrium is gone)
before the snap. Writes benchmarks/results/bench_coupled_events.md (or --out).
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import replace
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from benchmarks.report import header, write  # noqa: E402
from gfmd import chains, integrators  # noqa: E402
from gfmd.settings import Settings  # noqa: E402
from gfmd_contact.app.study_task import reuse_freed_arrays  # noqa: E402

DECADES = (1e-1, 1e-2, 1e-3)
HANDOVER = Settings().coupled_handover  # the residual the chain's FIRE link runs to


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=15)
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.1)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_coupled_events.md"))
    args = ap.parse_args(argv)
    reuse_freed_arrays()
    fire = chains.ALGORITHMS["dynamics"]
    restarts = [0]
    adapt = integrators.Fire.adapt

    def counted(self, power):
        restart = adapt(self, power)
        restarts[0] += restart
        return restart

    events = []

    def handover(problem, start, settings):  # the chain's FIRE, measured where it runs to the handover residual
        restarts[0] = 0
        out = fire(problem, start, settings)
        if settings.tolerance != HANDOVER or not out.converged:
            return out
        found = restarts[0]
        passed = [fire(problem, start, replace(settings, tolerance=t)).iterations for t in DECADES]
        move = float(np.max(np.abs(problem.displacements(out.u_hat - start)))) / problem.law.law.length_scale
        events.append((passed, out.iterations, found, move))
        return out

    integrators.Fire.adapt = counted
    chains.ALGORITHMS["dynamics"] = handover
    try:
        rows = ramp(2**args.size, "coupled", realization=args.realization, a_rel_stop=2.0,
                    scene_keys={"material.poisson_ratio": args.nu})
    finally:
        chains.ALGORITHMS["dynamics"], integrators.Fire.adapt = fire, adapt
    lines = header(f"FIRE on the coupled event steps, N = 2^{args.size}, ν = {args.nu:g}, realization "
                   f"{args.realization}", "bench_coupled_events.py", argv)
    lines += [f"Whole ramp: {len(rows)} steps, {sum(r['cpu'] for r in rows):.1f} CPU s; FIRE to the handover residual "
              f"on {len(events)} steps.", "",
              "| event | iterations to 1e-1 | 1e-2 | 1e-3 | handover (1e-4) | restarts | move at handover (law lengths) |",
              "|---|---|---|---|---|---|---|"]
    for i, (passed, total, found, move) in enumerate(events, 1):
        lines.append(f"| {i} | {' | '.join(str(p) for p in passed)} | {total} | {found} | {move:.2f} |")
    if events:
        sums = np.sum([[*p, t] for p, t, _, _ in events], axis=0)
        last = sums[-1] - sums[-2]
        lines += [f"| all | {' | '.join(str(int(s)) for s in sums)} | {sum(e[2] for e in events)} | |", "",
                  f"FIRE's iterations on the event steps: {int(sums[-1])}; {int(last)} ({last / sums[-1]:.0%}) of them "
                  f"between 1e-3 and the handover residual, {int(sums[-2] - sums[-3])} between 1e-2 and 1e-3."]
    write(lines, args.out)


if __name__ == "__main__":
    main()
