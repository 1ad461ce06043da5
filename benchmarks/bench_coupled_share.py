"""Where the coupled law's ramp spends its time against the normal law's on the same profile (issue 24's 2× target).

Usage: python benchmarks/bench_coupled_share.py [--size 17] [--realization 2] [--nu 0.45] [--top 15] [--out FILE]

One process, one whole 201-step ramp per law on bench_adhesion_scaling's seed base scene (φn* = 0.15): the normal
law (c = 0: the NCG on u_z alone, one component per transform) and the coupled law (c = 0.5, δt = 1 nm: the
Newton–Krylov chain on (u_x, u_z), two components per transform), each under cProfile with a process-time timer.
Per law and step kind (regular: the chain's first algorithm converged alone; event: a fallback ran): steps,
iterations, FFT pairs and CPU s per step; then the coupled ramp's functions by own time (the profiler's overhead
is in every row: shares, not absolute times). An FFT pair counts one rfft + irfft call whatever the components.
Writes benchmarks/results/bench_coupled_share_e<size>_nu<nu>_r<realization>.md (or --out).
"""

from __future__ import annotations

import argparse
import cProfile
import io
import os
import pstats
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from benchmarks.report import header  # noqa: E402

FIRST = {"cohesive": "ncg", "coupled": "newton"}  # each chain's first algorithm: a step it converged alone is regular


def profiled(n, cls, realization, nu):
    """One whole ramp under cProfile: (rows, pstats.Stats)."""
    profile = cProfile.Profile(time.process_time)
    profile.enable()
    rows = ramp(n, cls, realization=realization, scene_keys={"material.poisson_ratio": nu}, a_rel_stop=1.0)
    profile.disable()
    return rows, pstats.Stats(profile)


def kinds(rows, first):
    """{kind: (steps, it/step, pairs/step, CPU s/step, CPU s)} of regular and event steps and all of them."""
    out = {}
    for kind, sel in (("regular", [r for r in rows if r["method"] == first]),
                      ("event", [r for r in rows if r["method"] != first]), ("all", rows)):
        if sel:
            m = len(sel)
            cpu = sum(r["cpu"] for r in sel)
            out[kind] = (m, sum(r["it"] for r in sel) / m, sum(r["pairs"] for r in sel) / m, cpu / m, cpu)
    return out


def top(stats, count):
    """The `count` functions with the most own time: (name, calls, own s, share of the total)."""
    total = stats.total_tt
    rows = sorted(stats.stats.items(), key=lambda kv: -kv[1][2])[:count]
    return [(f"{Path(f).name}:{line}({name})", calls, tt, tt / total) for (f, line, name), (_, calls, tt, _, _) in rows]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=17)
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.45)
    ap.add_argument("--top", type=int, default=15)
    ap.add_argument("--out", type=Path)
    a = ap.parse_args(argv)
    n = 2 ** a.size
    results = {cls: profiled(n, cls, a.realization, a.nu) for cls in ("cohesive", "coupled")}
    lines = header(f"The coupled law's ramp against the normal law's, N = 2^{a.size}, ν = {a.nu:g}, realization "
                   f"{a.realization}", "bench_coupled_share.py", argv) + [
        "One process, the normal-law ramp then the coupled one, each whole (201 steps) under cProfile (process time); "
        "an FFT pair is one rfft + irfft call: one component (u_z) for the normal law, two (u_x, u_z) for the coupled.",
        "",
        "| law | steps | count | iterations / step | FFT pairs / step | CPU s / step | CPU s |",
        "|---|---|---|---|---|---|---|"]
    totals = {}
    for cls, (rows, _) in results.items():
        for kind, (m, it, pairs, per, cpu) in kinds(rows, FIRST[cls]).items():
            lines.append(f"| {cls} | {kind} | {m} | {it:.2f} | {pairs:.1f} | {per:.3f} | {cpu:.1f} |")
            if kind == "all":
                totals[cls] = cpu
    coupled = kinds(results["coupled"][0], "newton")
    ratio = totals["coupled"] / totals["cohesive"]
    regular = coupled.get("regular", (0, 0, 0, 0, 0.0))[4] / totals["cohesive"]
    lines += ["", f"**Coupled / normal CPU: {ratio:.2f}** (the coupled ramp's regular steps alone: {regular:.2f} of the "
                  "normal ramp).", "", "The coupled ramp's functions by own time:", "",
              "| function | calls | own s | share |", "|---|---|---|---|"]
    for name, calls, tt, share in top(results["coupled"][1], a.top):
        lines.append(f"| {name} | {calls} | {tt:.2f} | {share:.1%} |")
    lines += ["", f"Load average at end: {os.getloadavg()[0]:.2f}."]
    out = a.out or ROOT / "benchmarks" / "results" / f"bench_coupled_share_e{a.size}_nu{a.nu:g}_r{a.realization}.md"
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
