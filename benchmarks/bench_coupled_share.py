"""Where the coupled law's ramp spends its time against the normal law's on the same profile (issue 24's 2× target).

Usage: python benchmarks/bench_coupled_share.py [--size 17] [--realization 2] [--nu 0.45] [--chain auto] [--top 15]
                                              [--out FILE]

One process, one whole 201-step ramp per law on bench_adhesion_scaling's seed base scene (φn* = 0.15): the normal
law (c = 0: the NCG on u_z alone, one component per transform) and the coupled law (c = 0.5, δt = 1 nm: the
Newton–Krylov chain on (u_x, u_z), two components per transform), each under cProfile with a process-time timer.
Per law and step kind (regular: the chain's first algorithm converged alone; event: a fallback ran): steps,
iterations, FFT pairs and CPU s per step; then the coupled ramp's functions by own time (the profiler's overhead
is in every row: shares, not absolute times). An FFT pair counts one rfft + irfft call whatever the components;
the FFT work counts component pairs (pairs × components), what the transforms cost. The event steps' links: each
algorithm the chain ran on them, by its place in the chain (the continuation Newton that gave the step up, the link
that crossed the event, the Newton that finished it, ...), with its FFT pairs and CPU; and the event steps' FFT work
per step that would bring the coupled ramp's FFT work to twice the normal ramp's, the regular steps as they are.
--chain: Settings.coupled (e.g. "ncg-first"). Writes
benchmarks/results/bench_coupled_share_e<size>_nu<nu>_r<realization>.md (with _<chain> for another chain than "auto";
or --out).
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

from benchmarks import bench_adhesion_scaling  # noqa: E402
from benchmarks.report import header  # noqa: E402
from gfmd import chains  # noqa: E402

FIRST = {"cohesive": "ncg", "coupled": "newton"}  # each chain's first algorithm: a step it converged alone is regular
COMPONENTS = {"cohesive": 1, "coupled": 2}  # the components each transform carries (u_z; u_x, u_z)


def profiled(n, cls, realization, nu, options=None):
    """One whole ramp under cProfile: (rows, pstats.Stats, links), links[k] the (algorithm, converged, FFT pairs,
    CPU s) of each algorithm run of step k in the chain's order (a retry from the last state, `ramp`'s second relax
    of the same step, continues its list)."""
    links, surface, runs = [], [None], dict(chains.ALGORITHMS)  # surface: the last step's indenter surface
    step = bench_adhesion_scaling.relax

    def relax(model, law, z_ind, *args, **kwargs):  # a new indenter surface: a new step
        if surface[0] is not z_ind:
            surface[0] = z_ind
            links.append([])
        return step(model, law, z_ind, *args, **kwargs)

    def timed(name, solve):
        def run(problem, start, settings):
            t0 = time.process_time()
            r = solve(problem, start, settings)
            links[-1].append((name, bool(r.converged), r.fft_pairs, time.process_time() - t0))
            return r
        return run

    profile = cProfile.Profile(time.process_time)
    chains.ALGORITHMS.update({name: timed(name, solve) for name, solve in runs.items()})
    bench_adhesion_scaling.relax = relax
    try:
        profile.enable()
        rows = bench_adhesion_scaling.ramp(n, cls, options, realization=realization,
                                           scene_keys={"material.poisson_ratio": nu}, a_rel_stop=1.0)
        profile.disable()
    finally:
        chains.ALGORITHMS.update(runs)
        bench_adhesion_scaling.relax = step
    return rows, pstats.Stats(profile), links


def event_links(rows, links, first):
    """{(place, algorithm, converged): [runs, FFT pairs, CPU s]} over the event steps' algorithm runs."""
    out = {}
    for row, runs in zip(rows, links, strict=True):
        if row["method"] == first:
            continue
        for place, (name, converged, pairs, cpu) in enumerate(runs):
            cell = out.setdefault((place, name, converged), [0, 0.0, 0.0])
            cell[0] += 1
            cell[1] += pairs
            cell[2] += cpu
    return out


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
    ap.add_argument("--chain", default="auto", help="Settings.coupled of the coupled ramp")
    ap.add_argument("--top", type=int, default=15)
    ap.add_argument("--out", type=Path)
    a = ap.parse_args(argv)
    n = 2 ** a.size
    options = {"cohesive": None, "coupled": {"coupled": a.chain}}
    results = {cls: profiled(n, cls, a.realization, a.nu, options[cls]) for cls in ("cohesive", "coupled")}
    lines = header(f"The coupled law's ramp against the normal law's, N = 2^{a.size}, ν = {a.nu:g}, realization "
                   f"{a.realization}, Settings.coupled = {a.chain!r}", "bench_coupled_share.py", argv) + [
        "One process, the normal-law ramp then the coupled one, each whole (201 steps) under cProfile (process time); "
        "an FFT pair is one rfft + irfft call: one component (u_z) for the normal law, two (u_x, u_z) for the coupled; "
        "the FFT work counts component pairs.",
        "",
        "| law | steps | count | iterations / step | FFT pairs / step | FFT work / step | CPU s / step | CPU s |",
        "|---|---|---|---|---|---|---|---|"]
    totals, work = {}, {}
    for cls, (rows, _, _) in results.items():
        for kind, (m, it, pairs, per, cpu) in kinds(rows, FIRST[cls]).items():
            c = COMPONENTS[cls]
            lines.append(f"| {cls} | {kind} | {m} | {it:.2f} | {pairs:.1f} | {c * pairs:.1f} | {per:.3f} | {cpu:.1f} |")
            work[cls, kind] = (m, c * pairs * m)
            if kind == "all":
                totals[cls] = cpu
    coupled = kinds(results["coupled"][0], "newton")
    ratio = totals["coupled"] / totals["cohesive"]
    regular = coupled.get("regular", (0, 0, 0, 0, 0.0))[4] / totals["cohesive"]
    fft_ratio = work["coupled", "all"][1] / work["cohesive", "all"][1]
    lines += ["", f"**Coupled / normal CPU: {ratio:.2f}** (the coupled ramp's regular steps alone: {regular:.2f} of "
                  f"the normal ramp); FFT work {fft_ratio:.2f}."]
    events, event_work = work.get(("coupled", "event"), (0, 0.0))
    if events:
        spare = 2.0 * work["cohesive", "all"][1] - work["coupled", "regular"][1]
        lines += ["", f"FFT work of an event step now {event_work / events:.0f} component pairs (the ramp's FFT "
                      f"work at twice the normal ramp's would leave it {spare / events:.0f}, the regular steps as "
                      "they are).",
                  "", "The coupled event steps' algorithm runs by their place in the chain (0: the continuation "
                  "Newton):",
                  "", "| place | algorithm | converged | runs | FFT pairs | CPU s |", "|---|---|---|---|---|---|"]
        links = event_links(results["coupled"][0], results["coupled"][2], "newton")
        for (place, name, converged), (count, pairs, cpu) in sorted(links.items()):
            lines.append(f"| {place} | {name} | {'yes' if converged else 'no'} | {count} | {pairs:.0f} | {cpu:.1f} |")
    lines += ["", "The coupled ramp's functions by own time:", "",
              "| function | calls | own s | share |", "|---|---|---|---|"]
    for name, calls, tt, share in top(results["coupled"][1], a.top):
        lines.append(f"| {name} | {calls} | {tt:.2f} | {share:.1%} |")
    lines += ["", f"Load average at end: {os.getloadavg()[0]:.2f}."]
    tail = "" if a.chain == "auto" else f"_{a.chain}"
    out = a.out or ROOT / "benchmarks" / "results" / (f"bench_coupled_share_e{a.size}_nu{a.nu:g}_r{a.realization}"
                                                      f"{tail}.md")
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
