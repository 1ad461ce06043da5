"""The coupled chain's frictionless predictor against "handover-near" on whole coupled ramps, and the normal law (issue 24).

Usage: python benchmarks/bench_coupled_frictionless.py [--sizes 15] [--nu 0.1 0.3 0.4 0.45] [--realizations 2 3]
                                                      [--normal] [--stability] [--chains A B] [--out DIR]

bench_adhesion_scaling's coupled class (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm) with material.poisson_ratio
= ν, realization seed r, the whole 201-step ramp (no a_rel stop), each chain its own ramp in the same process (warm-up of
3 steps each, untimed): Settings.coupled = "handover-near" (the default of sessions 26–39) and "frictionless-first".
Per ramp: converged steps, CPU s (time.process_time, one thread; the machine's speed drifts ±20 % between runs: the
FFT pairs are deterministic, but the predictor's NCG transforms one component where the coupled algorithms transform
two, so its pairs cost about half), FFT pairs, event steps (those the continuation Newton gives up) with their pairs
and CPU, predictions kept (label "newton→ncg-frictionless→newton"), and against "handover-near": the steps whose p̄
differs by more than 1e-6 of max |p̄| (another branch after an event) and the largest such difference. --stability:
at the first step of each differing run, the lowest Re λ / (φn/δn²) of the tangent at both chains' states
(`gfmd.coupled_stability`; > 0: locally stable). --normal: the same profile's normal-law ramp (c = 0, the NCG) for
the coupled / normal CPU ratio the issue's target names. --chains: the two Settings.coupled chains compared (the first
the reference; e.g. "handover-near ncg-first", whose kept event steps are labelled "newton→coupled-ncg→newton").
Writes benchmarks/results/bench_coupled_frictionless.md (--out).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import bench_adhesion_scaling as bas  # noqa: E402
from gfmd_contact.core.loading import indenter_surface, realization_steps  # noqa: E402
from gfmd.coupled_stability import coupled_stability  # noqa: E402
from gfmd.loading import prepare  # noqa: E402
from gfmd.problem import elastic_coupling  # noqa: E402
from gfmd_contact.app.io import code_version  # noqa: E402

CHAINS = ("handover-near", "frictionless-first")
#: the label of an event step each chain's second link finished, kept (the "predictions kept" column)
KEPT = {"frictionless-first": "newton→ncg-frictionless→newton", "ncg-first": "newton→coupled-ncg→newton"}


def ramp(n, cls, realization, nu, options):
    keys = {"material.poisson_ratio": nu}
    bas.ramp(n, cls, options, max_steps=3, scene_keys=keys)  # warm-up: compiled kernels, FFT plans
    t0 = time.process_time()
    rows = bas.ramp(n, cls, options, None, realization, scene_keys=keys, a_rel_stop=2.0, keep_u_hat=True)
    return rows, time.process_time() - t0


def lowest(n, realization, nu, k, u_hat):
    """Lowest Re λ / (φn/δn²) of the coupled tangent at step k's state u_hat."""
    scene, h = bas.task_of(n, "coupled", realization, {"material.poisson_ratio": nu})
    cell = prepare(scene, h)
    steps, _ = realization_steps(scene, h, 0)
    z = indenter_surface(h, scene.loading.initial_separation, steps[k])
    lam = coupled_stability(cell.physics, cell.law, z, u_hat)
    return None if lam is None else lam / cell.law.k_int_z


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[15])
    ap.add_argument("--nu", type=float, nargs="+", default=[0.1, 0.3, 0.4, 0.45])
    ap.add_argument("--realizations", type=int, nargs="+", default=[2, 3])
    ap.add_argument("--normal", action="store_true")
    ap.add_argument("--stability", action="store_true")
    ap.add_argument("--chains", nargs=2, default=list(CHAINS))
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_coupled_frictionless.md"))
    args = ap.parse_args(argv)
    lines = [f"`python benchmarks/bench_coupled_frictionless.py {' '.join(argv or sys.argv[1:])}`; {code_version()}; "
             f"load average at start {os.getloadavg()[0]:.2f} (2-core machine)", "",
             "| N | ν (coupling β) | real. | chain | converged | CPU s | FFT pairs | event steps | event pairs | "
             "event CPU s | predictions kept | steps on another branch | max |Δp̄|/max |p̄| | lowest Re λ (first such step) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for e in args.sizes:
        n = 2**e
        for nu in args.nu:
            scene, h = bas.task_of(n, "coupled", args.realizations[0], {"material.poisson_ratio": nu})
            beta = elastic_coupling(prepare(scene, h).physics)
            for real in args.realizations:
                ref = None
                for name in args.chains:
                    rows, cpu = ramp(n, "coupled", real, nu, {"coupled": name})
                    ev = [r for r in rows if r["method"] != "newton"]
                    kept = sum(r["method"] == KEPT.get(name) for r in rows)
                    other, dp, stab = "—", "—", "—"
                    if ref is None:
                        ref = rows
                    else:
                        scale = max(abs(r["p"]) for r in ref)
                        diff = [(a["k"], abs(a["p"] - b["p"]) / scale) for a, b in zip(ref, rows)
                                if abs(a["p"] - b["p"]) > 1e-6 * scale]
                        other = ", ".join(str(k) for k, _ in diff) or "none"
                        dp = f"{max((d for _, d in diff), default=0.0):.2g}"
                        if diff and args.stability:
                            k = diff[0][0]
                            stab = " / ".join(f"{lowest(n, real, nu, k, x[k]['u_hat']):.3g}" for x in (ref, rows))
                    line = (f"| 2^{e} | {nu:g} ({beta:.3f}) | {real} | {name} | {sum(r['converged'] for r in rows)}/"
                            f"{len(rows)} | {cpu:.1f} | {sum(r['pairs'] for r in rows):.0f} | {len(ev)} | "
                            f"{sum(r['pairs'] for r in ev):.0f} | {sum(r['cpu'] for r in ev):.1f} | "
                            f"{kept if name != args.chains[0] else '—'} | {other} | {dp} | {stab} |")
                    lines.append(line)
                    print(line, flush=True)
                if args.normal:
                    rows, cpu = ramp(n, "normal", real, nu, {})
                    line = (f"| 2^{e} | {nu:g} | {real} | normal law (c = 0, ncg) | {sum(r['converged'] for r in rows)}/"
                            f"{len(rows)} | {cpu:.1f} | {sum(r['pairs'] for r in rows):.0f} | | | | | | | |")
                    lines.append(line)
                    print(line, flush=True)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
