"""When a load step of the cohesive NCG switches to the two-level preconditioner, compared on whole ramps (issue 24).

Usage: python benchmarks/bench_cohesive_engage.py [--size 17] [--realization 2] [--phi 0.15] [--length-normal 1e-9]
       [--nu 0.45] [--reference 40/40] [--values 40/10 40/10/10] [--out FILE] [--data FILE]

Writes benchmarks/results/bench_cohesive_engage_e<size>_phi<φn*>_dn<δn nm>_nu<ν>_r<realization>.md (or --out).

The cohesive class of benchmarks/bench_adhesion_scaling.py (seed base scene, c = 0; --phi, --length-normal and --nu set
interface.phi_n_star, interface.length_normal and material.poisson_ratio) on the given realization (surface seed),
one whole 201-step ramp per value A/E[/R] of `gfmd.cohesive_preconditioner`'s ENGAGE_AFTER / ENGAGE_EARLY (a step's
first A iterations run with K⁻¹, the two-level preconditioner after them, or after E where the NCG's rate predicts more
than A: `slow_step`; E = A: never early) and REBUILD_EVERY (R: the preconditioner rebuilt from the state every R
iterations once engaged; without R the module's). CPU time on this 2-core machine moves by up to 25 % with what runs on the other
core (memory bandwidth: the same FFT took 1.24 ms in one ramp and 1.54 ms in another), and the two cores differ (the
same ramp on both at once: 9 % apart), so each value runs beside the reference as two simultaneous processes pinned
to one core each, twice, the cores swapped: its CPU ratio to the reference is the geometric mean of the two runs'
ratios (the core's factor cancels), and half their difference is the noise left. Per ramp: CPU s, NCG iterations, FFT pairs, and the states against the
reference's: max |Δp̄| / max |p̄|, max |Δa_rel| and the steps that settled on another branch of a jump-in
(|Δp̄| > BRANCH max |p̄|; such a step differs by about a percent of max p̄). The rows also go to a JSON file (--data,
default benchmarks/results/bench_cohesive_engage.json, keyed by the scene) that tests/test_cohesive_engage.py reads.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy: one thread
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from benchmarks import report  # noqa: E402
from benchmarks.report import header, ramp_differences, write  # noqa: E402
from gfmd import cohesive_preconditioner  # noqa: E402
from gfmd_contact.app.study_task import reuse_freed_arrays  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
#: a step whose p̄ differs from the reference's by more than this × max |p̄| settled on another equilibrium (the same
#: states differ by ≈ 1e-9 of it at the solver's tolerance 1e-8, another branch of a jump-in by ≈ 1e-2)
BRANCH = 1e-6


def engagement(value):
    """(ENGAGE_AFTER, ENGAGE_EARLY) of a value "A/E[/R]" (or "A": never early)."""
    after, _, rest = value.partition("/")
    early = rest.partition("/")[0]
    return int(after), int(early or after)


def rebuild_every(value):
    """REBUILD_EVERY of a value "A/E/R" (the module's where R is not given)."""
    parts = value.split("/")
    return int(parts[2]) if len(parts) > 2 else cohesive_preconditioner.REBUILD_EVERY


def run_one(size, realization, keys, value, dump, cpu):
    """The worker: one ramp at `value` on core `cpu`, its rows as JSON to `dump`."""
    os.sched_setaffinity(0, {cpu})
    reuse_freed_arrays()
    ramp(2**12, "cohesive", max_steps=3)  # numba's compilation and the caches outside the measured ramp
    cohesive_preconditioner.ENGAGE_AFTER, cohesive_preconditioner.ENGAGE_EARLY = engagement(value)
    cohesive_preconditioner.REBUILD_EVERY = rebuild_every(value)
    steps = ramp(2**size, "cohesive", realization=realization, a_rel_stop=2.0, scene_keys=keys)
    Path(dump).write_text(json.dumps([{k: s[k] for k in ("it", "pairs", "cpu", "a_rel", "p", "converged", "method")}
                                      for s in steps]))


def simultaneous(args, values):
    """The ramps of two values run as two simultaneous processes, the first on core 0, the second on core 1: rows."""
    return report.simultaneous([[sys.executable, __file__, "--size", str(args.size), "--realization",
                                 str(args.realization), "--phi", repr(args.phi), "--length-normal",
                                 repr(args.length_normal), "--nu", repr(args.nu), "--worker", value]
                                for value in values])


def row(label, value, steps, reference):
    after, early = engagement(value)
    dp, da, _ = ramp_differences(steps, reference)
    p, p_ref = (np.array([r["p"] for r in x]) for x in (steps, reference))
    other = np.flatnonzero(np.abs(p - p_ref) > BRANCH * np.max(np.abs(p_ref)))  # steps on another branch
    return {"run": label, "engage_after": after, "engage_early": early, "rebuild_every": rebuild_every(value),
            "steps": len(steps),
            "cpu_s": sum(s["cpu"] for s in steps), "fft_pairs": sum(s["pairs"] for s in steps),
            "iterations": sum(s["it"] for s in steps), "converged": sum(s["converged"] for s in steps),
            "final_a_rel": steps[-1]["a_rel"], "dp_rel": dp, "da_rel": da, "other_branch_steps": other.tolist()}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=17)
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--phi", type=float, default=0.15, help="interface.phi_n_star")
    ap.add_argument("--length-normal", type=float, default=1e-9, help="interface.length_normal δn (m)")
    ap.add_argument("--nu", type=float, default=0.45, help="material.poisson_ratio")
    ap.add_argument("--reference", default="40/40", help="A/E of the reference (40/40: before session 36)")
    ap.add_argument("--values", nargs="+", default=["40/10"])
    ap.add_argument("--out")
    ap.add_argument("--data", default=str(RESULTS / "bench_cohesive_engage.json"))
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--dump", help=argparse.SUPPRESS)
    ap.add_argument("--cpu", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    keys = {"interface.phi_n_star": args.phi, "interface.length_normal": args.length_normal,
            "material.poisson_ratio": args.nu}
    if args.worker:
        return run_one(args.size, args.realization, keys, args.worker, args.dump, args.cpu)
    label = f"e{args.size}_phi{args.phi:g}_dn{args.length_normal * 1e9:g}_nu{args.nu:g}_r{args.realization}"
    out = args.out or RESULTS / f"bench_cohesive_engage_{label}.md"
    rows, reference, ratios = [], None, {}
    for value in args.values:
        ref0, new1 = simultaneous(args, [args.reference, value])
        new0, ref1 = simultaneous(args, [value, args.reference])
        reference = reference or ref0
        rows += [row(f"reference, core 0, beside {value}", args.reference, ref0, reference),
                 row(f"{value}, core 1", value, new1, reference),
                 row(f"{value}, core 0", value, new0, reference),
                 row(f"reference, core 1, beside {value}", args.reference, ref1, reference)]
        r1, r2 = rows[-3]["cpu_s"] / rows[-4]["cpu_s"], rows[-2]["cpu_s"] / rows[-1]["cpu_s"]
        ratios[value] = {"engage_after": engagement(value)[0], "engage_early": engagement(value)[1],
                         "rebuild_every": rebuild_every(value),
                         "cpu_ratio": float(np.sqrt(r1 * r2)), "noise": abs(r1 - r2) / 2.0,
                         "other_branch_steps": sorted(set(rows[-3]["other_branch_steps"]) |
                                                      set(rows[-2]["other_branch_steps"])),
                         "steps": rows[-3]["steps"], "converged": min(rows[-3]["converged"], rows[-2]["converged"])}
    data = json.loads(Path(args.data).read_text()) if Path(args.data).exists() else {}
    data[label] = {"reference": list(engagement(args.reference)), "values": ratios, "rows": rows}
    Path(args.data).write_text(json.dumps(data, indent=1) + "\n")
    lines = header(f"When the cohesive NCG engages the two-level preconditioner: N = 2^{args.size}, φn* = {args.phi:g}, "
                   f"δn = {args.length_normal * 1e9:g} nm, ν = {args.nu:g}, realization {args.realization}",
                   "bench_cohesive_engage.py", argv, note="2-core machine, two simultaneous processes per pair")
    lines += ["| run | ENGAGE_AFTER / EARLY / REBUILD_EVERY | ramp CPU s | iterations | FFT pairs | converged | final a_rel "
              "| max Δp̄ / max p̄ | max Δa_rel | steps on another branch |", "|" + "---|" * 10]
    for r in rows:
        lines.append(f"| {r['run']} | {r['engage_after']} / {r['engage_early']} / {r['rebuild_every']} | {r['cpu_s']:.1f} | {r['iterations']} "
                     f"| {r['fft_pairs']:.0f} | {r['converged']}/{r['steps']} | {r['final_a_rel']:.3f} | "
                     f"{r['dp_rel']:.1e} | {r['da_rel']:.1e} | {', '.join(map(str, r['other_branch_steps'])) or 'none'} |")
    lines.append("")
    for value, r in ratios.items():
        lines.append(f"{value} against {args.reference}: CPU × {r['cpu_ratio']:.3f} (geometric mean over the two core "
                     f"placements; noise ± {r['noise']:.3f}), steps on another branch: "
                     f"{', '.join(map(str, r['other_branch_steps'])) or 'none'}.")
    write(lines, out)


if __name__ == "__main__":
    main()
